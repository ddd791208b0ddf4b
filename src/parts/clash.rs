//! Strip clashes: two strips that share no joint, lie in the same stacking
//! layer (docs/math.md 10.2) and whose centre lines (hole to hole, plus the end
//! margins) come closer than the strip width plus a clearance overlap in
//! the built piece. Found with a uniform grid over the strips' bounding
//! boxes, one layer at a time, so a lattice of n strips costs about n, not n^2.

use crate::lattice::{Lattice, RodType};

pub(crate) mod bent;
use glam::DVec3;

/// Two strips of one stacking layer, sharing no joint, whose centre lines
/// come closer than the strip width plus the clearance: they overlap.
#[derive(Clone, Debug, PartialEq)]
pub struct Clash {
    /// Rod ids (lattice.json order), the smaller first.
    pub(crate) rods: [usize; 2],
    /// Distance between the two centre lines (mm).
    pub(crate) distance: f64,
    /// Midpoint of the closest points: where they meet.
    pub(crate) at: DVec3,
}

/// A strip's centre line: the rod from tip to tip. 64 bytes: the normal
/// `pair` tests first is worked out there, for the few pairs whose boxes
/// meet, rather than stored for every line (a layer of a 4 M-cell sheet
/// has two million lines).
#[derive(Clone, Default)]
struct Line {
    a: DVec3,
    b: DVec3,
    /// Rod id (lattice.json order).
    rod: u32,
    /// Its two vertices (a rod's pivot is its own cell's: two rods of one
    /// cell are in different layers, and are also told apart below).
    start: u32,
    end: u32,
}

/// Buffers of the search, each layer's kept for the next layer: the
/// lattice's largest allocations then take their pages from the kernel
/// once, not once a layer.
#[derive(Default)]
pub(crate) struct Scratch {
    /// The rods of each layer.
    layers: Vec<Vec<u32>>,
    lines: Vec<Line>,
    lengths: Vec<f64>,
    long: Vec<bool>,
    spans: Vec<[u32; 3]>,
    offset: Vec<u32>,
    entries: Vec<u32>,
}

/// The clashes of `lattice` (for an intrinsic lattice, pass the assembled
/// one: the rows placed onto each other), strips `width` wide with
/// `margin` beyond the end holes: all counted, the closest `KEPT` kept.
///
/// Only strips of one layer can clash, so the layers are searched one at a
/// time: each with a uniform grid of cells about one strip's box wide, each
/// strip listed in every grid cell its box (widened by half the reach)
/// touches. Two strips closer than the reach share the grid cell of the
/// midpoint of their closest points; a pair is measured once, in the first
/// grid cell the two boxes share. Cost and memory are linear in the strips.
pub fn clashes(lattice: &Lattice, width: f64, margin: f64, clearance: f64) -> Clashes {
    clashes_in(lattice, width, margin, clearance, Scratch::default())
}

/// `clashes`, searched in the buffers of `scratch`.
pub(crate) fn clashes_in(
    lattice: &Lattice,
    width: f64,
    margin: f64,
    clearance: f64,
    scratch: Scratch,
) -> Clashes {
    let mut found = Clashes::keeping(KEPT);
    search(lattice, width, margin, clearance, scratch, &mut |c| {
        found.add(c);
    });
    found.finish();
    found
}

/// How many clashes of `lattice` pass `counts` (strips as in `clashes`),
/// none of them kept: the row fit's score of a trial row.
pub(crate) fn count_clashes(
    lattice: &Lattice,
    width: f64,
    margin: f64,
    clearance: f64,
    counts: impl Fn(&Clash) -> bool,
) -> usize {
    let mut n = 0;
    search(
        lattice,
        width,
        margin,
        clearance,
        Scratch::default(),
        &mut |c| n += usize::from(counts(&c)),
    );
    n
}

/// How many of the closest clashes a search keeps: what the reports show
/// (the closest pair; `check --json` lists the first hundred) and the
/// optimiser's cost sums by distance, with room to spare. A lattice of
/// many overlapping strips has clashes by the square of them (a 1,000-row
/// torus 588,000, a 3,000-point tube 4.4 million): only their count and
/// distances' sum grow past this, not the memory (a buffer of at most
/// 32,768 clashes of 48 bytes: 20,000 found are cut back to 10,000).
pub const KEPT: usize = 10_000;

/// The clashes a search found: all counted, the closest kept, closest
/// first (in distance, then rod id order: the same whatever order they
/// were found in).
#[derive(Clone, Debug, PartialEq)]
pub struct Clashes {
    /// The closest `keep` (closest first once `finish`ed); while the search
    /// runs, up to twice as many, in the order found.
    closest: Vec<Clash>,
    keep: usize,
    count: usize,
    /// Distances of the clashes counted but not kept, summed.
    dropped_distance: f64,
}

impl Clashes {
    fn keeping(keep: usize) -> Self {
        Self {
            closest: Vec::new(),
            keep,
            count: 0,
            dropped_distance: 0.0,
        }
    }

    /// How many clashes were found (kept or not).
    pub fn len(&self) -> usize {
        self.count
    }

    /// No clash found.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The closest clash.
    pub fn first(&self) -> Option<&Clash> {
        self.closest.first()
    }

    /// The kept clashes, closest first: all of them unless `dropped`
    /// says otherwise.
    pub fn iter(&self) -> std::slice::Iter<'_, Clash> {
        self.closest.iter()
    }

    /// How many clashes were counted but not kept (all farther than the
    /// kept ones), and their distances summed.
    pub fn dropped(&self) -> (usize, f64) {
        (self.count - self.closest.len(), self.dropped_distance)
    }

    #[inline]
    fn add(&mut self, c: Clash) {
        self.count += 1;
        self.closest.push(c);
        if self.closest.len() >= 2 * self.keep.max(1) {
            self.cut();
        }
    }

    /// Only the closest `keep` left, unordered (amortised: once every
    /// `keep` clashes found). Kept out of line: `add` is inlined into the
    /// search's pair loop, which slows by a fifth when it grows (measured).
    #[cold]
    #[inline(never)]
    fn cut(&mut self) {
        if self.closest.len() > self.keep {
            if self.keep > 0 {
                self.closest.select_nth_unstable_by(self.keep - 1, closer);
            }
            self.dropped_distance += self.closest[self.keep..]
                .iter()
                .map(|c| c.distance)
                .sum::<f64>();
            self.closest.truncate(self.keep);
        }
    }

    fn finish(&mut self) {
        self.cut();
        self.closest.sort_by(closer);
    }
}

impl<'a> IntoIterator for &'a Clashes {
    type Item = &'a Clash;
    type IntoIter = std::slice::Iter<'a, Clash>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

/// Closest first, then by rod ids (a pair is found once): a total order.
fn closer(a: &Clash, b: &Clash) -> std::cmp::Ordering {
    a.distance.total_cmp(&b.distance).then(a.rods.cmp(&b.rods))
}

/// Every clash of `lattice` (strips as in `clashes`) to `found`, in the
/// search's order.
fn search(
    lattice: &Lattice,
    width: f64,
    margin: f64,
    clearance: f64,
    mut scratch: Scratch,
    found: &mut impl FnMut(Clash),
) {
    let reach = width + clearance;
    // Rods grouped by layer, in id order within a layer: one pass over the
    // cells (a counting sort would read them twice, 56 bytes a cell).
    let mut layers = std::mem::take(&mut scratch.layers);
    layers.iter_mut().for_each(Vec::clear);
    let rods_per_layer = lattice.cells.len() / 2;
    for (c, cell) in lattice.cells.iter().enumerate() {
        for (r, kind) in [(2 * c, RodType::A), (2 * c + 1, RodType::B)] {
            let l = lattice.layer(cell, kind) as usize;
            if layers.len() <= l {
                // Room for a quarter of the rods (four layers, as most
                // lattices have): reserved, not touched.
                layers.resize_with(l + 1, || Vec::with_capacity(rods_per_layer));
            }
            layers[l].push(r as u32);
        }
    }
    for ids in &layers {
        layer_clashes(lattice, ids, margin, reach, &mut scratch, found);
    }
}

/// The clashes among `ids`, rods of one layer in increasing id order.
fn layer_clashes(
    lattice: &Lattice,
    ids: &[u32],
    margin: f64,
    reach: f64,
    scratch: &mut Scratch,
    found: &mut impl FnMut(Clash),
) {
    if ids.len() < 2 {
        return;
    }
    assert!(
        ids.len() <= INDEX as usize,
        "a layer of more than 2^29 strips"
    );
    let Scratch {
        layers: _,
        lines,
        lengths,
        long,
        spans,
        offset,
        entries,
    } = scratch;
    let (lo, hi) = layer_lines(lattice, ids, margin, lines);
    if lines.len() < 2 {
        return;
    }
    let Some(grid) = Grid::new(lines, lengths, reach, lo, hi) else {
        return;
    };
    // A strip far longer than the rest (a runaway design tried by the
    // optimiser) would be listed in every grid cell of its whole box, which
    // can be billions: such strips are measured against every strip
    // instead. Marked as the grid is filled (`long`).
    long.clear();
    long.resize(lines.len(), false);
    let lines = &lines[..];
    // Far above the rounding of a projection (1e-16 of the coordinates):
    // a pair is only skipped when it is surely out of reach.
    let slack = 1e-9 * (1.0 + grid.lo.abs().max(grid.hi.abs()).max_element());
    let far = (reach + slack) * (reach + slack);
    // A pair is measured in the first grid cell both boxes touch only: the
    // cell where, on every axis, one of the two boxes starts. Each entry of
    // a grid cell's list carries the axes on which its box starts there
    // (`entry`), so that test reads no line; the list is sorted into a
    // bucket per set of axes (stable: line order within a bucket), and only
    // buckets whose sets cover every axis together are paired, so the
    // pairs that cannot count (most of them) are never visited.
    //
    // Most pairs left have boxes apart by the reach (strips of the rows
    // above and below): `pair`'s first test, taken here on the list's
    // boxes, each computed once a grid cell rather than once a pair, so
    // that only pairs whose boxes meet read their lines.
    let mut boxes: Vec<Boxed> = Vec::new();
    let mut visit = |list: &mut [u32]| visit_cell(list, &mut boxes, lines, reach, far, found);
    let grid_cells = grid.dims.iter().try_fold(1usize, |a, &d| a.checked_mul(d));
    match grid_cells {
        // A dense grid when it is not much larger than the strips (sheets).
        Some(g) if g <= 4 * lines.len() + 1024 => {
            dense_grid(&grid, g, lines, long, spans, offset, entries, &mut visit);
        }
        // Sparse (a curved surface in a large box): the entries sorted by cell.
        _ => sparse_grid(&grid, lines, long, &mut visit),
    }
    long_pairs(lines, long, reach, far, found);
}

/// The layer's lines, each widened by `margin` at both ends, into `lines`;
/// returns their bounding box.
#[inline]
fn layer_lines(
    lattice: &Lattice,
    ids: &[u32],
    margin: f64,
    lines: &mut Vec<Line>,
) -> (DVec3, DVec3) {
    lines.clear();
    // The lines' bounding box, taken as they are built (one pass over them).
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for &r in ids {
        let cell = &lattice.cells[r as usize / 2];
        // Corners UL to LR for an A rod, UR to LL for a B (`corners`).
        let (s, e, start, end) = if r % 2 == 0 {
            (
                lattice.corner(cell, 0),
                lattice.corner(cell, 3),
                cell.ul,
                cell.lr,
            )
        } else {
            (
                lattice.corner(cell, 1),
                lattice.corner(cell, 2),
                cell.ur,
                cell.ll,
            )
        };
        let dir = (e - s).normalize_or_zero();
        let (a, b) = (s - margin * dir, e + margin * dir);
        // A line with a NaN coordinate never clashes (its closest points
        // to any line are NaN), and would hide from the box (glam's `min`
        // and `max` keep either side of a NaN): it is left out.
        if a.is_nan() || b.is_nan() {
            continue;
        }
        (lo, hi) = (lo.min(a.min(b)), hi.max(a.max(b)));
        lines.push(Line {
            a,
            b,
            rod: r,
            start,
            end,
        });
    }
    (lo, hi)
}

/// A layer's uniform grid: the box it covers and its cells' size.
struct Grid {
    lo: DVec3,
    hi: DVec3,
    half: DVec3,
    inv_h: f64,
    dims: [usize; 3],
}

impl Grid {
    /// The grid of `lines` in their box [lo, hi], widened by half the
    /// reach; none when that box is not finite.
    #[inline]
    fn new(
        lines: &[Line],
        lengths: &mut Vec<f64>,
        reach: f64,
        lo: DVec3,
        hi: DVec3,
    ) -> Option<Grid> {
        // Grid cells `GRID_STRIPS` strips long, so each strip touches a few: a
        // strip's length is the median of a sample of the lines spread over
        // the layer (the grid's size changes how fast the search is, never
        // what it finds).
        lengths.clear();
        let step = (lines.len() / LENGTH_SAMPLES).max(1);
        lengths.extend(lines.iter().step_by(step).map(|l| l.a.distance(l.b)));
        let mid = lengths.len() / 2;
        let median = *lengths.select_nth_unstable_by(mid, f64::total_cmp).1;
        let half = DVec3::splat(reach / 2.0);
        let (lo, hi) = (lo - half, hi + half);
        if !(lo.is_finite() && hi.is_finite()) {
            return None;
        }
        // Never more than about 2^20 grid cells along an axis.
        let h = (GRID_STRIPS * (median + reach))
            .max(1e-6)
            .max((hi - lo).max_element() / (1u64 << 20) as f64);
        // Every point keyed lies in the box [lo, hi], so the quotient is not
        // negative and truncation is its floor (without a libm call). A product
        // by 1 / h rather than a quotient (three divisions a key, six keys a
        // line): the keys may differ from the quotient's by a rounding, but
        // they still grow with the point, which is all the grid needs.
        let inv_h = 1.0 / h;
        let mut grid = Grid {
            lo,
            hi,
            half,
            inv_h,
            dims: [0; 3],
        };
        grid.dims = grid.key(hi).map(|k| k as usize + 1);
        Some(grid)
    }

    /// The grid cell of a point of the box.
    #[inline]
    fn key(&self, p: DVec3) -> [i32; 3] {
        let q = (p - self.lo) * self.inv_h;
        [q.x as i32, q.y as i32, q.z as i32]
    }

    /// Grid cells of the lower and upper corners of a line's box widened by
    /// half the reach: computed where needed rather than stored (a layer of
    /// a 4 M-cell sheet has a million lines).
    #[inline]
    fn span(&self, l: &Line) -> ([i32; 3], [i32; 3]) {
        (
            self.key(l.a.min(l.b) - self.half),
            self.key(l.a.max(l.b) + self.half),
        )
    }
}

/// Whether a span covers so many grid cells that its strip is measured
/// against every strip instead (`long`).
#[inline]
fn is_long((lo, hi): ([i32; 3], [i32; 3])) -> bool {
    (0..3)
        .map(|k| i64::from(hi[k] - lo[k]) + 1)
        .product::<i64>()
        > 512
}

/// The clash of two strips of this layer whose boxes are not apart by
/// the reach (`Boxed::apart`, taken first), if they clash.
#[inline]
fn pair(li: &Line, lj: &Line, reach: f64, far: f64) -> Option<Clash> {
    if [li.start, li.end]
        .iter()
        .any(|v| [lj.start, lj.end].contains(v))
        || li.rod / 2 == lj.rod / 2
    {
        return None;
    }
    // Projections on any unit axis are no farther apart than the
    // strips: across the first strip, parallel neighbours (most of the
    // pairs whose boxes meet) are apart by more than the reach. The
    // axis is the xy normal of its direction, not normalised: the gap
    // of the projections on it and its length are compared squared (no
    // square root or division a pair), within the slack, far above
    // their rounding. A strip along z has no such normal (gap 0).
    // Only finite figures rule a pair out: at coordinates near 1e150 mm
    // the squares overflow (inf >= inf) or a projection is NaN, which
    // min and max would drop; such a pair goes to the exact test.
    let d = li.b - li.a;
    let (nx, ny) = (-d.y, d.x);
    let across = |p: DVec3| p.x * nx + p.y * ny;
    let (i0, i1, j0, j1) = (across(li.a), across(li.b), across(lj.a), across(lj.b));
    let gap = (j0.min(j1) - i0.max(i1)).max(i0.min(i1) - j0.max(j1));
    let bound = far * (nx * nx + ny * ny);
    let finite = bound.is_normal() && [i0, i1, j0, j1].iter().all(|x| x.is_finite());
    if gap > 0.0 && finite && gap * gap >= bound {
        return None;
    }
    let (li, lj) = if li.rod < lj.rod { (li, lj) } else { (lj, li) };
    let (p, q) = closest_points(li.a, li.b, lj.a, lj.b);
    let d = p.distance(q);
    (d < reach).then(|| Clash {
        rods: [li.rod as usize, lj.rod as usize],
        distance: d,
        at: (p + q) / 2.0,
    })
}

/// The pairs of one grid cell's list (`layer_clashes`).
#[inline]
fn visit_cell(
    list: &mut [u32],
    boxes: &mut Vec<Boxed>,
    lines: &[Line],
    reach: f64,
    far: f64,
    found: &mut impl FnMut(Clash),
) {
    // An entry holds its axes above its line's index: in numeric order
    // the list comes bucket by bucket, in line order within each (a
    // line is listed once in a grid cell).
    list.sort_unstable();
    let mut bounds = [0usize; BUCKETS + 1];
    boxes.clear();
    boxes.extend(list.iter().map(|&e| {
        bounds[(e >> INDEX_BITS) as usize + 1] += 1;
        Boxed::of(e & INDEX, &lines[(e & INDEX) as usize])
    }));
    for m in 0..BUCKETS {
        bounds[m + 1] += bounds[m];
    }
    let bucket = |m: usize| &boxes[bounds[m]..bounds[m + 1]];
    let mut measure = |i: &Boxed, j: &Boxed| {
        if !i.apart(j, reach) {
            // The earlier line first, as in the list.
            let (i, j) = if i.line < j.line { (i, j) } else { (j, i) };
            if let Some(c) = pair(&lines[i.line as usize], &lines[j.line as usize], reach, far) {
                found(c);
            }
        }
    };
    let all = bucket(ALL_AXES as usize);
    for (n, i) in all.iter().enumerate() {
        for j in &all[n + 1..] {
            measure(i, j);
        }
    }
    for m in 0..ALL_AXES as usize {
        let first = bucket(m);
        if first.is_empty() {
            continue;
        }
        for n in (m + 1..BUCKETS).filter(|&n| m | n == ALL_AXES as usize) {
            for i in first {
                for j in bucket(n) {
                    measure(i, j);
                }
            }
        }
    }
}

/// The dense grid: each grid cell's list in `entries`, from `offset`.
#[allow(clippy::too_many_arguments)]
#[inline]
fn dense_grid(
    grid: &Grid,
    g: usize,
    lines: &[Line],
    long: &mut [bool],
    spans: &mut Vec<[u32; 3]>,
    offset: &mut Vec<u32>,
    entries: &mut Vec<u32>,
    visit: &mut impl FnMut(&mut [u32]),
) {
    let dims = grid.dims;
    let index = |k: [i32; 3]| k[0] as usize + dims[0] * (k[1] as usize + dims[1] * k[2] as usize);
    // The grid cells of a span: the first of each run along x, and
    // the run's length.
    let (row, plane) = (dims[0], dims[0] * dims[1]);
    let runs = |(lo, hi): ([i32; 3], [i32; 3])| {
        let first = index(lo);
        let n = [0, 1, 2].map(|k| (hi[k] - lo[k]) as usize + 1);
        (0..n[2]).flat_map(move |z| {
            (0..n[1]).map(move |y| (first + z * plane + y * row, n[0], z == 0, y == 0))
        })
    };
    // Counted into `offset[c + 1]`, summed, then filled with
    // `offset[c]` as grid cell c's cursor, which leaves it at the
    // start of cell c + 1: cell c's list ends there.
    offset.clear();
    offset.resize(g + 1, 0);
    // Each line's span, kept from the count for the fill (12 bytes
    // a line rather than its keys computed again).
    spans.clear();
    spans.reserve(lines.len());
    for (l, long) in lines.iter().zip(long.iter_mut()) {
        let (lo, h) = grid.span(l);
        if is_long((lo, h)) {
            *long = true;
            spans.push([0; 3]);
            continue;
        }
        spans.push(pack(lo, h));
        for (c, n, _, _) in runs((lo, h)) {
            for count in &mut offset[c + 1..c + 1 + n] {
                *count += 1;
            }
        }
    }
    for c in 0..g {
        offset[c + 1] += offset[c];
    }
    entries.clear();
    entries.resize(offset[g] as usize, 0);
    for (i, &span) in spans.iter().enumerate().filter(|&(i, _)| !long[i]) {
        for (c, n, z0, y0) in runs(unpack(span)) {
            // The axes on which the line's box starts in each cell
            // (`entry`): z and y for the run, x for its first cell.
            let zy = i as u32 | (u32::from(z0) << 2 | u32::from(y0) << 1) << INDEX_BITS;
            for (x, cursor) in offset[c..c + n].iter_mut().enumerate() {
                entries[*cursor as usize] = zy | u32::from(x == 0) << INDEX_BITS;
                *cursor += 1;
            }
        }
    }
    let mut begin = 0;
    for &end in &offset[..g] {
        let list = &mut entries[begin..end as usize];
        if list.len() > 1 {
            visit(list);
        }
        begin = end as usize;
    }
}

/// The sparse grid: the entries sorted by cell.
#[inline]
fn sparse_grid(grid: &Grid, lines: &[Line], long: &mut [bool], visit: &mut impl FnMut(&mut [u32])) {
    let mut entries: Vec<([i32; 3], u32)> = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        let (lo, h) = grid.span(l);
        if is_long((lo, h)) {
            long[i] = true;
            continue;
        }
        for z in lo[2]..=h[2] {
            for y in lo[1]..=h[1] {
                for x in lo[0]..=h[0] {
                    entries.push(([z, y, x], entry(i, lo, [x, y, z])));
                }
            }
        }
    }
    entries.sort_unstable();
    let mut list = Vec::new();
    for run in entries.chunk_by(|a, b| a.0 == b.0) {
        if run.len() > 1 {
            list.clear();
            list.extend(run.iter().map(|e| e.1));
            visit(&mut list);
        }
    }
}

/// The long strips, measured against every strip.
#[inline]
fn long_pairs(lines: &[Line], long: &[bool], reach: f64, far: f64, found: &mut impl FnMut(Clash)) {
    for (i, li) in lines.iter().enumerate() {
        if long[i] {
            let boxed = Boxed::of(0, li);
            // Long against short here; long against long once (j > i).
            for (j, lj) in lines.iter().enumerate() {
                if j != i
                    && (!long[j] || j > i)
                    && !boxed.apart(&Boxed::of(0, lj), reach)
                    && let Some(c) = pair(li, lj, reach, far)
                {
                    found(c);
                }
            }
        }
    }
}

/// Grid cells are this many strips (each its median length plus the
/// reach) wide. Wider cells list each strip in fewer of them but pair more
/// strips in each; on a 500 x 500 sheet (strips at 45 deg) the search
/// took 817, 684, 625, 591, 570, 567, 587, 613 and 690 M instructions at
/// 0.6, 0.8, 1, 1.3, 1.7, 2, 2.5, 3 and 4: 1.7 is within 1 % of the
/// least, and pairs fewer strips a cell than 2 where they lie denser.
const GRID_STRIPS: f64 = 1.7;

/// How many lines of a layer give the median length the grid is sized by.
const LENGTH_SAMPLES: usize = 4096;

/// Bits of a grid entry holding the line's index; the three above them say
/// on which axes the line's box starts in the entry's grid cell.
const INDEX_BITS: u32 = 29;
const INDEX: u32 = (1 << INDEX_BITS) - 1;
const ALL_AXES: u32 = 0b111;
/// One bucket of a grid cell's list per set of axes.
const BUCKETS: usize = 8;

/// A grid cell's entry with its line's bounding box.
struct Boxed {
    line: u32,
    lo: DVec3,
    hi: DVec3,
}

impl Boxed {
    fn of(line: u32, l: &Line) -> Self {
        Self {
            line,
            lo: l.a.min(l.b),
            hi: l.a.max(l.b),
        }
    }

    /// Boxes apart by `reach` on some axis: no clash (and no closest points
    /// to compute). No coordinate is infinite or NaN here (a layer with an
    /// infinite one has no finite box and is not searched; a line with a
    /// NaN one is left out).
    #[inline]
    fn apart(&self, other: &Self, reach: f64) -> bool {
        let (i, j) = (self, other);
        i.lo.x - j.hi.x >= reach
            || j.lo.x - i.hi.x >= reach
            || i.lo.y - j.hi.y >= reach
            || j.lo.y - i.hi.y >= reach
            || i.lo.z - j.hi.z >= reach
            || j.lo.z - i.hi.z >= reach
    }
}

/// Bits of a packed span's axis holding the grid cell where it starts (the
/// grid has at most 2^20 + 2 cells along an axis); the bits above hold how
/// many more cells it covers (at most 511: a span of more than 512 grid
/// cells is a long line's, not packed).
const KEY_BITS: u32 = 21;

/// A short line's span, the grid cells `lo` to `hi`, in 12 bytes.
#[inline]
fn pack(lo: [i32; 3], hi: [i32; 3]) -> [u32; 3] {
    [0, 1, 2].map(|k| lo[k] as u32 | ((hi[k] - lo[k]) as u32) << KEY_BITS)
}

/// The span `pack` packed.
#[inline]
fn unpack(span: [u32; 3]) -> ([i32; 3], [i32; 3]) {
    let lo = span.map(|a| (a & ((1 << KEY_BITS) - 1)) as i32);
    let hi = [0, 1, 2].map(|k| lo[k] + (span[k] >> KEY_BITS) as i32);
    (lo, hi)
}

/// The grid entry of line `i`, whose box starts in grid cell `lo`, in grid
/// cell `at`.
#[inline]
fn entry(i: usize, lo: [i32; 3], at: [i32; 3]) -> u32 {
    let starts = (0..3).fold(0, |m, k| m | u32::from(lo[k] == at[k]) << k);
    i as u32 | starts << INDEX_BITS
}

/// The closest points of segments `p0 p1` and `q0 q1` (Ericson, Real-Time
/// Collision Detection, 5.1.9).
pub(crate) fn closest_points(p0: DVec3, p1: DVec3, q0: DVec3, q1: DVec3) -> (DVec3, DVec3) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    let eps = 1e-18;
    let (s, t);
    if a <= eps && e <= eps {
        return (p0, q0);
    }
    if a <= eps {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(r);
        if e <= eps {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > eps * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    (p0 + d1 * s, q0 + d2 * t)
}

/// A rod as the reports name it: its strip id in parts.csv.
pub(crate) fn rod_name(lattice: &Lattice, rod: usize) -> String {
    let cell = &lattice.cells[rod / 2];
    let kind = if rod.is_multiple_of(2) {
        crate::lattice::RodType::A
    } else {
        crate::lattice::RodType::B
    };
    let max_row = lattice.cells.iter().map(|c| c.row).max().unwrap_or(0);
    let max_col = lattice.cells.iter().map(|c| c.col).max().unwrap_or(0);
    let digits = |m: u32| m.to_string().len().max(2);
    super::strip_id(cell.row, cell.col, kind, digits(max_row), digits(max_col))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::{Kind, Rod, RowParams, grow};
    use crate::legs::{Direction, Leg};

    #[test]
    fn closest_points_of_crossing_parallel_and_skew_segments() {
        let o = DVec3::ZERO;
        let (p, q) = closest_points(
            o,
            DVec3::X * 2.0,
            DVec3::new(1.0, -1.0, 3.0),
            DVec3::new(1.0, 1.0, 3.0),
        );
        assert!(p.distance(DVec3::X) < 1e-12 && q.distance(DVec3::new(1.0, 0.0, 3.0)) < 1e-12);
        let (p, q) = closest_points(
            o,
            DVec3::X,
            DVec3::new(0.5, 2.0, 0.0),
            DVec3::new(3.0, 2.0, 0.0),
        );
        assert!((p.distance(q) - 2.0).abs() < 1e-12);
        let (p, q) = closest_points(
            o,
            DVec3::X,
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(5.0, 0.0, 0.0),
        );
        assert!((p.distance(q) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn a_span_packs_at_the_grids_limits() {
        let far = (1 << 20) + 1;
        for (lo, hi) in [
            ([0, 0, 0], [0, 0, 0]),
            ([far, 7, 0], [far, 7 + 511, 0]),
            ([3, far - 511, far], [3 + 511, far, far]),
        ] {
            assert_eq!(unpack(pack(lo, hi)), (lo, hi));
        }
    }

    /// A sheet of `rows` rows of 40 mm cells, legs at `angle` degrees (the
    /// bent-strip search's tests use it too).
    pub(super) fn sheet(rows: usize, angle: f64) -> Lattice {
        let points: Vec<DVec3> = (0..5)
            .map(|j| DVec3::new(40.0 * j as f64, 0.0, 0.0))
            .collect();
        let row = RowParams {
            direction: Some(Direction::Angles {
                angle_deg: angle,
                tilt_deg: 0.0,
            }),
            left_leg: Leg::Match,
            right_leg: Leg::Match,
            ..RowParams::default()
        };
        grow(Kind::Sheet, 2, &points, &[0.0; 4], &vec![row; rows]).unwrap()
    }

    #[test]
    fn an_open_sheet_has_no_clash() {
        // Square cells of 40 mm: neighbouring parallel strips 28 mm apart.
        assert!(clashes(&sheet(4, 45.0), 10.0, 6.0, 1.0).is_empty());
    }

    #[test]
    fn a_constructed_clash_and_a_near_miss() {
        // Two rows only, so rows i and i+2 never meet: the clashes are the
        // parallel strips of one row. With the legs 5 deg from the cone axis (the
        // front) the cells are nearly collapsed; neighbouring parallel
        // strips are about 40 sin(5 deg) = 3.5 mm apart.
        let flat = sheet(1, 5.0);
        let found = clashes(&flat, 10.0, 6.0, 1.0);
        assert!(!found.is_empty());
        for c in &found {
            let (a, b) = (c.rods[0], c.rods[1]);
            assert_eq!(a % 2, b % 2, "same layer: both A or both B");
            assert!(c.distance < 11.0);
        }
        // The near miss: with the cells this shape, the gap between
        // neighbouring parallel strips is exactly computable; a strip just
        // narrower than it (less the clearance) does not clash.
        let lat = sheet(1, 30.0);
        let rods: Vec<Rod> = lat.rods().collect();
        let (a0, a1) = (rods[0], rods[2]);
        let (p, q) = closest_points(
            a0.hole_pos[0],
            a0.hole_pos[2],
            a1.hole_pos[0],
            a1.hole_pos[2],
        );
        let gap = p.distance(q);
        assert!(gap > 15.0, "{gap}");
        assert!(clashes(&lat, gap - 1.0 - 1e-6, 0.0, 1.0).is_empty());
        let hit = clashes(&lat, gap - 1.0 + 1e-6, 0.0, 1.0);
        assert!(hit.iter().any(|c| c.rods == [0, 2]), "{hit:?}");
    }

    /// The same-layer clashes of `lat` by measuring every pair.
    fn all_pairs(lat: &Lattice) -> usize {
        let lines: Vec<Rod> = lat.rods().collect();
        let mut brute = 0;
        for i in 0..lines.len() {
            for j in i + 1..lines.len() {
                let (a, b) = (&lines[i], &lines[j]);
                let (ca, cb) = (&lat.cells[a.cell], &lat.cells[b.cell]);
                let shared = [a.start, a.end]
                    .iter()
                    .any(|v| [b.start, b.end].contains(v))
                    || a.cell == b.cell;
                if lat.layer(ca, a.kind) != lat.layer(cb, b.kind) || shared {
                    continue;
                }
                let da = (a.hole_pos[2] - a.hole_pos[0]).normalize();
                let db = (b.hole_pos[2] - b.hole_pos[0]).normalize();
                let (p, q) = closest_points(
                    a.hole_pos[0] - 6.0 * da,
                    a.hole_pos[2] + 6.0 * da,
                    b.hole_pos[0] - 6.0 * db,
                    b.hole_pos[2] + 6.0 * db,
                );
                if p.distance(q) < 11.0 {
                    brute += 1;
                }
            }
        }
        brute
    }

    #[test]
    fn the_grid_finds_what_all_pairs_find() {
        let lat = sheet(6, 15.0);
        let brute = all_pairs(&lat);
        assert!(brute > 0);
        assert_eq!(clashes(&lat, 10.0, 6.0, 1.0).len(), brute);
    }

    #[test]
    fn the_grid_finds_what_all_pairs_find_in_space() {
        // Every vertex moved at random, in z too: strips of every direction,
        // some vertical or nearly so.
        let mut rng = crate::rng::Rng::new(11);
        for angle in [15.0, 45.0] {
            let mut lat = sheet(6, angle);
            for v in &mut lat.vertices {
                v.pos += DVec3::new(rng.signed(), rng.signed(), rng.signed()) * 12.0;
            }
            let found = clashes(&lat, 10.0, 6.0, 1.0);
            assert_eq!(found.len(), all_pairs(&lat));
            assert!(!found.is_empty());
        }
    }

    /// `clashes` by measuring every pair of a layer, from the definition:
    /// the oracle of the grid search, clash by clash and bit by bit. A
    /// layer with a line that has no finite box is not searched.
    fn every_pair(lat: &Lattice, width: f64, margin: f64, clearance: f64) -> Vec<Clash> {
        let reach = width + clearance;
        let line = |r: usize| {
            let cell = &lat.cells[r / 2];
            let [ul, ur, ll, lr] = lat.corners(cell);
            let (s, e, ends) = if r.is_multiple_of(2) {
                (ul, lr, [cell.ul, cell.lr])
            } else {
                (ur, ll, [cell.ur, cell.ll])
            };
            let dir = (e - s).normalize_or_zero();
            (s - margin * dir, e + margin * dir, ends)
        };
        let kind = |r: usize| {
            if r.is_multiple_of(2) {
                RodType::A
            } else {
                RodType::B
            }
        };
        let layer = |r: usize| lat.layer(&lat.cells[r / 2], kind(r));
        let rods = 2 * lat.cells.len();
        let mut out = Vec::new();
        let top = (0..rods).map(layer).max().unwrap_or(0);
        for l in 0..=top {
            // A line with a NaN coordinate cannot clash (its closest
            // points are NaN) and is left out of the layer's box.
            let ids: Vec<usize> = (0..rods)
                .filter(|&r| layer(r) == l && !(line(r).0.is_nan() || line(r).1.is_nan()))
                .collect();
            let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
            for &r in &ids {
                let (a, b, _) = line(r);
                (lo, hi) = (lo.min(a.min(b)), hi.max(a.max(b)));
            }
            let half = DVec3::splat(reach / 2.0);
            if !((lo - half).is_finite() && (hi + half).is_finite()) {
                continue;
            }
            for (n, &i) in ids.iter().enumerate() {
                for &j in &ids[n + 1..] {
                    let ((a, b, vi), (c, d, vj)) = (line(i), line(j));
                    if vi.iter().any(|v| vj.contains(v)) || i / 2 == j / 2 {
                        continue;
                    }
                    let (p, q) = closest_points(a, b, c, d);
                    let distance = p.distance(q);
                    if distance < reach {
                        out.push(Clash {
                            rods: [i, j],
                            distance,
                            at: (p + q) / 2.0,
                        });
                    }
                }
            }
        }
        out.sort_by(|a, b| a.distance.total_cmp(&b.distance).then(a.rods.cmp(&b.rods)));
        out
    }

    /// The two lists the same clash by clash, every figure to the bit.
    fn assert_same(found: &Clashes, oracle: &[Clash], what: &str) {
        let bits = |c: &Clash| {
            (
                c.rods,
                c.distance.to_bits(),
                c.at.to_array().map(f64::to_bits),
            )
        };
        assert_eq!(found.len(), oracle.len(), "{what}");
        assert_eq!(found.dropped(), (0, 0.0), "{what}");
        for (f, o) in found.iter().zip(oracle) {
            assert_eq!(bits(f), bits(o), "{what}");
        }
    }

    #[test]
    fn the_grid_finds_every_pairs_clashes_on_random_and_damaged_lattices() {
        let mut rng = crate::rng::Rng::new(14);
        let mut lattices: Vec<(String, Lattice)> = Vec::new();
        for (t, lat) in crate::lattice::shape::random_sheets(5, 24, |t| 2 + t % 2)
            .into_iter()
            .enumerate()
        {
            lattices.push((format!("random sheet {t}"), lat));
        }
        for (rows, angle) in [(6, 15.0), (30, 5.0), (25, 45.0), (12, 80.0)] {
            lattices.push((format!("sheet {rows} rows at {angle}"), sheet(rows, angle)));
        }
        // Damaged copies: every vertex moved at random by up to 1, 12 and
        // 40 mm (in z too, or only in the plane), a vertex thrown far
        // away (long lines; a sparse grid when thrown along z), two
        // vertices made one, and a NaN or an infinite coordinate.
        let base: Vec<(String, Lattice)> = lattices.clone();
        for (name, lat) in &base {
            for (k, amp) in [1.0, 12.0, 40.0].into_iter().enumerate() {
                let mut moved = lat.clone();
                for v in &mut moved.vertices {
                    let z = if k == 1 { 0.0 } else { rng.signed() };
                    v.pos += DVec3::new(rng.signed(), rng.signed(), z) * amp;
                }
                lattices.push((format!("{name}, moved {amp} mm"), moved));
            }
            let n = lat.vertices.len();
            for (what, shift) in [
                ("thrown", DVec3::new(5.0e4, 3.0e4, 2.0e4)),
                ("thrown along z", DVec3::new(0.0, 0.0, 3.0e4)),
                // Far enough that the pair test's squares overflow.
                ("thrown 1e200 mm", DVec3::new(1.0, 0.7, 0.3) * 1e200),
                ("NaN", DVec3::new(f64::NAN, 0.0, 0.0)),
                ("infinite", DVec3::new(0.0, f64::INFINITY, 0.0)),
            ] {
                let mut hurt = lat.clone();
                hurt.vertices[n / 2].pos += shift;
                lattices.push((format!("{name}, a vertex {what}"), hurt));
            }
            let mut merged = lat.clone();
            merged.vertices[n / 3].pos = merged.vertices[n / 3 + 1].pos;
            lattices.push((format!("{name}, two vertices made one"), merged));
        }
        let mut clashing = 0;
        for (name, lat) in &lattices {
            for (width, margin, clearance) in [(10.0, 6.0, 1.0), (30.0, 2.0, 0.5), (4.0, 0.0, 0.0)]
            {
                let oracle = every_pair(lat, width, margin, clearance);
                clashing += usize::from(!oracle.is_empty());
                let found = clashes(lat, width, margin, clearance);
                assert_same(&found, &oracle, &format!("{name}, {width} mm strips"));
            }
        }
        // The cases must clash, or the comparison says little.
        assert!(
            clashing > lattices.len(),
            "{clashing} of {}",
            3 * lattices.len()
        );
    }

    #[test]
    fn a_strip_thrown_past_the_squares_range_keeps_its_near_clash() {
        // The runaway strip's near end still clashes at 10.35 mm; the pair
        // test's squared figures overflow there and must not rule it out
        // (review24's case).
        let mut lat = sheet(6, 15.0);
        lat.vertices[11].pos += DVec3::new(1.0, 0.7, 0.3) * 1e200;
        let oracle = every_pair(&lat, 10.0, 6.0, 1.0);
        assert!(oracle.iter().any(|c| c.rods == [11, 13]));
        assert_same(&clashes(&lat, 10.0, 6.0, 1.0), &oracle, "thrown 1e200 mm");
    }

    #[test]
    fn many_clashes_are_all_counted_and_only_the_closest_kept() {
        // Strips a metre wide on a sheet of 40 mm cells: nearly every pair
        // of a layer clashes, 70,000 or so. All are counted; the closest
        // `keep` are kept, exactly the oracle's first ones, and the buffer
        // stays within a few times that (the search used to keep them all).
        let lat = sheet(100, 30.0);
        let oracle = every_pair(&lat, 1000.0, 6.0, 1.0);
        assert!(oracle.len() > 3 * KEPT, "{}", oracle.len());
        for keep in [1, 7, 1000, KEPT] {
            let mut found = Clashes::keeping(keep);
            let mut most = 0;
            search(&lat, 1000.0, 6.0, 1.0, Scratch::default(), &mut |c| {
                found.add(c);
                most = most.max(found.closest.capacity());
            });
            found.finish();
            assert!(most < 4 * keep.max(2), "{most} held for {keep} kept");
            assert_eq!(found.len(), oracle.len());
            assert_eq!(found.iter().len(), keep);
            let kept: Vec<Clash> = found.iter().cloned().collect();
            let mut wanted = Clashes::keeping(usize::MAX);
            wanted.closest = oracle[..keep].to_vec();
            wanted.count = keep;
            assert_same(&wanted, &kept, &format!("{keep} kept"));
            let (dropped, distance) = found.dropped();
            let rest: f64 = oracle[keep..].iter().map(|c| c.distance).sum();
            assert_eq!(dropped, oracle.len() - keep);
            assert!((distance - rest).abs() <= 1e-9 * rest, "{distance} {rest}");
        }
        // What `clashes` returns: the same count, `KEPT` kept.
        let found = clashes(&lat, 1000.0, 6.0, 1.0);
        assert_eq!((found.len(), found.iter().len()), (oracle.len(), KEPT));
        assert_eq!(found.first(), oracle.first());
        // The row fit's count keeps nothing and counts the same.
        let n = count_clashes(&lat, 1000.0, 6.0, 1.0, |c| c.rods[1] >= 100);
        assert_eq!(n, oracle.iter().filter(|c| c.rods[1] >= 100).count());
    }

    #[test]
    fn a_runaway_strip_is_measured_without_filling_its_box() {
        // One vertex thrown 50 m away diagonally (as an optimiser's wild try
        // can): its strips' boxes span about 10^9 grid cells. They must be
        // measured against every strip instead, with the same answer.
        let mut lat = sheet(6, 15.0);
        let v = lat.vertices.len() / 2;
        lat.vertices[v].pos += DVec3::new(5.0e4, 3.0e4, 2.0e4);
        let brute = all_pairs(&lat);
        assert!(brute > 0);
        assert_eq!(clashes(&lat, 10.0, 6.0, 1.0).len(), brute);
    }
}
