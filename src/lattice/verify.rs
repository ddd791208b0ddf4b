//! Verification of a grown lattice (docs/math.md 8.0-8.3). Every residual is
//! recomputed from the stored positions and z values, never copied from the
//! construction, and made relative (lengths over the cell's mean leg).

use super::{Cell, Lattice, Legs, Vertex};
use glam::DVec3;

/// A lattice passes when every relative residual is at most this (or, for
/// a lattice of enormous extent, `tolerance`).
pub const TOLERANCE: f64 = 1e-9;

/// Rounding drift of a relative residual per leg of distance from the
/// origin. docs/math.md 8.5 measured f64 residuals growing linearly with the
/// extent: 4e-13 at 200 rows, about 2e-15 (9 ulp) per leg; this allows
/// seven times that.
pub const DRIFT_PER_LEG: f64 = 64.0 * f64::EPSILON;

/// How far a vertex is from the origin, coordinate- and z-wise.
#[inline]
fn vertex_extent(v: &super::Vertex) -> f64 {
    v.pos.abs().max_element().max(v.z.abs())
}

/// The tolerance `lattice` is verified against, given the sum over its
/// cells of their mean legs and its largest `vertex_extent`: `TOLERANCE`, or
/// `DRIFT_PER_LEG` times its extent in mean legs when that is larger (only
/// beyond about 70,000 legs from the origin, e.g. a sheet of more than
/// 70,000 rows), since rounding of absolute coordinates alone then reaches
/// 1e-9 in exact constructions.
fn tolerance_of(lattice: &Lattice, legs: f64, extent: f64) -> f64 {
    let leg = legs / lattice.cells.len().max(1) as f64;
    if !(leg > 0.0) || !extent.is_finite() {
        return TOLERANCE;
    }
    TOLERANCE.max(DRIFT_PER_LEG * extent / leg)
}

/// An invariant of docs/math.md 8.0-8.3 that verification checks; each is one
/// `Check` of a `Report`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Invariant {
    /// Each rod is straight through its pivot: the sine of its bend there.
    RodStraightness,
    /// Each leg equals the difference of the construction z at its two ends.
    LegsMatchZ,
    /// First row: `l4 - l1` equals the seed edge's kappa.
    SeedKappa,
    /// Collapsibility (H) between cells side by side in a row.
    HorizontalPores,
    /// Collapsibility (V) between a cell and the cell below it.
    VerticalPores,
    /// An edge shared by two cells has the same length in both.
    SharedEdges,
    /// Loops: rod B of cell 0, which ends where the round of transfers came
    /// back, is straight.
    LoopClosure,
    /// Four-map composition around an interior vertex (docs/math.md 8.2): slope - 1.
    CompatibilitySlope,
    /// Four-map composition: intercept over the squared left edge.
    CompatibilityIntercept,
    /// Four-map composition: intercept over its natural magnitude (better
    /// conditioned than over the edge).
    CompatibilityInterceptNatural,
    /// The z recomputed from the legs alone is single-valued at every vertex
    /// and pivot.
    CollapsedSingleValued,
    /// The recomputed z equals the construction z up to a constant.
    CollapsedMatchesConstruction,
    /// In the collapsed state each rod's z span equals its deployed length.
    CollapsedRodLength,
}

impl Invariant {
    /// What the invariant checks, in words for reports and messages.
    pub fn describe(self) -> &'static str {
        match self {
            Self::RodStraightness => "rod straightness (sine of the bend at the pivot)",
            Self::LegsMatchZ => "legs equal collapsed-z differences",
            Self::SeedKappa => "first row: l4 - l1 = seed kappa",
            Self::HorizontalPores => "collapsibility (H) at horizontal pores",
            Self::VerticalPores => "collapsibility (V) at vertical pores",
            Self::SharedEdges => "shared edges equal in both cells",
            Self::LoopClosure => "loop closure: sine of rod B's bend in cell 0",
            Self::CompatibilitySlope => "four-map composition: slope - 1",
            Self::CompatibilityIntercept => "four-map composition: intercept / |s|^2",
            Self::CompatibilityInterceptNatural => {
                "four-map composition: intercept / its magnitude"
            }
            Self::CollapsedSingleValued => "collapsed state: z single-valued",
            Self::CollapsedMatchesConstruction => "collapsed state: z equals construction z",
            Self::CollapsedRodLength => "collapsed state: rods keep their length",
        }
    }
}

/// The largest residual of one invariant and where it occurs.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// The invariant checked.
    pub invariant: Invariant,
    /// How many places were checked.
    pub(crate) count: usize,
    /// The largest residual found.
    pub max: f64,
    /// Where the largest residual occurs, if anywhere.
    pub site: Option<String>,
    /// What `max` must not exceed (see `tolerance_of`).
    pub(crate) tolerance: f64,
}

impl Check {
    fn new(invariant: Invariant) -> Self {
        Self {
            invariant,
            count: 0,
            max: 0.0,
            site: None,
            tolerance: TOLERANCE,
        }
    }

    #[inline(always)]
    fn record(&mut self, residual: f64, site: impl FnOnce() -> String) {
        self.count += 1;
        // One comparison for the common case: false for a residual above
        // the largest, for a NaN residual and for a NaN largest.
        if !(residual.abs() <= self.max) {
            self.raise(residual, site);
        }
    }

    /// A new largest residual: rare after the first cells, and its site's
    /// name (a formatted string) kept out of the checks' loop. A NaN
    /// residual must fail the check, so it sticks once seen.
    #[cold]
    #[inline(never)]
    fn raise(&mut self, residual: f64, site: impl FnOnce() -> String) {
        if self.max.is_nan() {
            return;
        }
        if residual.is_nan() || residual.abs() > self.max {
            self.max = residual.abs();
            self.site = Some(site());
        }
    }

    /// `record(num / den, site)`, without the division when the quotient
    /// cannot exceed the largest residual so far: `|num| < 0.999 max |den|`
    /// with `max |den|` a normal, finite number puts the exact quotient
    /// below `max` by far more than its rounding. Anything else (NaN, a
    /// zero or subnormal bound, an overflow, the first residuals while the
    /// largest is still 0) is divided and recorded as before, so the
    /// largest residual and its site are the same bits. Nearly every
    /// residual of a good lattice is below the largest one: the divisions,
    /// much of verification's time, are mostly skipped.
    #[inline(always)]
    fn record_ratio(&mut self, num: f64, den: f64, site: impl FnOnce() -> String) {
        let bound = self.max * den.abs();
        if bound.is_finite() && bound >= f64::MIN_POSITIVE && num.abs() < 0.999 * bound {
            self.count += 1;
            return;
        }
        self.record(num / den, site);
    }

    /// `record(bend(a, la, b, lb), site)`, the same way without the square
    /// root and the division when the sine cannot exceed the largest so far
    /// (`|a x b|^2 < 0.998 (max la lb)^2`, see `record_ratio`).
    #[inline(always)]
    fn record_bend(
        &mut self,
        (a, la): (DVec3, f64),
        (b, lb): (DVec3, f64),
        site: impl FnOnce() -> String,
    ) {
        let cross = a.cross(b).length_squared();
        let den = la * lb;
        let bound = self.max * den;
        let bound2 = bound * bound;
        if bound2.is_finite() && bound2 >= f64::MIN_POSITIVE && cross < 0.998 * bound2 {
            self.count += 1;
            return;
        }
        self.record(cross.sqrt() / den, site);
    }

    pub(crate) fn passed(&self) -> bool {
        self.max <= self.tolerance
    }
}

/// The verification of one lattice: the largest residual of every
/// invariant, where it occurs, and the tolerance all were held to.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    pub(crate) cells: usize,
    pub(crate) vertices: usize,
    pub(crate) rods: usize,
    pub(crate) horizontal_pores: usize,
    pub(crate) vertical_pores: usize,
    pub(crate) interior_vertices: usize,
    /// One check per invariant, in `Invariant` order.
    pub checks: Vec<Check>,
    /// The tolerance every check was held to.
    pub tolerance: f64,
}

impl Report {
    /// True when every check is within the tolerance (a NaN residual fails).
    pub fn passed(&self) -> bool {
        self.checks.iter().all(Check::passed)
    }

    /// The check of `invariant`.
    pub fn check(&self, invariant: Invariant) -> &Check {
        self.checks
            .iter()
            .find(|c| c.invariant == invariant)
            .expect("every invariant is checked")
    }

    /// The largest residual over all invariants.
    pub fn worst(&self) -> f64 {
        self.checks
            .iter()
            .map(|c| c.max)
            .fold(0.0, |a, b| if b.is_nan() { b } else { a.max(b) })
    }
}

const NONE: u32 = u32::MAX;

/// For every vertex, the cell in which it is UL, UR, LL, LR (or NONE).
enum Incidence {
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
struct Grid {
    width: usize,
    front: usize,
    rows: usize,
    closed: bool,
}

impl Grid {
    /// The corner indices `[UL, UR, LL, LR]` of cell `(i, j)`.
    #[inline]
    fn corners(&self, i: usize, j: usize) -> [usize; 4] {
        let (top, bottom) = (i * self.front, (i + 1) * self.front);
        let right = super::wrap(j + 1, self.front);
        [top + j, top + right, bottom + j, bottom + right]
    }

    /// The grid a sheet or loop of whole rows would have, if its cells
    /// hold the corners of their positions (`holds`, checked apart: by
    /// `Incidence::grid` at once, and row by row by `Row::measure`'s
    /// branch-free copy of it) and its vertices are exactly its rows'
    /// fronts.
    fn of(lattice: &Lattice) -> Option<Grid> {
        let width = lattice.width;
        let closed = match lattice.kind {
            super::Kind::Sheet => false,
            super::Kind::Loop => true,
            super::Kind::Helix => return None,
        };
        let front = if closed { width } else { width + 1 };
        let cells = lattice.cells.len();
        if width == 0 || (closed && width < 3) || cells % width != 0 {
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
    fn holds(&self, i: usize, j: usize, cell: &super::Cell) -> bool {
        cell.corner_ids().map(|v| v as usize) == self.corners(i, j)
    }

    /// `Incidence::Table`'s entry for the vertex in row `r`, column `c`
    /// of the fronts, from the numbering.
    #[inline(always)]
    fn at_vertex(&self, r: usize, c: usize) -> [u32; 4] {
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

const UL: usize = 0;
const UR: usize = 1;
const LL: usize = 2;
const LR: usize = 3;

impl Incidence {
    /// The incidence, in one pass over the cells' corner indices (the legs
    /// are measured later, once, by the checks' `LegWindow`).
    fn new(lattice: &Lattice) -> Self {
        match Self::grid(lattice) {
            Some(grid) => Self::Grid(grid),
            None => Self::table(lattice),
        }
    }

    /// The table, read from the cells' corner indices.
    fn table(lattice: &Lattice) -> Self {
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
    fn grid(lattice: &Lattice) -> Option<Grid> {
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
    fn at(&self, v: u32, rc: (usize, usize), corner: usize) -> u32 {
        match self {
            Self::Table(inc) => inc[v as usize][corner],
            Self::Grid(grid) => grid.at_vertex(rc.0, rc.1)[corner],
        }
    }

    /// The cells in which vertex `v` is UL, UR, LL and LR (`rc` as in `at`).
    #[inline(always)]
    fn of(&self, v: u32, rc: (usize, usize)) -> [u32; 4] {
        match self {
            Self::Table(inc) => inc[v as usize],
            Self::Grid(grid) => grid.at_vertex(rc.0, rc.1),
        }
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

fn vertex_site(lattice: &Lattice, v: usize) -> String {
    format!("vertex {}", lattice.vertex_name(v as u32))
}

/// Sine of the angle between two legs `a`, `b` of one rod (either way
/// round: the sine is the same), given their lengths.
fn bend(a: DVec3, la: f64, b: DVec3, lb: f64) -> f64 {
    a.cross(b).length() / (la * lb)
}

/// `(|a - b| - |c - d|) / s`, the relative difference of two edges. The
/// same stored points make the same distance, so an edge whose two cells
/// hold the same corners (every extrinsic lattice) takes no square root;
/// the result is bit for bit the full formula's.
#[inline]
fn edge_residual(a: DVec3, b: DVec3, c: DVec3, d: DVec3, s: f64) -> f64 {
    if a == c && b == d && a.is_finite() && b.is_finite() {
        // What 0.0 / s gives, without the division: NaN when s is 0 or
        // NaN (the sign of a zero does not matter to a residual).
        if s == 0.0 || s.is_nan() {
            f64::NAN
        } else {
            0.0
        }
    } else {
        (a.distance(b) - c.distance(d)) / s
    }
}

/// Corners `which` of the neighbour `b` on the edge it shares with a
/// cell whose own corners there are `own`: the same stored vertices, so
/// the same positions when the lattice is extrinsic (no corner is then
/// read from a rebuilt front), and `b`'s corners in its own frame if not.
#[inline]
fn shared_edge(
    lattice: &Lattice,
    extrinsic: bool,
    b: &super::Cell,
    which: [usize; 2],
    own: (DVec3, DVec3),
) -> (DVec3, DVec3) {
    if extrinsic {
        own
    } else {
        let corners = lattice.corners(b);
        (corners[which[0]], corners[which[1]])
    }
}

fn mean(legs: &Legs) -> f64 {
    legs.iter().sum::<f64>() / 4.0
}

/// Check every invariant of docs/math.md 8.0-8.3: by rows for a regular,
/// extrinsic sheet or loop (`verify_rows`), in one pass over the cells for
/// anything else (`verify_with`); the same report either way.
pub fn verify(lattice: &Lattice) -> Report {
    // The rows' pass checks each row's corner indices as it measures the
    // row (no pass of its own over the cells), and gives up on the first
    // row that is not its grid's.
    if let Some(grid) = Grid::of(lattice).filter(|_| lattice.extrinsic())
        && let Some(report) = verify_rows(lattice, &grid)
    {
        return report;
    }
    verify_with(lattice, &Incidence::new(lattice))
}

/// `verify` with the incidence given (a grid or a table: the same report).
fn verify_with(lattice: &Lattice, inc: &Incidence) -> Report {
    use Invariant as I;
    // The sum of the cells' mean legs, in cell order: the tolerance's and
    // the collapsed state's scale, known once every cell is checked.
    let mut leg_sum = 0.0;
    let mut legs = LegWindow::new(lattice);
    let width = lattice.width;
    // Every corner is its vertex's stored position when no row grew on a
    // rebuilt front: a neighbour's corners on the shared edge are then the
    // same vertices, so the same positions as this cell's own.
    let extrinsic = lattice.extrinsic();
    let z = |v: u32| lattice.vertices[v as usize].z;

    let mut straight = Check::new(I::RodStraightness);
    let mut legs_z = Check::new(I::LegsMatchZ);
    let mut seed = Check::new(I::SeedKappa);
    let mut pores_h = Check::new(I::HorizontalPores);
    let mut pores_v = Check::new(I::VerticalPores);
    let mut edges = Check::new(I::SharedEdges);
    let mut closure = Check::new(I::LoopClosure);
    let mut slope = Check::new(I::CompatibilitySlope);
    let mut intercept = Check::new(I::CompatibilityIntercept);
    let mut natural = Check::new(I::CompatibilityInterceptNatural);
    let mut collapsed = Collapsed::new(lattice);
    // Row and column of the cell on a grid (`Incidence::Grid`), counted
    // along, not divided out; the column of its upper-right corner.
    let front = match inc {
        Incidence::Grid(grid) => grid.front,
        Incidence::Table(_) => usize::MAX,
    };
    let (mut i, mut j) = (0, 0);
    for (c, cell) in lattice.cells.iter().enumerate() {
        let j_right = if j + 1 == front { 0 } else { j + 1 };
        legs.advance(c + width + 1);
        let own = legs.get(c);
        let [l1, l2, l3, l4] = own;
        let scale = mean(&own);
        leg_sum += scale;
        let inv = 1.0 / scale;
        let site = || lattice.cell_name(cell);
        let rel = |x: f64| x * inv;
        // The sine of each rod's bend at the pivot: first order in a sideways
        // offset of the pivot, where docs/math.md's |LR-UL| - (l1+l3) is second order.
        let p = cell.pivot;
        let corners = lattice.corners(cell);
        let [ul, ur, ll, lr] = corners;
        collapsed.step(lattice, c, (&own, inv), &corners);
        straight.record_bend((p - ul, l1), (lr - p, l3), site);
        straight.record_bend((p - ur, l4), (ll - p, l2), site);
        if lattice.kind == super::Kind::Loop && cell.col == 0 {
            // Rod B of cell 0 ends where the round of transfers came back.
            closure.record(bend(p - ur, l4, ll - p, l2), site);
        }
        let zp = cell.z_pivot;
        legs_z.record(rel(zp - z(cell.ul) - l1), site);
        legs_z.record(rel(zp - z(cell.ur) - l4), site);
        legs_z.record(rel(z(cell.ll) - zp - l2), site);
        legs_z.record(rel(z(cell.lr) - zp - l3), site);
        if cell.row == 0 {
            seed.record(rel((l4 - l1) - lattice.kappa(cell)), site);
        }
        // Right neighbour: B.UL = A.UR and B.LL = A.LR.
        let right = inc.at(cell.ur, (i, j_right), UL);
        if right != NONE && lattice.cells[right as usize].ll == cell.lr {
            let b = &lattice.cells[right as usize];
            let theirs = legs.get(right as usize);
            let [m1, m2, _, _] = theirs;
            let s = 0.5 * (scale + mean(&theirs));
            pores_h.record_ratio((l3 + l4) - (m1 + m2), s, site);
            // Shared edge: A's right edge UR-LR and B's left edge UL-LL.
            let (bul, bll) = shared_edge(lattice, extrinsic, b, [0, 2], (ur, lr));
            edges.record(edge_residual(ur, lr, bul, bll, s), site);
        }
        // Neighbour below: B.UL = A.LL and B.UR = A.LR.
        let below = inc.at(cell.ll, (i + 1, j), UL);
        if below != NONE && lattice.cells[below as usize].ur == cell.lr {
            let b = &lattice.cells[below as usize];
            let theirs = legs.get(below as usize);
            let [m1, _, _, m4] = theirs;
            let s = 0.5 * (scale + mean(&theirs));
            pores_v.record_ratio((l2 + m1) - (l3 + m4), s, site);
            // Shared edge: A's bottom edge LL-LR and B's top edge UL-UR; in an
            // intrinsic lattice the two are in different frames.
            let (bul, bur) = shared_edge(lattice, extrinsic, b, [0, 1], (ll, lr));
            edges.record(edge_residual(ll, lr, bul, bur, s), site);
        }
        // Compatibility at the vertex this cell is the UL of (docs/math.md 8.2):
        // each vertex once, at the cell its incidence names, in the order
        // of the cells (that of their UL vertices), without a pass of its own.
        let v = cell.ul as usize;
        let [ul_of, ur_of, ll_of, lr_of] = inc.of(cell.ul, (i, j));
        let (a, b, cc, d) = (c as u32, ll_of, lr_of, ur_of);
        if ul_of == a && ![b, cc, d].contains(&NONE) {
            let [a, b, cc, d] = [
                legs.get(a as usize),
                legs.get(b as usize),
                legs.get(cc as usize),
                legs.get(d as usize),
            ];
            let (m, k, magnitude) = compose(a, b, cc, d);
            let s2 = ul.distance_squared(ll);
            let site = || vertex_site(lattice, v);
            slope.record(m - 1.0, site);
            intercept.record_ratio(k, s2, site);
            natural.record_ratio(k, magnitude, site);
        }
        j += 1;
        if j >= width {
            (i, j) = (i + 1, 0);
        }
    }

    let checks = [
        straight, legs_z, seed, pores_h, pores_v, edges, closure, slope, intercept, natural,
    ];
    report(lattice, leg_sum, checks, collapsed)
}

/// The report of a pass over the cells: its ten checks in `Invariant`
/// order, then the collapsed state's three, all held to the tolerance.
fn report(lattice: &Lattice, leg_sum: f64, checks: [Check; 10], collapsed: Collapsed) -> Report {
    let (collapsed, extent) = collapsed.finish(lattice, leg_sum);
    let tolerance = tolerance_of(lattice, leg_sum, extent);
    let count = |k: usize| checks[k].count;
    Report {
        tolerance,
        cells: lattice.cells.len(),
        vertices: lattice.vertices.len(),
        rods: 2 * lattice.cells.len(),
        horizontal_pores: count(3),
        vertical_pores: count(4),
        interior_vertices: count(7),
        checks: checks
            .into_iter()
            .chain(collapsed)
            .map(|c| Check { tolerance, ..c })
            .collect(),
    }
}

/// The four-map composition around an interior vertex (docs/math.md 8.2), from
/// the legs of the cells in which it is UL (`a`), LL (`b`), LR (`c`) and UR
/// (`d`): the composed map's slope, intercept and the intercept's natural
/// magnitude.
#[inline(always)]
fn compose(a: Legs, b: Legs, cc: Legs, d: Legs) -> (f64, f64, f64) {
    // f^(a,b,c)(S) = gamma - eta S as (slope, intercept), docs/math.md 2.
    // One division a map: `-(lc / la)` is `-lc / la`, bit for bit
    // (division rounds the same either side of 0; a NaN differs at most in
    // its sign, which every residual's `abs` drops).
    let f = |la: f64, lb: f64, lc: f64| {
        let q = lc / la;
        (-q, lb * lb + lc * lc + q * (la * la + lb * lb))
    };
    let maps = [
        f(a[1], a[0], a[3]),    // f_a^(2,1,4): left edge -> top edge
        f(b[2], b[1], b[0]),    // f_b^(3,2,1): bottom edge -> left edge
        f(cc[3], cc[2], cc[1]), // f_c^(4,3,2): right edge -> bottom edge
        f(d[0], d[3], d[2]),    // f_d^(1,4,3): top edge -> right edge
    ];
    let (mut m, mut k, mut magnitude) = (1.0, 0.0, 0.0);
    for (mi, ci) in maps.iter().rev() {
        // Outermost map first: accumulate the product of the slopes
        // applied after each intercept, as in the natural magnitude.
        magnitude += (m * ci).abs();
        k += m * ci;
        m *= mi;
    }
    (m, k, magnitude)
}

/// One row of a grid's cells, measured once (structure of arrays): each
/// cell's legs, mean leg and its inverse, and what the checks with its
/// neighbours need of its corners, so that no corner is copied. The
/// residuals a cell needs no neighbour for (its rods' bends, its legs
/// against the construction z) are computed as the row is measured, with
/// the corners at hand, and compared with their checks' largest then
/// (`Watch`: a largest of an earlier row is never above the one the row is
/// settled against, so the watch lets through at least the cells it must).
#[derive(Default)]
struct Row {
    legs: Vec<Legs>,
    means: Vec<f64>,
    /// `1 / means[j]`: one division a cell, where the sweep, the legs'
    /// and the rods' residuals each took it.
    invs: Vec<f64>,
    /// `|LR - UL|` and `|LL - UR|`: the rods' lengths the collapsed state
    /// must keep.
    spans: Vec<[f64; 2]>,
    /// `|UL - LL|^2`: the compatibility's scale at the cell's UL vertex.
    left2: Vec<f64>,
    /// Every mean leg of the row is finite, so every corner is: a corner
    /// with a NaN or infinite coordinate makes its leg NaN or infinite.
    finite: bool,
    straight: Watch,
    legs_z: Watch,
}

/// What the rows' pass records as it measures each row, in cell order:
/// the sum of the mean legs, the checks a cell needs no neighbour for
/// (watched: rod straightness, legs against z; recorded: the first row's
/// and the loop's first column's rare checks).
struct Local {
    leg_sum: f64,
    straight: Check,
    legs_z: Check,
    seed: Check,
    closure: Check,
}

/// Fronts `i` and `i + 1` of a grid, the top and bottom corners of row `i`.
fn fronts<'a>(lattice: &'a Lattice, grid: &Grid, i: usize) -> [&'a [Vertex]; 2] {
    let front = grid.front;
    let v = &lattice.vertices;
    [
        &v[i * front..(i + 1) * front],
        &v[(i + 1) * front..(i + 2) * front],
    ]
}

/// The vectors from a cell's corners to its pivot `p`, in the order of its
/// legs (UL, LL, LR, UR): their lengths are the legs (`p.distance(c)` is
/// `|p - c|`), and each rod's bend is the angle between two of them
/// (`(p - a) x (b - p)` is `-((p - a) x (p - b))` exactly, so the same
/// sine).
#[inline(always)]
fn to_pivot(p: DVec3, [ul, ur, ll, lr]: [DVec3; 4]) -> [DVec3; 4] {
    [p - ul, p - ll, p - lr, p - ur]
}

/// A cell's residuals that need no neighbour, from its corner vertices
/// `[UL, UR, LL, LR]`, the vectors from them to its pivot (`to_pivot`),
/// its legs and `1 / mean leg`: its rods' bends (A, B) and its legs
/// against the construction z. One formula for `Row::measure` and the
/// replays.
#[inline(always)]
fn local_residuals(
    cell: &Cell,
    [ul, ur, ll, lr]: [&Vertex; 4],
    [d1, d2, d3, d4]: [DVec3; 4],
    legs: Legs,
    inv: f64,
) -> ([f64; 2], [f64; 4]) {
    let [l1, l2, l3, l4] = legs;
    let bends = [bend(d1, l1, d3, l3), bend(d4, l4, d2, l2)];
    let z = [ul.z, ur.z, ll.z, lr.z];
    (bends, legs_z_of(legs, z, cell.z_pivot, inv))
}

impl Row {
    /// Measure row `i` of `grid` (extrinsic: every corner is its vertex's
    /// stored position, the legs the same bits as `Lattice::legs`) and
    /// record its cells into `local`; false when some cell of the row does
    /// not hold its grid corners (`Grid::holds`), and the row's measures
    /// are then meaningless.
    fn measure(&mut self, lattice: &Lattice, grid: &Grid, i: usize, local: &mut Local) -> bool {
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
        let is_loop = lattice.kind == super::Kind::Loop;
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
            let [ul, ur, ll, lr] = corners;
            let d = to_pivot(cell.pivot, corners);
            *legs = d.map(DVec3::length);
            *mean_leg = mean(legs);
            *inv = 1.0 / *mean_leg;
            *span = [ul.distance(lr), ur.distance(ll)];
            *left2 = ul.distance_squared(ll);
            local.leg_sum += *mean_leg;
            finite &= super::finite(*mean_leg);
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
                let [l1, _, _, l4] = *legs;
                let kappa = top[j].z - top[right].z;
                local.seed.record(((l4 - l1) - kappa) * *inv, site);
            }
        }
        (self.finite, self.straight, self.legs_z) = (finite, straight, legs_z);
        regular
    }
}

/// `edge_residual(a, b, a, b, s)`, for the edge a cell shares with a
/// neighbour holding the same stored corners: 0 when both points are
/// finite and `s` is neither 0 nor NaN, else NaN (`|a - b|` of a
/// non-finite point is NaN or infinite, and its difference with itself
/// NaN). The sign of a zero does not matter to a residual.
#[inline(always)]
fn same_edge(a: DVec3, b: DVec3, s: f64) -> f64 {
    if a.is_finite() && b.is_finite() && s != 0.0 && !s.is_nan() {
        0.0
    } else {
        f64::NAN
    }
}

/// A check's largest when a row starts, and the first and last cells of
/// the row with a residual that may exceed it: each residual is compared
/// as it is computed (no array of them stored and read again), and only
/// the cells from the first to the last of those are recorded again, one
/// residual at a time (`settle`): the others cannot raise the check.
#[derive(Clone, Copy)]
struct Watch {
    max: f64,
    first: usize,
    last: usize,
}

/// A watch that lets no cell through (until `Row::measure` sets it).
impl Default for Watch {
    fn default() -> Self {
        Self {
            max: 0.0,
            first: usize::MAX,
            last: 0,
        }
    }
}

impl Watch {
    fn of(check: &Check) -> Self {
        Self {
            max: check.max,
            first: usize::MAX,
            last: 0,
        }
    }

    /// Cell j's residuals, compared with the largest: `record`'s test, one
    /// comparison a residual and one branch a cell (a NaN residual, or a
    /// NaN largest, may raise).
    #[inline(always)]
    fn cell<const K: usize>(&mut self, j: usize, residuals: [f64; K]) {
        let over = residuals
            .iter()
            .fold(false, |any, r| any | !(r.abs() <= self.max));
        if over {
            self.first = self.first.min(j);
            self.last = self.last.max(j);
        }
    }

    /// Count a row's `count` residuals into `check`, recording those of
    /// the cells that may raise it one at a time, cell by cell, each
    /// cell's in the order `residuals(j)` gives them: the order of the
    /// pass over the cells, so the largest, its site (the first attaining
    /// it) and the count are the same bits.
    #[inline(always)]
    fn settle<I: IntoIterator<Item = f64>>(
        self,
        check: &mut Check,
        count: usize,
        residuals: impl Fn(usize) -> I,
        site: impl Fn(usize) -> String,
    ) {
        let before = check.count;
        if self.first <= self.last {
            replay(check, self.first..self.last + 1, residuals, site);
        }
        check.count = before + count;
    }
}

/// `Watch::settle` of a row that may hold a new largest.
#[cold]
#[inline(never)]
fn replay<I: IntoIterator<Item = f64>>(
    check: &mut Check,
    cells: std::ops::Range<usize>,
    residuals: impl Fn(usize) -> I,
    site: impl Fn(usize) -> String,
) {
    for k in cells {
        for r in residuals(k) {
            check.record(r, || site(k));
        }
    }
}

/// Each leg against the difference of the construction z at its ends
/// (`z` of UL, UR, LL, LR; `zp` the pivot's; `inv` 1 / the mean leg).
#[inline(always)]
fn legs_z_of(
    [l1, l2, l3, l4]: Legs,
    [zul, zur, zll, zlr]: [f64; 4],
    zp: f64,
    inv: f64,
) -> [f64; 4] {
    [
        (zp - zul - l1) * inv,
        (zp - zur - l4) * inv,
        (zll - zp - l2) * inv,
        (zlr - zp - l3) * inv,
    ]
}

/// The collapsed rods' lengths against the deployed (`zs` the recomputed
/// z of UL, UR, LL, LR; `spans` `|LR - UL|` and `|LL - UR|`).
#[inline(always)]
fn rods_of([zul, zur, zll, zlr]: [f64; 4], [a, b]: [f64; 2], inv: f64) -> [f64; 2] {
    [(zlr - zul - a) * inv, (zll - zur - b) * inv]
}

/// One row's measured arrays (`Row`) and its neighbours' legs, each
/// residual of a cell computed by one method, inlined: the watch over the
/// row and the replay of a row that may hold a new largest use the same
/// arithmetic.
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
        let d = to_pivot(cell.pivot, corners.map(|v| v.pos));
        local_residuals(cell, corners, d, self.legs[j], self.invs[j])
    }

    /// The horizontal pore between cell j and its right neighbour (the
    /// next cell, the first for a loop's last; B.UL = A.UR, B.LL = A.LR):
    /// its numerator and scale.
    #[inline(always)]
    fn pore_h(&self, j: usize) -> (f64, f64) {
        let k = if j + 1 == self.legs.len() { 0 } else { j + 1 };
        let ([_, _, l3, l4], [m1, m2, _, _]) = (self.legs[j], self.legs[k]);
        ((l3 + l4) - (m1 + m2), 0.5 * (self.means[j] + self.means[k]))
    }

    /// The vertical pore between cell j and the cell below (B.UL = A.LL,
    /// B.UR = A.LR).
    #[inline(always)]
    fn pore_v(&self, j: usize) -> (f64, f64) {
        let ([_, l2, l3, _], [m1, _, _, m4]) = (self.legs[j], self.under[j]);
        (
            (l2 + m1) - (l3 + m4),
            0.5 * (self.means[j] + self.under_means[j]),
        )
    }

    /// `same_edge(a, b, s)` for two corners `a`, `b` of cell j (indices
    /// into its corners), without reading them when the row's corners are
    /// all finite.
    #[inline(always)]
    fn edge(&self, j: usize, [a, b]: [usize; 2], s: f64) -> f64 {
        if self.finite {
            same_edge(DVec3::ZERO, DVec3::ZERO, s)
        } else {
            let corners = self.corners(j);
            same_edge(corners[a].pos, corners[b].pos, s)
        }
    }

    /// Cell j's right edge UR-LR against its neighbour's left edge, on
    /// scale `s`: the same stored corners (extrinsic).
    #[inline(always)]
    fn edge_right(&self, j: usize, s: f64) -> f64 {
        self.edge(j, [1, 3], s)
    }

    /// Cell j's bottom edge LL-LR against the top edge of the cell below.
    #[inline(always)]
    fn edge_below(&self, j: usize, s: f64) -> f64 {
        self.edge(j, [2, 3], s)
    }

    /// The compatibility at cell j's UL vertex, whose cells above and to
    /// the left exist (a loop's left of column 0 is its last column): the
    /// slope, the intercept, its squared left edge and its natural
    /// magnitude.
    #[inline(always)]
    fn compat(&self, j: usize) -> (f64, f64, f64, f64) {
        let left = if j == 0 { self.legs.len() - 1 } else { j - 1 };
        let (legs, over) = (self.legs, self.over);
        let (m, c, magnitude) = compose(legs[j], over[j], over[left], legs[left]);
        (m, c, self.left2[j], magnitude)
    }

    /// Cell j's collapsed rods, `zs` the recomputed z of the row's two
    /// fronts.
    #[inline(always)]
    fn rods(&self, zs: &[f64], j: usize) -> [f64; 2] {
        let front = zs.len() / 2;
        let right = if j + 1 == front { 0 } else { j + 1 };
        let at = [zs[j], zs[right], zs[front + j], zs[front + right]];
        rods_of(at, self.spans[j], self.invs[j])
    }
}

/// `verify` of a regular, extrinsic sheet or loop, row by row: each row's
/// legs measured once into arrays (`Row`), each invariant's residuals
/// computed over the row in a simple loop and compared with the check's
/// largest as they are computed (`Watch`); a row that may hold a new
/// largest is recorded again one residual at a time. The same residuals,
/// in the same order, with the same arithmetic as `verify_with`, so the
/// same report bit for bit (a unit test holds the two together, on good
/// and damaged lattices). None, as soon as a row's cells do not hold the
/// corners of the grid (`verify` then takes the pass over the cells).
fn verify_rows(lattice: &Lattice, grid: &Grid) -> Option<Report> {
    use Invariant as I;
    let Grid {
        width,
        rows,
        front,
        closed,
    } = *grid;
    let mut local = Local {
        leg_sum: 0.0,
        straight: Check::new(I::RodStraightness),
        legs_z: Check::new(I::LegsMatchZ),
        seed: Check::new(I::SeedKappa),
        closure: Check::new(I::LoopClosure),
    };
    let [
        mut pores_h,
        mut pores_v,
        mut edges,
        mut slope,
        mut intercept,
        mut natural,
    ] = [
        I::HorizontalPores,
        I::VerticalPores,
        I::SharedEdges,
        I::CompatibilitySlope,
        I::CompatibilityIntercept,
        I::CompatibilityInterceptNatural,
    ]
    .map(Check::new);
    let mut collapsed = Collapsed::new(lattice);
    let (mut above, mut here, mut below) = (Row::default(), Row::default(), Row::default());
    if rows > 0 && !here.measure(lattice, grid, 0, &mut local) {
        return None;
    }
    // Cells with a right neighbour: all of a loop's, all but a sheet's last.
    let paired = if closed { width } else { width - 1 };
    // The first cell whose UL vertex has a cell on its left.
    let from = if closed { 0 } else { 1 };
    let n = width;
    for i in 0..rows {
        let first = i * width;
        let cells = &lattice.cells[first..first + width];
        let cell_site = |k: usize| lattice.cell_name(&cells[k]);
        let has_below = i + 1 < rows;
        if has_below && !below.measure(lattice, grid, i + 1, &mut local) {
            return None;
        }
        // The collapsed sweep (each cell's z from the cells before it),
        // with the collapsed rods, whose corners' z are final once the
        // cell is swept.
        let rods_watch = collapsed.sweep_row(lattice, grid, i, &here);
        // Each residual with a neighbour over the row, in loops over the
        // row's cells, compared with its check's largest as it is computed.
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
        let compat_cells = if i >= 1 { from..n } else { 0..0 };
        // Each residual's formula, written once: the watch loops and the
        // replays below must compute the same bits, or a replay could miss
        // a cell the watch let through.
        let pore = |(num, s): (f64, f64)| [num / s];
        let compat = |j: usize| {
            let (m, c, s2, magnitude) = view.compat(j);
            [m - 1.0, c / s2, c / magnitude]
        };
        let [mut w_pores_h, mut w_pores_v, mut w_edges] =
            [&pores_h, &pores_v, &edges].map(Watch::of);
        for j in 0..paired {
            let h = view.pore_h(j);
            w_pores_h.cell(j, pore(h));
            w_edges.cell(j, [view.edge_right(j, h.1)]);
        }
        for j in 0..n_below {
            let v = view.pore_v(j);
            w_pores_v.cell(j, pore(v));
            w_edges.cell(j, [view.edge_below(j, v.1)]);
        }
        let [mut w_slope, mut w_intercept, mut w_natural] =
            [&slope, &intercept, &natural].map(Watch::of);
        for j in compat_cells.clone() {
            let [slope, intercept, natural] = compat(j);
            w_slope.cell(j, [slope]);
            w_intercept.cell(j, [intercept]);
            w_natural.cell(j, [natural]);
        }
        // The same residuals again, for the cells that may raise a check.
        // The collapsed rods are measured again after the sweep if some
        // cell was not reached.
        if collapsed.all_reached {
            let zs = &collapsed.z[i * front..(i + 2) * front];
            let rods = |j: usize| view.rods(zs, j);
            rods_watch.settle(&mut collapsed.rods, 2 * n, rods, cell_site);
        }
        let bends = |j: usize| view.local(j).0;
        here.straight
            .settle(&mut local.straight, 2 * n, bends, cell_site);
        let legs_z = |j: usize| view.local(j).1;
        here.legs_z
            .settle(&mut local.legs_z, 4 * n, legs_z, cell_site);
        let pore_h = |j: usize| pore(view.pore_h(j));
        w_pores_h.settle(&mut pores_h, paired, pore_h, cell_site);
        let pore_v = |j: usize| pore(view.pore_v(j));
        w_pores_v.settle(&mut pores_v, n_below, pore_v, cell_site);
        // A cell's right edge, then its bottom edge, as the pass over the
        // cells records them.
        let edge = |j: usize| {
            let right = (j < paired).then(|| view.edge_right(j, view.pore_h(j).1));
            let below = (j < n_below).then(|| view.edge_below(j, view.pore_v(j).1));
            [right, below].into_iter().flatten()
        };
        w_edges.settle(&mut edges, paired + n_below, edge, cell_site);
        let vertex = |k: usize| vertex_site(lattice, cells[k].ul as usize);
        let interior = compat_cells.len();
        w_slope.settle(&mut slope, interior, |j| [compat(j)[0]], vertex);
        w_intercept.settle(&mut intercept, interior, |j| [compat(j)[1]], vertex);
        w_natural.settle(&mut natural, interior, |j| [compat(j)[2]], vertex);
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
    let checks = [
        straight, legs_z, seed, pores_h, pores_v, edges, closure, slope, intercept, natural,
    ];
    Some(report(lattice, leg_sum, checks, collapsed))
}

/// `Collapsed::reached` of a cell reached through no corner.
const UNREACHED: u8 = u8::MAX;

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
struct Collapsed {
    single: Check,
    rods: Check,
    z: Vec<f64>,
    /// For every cell swept, in cell order, the corner (0 to 3: UL, UR,
    /// LL, LR) whose z gave the pivot's, or `UNREACHED`.
    reached: Vec<u8>,
    all_reached: bool,
    /// Swept by rows (`sweep_row`): a `Block` of the comparison with the
    /// construction for every front of vertices, then every row of cells,
    /// and the largest `vertex_extent`, measured in the rows' pass.
    blocks: Option<Blocks>,
}

/// What the rows' pass measured of the comparison with the construction,
/// so that `Collapsed::finish` replays only the fronts and rows that may
/// hold a new largest residual: for a good lattice a few, not the whole
/// lattice read again.
struct Blocks {
    /// Vertices a front, cells a row.
    front: usize,
    width: usize,
    fronts: Vec<Block>,
    rows: Vec<Block>,
    extent: f64,
}

impl Blocks {
    fn new(grid: &Grid) -> Self {
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
struct Block {
    num: f64,
    den: f64,
    sum: f64,
}

impl Block {
    /// A block of no comparison yet.
    const EMPTY: Self = Self {
        num: 0.0,
        den: f64::INFINITY,
        sum: 0.0,
    };

    /// Plain comparisons (one instruction each), not `f64::max` and `min`,
    /// whose rules for NaN `sum` already covers.
    #[inline(always)]
    fn add(&mut self, num: f64, den: f64) {
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
    fn new(lattice: &Lattice) -> Self {
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
    /// and measure its rods (`verify_rows` has `sweep_row` compare each
    /// swept cell's rods with their check as it goes, and settles them
    /// after the row: the z of a swept cell's corners are final).
    #[inline]
    fn step(
        &mut self,
        lattice: &Lattice,
        c: usize,
        (legs, inv): (&Legs, f64),
        corners: &[DVec3; 4],
    ) {
        let cell = &lattice.cells[c];
        let [l1, l2, l3, l4] = *legs;
        let at = cell.corner_ids().map(|v| v as usize);
        let site = || lattice.cell_name(cell);
        let (k, _, zs) = sweep(
            &mut self.single,
            &mut self.z,
            at,
            [-l1, -l4, l2, l3],
            inv,
            site,
        );
        self.reached.push(k);
        if k == UNREACHED {
            self.all_reached = false;
            return;
        }
        if self.all_reached {
            let [ul, ur, ll, lr] = *corners;
            let spans = [ul.distance(lr), ur.distance(ll)];
            for r in rods_of(zs, spans, inv) {
                self.rods.record(r, site);
            }
        }
    }

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
            let [l1, l2, l3, l4] = *legs;
            let at = [j, right, front + j, front + right];
            let offsets = [-l1, -l4, l2, l3];
            let site = || lattice.cell_name(cell);
            let (k, zp, zs) = sweep(&mut self.single, z, at, offsets, inv, site);
            self.reached.push(k);
            rods.cell(j, rods_of(zs, spans, inv));
            // The pivot's z is what `finish` takes again (NaN if unreached).
            block.add(zp - cell.z_pivot, cell.z_pivot.abs());
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
            block.add(zc - vertex.z, z);
        }
        blocks.extent = extent;
        blocks.fronts.push(block);
    }

    /// The last front of a grid swept by rows (`rows` of them).
    fn last_front(&mut self, lattice: &Lattice, grid: &Grid) {
        let blocks = self.blocks.get_or_insert_with(|| Blocks::new(grid));
        Self::front_block(blocks, lattice, &self.z, grid.rows);
    }

    /// The comparison with the construction, after the sweep, on the scale
    /// of the lattice's mean leg (`leg_sum` over the cells): the vertices'
    /// first, then the pivots', each front and row replayed unless its
    /// `Block` shows it holds no new largest. Also the largest
    /// `vertex_extent` (measured by the rows' pass, if any).
    fn finish(self, lattice: &Lattice, leg_sum: f64) -> ([Check; 3], f64) {
        let Self {
            single,
            mut rods,
            z,
            reached,
            all_reached,
            blocks,
        } = self;
        let global = leg_sum / lattice.cells.len().max(1) as f64;
        let mut matches = Check::new(Invariant::CollapsedMatchesConstruction);
        // Without blocks, the whole lattice is one front and one row, each
        // replayed.
        let (front, width, fronts, rows, extent) = match blocks {
            Some(b) => (b.front, b.width, b.fronts, b.rows, b.extent),
            None => (
                lattice.vertices.len().max(1),
                lattice.cells.len().max(1),
                Vec::new(),
                Vec::new(),
                lattice
                    .vertices
                    .iter()
                    .fold(0.0, |e: f64, v| e.max(vertex_extent(v))),
            ),
        };
        let quiet = |blocks: &[Block], k: usize, check: &Check| {
            blocks.get(k).is_some_and(|b| b.quiet(check, global))
        };
        for (f, vertices) in lattice.vertices.chunks(front).enumerate() {
            if quiet(&fronts, f, &matches) {
                matches.count += vertices.len();
                continue;
            }
            for (k, vertex) in vertices.iter().enumerate() {
                let v = f * front + k;
                matches.record_ratio(z[v] - vertex.z, global + vertex.z.abs(), || {
                    vertex_site(lattice, v)
                });
            }
        }
        for (i, (cells, reached)) in lattice
            .cells
            .chunks(width)
            .zip(reached.chunks(width))
            .enumerate()
        {
            if quiet(&rows, i, &matches) {
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
                        z[v as usize] - off
                    }
                };
                matches.record_ratio(zp - cell.z_pivot, global + cell.z_pivot.abs(), || {
                    lattice.cell_name(cell)
                });
            }
        }
        if !all_reached {
            rods = Check::new(Invariant::CollapsedRodLength);
            for cell in &lattice.cells {
                let site = || lattice.cell_name(cell);
                let inv = 1.0 / mean(&lattice.legs(cell));
                let [ul, ur, ll, lr] = lattice.corners(cell);
                rods.record(
                    (z[cell.lr as usize] - z[cell.ul as usize] - ul.distance(lr)) * inv,
                    site,
                );
                rods.record(
                    (z[cell.ll as usize] - z[cell.ur as usize] - ur.distance(ll)) * inv,
                    site,
                );
            }
        }
        ([single, matches, rods], extent)
    }
}

/// The sweep of one cell whose corners UL, UR, LL, LR have their z at
/// `z[at[k]]` (NaN while unknown), `offsets[k]` from its pivot's (docs/math.md
/// 3.2): the pivot's z from the first corner that has one, then each
/// corner in turn set, or compared with what it has (`inv` = 1 / the
/// cell's mean leg). Returns that corner, the pivot's z and the corners'
/// z (final: a z once set never changes), or `UNREACHED` and NaN (and
/// records a failure) when none has a z.
#[inline(always)]
fn sweep(
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
            single.record((*slot - expect) * inv, &site);
        }
        *out = *slot;
    }
    (k as u8, zp, zs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::{Kind, fixtures};

    fn sheet() -> Lattice {
        fixtures::sheet(&fixtures::line(3), &[0.0; 3], 1, 45.0, 3)
    }

    /// `record` keeps the largest residual (a NaN sticks) and its first
    /// site; the shortcuts of `record_ratio` and `record_bend` keep the largest
    /// residual, its site and the count of `record` of the full formula,
    /// over residuals of every magnitude, with zeros, NaNs and infinities.
    #[test]
    fn shortcut_records_match_the_full_formula() {
        let mut rng = crate::rng::Rng::new(14);
        let value = |rng: &mut crate::rng::Rng| match rng.next_u64() % 40 {
            0 => 0.0,
            1 => f64::NAN,
            2 => f64::INFINITY,
            3 => f64::MIN_POSITIVE * rng.signed(),
            _ => rng.signed() * 10f64.powf(60.0 * rng.signed()),
        };
        for round in 0..200 {
            let (mut full, mut ratio) = (
                Check::new(Invariant::HorizontalPores),
                Check::new(Invariant::HorizontalPores),
            );
            let (mut full_bend, mut bend_check) = (
                Check::new(Invariant::RodStraightness),
                Check::new(Invariant::RodStraightness),
            );
            let mut reference: (f64, Option<String>) = (0.0, None);
            for k in 0..500 {
                // Mostly near-equal residuals, as in a good lattice.
                let scale = if round % 2 == 0 { 1e-12 } else { 1.0 };
                let num = if k % 7 == 0 {
                    value(&mut rng)
                } else {
                    scale * rng.signed()
                };
                let den = if k % 11 == 0 {
                    value(&mut rng)
                } else {
                    1.0 + rng.uniform()
                };
                let site = || format!("{k}");
                // `record`'s rule spelled out: a NaN sticks once seen, a
                // larger residual (or the first NaN) replaces the largest.
                let r = num / den;
                if !reference.0.is_nan() && (r.is_nan() || r.abs() > reference.0) {
                    reference = (r.abs(), Some(site()));
                }
                full.record(r, site);
                ratio.record_ratio(num, den, site);
                let a = DVec3::new(rng.signed(), scale * rng.signed(), num.min(1e3));
                let b = DVec3::new(rng.signed(), rng.signed(), rng.signed());
                let (la, lb) = (1.0 + rng.uniform(), den);
                full_bend.record(bend(a, la, b, lb), site);
                bend_check.record_bend((a, la), (b, lb), site);
            }
            assert_eq!(full.count, 500);
            assert_eq!(full.max.to_bits(), reference.0.to_bits(), "round {round}");
            assert_eq!(full.site, reference.1, "round {round}");
            for (x, y) in [(&full, &ratio), (&full_bend, &bend_check)] {
                assert_eq!(x.count, y.count);
                assert_eq!(x.max.to_bits(), y.max.to_bits(), "round {round}");
                assert_eq!(x.site, y.site, "round {round}");
            }
        }
    }

    /// A tube of `n` points round a circle, `rows` rows tilted up.
    fn tube(n: usize, rows: usize) -> Lattice {
        let step = glam::DQuat::from_rotation_z(std::f64::consts::TAU / n as f64);
        let ring: Vec<DVec3> = std::iter::successors(Some(30.0 * DVec3::X), |p| Some(step * *p))
            .take(n)
            .collect();
        let row = crate::lattice::RowParams {
            direction: Some(crate::legs::Direction::Angles {
                angle_deg: 45.0,
                tilt_deg: 90.0,
            }),
            ..Default::default()
        };
        crate::lattice::grow(Kind::Loop, 3, &ring, &vec![0.0; n], &vec![row; rows])
            .expect("the tube grows")
    }

    /// A grown sheet or loop is a grid whose formula names the cells the
    /// table read from the corner indices holds, for every vertex, and
    /// verification gives the same report with either; a cell with other
    /// corners, or a vertex more, makes it a table again.
    #[test]
    fn a_grid_names_the_cells_of_the_table() {
        // The tube of templates/tube.toml: ten points round a circle.
        let tube = tube(10, 3);
        for lattice in [sheet(), tube] {
            let grid = Incidence::grid(&lattice).expect("a grown sheet or loop is a grid");
            let Incidence::Table(table) = Incidence::table(&lattice) else {
                unreachable!("a table")
            };
            assert_eq!(table.len(), lattice.vertices.len());
            for (v, entry) in table.iter().enumerate() {
                let rc = (v / grid.front, v % grid.front);
                assert_eq!(grid.at_vertex(rc.0, rc.1), *entry, "vertex {v}");
            }
            // Both give the same report, bit for bit.
            assert_eq!(
                verify_with(&lattice, &Incidence::table(&lattice)),
                verify(&lattice)
            );
            let mut odd = lattice.clone();
            odd.cells[1].ur = odd.cells[1].ul;
            assert!(Incidence::grid(&odd).is_none());
            let mut extra = lattice.clone();
            extra.vertices.push(extra.vertices[0]);
            assert!(Incidence::grid(&extra).is_none());
        }
    }

    /// Two reports the same bits (NaN included, which `==` would not
    /// allow): every check's largest, site and count, and the tolerance.
    fn same_bits(x: &Report, y: &Report) -> bool {
        let key = |r: &Report| {
            let checks: Vec<_> = r
                .checks
                .iter()
                .map(|c| (c.invariant, c.count, c.max.to_bits(), c.site.clone()))
                .collect();
            (checks, r.tolerance.to_bits(), r.interior_vertices)
        };
        key(x) == key(y)
    }

    /// Verification by rows gives the report of the pass over the cells,
    /// bit for bit, on sheets and loops both good and damaged: positions,
    /// pivots and z moved by amounts from rounding to gross, NaN and
    /// infinite coordinates, a cell's column renamed, a corner index moved off the grid.
    #[test]
    fn rows_give_the_report_of_the_pass_over_the_cells() {
        let tube = tube(7, 4);
        let wide = fixtures::sheet(&fixtures::line(6), &[0.0; 6], 2, 40.0, 5);
        // Rows enough that most fronts and rows are left out of the
        // comparison with the construction, unless damaged (`Block`).
        let tall = fixtures::sheet(&fixtures::line(12), &[0.0; 12], 5, 45.0, 12);
        let mut rng = crate::rng::Rng::new(5);
        for lattice in [sheet(), wide, tube, tall] {
            let grid = Incidence::grid(&lattice).expect("a grid");
            assert!(lattice.extrinsic());
            let table = Incidence::table(&lattice);
            assert!(same_bits(
                &verify_rows(&lattice, &grid).expect("a regular grid"),
                &verify_with(&lattice, &table)
            ));
            for round in 0..300 {
                let mut bad = lattice.clone();
                for _ in 0..1 + round % 3 {
                    let size = match rng.next_u64() % 6 {
                        0 => f64::NAN,
                        1 => f64::INFINITY,
                        k => 10f64.powi(-(3 * k as i32)) * rng.signed(),
                    };
                    let v = (rng.next_u64() % bad.vertices.len() as u64) as usize;
                    let c = (rng.next_u64() % bad.cells.len() as u64) as usize;
                    let axis = (rng.next_u64() % 3) as usize;
                    match rng.next_u64() % 6 {
                        0 => bad.vertices[v].pos[axis] += size,
                        1 => bad.vertices[v].z += size,
                        2 => bad.cells[c].pivot[axis] += size,
                        3 => bad.cells[c].z_pivot += size,
                        4 => bad.cells[c].col ^= 1,
                        // A corner index off the grid: the rows' pass
                        // gives up at that row, the pass over the cells
                        // reports.
                        _ => bad.cells[c].lr = bad.cells[c].ll,
                    }
                }
                let rows = verify(&bad);
                let cells = verify_with(&bad, &Incidence::table(&bad));
                assert!(
                    same_bits(&rows, &cells),
                    "round {round}: {rows:?} {cells:?}"
                );
            }
        }
    }

    /// A cell reached through no corner fails the collapsed state, and the
    /// rod lengths are then measured after the sweep with the final z:
    /// those of the cells that were reached stay exact.
    #[test]
    fn a_disconnected_cell_fails_and_the_rods_are_measured_after_the_sweep() {
        let good = verify(&sheet());
        assert!(good.passed());
        let mut lattice = sheet();
        // Give the last cell four corners of its own: no cell before it
        // reaches them.
        let last = lattice.cells.len() - 1;
        let cell = lattice.cells[last];
        for corner in cell.corner_ids() {
            let copy = lattice.vertices[corner as usize];
            lattice.vertices.push(copy);
        }
        let n = lattice.vertices.len() as u32;
        let c = &mut lattice.cells[last];
        (c.ul, c.ur, c.ll, c.lr) = (n - 4, n - 3, n - 2, n - 1);
        let report = verify(&lattice);
        let single = report.check(Invariant::CollapsedSingleValued);
        assert!(single.max.is_nan(), "{single:?}");
        assert!(
            single
                .site
                .as_deref()
                .is_some_and(|s| s.contains("not connected"))
        );
        // The last cell's corners have no z (NaN): its rods fail.
        assert!(report.check(Invariant::CollapsedRodLength).max.is_nan());
        assert!(!report.passed());
    }
}
