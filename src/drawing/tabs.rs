//! Holding tabs: small bridges left uncut in a strip's outline so the cut
//! sheet holds its strips like a parts tray. The outline is then drawn as
//! open pieces with a gap of the tab width at each tab; every writer draws
//! the pieces as they are, so the gaps are the same in SVG, DXF, PDF and
//! LightBurn. The tabs sit on the long straight sides, away from the holes'
//! ends: one on each side of a strip (the one on top a third of the way
//! along, the one below two thirds), more for long strips (one a side per
//! started 200 mm of straight edge), staggered so the strip cannot swing.

use super::Segment;
use glam::DVec2;

/// Most straight edge (mm) one tab holds on each side.
pub(crate) const TAB_SPACING: f64 = 200.0;

/// Tab centres along the axis, on the top side (y < 0) and the bottom side,
/// for straight sides from `left` to `right`; none when the sides are too
/// short for three tab widths.
pub fn centres(left: f64, right: f64, tab: f64) -> (Vec<f64>, Vec<f64>) {
    let straight = right - left;
    if tab <= 0.0 || straight < 3.0 * tab {
        return (Vec::new(), Vec::new());
    }
    let n = (straight / TAB_SPACING).ceil().max(1.0) as usize;
    let at = |f: f64| (0..n).map(move |i| left + straight * (i as f64 + f) / n as f64);
    (at(1.0 / 3.0).collect(), at(2.0 / 3.0).collect())
}

/// A stadium outline (straight sides from `left` to `right` at y = -r and
/// y = r, half-circle ends) cut into open pieces with a gap of width `tab`
/// at each tab, in the strip's frame; each piece is a start and its
/// segments, in the same clockwise order as the closed outline.
pub(crate) fn pieces(left: f64, right: f64, r: f64, tab: f64) -> Vec<(DVec2, Vec<Segment>)> {
    let (top, bottom) = centres(left, right, tab);
    if top.is_empty() {
        return Vec::new();
    }
    let h = tab / 2.0;
    // Walk the outline clockwise from the first top gap's far edge.
    let first = top[0];
    let mut out = Vec::new();
    let mut start = DVec2::new(first + h, -r);
    let mut segments = Vec::new();
    let mut cut = |to_gap: DVec2, resume: DVec2, segments: &mut Vec<Segment>, start: &mut DVec2| {
        segments.push(Segment::Line(to_gap));
        out.push((*start, std::mem::take(segments)));
        *start = resume;
    };
    for &c in &top[1..] {
        cut(
            DVec2::new(c - h, -r),
            DVec2::new(c + h, -r),
            &mut segments,
            &mut start,
        );
    }
    segments.push(Segment::Line(DVec2::new(right, -r)));
    segments.push(Segment::Arc {
        to: DVec2::new(right, r),
        center: DVec2::new(right, 0.0),
        clockwise: true,
    });
    // The bottom side runs right to left.
    for &c in bottom.iter().rev() {
        cut(
            DVec2::new(c + h, r),
            DVec2::new(c - h, r),
            &mut segments,
            &mut start,
        );
    }
    segments.push(Segment::Line(DVec2::new(left, r)));
    segments.push(Segment::Arc {
        to: DVec2::new(left, -r),
        center: DVec2::new(left, 0.0),
        clockwise: true,
    });
    segments.push(Segment::Line(DVec2::new(first - h, -r)));
    out.push((start, segments));
    out
}

#[cfg(test)]
mod tests {
    use super::super::Shape;
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn the_gaps_add_up_to_the_tabs() {
        for (left, right) in [(5.0, 95.0), (5.0, 505.0)] {
            let (r, tab) = (5.0, 0.5);
            let (top, bottom) = centres(left, right, tab);
            let pieces = pieces(left, right, r, tab);
            assert_eq!(pieces.len(), top.len() + bottom.len());
            let drawn: f64 = pieces
                .into_iter()
                .map(|(start, segments)| {
                    Shape::Path {
                        start,
                        segments,
                        closed: false,
                    }
                    .length()
                })
                .sum();
            let perimeter = 2.0 * (right - left) + 2.0 * PI * r;
            let tabs = (top.len() + bottom.len()) as f64;
            assert!((perimeter - drawn - tabs * tab).abs() < 1e-9);
        }
        assert_eq!(centres(5.0, 95.0, 0.5).0, vec![35.0]);
        assert_eq!(centres(5.0, 505.0, 0.5).0.len(), 3);
        assert!(centres(5.0, 6.0, 0.5).0.is_empty());
    }
}
