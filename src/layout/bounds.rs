//! Lower bounds on the number of sheets (FABRICATION.md), so a build can
//! say how far its layout is from the best possible.

use crate::fabrication::SheetSpec;
use std::f64::consts::PI;

/// Lower bounds on the sheet count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bounds {
    /// Any layout: parts' area (with half the gap around each) over the sheet area.
    pub area: usize,
    /// Lane layouts: total lane length over the lane length of a sheet.
    pub lanes: usize,
}

/// Area of a stadium of tip-to-tip length `l` and width `w`.
pub(crate) fn stadium_area(l: f64, w: f64) -> f64 {
    w * (l - w) + PI * w * w / 4.0
}

/// Lower bound on the sheet count by area: the parts, each with half the gap
/// around it, over the usable sheet area.
pub(crate) fn area_bound(lengths: &[f64], w: f64, sheet: &SheetSpec) -> usize {
    let g = sheet.gap;
    let (uw, uh) = sheet.usable();
    // Each part with half the gap around it: a stadium of width w + g.
    let parts: f64 = lengths
        .iter()
        .map(|&l| (w + g) * (l - w) + PI * (w + g) * (w + g) / 4.0)
        .sum();
    ceil(parts / ((uw + g) * (uh + g)))
}

/// Lane layouts with every lane in one orientation (the better of the two).
pub(crate) fn lane_bound(lengths: &[f64], w: f64, sheet: &SheetSpec) -> usize {
    let g = sheet.gap;
    let (uw, uh) = sheet.usable();
    let total: f64 = lengths.iter().map(|&l| l + g).sum();
    let sheets = |run: f64, span: f64| {
        let lanes = ceil(total / (run + g));
        let per_sheet = ((span + g) / (w + g)).floor().max(1.0) as usize;
        lanes.div_ceil(per_sheet)
    };
    sheets(uw, uh).min(sheets(uh, uw))
}

/// Ceiling that forgives rounding noise just above a whole number.
fn ceil(x: f64) -> usize {
    (x - 1e-9).ceil().max(0.0) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::layout::tests::small_sheet as sheet;

    #[test]
    fn bounds_by_hand() {
        // Usable 100 x 40, pitch 12. Along x: lanes of 100 (+ gap = 102),
        // 3 a sheet. Along y: lanes of 40 (+ gap = 42), 8 a sheet.
        let s = sheet();
        // 6 x 52 = 312: 4 lanes along x (2 sheets), 8 along y (1 sheet).
        assert_eq!(lane_bound(&[50.0; 6], 10.0, &s), 1);
        // 4 x 102 = 408: 4 lanes along x (2 sheets), 10 along y (2 sheets).
        assert_eq!(lane_bound(&[100.0; 4], 10.0, &s), 2);
        let one = (12.0 * 40.0 + PI * 144.0 / 4.0) / (102.0 * 42.0);
        assert_eq!(area_bound(&[50.0], 10.0, &s), one.ceil() as usize);
        assert_eq!(area_bound(&[], 10.0, &s), 0);
    }
}
