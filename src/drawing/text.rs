//! Text metrics for layout (Helvetica's standard advance widths, in
//! thousandths of the font size), and text as single strokes for writers
//! without fonts.

use super::{Align, Font, Shape};
use crate::font;
use glam::DVec2;

/// Advance widths of ASCII 32..=126 in Helvetica.
const REGULAR: [u16; 95] = [
    278, 278, 355, 556, 556, 889, 667, 191, 333, 333, 389, 584, 278, 333, 278, 278, 556, 556, 556,
    556, 556, 556, 556, 556, 556, 556, 278, 278, 584, 584, 584, 556, 1015, 667, 667, 722, 722, 667,
    611, 778, 722, 278, 500, 667, 556, 833, 722, 778, 667, 778, 722, 667, 611, 722, 667, 944, 667,
    667, 611, 278, 278, 278, 469, 556, 333, 556, 556, 500, 556, 556, 278, 556, 556, 222, 222, 500,
    222, 833, 556, 556, 556, 556, 333, 500, 278, 556, 500, 722, 500, 500, 500, 334, 260, 334, 584,
];

/// Advance widths of ASCII 32..=126 in Helvetica-Bold.
const BOLD: [u16; 95] = [
    278, 333, 474, 556, 556, 889, 722, 238, 333, 333, 389, 584, 278, 333, 278, 278, 556, 556, 556,
    556, 556, 556, 556, 556, 556, 556, 333, 333, 584, 584, 584, 611, 975, 722, 722, 722, 722, 667,
    611, 778, 722, 278, 556, 722, 611, 833, 722, 778, 667, 778, 722, 667, 611, 722, 667, 944, 667,
    667, 611, 333, 278, 333, 584, 556, 333, 556, 611, 556, 611, 556, 333, 611, 611, 278, 278, 556,
    278, 889, 611, 611, 611, 611, 389, 556, 333, 611, 556, 778, 556, 556, 500, 389, 280, 389, 584,
];

/// Width of `text` set in `font` at `size` (same unit as size).
pub fn width(text: &str, font: Font, size: f64) -> f64 {
    let table = match font {
        Font::Regular => &REGULAR,
        Font::Bold => &BOLD,
    };
    let ascii = |c: char| table[(c as u32 - 32) as usize] as u32;
    // Beyond ASCII: the WinAnsi glyph's width, or the `?` shown instead.
    let bold = matches!(font, Font::Bold);
    let units: u32 = text
        .chars()
        .map(|c| {
            if (' '..='~').contains(&c) {
                ascii(c)
            } else {
                super::winansi::upper_width(c, bold).map_or(ascii('?'), u32::from)
            }
        })
        .sum();
    units as f64 * size / 1000.0
}

/// Where a text's baseline starts once aligned at `at`.
pub fn start(at: DVec2, text: &str, font: Font, size: f64, align: Align) -> DVec2 {
    let w = width(text, font, size);
    match align {
        Align::Left => at,
        Align::Center => at - DVec2::new(w / 2.0, 0.0),
        Align::Right => at - DVec2::new(w, 0.0),
    }
}

/// The stroke font's capitals are this part of a text's size, as in
/// Helvetica.
pub(crate) const CAP_OF_SIZE: f64 = 0.7;

/// A text shape as single-stroke polylines on a y-down page.
pub(crate) fn strokes(shape: &Shape) -> Vec<Vec<DVec2>> {
    let Shape::Text {
        at,
        size,
        text,
        font: f,
        align,
    } = shape
    else {
        return Vec::new();
    };
    let cap = CAP_OF_SIZE * size;
    let w = font::width(text, cap);
    let x0 = match align {
        Align::Left => at.x,
        Align::Center => at.x - w / 2.0,
        Align::Right => at.x - w,
    };
    let _ = f;
    font::text(text, cap)
        .into_iter()
        .map(|s| {
            s.into_iter()
                .map(|p| DVec2::new(x0 + p.x, at.y - p.y))
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widths_follow_helvetica() {
        assert!(
            (width("Step", Font::Regular, 10.0) - (667.0 + 278.0 + 556.0 + 556.0) / 100.0).abs()
                < 1e-12
        );
        assert!(width("W", Font::Bold, 10.0) > width("i", Font::Bold, 10.0));
        // Latin letters by their own glyphs; others as the `?` shown.
        assert_eq!(
            width("ü", Font::Regular, 1.0),
            width("u", Font::Regular, 1.0)
        );
        assert_eq!(width("Ä", Font::Bold, 1.0), width("A", Font::Bold, 1.0));
        assert_eq!(width("円", Font::Bold, 1.0), width("?", Font::Bold, 1.0));
        assert_eq!(
            start(
                DVec2::new(10.0, 0.0),
                "ab",
                Font::Regular,
                1.0,
                Align::Right
            )
            .x,
            10.0 - 1.112
        );
    }
}
