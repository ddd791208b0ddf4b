//! Which cell is at each corner of each vertex: the neighbours the pass
//! over the cells (`cells.rs`) reads, from a table of the cells' corner
//! indices, or from the numbering of a regular sheet or loop (`Grid`),
//! whose rows the rows' pass (`rows.rs`) walks.

use crate::lattice::{Cell, Kind, Lattice, wrap};

/// No cell (at this corner of a vertex).
pub(super) const NONE: u32 = u32::MAX;

/// For every vertex, the cell in which it is UL, UR, LL, LR (or NONE).
pub(super) enum Incidence {
    /// Read from the cells' corner indices: a vertex's four side by side,
    /// in one cache line.
    Table(Vec<[u32; 4]>),
    /// A sheet or loop whose every cell has the corner indices of its row
    /// and column, as growth numbers them (checked cell by cell, see
    /// `Incidence::grid`): the table is then a formula, and verification
    /// neither fills nor allocates it (16 bytes a vertex, every page
    /// supplied by the kernel).
    Grid(Grid),
}

/// The numbering of a regular sheet or loop: `rows` rows of `width` cells
/// on fronts of `front` vertices (`width + 1` for a sheet, `width` for a
/// loop, whose cells wrap).
#[derive(Clone, Copy)]
pub(super) struct Grid {
    pub(super) width: usize,
    pub(super) front: usize,
    pub(super) rows: usize,
    pub(super) closed: bool,
}

impl Grid {
    /// The corner indices `[UL, UR, LL, LR]` of cell `(i, j)`.
    #[inline]
    fn corners(&self, i: usize, j: usize) -> [usize; 4] {
        let (top, bottom) = (i * self.front, (i + 1) * self.front);
        let right = wrap(j + 1, self.front);
        [top + j, top + right, bottom + j, bottom + right]
    }

    /// The grid a sheet or loop of whole rows would have, if its cells
    /// hold the corners of their positions (`holds`, checked apart: by
    /// `Incidence::grid` at once, and row by row by `Row::measure`'s
    /// branch-free copy of it) and its vertices are exactly its rows'
    /// fronts.
    pub(super) fn of(lattice: &Lattice) -> Option<Grid> {
        let width = lattice.width;
        let closed = match lattice.kind {
            Kind::Sheet => false,
            Kind::Loop => true,
            Kind::Helix => return None,
        };
        let front = if closed { width } else { width + 1 };
        let cells = lattice.cells.len();
        if width == 0 || (closed && width < 3) || !cells.is_multiple_of(width) {
            return None;
        }
        let grid = Grid {
            width,
            front,
            rows: cells / width,
            closed,
        };
        (lattice.vertices.len() == (grid.rows + 1) * front).then_some(grid)
    }

    /// True when `cell` has the corner indices of cell `(i, j)`.
    #[inline(always)]
    fn holds(&self, i: usize, j: usize, cell: &Cell) -> bool {
        cell.corner_ids().map(|v| v as usize) == self.corners(i, j)
    }

    /// `Incidence::Table`'s entry for the vertex in row `r`, column `c`
    /// of the fronts, from the numbering.
    #[inline(always)]
    pub(super) fn at_vertex(&self, r: usize, c: usize) -> [u32; 4] {
        let cell = |i: usize, j: usize| (i * self.width + j) as u32;
        // The column of the cell left of vertex column c, if any.
        let left = match (c, self.closed) {
            (0, true) => Some(self.width - 1),
            (0, false) => None,
            _ => Some(c - 1),
        };
        let here = (c < self.width).then_some(c);
        let mut out = [NONE; 4];
        if r < self.rows {
            if let Some(j) = here {
                out[UL] = cell(r, j);
            }
            if let Some(j) = left {
                out[UR] = cell(r, j);
            }
        }
        if r >= 1 && r <= self.rows {
            if let Some(j) = here {
                out[LL] = cell(r - 1, j);
            }
            if let Some(j) = left {
                out[LR] = cell(r - 1, j);
            }
        }
        out
    }
}

/// The corners of a cell, as indices into `Incidence::Table`'s entries.
pub(super) const UL: usize = 0;
const UR: usize = 1;
const LL: usize = 2;
const LR: usize = 3;

impl Incidence {
    /// The incidence, in one pass over the cells' corner indices (the legs
    /// are measured later, once, by the checks' `LegWindow`).
    pub(super) fn new(lattice: &Lattice) -> Self {
        match Self::grid(lattice) {
            Some(grid) => Self::Grid(grid),
            None => Self::table(lattice),
        }
    }

    /// The table, read from the cells' corner indices.
    pub(super) fn table(lattice: &Lattice) -> Self {
        let mut inc = vec![[NONE; 4]; lattice.vertices.len()];
        for (c, cell) in lattice.cells.iter().enumerate() {
            inc[cell.ul as usize][UL] = c as u32;
            inc[cell.ur as usize][UR] = c as u32;
            inc[cell.ll as usize][LL] = c as u32;
            inc[cell.lr as usize][LR] = c as u32;
        }
        Self::Table(inc)
    }

    /// The grid of a sheet or loop of whole rows whose every cell has
    /// the corners of its position and whose vertices are exactly its
    /// rows' fronts: then every vertex is each corner of at most the one
    /// cell `Grid::at_vertex` names, which is the table's entry. Anything
    /// else (a helix, a corrupted lattice) gets the table.
    pub(super) fn grid(lattice: &Lattice) -> Option<Grid> {
        let grid = Grid::of(lattice)?;
        let regular = lattice
            .cells
            .chunks_exact(grid.width)
            .enumerate()
            .all(|(i, row)| {
                row.iter()
                    .enumerate()
                    .all(|(j, cell)| grid.holds(i, j, cell))
            });
        regular.then_some(grid)
    }

    /// The cell in which vertex `v` is the corner `corner`; `rc` is the
    /// vertex's row and column on the grid (ignored by a table).
    #[inline(always)]
    pub(super) fn at(&self, v: u32, rc: (usize, usize), corner: usize) -> u32 {
        match self {
            Self::Table(inc) => inc[v as usize][corner],
            Self::Grid(grid) => grid.at_vertex(rc.0, rc.1)[corner],
        }
    }

    /// The cells in which vertex `v` is UL, UR, LL and LR (`rc` as in `at`).
    #[inline(always)]
    pub(super) fn of(&self, v: u32, rc: (usize, usize)) -> [u32; 4] {
        match self {
            Self::Table(inc) => inc[v as usize],
            Self::Grid(grid) => grid.at_vertex(rc.0, rc.1),
        }
    }
}
