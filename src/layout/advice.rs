//! Sheet advice: the smallest sheet preset that holds the job (fewest
//! sheets, then the smallest sheet area, then the preset list's order),
//! which `--sheet auto` picks and `check` and `build` report.
//!
//! Finding it nests the job on as few presets as it can: every preset gets
//! a lower bound on its sheet count (by area, and by the lane length a
//! sheet offers), the presets are tried in the order of (bound, area), and
//! the search stops at the first whose bound cannot beat the best nesting
//! found. The pick is the one nesting every preset would give.

use super::{Job, Layout, area_bound, lane_capacity};
use crate::fabrication::{SHEET_PRESETS, SheetSpec};
use std::cmp::Ordering;

/// The job on one preset.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SheetOption {
    pub(crate) name: String,
    pub(crate) width: f64,
    pub(crate) height: f64,
    /// Sheets needed, or None when some strip is longer than the preset.
    pub(crate) sheets: Option<usize>,
    /// Fraction of the sheets' area covered by parts (0 when it does not hold the job).
    pub(crate) utilisation: f64,
}

impl SheetOption {
    /// The preset as a sheet, with the margin and gap of `base`.
    pub(crate) fn spec(&self, base: &SheetSpec) -> SheetSpec {
        SheetSpec {
            name: self.name.clone(),
            width: self.width,
            height: self.height,
            ..base.clone()
        }
    }

    fn of(spec: &SheetSpec, layout: Option<&Layout>) -> Self {
        SheetOption {
            name: spec.name.clone(),
            width: spec.width,
            height: spec.height,
            sheets: layout.map(|l| l.sheets.len()),
            utilisation: layout.map_or(0.0, Layout::utilisation),
        }
    }
}

/// Every preset as a sheet with the margin and gap of `base`, in the
/// presets' order.
fn presets(base: &SheetSpec) -> impl Iterator<Item = SheetSpec> + '_ {
    SHEET_PRESETS
        .iter()
        .map(|&(name, width, height)| SheetSpec {
            name: name.into(),
            width,
            height,
            ..base.clone()
        })
}

/// The job on `spec`: `known` when it was nested on a sheet of the same
/// size, margin and gap already (the build's own sheet), else nested now.
fn nested(job: &Job, spec: &SheetSpec, known: Option<&Layout>) -> Layout {
    let same = |l: &&Layout| {
        let s = &l.sheet;
        (s.width, s.height, s.margin, s.gap) == (spec.width, spec.height, spec.margin, spec.gap)
    };
    match known.filter(same) {
        Some(l) => Layout {
            sheet: spec.clone(),
            ..l.clone()
        },
        None => job.nest(spec),
    }
}

/// The job nested on each preset, in the presets' order, keeping the
/// margin and gap of `base` (what `--json` lists). `known` is a layout of
/// the job already made, reused for the preset of its size.
pub(crate) fn sheet_options(
    job: &Job,
    base: &SheetSpec,
    known: Option<&Layout>,
) -> Vec<SheetOption> {
    presets(base)
        .map(|spec| {
            let layout = job.holds(&spec).then(|| nested(job, &spec, known));
            SheetOption::of(&spec, layout.as_ref())
        })
        .collect()
}

/// Fewer sheets first, then the smaller sheet area, then the presets' order.
fn rank((sheets, area, index): (usize, f64, usize), other: (usize, f64, usize)) -> Ordering {
    sheets
        .cmp(&other.0)
        .then(area.total_cmp(&other.1))
        .then(index.cmp(&other.2))
}

/// No layout of the job on `spec` has fewer sheets than this.
pub(crate) fn sheets_at_least(job: &Job, spec: &SheetSpec) -> usize {
    let (uw, uh) = spec.usable();
    let mut all = job.lengths.clone();
    all.extend(
        job.test_piece
            .filter(|&l| l <= uw.max(uh) && job.width <= uw.min(uh)),
    );
    let lanes: f64 = all.iter().map(|&l| l + spec.gap).sum();
    let by_lanes = (lanes / lane_capacity(job.width, spec) - 1e-9)
        .ceil()
        .max(0.0) as usize;
    area_bound(&all, job.width, spec).max(by_lanes)
}

/// The smallest preset that holds the job and the job nested on it (None
/// when no preset holds it). `known` is a layout of the job already made,
/// reused for the preset of its size.
pub(crate) fn pick(
    job: &Job,
    base: &SheetSpec,
    known: Option<&Layout>,
) -> Option<(SheetOption, Layout)> {
    let mut candidates: Vec<((usize, f64, usize), SheetSpec)> = presets(base)
        .enumerate()
        .filter(|(_, spec)| job.holds(spec))
        .map(|(i, spec)| {
            (
                (sheets_at_least(job, &spec), spec.width * spec.height, i),
                spec,
            )
        })
        .collect();
    candidates.sort_by(|a, b| rank(a.0, b.0));
    let mut best: Option<((usize, f64, usize), SheetSpec, Layout)> = None;
    for (bound, spec) in candidates {
        // Every candidate from here on needs at least as many sheets as its bound.
        if best.as_ref().is_some_and(|b| rank(bound, b.0).is_ge()) {
            break;
        }
        let layout = nested(job, &spec, known);
        let key = (layout.sheets.len(), bound.1, bound.2);
        if best.as_ref().is_none_or(|b| rank(key, b.0).is_lt()) {
            best = Some((key, spec, layout));
        }
    }
    best.map(|(_, spec, layout)| (SheetOption::of(&spec, Some(&layout)), layout))
}

/// The smallest preset that holds the job among `options`: fewest sheets,
/// then the smallest sheet area; ties keep the presets' order. The unit
/// tests' reference for the advice's pick.
#[cfg(test)]
fn smallest(options: &[SheetOption]) -> Option<&SheetOption> {
    options
        .iter()
        .filter(|o| o.sheets.is_some())
        .min_by(|a, b| {
            a.sheets
                .cmp(&b.sheets)
                .then((a.width * a.height).total_cmp(&(b.width * b.height)))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base() -> SheetSpec {
        SheetSpec {
            name: "x".into(),
            width: 600.0,
            height: 400.0,
            margin: 5.0,
            gap: 2.0,
        }
    }

    #[test]
    fn fewest_sheets_first_then_the_smallest_area() {
        let base = base();
        // Ten strips of 280 mm: one A3 lane (410 mm) takes one, so A3 needs
        // one sheet (23 lanes); A4 (287 mm lanes) takes them too.
        let job = Job {
            lengths: vec![280.0; 10],
            width: 10.0,
            test_piece: None,
            steps: None,
            steps_if_free: false,
        };
        let options = sheet_options(&job, &base, None);
        assert_eq!(options.len(), SHEET_PRESETS.len());
        assert!(options.iter().all(|o| o.sheets == Some(1)));
        assert_eq!(smallest(&options).unwrap().name, "a4");
        assert_eq!(pick(&job, &base, None).unwrap().0.name, "a4");
        // 290 mm strips do not fit A4's 287 mm: A3 is the smallest.
        let job = Job {
            lengths: vec![290.0; 10],
            ..job
        };
        let options = sheet_options(&job, &base, None);
        assert_eq!(
            options.iter().find(|o| o.name == "a4").unwrap().sheets,
            None
        );
        assert_eq!(smallest(&options).unwrap().name, "a3");
        assert_eq!(pick(&job, &base, None).unwrap().0.name, "a3");
        // Longer than every preset: no advice.
        let job = Job {
            lengths: vec![700.0],
            ..job
        };
        assert_eq!(pick(&job, &base, None), None);
    }

    #[test]
    fn the_pick_is_the_smallest_of_every_preset_nested_and_the_bounds_hold() {
        let mut rng = crate::rng::Rng::new(8);
        let mut searched = 0;
        for case in 0..60 {
            let base = SheetSpec {
                margin: 10.0 * rng.uniform(),
                gap: 0.5 + 3.0 * rng.uniform(),
                ..base()
            };
            let width = 5.0 + 15.0 * rng.uniform();
            let n = 1 + (300.0 * rng.uniform()) as usize;
            let longest = 20.0 + 600.0 * rng.uniform();
            let lengths: Vec<f64> = (0..n)
                .map(|_| width + (longest - width) * rng.uniform().powi(3))
                .collect();
            let steps = (case % 4 == 1).then(|| (0..n).map(|i| i / 7).collect());
            let job = Job {
                lengths,
                width,
                test_piece: (case % 2 == 0).then_some(90.0),
                steps,
                steps_if_free: case % 8 == 5,
            };
            let options = sheet_options(&job, &base, None);
            for (o, spec) in options.iter().zip(presets(&base)) {
                if let Some(n) = o.sheets {
                    assert!(sheets_at_least(&job, &spec) <= n, "case {case}: {o:?}");
                }
            }
            let picked = pick(&job, &base, None);
            assert_eq!(
                picked.as_ref().map(|p| &p.0),
                smallest(&options),
                "case {case}"
            );
            if let Some((o, layout)) = picked {
                assert_eq!(layout, job.nest(&o.spec(&base)), "case {case}");
                searched += 1;
            }
            // A layout the build made already is the one the pick reports.
            let a3 = presets(&base).find(|s| s.name == "a3").unwrap();
            if job.holds(&a3) {
                let known = job.nest(&a3);
                let with = pick(&job, &base, Some(&known)).map(|p| p.0);
                assert_eq!(with.as_ref(), smallest(&options), "case {case}");
            }
        }
        assert!(searched > 40, "{searched}");
    }
}
