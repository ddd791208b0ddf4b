//! Growing a sheet row by row on an open front (docs/math.md section 5), with the
//! validity rules of section 9 reported at the row and column where they fail.

use super::closure::{Closure, Holonomy, closure};
use super::construct::{Point, Refusal, lower_left, lower_right, pivot_from_v1, pivot_from_v2};
use super::front::{FrontMoves, rebuild};
use super::{
    Cell, Kind, Lattice, Vertex, VertexKey, all_finite, angle_between, positive_finite, wrap,
};
use crate::legs::{Direction, Leg};
use glam::DVec3;
use std::fmt;

mod errors;
mod loop_row;
mod open_row;
mod pivot;

pub use errors::GrowthError;
pub(crate) use errors::Param;
use errors::*;
pub(crate) use pivot::resolve_direction;
use pivot::*;
pub use pivot::{FrontFrame, front_frame};

/// Cells whose opening angle is this close to 0 or pi are refused.
pub(crate) const EPS_ANGLE: f64 = 1e-6;
/// Upper bound on lattice size, so an absurd recipe fails with a message
/// instead of exhausting memory (about 150 bytes a cell).
pub(crate) const MAX_CELLS: usize = 4_000_000;

/// The free parameters of one row (docs/math.md 5, 6.2, 7).
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
    /// Loops: where the new vertex `x[i+1][1]` goes (symmetric rows), or which
    /// closing direction to take (the one landing nearest it).
    pub target: Option<DVec3>,
    /// Loops: the closing direction to take, 1 or 2, counted from the cone
    /// axis of cell 0 outwards. Default: 1, the more open cell.
    pub candidate: Option<usize>,
    /// Intrinsic growth: rebuild the front before growing on it.
    pub front: Option<FrontMoves>,
}

// The growth errors of docs/math.md 9 are kinds of the one error enum.
use crate::diagnostic::ErrorKind;

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
        return Err(GrowthError::of_design(
            ErrorKind::TooLarge,
            Param::SeedPoints,
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

/// How a loop row was closed (docs/math.md 6.2), for the verification report.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosureRecord {
    pub(crate) row: usize,
    /// The holonomy was the identity: the direction was a design input.
    pub free: bool,
    /// Admissible closing directions found (generic case).
    pub(crate) candidates: usize,
    /// `|v2' - v2|` after the row was built.
    pub residual: f64,
    pub(crate) ill_conditioned: bool,
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
        use ErrorKind as K;
        let closed = kind == Kind::Loop;
        let min = if closed { 3 } else { 2 };
        if points.len() < min {
            return Err(GrowthError::of_design(
                K::SeedTooShort,
                Param::SeedPoints,
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
            stacking: Default::default(),
        };
        seed_front(&mut lattice, points, kappa)?;
        if closed {
            let perimeter: f64 = (0..width)
                .map(|j| points[j].distance(points[(j + 1) % width]))
                .sum();
            let sum: f64 = kappa.iter().sum();
            if !(sum.abs() <= 1e-9 * perimeter) {
                return Err(GrowthError::of_design(
                    K::LoopKappaSumNonzero,
                    Param::SeedKappa(width),
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
    pub(crate) fn reserve_rows(&mut self, rows: usize) {
        let n = self.front_len();
        let lattice = &mut self.lattice;
        lattice.cells.reserve_exact(rows * lattice.width);
        lattice.vertices.reserve_exact(rows * n);
        lattice.fronts.reserve_exact(rows);
    }

    pub(crate) fn lattice(&self) -> &Lattice {
        &self.lattice
    }

    /// The lattice grown so far, ending the growth.
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
    pub(crate) fn front(&self) -> Vec<Point> {
        let n = self.front_len();
        let base = self.lattice.vertices.len() - n;
        self.lattice.vertices[base..]
            .iter()
            .map(|v| Point { pos: v.pos, z: v.z })
            .collect()
    }

    /// Remove the last grown row.
    pub(crate) fn undo_row(&mut self) {
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
                        ErrorKind::FrontNotCompatible,
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

    /// Commit the grown row: new front vertices, then cells left to right.
    fn commit(&mut self, i: usize) -> Result<(), GrowthError> {
        let m = self.lattice.width;
        let n = self.front_len();
        let base = self.lattice.vertices.len() - n;
        let next_base = base + n;
        for j in 0..n {
            let q = self.next[j].expect("front vertex grown");
            if !all_finite([q.pos.x, q.pos.y, q.pos.z, q.z]) {
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
        let dim = self.lattice.dim;
        for (j, pivot) in self.pivots[..m].iter().enumerate() {
            let pivot = pivot.expect("pivot grown");
            let right = wrap(j + 1, n);
            let cell = Cell {
                row: i as u32,
                col: j as u32,
                ul: (base + j) as u32,
                ur: (base + right) as u32,
                ll: (next_base + j) as u32,
                lr: (next_base + right) as u32,
                pivot: pivot.pos,
                z_pivot: pivot.z,
            };
            // The row's top corners, the front just committed before it
            // (one slice, not a lookup a corner).
            let top = &self.lattice.vertices[base..next_base];
            check_corners_turn(dim, &cell, top[j].pos, top[right].pos, first)?;
            self.lattice.cells.push(cell);
            if first.is_none() {
                first = first_turn(&self.lattice);
            }
        }
        Ok(())
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

/// A seed edge must be spacelike: longer than its |kappa| (docs/math.md 9).
fn seed_edge(a: DVec3, b: DVec3, kappa: f64, j: usize) -> Result<(), GrowthError> {
    let t = b - a;
    if kappa.abs() < t.length() {
        return Ok(());
    }
    Err(GrowthError::new(
        ErrorKind::SeedEdgeNotSpacelike,
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

/// Degenerate and inverted cells (docs/math.md 9).
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
    let (ul, ur) = (lattice.vertex(cell.ul).pos, lattice.vertex(cell.ur).pos);
    check_corners_turn(lattice.dim, cell, ul, ur, first)
}

/// `check_cell_turn` of a cell whose stored UL and UR are at `ul` and
/// `ur`, in a lattice of dimension `dim`: inlined into growth's commit,
/// with the rare cases (a cell near the limit, an error) out of line.
#[inline(always)]
fn check_corners_turn(
    dim: usize,
    cell: &Cell,
    ul: DVec3,
    ur: DVec3,
    first: Option<f64>,
) -> Result<(), GrowthError> {
    let p = cell.pivot;
    if !all_finite([p.x, p.y, p.z, cell.z_pivot]) {
        return Err(breakdown(cell.row as usize, cell.col as usize));
    }
    let (ul, ur) = (ul - cell.pivot, ur - cell.pivot);
    let cross = ul.cross(ur);
    // sin^2 phi = |ul x ur|^2 / (|ul|^2 |ur|^2): one square root where the
    // lengths take three, and neither it nor the division for a cell well
    // away from the limit: sin^2 phi >= 4 EPS_ANGLE^2 (twice the angle,
    // far beyond rounding) with a finite, normal denominator gives a
    // finite sin phi >= EPS_ANGLE, the same verdict as the full test.
    let (num, den) = (
        cross.length_squared(),
        ul.length_squared() * ur.length_squared(),
    );
    // (Finite as `<= f64::MAX`: see `finite`. Not `RangeInclusive::
    // contains` for `den`, which clippy suggests: measured, 6 more
    // instructions a cell.)
    if !(den >= f64::MIN_POSITIVE
        && num <= f64::MAX
        && den <= f64::MAX
        && num >= 4.0 * EPS_ANGLE * EPS_ANGLE * den)
    {
        check_angle(cell, ul, ur, num / den)?;
    }
    if dim == 2 && first.is_some_and(|s| s != cross.z.signum()) {
        return Err(inverted(cell));
    }
    Ok(())
}

/// The full test of a cell's opening angle, given `sin^2 phi` and its
/// legs to UL and UR from the pivot: a cell near 0 or 180 deg.
#[cold]
#[inline(never)]
fn check_angle(cell: &Cell, ul: DVec3, ur: DVec3, sin2: f64) -> Result<(), GrowthError> {
    let (i, j) = (cell.row as usize, cell.col as usize);
    let sin_phi = sin2.sqrt();
    if !sin_phi.is_finite() {
        return Err(breakdown(i, j));
    }
    if sin_phi < EPS_ANGLE {
        let phi = angle_between(ul / ul.length(), ur / ur.length());
        let state = if ul.dot(ur) > 0.0 {
            "collapsed (phi near 0)"
        } else {
            "flat-open (phi near 180 deg)"
        };
        return Err(GrowthError::new(
            ErrorKind::DegenerateCell,
            Param::Direction,
            Some(i),
            Some(j),
            format!("the cell is {state}: phi = {:.6} deg", phi.to_degrees()),
            "change this row's direction so the cell opens between 0 and 180 deg",
        ));
    }
    Ok(())
}

/// A cell of a planar lattice turns the same way as the lattice's first
/// cell: this one is mirrored.
#[cold]
#[inline(never)]
fn inverted(cell: &Cell) -> GrowthError {
    GrowthError::new(
        ErrorKind::InvertedCell,
        Param::Direction,
        Some(cell.row as usize),
        Some(cell.col as usize),
        "the cell is mirrored relative to the first cell of the lattice (its rods cross the other way)",
        "keep every row's direction on the same side of the front",
    )
}

/// Lengths in messages: enough digits to compare, no float noise.
pub(crate) fn fmt_len(x: f64) -> String {
    format!("{x:.6} mm")
}
