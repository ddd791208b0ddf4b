//! The grown lattice: vertices, cells (with their scissor pivots), and what is
//! derived from them (legs, rods, joints). Notation follows MATH.md section 1.
//!
//! Geometry is stored in `DVec3` for both 2-D and 3-D lattices; a 2-D lattice
//! keeps its third coordinate at exactly 0 and `dim` says how many
//! coordinates are meaningful.

mod construct;
mod grow;
mod joints;
mod rods;
mod verify;

pub use grow::{
    FrontFrame, GrowthError, GrowthErrorKind, MAX_CELLS, Param, RowParams, fmt_len, front_frame,
    grow_sheet,
};
pub use joints::{Joint, JointEnd, RodEnd, joints, layer};
pub use rods::{Rod, RodType};
pub use verify::{Invariant, Report, TOLERANCE, verify};

use glam::DVec3;

/// Topology of the seed front.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Open front with two free edges (MATH.md 6.1).
    Sheet,
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::Sheet => "sheet",
        }
    }
}

/// How a vertex is named in lattice.json: `[i, j]` for sheets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VertexKey {
    pub row: u32,
    pub col: u32,
}

/// A vertex pivot `x[i][j]` with its collapsed coordinate `z` (MATH.md 3.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    pub key: VertexKey,
    pub pos: DVec3,
    pub z: f64,
}

/// Cell `(row, col)`: four corner vertices (indices into `Lattice::vertices`)
/// and the scissor pivot where its two rods cross.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    pub row: u32,
    pub col: u32,
    pub ul: u32,
    pub ur: u32,
    pub ll: u32,
    pub lr: u32,
    pub pivot: DVec3,
    pub z_pivot: f64,
}

/// Legs of a cell measured from the pivot: `[l1, l2, l3, l4]` to UL, LL, LR, UR.
pub type Legs = [f64; 4];

#[derive(Clone, Debug, PartialEq)]
pub struct Lattice {
    pub kind: Kind,
    /// Embedding dimension, 2 or 3.
    pub dim: usize,
    /// Cells per row (m); a sheet row has m + 1 vertices.
    pub width: usize,
    /// Vertices in creation order: the seed front, then row by row, left to right.
    pub vertices: Vec<Vertex>,
    /// Cells row by row, left to right.
    pub cells: Vec<Cell>,
}

impl Lattice {
    /// Number of grown rows of cells.
    pub fn rows(&self) -> usize {
        self.cells.len().checked_div(self.width).unwrap_or(0)
    }

    pub fn vertex(&self, index: u32) -> &Vertex {
        &self.vertices[index as usize]
    }

    /// Corner positions `[UL, UR, LL, LR]`.
    pub fn corners(&self, cell: &Cell) -> [DVec3; 4] {
        [cell.ul, cell.ur, cell.ll, cell.lr].map(|v| self.vertex(v).pos)
    }

    /// Legs as distances from the pivot to the stored corners (never copied
    /// from the construction, so checks on them mean something).
    pub fn legs(&self, cell: &Cell) -> Legs {
        let [ul, ur, ll, lr] = self.corners(cell);
        let p = cell.pivot;
        [
            p.distance(ul),
            p.distance(ll),
            p.distance(lr),
            p.distance(ur),
        ]
    }

    /// The collapsibility parameter `kappa = z(UL) - z(UR)` of a cell.
    pub fn kappa(&self, cell: &Cell) -> f64 {
        self.vertex(cell.ul).z - self.vertex(cell.ur).z
    }

    /// Opening angle `phi` at the pivot between legs 1 and 4 (MATH.md 1.3).
    pub fn phi(&self, cell: &Cell) -> f64 {
        let v1 = (cell.pivot - self.vertex(cell.ul).pos).normalize();
        let v2 = (cell.pivot - self.vertex(cell.ur).pos).normalize();
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

/// Angle between two unit vectors, accurate near 0 and pi (atan2 form).
pub fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}
