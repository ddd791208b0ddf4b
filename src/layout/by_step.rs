//! Nesting by assembly step, for a maker who cuts and assembles row by row:
//! every lane runs along the sheet's longer side, and the steps follow each
//! other in assembly order, lane after lane, sheet after sheet, each step's
//! strips in ID order (next-fit, so a lane reads like the row). A step
//! starts a lane of its own unless it fits whole in what is left of the
//! current lane (small steps, such as the one-cell steps of a helix, share
//! lanes but are never split by a lane break they could have avoided). A
//! step that does not fit what is left of a sheet starts a new sheet when a
//! whole sheet holds it, so no step is split across sheets unless it is
//! larger than a sheet. The test piece comes first, on sheet 1.

use super::{Layout, Placement, Sheet};
use crate::fabrication::SheetSpec;

/// Lanes of a sheet, all along its longer usable side: (x, y, rotated).
fn lanes(width: f64, sheet: &SheetSpec) -> (Vec<(f64, f64, bool)>, f64) {
    let (uw, uh) = sheet.usable();
    let (g, m) = (sheet.gap, sheet.margin);
    let rotated = uh > uw;
    let (run, span) = if rotated { (uh, uw) } else { (uw, uh) };
    let count = ((span + g) / (width + g)).floor().max(1.0) as usize;
    let lanes = (0..count)
        .map(|r| {
            let offset = m + r as f64 * (width + g);
            if rotated {
                (offset, m, true)
            } else {
                (m, offset, false)
            }
        })
        .collect();
    (lanes, run)
}

/// Next-fit of `parts` (in order) into lanes from `lane` on, `used` of it
/// taken already: each part's lane and its offset along it, or None once
/// the sheet's lanes run out.
fn next_fit(
    parts: &[usize],
    lengths: &[f64],
    (lane, used): (usize, f64),
    count: usize,
    run: f64,
    gap: f64,
) -> Vec<Option<(usize, f64)>> {
    let (mut lane, mut used) = (lane, used);
    parts
        .iter()
        .map(|&p| {
            if used > 0.0 && used + lengths[p] > run + 1e-9 {
                lane += 1;
                used = 0.0;
            }
            if lane >= count {
                return None;
            }
            let at = used;
            used += lengths[p] + gap;
            Some((lane, at))
        })
        .collect()
}

/// Nest with each step's parts together (see the module comment). `step_of`
/// gives each part's assembly step; parts keep their index order within a
/// step. The test piece (outline length) goes first if given.
pub(crate) fn nest_by_step(
    lengths: &[f64],
    width: f64,
    sheet: &SheetSpec,
    test_piece: Option<f64>,
    step_of: &[usize],
) -> Layout {
    let n = lengths.len();
    let all: Vec<f64> = lengths.iter().copied().chain(test_piece).collect();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&p| (step_of[p], p));
    // Runs of one step each; the test piece is a run of its own.
    let mut runs: Vec<Vec<usize>> = Vec::new();
    if test_piece.is_some() {
        runs.push(vec![n]);
    }
    for &p in &order {
        match runs.last_mut() {
            Some(r) if r[0] < n && step_of[r[0]] == step_of[p] => r.push(p),
            _ => runs.push(vec![p]),
        }
    }
    let (lanes, run) = lanes(width, sheet);
    let count = lanes.len();
    let mut sheets = vec![Sheet::default()];
    // Where the next part goes: a lane and how much of it is taken.
    let mut at = (0, 0.0);
    let fresh = (0, 0.0);
    for parts in runs {
        let mut rest: &[usize] = &parts;
        let fits = |from: (usize, f64)| -> Vec<Option<(usize, f64)>> {
            next_fit(&parts, &all, from, count, run, sheet.gap)
        };
        // The tail of the current lane, if the whole step fits there; else a new lane.
        if at.1 > 0.0 && !fits(at).iter().all(|f| f.is_some_and(|(l, _)| l == at.0)) {
            at = (at.0 + 1, 0.0);
        }
        // A step that overflows this sheet starts a fresh one if a whole sheet holds it.
        if at != fresh
            && fits(at).iter().any(Option::is_none)
            && fits(fresh).iter().all(Option::is_some)
        {
            sheets.push(Sheet::default());
            at = fresh;
        }
        while !rest.is_empty() {
            let fit = next_fit(rest, &all, at, count, run, sheet.gap);
            let placed = fit.iter().take_while(|f| f.is_some()).count();
            let current = sheets.last_mut().expect("a sheet");
            for (&p, f) in rest.iter().zip(&fit).take(placed) {
                let (l, along) = f.expect("placed");
                let (x, y, rotated) = lanes[l];
                let placement = Placement {
                    part: p,
                    x: if rotated { x } else { x + along },
                    y: if rotated { y + along } else { y },
                    rotated,
                };
                if p == n {
                    current.test_piece = Some(placement);
                } else {
                    current.placements.push(placement);
                }
                at = (l, along + all[p] + sheet.gap);
            }
            assert!(
                placed > 0 || !current.placements.is_empty() || current.test_piece.is_some(),
                "a part longer than the sheet reached nesting"
            );
            rest = &rest[placed..];
            if !rest.is_empty() {
                sheets.push(Sheet::default());
                at = fresh;
            }
        }
    }
    for s in &mut sheets {
        s.placements.sort_by_key(|p| p.part);
    }
    sheets.retain(|s| !s.placements.is_empty() || s.test_piece.is_some());
    Layout::new(sheet, width, lengths, test_piece, sheets)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Usable 100 x 40: lanes of 100 along x, pitch 12, 3 lanes.
    use crate::layout::tests::small_sheet as sheet;

    #[test]
    fn steps_keep_to_their_lanes_and_to_one_sheet_when_they_can() {
        // Step 0: three parts of 45 (two lanes); step 1: two of 30 (one
        // lane); step 2: four of 45 (two lanes: does not fit the one lane
        // left, so it starts sheet 2).
        let lengths = [45.0, 45.0, 45.0, 30.0, 30.0, 45.0, 45.0, 45.0, 45.0];
        let step_of = [0, 0, 0, 1, 1, 2, 2, 2, 2];
        let layout = nest_by_step(&lengths, 10.0, &sheet(), None, &step_of);
        assert_eq!(layout.sheets.len(), 2);
        let lane = |p: &Placement| ((p.y - 5.0) / 12.0).round() as usize;
        let on = |s: usize| -> Vec<(usize, usize, f64)> {
            layout.sheets[s]
                .placements
                .iter()
                .map(|p| (p.part, lane(p), p.x))
                .collect()
        };
        assert_eq!(
            on(0),
            vec![
                (0, 0, 5.0),
                (1, 0, 52.0),
                (2, 1, 5.0),
                (3, 2, 5.0),
                (4, 2, 37.0)
            ]
        );
        assert_eq!(
            on(1),
            vec![(5, 0, 5.0), (6, 0, 52.0), (7, 1, 5.0), (8, 1, 52.0)]
        );
    }

    #[test]
    fn small_steps_share_a_lane_when_they_fit_whole() {
        // One-cell steps of two 20 mm strips: two steps (88 mm) fill a lane
        // of 100; the third step starts the next lane.
        let lengths = [20.0; 6];
        let layout = nest_by_step(&lengths, 10.0, &sheet(), None, &[0, 0, 1, 1, 2, 2]);
        let lanes: Vec<f64> = layout.sheets[0].placements.iter().map(|p| p.y).collect();
        assert_eq!(lanes, vec![5.0, 5.0, 5.0, 5.0, 17.0, 17.0]);
    }

    #[test]
    fn a_step_larger_than_a_sheet_runs_on() {
        let lengths = [90.0; 5];
        let layout = nest_by_step(&lengths, 10.0, &sheet(), Some(60.0), &[0; 5]);
        // Sheet 1: the test piece, then two parts in lanes of their own
        // (a part of 90 does not fit beside the piece); sheet 2: three.
        assert_eq!(layout.sheets.len(), 2);
        assert!(layout.sheets[0].test_piece.is_some());
        assert_eq!(layout.sheets[0].placements.len(), 2);
        assert_eq!(layout.sheets[1].placements.len(), 3);
    }
}
