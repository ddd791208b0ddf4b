//! Growing a sheet row by row on an open front (MATH.md section 5), with the
//! validity rules of section 9 reported at the row and column where they fail.

use super::closure::{Closure, Holonomy, closure};
use super::construct::{Point, Refusal, lower_left, lower_right, pivot_from_v1, pivot_from_v2};
use super::front::{FrontMoves, rebuild};
use super::{Cell, Kind, Lattice, Vertex, VertexKey, angle_between};
use crate::geometry::{Direction, Leg};
use glam::DVec3;
use std::fmt;

/// Cells whose opening angle is this close to 0 or pi are refused.
pub const EPS_ANGLE: f64 = 1e-6;
/// Upper bound on lattice size, so an absurd recipe fails with a message
/// instead of exhausting memory (about 150 bytes a cell).
pub const MAX_CELLS: usize = 4_000_000;

/// The free parameters of one row (MATH.md 5, 6.2, 7).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RowParams {
    /// The start site j0 whose leg direction is given (open fronts).
    pub start: usize,
    /// Required on an open front; on a loop, the direction of a symmetric
    /// row, or a check that the row closes.
    pub direction: Option<Direction>,
    /// `L2 = l2[i][0]`, the free leg at the left end (open fronts).
    pub left_leg: Leg,
    /// `L3 = l3[i][m-1]`, the free leg at the right end (open fronts).
    pub right_leg: Leg,
    /// Loops: where the new vertex x[i+1][1] goes (symmetric rows), or which
    /// closing direction to take (the one landing nearest it).
    pub target: Option<DVec3>,
    /// Loops: the closing direction to take, 1 or 2, counted from the cone
    /// axis of cell 0 outwards. Default: 1, the more open cell.
    pub candidate: Option<usize>,
    /// Intrinsic growth: rebuild the front before growing on it.
    pub front: Option<FrontMoves>,
}

/// The growth errors of MATH.md 9 are kinds of the one error enum.
pub use crate::diagnostic::ErrorKind as GrowthErrorKind;

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
    Target,
    Candidate,
    FrontMoves,
    /// A helix's cell count.
    Cells,
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
    pub fn new(
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
    grow(Kind::Sheet, dim, points, kappa, rows)
}

/// Grow a sheet or a loop from its seed and one parameter set per row.
pub fn grow(
    kind: Kind,
    dim: usize,
    points: &[DVec3],
    kappa: &[f64],
    rows: &[RowParams],
) -> Result<Lattice, GrowthError> {
    let width = if kind == Kind::Loop {
        points.len()
    } else {
        points.len().saturating_sub(1)
    };
    if width.saturating_mul(rows.len()) > MAX_CELLS {
        return Err(GrowthError::new(
            GrowthErrorKind::TooLarge,
            Param::SeedPoints,
            None,
            None,
            format!(
                "{width} x {} cells is more than the limit of {MAX_CELLS}",
                rows.len()
            ),
            "grow fewer rows or use fewer seed points",
        ));
    }
    let mut grower = Grower::new(kind, dim, points, kappa)?;
    // Room for every row at once: no reallocation copies the lattice, and
    // the peak memory is the lattice's own size, not up to twice it.
    grower.reserve_rows(rows.len());
    for params in rows {
        grower.grow_row(params)?;
    }
    Ok(grower.into_lattice())
}

/// How a loop row was closed (MATH.md 6.2), for the verification report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosureRecord {
    pub row: usize,
    /// The holonomy was the identity: the direction was a design input.
    pub free: bool,
    /// Admissible closing directions found (generic case).
    pub candidates: usize,
    /// `|v2' - v2|` after the row was built.
    pub residual: f64,
    pub ill_conditioned: bool,
}

/// Grows a lattice one row at a time; a row can be undone, so a fitting
/// search can try parameters and keep the best.
pub struct Grower {
    lattice: Lattice,
    /// How each loop row closed (empty for sheets).
    pub closures: Vec<ClosureRecord>,
    front: Vec<Point>,
    pivots: Vec<Option<Point>>,
    next: Vec<Option<Point>>,
}

impl Grower {
    /// Check a sheet or loop seed and start a lattice on it.
    pub fn new(
        kind: Kind,
        dim: usize,
        points: &[DVec3],
        kappa: &[f64],
    ) -> Result<Self, GrowthError> {
        use GrowthErrorKind as K;
        let closed = kind == Kind::Loop;
        let min = if closed { 3 } else { 2 };
        if points.len() < min {
            return Err(GrowthError::new(
                K::SeedTooShort,
                Param::SeedPoints,
                None,
                None,
                format!(
                    "a {} seed needs at least {min} points, this one has {}",
                    kind.name(),
                    points.len()
                ),
                "add points to the seed front",
            ));
        }
        let width = if closed {
            points.len()
        } else {
            points.len() - 1
        };
        assert_eq!(
            kappa.len(),
            width,
            "the design layer checks one kappa per seed edge"
        );
        let mut lattice = Lattice {
            kind,
            dim,
            width,
            vertices: Vec::with_capacity(points.len()),
            cells: Vec::new(),
            fronts: Vec::new(),
        };
        seed_front(&mut lattice, points, kappa)?;
        if closed {
            let perimeter: f64 = (0..width)
                .map(|j| points[j].distance(points[(j + 1) % width]))
                .sum();
            let sum: f64 = kappa.iter().sum();
            if !(sum.abs() <= 1e-9 * perimeter) {
                return Err(GrowthError::new(
                    K::LoopKappaSumNonzero,
                    Param::SeedKappa(width),
                    None,
                    None,
                    format!(
                        "the kappa of a loop must sum to 0 (the collapsed state goes once round the loop), but they sum to {}",
                        fmt_len(sum)
                    ),
                    "change the kappa values so that they sum to 0, e.g. kappa = 0.0 for every edge",
                ));
            }
        }
        Ok(Self {
            lattice,
            closures: Vec::new(),
            front: Vec::with_capacity(width + 1),
            pivots: vec![None; width],
            next: vec![None; width + 1],
        })
    }

    /// Reserve room for `rows` more rows.
    pub fn reserve_rows(&mut self, rows: usize) {
        let n = self.front_len();
        let lattice = &mut self.lattice;
        lattice.cells.reserve_exact(rows * lattice.width);
        lattice.vertices.reserve_exact(rows * n);
        lattice.fronts.reserve_exact(rows);
    }

    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }

    pub fn into_lattice(self) -> Lattice {
        self.lattice
    }

    /// Vertices a front has: m + 1 for a sheet, N for a loop.
    fn front_len(&self) -> usize {
        match self.lattice.kind {
            Kind::Loop => self.lattice.width,
            _ => self.lattice.width + 1,
        }
    }

    /// The current front as points in the frame of the next row (before any
    /// rebuild): the last row's new vertices.
    pub fn front(&self) -> Vec<Point> {
        let n = self.front_len();
        let base = self.lattice.vertices.len() - n;
        self.lattice.vertices[base..]
            .iter()
            .map(|v| Point { pos: v.pos, z: v.z })
            .collect()
    }

    /// Remove the last grown row.
    pub fn undo_row(&mut self) {
        let rows = self.lattice.rows();
        if rows == 0 {
            return;
        }
        let n = self.front_len();
        self.lattice.vertices.truncate(rows * n);
        self.lattice.cells.truncate((rows - 1) * self.lattice.width);
        self.lattice.fronts.truncate(rows - 1);
        self.closures.retain(|c| c.row + 1 < rows);
    }

    /// Grow the next row; on error the lattice is left as it was.
    pub fn grow_row(&mut self, params: &RowParams) -> Result<(), GrowthError> {
        let i = self.lattice.rows();
        let before = (self.lattice.vertices.len(), self.lattice.cells.len());
        let result = self.try_row(i, params);
        if result.is_err() {
            self.lattice.vertices.truncate(before.0);
            self.lattice.cells.truncate(before.1);
            self.lattice.fronts.truncate(i);
            self.closures.retain(|c| c.row < i);
        }
        result
    }

    fn try_row(&mut self, i: usize, params: &RowParams) -> Result<(), GrowthError> {
        // The last row's vertices, into the buffer of the previous row.
        let mut front = std::mem::take(&mut self.front);
        let n = self.front_len();
        let base = self.lattice.vertices.len() - n;
        front.clear();
        front.extend(
            self.lattice.vertices[base..]
                .iter()
                .map(|v| Point { pos: v.pos, z: v.z }),
        );
        let rebuilt = match &params.front {
            Some(moves) => {
                let pos: Vec<DVec3> = front.iter().map(|p| p.pos).collect();
                let closed = self.lattice.kind == Kind::Loop;
                let new = rebuild(&pos, closed, self.lattice.dim, moves).map_err(|e| {
                    GrowthError::new(
                        GrowthErrorKind::FrontNotCompatible,
                        Param::FrontMoves,
                        Some(i),
                        None,
                        e.message,
                        e.hint,
                    )
                })?;
                for (p, q) in front.iter_mut().zip(&new) {
                    p.pos = *q;
                }
                new
            }
            None => Vec::new(),
        };
        self.lattice.fronts.push(rebuilt);
        self.front = front;
        match self.lattice.kind {
            Kind::Loop => self.grow_loop_row(i, params)?,
            _ => self.grow_open_row(i, params)?,
        }
        self.commit(i)
    }

    /// MATH.md 5 on an open front.
    fn grow_open_row(&mut self, i: usize, params: &RowParams) -> Result<(), GrowthError> {
        use GrowthErrorKind as K;
        let m = self.lattice.width;
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
        let Some(direction) = params.direction else {
            return Err(GrowthError::new(
                K::BadDirection,
                Param::Direction,
                row,
                Some(j0),
                "the row has no leg direction",
                "give `angle` (degrees) or `direction` for this row",
            ));
        };
        let v2 = resolve_direction(direction, x[j0].pos, x[j0 + 1].pos, self.lattice.dim).map_err(
            |(msg, hint)| {
                GrowthError::new(K::BadDirection, Param::Direction, row, Some(j0), msg, hint)
            },
        )?;
        let start = start_pivot(x, j0, v2, i)?;
        self.pivots[j0] = Some(start);

        // The two chains of transfers, right and left of j0, depend on
        // nothing of each other: grown in one loop, a step of each at a
        // time, their square roots and divisions overlap (half the time
        // of a row). Any refusal grows the row again one chain after the
        // other, so that the error reported is the one the sequential
        // order meets first.
        let right_steps = m.saturating_sub(1).saturating_sub(j0);
        let (mut right, mut left) = (start, start);
        let mut ok = true;
        for k in 0..right_steps.max(j0) {
            if k < right_steps {
                match right_step(x, j0 + k, right, i) {
                    Ok((lr, p)) => {
                        self.next[j0 + k + 1] = Some(lr);
                        self.pivots[j0 + k + 1] = Some(p);
                        right = p;
                    }
                    Err(_) => {
                        ok = false;
                        break;
                    }
                }
            }
            if k < j0 {
                match left_step(x, j0 - k, left, i) {
                    Ok((ll, p)) => {
                        self.next[j0 - k] = Some(ll);
                        self.pivots[j0 - k - 1] = Some(p);
                        left = p;
                    }
                    Err(_) => {
                        ok = false;
                        break;
                    }
                }
            }
        }
        if !ok {
            // Right of j0: rod A of cell j fixes the lower-right corner,
            // which fixes rod B (and so the pivot) of cell j + 1.
            for j in j0..m.saturating_sub(1) {
                let p = self.pivots[j].expect("pivot grown");
                let (lr, next) = right_step(x, j, p, i)?;
                self.next[j + 1] = Some(lr);
                self.pivots[j + 1] = Some(next);
            }
            // Left of j0, the mirror image.
            for j in (1..=j0).rev() {
                let p = self.pivots[j].expect("pivot grown");
                let (ll, cell) = left_step(x, j, p, i)?;
                self.next[j] = Some(ll);
                self.pivots[j - 1] = Some(cell);
            }
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
        Ok(())
    }

    /// Commit the grown row: new front vertices, then cells left to right.
    fn commit(&mut self, i: usize) -> Result<(), GrowthError> {
        let m = self.lattice.width;
        let n = self.front_len();
        let base = self.lattice.vertices.len() - n;
        let next_base = base + n;
        for j in 0..n {
            let q = self.next[j].expect("front vertex grown");
            if !(q.pos.is_finite() && q.z.is_finite()) {
                return Err(breakdown(i, j));
            }
            self.lattice.vertices.push(Vertex {
                key: VertexKey {
                    row: (i + 1) as u32,
                    col: j as u32,
                },
                pos: q.pos,
                z: q.z,
            });
        }
        // The turn of the lattice's first cell, once a row, not once a cell.
        let mut first = first_turn(&self.lattice);
        for j in 0..m {
            let pivot = self.pivots[j].expect("pivot grown");
            let cell = Cell {
                row: i as u32,
                col: j as u32,
                ul: (base + j) as u32,
                ur: (base + (j + 1) % n) as u32,
                ll: (next_base + j) as u32,
                lr: (next_base + (j + 1) % n) as u32,
                pivot: pivot.pos,
                z_pivot: pivot.z,
            };
            check_cell_turn(&self.lattice, &cell, first)?;
            self.lattice.cells.push(cell);
            if first.is_none() {
                first = first_turn(&self.lattice);
            }
        }
        Ok(())
    }

    /// MATH.md 6.2: a row on a closed front, its direction fixed by closure.
    fn grow_loop_row(&mut self, i: usize, params: &RowParams) -> Result<(), GrowthError> {
        use GrowthErrorKind as K;
        let x = self.front.clone();
        let dim = self.lattice.dim;
        let row = Some(i);
        let axis = -(x[1].pos - x[0].pos).normalize();
        let holonomy = Holonomy::new(&x);
        let record = match closure(&holonomy, axis, dim) {
            Closure::Free => {
                let v2 = if let Some(target) = params.target {
                    // Place x[i+1][1] towards the target: rod A of cell 0 points at it.
                    let v1 = (target - x[0].pos).normalize();
                    let p = pivot_from_v1(x[0], x[1], v1).map_err(|_| {
                        GrowthError::new(
                            K::InadmissibleDirection,
                            Param::Target,
                            row,
                            Some(0),
                            "the target is outside the admissible cone of cell 0 (seen from the cell's upper-left corner)",
                            "move the target towards the growth side of the front",
                        )
                    })?;
                    (p.pos - x[1].pos).normalize()
                } else if let Some(direction) = params.direction {
                    resolve_direction(direction, x[0].pos, x[1].pos, dim).map_err(|(m, h)| {
                        GrowthError::new(K::BadDirection, Param::Direction, row, Some(0), m, h)
                    })?
                } else {
                    return Err(GrowthError::new(
                        K::LoopClosureFree,
                        Param::Direction,
                        row,
                        None,
                        "the front is symmetric (its holonomy is the identity), so every direction closes and the row needs one",
                        "give this row an `angle`, a `direction`, or a `target` point for its vertex x[i+1][1]",
                    ));
                };
                let residual = self.build_loop(&x, v2, i)?;
                ClosureRecord {
                    row: i,
                    free: true,
                    candidates: 0,
                    residual,
                    ill_conditioned: false,
                }
            }
            Closure::Fixed {
                directions,
                ill_conditioned,
            } => {
                // Polish each candidate on the real construction, keep the admissible ones.
                let mut admissible: Vec<(DVec3, f64)> = Vec::new();
                let mut last_error = None;
                for v in directions {
                    let v = polish(&x, v, dim);
                    match self.build_loop(&x, v, i) {
                        Ok(residual) => admissible.push((v, residual)),
                        Err(e) => last_error = Some(e),
                    }
                }
                admissible
                    .sort_by(|a, b| angle_between(a.0, axis).total_cmp(&angle_between(b.0, axis)));
                if admissible.is_empty() {
                    let why = match last_error {
                        Some(e) => format!(" (the closing directions fail: {})", e.message),
                        None => " (the holonomy has no real fixed point: an elliptic planar front)"
                            .to_string(),
                    };
                    return Err(GrowthError::new(
                        K::NoLoopClosure,
                        Param::Front,
                        row,
                        None,
                        format!("no admissible leg direction closes this loop row{why}"),
                        "make the front more symmetric (points evenly round a circle, kappa = 0 closes for every direction)",
                    ));
                }
                let pick = if let Some(direction) = params.direction {
                    let v = resolve_direction(direction, x[0].pos, x[1].pos, dim).map_err(
                        |(m, h)| {
                            GrowthError::new(K::BadDirection, Param::Direction, row, Some(0), m, h)
                        },
                    )?;
                    let (k, off) = admissible
                        .iter()
                        .map(|a| angle_between(a.0, v))
                        .enumerate()
                        .min_by(|a, b| a.1.total_cmp(&b.1))
                        .expect("some candidate");
                    if holonomy.map(v).distance(v) > 1e-9 {
                        return Err(GrowthError::new(
                            K::NoLoopClosure,
                            Param::Direction,
                            row,
                            Some(0),
                            format!(
                                "this direction does not close the loop: it comes back {:.6} deg off, and the nearest closing direction is {:.6} deg away",
                                angle_between(holonomy.map(v).normalize(), v).to_degrees(),
                                off.to_degrees()
                            ),
                            "leave `direction` out (the closing direction is found), or give `candidate = 1` or `2`",
                        ));
                    }
                    k
                } else if let Some(c) = params.candidate {
                    if c == 0 || c > admissible.len() {
                        return Err(GrowthError::new(
                            K::NoLoopClosure,
                            Param::Candidate,
                            row,
                            None,
                            format!(
                                "candidate = {c}, but this row has {} admissible closing direction(s)",
                                admissible.len()
                            ),
                            format!(
                                "use candidate = 1{}",
                                if admissible.len() > 1 { " or 2" } else { "" }
                            ),
                        ));
                    }
                    c - 1
                } else if let Some(target) = params.target {
                    // The candidate whose new vertex x[i+1][1] lands nearest the target.
                    let mut best = (0, f64::INFINITY);
                    for (k, (v, _)) in admissible.iter().enumerate() {
                        self.build_loop(&x, *v, i)?;
                        let d = self.next[1].expect("grown").pos.distance(target);
                        if d < best.1 {
                            best = (k, d);
                        }
                    }
                    best.0
                } else {
                    0
                };
                let count = admissible.len();
                let v2 = admissible[pick].0;
                let residual = self.build_loop(&x, v2, i)?;
                ClosureRecord {
                    row: i,
                    free: false,
                    candidates: count,
                    residual,
                    ill_conditioned,
                }
            }
        };
        if record.residual > CLOSURE_TOL {
            return Err(GrowthError::new(
                K::LoopClosureResidual,
                Param::Direction,
                row,
                Some(0),
                format!(
                    "the loop closes only to {:.2e} (more than {CLOSURE_TOL:.0e})",
                    record.residual
                ),
                "the closure is ill-conditioned here: make the front more or less symmetric",
            ));
        }
        self.closures.push(record);
        Ok(())
    }

    /// Build a loop row from `v2` at cell 0 by right transfers all the way
    /// round; returns the closure residual `|v2' - v2|`.
    fn build_loop(&mut self, x: &[Point], v2: DVec3, i: usize) -> Result<f64, GrowthError> {
        let n = x.len();
        self.pivots[0] = Some(start_pivot(x, 0, v2, i)?);
        for j in 0..n {
            let p = self.pivots[j].expect("pivot grown");
            let lr = right_transfer(x, j, p, i)?;
            self.next[(j + 1) % n] = Some(lr);
            if j + 1 < n {
                self.pivots[j + 1] = Some(next_pivot(x, j, lr, i)?);
            }
        }
        let ll = self.next[0].expect("closing vertex");
        let p0 = self.pivots[0].expect("pivot grown");
        check_leg(ll.z - p0.z, "l2", i, 0)?;
        Ok((ll.pos - x[1].pos).normalize().distance(v2))
    }
}

/// Push the seed front as row 0 (z = 0 at its first point, then
/// `z(x[j+1]) = z(x[j]) - kappa[j]`), checking each of its `kappa.len()`
/// edges; the edge after the last point wraps to the first (loops).
pub(super) fn seed_front(
    lattice: &mut Lattice,
    points: &[DVec3],
    kappa: &[f64],
) -> Result<(), GrowthError> {
    let mut z = 0.0;
    for (j, &pos) in points.iter().enumerate() {
        lattice.vertices.push(Vertex {
            key: VertexKey {
                row: 0,
                col: j as u32,
            },
            pos,
            z,
        });
        if let Some(&k) = kappa.get(j) {
            seed_edge(pos, points[(j + 1) % points.len()], k, j)?;
            z -= k;
        }
    }
    Ok(())
}

/// A seed edge must be spacelike: longer than its |kappa| (MATH.md 9).
fn seed_edge(a: DVec3, b: DVec3, kappa: f64, j: usize) -> Result<(), GrowthError> {
    let t = b - a;
    if kappa.abs() < t.length() {
        return Ok(());
    }
    Err(GrowthError::new(
        GrowthErrorKind::SeedEdgeNotSpacelike,
        Param::SeedKappa(j),
        None,
        Some(j),
        format!(
            "|kappa| = {} is not smaller than the edge length |t| = {}",
            fmt_len(kappa.abs()),
            fmt_len(t.length())
        ),
        "every seed edge must be longer than its |kappa|: lower kappa or move the points apart",
    ))
}

/// Largest closure residual `|v2' - v2|` a loop row may keep.
pub const CLOSURE_TOL: f64 = 1e-9;

/// The loop map computed by the real transfers (no admissibility checks),
/// for polishing: where `v2` at cell 0 comes back after one round.
fn loop_map(x: &[Point], v2: DVec3) -> Option<DVec3> {
    let n = x.len();
    let mut p = pivot_from_v2(x[0], x[1], v2).ok()?;
    for j in 0..n {
        let v1 = (p.pos - x[j].pos).normalize();
        let lr = lower_right(x[j], x[(j + 2) % n], v1).ok()?;
        let v = (lr.pos - x[(j + 2) % n].pos).normalize();
        if j + 1 == n {
            return Some((lr.pos - x[1].pos).normalize());
        }
        p = pivot_from_v2(x[j + 1], x[(j + 2) % n], v).ok()?;
    }
    None
}

/// A few Newton steps on `loop_map(v) = v` in tangent coordinates.
fn polish(x: &[Point], v: DVec3, dim: usize) -> DVec3 {
    let basis: Vec<DVec3> = if dim == 2 {
        vec![DVec3::Z.cross(v).normalize()]
    } else {
        let a = v.any_orthonormal_vector();
        vec![a, v.cross(a)]
    };
    let residual = |v: DVec3| -> Option<Vec<f64>> {
        let w = loop_map(x, v)?;
        Some(basis.iter().map(|b| (w - v).dot(*b)).collect())
    };
    let mut v = v;
    for _ in 0..4 {
        let Some(r) = residual(v) else { return v };
        if r.iter().all(|e| e.abs() < 1e-15) {
            break;
        }
        let h = 1e-7;
        let cols: Option<Vec<Vec<f64>>> = basis
            .iter()
            .map(|b| {
                let rp = residual((v + h * *b).normalize())?;
                Some(rp.iter().zip(&r).map(|(a, b)| (a - b) / h).collect())
            })
            .collect();
        let Some(j) = cols else { return v };
        let step = if dim == 2 {
            if j[0][0].abs() < 1e-14 {
                return v;
            }
            vec![-r[0] / j[0][0]]
        } else {
            // Solve the 2x2 system J s = -r (J's columns are `cols`).
            let det = j[0][0] * j[1][1] - j[1][0] * j[0][1];
            if det.abs() < 1e-14 {
                return v;
            }
            vec![
                (-r[0] * j[1][1] + r[1] * j[1][0]) / det,
                (-r[1] * j[0][0] + r[0] * j[0][1]) / det,
            ]
        };
        let moved = (v + basis.iter().zip(&step).map(|(b, s)| *b * *s).sum::<DVec3>()).normalize();
        if residual(moved).is_none() {
            return v;
        }
        v = moved;
    }
    v
}

/// The start cell's pivot from its direction (MATH.md 4.2).
fn start_pivot(x: &[Point], j0: usize, v2: DVec3, i: usize) -> Result<Point, GrowthError> {
    let n = x.len();
    let (ul, ur) = (x[j0], x[(j0 + 1) % n]);
    pivot_from_v2(ul, ur, v2).map_err(|_| {
        let t = ur.pos - ul.pos;
        let kappa = ul.z - ur.z;
        let half = (kappa / t.length()).clamp(-1.0, 1.0).acos().to_degrees();
        let axis = angle_between(v2, -t.normalize()).to_degrees();
        GrowthError::new(
            GrowthErrorKind::InadmissibleDirection,
            Param::Direction,
            Some(i),
            Some(j0),
            format!(
                "the leg direction is {axis:.3} deg from the cone axis (the direction back along the front edge), but it must be less than {half:.3} deg",
            ),
            "turn the direction towards the front edge (a smaller angle)",
        )
    })
}

/// Right transfer from cell j (4.3), indices mod the front length: the
/// lower-right corner of cell j, on rod A beyond its pivot `p`.
fn right_transfer(x: &[Point], j: usize, p: Point, i: usize) -> Result<Point, GrowthError> {
    let j2 = (j + 2) % x.len();
    let v1 = (p.pos - x[j].pos).normalize();
    let lr = lower_right(x[j], x[j2], v1).map_err(|r| transfer_error(r, x, j, j2, i, j))?;
    check_leg(lr.z - p.z, "l3", i, j)?;
    Ok(lr)
}

/// The pivot of cell j + 1, whose rod B runs from its upper-right corner
/// to `ll`, the lower-right corner just found for cell j.
fn next_pivot(x: &[Point], j: usize, ll: Point, i: usize) -> Result<Point, GrowthError> {
    let n = x.len();
    let (j1, j2) = ((j + 1) % n, (j + 2) % n);
    let v2 = (ll.pos - x[j2].pos).normalize();
    let cell = pivot_from_v2(x[j1], x[j2], v2).map_err(|_| propagated_cone(i, j1))?;
    check_leg(ll.z - cell.z, "l2", i, j1)?;
    Ok(cell)
}

/// One step right of the start: from the pivot `p` of cell j, the
/// lower-right corner of cell j and the pivot of cell j + 1.
#[inline]
fn right_step(x: &[Point], j: usize, p: Point, i: usize) -> Result<(Point, Point), GrowthError> {
    let lr = right_transfer(x, j, p, i)?;
    Ok((lr, next_pivot(x, j, lr, i)?))
}

/// One step left of the start: from the pivot `p` of cell j, the
/// lower-left corner of cell j and the pivot of cell j - 1.
#[inline]
fn left_step(x: &[Point], j: usize, p: Point, i: usize) -> Result<(Point, Point), GrowthError> {
    let v2 = (p.pos - x[j + 1].pos).normalize();
    let ll =
        lower_left(x[j - 1], x[j + 1], v2).map_err(|r| transfer_error(r, x, j - 1, j + 1, i, j))?;
    check_leg(ll.z - p.z, "l2", i, j)?;
    let v1 = (ll.pos - x[j - 1].pos).normalize();
    let cell = pivot_from_v1(x[j - 1], x[j], v1).map_err(|_| propagated_cone(i, j - 1))?;
    check_leg(ll.z - cell.z, "l3", i, j - 1)?;
    Ok((ll, cell))
}

/// Degenerate and inverted cells (MATH.md 9).
pub(super) fn check_cell(lattice: &Lattice, cell: &Cell) -> Result<(), GrowthError> {
    check_cell_turn(lattice, cell, first_turn(lattice))
}

/// The sign of the z component of `(UL - P) x (UR - P)` of the lattice's
/// first cell: the way every cell of a planar lattice turns.
fn first_turn(lattice: &Lattice) -> Option<f64> {
    lattice.cells.first().map(|c| {
        let [ul, ur, _, _] = lattice.corners(c);
        (ul - c.pivot).cross(ur - c.pivot).z.signum()
    })
}

/// `check_cell`, given the first cell's turn (`first_turn`).
fn check_cell_turn(lattice: &Lattice, cell: &Cell, first: Option<f64>) -> Result<(), GrowthError> {
    let (i, j) = (cell.row as usize, cell.col as usize);
    if !(cell.pivot.is_finite() && cell.z_pivot.is_finite()) {
        return Err(breakdown(i, j));
    }
    let ul = lattice.vertex(cell.ul).pos - cell.pivot;
    let ur = lattice.vertex(cell.ur).pos - cell.pivot;
    let (cross, dot) = (ul.cross(ur), ul.dot(ur));
    // One square root where |ul x ur| / (|ul| |ur|) takes three.
    let sin_phi = (cross.length_squared() / (ul.length_squared() * ur.length_squared())).sqrt();
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
        // Every cell turns the same way as the first cell of the lattice.
        let sign = cross.z.signum();
        match first {
            None => {}
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
