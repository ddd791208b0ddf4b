//! The collapsed state (docs/verification.md, "The invariants"; docs/math.md
//! 8.3): z recomputed from the leg lengths alone, single-valued, equal to
//! the construction's and keeping every rod's length. Swept a cell at a
//! time by the pass over the cells (`Collapsed::step`) or a row at a time
//! by the rows' pass (`rows.rs`), and compared with the construction once
//! the lattice's mean leg is known (`Collapsed::finish`).

use super::incidence::Grid;
use super::report::{Check, Invariant};
use super::residuals as r;
use super::{Lattice, Legs, mean, vertex_extent, vertex_site};
use glam::DVec3;

/// `Collapsed::reached` of a cell reached through no corner.
pub(super) const UNREACHED: u8 = u8::MAX;

/// docs/math.md 8.3: z from leg lengths alone, starting from `z = 0` at vertex 0,
/// then compared with the construction and with the deployed rod lengths.
/// Cells are stored in growth order, so sweeping them in that order reaches
/// every cell through a corner that already has a z (a breadth-first search
/// would visit the same offsets; this needs no queue). A cell reached
/// through no corner is a disconnected lattice and fails the check.
///
/// The sweep runs a cell at a time inside `verify`'s pass over the cells
/// (`step`), or a row at a time in `verify_rows` (`sweep_row`), with the
/// rod lengths of the cells just swept: their corners' z are final then,
/// unless some cell was not reached, when `finish` measures the rods
/// again after the sweep, as they were measured before. The comparison
/// with the construction needs the lattice's mean leg, known only after
/// the pass: `finish` compares the vertices', then the pivots' in cell
/// order, each pivot's z taken again from the corner it was reached
/// through (a byte a cell remembers which) and that corner's leg,
/// measured again: the same bits, since a z once set never changes. A
/// sweep by rows bounds each front's and row's comparisons (`Block`), and
/// `finish` replays only those that may hold a new largest.
pub(super) struct Collapsed {
    pub(super) single: Check,
    pub(super) rods: Check,
    pub(super) z: Vec<f64>,
    /// For every cell swept, in cell order, the corner (0 to 3: UL, UR,
    /// LL, LR) whose z gave the pivot's, or `UNREACHED`.
    pub(super) reached: Vec<u8>,
    pub(super) all_reached: bool,
    /// Swept by rows (`sweep_row`): a `Block` of the comparison with the
    /// construction for every front of vertices, then every row of cells,
    /// and the largest `vertex_extent`, measured in the rows' pass.
    pub(super) blocks: Option<Blocks>,
}

/// What the rows' pass measured of the comparison with the construction,
/// so that `Collapsed::finish` replays only the fronts and rows that may
/// hold a new largest residual: for a good lattice a few, not the whole
/// lattice read again.
pub(super) struct Blocks {
    /// Vertices a front, cells a row.
    pub(super) front: usize,
    width: usize,
    pub(super) fronts: Vec<Block>,
    pub(super) rows: Vec<Block>,
    pub(super) extent: f64,
}

impl Blocks {
    pub(super) fn new(grid: &Grid) -> Self {
        Self {
            front: grid.front,
            width: grid.width,
            fronts: Vec::with_capacity(grid.rows + 1),
            rows: Vec::with_capacity(grid.rows),
            extent: 0.0,
        }
    }
}

/// The comparisons `num / (global + den)` of a front or row (`num` the
/// difference of the recomputed and the construction z, `den` the
/// construction z's magnitude), summed up: their largest `|num|` and
/// smallest `den` (a NaN left out), and the sum of all of them, which is
/// not finite when any is NaN (or infinite, or the sum overflows: such a
/// block is replayed, which is never wrong).
#[derive(Clone, Copy)]
pub(super) struct Block {
    num: f64,
    den: f64,
    sum: f64,
}

impl Block {
    /// A block of no comparison yet.
    pub(super) const EMPTY: Self = Self {
        num: 0.0,
        den: f64::INFINITY,
        sum: 0.0,
    };

    /// Add a comparison, `r::matches_construction` of a recomputed and a
    /// construction z. Plain comparisons (one instruction each), not
    /// `f64::max` and `min`, whose rules for NaN `sum` already covers.
    #[inline(always)]
    pub(super) fn add(&mut self, (num, den): (f64, f64)) {
        let num_abs = num.abs();
        if num_abs > self.num {
            self.num = num_abs;
        }
        if den < self.den {
            self.den = den;
        }
        self.sum += num + den;
    }

    /// True when none of the block's comparisons can raise `check`, on the
    /// scale `global`: every denominator is at least `d = global + den`
    /// (rounding is monotone), so with `d > 0` every residual is at most
    /// `num / d`, rounded the same way. False whenever a NaN is involved
    /// (or the block's `sum` is not finite),
    /// unless `check`'s largest is already NaN (which nothing raises).
    fn quiet(self, check: &Check, global: f64) -> bool {
        let d = global + self.den;
        check.max.is_nan() || (self.sum.is_finite() && d > 0.0 && self.num / d <= check.max)
    }
}

impl Collapsed {
    pub(super) fn new(lattice: &Lattice) -> Self {
        use Invariant as I;
        let mut z = vec![f64::NAN; lattice.vertices.len()];
        if let Some(first) = z.first_mut() {
            *first = 0.0;
        }
        Self {
            single: Check::new(I::CollapsedSingleValued),
            rods: Check::new(I::CollapsedRodLength),
            z,
            reached: Vec::with_capacity(lattice.cells.len()),
            all_reached: true,
            blocks: None,
        }
    }

    /// Sweep cell `c` (`inv` = 1 / its mean leg, `corners` its corners),
    /// and measure its rods (the rows' pass has `sweep_row` compare each
    /// swept cell's rods with their check as it goes, and settles them
    /// after the row: the z of a swept cell's corners are final).
    #[inline]
    pub(super) fn step(
        &mut self,
        lattice: &Lattice,
        c: usize,
        (legs, inv): (&Legs, f64),
        corners: &[DVec3; 4],
    ) {
        let cell = &lattice.cells[c];
        let at = cell.corner_ids().map(|v| v as usize);
        let site = || lattice.cell_name(cell);
        let (k, _, zs) = sweep(&mut self.single, &mut self.z, at, offsets(*legs), inv, site);
        self.reached.push(k);
        if k == UNREACHED {
            self.all_reached = false;
            return;
        }
        if self.all_reached {
            for residual in r::collapsed_rods(zs, r::rod_spans(*corners), inv) {
                self.rods.record(residual, site);
            }
        }
    }

    /// The comparison with the construction, after the sweep, on the scale
    /// of the lattice's mean leg (`leg_sum` over the cells): the vertices'
    /// first, then the pivots', each front and row replayed unless its
    /// `Block` shows it holds no new largest. Also the largest
    /// `vertex_extent` (measured by the rows' pass, if any).
    pub(super) fn finish(mut self, lattice: &Lattice, leg_sum: f64) -> ([Check; 3], f64) {
        let global = leg_sum / lattice.cells.len().max(1) as f64;
        // Without blocks, the whole lattice is one front and one row, each
        // replayed.
        let blocks = self.blocks.take().unwrap_or_else(|| Blocks {
            front: lattice.vertices.len().max(1),
            width: lattice.cells.len().max(1),
            fronts: Vec::new(),
            rows: Vec::new(),
            extent: lattice
                .vertices
                .iter()
                .fold(0.0, |e: f64, v| e.max(vertex_extent(v))),
        });
        let mut matches = Check::new(Invariant::CollapsedMatchesConstruction);
        self.compare_vertices(
            lattice,
            &mut matches,
            (blocks.front, &blocks.fronts),
            global,
        );
        self.compare_pivots(lattice, &mut matches, (blocks.width, &blocks.rows), global);
        let rods = if self.all_reached {
            self.rods
        } else {
            self.rods_again(lattice)
        };
        ([self.single, matches, rods], blocks.extent)
    }

    /// The vertices' comparison with the construction, `front` vertices a
    /// block (`fronts`, if measured).
    fn compare_vertices(
        &self,
        lattice: &Lattice,
        matches: &mut Check,
        (front, fronts): (usize, &[Block]),
        global: f64,
    ) {
        for (f, vertices) in lattice.vertices.chunks(front).enumerate() {
            if fronts.get(f).is_some_and(|b| b.quiet(matches, global)) {
                matches.count += vertices.len();
                continue;
            }
            for (k, vertex) in vertices.iter().enumerate() {
                let v = f * front + k;
                let residual = r::matches_construction(self.z[v], vertex.z);
                matches.record_ratio(r::on_scale(residual, global), || vertex_site(lattice, v));
            }
        }
    }

    /// The pivots' comparison with the construction, `width` cells a block
    /// (`rows`, if measured), each pivot's z taken again from the corner it
    /// was reached through.
    fn compare_pivots(
        &self,
        lattice: &Lattice,
        matches: &mut Check,
        (width, rows): (usize, &[Block]),
        global: f64,
    ) {
        let cells = lattice.cells.chunks(width).zip(self.reached.chunks(width));
        for (i, (cells, reached)) in cells.enumerate() {
            if rows.get(i).is_some_and(|b| b.quiet(matches, global)) {
                matches.count += cells.len();
                continue;
            }
            for (cell, &k) in cells.iter().zip(reached) {
                // An unreached pivot has no z: its comparison is NaN and fails.
                let zp = match k {
                    UNREACHED => f64::NAN,
                    k => {
                        let leg = cell.pivot.distance(lattice.corner(cell, k as usize));
                        let (v, off) = match k {
                            0 => (cell.ul, -leg),
                            1 => (cell.ur, -leg),
                            2 => (cell.ll, leg),
                            _ => (cell.lr, leg),
                        };
                        self.z[v as usize] - off
                    }
                };
                let residual = r::matches_construction(zp, cell.z_pivot);
                matches.record_ratio(r::on_scale(residual, global), || lattice.cell_name(cell));
            }
        }
    }

    /// The collapsed rods measured again after the sweep, with the final
    /// z, when some cell was not reached (its corners' z may have been set
    /// after the cells before it were swept).
    fn rods_again(&self, lattice: &Lattice) -> Check {
        let mut rods = Check::new(Invariant::CollapsedRodLength);
        for cell in &lattice.cells {
            let site = || lattice.cell_name(cell);
            let inv = 1.0 / mean(&lattice.legs(cell));
            let zs = cell.corner_ids().map(|v| self.z[v as usize]);
            let spans = r::rod_spans(lattice.corners(cell));
            for residual in r::collapsed_rods(zs, spans, inv) {
                rods.record(residual, site);
            }
        }
        rods
    }
}

/// A cell's corners' offsets in z from its pivot's (docs/math.md 3.2), UL, UR,
/// LL, LR, from its legs: the upper corners a leg below the pivot, the
/// lower a leg above.
#[inline(always)]
pub(super) fn offsets([l1, l2, l3, l4]: Legs) -> [f64; 4] {
    [-l1, -l4, l2, l3]
}

/// The sweep of one cell whose corners UL, UR, LL, LR have their z at
/// `z[at[k]]` (NaN while unknown), `offsets[k]` from its pivot's
/// (`offsets`): the pivot's z from the first corner that has one, then
/// each corner in turn set, or compared with what it has (`inv` = 1 / the
/// cell's mean leg). Returns that corner, the pivot's z and the corners'
/// z (final: a z once set never changes), or `UNREACHED` and NaN (and
/// records a failure) when none has a z.
#[inline(always)]
pub(super) fn sweep(
    single: &mut Check,
    z: &mut [f64],
    at: [usize; 4],
    offsets: [f64; 4],
    inv: f64,
    site: impl Fn() -> String,
) -> (u8, f64, [f64; 4]) {
    let Some(k) = at.iter().position(|&v| !z[v].is_nan()) else {
        single.record(f64::NAN, || {
            format!("{} (not connected to vertex 0)", site())
        });
        return (UNREACHED, f64::NAN, [f64::NAN; 4]);
    };
    let zp = z[at[k]] - offsets[k];
    let mut zs = [0.0; 4];
    for ((v, offset), out) in at.into_iter().zip(offsets).zip(&mut zs) {
        let expect = zp + offset;
        let slot = &mut z[v];
        if slot.is_nan() {
            *slot = expect;
        } else {
            single.record(r::single_valued(*slot, expect, inv), &site);
        }
        *out = *slot;
    }
    (k as u8, zp, zs)
}
