//! Rods: the two straight members of each cell (docs/math.md 1.2, 10.1).

use super::{Cell, Lattice};
use glam::DVec3;

/// Which of a cell's two crossing rods (docs/math.md 1.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RodType {
    /// UL -> pivot -> LR, legs l1 and l3.
    A,
    /// UR -> pivot -> LL, legs l4 and l2.
    B,
}

impl RodType {
    pub(crate) fn letter(self) -> &'static str {
        match self {
            RodType::A => "A",
            RodType::B => "B",
        }
    }
}

/// One rod with its three holes: start vertex, scissor pivot, end vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rod {
    /// `2 * cell index` for A, `+ 1` for B (lattice.json order).
    pub(crate) id: usize,
    pub(crate) cell: usize,
    pub(crate) kind: RodType,
    pub(crate) start: u32,
    pub(crate) end: u32,
    /// Leg lengths from the start vertex to the pivot and on to the end.
    pub(crate) legs: [f64; 2],
    /// Hole centres in space: start vertex, pivot, end vertex.
    pub(crate) hole_pos: [DVec3; 3],
}

impl Rod {
    /// Hole-to-hole length.
    pub fn length(&self) -> f64 {
        self.legs[0] + self.legs[1]
    }

    /// Hole positions along the rod's axis, from the start vertex.
    pub(crate) fn holes(&self) -> [f64; 3] {
        [0.0, self.legs[0], self.length()]
    }
}

impl Lattice {
    /// The two rods of a cell, A then B.
    pub(crate) fn cell_rods(&self, index: usize) -> [Rod; 2] {
        let cell: &Cell = &self.cells[index];
        let [l1, l2, l3, l4] = self.legs(cell);
        let [ul, ur, ll, lr] = self.corners(cell);
        [
            Rod {
                id: 2 * index,
                cell: index,
                kind: RodType::A,
                start: cell.ul,
                end: cell.lr,
                legs: [l1, l3],
                hole_pos: [ul, cell.pivot, lr],
            },
            Rod {
                id: 2 * index + 1,
                cell: index,
                kind: RodType::B,
                start: cell.ur,
                end: cell.ll,
                legs: [l4, l2],
                hole_pos: [ur, cell.pivot, ll],
            },
        ]
    }

    /// Every rod in id order.
    pub fn rods(&self) -> impl Iterator<Item = Rod> + '_ {
        (0..self.cells.len()).flat_map(|c| self.cell_rods(c))
    }
}
