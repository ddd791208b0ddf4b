//! Sheet advice: the job nested on every sheet preset, and the smallest
//! preset that holds it (fewest sheets, then the smallest sheet area, then
//! the preset list's order), which `--sheet auto` picks.

use super::{Job, Layout};
use crate::fabrication::{SHEET_PRESETS, SheetSpec};

/// The job on one preset.
#[derive(Clone, Debug, PartialEq)]
pub struct SheetOption {
    pub name: String,
    pub width: f64,
    pub height: f64,
    /// Sheets needed, or None when some strip is longer than the preset.
    pub sheets: Option<usize>,
    /// Fraction of the sheets' area covered by parts (0 when it does not hold the job).
    pub utilisation: f64,
}

impl SheetOption {
    /// The preset as a sheet, with the margin and gap of `base`.
    pub fn spec(&self, base: &SheetSpec) -> SheetSpec {
        SheetSpec {
            name: self.name.clone(),
            width: self.width,
            height: self.height,
            ..base.clone()
        }
    }
}

/// The job nested on each preset, in the presets' order, keeping the
/// margin and gap of `base`.
pub fn sheet_options(job: &Job, base: &SheetSpec) -> Vec<SheetOption> {
    SHEET_PRESETS
        .iter()
        .map(|&(name, width, height)| {
            let spec = SheetSpec {
                name: name.into(),
                width,
                height,
                ..base.clone()
            };
            let layout: Option<Layout> = job.holds(&spec).then(|| job.nest(&spec));
            SheetOption {
                name: name.into(),
                width,
                height,
                sheets: layout.as_ref().map(|l| l.sheets.len()),
                utilisation: layout.as_ref().map_or(0.0, Layout::utilisation),
            }
        })
        .collect()
}

/// The smallest preset that holds the job: fewest sheets, then the smallest
/// sheet area; ties keep the presets' order.
pub fn smallest(options: &[SheetOption]) -> Option<&SheetOption> {
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

    #[test]
    fn fewest_sheets_first_then_the_smallest_area() {
        let base = SheetSpec {
            name: "x".into(),
            width: 600.0,
            height: 400.0,
            margin: 5.0,
            gap: 2.0,
        };
        // Ten strips of 280 mm: one A3 lane (410 mm) takes one, so A3 needs
        // one sheet (23 lanes); A4 (287 mm lanes) takes them too.
        let job = Job {
            lengths: vec![280.0; 10],
            width: 10.0,
            test_piece: None,
            steps: None,
        };
        let options = sheet_options(&job, &base);
        assert_eq!(options.len(), SHEET_PRESETS.len());
        assert!(options.iter().all(|o| o.sheets == Some(1)));
        assert_eq!(smallest(&options).unwrap().name, "a4");
        // 290 mm strips do not fit A4's 287 mm: A3 is the smallest.
        let job = Job {
            lengths: vec![290.0; 10],
            ..job
        };
        let options = sheet_options(&job, &base);
        assert_eq!(
            options.iter().find(|o| o.name == "a4").unwrap().sheets,
            None
        );
        assert_eq!(smallest(&options).unwrap().name, "a3");
    }
}
