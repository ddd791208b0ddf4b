//! Growing a sheet row by row on an open front (MATH.md section 5), with the
//! validity rules of section 9 reported at the row and column where they fail.

use super::construct::{Point, Refusal, lower_left, lower_right, pivot_from_v1, pivot_from_v2};
use super::{Cell, Kind, Lattice, Vertex, VertexKey, angle_between};
use crate::geometry::{Direction, Leg};
use glam::DVec3;
use std::fmt;

/// Cells whose opening angle is this close to 0 or pi are refused.
pub const EPS_ANGLE: f64 = 1e-6;
/// Upper bound on lattice size, so an absurd recipe fails with a message
/// instead of exhausting memory (about 150 bytes a cell).
pub const MAX_CELLS: usize = 4_000_000;

/// The free parameters of one open-front row (MATH.md 5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowParams {
    /// The start site j0 whose leg direction is given.
    pub start: usize,
    pub direction: Direction,
    /// `L2 = l2[i][0]`, the free leg at the left end.
    pub left_leg: Leg,
    /// `L3 = l3[i][m-1]`, the free leg at the right end.
    pub right_leg: Leg,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GrowthErrorKind {
    SeedTooShort,
    SeedEdgeNotSpacelike,
    StartOutOfRange,
    BadDirection,
    InadmissibleDirection,
    DoubleEdgeNotSpacelike,
    NonPositiveLeg,
    MatchNeedsLength,
    DegenerateCell,
    InvertedCell,
    TooLarge,
    NumericalBreakdown,
}

impl GrowthErrorKind {
    /// The error class name of MATH.md 9, shown to users for searching.
    pub fn name(self) -> &'static str {
        match self {
            Self::SeedTooShort => "SeedTooShort",
            Self::SeedEdgeNotSpacelike => "SeedEdgeNotSpacelike",
            Self::StartOutOfRange => "StartOutOfRange",
            Self::BadDirection => "BadDirection",
            Self::InadmissibleDirection => "InadmissibleDirection",
            Self::DoubleEdgeNotSpacelike => "DoubleEdgeNotSpacelike",
            Self::NonPositiveLeg => "NonPositiveLeg",
            Self::MatchNeedsLength => "MatchNeedsLength",
            Self::DegenerateCell => "DegenerateCell",
            Self::InvertedCell => "InvertedCell",
            Self::TooLarge => "TooLarge",
            Self::NumericalBreakdown => "NumericalBreakdown",
        }
    }
}

/// The design parameter a growth error is about, so the recipe layer can
/// point at the text that sets it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    SeedPoints,
    /// The kappa of one seed edge.
    SeedKappa(usize),
    /// The front a row grows on: the seed for row 0, else the previous row.
    Front,
    Start,
    Direction,
    LeftLeg,
    RightLeg,
}

/// A design that cannot be grown, with the place it fails.
#[derive(Clone, Debug, PartialEq)]
pub struct GrowthError {
    pub kind: GrowthErrorKind,
    pub param: Param,
    /// The row being grown (`None` for a problem of the seed itself).
    pub row: Option<usize>,
    /// The column (cell, or seed edge) where it fails, when there is one.
    pub col: Option<usize>,
    pub message: String,
    pub hint: String,
}

impl GrowthError {
    fn new(
        kind: GrowthErrorKind,
        param: Param,
        row: Option<usize>,
        col: Option<usize>,
        message: impl Into<String>,
        hint: impl Into<String>,
    ) -> Self {
        Self {
            kind,
            param,
            row,
            col,
            message: message.into(),
            hint: hint.into(),
        }
    }

    /// "row 3, column 2" style location in lattice terms.
    pub fn site(&self) -> String {
        match (self.row, self.col) {
            (Some(r), Some(c)) => format!("row {r}, column {c}"),
            (Some(r), None) => format!("row {r}"),
            (None, Some(c)) => format!("seed edge {c}"),
            (None, None) => "seed".to_string(),
        }
    }
}

impl fmt::Display for GrowthError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} at {}: {}",
            self.kind.name(),
            self.site(),
            self.message
        )
    }
}

impl std::error::Error for GrowthError {}

/// Grow a sheet from its seed front (`points` with one `kappa` per edge) and
/// one parameter set per row.
pub fn grow_sheet(
    dim: usize,
    points: &[DVec3],
    kappa: &[f64],
    rows: &[RowParams],
) -> Result<Lattice, GrowthError> {
    use GrowthErrorKind as K;
    if points.len() < 2 {
        return Err(GrowthError::new(
            K::SeedTooShort,
            Param::SeedPoints,
            None,
            None,
            format!(
                "a sheet seed needs at least 2 points, this one has {}",
                points.len()
            ),
            "add points to the seed front",
        ));
    }
    let m = points.len() - 1;
    assert_eq!(
        kappa.len(),
        m,
        "the design layer checks one kappa per seed edge"
    );
    if m.saturating_mul(rows.len()) > MAX_CELLS {
        return Err(GrowthError::new(
            K::TooLarge,
            Param::SeedPoints,
            None,
            None,
            format!(
                "{m} x {} cells is more than the limit of {MAX_CELLS}",
                rows.len()
            ),
            "grow fewer rows or use fewer seed points",
        ));
    }
    let mut lattice = Lattice {
        kind: Kind::Sheet,
        dim,
        width: m,
        vertices: Vec::with_capacity((m + 1) * (rows.len() + 1)),
        cells: Vec::with_capacity(m * rows.len()),
    };
    let mut z = 0.0;
    for (j, &pos) in points.iter().enumerate() {
        if j > 0 {
            let t = pos - points[j - 1];
            let k = kappa[j - 1];
            if !(k.abs() < t.length()) {
                return Err(GrowthError::new(
                    K::SeedEdgeNotSpacelike,
                    Param::SeedKappa(j - 1),
                    None,
                    Some(j - 1),
                    format!(
                        "|kappa| = {} is not smaller than the edge length |t| = {}",
                        fmt_len(k.abs()),
                        fmt_len(t.length())
                    ),
                    "every seed edge must be longer than its |kappa|: lower kappa or move the points apart",
                ));
            }
            z -= k;
        }
        lattice.vertices.push(Vertex {
            key: VertexKey {
                row: 0,
                col: j as u32,
            },
            pos,
            z,
        });
    }
    let mut grower = RowGrower {
        m,
        orientation: None,
        front: Vec::with_capacity(m + 1),
        pivots: vec![None; m],
        next: vec![None; m + 1],
    };
    for (i, params) in rows.iter().enumerate() {
        grower.grow(&mut lattice, i, params)?;
    }
    Ok(lattice)
}

/// Scratch space reused by every row.
struct RowGrower {
    m: usize,
    /// Sign of the first cell's orientation (2-D only).
    orientation: Option<f64>,
    front: Vec<Point>,
    pivots: Vec<Option<Point>>,
    next: Vec<Option<Point>>,
}

impl RowGrower {
    fn grow(
        &mut self,
        lattice: &mut Lattice,
        i: usize,
        params: &RowParams,
    ) -> Result<(), GrowthError> {
        use GrowthErrorKind as K;
        let m = self.m;
        let base = i * (m + 1);
        self.front.clear();
        self.front.extend(
            lattice.vertices[base..base + m + 1]
                .iter()
                .map(|v| Point { pos: v.pos, z: v.z }),
        );
        self.pivots.iter_mut().for_each(|p| *p = None);
        self.next.iter_mut().for_each(|p| *p = None);
        let x = &self.front;
        let row = Some(i);

        let j0 = params.start;
        if j0 >= m {
            return Err(GrowthError::new(
                K::StartOutOfRange,
                Param::Start,
                row,
                None,
                format!("start = {j0}, but a row has cells 0 to {}", m - 1),
                format!("use a start site between 0 and {}", m - 1),
            ));
        }
        let v2 = resolve_direction(params.direction, x[j0].pos, x[j0 + 1].pos, lattice.dim)
            .map_err(|(msg, hint)| {
                GrowthError::new(K::BadDirection, Param::Direction, row, Some(j0), msg, hint)
            })?;
        let start = pivot_from_v2(x[j0], x[j0 + 1], v2).map_err(|_| {
            let t = x[j0 + 1].pos - x[j0].pos;
            let kappa = x[j0].z - x[j0 + 1].z;
            let half = (kappa / t.length()).clamp(-1.0, 1.0).acos().to_degrees();
            let axis = angle_between(v2, -t.normalize()).to_degrees();
            GrowthError::new(
                K::InadmissibleDirection,
                Param::Direction,
                row,
                Some(j0),
                format!(
                    "the leg direction is {axis:.3} deg from the cone axis (the direction back along the front edge), but it must be less than {half:.3} deg",
                    ),
                "turn the direction towards the front edge (a smaller angle)",
            )
        })?;
        self.pivots[j0] = Some(start);

        // Right of j0: rod A of cell j fixes the lower-right corner, which
        // fixes rod B (and so the pivot) of cell j + 1.
        for j in j0..m.saturating_sub(1) {
            let p = self.pivots[j].expect("pivot grown");
            let v1 = (p.pos - x[j].pos).normalize();
            let lr = lower_right(x[j], x[j + 2], v1)
                .map_err(|r| transfer_error(r, x, j, j + 2, i, j))?;
            check_leg(lr.z - p.z, "l3", i, j)?;
            self.next[j + 1] = Some(lr);
            let v2 = (lr.pos - x[j + 2].pos).normalize();
            let cell =
                pivot_from_v2(x[j + 1], x[j + 2], v2).map_err(|_| propagated_cone(i, j + 1))?;
            check_leg(lr.z - cell.z, "l2", i, j + 1)?;
            self.pivots[j + 1] = Some(cell);
        }
        // Left of j0, the mirror image.
        for j in (1..=j0).rev() {
            let p = self.pivots[j].expect("pivot grown");
            let v2 = (p.pos - x[j + 1].pos).normalize();
            let ll = lower_left(x[j - 1], x[j + 1], v2)
                .map_err(|r| transfer_error(r, x, j - 1, j + 1, i, j))?;
            check_leg(ll.z - p.z, "l2", i, j)?;
            self.next[j] = Some(ll);
            let v1 = (ll.pos - x[j - 1].pos).normalize();
            let cell = pivot_from_v1(x[j - 1], x[j], v1).map_err(|_| propagated_cone(i, j - 1))?;
            check_leg(ll.z - cell.z, "l3", i, j - 1)?;
            self.pivots[j - 1] = Some(cell);
        }

        // The two free boundary legs (4.5).
        let p_first = self.pivots[0].expect("pivot grown");
        let p_last = self.pivots[m - 1].expect("pivot grown");
        let matched_left = self.next[1].map(|q| q.z - p_first.z);
        let matched_right = self.next[m - 1].map(|q| q.z - p_last.z);
        let (l2, l3) = match (params.left_leg, params.right_leg) {
            (Leg::Length(a), Leg::Length(b)) => (a, b),
            (Leg::Length(a), Leg::Match) => (a, matched_right.unwrap_or(a)),
            (Leg::Match, Leg::Length(b)) => (matched_left.unwrap_or(b), b),
            (Leg::Match, Leg::Match) => match (matched_left, matched_right) {
                (Some(a), Some(b)) => (a, b),
                _ => {
                    return Err(GrowthError::new(
                        K::MatchNeedsLength,
                        Param::LeftLeg,
                        row,
                        Some(0),
                        "both end legs are \"match\", but in a one-cell-wide row each end matches the other",
                        "give left_leg or right_leg as a length in mm",
                    ));
                }
            },
        };
        check_boundary_leg(l2, Param::LeftLeg, i, 0)?;
        check_boundary_leg(l3, Param::RightLeg, i, m - 1)?;
        let v2_first = (p_first.pos - x[1].pos).normalize();
        let v1_last = (p_last.pos - x[m - 1].pos).normalize();
        self.next[0] = Some(Point {
            pos: p_first.pos + l2 * v2_first,
            z: p_first.z + l2,
        });
        self.next[m] = Some(Point {
            pos: p_last.pos + l3 * v1_last,
            z: p_last.z + l3,
        });

        // Commit the row: new front vertices, then cells left to right.
        let next_base = (i + 1) * (m + 1);
        for (j, q) in self.next.iter().enumerate() {
            let q = q.expect("front vertex grown");
            if !(q.pos.is_finite() && q.z.is_finite()) {
                return Err(breakdown(i, j));
            }
            lattice.vertices.push(Vertex {
                key: VertexKey {
                    row: (i + 1) as u32,
                    col: j as u32,
                },
                pos: q.pos,
                z: q.z,
            });
        }
        for j in 0..m {
            let pivot = self.pivots[j].expect("pivot grown");
            let cell = Cell {
                row: i as u32,
                col: j as u32,
                ul: (base + j) as u32,
                ur: (base + j + 1) as u32,
                ll: (next_base + j) as u32,
                lr: (next_base + j + 1) as u32,
                pivot: pivot.pos,
                z_pivot: pivot.z,
            };
            self.check_cell(lattice, &cell)?;
            lattice.cells.push(cell);
        }
        Ok(())
    }

    /// Degenerate and inverted cells (MATH.md 9).
    fn check_cell(&mut self, lattice: &Lattice, cell: &Cell) -> Result<(), GrowthError> {
        let (i, j) = (cell.row as usize, cell.col as usize);
        if !(cell.pivot.is_finite() && cell.z_pivot.is_finite()) {
            return Err(breakdown(i, j));
        }
        let ul = lattice.vertex(cell.ul).pos - cell.pivot;
        let ur = lattice.vertex(cell.ur).pos - cell.pivot;
        let (cross, dot) = (ul.cross(ur), ul.dot(ur));
        let norms = ul.length() * ur.length();
        let sin_phi = cross.length() / norms;
        if !sin_phi.is_finite() {
            return Err(breakdown(i, j));
        }
        if sin_phi < EPS_ANGLE {
            let phi = angle_between(ul / ul.length(), ur / ur.length());
            let state = if dot > 0.0 {
                "collapsed (phi near 0)"
            } else {
                "flat-open (phi near 180 deg)"
            };
            return Err(GrowthError::new(
                GrowthErrorKind::DegenerateCell,
                Param::Direction,
                Some(i),
                Some(j),
                format!("the cell is {state}: phi = {:.6} deg", phi.to_degrees()),
                "change this row's direction so the cell opens between 0 and 180 deg",
            ));
        }
        if lattice.dim == 2 {
            let sign = cross.z.signum();
            match self.orientation {
                None => self.orientation = Some(sign),
                Some(s) if s != sign => {
                    return Err(GrowthError::new(
                        GrowthErrorKind::InvertedCell,
                        Param::Direction,
                        Some(i),
                        Some(j),
                        "the cell is mirrored relative to the first cell of the lattice (its rods cross the other way)",
                        "keep every row's direction on the same side of the front",
                    ));
                }
                Some(_) => {}
            }
        }
        Ok(())
    }
}

/// The unit leg direction `v2` at the start site, from what the design gave.
fn resolve_direction(
    direction: Direction,
    ul: DVec3,
    ur: DVec3,
    dim: usize,
) -> Result<DVec3, (String, String)> {
    match direction {
        Direction::Vector(v) => {
            let len = v.length();
            if !(len.is_finite() && len > 0.0) {
                return Err((
                    "the direction vector has zero length".into(),
                    "give a non-zero direction, e.g. [-0.87, -0.5]".into(),
                ));
            }
            Ok(v / len)
        }
        Direction::Angles {
            angle_deg,
            tilt_deg,
        } => {
            if dim == 2 && tilt_deg != 0.0 {
                return Err((
                    "a tilt angle needs a 3-D lattice".into(),
                    "give `angle` as one number in 2-D".into(),
                ));
            }
            let frame = front_frame(ul, ur).ok_or_else(|| {
                (
                    "the front edge at the start site is vertical (along z), so angles have no reference"
                        .to_string(),
                    "give `direction` as a vector for this row".to_string(),
                )
            })?;
            let (a, b) = (angle_deg.to_radians(), tilt_deg.to_radians());
            Ok(a.cos() * frame.axis + a.sin() * (b.cos() * frame.down + b.sin() * frame.out))
        }
    }
}

/// The front-local frame at a site: `axis` points from UR back to UL (the
/// cone axis of MATH.md 4.2), `down` is the growth side within the plane of
/// the front and +z (in 2-D, the clockwise normal), `out` completes it.
#[derive(Clone, Copy, Debug)]
pub struct FrontFrame {
    pub axis: DVec3,
    pub down: DVec3,
    pub out: DVec3,
}

pub fn front_frame(ul: DVec3, ur: DVec3) -> Option<FrontFrame> {
    let along = (ur - ul).normalize();
    let down = along.cross(DVec3::Z);
    let len = down.length();
    if !(len > 1e-9) {
        return None;
    }
    let down = down / len;
    Some(FrontFrame {
        axis: -along,
        down,
        out: down.cross(along),
    })
}

/// A refused transfer across the double edge from front vertex `a` to `b`.
fn transfer_error(
    refusal: Refusal,
    x: &[Point],
    a: usize,
    b: usize,
    i: usize,
    j: usize,
) -> GrowthError {
    match refusal {
        Refusal::NotSpacelike => GrowthError::new(
            GrowthErrorKind::DoubleEdgeNotSpacelike,
            Param::Front,
            Some(i),
            Some(j),
            format!(
                "the front is too folded at cell {j}: front vertices {a} and {b} are {} apart, not more than |kappa| summed between them ({})",
                fmt_len(x[a].pos.distance(x[b].pos)),
                fmt_len((x[a].z - x[b].z).abs()),
            ),
            "unfold the front here: change the seed points or kappa (row 0), or the previous row's direction or legs",
        ),
        Refusal::MissesCone => propagated_cone(i, j),
    }
}

fn propagated_cone(i: usize, j: usize) -> GrowthError {
    GrowthError::new(
        GrowthErrorKind::InadmissibleDirection,
        Param::Direction,
        Some(i),
        Some(j),
        "the leg direction carried over from the neighbouring cell falls outside this cell's admissible cone (the pivot would be at infinity)",
        "this row's start direction is admissible at its start site but not across the row: choose a direction nearer the cone axis",
    )
}

fn check_leg(leg: f64, name: &str, i: usize, j: usize) -> Result<(), GrowthError> {
    if leg.is_finite() && leg > 0.0 {
        return Ok(());
    }
    if !leg.is_finite() {
        return Err(breakdown(i, j));
    }
    Err(GrowthError::new(
        GrowthErrorKind::NonPositiveLeg,
        Param::Direction,
        Some(i),
        Some(j),
        format!(
            "leg {name} would be {} (the pivot lies beyond the corner)",
            fmt_len(leg)
        ),
        "choose a direction nearer the cone axis for this row",
    ))
}

fn check_boundary_leg(leg: f64, param: Param, i: usize, j: usize) -> Result<(), GrowthError> {
    if leg.is_finite() && leg > 0.0 {
        return Ok(());
    }
    let name = if param == Param::LeftLeg {
        "left_leg (L2)"
    } else {
        "right_leg (L3)"
    };
    Err(GrowthError::new(
        GrowthErrorKind::NonPositiveLeg,
        param,
        Some(i),
        Some(j),
        format!("{name} is {} but must be a positive length", fmt_len(leg)),
        format!(
            "give {} a positive length in mm, or \"match\"",
            name.split(' ').next().unwrap_or(name)
        ),
    ))
}

fn breakdown(i: usize, j: usize) -> GrowthError {
    GrowthError::new(
        GrowthErrorKind::NumericalBreakdown,
        Param::Direction,
        Some(i),
        Some(j),
        "the construction produced a non-finite number",
        "the design is too close to degenerate here: change this row's direction or legs",
    )
}

/// Lengths in messages: enough digits to compare, no float noise.
pub fn fmt_len(x: f64) -> String {
    format!("{x:.6} mm")
}
