//! One PDF content stream, a page's or a symbol's: the drawing's items as
//! PDF operators in points, paint state set only when it changes.

use super::PT_PER_MM;
use crate::drawing::{
    Font, Ink, Item, Place, Segment, Shape, arc_to_cubics, circle_to_cubics, text, walk, winansi,
};
use glam::DVec2;
use pdf_writer::{Content, Name, Str};
use std::collections::HashMap;

pub(super) const REGULAR: Name = Name(b"F1");
pub(super) const BOLD: Name = Name(b"F2");

/// How finely a document's coordinates are written, in steps a point.
/// Cut sheets keep a hundredth of a point (3.5 um: far below a laser's
/// kerf); the guide's pictures, printed on paper, a tenth (35 um, under a
/// 600 dpi printer's dot), which takes a digit off every number.
pub(crate) const CUT_GRID: f64 = 100.0;
pub(crate) const PRINT_GRID: f64 = 10.0;

/// Page coordinates (mm, y down from `origin`) to PDF points (y up): the
/// page's own space has its origin at the bottom-left corner, a symbol's at
/// the point where it is placed.
#[derive(Clone, Copy)]
pub(super) struct ToPdf {
    /// The y (mm, down the page) that maps to 0.
    pub(super) top: f64,
    /// Steps a point that coordinates are rounded to (`CUT_GRID`, `PRINT_GRID`).
    pub(super) grid: f64,
}

impl ToPdf {
    /// `mm` in points, rounded to the grid.
    fn pt(self, mm: f64) -> f32 {
        ((mm * PT_PER_MM * self.grid).round() / self.grid) as f32
    }

    fn xy(self, p: DVec2) -> (f32, f32) {
        (self.pt(p.x), self.pt(self.top - p.y))
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

/// A colour channel to 3 decimals: still exactly its 8-bit value (steps of
/// 1/255 are wider than 0.001), in 5 characters rather than 10.
fn channel(c: u8) -> f32 {
    ((c as f64 / 255.0 * 1000.0).round() / 1000.0) as f32
}

fn rgb([r, g, b]: [u8; 3]) -> (f32, f32, f32) {
    (channel(r), channel(g), channel(b))
}

/// A line width in points, to a hundredth.
fn width_pt(mm: f64) -> f32 {
    ((mm * PT_PER_MM * 100.0).round() / 100.0) as f32
}

/// A circle of one radius and paint (fill, stroke or both), drawn once as
/// a Form XObject centred on its origin and placed by `cm ... Do`: the
/// guide's pivot dots, a hundred or more on a step page, then cost about 35
/// bytes each instead of a 200-byte path of four Beziers. The form paints
/// with the colours and line width in effect where it is placed.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub(super) struct Dot {
    radius: u64,
    fill: bool,
    stroke: bool,
}

impl Dot {
    /// The form's content and its bounding box half-size (points), for a
    /// line width of `width` mm.
    pub(super) fn content(self, grid: f64, width: f64) -> (Vec<u8>, f64) {
        let radius = f64::from_bits(self.radius);
        let to = ToPdf { top: 0.0, grid };
        let mut c = Content::new();
        to.path(
            &mut c,
            &Shape::Circle {
                center: DVec2::ZERO,
                radius,
            },
        );
        paint(&mut c, self.fill, self.stroke);
        (c.finish().to_vec(), (radius + width) * PT_PER_MM + 1.0)
    }
}

/// The dots of a document, in order of first use, each with the widest
/// line it is stroked with (for its bounding box).
#[derive(Default)]
pub(super) struct Dots {
    index: HashMap<Dot, usize>,
    pub(super) list: Vec<(Dot, f64)>,
}

fn paint(c: &mut Content, fill: bool, stroke: bool) {
    match (fill, stroke) {
        (true, true) => c.fill_nonzero_and_stroke(),
        (true, false) => c.fill_nonzero(),
        _ => c.stroke(),
    };
}

/// One content stream (a page's or a symbol's) being written: paint state
/// is set only when it changes, and starts unknown in every stream (a form
/// inherits whatever state the page had where it is placed).
pub(super) struct Stream<'a> {
    pub(super) content: Content,
    to: ToPdf,
    stroke: Option<[u8; 3]>,
    fill: Option<[u8; 3]>,
    width: Option<f64>,
    /// Fonts, symbols and dots (with repeats) the stream uses: its resources.
    pub(super) fonts: [bool; 2],
    pub(super) symbols: Vec<usize>,
    pub(super) dots: Vec<usize>,
    /// The document's shared dots, when circles are drawn as dots.
    shared: Option<&'a mut Dots>,
}

impl<'a> Stream<'a> {
    pub(super) fn new(to: ToPdf, shared: Option<&'a mut Dots>) -> Self {
        Self {
            content: Content::new(),
            to,
            stroke: None,
            fill: None,
            width: None,
            fonts: [false; 2],
            symbols: Vec::new(),
            dots: Vec::new(),
            shared,
        }
    }

    /// Place the shared dot of a circle's radius and paint, if dots are shared.
    fn dot(&mut self, center: DVec2, radius: f64, fill: bool, stroke: bool, width: f64) -> bool {
        let Some(shared) = self.shared.as_deref_mut() else {
            return false;
        };
        let dot = Dot {
            radius: radius.to_bits(),
            fill,
            stroke,
        };
        let next = shared.list.len();
        let k = *shared.index.entry(dot).or_insert(next);
        if k == next {
            shared.list.push((dot, 0.0));
        }
        if stroke {
            shared.list[k].1 = shared.list[k].1.max(width);
        }
        let (x, y) = self.to.xy(center);
        self.content
            .save_state()
            .transform([1.0, 0.0, 0.0, 1.0, x, y])
            .x_object(Name(dot_name(k).as_bytes()))
            .restore_state();
        self.dots.push(k);
        true
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
                self.content.set_line_width(width_pt(w));
                self.width = Some(w);
            }
        }
        let fill_colour = if is_text { f.or(s) } else { f };
        if let Some(c) = fill_colour
            && self.fill != Some(c)
        {
            let (r, g, b) = rgb(c);
            self.content.set_fill_rgb(r, g, b);
            self.fill = Some(c);
        }
        if let Shape::Text {
            at,
            size,
            text: t,
            font,
            align,
        } = shape
        {
            let start = text::start(*at, t, *font, *size, *align);
            let name = match font {
                Font::Regular => REGULAR,
                Font::Bold => BOLD,
            };
            self.fonts[matches!(font, Font::Bold) as usize] = true;
            // Text stays on the fine grid: where pdftotext puts a word
            // depends on its exact place, and the guide's text must read
            // the same as before the coarser grid.
            let fine = ToPdf {
                grid: CUT_GRID,
                ..self.to
            };
            let (x, y) = fine.xy(start);
            self.content
                .begin_text()
                .set_font(name, (size * PT_PER_MM) as f32)
                .next_line(x, y)
                .show(Str(&winansi::encode(t)))
                .end_text();
            return;
        }
        if f.is_none() && s.is_none() {
            return;
        }
        if let Shape::Circle { center, radius } = shape
            && self.dot(*center, *radius, f.is_some(), s.is_some(), w)
        {
            return;
        }
        self.to.path(&mut self.content, shape);
        paint(&mut self.content, f.is_some(), s.is_some());
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

/// The resource name of dot `i`.
pub(super) fn dot_name(i: usize) -> String {
    format!("D{i}")
}
