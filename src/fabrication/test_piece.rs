//! The test piece cut first on sheet 1: a strip exactly 100 mm tip to tip
//! (as cut when kerf compensation is on; 100 mm minus the kerf when it is
//! off, which measures the kerf) with eyelet holes stepped across diameters
//! around the nominal one, each labelled with its diameter, so the maker
//! checks scale, kerf and eyelet fit before cutting the job. It is shaped
//! like a strip (same width, rounded ends) so it nests in a lane like one.

use crate::fabrication::Fabrication;
use crate::font;
use glam::DVec2;

/// Thinnest wall kept beside a test hole (as for the strips' holes).
const MIN_WALL: f64 = 1.0;
/// Nominal tip-to-tip length (mm).
pub const LENGTH: f64 = 100.0;
/// Step between the test holes' diameters (mm).
pub(crate) const STEP: f64 = 0.1;
/// Space from a hole's edge to its label, and from the label to the next hole.
const LABEL_BEFORE: f64 = 0.8;
const LABEL_AFTER: f64 = 2.5;
/// Most test holes: the nominal diameter and two steps each side.
pub(crate) const MAX_HOLES: usize = 5;

/// A test strip cut before the job: holes stepped around the eyelet's
/// nominal diameter and a 100 mm length, to check kerf and eyelet fit.
#[derive(Clone, Debug, PartialEq)]
pub struct TestPiece {
    /// Nominal tip-to-tip length, like `Strip::length`.
    pub(crate) length: f64,
    /// Hole centres along the axis and their nominal diameters (before any
    /// kerf compensation), smallest first from the start tip.
    pub holes: Vec<(f64, f64)>,
    /// Engraved strokes in the strip frame: each hole's diameter and "100 mm".
    pub(crate) engraving: Vec<Vec<DVec2>>,
    /// The label texts, in order (for the guide and tests).
    pub labels: Vec<String>,
}

/// Text centred at `x` along the axis, on the centreline.
fn label(text: &str, x: f64, height: f64) -> Vec<Vec<DVec2>> {
    let x0 = x - font::width(text, height) / 2.0;
    font::text(text, height)
        .into_iter()
        .map(|s| {
            s.into_iter()
                .map(|p| DVec2::new(x0 + p.x, height / 2.0 - p.y))
                .collect()
        })
        .collect()
}

/// The test piece for these settings, or None when it is turned off or a
/// 100 mm strip does not fit the sheet.
pub fn test_piece(fab: &Fabrication) -> Option<TestPiece> {
    if !fab.test_piece {
        return None;
    }
    let grow = if fab.compensate_kerf { fab.kerf } else { 0.0 };
    let (uw, uh) = fab.sheet.usable();
    if LENGTH + grow > uw.max(uh) || fab.material.width + grow > uw.min(uh) {
        return None;
    }
    let w = fab.material.width;
    let d = fab.eyelet.hole;
    let height = (0.4 * w).min(3.0);
    let labelled = height >= super::MIN_LABEL_HEIGHT;
    let text = |v: f64| format!("{v:.1}");
    // Diameters: nominal +- whole steps, each leaving a wall on both sides.
    let smallest = fab.plotter.as_ref().map_or(0.5, |p| p.min_hole - 1e-9);
    let diameters: Vec<f64> = (-2i32..=2)
        .map(|k| d + k as f64 * STEP)
        // A plotter's blade tears holes under its minimum: no such steps
        // (3.2 - 0.2 is 3.0000000000000004, so within a nanometre).
        .filter(|&x| x >= smallest && x <= w - 2.0 * MIN_WALL)
        .collect();
    let widest = diameters.iter().copied().fold(d, f64::max);
    let label_w = if labelled {
        font::width(&text(widest), height)
    } else {
        0.0
    };
    // Each hole, then its label to its right; pitches wide enough for the
    // eyelet flanges so every hole can take an eyelet.
    // A label sits close after its hole and well before the next one.
    let pitch = (widest + LABEL_BEFORE + label_w + LABEL_AFTER).max(fab.eyelet.flange + 1.0);
    let reference = "100 mm";
    let ref_w = if labelled {
        font::width(reference, height) + 2.0
    } else {
        0.0
    };
    let first = fab.end_margin.max(widest / 2.0 + MIN_WALL);
    let room = LENGTH - first - fab.end_margin.max(w / 2.0) - ref_w;
    let fit = ((room - widest / 2.0 - LABEL_BEFORE - label_w) / pitch).floor() as i64 + 1;
    let n = (fit.max(0) as usize).min(MAX_HOLES).min(diameters.len());
    // Keep the middle n diameters (around the nominal one).
    let skip = (diameters.len() - n) / 2;
    let chosen = &diameters[skip..skip + n];
    let mut holes = Vec::new();
    let mut engraving = Vec::new();
    let mut labels = Vec::new();
    for (k, &dia) in chosen.iter().enumerate() {
        let x = first + k as f64 * pitch;
        holes.push((x, dia));
        if labelled {
            let t = text(dia);
            engraving.extend(label(
                &t,
                x + widest / 2.0 + LABEL_BEFORE + label_w / 2.0,
                height,
            ));
            labels.push(t);
        }
    }
    if labelled {
        let end = LENGTH - fab.end_margin.max(w / 2.0);
        engraving.extend(label(reference, end - ref_w / 2.0, height));
        labels.push(reference.to_string());
    }
    Some(TestPiece {
        length: LENGTH,
        holes,
        engraving,
        labels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holes_step_around_the_nominal_diameter_and_labels_stay_clear() {
        let fab = Fabrication::default();
        let p = test_piece(&fab).unwrap();
        let d: Vec<f64> = p.holes.iter().map(|h| h.1).collect();
        assert_eq!(d.len(), 5);
        assert!((d[2] - fab.eyelet.hole).abs() < 1e-12);
        for pair in p.holes.windows(2) {
            assert!(pair[1].0 - pair[0].0 >= fab.eyelet.flange + 1.0);
            assert!((pair[1].1 - pair[0].1 - STEP).abs() < 1e-12);
        }
        assert_eq!(p.labels, ["3.0", "3.1", "3.2", "3.3", "3.4", "100 mm"]);
        for q in p.engraving.iter().flatten() {
            assert!(q.x > 0.0 && q.x < LENGTH && q.y.abs() < fab.material.width / 2.0);
            for &(x, dia) in &p.holes {
                assert!(q.distance(DVec2::new(x, 0.0)) > dia / 2.0 + 0.3, "{q}");
            }
        }
        let last = p.holes.last().unwrap();
        assert!(last.0 + last.1 / 2.0 < LENGTH - MIN_WALL);
    }

    #[test]
    fn it_can_be_left_out() {
        let fab = Fabrication {
            test_piece: false,
            ..Fabrication::default()
        };
        assert!(test_piece(&fab).is_none());
    }
}
