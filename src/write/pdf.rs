//! PDF files: cut sheets (one page per sheet, the page exactly the sheet's
//! size at true scale, mm x 72 / 25.4 pt, hairline strokes in the layer
//! colours) and the assembly guide, whose shared drawings are written once
//! as Form XObjects and placed by reference on every page that shows them.
//!
//! Written with `pdf-writer`: it streams objects straight into the file's
//! bytes and has Form XObjects, where printpdf built a lopdf document of
//! every operation first (31.6 s of a 37.7 s 100 x 100 build) and named
//! its resources from a process-wide counter.

use crate::design::fnv1a;
use crate::drawing::{
    Font, Group, Ink, Item, Page, Place, Segment, Shape, Symbol, arc_to_cubics, circle_to_cubics,
    text,
};
use glam::DVec2;
use pdf_writer::{Content, Filter, Finish, Name, Pdf, Rect, Ref, Str, TextStr};
use std::collections::HashMap;

/// Points per millimetre.
pub const PT_PER_MM: f64 = 72.0 / 25.4;
/// Hairline width in mm (0.025 mm = 0.07 pt; print drivers for lasers treat
/// anything at or below 0.001 in as a vector cut).
pub const HAIRLINE_MM: f64 = 0.025;

/// Deflate level of content streams. Measured on the 42 MB of content of a
/// 100 x 100 build's two PDFs: level 1 deflates them 5 times faster than
/// zlib's default 6, into files 23% larger.
const DEFLATE_LEVEL: u8 = 1;

const REGULAR: Name = Name(b"F1");
const BOLD: Name = Name(b"F2");

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
struct ToPdf {
    /// The y (mm, down the page) that maps to 0.
    top: f64,
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
                let mut current = *start;
                for s in segments {
                    match *s {
                        Segment::Line(p) => {
                            let (x, y) = self.xy(p);
                            c.line_to(x, y);
                            current = p;
                        }
                        Segment::Arc {
                            to,
                            center,
                            clockwise,
                        } => {
                            self.cubics(c, &arc_to_cubics(current, to, center, clockwise));
                            current = to;
                        }
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
struct Stream {
    content: Content,
    to: ToPdf,
    stroke: Option<[u8; 3]>,
    fill: Option<[u8; 3]>,
    width: Option<f64>,
    /// Fonts and symbols (with repeats) the stream uses: its resources.
    fonts: [bool; 2],
    symbols: Vec<usize>,
}

impl Stream {
    fn new(to: ToPdf) -> Self {
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

    fn item(&mut self, Item { ink, shape, .. }: &Item) {
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
    fn place(&mut self, place: &Place) {
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
fn symbol_name(i: usize) -> String {
    format!("S{i}")
}

/// Deflate a content stream.
fn deflate(bytes: &[u8]) -> Vec<u8> {
    miniz_oxide::deflate::compress_to_vec_zlib(bytes, DEFLATE_LEVEL)
}

/// All pages in one PDF. A drawing that repeats (the strips of one part
/// type on the cut sheets) is written once, as a symbol, and each copy
/// places it: see `share_repeats`.
pub fn write(title: &str, pages: &[Page]) -> Vec<u8> {
    let (pages, symbols) = share_repeats(pages);
    write_with_symbols(title, &pages, &symbols)
}

/// Where a group is anchored: the first point of its first item.
fn anchor(g: &Group) -> Option<DVec2> {
    match &g.items.first()?.shape {
        Shape::Circle { center, .. } => Some(*center),
        Shape::Path { start, .. } => Some(*start),
        Shape::Text { at, .. } => Some(*at),
    }
}

/// `shape` moved by `d`.
fn moved(shape: &Shape, d: DVec2) -> Shape {
    let mut shape = shape.clone();
    match &mut shape {
        Shape::Circle { center, .. } => *center += d,
        Shape::Text { at, .. } => *at += d,
        Shape::Path {
            start, segments, ..
        } => {
            *start += d;
            for s in segments {
                match s {
                    Segment::Line(p) => *p += d,
                    Segment::Arc { to, center, .. } => {
                        *to += d;
                        *center += d;
                    }
                }
            }
        }
    }
    shape
}

/// A group's drawing relative to its anchor, as text on the 0.1 um grid:
/// two groups with the same key draw the same thing, moved.
fn key(items: &[Item]) -> String {
    let mut k = String::new();
    let p = |k: &mut String, v: DVec2| {
        k.push_str(&format!("{} {} ", (v.x * 1e4).round(), (v.y * 1e4).round()));
    };
    for i in items {
        k.push_str(&format!("{:?} {:?} ", i.layer, i.ink));
        match &i.shape {
            Shape::Circle { center, radius } => {
                k.push_str(&format!("C{radius} "));
                p(&mut k, *center);
            }
            Shape::Path {
                start,
                segments,
                closed,
            } => {
                k.push_str(&format!("P{closed} "));
                p(&mut k, *start);
                for s in segments {
                    match s {
                        Segment::Line(q) => p(&mut k, *q),
                        Segment::Arc {
                            to,
                            center,
                            clockwise,
                        } => {
                            k.push_str(&format!("A{clockwise} "));
                            p(&mut k, *to);
                            p(&mut k, *center);
                        }
                    }
                }
            }
            text @ Shape::Text { at, .. } => {
                k.push_str(&format!("{text:?} "));
                p(&mut k, *at);
            }
        }
        k.push('|');
    }
    k
}

/// The pages with every group whose drawing occurs more than once (up to
/// a move) replaced by a place of one shared symbol: a Form XObject
/// written once. A 100 x 100 sheet build has 20,000 strips of one or two
/// drawings; each copy then costs one short `cm ... Do` line.
fn share_repeats(pages: &[Page]) -> (Vec<Page>, Vec<Symbol>) {
    let relative = |g: &Group| -> Option<(DVec2, Vec<Item>)> {
        let a = anchor(g).filter(|_| g.symbols.is_empty())?;
        let items = g
            .items
            .iter()
            .map(|i| Item {
                shape: moved(&i.shape, -a),
                ..i.clone()
            })
            .collect();
        Some((a, items))
    };
    let mut count: HashMap<String, usize> = HashMap::new();
    for g in pages.iter().flat_map(|p| &p.groups) {
        if let Some((_, items)) = relative(g) {
            *count.entry(key(&items)).or_default() += 1;
        }
    }
    let mut index: HashMap<String, usize> = HashMap::new();
    let mut symbols: Vec<Symbol> = Vec::new();
    let mut out = Vec::with_capacity(pages.len());
    for page in pages {
        let mut page = page.clone();
        for g in &mut page.groups {
            let Some((at, items)) = relative(g) else {
                continue;
            };
            let k = key(&items);
            if count[&k] < 2 {
                continue;
            }
            let symbol = *index.entry(k).or_insert_with(|| {
                symbols.push(Symbol {
                    uses: Vec::new(),
                    items,
                });
                symbols.len() - 1
            });
            g.symbols = vec![Place { symbol, at }];
            g.items.clear();
        }
        out.push(page);
    }
    (out, symbols)
}

/// All pages in one PDF, with the symbols their groups place: each symbol
/// is one Form XObject, written once however many pages show it.
pub fn write_with_symbols(title: &str, pages: &[Page], symbols: &[Symbol]) -> Vec<u8> {
    let mut pdf = Pdf::new();
    let mut next = 1;
    let mut alloc = || {
        let r = Ref::new(next);
        next += 1;
        r
    };
    let catalog = alloc();
    let tree = alloc();
    let info = alloc();
    let fonts = [alloc(), alloc()];
    let symbol_refs: Vec<Ref> = symbols.iter().map(|_| alloc()).collect();
    let page_refs: Vec<(Ref, Ref)> = pages.iter().map(|_| (alloc(), alloc())).collect();
    let mut hash = fnv1a(title.as_bytes());

    pdf.catalog(catalog).pages(tree);
    pdf.pages(tree)
        .kids(page_refs.iter().map(|p| p.0))
        .count(pages.len() as i32);
    for (id, base) in fonts.iter().zip([&b"Helvetica"[..], b"Helvetica-Bold"]) {
        pdf.type1_font(*id)
            .base_font(Name(base))
            .encoding_predefined(Name(b"WinAnsiEncoding"));
    }

    // Symbols: a symbol's own content is in points with y up from where it
    // is placed; its bounding box is what its items and symbols cover.
    let mut boxes: Vec<Rect> = Vec::with_capacity(symbols.len());
    for (i, symbol) in symbols.iter().enumerate() {
        let mut s = Stream::new(ToPdf { top: 0.0 });
        let mut bounds = Bounds::default();
        for &u in &symbol.uses {
            assert!(u < i, "a symbol places only earlier symbols");
            s.place(&Place {
                symbol: u,
                at: DVec2::ZERO,
            });
            bounds.rect(boxes[u]);
        }
        for item in &symbol.items {
            s.item(item);
            bounds.item(item);
        }
        let rect = bounds.to_rect();
        let data = deflate(&s.content.finish());
        hash = fnv1a(&[hash.to_le_bytes(), fnv1a(&data).to_le_bytes()].concat());
        let mut form = pdf.form_xobject(symbol_refs[i], &data);
        form.filter(Filter::FlateDecode);
        form.bbox(rect);
        resources(form.resources(), s.fonts, &s.symbols, &fonts, &symbol_refs);
        form.finish();
        boxes.push(rect);
    }

    for (page, (page_ref, content_ref)) in pages.iter().zip(&page_refs) {
        let mut s = Stream::new(ToPdf { top: page.height });
        for group in &page.groups {
            for place in &group.symbols {
                s.place(place);
            }
            for item in &group.items {
                s.item(item);
            }
        }
        let data = deflate(&s.content.finish());
        hash = fnv1a(&[hash.to_le_bytes(), fnv1a(&data).to_le_bytes()].concat());
        pdf.stream(*content_ref, &data).filter(Filter::FlateDecode);
        let mut p = pdf.page(*page_ref);
        p.parent(tree)
            .media_box(Rect::new(
                0.0,
                0.0,
                (page.width * PT_PER_MM) as f32,
                (page.height * PT_PER_MM) as f32,
            ))
            .contents(*content_ref);
        resources(p.resources(), s.fonts, &s.symbols, &fonts, &symbol_refs);
        p.finish();
    }

    let creator = format!("karigami {}", env!("CARGO_PKG_VERSION"));
    let subject = pages.first().map(|first| {
        first
            .metadata
            .iter()
            .map(|(k, v)| format!("{k}: {v}"))
            .collect::<Vec<_>>()
            .join("; ")
    });
    let mut doc = pdf.document_info(info);
    doc.title(TextStr(title))
        .creator(TextStr(&creator))
        .producer(TextStr(&creator));
    if let Some(subject) = subject.as_deref().filter(|s| !s.is_empty()) {
        doc.subject(TextStr(subject));
    }
    doc.finish();
    // The same document always gets the same identifier: a hash of what
    // it draws.
    let id = format!("{:016x}{:016x}", hash, fnv1a(&hash.to_le_bytes()));
    pdf.set_file_id((id.as_bytes().to_vec(), id.as_bytes().to_vec()));
    pdf.finish()
}

fn resources(
    mut r: pdf_writer::writers::Resources,
    used_fonts: [bool; 2],
    used_symbols: &[usize],
    fonts: &[Ref; 2],
    symbols: &[Ref],
) {
    if used_fonts.iter().any(|&f| f) {
        let mut dict = r.fonts();
        for (k, name) in [REGULAR, BOLD].into_iter().enumerate() {
            if used_fonts[k] {
                dict.pair(name, fonts[k]);
            }
        }
    }
    if !used_symbols.is_empty() {
        let mut dict = r.x_objects();
        let mut used = used_symbols.to_vec();
        used.sort_unstable();
        used.dedup();
        for i in used {
            dict.pair(Name(symbol_name(i).as_bytes()), symbols[i]);
        }
    }
}

/// The box (points, y up) a symbol's drawing covers, stroke widths and all.
#[derive(Default)]
struct Bounds {
    lo: Option<DVec2>,
    hi: DVec2,
}

impl Bounds {
    fn add(&mut self, p: DVec2, pad: f64) {
        let (lo, hi) = (p - DVec2::splat(pad), p + DVec2::splat(pad));
        match self.lo {
            None => {
                self.lo = Some(lo);
                self.hi = hi;
            }
            Some(l) => {
                self.lo = Some(l.min(lo));
                self.hi = self.hi.max(hi);
            }
        }
    }

    /// Add an item drawn in a symbol (mm, y down from the symbol's origin).
    fn item(&mut self, item: &Item) {
        let to = |p: DVec2| DVec2::new(p.x, -p.y) * PT_PER_MM;
        let pad = item.ink.width * PT_PER_MM + 1.0;
        match &item.shape {
            Shape::Circle { center, radius } => self.add(to(*center), radius * PT_PER_MM + pad),
            Shape::Path {
                start, segments, ..
            } => {
                self.add(to(*start), pad);
                for s in segments {
                    match *s {
                        Segment::Line(p) => self.add(to(p), pad),
                        // The whole circle bounds an arc of it.
                        Segment::Arc {
                            to: end, center, ..
                        } => {
                            let r = (end - center).length() * PT_PER_MM;
                            self.add(to(center), r + pad);
                        }
                    }
                }
            }
            Shape::Text { at, size, text, .. } => {
                let reach = text::width(text, Font::Bold, *size) + size;
                self.add(to(*at), reach * PT_PER_MM + pad);
            }
        }
    }

    fn rect(&mut self, r: Rect) {
        self.add(DVec2::new(r.x1 as f64, r.y1 as f64), 0.0);
        self.add(DVec2::new(r.x2 as f64, r.y2 as f64), 0.0);
    }

    fn to_rect(&self) -> Rect {
        match self.lo {
            None => Rect::new(0.0, 0.0, 0.0, 0.0),
            Some(lo) => Rect::new(
                lo.x.floor() as f32,
                lo.y.floor() as f32,
                self.hi.x.ceil() as f32,
                self.hi.y.ceil() as f32,
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::Layer;

    /// A strip-like group (a hole and a closed outline) anchored at `at`.
    fn strip(id: &str, at: DVec2, hole: f64) -> Group {
        let c = |x: f64, y: f64| at + DVec2::new(x, y);
        Group::new(
            id,
            vec![
                Item::on(
                    Layer::Holes,
                    Shape::Circle {
                        center: c(0.0, 0.0),
                        radius: hole,
                    },
                ),
                Item::on(
                    Layer::Outlines,
                    Shape::polyline(&[c(-5.0, -5.0), c(30.0, -5.0), c(30.0, 5.0)], true),
                ),
            ],
        )
    }

    #[test]
    fn repeated_drawings_become_one_symbol_placed_where_each_copy_was() {
        let page = |groups| Page {
            width: 200.0,
            height: 100.0,
            title: "t".into(),
            metadata: Vec::new(),
            groups,
        };
        let a = DVec2::new(10.0, 20.0);
        let b = DVec2::new(60.123_45, 70.0);
        let pages = vec![
            page(vec![strip("A", a, 1.6), strip("odd", a, 2.0)]),
            page(vec![strip("B", b, 1.6)]),
        ];
        let (shared, symbols) = share_repeats(&pages);
        assert_eq!(symbols.len(), 1, "one drawing repeats");
        // The symbol is the drawing relative to its anchor (the hole).
        assert_eq!(
            symbols[0].items,
            strip("A", DVec2::ZERO, 1.6).items,
            "the symbol draws the strip at the origin"
        );
        let places: Vec<(String, Vec<Place>, usize)> = shared
            .iter()
            .flat_map(|p| &p.groups)
            .map(|g| (g.id.clone(), g.symbols.clone(), g.items.len()))
            .collect();
        assert_eq!(places[0], ("A".into(), vec![Place { symbol: 0, at: a }], 0));
        // A drawing that occurs once stays inline.
        assert_eq!(places[1], ("odd".into(), vec![], 2));
        assert_eq!(places[2], ("B".into(), vec![Place { symbol: 0, at: b }], 0));
        // And the PDF places it twice, with one Form XObject.
        let bytes = write("t", &pages);
        let text = String::from_utf8_lossy(&bytes);
        assert_eq!(text.matches("/Subtype /Form").count(), 1);
    }
}
