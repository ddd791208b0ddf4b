//! PDF files: cut sheets (one page per sheet, the page exactly the sheet's
//! size at true scale, mm x 72 / 25.4 pt, hairline strokes in the layer
//! colours) and the assembly guide, whose shared drawings are written once
//! as Form XObjects and placed by reference on every page that shows them.
//!
//! Written with `pdf-writer`: it streams objects straight into the file's
//! bytes and has Form XObjects, where printpdf built a lopdf document of
//! every operation first (31.6 s of a 37.7 s 100 x 100 build) and named
//! its resources from a process-wide counter.
//!
//! The document (objects, resources, the file identifier) is written here;
//! each page's and symbol's drawing operators in `stream.rs`; drawings that
//! repeat are found and made symbols in `repeats.rs`.

mod repeats;
mod stream;

use crate::drawing::{Font, Item, Page, Place, Segment, Shape, Symbol, text};
use crate::hash::fnv1a;
use glam::DVec2;
use pdf_writer::{Filter, Finish, Name, Pdf, Rect, Ref, TextStr};
use repeats::share_repeats;
use stream::{BOLD, CUT_GRID, Dots, PRINT_GRID, REGULAR, Stream, ToPdf, dot_name, symbol_name};

/// Points per millimetre.
pub(crate) const PT_PER_MM: f64 = 72.0 / 25.4;

/// Deflate level of content streams. Measured with miniz_oxide on the
/// 15.7 MB of content of a 100 x 100 build's guide (best of 3 runs):
/// level 1 3.29 MB in 0.12 s, 2 2.63 MB in 0.22 s, 3 2.50 MB in 0.23 s,
/// 6 2.37 MB in 0.63 s. Level 3 takes most of what deflate can save for
/// a fifth of level 6's extra time.
const DEFLATE_LEVEL: u8 = 3;

/// Deflate a content stream.
fn deflate(bytes: &[u8]) -> Vec<u8> {
    miniz_oxide::deflate::compress_to_vec_zlib(bytes, DEFLATE_LEVEL)
}

/// All pages in one PDF. A drawing that repeats (the strips of one part
/// type on the cut sheets) is written once, as a symbol, and each copy
/// places it: see `share_repeats`.
pub(crate) fn write(title: &str, pages: &[Page]) -> Vec<u8> {
    let (pages, symbols) = share_repeats(pages);
    document(title, &pages, &symbols, CUT_GRID, None)
}

/// The assembly guide: all pages in one PDF, with the symbols their groups
/// place, each one Form XObject written once however many pages show it.
/// Printed on paper, it is written on the coarser `PRINT_GRID`, and its
/// circles (the pivot dots) are shared forms too.
pub(crate) fn write_with_symbols(title: &str, pages: &[Page], symbols: &[Symbol]) -> Vec<u8> {
    let mut dots = Dots::default();
    document(title, pages, symbols, PRINT_GRID, Some(&mut dots))
}

fn document(
    title: &str,
    pages: &[Page],
    symbols: &[Symbol],
    grid: f64,
    mut dots: Option<&mut Dots>,
) -> Vec<u8> {
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
    // Dots are found while the streams are written: theirs are the
    // numbers after every other object's.
    let first_dot = alloc().get();
    let dot_refs = |k: usize| Ref::new(first_dot + k as i32);
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
        let mut s = Stream::new(ToPdf { top: 0.0, grid }, dots.as_deref_mut());
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
        resources(
            form.resources(),
            (s.fonts, &s.symbols, &s.dots),
            &fonts,
            &symbol_refs,
            &dot_refs,
        );
        form.finish();
        boxes.push(rect);
    }

    for (page, (page_ref, content_ref)) in pages.iter().zip(&page_refs) {
        let mut s = Stream::new(
            ToPdf {
                top: page.height,
                grid,
            },
            dots.as_deref_mut(),
        );
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
        resources(
            p.resources(),
            (s.fonts, &s.symbols, &s.dots),
            &fonts,
            &symbol_refs,
            &dot_refs,
        );
        p.finish();
    }

    for (k, (dot, width)) in dots
        .map(|d| d.list.clone())
        .unwrap_or_default()
        .into_iter()
        .enumerate()
    {
        let (content, half) = dot.content(grid, width);
        let data = deflate(&content);
        hash = fnv1a(&[hash.to_le_bytes(), fnv1a(&data).to_le_bytes()].concat());
        let half = half.ceil() as f32;
        let mut form = pdf.form_xobject(dot_refs(k), &data);
        form.filter(Filter::FlateDecode);
        form.bbox(Rect::new(-half, -half, half, half));
        form.finish();
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
    (used_fonts, used_symbols, used_dots): ([bool; 2], &[usize], &[usize]),
    fonts: &[Ref; 2],
    symbols: &[Ref],
    dots: &dyn Fn(usize) -> Ref,
) {
    if used_fonts.iter().any(|&f| f) {
        let mut dict = r.fonts();
        for (k, name) in [REGULAR, BOLD].into_iter().enumerate() {
            if used_fonts[k] {
                dict.pair(name, fonts[k]);
            }
        }
    }
    if !used_symbols.is_empty() || !used_dots.is_empty() {
        let mut dict = r.x_objects();
        let used = |list: &[usize]| {
            let mut used = list.to_vec();
            used.sort_unstable();
            used.dedup();
            used
        };
        for i in used(used_symbols) {
            dict.pair(Name(symbol_name(i).as_bytes()), symbols[i]);
        }
        for i in used(used_dots) {
            dict.pair(Name(dot_name(i).as_bytes()), dots(i));
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
    use crate::drawing::{Group, Item, Layer};

    /// A page of `n` dots of one radius, and one of another.
    fn dots(n: usize) -> Vec<Page> {
        let dot = |x: f64, r: f64| {
            Item::on(
                Layer::Art,
                Shape::Circle {
                    center: DVec2::new(x, 50.0),
                    radius: r,
                },
            )
        };
        let mut items: Vec<Item> = (0..n).map(|k| dot(10.0 + 5.0 * k as f64, 1.0)).collect();
        items.push(dot(90.0, 2.0));
        vec![Page {
            width: 100.0,
            height: 100.0,
            title: "t".into(),
            metadata: Vec::new(),
            laser: None,
            groups: vec![Group::new("dots", items)],
        }]
    }

    #[test]
    fn the_guides_circles_are_one_form_a_radius_placed_at_each_centre() {
        let bytes = write_with_symbols("t", &dots(5), &[]);
        let text = String::from_utf8_lossy(&bytes);
        // Two radii: two forms, each drawn once; six places.
        assert_eq!(text.matches("/Subtype /Form").count(), 2);
        let page = pdf_content(&bytes, 0);
        assert_eq!(page.matches("/D0 Do").count(), 5);
        assert_eq!(page.matches("/D1 Do").count(), 1);
        assert!(page.contains("1 0 0 1 28.3 141.7 cm"), "{page}");
        assert!(!page.contains(" c\n"), "no circle drawn inline");
        // Cut sheets draw their circles inline, on the finer grid.
        let cut = pdf_content(&write("t", &dots(1)), 0);
        assert_eq!(cut.matches(" c\n").count(), 8, "{cut}");
    }

    /// The inflated stream number `k` of a PDF, in file order.
    fn pdf_content(pdf: &[u8], k: usize) -> String {
        let starts: Vec<usize> = (0..pdf.len())
            .filter(|&i| pdf[i..].starts_with(b">>\nstream\n"))
            .map(|i| i + 10)
            .collect();
        let data = &pdf[starts[k]..];
        let end = (0..data.len())
            .find(|&i| data[i..].starts_with(b"\nendstream"))
            .expect("the stream's end");
        let inflated =
            miniz_oxide::inflate::decompress_to_vec_zlib(&data[..end]).expect("a deflated stream");
        String::from_utf8(inflated).unwrap()
    }
}
