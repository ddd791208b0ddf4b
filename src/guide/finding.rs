//! Finding a strip: which sheet and lane of the nesting it was cut on, and
//! what is engraved on it, so every step can say "from sheet 2, lanes 3-4:
//! R03-C00-A R03-C00-B ..." and the sheet maps show where that is.
//!
//! A lane is a line of strips along one side of a sheet (docs/fabrication.md,
//! Nesting): the lanes along the sheet's width are numbered from the top,
//! then those down it from the left, the way the sheet map numbers them.

use crate::parts::{Marking, PartType, Strip};
use crate::pipeline::Build;
use crate::words::plural;
use std::collections::BTreeMap;

/// Where a strip was cut: its sheet and lane, both from 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Spot {
    pub(crate) sheet: usize,
    pub(crate) lane: usize,
}

/// Each strip's spot, by strip index, and each sheet's lanes: (rotated,
/// the lane's top or left edge in mm), in lane order.
pub(crate) struct Spots {
    pub(crate) of: Vec<Spot>,
    pub(crate) lanes: Vec<Vec<(bool, f64)>>,
}

impl Spots {
    pub(crate) fn new(b: &Build) -> Self {
        let mut of = vec![Spot { sheet: 0, lane: 0 }; b.parts.strips.len()];
        let mut lanes = Vec::new();
        for (k, sheet) in b.layout.sheets.iter().enumerate() {
            // Lanes along the width first (by their top edge), then those
            // down the sheet (by their left edge); to 0.01 mm.
            let key = |p: &crate::layout::Placement| {
                let at = if p.rotated { p.x } else { p.y };
                (p.rotated, (at * 100.0).round() as i64)
            };
            let keys: std::collections::BTreeSet<(bool, i64)> =
                sheet.placements.iter().map(key).collect();
            let order: Vec<(bool, i64)> = keys.into_iter().collect();
            for p in &sheet.placements {
                let lane = order.binary_search(&key(p)).expect("its lane") + 1;
                of[p.part] = Spot { sheet: k + 1, lane };
            }
            lanes.push(
                order
                    .iter()
                    .map(|&(r, at)| (r, at as f64 / 100.0))
                    .collect(),
            );
        }
        Spots { of, lanes }
    }

    /// "sheet 2, lanes 3-4" for a set of strips on one sheet.
    fn sheet_and_lanes(&self, sheet: usize, strips: &[usize]) -> String {
        let mut lanes: Vec<usize> = strips.iter().map(|&s| self.of[s].lane).collect();
        lanes.sort_unstable();
        lanes.dedup();
        let (lo, hi) = (lanes[0], lanes[lanes.len() - 1]);
        let which = if lo == hi {
            format!("lane {lo}")
        } else if hi - lo + 1 == lanes.len() {
            format!("lanes {lo}-{hi}")
        } else {
            let l: Vec<String> = lanes.iter().map(|l| l.to_string()).collect();
            format!("lanes {}", l.join(", "))
        };
        format!("sheet {sheet}, {which}")
    }

    /// A step's strips by sheet, in sheet order.
    pub(crate) fn by_sheet(&self, strips: &[usize]) -> BTreeMap<usize, Vec<usize>> {
        let mut by: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
        for &s in strips {
            by.entry(self.of[s].sheet).or_default().push(s);
        }
        by
    }

    /// The sheets a step's strips are on: "sheet 2" or "sheets 1-2".
    pub(crate) fn sheets_of(&self, strips: &[usize]) -> Vec<usize> {
        self.by_sheet(strips).into_keys().collect()
    }
}

/// What is engraved on a strip, as a maker reads it: its ID, its type
/// code, its dot code ("3 dots") or only the arrow.
pub(crate) fn engraved_text(s: &Strip, types: &[PartType]) -> String {
    match s.marking {
        Marking::Id => s.id.clone(),
        Marking::Compact => format!("{}.{}{}", s.row, s.col, s.kind.letter()),
        Marking::Type => types[s.part_type].code.clone(),
        Marking::Dots(n) => plural(n, "dot"),
        Marking::Arrow => "the arrow only".into(),
    }
}

/// A new strip's label in a step picture: what is engraved on it, with its
/// type after an engraved ID ("R01-C02-A (E)"), as the step's words name it.
pub(crate) fn picture_label(s: &Strip, types: &[PartType]) -> String {
    match s.marking {
        Marking::Id | Marking::Compact => {
            format!("{} ({})", engraved_text(s, types), types[s.part_type].code)
        }
        _ => engraved_text(s, types),
    }
}

/// A step's "Take" line: its strips by sheet and lane, each named by what
/// is engraved on it with its type: strips engraved with their ID one by
/// one ("R03-C00-A (type C)"), the others counted ("4 x type D, engraved D").
pub(crate) fn take_line(b: &Build, spots: &Spots, strips: &[usize]) -> String {
    let types = &b.parts.types;
    let parts: Vec<String> = spots
        .by_sheet(strips)
        .into_iter()
        .map(|(sheet, on)| {
            // Strips told apart by their engraving, then types counted.
            let mut named = Vec::new();
            let mut counted: BTreeMap<(usize, String), usize> = BTreeMap::new();
            for &s in &on {
                let strip = &b.parts.strips[s];
                match strip.marking {
                    Marking::Id | Marking::Compact => named.push(format!(
                        "{} ({})",
                        engraved_text(strip, types),
                        types[strip.part_type].code
                    )),
                    _ => {
                        *counted
                            .entry((strip.part_type, engraved_text(strip, types)))
                            .or_default() += 1;
                    }
                }
            }
            let mut what = named;
            for ((t, engraved), n) in counted {
                what.push(format!("{n} x type {}, engraved {engraved}", types[t].code));
            }
            format!(
                "from {}: {}",
                spots.sheet_and_lanes(sheet, &on),
                what.join(", ")
            )
        })
        .collect();
    format!("Take {}.", parts.join("; "))
}

/// "Steps 6-11: sheet 2" lines: which sheets each run of steps is cut on.
pub(crate) fn steps_by_sheet(b: &Build, spots: &Spots) -> Vec<String> {
    let mut lines = Vec::new();
    let mut run: Option<(usize, usize, Vec<usize>)> = None;
    for step in &b.steps {
        let sheets = spots.sheets_of(&step.strips);
        match &mut run {
            Some((_, last, s)) if *s == sheets => *last = step.number,
            _ => {
                if let Some(r) = run.take() {
                    lines.push(run_line(&r));
                }
                run = Some((step.number, step.number, sheets));
            }
        }
    }
    if let Some(r) = run {
        lines.push(run_line(&r));
    }
    lines
}

fn run_line((first, last, sheets): &(usize, usize, Vec<usize>)) -> String {
    let steps = if first == last {
        format!("Step {first}")
    } else {
        format!("Steps {first}-{last}")
    };
    let s: Vec<String> = sheets.iter().map(|s| s.to_string()).collect();
    let on = match s.len() {
        1 => format!("sheet {}", s[0]),
        _ => format!("sheets {}", s.join(", ")),
    };
    format!("{steps}: {on}")
}
