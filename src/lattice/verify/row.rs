//! One row of a regular grid measured once, in structure-of-arrays form,
//! for the rows' pass (`rows.rs`): each cell's legs and what its
//! neighbours' residuals need, and as it goes the residuals a cell needs
//! no neighbour for.

use super::incidence::Grid;
use super::report::Check;
use super::residuals as r;
use super::watch::Watch;
use super::{Lattice, Legs, Vertex, mean};
use crate::lattice::{Cell, Kind};
use glam::DVec3;

/// One row of a grid's cells, measured once (structure of arrays): each
/// cell's legs, mean leg and its inverse, and what the checks with its
/// neighbours need of its corners, so that no corner is copied. The
/// residuals a cell needs no neighbour for (its rods' bends, its legs
/// against the construction z) are computed as the row is measured, with
/// the corners at hand, and compared with their checks' largest then
/// (`Watch`: a largest of an earlier row is never above the one the row is
/// settled against, so the watch lets through at least the cells it must).
#[derive(Default)]
pub(super) struct Row {
    pub(super) legs: Vec<Legs>,
    pub(super) means: Vec<f64>,
    /// `1 / means[j]`: one division a cell, where the sweep, the legs'
    /// and the rods' residuals each took it.
    pub(super) invs: Vec<f64>,
    /// `|LR - UL|` and `|LL - UR|`: the rods' lengths the collapsed state
    /// must keep.
    pub(super) spans: Vec<[f64; 2]>,
    /// `|UL - LL|^2`: the compatibility's scale at the cell's UL vertex.
    pub(super) left2: Vec<f64>,
    /// Every mean leg of the row is finite, so every corner is: a corner
    /// with a NaN or infinite coordinate makes its leg NaN or infinite.
    pub(super) finite: bool,
    pub(super) straight: Watch,
    pub(super) legs_z: Watch,
}

/// What the rows' pass records as it measures each row, in cell order:
/// the sum of the mean legs, the checks a cell needs no neighbour for
/// (watched: rod straightness, legs against z; recorded: the first row's
/// and the loop's first column's rare checks).
pub(super) struct Local {
    pub(super) leg_sum: f64,
    pub(super) straight: Check,
    pub(super) legs_z: Check,
    pub(super) seed: Check,
    pub(super) closure: Check,
}

/// Fronts `i` and `i + 1` of a grid, the top and bottom corners of row `i`.
pub(super) fn fronts<'a>(lattice: &'a Lattice, grid: &Grid, i: usize) -> [&'a [Vertex]; 2] {
    let front = grid.front;
    let v = &lattice.vertices;
    [
        &v[i * front..(i + 1) * front],
        &v[(i + 1) * front..(i + 2) * front],
    ]
}

/// A cell's residuals that need no neighbour, from its corner vertices
/// `[UL, UR, LL, LR]`, the vectors from them to its pivot (`r::to_pivot`),
/// its legs and `1 / mean leg`: its rods' bends (A, B) and its legs
/// against the construction z. One formula for `Row::measure` and the
/// replays.
#[inline(always)]
pub(super) fn local_residuals(
    cell: &Cell,
    [ul, ur, ll, lr]: [&Vertex; 4],
    d: [DVec3; 4],
    legs: Legs,
    inv: f64,
) -> ([f64; 2], [f64; 4]) {
    let bends = r::rods(d, legs).map(r::bend);
    let z = [ul.z, ur.z, ll.z, lr.z];
    (bends, r::legs_z(legs, z, cell.z_pivot, inv))
}

impl Row {
    /// Measure row `i` of `grid` (extrinsic: every corner is its vertex's
    /// stored position, the legs the same bits as `Lattice::legs`) and
    /// record its cells into `local`; false when some cell of the row does
    /// not hold its grid corners (`Grid::holds`), and the row's measures
    /// are then meaningless.
    pub(super) fn measure(
        &mut self,
        lattice: &Lattice,
        grid: &Grid,
        i: usize,
        local: &mut Local,
    ) -> bool {
        let (width, front) = (grid.width, grid.front);
        let cells = &lattice.cells[i * width..(i + 1) * width];
        let [top, bottom] = fronts(lattice, grid, i);
        self.legs.resize(width, [0.0; 4]);
        self.means.resize(width, 0.0);
        self.invs.resize(width, 0.0);
        self.spans.resize(width, [0.0; 2]);
        self.left2.resize(width, 0.0);
        let out = self.legs.iter_mut().zip(&mut self.means).zip(
            self.invs
                .iter_mut()
                .zip(self.spans.iter_mut().zip(&mut self.left2)),
        );
        let (mut straight, mut legs_z) = (Watch::of(&local.straight), Watch::of(&local.legs_z));
        let is_loop = lattice.kind == Kind::Loop;
        let (mut regular, mut finite) = (true, true);
        for (j, (cell, ((legs, mean_leg), (inv, (span, left2))))) in
            cells.iter().zip(out).enumerate()
        {
            let right = if j + 1 == front { 0 } else { j + 1 };
            // `grid.holds(i, j, cell)`, from the indices at hand, without
            // a branch.
            let (t, b) = (i * front, (i + 1) * front);
            regular &= (cell.ul as usize == t + j)
                & (cell.ur as usize == t + right)
                & (cell.ll as usize == b + j)
                & (cell.lr as usize == b + right);
            let vertices = [&top[j], &top[right], &bottom[j], &bottom[right]];
            let corners = vertices.map(|v| v.pos);
            let [ul, _, ll, _] = corners;
            let d = r::to_pivot(cell.pivot, corners);
            *legs = d.map(DVec3::length);
            *mean_leg = mean(legs);
            *inv = 1.0 / *mean_leg;
            *span = r::rod_spans(corners);
            *left2 = r::left_edge_squared(ul, ll);
            local.leg_sum += *mean_leg;
            finite &= crate::lattice::finite(*mean_leg);
            let (bends, legs_zs) = local_residuals(cell, vertices, d, *legs, *inv);
            straight.cell(j, bends);
            legs_z.cell(j, legs_zs);
            let site = || lattice.cell_name(cell);
            if is_loop && cell.col == 0 {
                // Rod B of cell 0 ends where the round of transfers came back.
                local.closure.record(bends[1], site);
            }
            if cell.row == 0 {
                // `Lattice::kappa` of a cell holding its grid corners.
                let kappa = top[j].z - top[right].z;
                local.seed.record(r::seed_kappa(*legs, kappa, *inv), site);
            }
        }
        (self.finite, self.straight, self.legs_z) = (finite, straight, legs_z);
        regular
    }
}
