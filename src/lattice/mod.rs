//! The grown lattice: vertices, cells (with their scissor pivots), and what is
//! derived from them (legs, rods, joints). Notation follows docs/math.md section 1.
//!
//! Geometry is stored in `DVec3` for both 2-D and 3-D lattices; a 2-D lattice
//! keeps its third coordinate at exactly 0 and `dim` says how many
//! coordinates are meaningful.

mod closure;
mod construct;
pub mod deploy;
mod front;
mod grow;
mod helix;
mod joints;
mod placed;
mod rods;
mod saddle;
pub mod shape;
mod verify;

pub(crate) use construct::{Point, pivot_from_v2};
pub use front::{Crank, FrontMoves, PivotMove};
pub use grow::{
    ClosureRecord, FrontFrame, Grower, GrowthError, RowParams, front_frame, grow, grow_sheet,
};
pub(crate) use grow::{MAX_CELLS, Param, resolve_direction};
pub use helix::{grow_helix, grow_helix_partial, seed_defect};
pub use joints::{Joint, JointEnd, joints};
pub(crate) use joints::{RodEnd, vertex_eyelet_count, vertex_eyelets};
pub use rods::{Rod, RodType};
pub use saddle::Saddle;
pub(crate) use saddle::lay as lay_on_saddle;
pub use verify::{Check, DRIFT_PER_LEG, Invariant, Report, TOLERANCE, verify};

use glam::DVec3;

/// Topology of the seed front.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Open front with two free edges (docs/math.md 6.1).
    Sheet,
    /// Periodic front: a tube or annulus (docs/math.md 6.2).
    Loop,
    /// A single front wrapping onto itself, one cell a step (docs/math.md 6.3).
    Helix,
}

impl Kind {
    /// The lowercase name recipes, lattice.json and messages use: `sheet`,
    /// `loop` or `helix`.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Sheet => "sheet",
            Kind::Loop => "loop",
            Kind::Helix => "helix",
        }
    }
}

/// How a vertex is named in lattice.json: `[i, j]` for sheets and loops;
/// a helix vertex `y_k` has `row = 0`, `col = k` and is written `[k]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexKey {
    /// Row `i` of the vertex (its front); 0 for every helix vertex.
    pub row: u32,
    /// Column `j` along the front; `k` for a helix vertex `y_k`.
    pub col: u32,
}

/// A vertex pivot `x[i][j]` with its collapsed coordinate `z` (docs/math.md 3.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// How lattice.json and messages name the vertex.
    pub key: VertexKey,
    /// Position in mm (third coordinate 0 in 2-D); in an intrinsic lattice, in
    /// the frame of the row that grew it.
    pub pos: DVec3,
    /// Collapsed coordinate (mm): where the vertex lies on the common line when
    /// every cell is closed to `phi = 0`.
    pub z: f64,
}

/// Cell `(row, col)`: four corner vertices (indices into `Lattice::vertices`)
/// and the scissor pivot where its two rods cross. Helix cell `k` has
/// `row = k / N` (the turn) and `col = k % N`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    /// Row `i` of the cell (its growth step; the turn for a helix).
    pub row: u32,
    /// Column `j` within the row.
    pub col: u32,
    /// Upper-left corner `x[i][j]`, where rod A starts (index into `Lattice::vertices`).
    pub ul: u32,
    /// Upper-right corner `x[i][j+1]`, where rod B starts.
    pub ur: u32,
    /// Lower-left corner `x[i+1][j]`, where rod B ends.
    pub ll: u32,
    /// Lower-right corner `x[i+1][j+1]`, where rod A ends.
    pub lr: u32,
    /// Scissor pivot `p[i][j]` where rods A and B cross (mm, in the row's frame).
    pub pivot: DVec3,
    /// Collapsed coordinate of the pivot (mm): `z(UL) + l1 = z(UR) + l4`.
    pub z_pivot: f64,
}

impl Cell {
    /// Its corners `[UL, UR, LL, LR]` as vertex indices, in the order of
    /// `Lattice::corners`.
    #[inline]
    pub fn corner_ids(&self) -> [u32; 4] {
        [self.ul, self.ur, self.ll, self.lr]
    }
}

/// Legs of a cell measured from the pivot: `[l1, l2, l3, l4]` to UL, LL, LR, UR.
pub(crate) type Legs = [f64; 4];

/// A grown scissor lattice: its vertex pivots and cells, from which legs,
/// rods and joints are derived. Lengths in mm.
#[derive(Clone, Debug, PartialEq)]
pub struct Lattice {
    /// Topology of the seed front: sheet, loop or helix.
    pub kind: Kind,
    /// Embedding dimension, 2 or 3.
    pub dim: usize,
    /// Cells per row: m for a sheet (m + 1 vertices a row), N for a loop
    /// (N vertices a row) and for a helix (its loop length).
    pub width: usize,
    /// Vertices in creation order: the seed front, then row by row, left to right.
    pub vertices: Vec<Vertex>,
    /// Cells row by row, left to right (helix cells in k order).
    pub cells: Vec<Cell>,
    /// Intrinsic growth (docs/math.md 7): for each row grown on a rebuilt front,
    /// that front's positions (one per front vertex, in the row's own
    /// frame); empty for a row grown on the previous row's vertices. Empty
    /// altogether for an extrinsic lattice.
    pub(crate) fronts: Vec<Vec<DVec3>>,
    /// How strips are given their stacking layers (see `layer`).
    pub stacking: Stacking,
}

/// Which neighbours of a loop alternate their stacking layers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Stacking {
    /// Rows alternate (every lattice unless the recipe asks otherwise).
    #[default]
    Rows,
    /// Columns alternate: for loops of an even number of columns.
    Columns,
}

impl Lattice {
    /// Each cell as a quadrilateral facet of vertex indices (upper left,
    /// upper right, lower right, lower left), for fits to a target.
    pub fn facets(&self) -> Vec<[u32; 4]> {
        self.cells
            .iter()
            .map(|c| [c.ul, c.ur, c.lr, c.ll])
            .collect()
    }

    /// The sizes of a ring of per-vertex sums (vertex v in slot v mod
    /// size) for passes over the cells in order, and the size that holds
    /// every vertex: growth numbers a cell's corners within about two
    /// fronts of each other, so a few thousand slots stand for the whole
    /// lattice (and stay in cache). A pass whose corners spread wider than
    /// the ring starts again with the full size; both give the same sums.
    pub(crate) fn vertex_rings(&self) -> (usize, usize) {
        let full = self.vertices.len().next_power_of_two();
        ((2 * self.width + 8).next_power_of_two().min(full), full)
    }

    /// Number of grown rows of cells (started turns, for a helix).
    pub fn rows(&self) -> usize {
        self.cells.len().div_ceil(self.width.max(1))
    }

    /// Number of growth steps: a row for sheets and loops, a cell for helices.
    pub fn steps(&self) -> usize {
        match self.kind {
            Kind::Helix => self.cells.len(),
            _ => self.rows(),
        }
    }

    /// The growth step that adds cell `index`.
    pub fn step_of(&self, index: usize) -> usize {
        match self.kind {
            Kind::Helix => index,
            _ => self.cells[index].row as usize,
        }
    }

    /// True unless some row grew on a rebuilt front (docs/math.md 7).
    pub fn extrinsic(&self) -> bool {
        self.fronts.iter().all(Vec::is_empty)
    }

    /// The vertex at `index` in `Lattice::vertices`.
    #[inline]
    pub fn vertex(&self, index: u32) -> &Vertex {
        &self.vertices[index as usize]
    }

    /// Corner positions `[UL, UR, LL, LR]` in the cell's own frame: the top
    /// corners come from the row's rebuilt front when it has one.
    /// Inlined and without temporaries: verification and growth call it
    /// several times a cell (it was a quarter of their time).
    #[inline]
    pub fn corners(&self, cell: &Cell) -> [DVec3; 4] {
        let v = &self.vertices;
        let (ll, lr) = (v[cell.ll as usize].pos, v[cell.lr as usize].pos);
        let (ul, ur) = (&v[cell.ul as usize], &v[cell.ur as usize]);
        match self.fronts.get(cell.row as usize) {
            Some(front) if !front.is_empty() => [
                front[ul.key.col as usize],
                front[ur.key.col as usize],
                ll,
                lr,
            ],
            _ => [ul.pos, ur.pos, ll, lr],
        }
    }

    /// Corner `k` (0 to 3: UL, UR, LL, LR) of `corners`, alone.
    #[inline]
    pub(crate) fn corner(&self, cell: &Cell, k: usize) -> DVec3 {
        let v = &self.vertices[cell.corner_ids()[k] as usize];
        match self.fronts.get(cell.row as usize) {
            Some(front) if k < 2 && !front.is_empty() => front[v.key.col as usize],
            _ => v.pos,
        }
    }

    /// A vertex as lattice.json and messages name it: `[i, j]`, or `[k]`.
    pub(crate) fn vertex_name(&self, index: u32) -> String {
        let k = self.vertex(index).key;
        match self.kind {
            Kind::Helix => format!("[{}]", k.col),
            _ => format!("[{}, {}]", k.row, k.col),
        }
    }

    /// A cell as messages name it.
    pub fn cell_name(&self, cell: &Cell) -> String {
        match self.kind {
            Kind::Helix => format!(
                "cell {}",
                cell.row as usize * self.width + cell.col as usize
            ),
            _ => format!("cell (row {}, column {})", cell.row, cell.col),
        }
    }

    /// Stacking layer of a rod (docs/math.md 10.2): all strips meeting at any
    /// joint get distinct layers, contiguous (0..3 at a full joint).
    pub fn layer(&self, cell: &Cell, kind: RodType) -> u32 {
        let ab = match kind {
            RodType::A => 0,
            RodType::B => 1,
        };
        match self.kind {
            Kind::Helix => {
                let n = self.width as u32;
                let k = cell.row * n + cell.col;
                // The smallest q >= 2 dividing neither N - 1 nor N + 1.
                let q = (2..)
                    .find(|q| !(n - 1).is_multiple_of(*q) && !(n + 1).is_multiple_of(*q))
                    .expect("some q divides neither");
                2 * (k % q) + ab
            }
            // Columns alternate instead of rows (an even loop whose recipe
            // asks for it): two A (or B) strips of neighbouring columns then
            // never share a layer, so a ring closing in on the axis (the
            // pole of a dome) is bounded by strips two columns apart, not
            // one. Every joint still holds layers 0..3 once each: row i's A
            // and row i-1's B of column j, row i's B and row i-1's A of
            // column j - 1, whose parities differ.
            Kind::Loop if self.stacking == Stacking::Columns && self.width.is_multiple_of(2) => {
                2 * (cell.col % 2) + ab
            }
            _ => 2 * (cell.row % 2) + ab,
        }
    }

    /// Legs as distances from the pivot to the stored corners (never copied
    /// from the construction, so checks on them mean something).
    #[inline]
    pub fn legs(&self, cell: &Cell) -> Legs {
        shape::legs_of(self.corners(cell), cell.pivot)
    }

    /// The collapsibility parameter `kappa = z(UL) - z(UR)` of a cell.
    pub(crate) fn kappa(&self, cell: &Cell) -> f64 {
        self.vertex(cell.ul).z - self.vertex(cell.ur).z
    }

    /// Opening angle `phi` at the pivot between legs 1 and 4 (docs/math.md 1.3).
    pub fn phi(&self, cell: &Cell) -> f64 {
        let [ul, ur, _, _] = self.corners(cell);
        let v1 = (cell.pivot - ul).normalize();
        let v2 = (cell.pivot - ur).normalize();
        angle_between(v1, v2)
    }

    /// Largest coordinate magnitude and leg: the length scale of the lattice.
    pub fn extent(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for p in self
            .vertices
            .iter()
            .map(|v| v.pos)
            .chain(self.cells.iter().map(|c| c.pivot))
        {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        (lo, hi)
    }
}

/// `k % n`, with the division only when `k` is past the end: growth and
/// verification step round a front a vertex or two at a time, and an
/// integer division costs tens of cycles where the comparison costs one.
#[inline(always)]
pub(crate) fn wrap(k: usize, n: usize) -> usize {
    if k < n { k } else { k % n }
}

// Finiteness tests written as comparisons with `f64::MAX`: LLVM turns
// `is_finite()` and `x < INFINITY`, with `x > 0.0` beside them, into a
// test of the number's class done on its bits in integer registers, 16
// instructions for `is_finite() && x > 0.0` where the two comparisons
// below are 4, and growth runs such a test on every leg it makes.

/// `x` is finite: `|x| <= f64::MAX` (false for a NaN and an infinity).
#[inline(always)]
pub(crate) fn finite(x: f64) -> bool {
    x.abs() <= f64::MAX
}

/// Every one of `xs` is finite (`finite`), tested without a branch each.
#[inline(always)]
pub(crate) fn all_finite<const N: usize>(xs: [f64; N]) -> bool {
    xs.iter().fold(true, |all, &x| all & finite(x))
}

/// `x` is finite and above 0 (false for a NaN).
#[inline(always)]
pub(crate) fn positive_finite(x: f64) -> bool {
    x > 0.0 && x <= f64::MAX
}

/// Angle between two unit vectors, accurate near 0 and pi (atan2 form).
pub(crate) fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

#[cfg(test)]
mod tests {
    use super::{all_finite, finite, positive_finite};

    /// The comparisons with `f64::MAX` give `is_finite`'s verdicts on
    /// every kind of number.
    #[test]
    fn finiteness_tests_agree_with_is_finite() {
        let values = [
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
            f64::MIN_POSITIVE / 4.0,
            -f64::MIN_POSITIVE / 4.0,
            1.0,
            -1.0,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
        ];
        for x in values {
            assert_eq!(finite(x), x.is_finite(), "{x}");
            assert_eq!(positive_finite(x), x.is_finite() && x > 0.0, "{x}");
            for y in values {
                let both = x.is_finite() && y.is_finite();
                assert_eq!(all_finite([x, y, 1.0, -2.0]), both, "{x} {y}");
                assert_eq!(all_finite([1.0, y, x]), both, "{x} {y}");
            }
        }
    }
}

/// Small lattices for the unit tests of the lattice's modules.
#[cfg(test)]
pub(crate) mod fixtures {
    use super::{Kind, Lattice, RowParams, grow};
    use crate::legs::{Direction, Leg};
    use glam::DVec3;

    /// A sheet grown on `points` with these `kappa`, `rows` rows at
    /// `angle_deg` from site `start`, both ends matched.
    pub(crate) fn sheet(
        points: &[DVec3],
        kappa: &[f64],
        start: usize,
        angle_deg: f64,
        rows: usize,
    ) -> Lattice {
        let row = RowParams {
            start,
            direction: Some(Direction::Angles {
                angle_deg,
                tilt_deg: 0.0,
            }),
            left_leg: Leg::Match,
            right_leg: Leg::Match,
            ..RowParams::default()
        };
        grow(Kind::Sheet, 2, points, kappa, &vec![row; rows]).unwrap()
    }

    /// `n + 1` seed points 10 mm apart on the x axis.
    pub(crate) fn line(n: usize) -> Vec<DVec3> {
        (0..=n)
            .map(|j| DVec3::new(10.0 * j as f64, 0.0, 0.0))
            .collect()
    }
}
