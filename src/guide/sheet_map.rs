//! The sheet maps: each cut sheet drawn to scale, every strip tinted by the
//! step it is used in (the viewer's step colours) and labelled with what is
//! engraved on it where the label fits, the lanes numbered; under it, each
//! lane's strips in order, so a strip is found on the cut sheet by its
//! engraving from this page alone.

use super::finding::{Spots, engraved_text};
use super::rect;
use crate::drawing::flow::{BLACK, GREY, MARGIN, PageFlow, SMALL, text_item};
use crate::drawing::{Align, Font, Ink, Item, text};
use crate::pipeline::Build;
use glam::DVec2;

/// The smallest printed text (mm): as the engraving's.
const LABEL: f64 = 2.5;

/// A step's tint: blue to teal to green to olive over the steps, never the
/// red the step pages use for what is new (the viewer's `stepColour`).
pub(crate) fn step_colour(k: usize, steps: usize) -> [u8; 3] {
    let t = if steps > 1 {
        k as f64 / (steps - 1) as f64
    } else {
        0.0
    };
    let h = 215.0 - 150.0 * t;
    let (s, l) = (0.55, 0.42 + 0.08 * (std::f64::consts::PI * t).sin());
    let f = |n: f64| {
        let q = (n + h / 30.0) % 12.0;
        let a = s * l.min(1.0 - l);
        (255.0 * (l - a * (q - 3.0).min(9.0 - q).clamp(-1.0, 1.0))).round() as u8
    };
    [f(0.0), f(8.0), f(4.0)]
}

/// A colour mixed towards white by `t` (0: itself, 1: white).
fn pale(c: [u8; 3], t: f64) -> [u8; 3] {
    c.map(|v| (v as f64 + (255.0 - v as f64) * t).round() as u8)
}

/// One page per sheet: the map, then its lanes in words.
pub(super) fn sheet_maps(w: &mut PageFlow, b: &Build, spots: &Spots) {
    let mut step_of = vec![0; b.parts.strips.len()];
    for (k, step) in b.steps.iter().enumerate() {
        for &s in &step.strips {
            step_of[s] = k;
        }
    }
    let n = b.layout.sheets.len();
    for (k, sheet) in b.layout.sheets.iter().enumerate() {
        // The heading, its paragraph and the map together; the lanes follow.
        w.need(30.0 + scale(w, b) * b.layout.sheet.height);
        w.heading(&format!("Sheet map: sheet {} of {n}", k + 1));
        let steps: Vec<usize> = {
            let mut s: Vec<usize> = sheet
                .placements
                .iter()
                .map(|p| step_of[p.part] + 1)
                .collect();
            s.sort_unstable();
            s.dedup();
            s
        };
        let list: Vec<String> = steps.iter().map(|s| s.to_string()).collect();
        w.paragraph(
            &format!(
                "The cut sheet to scale, seen as it lies in the laser. Each strip is tinted by its step (steps {} \
                 here) and labelled with what is engraved on it where the label fits; the lanes are numbered in \
                 the margin. The lanes' strips follow in order.",
                list.join(", ")
            ),
            SMALL,
            GREY,
        );
        map(w, b, k, &step_of);
        lanes(w, b, k, spots);
    }
}

/// The map's scale: the sheet to the text width, at most half the page high.
fn scale(w: &PageFlow, b: &Build) -> f64 {
    let spec = &b.layout.sheet;
    let room = DVec2::new(w.width() - 8.0, 0.5 * (w.bottom() - MARGIN));
    (room.x / spec.width).min(room.y / spec.height)
}

/// The sheet drawn to scale.
fn map(w: &mut PageFlow, b: &Build, k: usize, step_of: &[usize]) {
    let spec = &b.layout.sheet;
    let scale = scale(w, b);
    let origin = DVec2::new(MARGIN + 8.0, w.y + 1.0);
    let at = |x: f64, y: f64| origin + DVec2::new(x, y) * scale;
    let sheet = &b.layout.sheets[k];
    let mut items = vec![Item::art(
        Ink::line(GREY, 0.3),
        rect(origin.x, origin.y, spec.width * scale, spec.height * scale),
    )];
    let width = b.layout.part_width;
    let mut lane_marks: Vec<(bool, f64)> = Vec::new();
    for p in &sheet.placements {
        let len = b.layout.lengths[p.part];
        let (dx, dy) = if p.rotated {
            (width, len)
        } else {
            (len, width)
        };
        let corner = at(p.x, p.y);
        let colour = step_colour(step_of[p.part], b.steps.len());
        items.push(Item::art(
            Ink {
                stroke: Some(colour),
                width: 0.15,
                fill: Some(pale(colour, 0.6)),
            },
            rect(corner.x, corner.y, dx * scale, dy * scale),
        ));
        let strip = &b.parts.strips[p.part];
        let label = engraved_text(strip, &b.parts.types);
        // Inside the strip where it fits with a margin; never rotated.
        let fits = !p.rotated
            && dy * scale >= 0.9 * LABEL
            && text::width(&label, Font::Regular, LABEL) + 1.0 <= dx * scale;
        if fits {
            let c = at(p.x + dx / 2.0, p.y + dy / 2.0);
            items.push(text_item(
                DVec2::new(c.x, c.y + 0.35 * LABEL),
                LABEL,
                &label,
                Font::Regular,
                Align::Center,
                BLACK,
            ));
        }
        let mark = (p.rotated, if p.rotated { p.x } else { p.y });
        if !lane_marks
            .iter()
            .any(|m| m.0 == mark.0 && (m.1 - mark.1).abs() < 0.01)
        {
            lane_marks.push(mark);
        }
    }
    if let Some(t) = sheet.test_piece {
        let len = b.layout.test_piece.unwrap_or(0.0);
        let (dx, dy) = if t.rotated {
            (width, len)
        } else {
            (len, width)
        };
        let corner = at(t.x, t.y);
        items.push(Item::art(
            Ink::line(BLACK, 0.2),
            rect(corner.x, corner.y, dx * scale, dy * scale),
        ));
    }
    // Lane numbers: left of the sheet for lanes along it, above it for lanes
    // down it (numbered as in the words below).
    lane_marks.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut last_end = f64::NEG_INFINITY;
    for (i, &(rotated, edge)) in lane_marks.iter().enumerate() {
        let label = (i + 1).to_string();
        let mid = edge + width / 2.0;
        let item = if rotated {
            let x = at(mid, 0.0).x;
            let half = text::width(&label, Font::Regular, LABEL) / 2.0;
            // Neighbouring numbers never overlap: skip one that would.
            if x - half < last_end + 0.3 {
                continue;
            }
            last_end = x + half;
            text_item(
                DVec2::new(x, origin.y - 0.8),
                LABEL,
                &label,
                Font::Regular,
                Align::Center,
                GREY,
            )
        } else {
            text_item(
                DVec2::new(origin.x - 1.5, at(0.0, mid).y + 0.35 * LABEL),
                LABEL,
                &label,
                Font::Regular,
                Align::Right,
                GREY,
            )
        };
        items.push(item);
    }
    w.need(spec.height * scale + 4.0);
    w.push(items);
    w.y = origin.y + spec.height * scale + 4.0;
}

/// Each lane's strips in words, in order along the lane: one paragraph.
fn lanes(w: &mut PageFlow, b: &Build, k: usize, spots: &Spots) {
    let sheet = &b.layout.sheets[k];
    let mut parts = Vec::new();
    for (i, &(rotated, _)) in spots.lanes[k].iter().enumerate() {
        let mut on: Vec<&crate::layout::Placement> = sheet
            .placements
            .iter()
            .filter(|p| spots.of[p.part].lane == i + 1)
            .collect();
        on.sort_by(|a, b| {
            if rotated {
                a.y.total_cmp(&b.y)
            } else {
                a.x.total_cmp(&b.x)
            }
        });
        let names: Vec<String> = on
            .iter()
            .map(|p| engraved_text(&b.parts.strips[p.part], &b.parts.types))
            .collect();
        let way = if rotated { " (down)" } else { "" };
        parts.push(format!("lane {}{way}: {}", i + 1, names.join(" ")));
    }
    w.paragraph(
        &format!(
            "Lanes, each left to right (a lane marked down: top to bottom): {}.",
            parts.join("; ")
        ),
        SMALL,
        BLACK,
    );
}
