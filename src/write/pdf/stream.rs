//! One PDF content stream, a page's or a symbol's: the drawing's items as
//! PDF operators in points, paint state set only when it changes.

use super::PT_PER_MM;
use crate::drawing::{
    Font, Ink, Item, Place, Segment, Shape, arc_to_cubics, circle_to_cubics, text, walk,
};
use glam::DVec2;
use pdf_writer::{Content, Name, Str};

pub(super) const REGULAR: Name = Name(b"F1");
pub(super) const BOLD: Name = Name(b"F2");

/// Coordinates to points, rounded to a hundredth of a point (3.5 um): far
/// below a laser's kerf or a printer's dot, and shorter numbers to write
/// and deflate.
fn pt(mm: f64) -> f32 {
    ((mm * PT_PER_MM * 100.0).round() / 100.0) as f32
}

/// Page coordinates (mm, y down from `origin`) to PDF points (y up): the
/// page's own space has its origin at the bottom-left corner, a symbol's at
/// the point where it is placed.
#[derive(Clone, Copy)]
pub(super) struct ToPdf {
    /// The y (mm, down the page) that maps to 0.
    pub(super) top: f64,
}

impl ToPdf {
    fn xy(self, p: DVec2) -> (f32, f32) {
        (pt(p.x), pt(self.top - p.y))
    }

    fn cubics(self, c: &mut Content, pieces: &[[DVec2; 3]]) {
        for [c1, c2, end] in pieces {
            let (x1, y1) = self.xy(*c1);
            let (x2, y2) = self.xy(*c2);
            let (x3, y3) = self.xy(*end);
            c.cubic_to(x1, y1, x2, y2, x3, y3);
        }
    }

    /// A path or circle as a path of the content stream; false for text.
    fn path(self, c: &mut Content, shape: &Shape) -> bool {
        match shape {
            Shape::Text { .. } => return false,
            Shape::Circle { center, radius } => {
                let (start, pieces) = circle_to_cubics(*center, *radius);
                let (x, y) = self.xy(start);
                c.move_to(x, y);
                self.cubics(c, &pieces);
                c.close_path();
            }
            Shape::Path {
                start,
                segments,
                closed,
            } => {
                let (x, y) = self.xy(*start);
                c.move_to(x, y);
                for (from, s) in walk(*start, segments) {
                    match s {
                        Segment::Line(p) => {
                            let (x, y) = self.xy(p);
                            c.line_to(x, y);
                        }
                        Segment::Arc {
                            to,
                            center,
                            clockwise,
                        } => self.cubics(c, &arc_to_cubics(from, to, center, clockwise)),
                    }
                }
                if *closed {
                    c.close_path();
                }
            }
        }
        true
    }
}

fn rgb([r, g, b]: [u8; 3]) -> (f32, f32, f32) {
    (r as f32 / 255.0, g as f32 / 255.0, b as f32 / 255.0)
}

/// Text the built-in fonts can show (their widths table is ASCII).
fn ascii(s: &str) -> String {
    s.chars()
        .map(|c| if (' '..='~').contains(&c) { c } else { '?' })
        .collect()
}

/// One content stream (a page's or a symbol's) being written: paint state
/// is set only when it changes, and starts unknown in every stream (a form
/// inherits whatever state the page had where it is placed).
pub(super) struct Stream {
    pub(super) content: Content,
    to: ToPdf,
    stroke: Option<[u8; 3]>,
    fill: Option<[u8; 3]>,
    width: Option<f64>,
    /// Fonts and symbols (with repeats) the stream uses: its resources.
    pub(super) fonts: [bool; 2],
    pub(super) symbols: Vec<usize>,
}

impl Stream {
    pub(super) fn new(to: ToPdf) -> Self {
        Self {
            content: Content::new(),
            to,
            stroke: None,
            fill: None,
            width: None,
            fonts: [false; 2],
            symbols: Vec::new(),
        }
    }

    pub(super) fn item(&mut self, Item { ink, shape, .. }: &Item) {
        let Ink {
            stroke: s,
            fill: f,
            width: w,
        } = *ink;
        let is_text = matches!(shape, Shape::Text { .. });
        if let Some(c) = s.filter(|_| !is_text) {
            if self.stroke != Some(c) {
                let (r, g, b) = rgb(c);
                self.content.set_stroke_rgb(r, g, b);
                self.stroke = Some(c);
            }
            if self.width != Some(w) {
                self.content.set_line_width((w * PT_PER_MM) as f32);
                self.width = Some(w);
            }
        }
        let fill_colour = if is_text { f.or(s) } else { f };
        if let Some(c) = fill_colour {
            if self.fill != Some(c) {
                let (r, g, b) = rgb(c);
                self.content.set_fill_rgb(r, g, b);
                self.fill = Some(c);
            }
        }
        if let Shape::Text {
            at,
            size,
            text: t,
            font,
            align,
        } = shape
        {
            let t = ascii(t);
            let start = text::start(*at, &t, *font, *size, *align);
            let name = match font {
                Font::Regular => REGULAR,
                Font::Bold => BOLD,
            };
            self.fonts[matches!(font, Font::Bold) as usize] = true;
            let (x, y) = self.to.xy(start);
            self.content
                .begin_text()
                .set_font(name, (size * PT_PER_MM) as f32)
                .next_line(x, y)
                .show(Str(t.as_bytes()))
                .end_text();
            return;
        }
        if f.is_none() && s.is_none() {
            return;
        }
        self.to.path(&mut self.content, shape);
        match (f.is_some(), s.is_some()) {
            (true, true) => self.content.fill_nonzero_and_stroke(),
            (true, false) => self.content.fill_nonzero(),
            _ => self.content.stroke(),
        };
    }

    /// Draw a symbol with its origin at `at` (page mm).
    pub(super) fn place(&mut self, place: &Place) {
        let (x, y) = self.to.xy(place.at);
        self.content
            .save_state()
            .transform([1.0, 0.0, 0.0, 1.0, x, y])
            .x_object(Name(symbol_name(place.symbol).as_bytes()))
            .restore_state();
        self.symbols.push(place.symbol);
    }
}

/// The resource name of symbol `i`.
pub(super) fn symbol_name(i: usize) -> String {
    format!("S{i}")
}
