//! Verification of a regular, extrinsic sheet or loop row by row: each
//! row's legs measured once into arrays (`row.rs`), each invariant's
//! residuals (`residuals.rs`) computed over the row in a simple loop and
//! compared with the check's largest as they are computed (`watch.rs`); a
//! row that may hold a new largest is recorded again one residual at a
//! time. The same residuals, by the same functions on the same operands,
//! in the same order as the pass over the cells (`cells.rs`), so the same
//! report bit for bit, in less time (see `mod.rs`).

use super::collapsed::{Block, Blocks, Collapsed, UNREACHED, offsets, sweep};
use super::incidence::Grid;
use super::report::{Check, Invariant, Report};
use super::residuals::{self as r, Compatibility, Ratio};
use super::row::{Local, Row, fronts, local_residuals};
use super::watch::Watch;
use super::{Lattice, Legs, Vertex, report, vertex_site};
use crate::lattice::Cell;
use std::ops::Range;

/// `verify` of a regular, extrinsic sheet or loop, row by row. None, as
/// soon as a row's cells do not hold the corners of the grid (`verify`
/// then takes the pass over the cells).
pub(super) fn verify_rows(lattice: &Lattice, grid: &Grid) -> Option<Report> {
    use Invariant as I;
    let mut local = Local {
        leg_sum: 0.0,
        straight: Check::new(I::RodStraightness),
        legs_z: Check::new(I::LegsMatchZ),
        seed: Check::new(I::SeedKappa),
        closure: Check::new(I::LoopClosure),
    };
    let mut pairs = Pairs::new();
    let mut collapsed = Collapsed::new(lattice);
    let (mut above, mut here, mut below) = (Row::default(), Row::default(), Row::default());
    if grid.rows > 0 && !here.measure(lattice, grid, 0, &mut local) {
        return None;
    }
    let n = grid.width;
    for i in 0..grid.rows {
        let cells = &lattice.cells[i * n..(i + 1) * n];
        let cell_site = |k: usize| lattice.cell_name(&cells[k]);
        let has_below = i + 1 < grid.rows;
        if has_below && !below.measure(lattice, grid, i + 1, &mut local) {
            return None;
        }
        // The collapsed sweep (each cell's z from the cells before it),
        // with the collapsed rods, whose corners' z are final once the
        // cell is swept.
        let rods_watch = collapsed.sweep_row(lattice, grid, i, &here);
        let n_below = if has_below { n } else { 0 };
        let [top, bottom] = fronts(lattice, grid, i);
        let view = RowView {
            cells,
            top,
            bottom,
            legs: &here.legs[..n],
            means: &here.means[..n],
            invs: &here.invs[..n],
            spans: &here.spans[..n],
            left2: &here.left2[..n],
            finite: here.finite,
            under: &below.legs[..n_below],
            under_means: &below.means[..n_below],
            over: &above.legs[..if i >= 1 { n } else { 0 }],
        };
        // The residuals a cell needs no neighbour for, watched as the row
        // was measured, recorded again for the cells that may raise their
        // check. The collapsed rods are measured again after the sweep if
        // some cell was not reached.
        if collapsed.all_reached {
            let zs = &collapsed.z[i * grid.front..(i + 2) * grid.front];
            let rods = |j: usize| view.rods(zs, j);
            rods_watch.settle(&mut collapsed.rods, 2 * n, rods, cell_site);
        }
        let bends = |j: usize| view.local(j).0;
        here.straight
            .settle(&mut local.straight, 2 * n, bends, cell_site);
        let legs_z = |j: usize| view.local(j).1;
        here.legs_z
            .settle(&mut local.legs_z, 4 * n, legs_z, cell_site);
        let shape = RowShape::of(grid, i, has_below);
        pairs.row(&view, &shape, cell_site, |k| {
            vertex_site(lattice, cells[k].ul as usize)
        });
        std::mem::swap(&mut above, &mut here);
        std::mem::swap(&mut here, &mut below);
    }
    collapsed.last_front(lattice, grid);
    let Local {
        leg_sum,
        straight,
        legs_z,
        seed,
        closure,
    } = local;
    let Pairs {
        pores_h,
        pores_v,
        edges,
        slope,
        intercept,
        natural,
    } = pairs;
    let checks = [
        straight, legs_z, seed, pores_h, pores_v, edges, closure, slope, intercept, natural,
    ];
    Some(report(lattice, leg_sum, checks, collapsed))
}

/// Which cells of a row have which neighbours.
struct RowShape {
    /// Cells `0..paired` have a right neighbour: all of a loop's, all but
    /// a sheet's last.
    paired: usize,
    /// Cells `0..below` have a neighbour below (none in the last row).
    below: usize,
    /// The cells whose UL vertex is interior (cells above it and to its
    /// left): none in the first row, all but a sheet's first column after.
    interior: Range<usize>,
}

impl RowShape {
    fn of(grid: &Grid, i: usize, has_below: bool) -> Self {
        let n = grid.width;
        // The first cell whose UL vertex has a cell on its left.
        let from = if grid.closed { 0 } else { 1 };
        Self {
            paired: if grid.closed { n } else { n - 1 },
            below: if has_below { n } else { 0 },
            interior: if i >= 1 { from..n } else { 0..0 },
        }
    }
}

/// The checks of residuals between neighbours, row by row.
struct Pairs {
    pores_h: Check,
    pores_v: Check,
    edges: Check,
    slope: Check,
    intercept: Check,
    natural: Check,
}

impl Pairs {
    fn new() -> Self {
        use Invariant as I;
        let [pores_h, pores_v, edges, slope, intercept, natural] = [
            I::HorizontalPores,
            I::VerticalPores,
            I::SharedEdges,
            I::CompatibilitySlope,
            I::CompatibilityIntercept,
            I::CompatibilityInterceptNatural,
        ]
        .map(Check::new);
        Self {
            pores_h,
            pores_v,
            edges,
            slope,
            intercept,
            natural,
        }
    }

    /// Each residual with a neighbour over the row `view`, in loops over
    /// the row's cells, compared with its check's largest as it is
    /// computed; then the same residuals again, one at a time, for the
    /// cells that may raise a check (`cell_site` and `vertex_site` name a
    /// cell and its UL vertex).
    fn row(
        &mut self,
        view: &RowView,
        shape: &RowShape,
        cell_site: impl Fn(usize) -> String,
        vertex_site: impl Fn(usize) -> String,
    ) {
        let (paired, n_below) = (shape.paired, shape.below);
        let [mut w_pores_h, mut w_pores_v, mut w_edges] =
            [&self.pores_h, &self.pores_v, &self.edges].map(Watch::of);
        for j in 0..paired {
            let h = view.pore_h(j);
            w_pores_h.cell(j, [h.value()]);
            w_edges.cell(j, [view.edge_right(j, h.den)]);
        }
        for j in 0..n_below {
            let v = view.pore_v(j);
            w_pores_v.cell(j, [v.value()]);
            w_edges.cell(j, [view.edge_below(j, v.den)]);
        }
        let [mut w_slope, mut w_intercept, mut w_natural] =
            [&self.slope, &self.intercept, &self.natural].map(Watch::of);
        for j in shape.interior.clone() {
            let [slope, intercept, natural] = compat_values(view.compat(j));
            w_slope.cell(j, [slope]);
            w_intercept.cell(j, [intercept]);
            w_natural.cell(j, [natural]);
        }
        let pore_h = |j: usize| [view.pore_h(j).value()];
        w_pores_h.settle(&mut self.pores_h, paired, pore_h, &cell_site);
        let pore_v = |j: usize| [view.pore_v(j).value()];
        w_pores_v.settle(&mut self.pores_v, n_below, pore_v, &cell_site);
        // A cell's right edge, then its bottom edge, as the pass over the
        // cells records them.
        let edge = |j: usize| {
            let right = (j < paired).then(|| view.edge_right(j, view.pore_h(j).den));
            let below = (j < n_below).then(|| view.edge_below(j, view.pore_v(j).den));
            [right, below].into_iter().flatten()
        };
        w_edges.settle(&mut self.edges, paired + n_below, edge, &cell_site);
        let interior = shape.interior.len();
        let compat = |j: usize| compat_values(view.compat(j));
        w_slope.settle(&mut self.slope, interior, |j| [compat(j)[0]], &vertex_site);
        w_intercept.settle(
            &mut self.intercept,
            interior,
            |j| [compat(j)[1]],
            &vertex_site,
        );
        w_natural.settle(
            &mut self.natural,
            interior,
            |j| [compat(j)[2]],
            &vertex_site,
        );
    }
}

/// The three residuals of a four-map composition, as `Check::record` and
/// `Check::record_ratio` of the pass over the cells give them.
#[inline(always)]
fn compat_values(c: Compatibility) -> [f64; 3] {
    [c.slope, c.intercept.value(), c.natural.value()]
}

/// One row's measured arrays (`Row`) and its neighbours' legs, the
/// operands of each residual of a cell read by one method, inlined: the
/// watch over the row and the replay of a row that may hold a new largest
/// use the same arithmetic.
struct RowView<'a> {
    cells: &'a [Cell],
    /// The row's top and bottom fronts (its corners).
    top: &'a [Vertex],
    bottom: &'a [Vertex],
    legs: &'a [Legs],
    means: &'a [f64],
    invs: &'a [f64],
    spans: &'a [[f64; 2]],
    left2: &'a [f64],
    /// Every corner of the row is finite (`Row::finite`).
    finite: bool,
    /// The legs and mean legs of the row below (empty for the last row).
    under: &'a [Legs],
    under_means: &'a [f64],
    /// The legs of the row above (empty for the first row).
    over: &'a [Legs],
}

impl RowView<'_> {
    /// The corner vertices `[UL, UR, LL, LR]` of cell j.
    #[inline(always)]
    fn corners(&self, j: usize) -> [&Vertex; 4] {
        let right = if j + 1 == self.top.len() { 0 } else { j + 1 };
        [
            &self.top[j],
            &self.top[right],
            &self.bottom[j],
            &self.bottom[right],
        ]
    }

    /// Cell j's residuals that need no neighbour (`local_residuals`),
    /// again: for the replays of `Row::measure`'s watches.
    #[inline(always)]
    fn local(&self, j: usize) -> ([f64; 2], [f64; 4]) {
        let (cell, corners) = (&self.cells[j], self.corners(j));
        let d = r::to_pivot(cell.pivot, corners.map(|v| v.pos));
        local_residuals(cell, corners, d, self.legs[j], self.invs[j])
    }

    /// The horizontal pore between cell j and its right neighbour (the
    /// next cell, the first for a loop's last).
    #[inline(always)]
    fn pore_h(&self, j: usize) -> Ratio {
        let k = if j + 1 == self.legs.len() { 0 } else { j + 1 };
        r::horizontal_pore((self.legs[j], self.means[j]), (self.legs[k], self.means[k]))
    }

    /// The vertical pore between cell j and the cell below.
    #[inline(always)]
    fn pore_v(&self, j: usize) -> Ratio {
        r::vertical_pore(
            (self.legs[j], self.means[j]),
            (self.under[j], self.under_means[j]),
        )
    }

    /// `r::same_edge(a, b, s)` for two corners `a`, `b` of cell j
    /// (indices into its corners), without reading them when the row's
    /// corners are all finite. An extrinsic lattice's neighbours hold the
    /// same stored corners: `r::shared_edge` of them is `same_edge`.
    #[inline(always)]
    fn edge(&self, j: usize, [a, b]: [usize; 2], s: f64) -> f64 {
        if self.finite {
            r::same_edge(glam::DVec3::ZERO, glam::DVec3::ZERO, s)
        } else {
            let corners = self.corners(j);
            r::same_edge(corners[a].pos, corners[b].pos, s)
        }
    }

    /// Cell j's right edge UR-LR against its neighbour's left edge, on
    /// scale `s`.
    #[inline(always)]
    fn edge_right(&self, j: usize, s: f64) -> f64 {
        self.edge(j, [1, 3], s)
    }

    /// Cell j's bottom edge LL-LR against the top edge of the cell below.
    #[inline(always)]
    fn edge_below(&self, j: usize, s: f64) -> f64 {
        self.edge(j, [2, 3], s)
    }

    /// The four-map composition at cell j's UL vertex, whose cells above
    /// and to the left exist (a loop's left of column 0 is its last
    /// column): cell j is its UL, the cell above its LL, the cell above
    /// left its LR, the cell left its UR.
    #[inline(always)]
    fn compat(&self, j: usize) -> Compatibility {
        let left = if j == 0 { self.legs.len() - 1 } else { j - 1 };
        let (legs, over) = (self.legs, self.over);
        r::compatibility(legs[j], over[j], over[left], legs[left], self.left2[j])
    }

    /// Cell j's collapsed rods, `zs` the recomputed z of the row's two
    /// fronts.
    #[inline(always)]
    fn rods(&self, zs: &[f64], j: usize) -> [f64; 2] {
        let front = zs.len() / 2;
        let right = if j + 1 == front { 0 } else { j + 1 };
        let at = [zs[j], zs[right], zs[front + j], zs[front + right]];
        r::collapsed_rods(at, self.spans[j], self.invs[j])
    }
}

/// The collapsed state's sweep by rows.
impl Collapsed {
    /// `step` of every cell of row `i` of a grid in turn (`row` its
    /// measures): the corners of cell `(i, j)` are columns `j` and `j + 1`
    /// (wrapped) of the row's two fronts, one slice of the z. Its rods are
    /// compared with their check's largest as each cell is swept; the
    /// watch is returned, for the caller to settle if every cell so far
    /// was reached.
    fn sweep_row(&mut self, lattice: &Lattice, grid: &Grid, i: usize, row: &Row) -> Watch {
        let (width, front) = (grid.width, grid.front);
        let cells = &lattice.cells[i * width..(i + 1) * width];
        let z = &mut self.z[i * front..(i + 2) * front];
        // The comparison with the construction of the row's pivots.
        let mut block = Block::EMPTY;
        let mut rods = Watch::of(&self.rods);
        let measures = row.legs.iter().zip(&row.invs).zip(&row.spans);
        for (j, (cell, ((legs, &inv), &spans))) in cells.iter().zip(measures).enumerate() {
            let right = if j + 1 == front { 0 } else { j + 1 };
            let at = [j, right, front + j, front + right];
            let site = || lattice.cell_name(cell);
            let (k, zp, zs) = sweep(&mut self.single, z, at, offsets(*legs), inv, site);
            self.reached.push(k);
            rods.cell(j, r::collapsed_rods(zs, spans, inv));
            // The pivot's z is what `finish` takes again (NaN if unreached).
            block.add(r::matches_construction(zp, cell.z_pivot));
            self.all_reached &= k != UNREACHED;
        }
        let blocks = self.blocks.get_or_insert_with(|| Blocks::new(grid));
        blocks.rows.push(block);
        // Front i's z are final once its two rows of cells are swept.
        Self::front_block(blocks, lattice, &self.z, i);
        rods
    }

    /// The block of front `f` of a grid swept by rows, and its extent.
    fn front_block(blocks: &mut Blocks, lattice: &Lattice, z: &[f64], f: usize) {
        let front = blocks.front;
        let range = f * front..(f + 1) * front;
        let mut block = Block::EMPTY;
        let mut extent = blocks.extent;
        for (zc, vertex) in z[range.clone()].iter().zip(&lattice.vertices[range]) {
            // `extent.max(vertex_extent(vertex))` (an extent is never
            // NaN), a comparison each: `f64::max` of the coordinates'
            // largest and `|z|` leaves out whichever is NaN, as a
            // comparison does.
            let [xyz, z] = [vertex.pos.abs().max_element(), vertex.z.abs()];
            if xyz > extent {
                extent = xyz;
            }
            if z > extent {
                extent = z;
            }
            block.add(r::matches_construction(*zc, vertex.z));
        }
        blocks.extent = extent;
        blocks.fronts.push(block);
    }

    /// The last front of a grid swept by rows (`rows` of them).
    fn last_front(&mut self, lattice: &Lattice, grid: &Grid) {
        let blocks = self.blocks.get_or_insert_with(|| Blocks::new(grid));
        Self::front_block(blocks, lattice, &self.z, grid.rows);
    }
}
