//! Verification in one pass over the cells of any lattice: each cell's
//! residuals (`residuals.rs`) with the neighbours its `Incidence` names,
//! recorded as they are computed. `verify` takes this pass for helices,
//! intrinsic lattices and anything that is not a regular grid; the rows'
//! pass (`rows.rs`) gives the same report, faster, for the rest.

use super::collapsed::Collapsed;
use super::incidence::{Incidence, NONE, UL};
use super::report::{Check, Invariant, Report};
use super::residuals as r;
use super::{Lattice, Legs, mean, report, vertex_site};
use crate::lattice::{Cell, Kind};
use glam::DVec3;

/// `verify` with the incidence given (a grid or a table: the same report).
pub(super) fn verify_with(lattice: &Lattice, inc: &Incidence) -> Report {
    let mut pass = Pass::new(lattice);
    // Row and column of the cell on a grid (`Incidence::Grid`), counted
    // along, not divided out; the column of its upper-right corner.
    let front = match inc {
        Incidence::Grid(grid) => grid.front,
        Incidence::Table(_) => usize::MAX,
    };
    let width = lattice.width;
    let (mut i, mut j) = (0, 0);
    for (c, cell) in lattice.cells.iter().enumerate() {
        let j_right = if j + 1 == front { 0 } else { j + 1 };
        pass.legs.advance(c + width + 1);
        let own = pass.legs.get(c);
        let scale = mean(&own);
        pass.leg_sum += scale;
        let inv = 1.0 / scale;
        let corners = lattice.corners(cell);
        pass.collapsed.step(lattice, c, (&own, inv), &corners);
        let at = Here {
            cell,
            corners,
            legs: own,
            scale,
        };
        pass.local(&at, inv);
        // Right neighbour: B.UL = A.UR and B.LL = A.LR.
        let right = inc.at(cell.ur, (i, j_right), UL);
        pass.right(&at, right);
        // Neighbour below: B.UL = A.LL and B.UR = A.LR.
        let below = inc.at(cell.ll, (i + 1, j), UL);
        pass.below(&at, below);
        // Compatibility at the vertex this cell is the UL of (docs/math.md 8.2):
        // each vertex once, at the cell its incidence names, in the order
        // of the cells (that of their UL vertices), without a pass of its own.
        let [ul_of, ur_of, ll_of, lr_of] = inc.of(cell.ul, (i, j));
        if ul_of == c as u32 && ![ll_of, lr_of, ur_of].contains(&NONE) {
            pass.compatibility(&at, [c as u32, ll_of, lr_of, ur_of]);
        }
        j += 1;
        if j >= width {
            (i, j) = (i + 1, 0);
        }
    }
    pass.report()
}

/// The cell being checked: its stored corners, legs and mean leg.
struct Here<'a> {
    cell: &'a Cell,
    corners: [DVec3; 4],
    legs: Legs,
    scale: f64,
}

/// The checks of the pass over the cells, filled cell by cell.
struct Pass<'a> {
    lattice: &'a Lattice,
    legs: LegWindow<'a>,
    /// Every corner is its vertex's stored position when no row grew on a
    /// rebuilt front: a neighbour's corners on the shared edge are then
    /// the same vertices, so the same positions as this cell's own.
    extrinsic: bool,
    /// The sum of the cells' mean legs, in cell order: the tolerance's and
    /// the collapsed state's scale, known once every cell is checked.
    leg_sum: f64,
    straight: Check,
    legs_z: Check,
    seed: Check,
    pores_h: Check,
    pores_v: Check,
    edges: Check,
    closure: Check,
    slope: Check,
    intercept: Check,
    natural: Check,
    collapsed: Collapsed,
}

impl<'a> Pass<'a> {
    fn new(lattice: &'a Lattice) -> Self {
        use Invariant as I;
        Self {
            lattice,
            legs: LegWindow::new(lattice),
            extrinsic: lattice.extrinsic(),
            leg_sum: 0.0,
            straight: Check::new(I::RodStraightness),
            legs_z: Check::new(I::LegsMatchZ),
            seed: Check::new(I::SeedKappa),
            pores_h: Check::new(I::HorizontalPores),
            pores_v: Check::new(I::VerticalPores),
            edges: Check::new(I::SharedEdges),
            closure: Check::new(I::LoopClosure),
            slope: Check::new(I::CompatibilitySlope),
            intercept: Check::new(I::CompatibilityIntercept),
            natural: Check::new(I::CompatibilityInterceptNatural),
            collapsed: Collapsed::new(lattice),
        }
    }

    /// The residuals a cell needs no neighbour for: its rods' bends (and a
    /// loop's closure), its legs against the construction z, and in the
    /// first row the seed's kappa (`inv` = 1 / its mean leg).
    fn local(&mut self, at: &Here, inv: f64) {
        let (lattice, cell) = (self.lattice, at.cell);
        let site = || lattice.cell_name(cell);
        let [rod_a, rod_b] = r::rods(r::to_pivot(cell.pivot, at.corners), at.legs);
        self.straight.record_bend(rod_a, site);
        self.straight.record_bend(rod_b, site);
        if lattice.kind == Kind::Loop && cell.col == 0 {
            // Rod B of cell 0 ends where the round of transfers came back.
            self.closure.record(r::bend(rod_b), site);
        }
        let z = cell.corner_ids().map(|v| lattice.vertex(v).z);
        for residual in r::legs_z(at.legs, z, cell.z_pivot, inv) {
            self.legs_z.record(residual, site);
        }
        if cell.row == 0 {
            let kappa = lattice.kappa(cell);
            self.seed.record(r::seed_kappa(at.legs, kappa, inv), site);
        }
    }

    /// The cell `right` (or `NONE`) named right of `at`, if it is its
    /// neighbour there (B.LL = A.LR): the horizontal pore, and A's right
    /// edge UR-LR against B's left edge UL-LL.
    fn right(&mut self, at: &Here, right: u32) {
        let cells = &self.lattice.cells;
        if right == NONE || cells[right as usize].ll != at.cell.lr {
            return;
        }
        let theirs = self.legs.get(right as usize);
        let pore = r::horizontal_pore((at.legs, at.scale), (theirs, mean(&theirs)));
        let [_, ur, _, lr] = at.corners;
        let (bul, bll) = self.edge_of(&cells[right as usize], [0, 2], (ur, lr));
        let site = || self.lattice.cell_name(at.cell);
        self.pores_h.record_ratio(pore, site);
        self.edges
            .record(r::shared_edge(ur, lr, bul, bll, pore.den), site);
    }

    /// The cell `below` (or `NONE`) named below `at`, if it is its
    /// neighbour there (B.UR = A.LR): the vertical pore, and A's bottom
    /// edge LL-LR against B's top edge UL-UR (in an intrinsic lattice the
    /// two are in different frames).
    fn below(&mut self, at: &Here, below: u32) {
        let cells = &self.lattice.cells;
        if below == NONE || cells[below as usize].ur != at.cell.lr {
            return;
        }
        let theirs = self.legs.get(below as usize);
        let pore = r::vertical_pore((at.legs, at.scale), (theirs, mean(&theirs)));
        let [_, _, ll, lr] = at.corners;
        let (bul, bur) = self.edge_of(&cells[below as usize], [0, 1], (ll, lr));
        let site = || self.lattice.cell_name(at.cell);
        self.pores_v.record_ratio(pore, site);
        self.edges
            .record(r::shared_edge(ll, lr, bul, bur, pore.den), site);
    }

    /// Corners `which` of the neighbour `b` on the edge it shares with the
    /// cell whose own corners there are `own`: the same stored vertices, so
    /// the same positions when the lattice is extrinsic (no corner is then
    /// read from a rebuilt front), and `b`'s corners in its own frame if not.
    #[inline]
    fn edge_of(&self, b: &Cell, which: [usize; 2], own: (DVec3, DVec3)) -> (DVec3, DVec3) {
        if self.extrinsic {
            own
        } else {
            let corners = self.lattice.corners(b);
            (corners[which[0]], corners[which[1]])
        }
    }

    /// The four-map composition at the UL vertex of `at`, from the cells in
    /// which it is UL (`at` itself), LL, LR and UR.
    fn compatibility(&mut self, at: &Here, around: [u32; 4]) {
        let [a, b, c, d] = around.map(|k| self.legs.get(k as usize));
        let [ul, _, ll, _] = at.corners;
        let composed = r::compatibility(a, b, c, d, r::left_edge_squared(ul, ll));
        let site = || vertex_site(self.lattice, at.cell.ul as usize);
        self.slope.record(composed.slope, site);
        self.intercept.record_ratio(composed.intercept, site);
        self.natural.record_ratio(composed.natural, site);
    }

    /// The report, once every cell is checked.
    fn report(self) -> Report {
        let checks = [
            self.straight,
            self.legs_z,
            self.seed,
            self.pores_h,
            self.pores_v,
            self.edges,
            self.closure,
            self.slope,
            self.intercept,
            self.natural,
        ];
        report(self.lattice, self.leg_sum, checks, self.collapsed)
    }
}

/// The legs of the cells around the one being checked, in a ring of the
/// last `2 width + 3` or more cells measured: the checks of cell `c` read
/// its neighbours `c - width - 1` to `c + width` in a sheet, loop or helix.
/// A cell outside the ring (a lattice whose cells are not row by row,
/// e.g. a corrupted one) has its legs measured again: `Lattice::legs` of
/// the same stored corners, so the same bits either way.
struct LegWindow<'a> {
    lattice: &'a Lattice,
    ring: Vec<Legs>,
    /// Cells `0..measured` have been measured; the ring holds the last
    /// `ring.len()` of them.
    measured: usize,
}

impl<'a> LegWindow<'a> {
    fn new(lattice: &'a Lattice) -> Self {
        let cells = lattice.cells.len();
        let len = (2 * lattice.width + 3)
            .min(cells.max(1))
            .next_power_of_two();
        Self {
            lattice,
            ring: vec![[0.0; 4]; len],
            measured: 0,
        }
    }

    /// Measure the cells before `end` not yet measured.
    #[inline]
    fn advance(&mut self, end: usize) {
        let cells = &self.lattice.cells;
        let end = end.min(cells.len());
        let mask = self.ring.len() - 1;
        while self.measured < end {
            self.ring[self.measured & mask] = self.lattice.legs(&cells[self.measured]);
            self.measured += 1;
        }
    }

    /// The legs of cell `k`.
    #[inline(always)]
    fn get(&self, k: usize) -> Legs {
        if k < self.measured && k + self.ring.len() >= self.measured {
            self.ring[k & (self.ring.len() - 1)]
        } else {
            self.measure(k)
        }
    }

    /// The legs of a cell outside the ring, measured again.
    #[cold]
    #[inline(never)]
    fn measure(&self, k: usize) -> Legs {
        self.lattice.legs(&self.lattice.cells[k])
    }
}
