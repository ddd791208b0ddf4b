//! Labels on the step pictures, placed so that none covers another: each
//! label tries spots around its anchor, nearest first, and takes the first
//! free one inside the picture; a label set away from its anchor gets a thin
//! leader line back to it. Every label sits on a white patch so that it
//! reads over the rods.

use crate::drawing::text::width;
use crate::drawing::{Align, Font, Ink, Item, Shape};
use glam::DVec2;

/// Font size of every picture label (mm): nothing in a guide is printed
/// smaller than 2.5 mm.
pub(crate) const SIZE: f64 = 2.6;

/// One label to place.
pub(crate) struct Label {
    pub(crate) anchor: DVec2,
    pub(crate) text: String,
    pub(crate) colour: [u8; 3],
    pub(crate) bold: bool,
    /// Preferred direction from the anchor (page coordinates, y down).
    pub(crate) toward: DVec2,
}

/// Places labels inside a box, avoiding each other.
pub(crate) struct Placer {
    lo: DVec2,
    hi: DVec2,
    taken: Vec<(DVec2, DVec2)>,
    pub(crate) items: Vec<Item>,
    /// Every label's text, in order (what the picture says, for tests).
    pub(crate) texts: Vec<String>,
}

impl Placer {
    pub(crate) fn new(lo: DVec2, hi: DVec2) -> Self {
        Self {
            lo,
            hi,
            taken: Vec::new(),
            items: Vec::new(),
            texts: Vec::new(),
        }
    }

    pub(crate) fn place(&mut self, label: &Label) {
        let font = if label.bold {
            Font::Bold
        } else {
            Font::Regular
        };
        let w = width(&label.text, font, SIZE) + 0.8;
        let h = SIZE * 0.95;
        let half = DVec2::new(w / 2.0, h / 2.0);
        let toward = label.toward.try_normalize().unwrap_or(DVec2::Y);
        // Directions: preferred first, then turning both ways round.
        let mut dirs = Vec::with_capacity(12);
        for k in 0..12 {
            let turn = ((k + 1) / 2) as f64 * std::f64::consts::PI / 6.0;
            let angle = if k % 2 == 1 { turn } else { -turn };
            let (s, c) = angle.sin_cos();
            dirs.push(DVec2::new(
                toward.x * c - toward.y * s,
                toward.x * s + toward.y * c,
            ));
        }
        let fits = |c: DVec2, taken: &[(DVec2, DVec2)]| {
            let (lo, hi) = (c - half, c + half);
            lo.x >= self.lo.x
                && lo.y >= self.lo.y
                && hi.x <= self.hi.x
                && hi.y <= self.hi.y
                && taken
                    .iter()
                    .all(|(a, b)| hi.x <= a.x || lo.x >= b.x || hi.y <= a.y || lo.y >= b.y)
        };
        let mut chosen = None;
        'search: for ring in 0..10 {
            let reach = 0.6 + ring as f64 * 1.6;
            for d in &dirs {
                // Distance from the anchor to the box's edge along d.
                let edge = (half.x / d.x.abs().max(1e-9)).min(half.y / d.y.abs().max(1e-9));
                let c = label.anchor + *d * (edge + reach);
                if fits(c, &self.taken) {
                    chosen = Some((c, ring));
                    break 'search;
                }
            }
        }
        // Crowded beyond every spot: the nearest spot inside the picture.
        let (centre, ring) = chosen.unwrap_or_else(|| {
            let c = label.anchor + toward * (half.y + 0.6);
            (
                c.clamp(self.lo + half, (self.hi - half).max(self.lo + half)),
                0,
            )
        });
        self.taken.push((centre - half, centre + half));
        if ring > 0 {
            let end = nearest_on_box(centre - half, centre + half, label.anchor);
            self.items.push(Item::art(
                Ink::line(label.colour, 0.15),
                Shape::polyline(&[label.anchor, end], false),
            ));
        }
        self.items.push(Item::art(
            Ink::fill([255, 255, 255]),
            Shape::polyline(
                &[
                    centre - half,
                    DVec2::new(centre.x + half.x, centre.y - half.y),
                    centre + half,
                    DVec2::new(centre.x - half.x, centre.y + half.y),
                ],
                true,
            ),
        ));
        self.items.push(Item::art(
            Ink::fill(label.colour),
            Shape::Text {
                at: DVec2::new(centre.x, centre.y + SIZE * 0.35),
                size: SIZE,
                text: label.text.clone(),
                font,
                align: Align::Center,
            },
        ));
        self.texts.push(label.text.clone());
    }
}

fn nearest_on_box(lo: DVec2, hi: DVec2, p: DVec2) -> DVec2 {
    p.clamp(lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crowded_labels_do_not_overlap() {
        let mut p = Placer::new(DVec2::ZERO, DVec2::new(60.0, 40.0));
        for k in 0..10 {
            p.place(&Label {
                anchor: DVec2::new(20.0 + 0.5 * k as f64, 20.0),
                text: format!("[{k},12]"),
                colour: [0, 0, 0],
                bold: false,
                toward: DVec2::Y,
            });
        }
        let boxes = &p.taken;
        for (i, a) in boxes.iter().enumerate() {
            for b in &boxes[i + 1..] {
                let apart = a.1.x <= b.0.x || a.0.x >= b.1.x || a.1.y <= b.0.y || a.0.y >= b.1.y;
                assert!(apart, "{a:?} overlaps {b:?}");
            }
        }
        assert_eq!(p.texts.len(), 10);
    }
}
