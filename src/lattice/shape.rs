//! The shape the cut strips make, measured from each cell's own corners
//! (what the strips physically fix), never from a picture's placement:
//! discrete Gaussian curvature (angle defects), regularity of the cells,
//! how far rebuilt fronts miss the rows they join, and how many different
//! strips there are. Target fit and coverage depend on the recipe's target
//! and live with it (`design::fit`).

use super::{Cell, Kind, Lattice, Legs, angle_between};
use glam::DVec3;
use std::f64::consts::TAU;

/// An angle defect beyond this (degrees) counts as curved, positive or
/// negative; below it a vertex is flat (a planar grid's defects are ~1e-14).
pub const CURVED_DEG: f64 = 0.5;
/// Strips whose hole-to-hole legs agree within this (mm) are the same strip.
pub(crate) const SAME_STRIP_MM: f64 = 0.05;

/// The discrete curvature at one interior vertex (shared by four cells).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexCurvature {
    /// Index into `Lattice::vertices`.
    pub vertex: u32,
    /// 2 pi minus the four corner angles, each from its own cell (radians).
    pub defect: f64,
    /// A quarter of the four cells' areas (mm^2).
    pub(crate) area: f64,
    /// Gaussian curvature `defect / area` (1/mm^2).
    pub k: f64,
}

/// How far the rebuilt fronts of an intrinsic lattice miss the rows they
/// join, after the best rigid placement: the bending the strips must take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrontGaps {
    /// Largest and mean miss (mm).
    pub(crate) max: f64,
    pub(crate) mean: f64,
    /// The same, relative to the mean front edge of their rows.
    pub max_rel: f64,
    pub(crate) mean_rel: f64,
    /// The row whose front misses most.
    pub(crate) worst_row: usize,
}

/// Every shape measure of a lattice that needs no target.
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    pub(crate) curvature: Vec<VertexCurvature>,
    /// Largest / smallest cell area.
    pub(crate) area_ratio: f64,
    /// Longest / shortest leg of the whole lattice.
    pub(crate) leg_ratio: f64,
    /// Shortest leg of the whole lattice (mm).
    pub min_leg: f64,
    /// Longest / shortest leg within a cell: the median and the largest.
    pub(crate) cell_leg_ratio_median: f64,
    pub(crate) cell_leg_ratio_max: f64,
    /// How far rebuilt fronts miss the rows they join; None for an extrinsic
    /// lattice.
    pub front_gaps: Option<FrontGaps>,
    /// Distinct strips (legs equal within `SAME_STRIP_MM`), and all strips.
    pub distinct_strips: usize,
    pub(crate) strips: usize,
}

/// The four corner angles of a cell, in corner order `[UL, UR, LL, LR]`,
/// from its own (planar) corners. Each edge is normalised once for the two
/// corners it joins: `b - a` is exactly `-(a - b)` in floating point, and so
/// are its normalised form, cross and dot products, so the angles are bit
/// for bit those of normalising the two edges at every corner.
pub(crate) fn corner_angles(c: [DVec3; 4]) -> [f64; 4] {
    let [ul, ur, ll, lr] = c;
    let top = (ur - ul).normalize();
    let left = (ll - ul).normalize();
    let right = (lr - ur).normalize();
    let bottom = (lr - ll).normalize();
    [
        angle_between(top, left),
        angle_between(-top, right),
        angle_between(-left, bottom),
        angle_between(-right, -bottom),
    ]
}

/// A cell's legs `[l1, l2, l3, l4]` from its pivot to UL, LL, LR, UR, given
/// its corners `[UL, UR, LL, LR]`: `Lattice::legs` from corners at hand.
#[inline]
pub(crate) fn legs_of(corners: [DVec3; 4], pivot: DVec3) -> Legs {
    let [ul, ur, ll, lr] = corners;
    [
        pivot.distance(ul),
        pivot.distance(ll),
        pivot.distance(lr),
        pivot.distance(ur),
    ]
}

/// Area of a cell: half the cross product of its diagonals (the rods cross,
/// so the quad is planar and convex).
pub(crate) fn cell_area(c: [DVec3; 4]) -> f64 {
    let [ul, ur, ll, lr] = c;
    0.5 * (lr - ul).cross(ll - ur).length()
}

/// The angle defects and curvatures of a lattice's vertices, summed cell
/// by cell and emitted in vertex order as the cells pass.
///
/// Each vertex's count, angle sum and area sum live in a ring of `window`
/// slots (vertex v in slot v mod window), as the planar misfits keep their
/// placements: growth numbers a cell's corners within about two fronts of
/// each other, so a few thousand slots stand for the whole lattice (on 4 M
/// cells: 96 MB fewer, and in cache). Every cell's corners lie in
/// `(high - window, high]`, `high` the largest corner so far; no later
/// cell then reaches a vertex at or below `high - window`, whose sums are
/// final and are emitted, freeing its slot for the vertex `window` above.
/// A cell whose corners lie farther apart (cells stored out of order)
/// stops the ring (`add` says false) and the caller measures again with a
/// slot for every vertex. Sums are taken in cell order either way, so the
/// numbers are those of one slot per vertex bit for bit.
struct Curvatures {
    /// Cells seen, sum of their corner angles, sum of their areas.
    sums: Vec<(u32, f64, f64)>,
    mask: usize,
    /// The largest corner seen, and the next vertex to emit.
    high: usize,
    next: usize,
    out: Vec<VertexCurvature>,
}

impl Curvatures {
    /// A ring of `window` slots (a power of two) for `vertices` vertices.
    fn new(vertices: usize, window: usize) -> Self {
        Self {
            sums: vec![(0, 0.0, 0.0); window],
            mask: window - 1,
            high: 0,
            next: 0,
            // Reserved, not touched: the pages of the unused part are
            // never faulted in, and `finish` hands them back.
            out: Vec::with_capacity(vertices),
        }
    }

    /// Add one cell's corner angles and area to its four vertices' sums;
    /// false when its corners do not fit in the ring.
    #[inline]
    fn add(&mut self, ids: [u32; 4], corners: [DVec3; 4], area: f64) -> bool {
        let angles = corner_angles(corners);
        let (lo, hi) = ids
            .iter()
            .fold((u32::MAX, 0), |(l, h), &v| (l.min(v), h.max(v)));
        self.high = self.high.max(hi as usize);
        let window = self.mask + 1;
        if lo as usize + window <= self.high {
            return false;
        }
        if self.high >= window {
            self.emit_to(self.high - window + 1);
        }
        for (v, a) in ids.into_iter().zip(angles) {
            let e = &mut self.sums[v as usize & self.mask];
            e.0 += 1;
            e.1 += a;
            e.2 += area;
        }
        true
    }

    /// Emit the vertices below `end` not yet emitted, and free their slots.
    fn emit_to(&mut self, end: usize) {
        for vertex in self.next..end {
            let (n, sum, area) =
                std::mem::replace(&mut self.sums[vertex & self.mask], (0, 0.0, 0.0));
            // The vertices shared by four cells.
            if n == 4 {
                let defect = TAU - sum;
                let area = area / 4.0;
                self.out.push(VertexCurvature {
                    vertex: vertex as u32,
                    defect,
                    area,
                    k: defect / area.max(f64::MIN_POSITIVE),
                });
            }
        }
        self.next = self.next.max(end);
    }

    /// Every vertex shared by four cells, with its defect and curvature.
    fn finish(mut self, vertices: usize) -> Vec<VertexCurvature> {
        self.emit_to(vertices);
        self.out.shrink_to_fit();
        self.out
    }
}

impl Lattice {
    /// How far each interior vertex of `c` (this lattice's `curvature`)
    /// stands out of the sheet (mm): its height over the mean of its edge
    /// neighbours, along the mean normal of its cells. Each cell's normal
    /// comes from its diagonals, oriented alike in every cell of a grown
    /// lattice, so the sign says to which side: a bump pushed through to
    /// the other side changes it and keeps its defect.
    pub fn heights(&self, c: &[VertexCurvature]) -> Vec<f64> {
        let n = self.vertices.len();
        let mut normal = vec![DVec3::ZERO; n];
        let mut near: Vec<Vec<u32>> = vec![Vec::new(); n];
        for cell in &self.cells {
            let [ul, ur, ll, lr] = self.corners(cell);
            let across = (ur - ll).cross(ul - lr);
            for (v, edges) in [
                (cell.ul, [cell.ur, cell.ll]),
                (cell.ur, [cell.ul, cell.lr]),
                (cell.ll, [cell.ul, cell.lr]),
                (cell.lr, [cell.ur, cell.ll]),
            ] {
                normal[v as usize] += across;
                for e in edges {
                    if !near[v as usize].contains(&e) {
                        near[v as usize].push(e);
                    }
                }
            }
        }
        c.iter()
            .map(|c| {
                let v = c.vertex as usize;
                let ring = &near[v];
                let mean = ring
                    .iter()
                    .map(|&u| self.vertices[u as usize].pos)
                    .sum::<DVec3>()
                    / ring.len().max(1) as f64;
                (self.vertices[v].pos - mean).dot(normal[v].normalize_or_zero())
            })
            .collect()
    }

    /// The angle defect and Gaussian curvature at every vertex shared by
    /// four cells, in vertex order.
    pub fn curvature(&self) -> Vec<VertexCurvature> {
        let (window, full) = self.vertex_rings();
        self.curvature_in(window)
            .or_else(|| self.curvature_in(full))
            .expect("a slot for every vertex")
    }

    /// `curvature` with a ring of `window` slots (`Curvatures`); None when
    /// some cell's corners lie too far apart for it.
    fn curvature_in(&self, window: usize) -> Option<Vec<VertexCurvature>> {
        let mut at = Curvatures::new(self.vertices.len(), window);
        for cell in &self.cells {
            let corners = self.corners(cell);
            let ids = cell.corner_ids();
            if !at.add(ids, corners, cell_area(corners)) {
                return None;
            }
        }
        Some(at.finish(self.vertices.len()))
    }

    /// Every target-free shape measure, in one pass over the cells: each
    /// cell's corners are read once for its area, legs, strips and corner
    /// angles (the same arithmetic, in the same order, as `curvature` and
    /// `legs`, so the figures are those of the separate passes bit for bit).
    /// Two cases read the cells again: strips whose legs spread wider than
    /// the tolerance (most irregular designs) take their keys in a second
    /// pass to sort them, and a lattice stored out of order (wider than the
    /// ring) is measured again with a slot a vertex.
    pub(crate) fn shape(&self) -> Shape {
        let (window, full) = self.vertex_rings();
        self.shape_in(window)
            .or_else(|| self.shape_in(full))
            .expect("a slot for every vertex")
    }

    /// `shape` with the curvature sums in a ring of `window` slots
    /// (`Curvatures`); None when some cell's corners lie too far apart.
    fn shape_in(&self, window: usize) -> Option<Shape> {
        let mut at = Curvatures::new(self.vertices.len(), window);
        let mut regularity = Regularity::new(self.cells.len());
        for cell in &self.cells {
            let (corners, area) = regularity.measure(self, cell);
            if !at.add(cell.corner_ids(), corners, area) {
                return None;
            }
        }
        Some(self.shape_of(at, regularity))
    }

    /// The shape from every cell's curvature sums and regularity.
    fn shape_of(&self, at: Curvatures, regularity: Regularity) -> Shape {
        let Regularity {
            amin,
            amax,
            lo,
            hi,
            ratios: mut cell_ratios,
            range,
        } = regularity;
        // The median and the largest, without sorting the whole list (the
        // ratios in any order: both are order statistics of `total_cmp`).
        let (median, max) = match cell_ratios.len() {
            0 => (1.0, 1.0),
            n => {
                let (_, &mut median, upper) =
                    cell_ratios.select_nth_unstable_by(n / 2, f64::total_cmp);
                let max = upper
                    .iter()
                    .copied()
                    .fold(median, |m, x| if x.total_cmp(&m).is_gt() { x } else { m });
                (median, max)
            }
        };
        drop(cell_ratios);
        let curvature = at.finish(self.vertices.len());
        // Strips whose legs all lie within the tolerance of each other are
        // one class (what sorting them and grouping finds, see `Range`);
        // otherwise their keys are taken in a second pass and sorted.
        let distinct_strips = if self.cells.is_empty() {
            0
        } else if range.within(SAME_STRIP_MM) {
            1
        } else {
            distinct_keys(self.strip_keys())
        };
        Shape {
            curvature,
            area_ratio: amax / amin,
            leg_ratio: hi / lo,
            min_leg: lo,
            cell_leg_ratio_median: median,
            cell_leg_ratio_max: max,
            front_gaps: self.front_gaps(),
            distinct_strips,
            strips: 2 * self.cells.len(),
        }
    }

    /// Every strip's key (`strip_keys`), less the repeats of the key before
    /// it of the same rod (A or B): neighbouring cells of a regular lattice
    /// have the same strips, and only the distinct keys count.
    fn strip_keys(&self) -> Vec<u128> {
        let mut strips = Vec::new();
        let mut last = [None; 2];
        for cell in &self.cells {
            for (key, last) in strip_keys(self.legs(cell)).into_iter().zip(&mut last) {
                if *last != Some(key) {
                    strips.push(key);
                    *last = Some(key);
                }
            }
        }
        strips
    }

    /// How far each rebuilt front misses its row (None for an extrinsic lattice).
    pub(crate) fn front_gaps(&self) -> Option<FrontGaps> {
        if self.extrinsic() {
            return None;
        }
        let (_, gaps) = self.placed_with_gaps();
        let mut out = FrontGaps {
            max: 0.0,
            mean: 0.0,
            max_rel: 0.0,
            mean_rel: 0.0,
            worst_row: 0,
        };
        let (mut n, mut sum, mut sum_rel) = (0usize, 0.0, 0.0);
        for (row, g) in gaps.iter().enumerate() {
            let Some(front) = self.fronts.get(row).filter(|f| !f.is_empty()) else {
                continue;
            };
            let edges = if self.kind == Kind::Loop {
                front.len()
            } else {
                front.len() - 1
            };
            let edge = (0..edges)
                .map(|j| front[j].distance(front[(j + 1) % front.len()]))
                .sum::<f64>()
                / edges.max(1) as f64;
            for &d in g {
                if d > out.max {
                    out.max = d;
                    out.worst_row = row;
                }
                out.max_rel = out.max_rel.max(d / edge);
                sum += d;
                sum_rel += d / edge;
                n += 1;
            }
        }
        out.mean = sum / n.max(1) as f64;
        out.mean_rel = sum_rel / n.max(1) as f64;
        Some(out)
    }
}

/// The regularity figures of cells: the smallest and largest area and leg,
/// each cell's longest over shortest leg, and the range of its strips'
/// legs. Every figure is a least, a largest or a list whose order the shape
/// does not read.
struct Regularity {
    amin: f64,
    amax: f64,
    lo: f64,
    hi: f64,
    ratios: Vec<f64>,
    /// The range of the strips' short and long legs, as `order_key`s.
    range: Range,
}

impl Regularity {
    /// Room for `cells` cells' ratios.
    fn new(cells: usize) -> Self {
        Self {
            amin: f64::INFINITY,
            amax: 0.0,
            lo: f64::INFINITY,
            hi: 0.0,
            ratios: Vec::with_capacity(cells),
            range: Range::default(),
        }
    }

    /// One cell, of this area and these legs.
    #[inline]
    fn add(&mut self, area: f64, legs: Legs) {
        (self.amin, self.amax) = (self.amin.min(area), self.amax.max(area));
        let (l, h) = legs
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        self.lo = self.lo.min(l);
        self.hi = self.hi.max(h);
        self.ratios.push(h / l);
        for key in strip_keys(legs) {
            self.range.add(key);
        }
    }

    /// One cell of `lattice` added: its corners and area, for the
    /// curvature sums.
    #[inline]
    fn measure(&mut self, lattice: &Lattice, cell: &Cell) -> ([DVec3; 4], f64) {
        let corners = lattice.corners(cell);
        let area = cell_area(corners);
        self.add(area, legs_of(corners, cell.pivot));
        (corners, area)
    }
}

/// A key whose unsigned order is `f64::total_cmp`'s (negative numbers have
/// every bit flipped, the others their sign bit set).
fn order_key(x: f64) -> u64 {
    let b = x.to_bits();
    if b >> 63 == 1 { !b } else { b | 1 << 63 }
}

/// The `(short leg, long leg)` pair as one integer ordered as the pairs
/// are (by short leg, then long leg): sorting millions of them is then an
/// integer sort.
fn strip_key(short: f64, long: f64) -> u128 {
    (order_key(short) as u128) << 64 | order_key(long) as u128
}

/// The number inverse to `order_key`.
fn key_value(k: u64) -> f64 {
    f64::from_bits(if k >> 63 == 1 { k & !(1 << 63) } else { !k })
}

/// The keys of a cell's two strips, rod A's (legs 1 and 3) and rod B's
/// (legs 4 and 2): a strip turned end for end is the same strip.
fn strip_keys(legs: Legs) -> [u128; 2] {
    let [l1, l2, l3, l4] = legs;
    [
        strip_key(l1.min(l3), l1.max(l3)),
        strip_key(l4.min(l2), l4.max(l2)),
    ]
}

/// The least and largest short leg and long leg of strips, as `order_key`s.
///
/// When both ranges are within the tolerance, `classes` finds one class
/// without sorting: its first strip has the least short leg `a0` and any
/// other `(a, b)` has `a - a0 <= max - min` and `|b - b0| <= max - min` of
/// the long legs, in floating point too (a rounded difference grows with
/// its first term and falls with its second).
struct Range {
    short: (u64, u64),
    long: (u64, u64),
}

impl Default for Range {
    fn default() -> Self {
        Self {
            short: (u64::MAX, 0),
            long: (u64::MAX, 0),
        }
    }
}

impl Range {
    #[inline]
    fn add(&mut self, key: u128) {
        let (s, l) = ((key >> 64) as u64, key as u64);
        self.short = (self.short.0.min(s), self.short.1.max(s));
        self.long = (self.long.0.min(l), self.long.1.max(l));
    }

    /// Both ranges within `tol` (false for NaN or infinite legs).
    fn within(&self, tol: f64) -> bool {
        let spread = |(lo, hi): (u64, u64)| key_value(hi) - key_value(lo);
        spread(self.short) <= tol && spread(self.long) <= tol
    }
}

/// The number of distinct strips among `strip_key`s.
fn distinct_keys(mut keys: Vec<u128>) -> usize {
    keys.sort_unstable();
    // Equal keys are equal strips, which join the same class: one of each
    // is enough for the greedy pass below.
    keys.dedup();
    classes(
        keys.iter()
            .map(|&k| (key_value((k >> 64) as u64), key_value(k as u64))),
    )
}

/// The number of distinct strips among `(short leg, long leg)` pairs.
#[cfg(test)]
fn distinct(strips: &mut [(f64, f64)]) -> usize {
    strips.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    classes(strips.iter().copied())
}

/// Greedy classes over strips sorted by short leg: a strip joins a class
/// when both legs are within the tolerance of the class's first strip.
fn classes(sorted: impl Iterator<Item = (f64, f64)>) -> usize {
    let mut classes: Vec<(f64, f64)> = Vec::new();
    for (a, b) in sorted {
        let found = classes
            .iter()
            .rev()
            .take_while(|c| a - c.0 <= SAME_STRIP_MM)
            .any(|c| (b - c.1).abs() <= SAME_STRIP_MM);
        if !found {
            classes.push((a, b));
        }
    }
    classes.len()
}

/// Summary statistics of the curvature, for reports and objectives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvatureSummary {
    /// Number of interior vertices measured.
    pub interior: usize,
    /// Defects in degrees.
    pub min_deg: f64,
    /// Mean angle defect (degrees).
    pub mean_deg: f64,
    /// Largest angle defect (degrees).
    pub max_deg: f64,
    /// Share of interior vertices with defect beyond +-`CURVED_DEG`.
    pub positive: f64,
    /// Share of interior vertices with defect below -`CURVED_DEG`.
    pub negative: f64,
    /// Mean and standard deviation of K (1/mm^2).
    pub k_mean: f64,
    /// Standard deviation of K over the interior vertices (1/mm^2).
    pub k_std: f64,
    /// Where the extremes are (indices into `Lattice::vertices`).
    pub(crate) min_at: u32,
    pub(crate) max_at: u32,
}

/// How many of the interior vertices `c` are dome-like (angle defect at
/// least +`deg` degrees: a bump or a cup) and how many saddle-like (at
/// most -`deg`).
pub fn relief(c: &[VertexCurvature], deg: f64) -> (usize, usize) {
    c.iter().fold((0, 0), |(dome, saddle), v| {
        let d = v.defect.to_degrees();
        (
            dome + usize::from(d >= deg),
            saddle + usize::from(d <= -deg),
        )
    })
}

/// Over how many rows and how many columns of `lattice` the interior
/// vertices `c` whose defect (degrees) passes `keep` spread.
pub fn spread(
    lattice: &Lattice,
    c: &[VertexCurvature],
    keep: impl Fn(f64) -> bool,
) -> (usize, usize) {
    let mut spread = Spread::default();
    for v in c.iter().filter(|v| keep(v.defect.to_degrees())) {
        spread.add(lattice, v);
    }
    spread.counts()
}

/// The rows and columns some interior vertices lie on (`spread`).
#[derive(Default)]
struct Spread {
    rows: std::collections::BTreeSet<u32>,
    cols: std::collections::BTreeSet<u32>,
}

impl Spread {
    fn add(&mut self, lattice: &Lattice, v: &VertexCurvature) {
        let key = lattice.vertex(v.vertex).key;
        self.rows.insert(key.row);
        self.cols.insert(key.col);
    }

    /// How many rows and how many columns.
    fn counts(&self) -> (usize, usize) {
        (self.rows.len(), self.cols.len())
    }
}

/// Defect and Gaussian-curvature statistics of the interior vertices `c`;
/// None when there are none.
pub fn summary(c: &[VertexCurvature]) -> Option<CurvatureSummary> {
    summary_visiting(c, |_, _| {})
}

/// The check report's curvature figures: `summary`, `relief` at `deg`
/// and the `spread` of the vertices at or beyond +`deg`, in the one pass
/// `summary` takes (and its second, for K's variance) rather than four
/// passes over the list (128 MB on 4 M cells).
pub(crate) fn survey(
    lattice: &Lattice,
    c: &[VertexCurvature],
    deg: f64,
) -> (Option<CurvatureSummary>, (usize, usize), (usize, usize)) {
    let (mut domes, mut saddles) = (0, 0);
    let mut spread = Spread::default();
    let summary = summary_visiting(c, |v, d| {
        let dome = d >= deg;
        domes += usize::from(dome);
        saddles += usize::from(d <= -deg);
        if dome {
            spread.add(lattice, v);
        }
    });
    (summary, (domes, saddles), spread.counts())
}

/// `summary`, showing `visit` every vertex with its defect in degrees.
fn summary_visiting(
    c: &[VertexCurvature],
    mut visit: impl FnMut(&VertexCurvature, f64),
) -> Option<CurvatureSummary> {
    if c.is_empty() {
        return None;
    }
    let n = c.len() as f64;
    // One pass for all but the variance (no list of the defects in
    // degrees: 32 MB on 4 M cells); the sums run in vertex order, as
    // summing the lists would.
    let (mut min_i, mut max_i) = (0, 0);
    let (mut min_deg, mut max_deg) = (c[0].defect.to_degrees(), c[0].defect.to_degrees());
    // From -0.0, as `Sum` starts (defects all -0.0 sum to -0.0).
    let (mut deg_sum, mut k_sum) = (-0.0, -0.0);
    let (mut positive, mut negative) = (0usize, 0usize);
    for (i, v) in c.iter().enumerate() {
        let d = v.defect.to_degrees();
        visit(v, d);
        if d < min_deg {
            (min_i, min_deg) = (i, d);
        }
        if d > max_deg {
            (max_i, max_deg) = (i, d);
        }
        deg_sum += d;
        k_sum += v.k;
        positive += usize::from(d > CURVED_DEG);
        negative += usize::from(d < -CURVED_DEG);
    }
    let k_mean = k_sum / n;
    let k_var = c.iter().map(|v| (v.k - k_mean).powi(2)).sum::<f64>() / n;
    Some(CurvatureSummary {
        interior: c.len(),
        min_deg,
        mean_deg: deg_sum / n,
        max_deg,
        positive: positive as f64 / n,
        negative: negative as f64 / n,
        k_mean,
        k_std: k_var.sqrt(),
        min_at: c[min_i].vertex,
        max_at: c[max_i].vertex,
    })
}

/// A sheet of `3 + trial % 7` uneven cells a row and `3 + trial % 5` rows,
/// random seed points, kappa and start leg (tilted out of the plane in
/// 3-D); None when it does not grow.
#[cfg(test)]
pub(crate) fn random_sheet(rng: &mut crate::rng::Rng, trial: usize, dim: usize) -> Option<Lattice> {
    use super::{RowParams, grow};
    use crate::legs::{Direction, Leg};
    let n = 3 + trial % 7;
    let points: Vec<DVec3> = (0..=n)
        .map(|j| {
            let (x, y) = (10.0 * j as f64 + rng.signed(), 0.3 * rng.signed());
            DVec3::new(x, y, if dim == 3 { 2.0 * rng.signed() } else { 0.0 })
        })
        .collect();
    let kappa: Vec<f64> = (0..n).map(|_| 0.4 * rng.signed()).collect();
    let row = RowParams {
        start: n / 2,
        direction: Some(Direction::Angles {
            angle_deg: 45.0 + 15.0 * rng.signed(),
            tilt_deg: if dim == 3 { 10.0 * rng.signed() } else { 0.0 },
        }),
        left_leg: Leg::Match,
        right_leg: Leg::Match,
        ..RowParams::default()
    };
    grow(Kind::Sheet, dim, &points, &kappa, &vec![row; 3 + trial % 5]).ok()
}

/// The sheets `random_sheet` grows in `trials` trials from `seed`, the
/// trial's dimension `dim(trial)`.
#[cfg(test)]
pub(crate) fn random_sheets(
    seed: u64,
    trials: usize,
    dim: impl Fn(usize) -> usize,
) -> Vec<Lattice> {
    let mut rng = crate::rng::Rng::new(seed);
    (0..trials)
        .filter_map(|trial| random_sheet(&mut rng, trial, dim(trial)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::{RowParams, grow};
    use crate::legs::{Direction, Leg};

    fn grid(rows: usize) -> Lattice {
        let points: Vec<DVec3> = (0..6)
            .map(|j| DVec3::new(40.0 * j as f64, 0.0, 0.0))
            .collect();
        let row = RowParams {
            direction: Some(Direction::Angles {
                angle_deg: 45.0,
                tilt_deg: 0.0,
            }),
            left_leg: Leg::Match,
            right_leg: Leg::Match,
            ..RowParams::default()
        };
        grow(Kind::Sheet, 2, &points, &[0.0; 5], &vec![row; rows]).unwrap()
    }

    /// Every figure of a curvature list, as bits.
    fn curvature_bits(c: &[VertexCurvature]) -> Vec<(u32, u64, u64, u64)> {
        c.iter()
            .map(|v| {
                (
                    v.vertex,
                    v.defect.to_bits(),
                    v.area.to_bits(),
                    v.k.to_bits(),
                )
            })
            .collect()
    }

    #[test]
    fn a_planar_grid_is_flat_everywhere() {
        let lattice = grid(5);
        let c = lattice.curvature();
        // 4 interior rows of front vertices x 4 interior columns.
        assert_eq!(c.len(), 16);
        for v in &c {
            assert!(v.defect.abs() < 1e-12, "{v:?}");
            assert!(v.area > 0.0);
        }
        let s = lattice.shape();
        assert!((s.area_ratio - 1.0).abs() < 1e-9, "{}", s.area_ratio);
        assert_eq!(s.distinct_strips, 1);
        assert_eq!(s.strips, 50);
        assert!(s.front_gaps.is_none());
        let sum = summary(&c).unwrap();
        assert_eq!((sum.positive, sum.negative), (0.0, 0.0));
    }

    #[test]
    fn corner_angles_of_a_square_and_a_kite() {
        let sq = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, -2.0, 0.0),
            DVec3::new(2.0, -2.0, 0.0),
        ];
        for a in corner_angles(sq) {
            assert!((a - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        }
        assert!((cell_area(sq) - 4.0).abs() < 1e-12);
        let kite = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(3.0, 0.0, 0.0),
        ];
        let s: f64 = corner_angles(kite).iter().sum();
        assert!((s - TAU).abs() < 1e-12);
        // Bit for bit the angles of normalising both edges at each corner.
        let at =
            |p: DVec3, a: DVec3, b: DVec3| angle_between((a - p).normalize(), (b - p).normalize());
        let mut rng = crate::rng::Rng::new(3);
        for _ in 0..1000 {
            let mut p = || DVec3::new(rng.signed(), rng.signed(), rng.signed()) * 40.0;
            let [ul, ur, ll, lr] = [p(), p(), p(), p()];
            let each = [
                at(ul, ur, ll),
                at(ur, ul, lr),
                at(ll, ul, lr),
                at(lr, ur, ll),
            ];
            let got = corner_angles([ul, ur, ll, lr]);
            assert_eq!(got.map(f64::to_bits), each.map(f64::to_bits));
        }
    }

    #[test]
    fn distinct_strips_merge_within_the_tolerance_only() {
        let mut s = vec![(10.0, 20.0), (10.04, 20.0), (10.0, 20.2), (10.1, 20.0)];
        assert_eq!(distinct(&mut s), 3);
    }

    #[test]
    fn integer_keys_sort_and_count_as_the_pairs_do() {
        let mut rng = crate::rng::Rng::new(7);
        let vals = [-0.0, 0.0, -1.5, 1e-300, f64::INFINITY, 3.25];
        for x in vals {
            assert_eq!(key_value(order_key(x)).to_bits(), x.to_bits());
        }
        for a in vals {
            for b in vals {
                assert_eq!(order_key(a).cmp(&order_key(b)), a.total_cmp(&b));
            }
        }
        let mut pairs: Vec<(f64, f64)> = (0..2000)
            .map(|_| {
                let a = 10.0 + (rng.uniform() * 40.0).round() * 0.01;
                let b = a + (rng.uniform() * 30.0).round() * 0.01;
                (a, b)
            })
            .collect();
        let keys = pairs.iter().map(|&(a, b)| strip_key(a, b)).collect();
        assert_eq!(distinct_keys(keys), distinct(&mut pairs));
    }

    /// The ring of curvature sums measures what a slot per vertex does, bit
    /// for bit, down to the smallest ring the corners allow; a ring too
    /// small says so, and a lattice stored out of order is measured with a
    /// slot per vertex. The strips' one-class shortcut counts what sorting
    /// them does.
    #[test]
    fn the_ring_of_curvature_sums_measures_what_a_slot_per_vertex_does() {
        let mut rng = crate::rng::Rng::new(11);
        let mut measured = 0;
        for trial in 0..24 {
            let Some(lattice) = random_sheet(&mut rng, trial, 2 + trial % 2) else {
                continue;
            };
            let nv = lattice.vertices.len();
            let full = nv.next_power_of_two();
            let every = lattice.curvature_in(full).expect("a slot for every vertex");
            assert!(!every.is_empty());
            let (usual, _) = lattice.vertex_rings();
            assert_eq!(curvature_bits(&lattice.curvature()), curvature_bits(&every));
            let shape = lattice.shape_in(full).expect("a slot for every vertex");
            assert_eq!(curvature_bits(&shape.curvature), curvature_bits(&every));
            assert_eq!(lattice.shape(), shape);
            let mut smallest = usual;
            for window in [4, 8, 16, 32].into_iter().filter(|&w| w < usual) {
                if let Some(ring) = lattice.curvature_in(window) {
                    assert_eq!(curvature_bits(&ring), curvature_bits(&every));
                    smallest = smallest.min(window);
                }
            }
            assert!(lattice.curvature_in(2).is_none());
            assert!(smallest <= (lattice.width + 3).next_power_of_two());
            // The strips counted by sorting every key.
            assert_eq!(shape.distinct_strips, distinct_keys(lattice.strip_keys()));
            measured += 1;
            let mut reversed = lattice.clone();
            reversed.cells.reverse();
            assert!(reversed.curvature_in(8).is_none());
            let mut sorted = curvature_bits(&reversed.curvature());
            sorted.sort();
            assert_eq!(sorted.len(), every.len());
            assert!(reversed.shape_in(8).is_none());
            assert_eq!(reversed.shape().curvature, reversed.curvature());
        }
        assert!(measured >= 12, "{measured} lattices grew");
        // One class without sorting: a regular grid's strips, and strips
        // spread just within the tolerance; a little more takes the sort.
        let g = grid(4);
        assert_eq!(g.shape().distinct_strips, 1);
        assert_eq!(distinct_keys(g.strip_keys()), 1);
        for (spread, within) in [(0.049, true), (0.051, false)] {
            let mut range = Range::default();
            let keys = [
                strip_key(10.0, 20.0),
                strip_key(10.0 + spread, 20.0 - spread),
            ];
            keys.iter().for_each(|&k| range.add(k));
            assert_eq!(range.within(SAME_STRIP_MM), within);
            assert_eq!(distinct_keys(keys.to_vec()), if within { 1 } else { 2 });
        }
        let mut range = Range::default();
        range.add(strip_key(f64::NAN, 20.0));
        assert!(!range.within(SAME_STRIP_MM));
    }

    /// The survey gives `summary`, `relief` and `spread` as they are.
    #[test]
    fn the_survey_is_the_summary_relief_and_spread() {
        let mut bumpy = 0;
        for lattice in random_sheets(19, 16, |_| 3) {
            let c = lattice.curvature();
            for deg in [0.0, 0.5, 3.0] {
                let (sum, relief_at, spread_at) = survey(&lattice, &c, deg);
                assert_eq!(sum, summary(&c));
                assert_eq!(relief_at, relief(&c, deg));
                assert_eq!(spread_at, spread(&lattice, &c, |d| d >= deg));
                bumpy += usize::from(spread_at.0 > 0);
            }
        }
        assert!(bumpy > 0, "no vertex at or beyond the thresholds");
        let sheets = random_sheets(19, 8, |_| 2);
        let flat = sheets.first().expect("a sheet grew");
        assert_eq!(survey(flat, &[], 3.0), (None, (0, 0), (0, 0)));
    }

    /// The one-pass summary is the lists' arithmetic bit for bit, down to
    /// the sign of a zero mean.
    #[test]
    fn the_summary_in_one_pass_is_the_lists_bit_for_bit() {
        let mut rng = crate::rng::Rng::new(13);
        let vertex = |i: u32, defect: f64, area: f64| VertexCurvature {
            vertex: i,
            defect,
            area,
            k: defect / area,
        };
        let random: Vec<VertexCurvature> = (0..500)
            .map(|i| vertex(i, 0.05 * rng.signed(), 10.0 + rng.uniform()))
            .collect();
        let zeros: Vec<VertexCurvature> = (0..5).map(|i| vertex(i, -0.0, 1.0)).collect();
        for c in [&random, &zeros] {
            let n = c.len() as f64;
            let deg: Vec<f64> = c.iter().map(|v| v.defect.to_degrees()).collect();
            let k_mean = c.iter().map(|v| v.k).sum::<f64>() / n;
            let s = summary(c).unwrap();
            assert_eq!(
                s.mean_deg.to_bits(),
                (deg.iter().sum::<f64>() / n).to_bits()
            );
            assert_eq!(s.k_mean.to_bits(), k_mean.to_bits());
            let lo = deg.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = deg.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            assert_eq!((s.min_deg, s.max_deg), (lo, hi));
            let first = |x: f64| deg.iter().position(|&d| d == x).unwrap() as u32;
            assert_eq!((s.min_at, s.max_at), (first(lo), first(hi)));
            let share = |f: fn(f64) -> bool| deg.iter().filter(|&&d| f(d)).count() as f64 / n;
            assert_eq!(s.positive, share(|d| d > CURVED_DEG));
            assert_eq!(s.negative, share(|d| d < -CURVED_DEG));
        }
        assert!(summary(&zeros).unwrap().mean_deg.is_sign_negative());
    }
}
