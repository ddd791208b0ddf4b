//! Nesting strips onto sheets. Strips are long thin stadiums, so parts go in
//! lanes: each lane is a 1-D bin (cutting stock). Each sheet tries every split
//! of k lanes in one orientation plus lanes of the other orientation in the
//! rest of the sheet, fills the lanes best-fit decreasing, and keeps the split
//! that places the most material. Deterministic: ties break by order.

pub(crate) mod advice;
mod bounds;
mod by_step;

pub(crate) use advice::{SheetOption, pick, sheet_options};
pub use bounds::Bounds;
pub(crate) use bounds::{area_bound, lane_bound, stadium_area};
pub(crate) use by_step::nest_by_step;

use crate::fabrication::SheetSpec;
use std::cmp::Ordering;
use std::collections::BTreeSet;

/// One strip on a sheet: the top-left corner of its outline's bounding box,
/// and whether it runs along y (start end at the top) instead of x (start
/// end on the left).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The part's index into `Layout::lengths` (`lengths.len()` for the test piece).
    pub part: usize,
    /// Left edge of the outline's bounding box, mm from the sheet's left edge.
    pub x: f64,
    /// Top edge of the outline's bounding box, mm from the sheet's top edge.
    pub y: f64,
    /// The strip runs along y, start end at the top.
    pub rotated: bool,
}

/// One laser sheet and the strips placed on it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sheet {
    /// The strips on this sheet.
    pub placements: Vec<Placement>,
    /// The test piece (first sheet only), nested in a lane like a part;
    /// its `part` is `Layout::lengths.len()`.
    pub test_piece: Option<Placement>,
}

/// The strips nested on sheets: what the cut-sheet pages draw.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// The sheet size every sheet of the layout has.
    pub sheet: SheetSpec,
    /// Outline width of every part.
    pub part_width: f64,
    /// Outline length of each part, by part index.
    pub lengths: Vec<f64>,
    /// Outline length of the test piece, when there is one.
    pub test_piece: Option<f64>,
    /// The sheets, first to last.
    pub sheets: Vec<Sheet>,
    /// Whether the strips are nested by assembly step (docs/fabrication.md,
    /// Cutting by assembly step).
    pub by_step: bool,
}

impl Layout {
    /// A layout of `sheets` of size `sheet`, for parts of outline width
    /// `width` and outline lengths `lengths`, with the test piece if any.
    pub(crate) fn new(
        sheet: &SheetSpec,
        width: f64,
        lengths: &[f64],
        test_piece: Option<f64>,
        sheets: Vec<Sheet>,
    ) -> Self {
        Layout {
            sheet: sheet.clone(),
            part_width: width,
            lengths: lengths.to_vec(),
            test_piece,
            sheets,
            by_step: false,
        }
    }

    /// Fraction of the sheets' full area covered by parts.
    pub fn utilisation(&self) -> f64 {
        let parts: f64 = self
            .all_lengths()
            .iter()
            .map(|&l| stadium_area(l, self.part_width))
            .sum();
        parts / (self.sheets.len() as f64 * self.sheet.width * self.sheet.height)
    }

    /// Lower bounds on the sheet count for these parts: how far the layout is
    /// from the best possible.
    pub fn bounds(&self) -> Bounds {
        let all = self.all_lengths();
        Bounds {
            area: area_bound(&all, self.part_width, &self.sheet),
            lanes: lane_bound(&all, self.part_width, &self.sheet),
        }
    }

    /// The parts' lengths and the test piece's: everything the sheets hold.
    pub(crate) fn all_lengths(&self) -> Vec<f64> {
        self.lengths
            .iter()
            .copied()
            .chain(self.test_piece)
            .collect()
    }
}

/// What there is to nest, independent of the sheet: the parts' outline
/// lengths and width, the test piece's outline length and, when the job is
/// cut by assembly step, each part's step.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Job {
    pub(crate) lengths: Vec<f64>,
    pub(crate) width: f64,
    pub(crate) test_piece: Option<f64>,
    pub(crate) steps: Option<Vec<usize>>,
    /// Group by step only where that takes no more sheets than nesting
    /// the strips freely (the default); false: by step whatever it costs.
    pub(crate) steps_if_free: bool,
}

impl Job {
    /// Whether every part fits the sheet (along its longer usable side).
    pub(crate) fn holds(&self, sheet: &SheetSpec) -> bool {
        let (uw, uh) = sheet.usable();
        self.width <= uw.min(uh) && self.lengths.iter().all(|&l| l <= uw.max(uh))
    }

    /// The job on `sheet`, which must hold it; the test piece is left out
    /// when it does not fit (as `parts::test_piece` leaves it out).
    pub(crate) fn nest(&self, sheet: &SheetSpec) -> Layout {
        let (uw, uh) = sheet.usable();
        let piece = self
            .test_piece
            .filter(|&l| l <= uw.max(uh) && self.width <= uw.min(uh));
        let Some(steps) = &self.steps else {
            return nest_with(&self.lengths, self.width, sheet, piece);
        };
        let mut grouped = nest_by_step(&self.lengths, self.width, sheet, piece, steps);
        grouped.by_step = true;
        if self.steps_if_free {
            let free = nest_with(&self.lengths, self.width, sheet, piece);
            if free.sheets.len() < grouped.sheets.len() {
                return free;
            }
        }
        grouped
    }
}

/// A lane: a straight run of parts end to end.
#[derive(Clone, Copy, Debug)]
struct Lane {
    x: f64,
    y: f64,
    rotated: bool,
    /// Capacity in "length + gap" units (the usable run plus one gap).
    capacity: f64,
}

impl Lane {
    /// Part `part` placed `along` mm down the lane from its start.
    fn place(&self, part: usize, along: f64) -> Placement {
        let (x, y) = if self.rotated {
            (self.x, self.y + along)
        } else {
            (self.x + along, self.y)
        };
        Placement {
            part,
            x,
            y,
            rotated: self.rotated,
        }
    }
}

/// f64 with a total order, for the best-fit search.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Len(f64);
impl Eq for Len {}
impl PartialOrd for Len {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Len {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// Nest parts of outline width `width` and the given outline lengths.
/// Every length must fit the sheet (checked by `parts`); a part that fits
/// nowhere panics, which would be a bug.
pub fn nest(lengths: &[f64], width: f64, sheet: &SheetSpec) -> Layout {
    nest_with(lengths, width, sheet, None)
}

/// `nest`, with a test piece of outline length `test_piece` that must go on
/// the first sheet: it is placed first, and a split of the first sheet's
/// lanes counts only if it takes the piece. The caller checks it fits.
pub(crate) fn nest_with(
    lengths: &[f64],
    width: f64,
    sheet: &SheetSpec,
    test_piece: Option<f64>,
) -> Layout {
    nest_by(lengths, width, sheet, test_piece, fill_sheet)
}

/// One sheet's filling: from the parts in `order` (lengths by part), of
/// outline width `width`, with `must` (if any) first and placed, the sheet
/// and the parts left over.
type Fill = fn(&[usize], &[f64], f64, &SheetSpec, Option<usize>) -> (Sheet, Vec<usize>);

/// `nest_with`, filling each sheet with `fill` (the property test passes the
/// old nester's filling, to check the new one nests as it did).
fn nest_by(
    lengths: &[f64],
    width: f64,
    sheet: &SheetSpec,
    test_piece: Option<f64>,
    fill: Fill,
) -> Layout {
    let n = lengths.len();
    let all: Vec<f64> = lengths.iter().copied().chain(test_piece).collect();
    let mut order: Vec<usize> = (0..n).collect();
    // Longest first; equal lengths keep part order.
    order.sort_by(|&a, &b| all[b].total_cmp(&all[a]).then(a.cmp(&b)));
    let mut must = None;
    if test_piece.is_some() {
        order.insert(0, n);
        must = Some(n);
    }
    let mut sheets = Vec::new();
    while !order.is_empty() {
        let (mut placed, rest) = fill(&order, &all, width, sheet, must.take());
        assert!(
            !placed.placements.is_empty(),
            "a part longer than the sheet reached nesting"
        );
        if let Some(i) = placed.placements.iter().position(|p| p.part == n) {
            placed.test_piece = Some(placed.placements.remove(i));
        }
        sheets.push(placed);
        order = rest;
    }
    Layout::new(sheet, width, lengths, test_piece, sheets)
}

/// Every split of the usable area worth trying, in the order the nester
/// tries them: the most lanes along x first, then the most along y.
fn splits(width: f64, sheet: &SheetSpec) -> impl Iterator<Item = Vec<Lane>> + '_ {
    let (uw, uh) = sheet.usable();
    let pitch = width + sheet.gap;
    [false, true]
        .into_iter()
        .flat_map(move |major_rotated| {
            let span = if major_rotated { uw } else { uh };
            let max_k = ((span + sheet.gap) / pitch).floor() as usize;
            (0..=max_k)
                .rev()
                .map(move |k| lanes(k, major_rotated, width, sheet))
        })
        .filter(|lanes| !lanes.is_empty())
}

/// The lanes of one split of the usable area: `k` lanes along `major`
/// (x when not rotated) and lanes of the other orientation in the rest.
fn lanes(k: usize, major_rotated: bool, width: f64, sheet: &SheetSpec) -> Vec<Lane> {
    let (uw, uh) = sheet.usable();
    let (g, m) = (sheet.gap, sheet.margin);
    let pitch = width + g;
    let mut out = Vec::new();
    // Along x: lanes stacked in y. Along y: lanes side by side in x.
    let (major_run, minor_span) = if major_rotated { (uh, uw) } else { (uw, uh) };
    for r in 0..k {
        let offset = m + r as f64 * pitch;
        out.push(if major_rotated {
            Lane {
                x: offset,
                y: m,
                rotated: true,
                capacity: major_run + g,
            }
        } else {
            Lane {
                x: m,
                y: offset,
                rotated: false,
                capacity: major_run + g,
            }
        });
    }
    let rest = minor_span - k as f64 * pitch;
    if rest >= width {
        let count = ((major_run + g) / pitch).floor() as usize;
        for c in 0..count {
            let offset = m + c as f64 * pitch;
            let start = m + k as f64 * pitch;
            out.push(if major_rotated {
                Lane {
                    x: start,
                    y: offset,
                    rotated: false,
                    capacity: rest + g,
                }
            } else {
                Lane {
                    x: offset,
                    y: start,
                    rotated: true,
                    capacity: rest + g,
                }
            });
        }
    }
    out
}

/// The most lane length (each part takes its length plus a gap) one sheet
/// offers, over every split of its lanes `nest_with` tries; cutting by step
/// uses one of those splits. The job's total over it bounds the sheets below.
pub(crate) fn lane_capacity(width: f64, sheet: &SheetSpec) -> f64 {
    let (uw, uh) = sheet.usable();
    let pitch = width + sheet.gap;
    [false, true]
        .into_iter()
        .flat_map(|major_rotated| {
            let span = if major_rotated { uw } else { uh };
            let max_k = ((span + sheet.gap) / pitch).floor().max(0.0) as usize;
            (0..=max_k).map(move |k| {
                lanes(k, major_rotated, width, sheet)
                    .iter()
                    .map(|l| l.capacity)
                    .sum::<f64>()
            })
        })
        .fold(0.0, f64::max)
}

/// Best-fit decreasing of `order` into `lanes`: for each part, the lane with
/// the least room that still takes it. Returns the placed parts as (index in
/// `order`, lane), in order; the others do not fit.
///
/// Parts after the first are longest first (`nest_with`), and no lane's
/// room ever grows, so once a part is longer than the roomiest lane every
/// part up to the first one that fits is skipped by a binary search: a
/// sheet costs what it places, not the whole job (the job is nested once
/// per sheet per split of its lanes).
fn best_fit(order: &[usize], lengths: &[f64], lanes: &[Lane], gap: f64) -> Vec<(usize, usize)> {
    // Lanes by (room, index), ascending: a sorted vector, where a placement
    // moves one lane a few places down (a short rotate), not a tree.
    let mut room: Vec<(Len, usize)> = lanes
        .iter()
        .enumerate()
        .map(|(i, l)| (Len(l.capacity), i))
        .collect();
    room.sort_unstable();
    let need = |i: usize| lengths[order[i]] + gap;
    let mut placed = Vec::new();
    let mut i = 0;
    while i < order.len() {
        let Some(&(Len(most), _)) = room.last() else {
            break;
        };
        if need(i).total_cmp(&most).is_gt() {
            // Does not fit. From the second part on the needs do not grow:
            // skip to the first that fits the roomiest lane.
            i = if i == 0 {
                1
            } else {
                i + order[i..].partition_point(|&p| (lengths[p] + gap).total_cmp(&most).is_gt())
            };
            continue;
        }
        // The lane with the least room that takes the part.
        let run = need(i);
        let at = room.partition_point(|&r| r < (Len(run), 0));
        let (Len(mut left), lane) = room[at];
        // Parts of the same length after it go to the same lane while it
        // takes them: its room only shrinks and every other lane that takes
        // them has more. One search a lane filled, not one a part (a big
        // sheet's strips are mostly of a few lengths).
        loop {
            left -= run;
            placed.push((i, lane));
            i += 1;
            if i == order.len() || need(i).total_cmp(&run).is_ne() || left.total_cmp(&run).is_lt() {
                break;
            }
        }
        let moved = (Len(left), lane);
        let to = room[..at].partition_point(|&r| r < moved);
        room[to..=at].rotate_right(1);
        room[to] = moved;
    }
    placed
}

/// Fill one sheet; returns it and the parts left over (still in order).
fn fill_sheet(
    order: &[usize],
    lengths: &[f64],
    width: f64,
    sheet: &SheetSpec,
    must: Option<usize>,
) -> (Sheet, Vec<usize>) {
    // The best split so far: material placed, its lanes, (index in order, lane).
    type Split = (f64, Vec<Lane>, Vec<(usize, usize)>);
    let mut best: Option<Split> = None;
    for lanes in splits(width, sheet) {
        let fit = best_fit(order, lengths, &lanes, sheet.gap);
        // `must` is always first in `order`.
        let takes_must = must.is_none_or(|m| fit.first().is_some_and(|&(i, _)| order[i] == m));
        if !takes_must {
            continue;
        }
        let placed: f64 = fit.iter().map(|&(i, _)| lengths[order[i]]).sum();
        if best.as_ref().is_none_or(|b| placed > b.0) {
            let all = fit.len() == order.len();
            best = Some((placed, lanes, fit));
            if all {
                break;
            }
        }
    }
    let (_, lanes, fit) = best.expect("a sheet has at least one lane");
    let mut cursor: Vec<f64> = vec![0.0; lanes.len()];
    let mut placements = Vec::with_capacity(fit.len());
    let mut taken = vec![false; order.len()];
    for &(i, l) in &fit {
        let p = order[i];
        taken[i] = true;
        placements.push(lanes[l].place(p, cursor[l]));
        cursor[l] += lengths[p] + sheet.gap;
    }
    let rest = order
        .iter()
        .zip(&taken)
        .filter(|(_, t)| !**t)
        .map(|(&p, _)| p)
        .collect();
    placements.sort_by_key(|p| p.part);
    (
        Sheet {
            placements,
            test_piece: None,
        },
        rest,
    )
}

/// Strip packing (fixed sheet height, minimise the used length), for
/// comparing against strip-packing tools on the same parts: the better of
/// lanes along the length (longest part first onto the least loaded lane)
/// and columns across it (best-fit decreasing into columns of the height).
pub fn strip_length(lengths: &[f64], width: f64, gap: f64, height: f64) -> f64 {
    let pitch = width + gap;
    let mut sorted = lengths.to_vec();
    sorted.sort_by(|a, b| b.total_cmp(a));
    let lanes = ((height + gap) / pitch).floor() as usize;
    let mut load: BTreeSet<(Len, usize)> = (0..lanes).map(|i| (Len(0.0), i)).collect();
    for &l in &sorted {
        let (Len(x), i) = load.pop_first().expect("at least one lane");
        load.insert((Len(x + l + gap), i));
    }
    let along = load.last().map_or(0.0, |(Len(x), _)| x - gap);
    let mut columns: BTreeSet<(Len, usize)> = BTreeSet::new();
    let mut count = 0;
    for &l in &sorted {
        let need = l + gap;
        match columns.range((Len(need), 0)..).next().copied() {
            Some((Len(room), c)) => {
                columns.remove(&(Len(room), c));
                columns.insert((Len(room - need), c));
            }
            None => {
                columns.insert((Len(height + gap - need), count));
                count += 1;
            }
        }
    }
    let across = count as f64 * pitch - gap;
    along.min(across)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 110 x 50 sheet, margin 5 and gap 2: usable 100 x 40.
    pub(super) fn small_sheet() -> SheetSpec {
        SheetSpec {
            name: "t".into(),
            width: 110.0,
            height: 50.0,
            margin: 5.0,
            gap: 2.0,
        }
    }

    // The nester before the binary-search skip (commit bd90a7a): every split
    // of every sheet ran best fit over the whole rest of the job. The new one
    // must nest exactly as it did.
    mod reference {
        use super::super::*;
        /// Best-fit decreasing of `order` into `lanes`: for each part, the lane with
        /// the least room that still takes it. Returns each part's lane (or None).
        pub(crate) fn best_fit(
            order: &[usize],
            lengths: &[f64],
            lanes: &[Lane],
            gap: f64,
        ) -> Vec<Option<usize>> {
            let mut room: BTreeSet<(Len, usize)> = lanes
                .iter()
                .enumerate()
                .map(|(i, l)| (Len(l.capacity), i))
                .collect();
            order
                .iter()
                .map(|&p| {
                    let need = lengths[p] + gap;
                    let &(Len(left), lane) = room.range((Len(need), 0)..).next()?;
                    room.remove(&(Len(left), lane));
                    room.insert((Len(left - need), lane));
                    Some(lane)
                })
                .collect()
        }

        /// Fill one sheet; returns it and the parts left over (still in order).
        pub(crate) fn fill_sheet(
            order: &[usize],
            lengths: &[f64],
            width: f64,
            sheet: &SheetSpec,
            must: Option<usize>,
        ) -> (Sheet, Vec<usize>) {
            let mut best: Option<(f64, Vec<Lane>, Vec<Option<usize>>)> = None;
            for lanes in splits(width, sheet) {
                let fit = best_fit(order, lengths, &lanes, sheet.gap);
                let takes_must = must
                    .is_none_or(|m| order.iter().zip(&fit).any(|(&p, f)| p == m && f.is_some()));
                if !takes_must {
                    continue;
                }
                let placed: f64 = order
                    .iter()
                    .zip(&fit)
                    .filter(|(_, f)| f.is_some())
                    .map(|(&p, _)| lengths[p])
                    .sum();
                if best.as_ref().is_none_or(|b| placed > b.0) {
                    let all = fit.iter().all(Option::is_some);
                    best = Some((placed, lanes, fit));
                    if all {
                        break;
                    }
                }
            }
            let (_, lanes, fit) = best.expect("a sheet has at least one lane");
            let mut cursor: Vec<f64> = vec![0.0; lanes.len()];
            let mut placements = Vec::new();
            let mut rest = Vec::new();
            for (&p, lane) in order.iter().zip(&fit) {
                match lane {
                    Some(l) => {
                        placements.push(lanes[*l].place(p, cursor[*l]));
                        cursor[*l] += lengths[p] + sheet.gap;
                    }
                    None => rest.push(p),
                }
            }
            placements.sort_by_key(|p| p.part);
            (
                Sheet {
                    placements,
                    test_piece: None,
                },
                rest,
            )
        }
    }

    #[test]
    fn the_nester_places_every_part_exactly_as_the_full_best_fit_did() {
        let mut rng = crate::rng::Rng::new(14);
        for case in 0..60 {
            let sheet = SheetSpec {
                name: "t".into(),
                width: 150.0 + 500.0 * rng.uniform(),
                height: 100.0 + 350.0 * rng.uniform(),
                margin: 5.0 * rng.uniform(),
                gap: 0.5 + 2.0 * rng.uniform(),
            };
            let (uw, uh) = sheet.usable();
            let width = 4.0 + 10.0 * rng.uniform();
            let longest = uw.max(uh);
            let n = 1 + (300.0 * rng.uniform()) as usize;
            // Mixes of short and long parts, with repeated lengths.
            let kinds: Vec<f64> = (0..1 + (6.0 * rng.uniform()) as usize)
                .map(|_| width + (longest - width) * rng.uniform().powi(2))
                .collect();
            let lengths: Vec<f64> = (0..n)
                .map(|_| kinds[(rng.uniform() * kinds.len() as f64) as usize])
                .collect();
            let piece = (case % 3 == 0).then(|| width + (longest - width) * rng.uniform());
            let new = nest_with(&lengths, width, &sheet, piece);
            // The old nester: the same sheet-by-sheet driver, the old filling.
            let old = nest_by(&lengths, width, &sheet, piece, reference::fill_sheet);
            assert_eq!(new, old, "case {case}");
        }
    }
}
