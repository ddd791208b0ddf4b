//! SVG cut files: root size in mm with a matching viewBox (one user unit is
//! one millimetre), hairline strokes, one pure colour per layer, holes before
//! outlines, true circles, each strip in a `<g>` named by its ID. Compact:
//! `fill="none"` and the hairline width set once on the root and inherited,
//! paths in relative commands (see `path_data`).
//!
//! A strip drawing placed more than once (up to a translation) is defined
//! once in `<defs>` and each strip's `<g>` places it with a `<use>`: a sheet
//! of 10,000 alike strips holds one drawing. Browsers, librsvg, Inkscape and
//! svgelements expand `<use>`; a laser program that does not would see only
//! the unique strips, which is why each `<use>` stays inside its strip's
//! named group (the trade-off is written in docs/fabrication.md).

use super::number::{fixed, num, units};
use super::repeats;
use crate::drawing::{Group, Item, Page, Segment, Shape, hex};
use std::fmt::Write as _;

/// Stroke width in mm: a hairline that laser software reads as a cut line.
pub(crate) const HAIRLINE: f64 = 0.025;

/// Path data in relative commands (`h`, `v`, `l`, `a`) after an absolute
/// `M`: the offsets are taken between points rounded to the 0.1 um grid, so
/// a reader's running sum lands on each rounded point exactly.
fn path_data(d: &mut String, start: glam::DVec2, segments: &[Segment], closed: bool) {
    let q = |p: glam::DVec2| (units(p.x), units(p.y));
    let _ = write!(d, "M{} {}", num(start.x), num(start.y));
    let mut at = q(start);
    for (from, s) in crate::drawing::walk(start, segments) {
        let to = s.end();
        let next = q(to);
        let (dx, dy) = (fixed(next.0 - at.0), fixed(next.1 - at.1));
        match s {
            Segment::Line(_) if next.1 == at.1 => {
                let _ = write!(d, "h{dx}");
            }
            Segment::Line(_) if next.0 == at.0 => {
                let _ = write!(d, "v{dy}");
            }
            Segment::Line(_) => {
                let _ = write!(d, "l{dx} {dy}");
            }
            Segment::Arc {
                center, clockwise, ..
            } => {
                let sweep = s.sweep(from);
                let r = num((from - center).length());
                let large = if sweep.abs() > std::f64::consts::PI + 1e-9 {
                    1
                } else {
                    0
                };
                // SVG's sweep flag 1 turns towards positive angles: clockwise on a y-down page.
                let _ = write!(d, "a{r} {r} 0 {large} {} {dx} {dy}", clockwise as u8);
            }
        }
        at = next;
    }
    if closed {
        d.push('z');
    }
}

/// One item, painted with its ink (cut layers: a hairline in the layer
/// colour), as one element on a line of its own. Attributes in name order;
/// `fill="none"` and the hairline width are inherited from the root.
fn item(out: &mut String, item: &Item) {
    let class = item.layer.name();
    match &item.shape {
        Shape::Circle { center, .. } => {
            let _ = write!(
                out,
                "\n<circle class=\"{}\" cx=\"{}\" cy=\"{}\"",
                attr(class),
                num(center.x),
                num(center.y)
            );
        }
        Shape::Path {
            start,
            segments,
            closed,
        } => {
            let _ = write!(out, "\n<path class=\"{}\" d=\"", attr(class));
            path_data(out, *start, segments, *closed);
            out.push('"');
        }
        // Text as single strokes: no fonts needed, and a laser scores it in one pass.
        text @ Shape::Text { .. } => {
            let _ = write!(out, "\n<path class=\"{}\" d=\"", attr(class));
            for s in crate::drawing::text::strokes(text) {
                let segments: Vec<Segment> = s[1..].iter().map(|&p| Segment::Line(p)).collect();
                path_data(out, s[0], &segments, false);
            }
            out.push('"');
        }
    }
    let ink = item.ink;
    let is_text = matches!(item.shape, Shape::Text { .. });
    if let (false, Some(fill)) = (is_text, ink.fill) {
        let _ = write!(out, " fill=\"{}\"", hex(fill));
    }
    if let Shape::Circle { radius, .. } = &item.shape {
        let _ = write!(out, " r=\"{}\"", num(*radius));
    }
    match ink.stroke.or(if is_text { ink.fill } else { None }) {
        Some(c) => {
            let width = if is_text {
                ink.width.max(HAIRLINE)
            } else {
                ink.width
            };
            let _ = write!(out, " stroke=\"{}\"", hex(c));
            if num(width) != num(HAIRLINE) {
                let _ = write!(out, " stroke-width=\"{}\"", num(width));
            }
            out.push_str("/>");
        }
        None => out.push_str(" stroke=\"none\"/>"),
    }
}

fn group(out: &mut String, g: &Group) {
    let _ = write!(out, "\n<g id=\"{}\"", attr(&g.id));
    if g.items.is_empty() {
        out.push_str("/>");
        return;
    }
    out.push('>');
    for i in &g.items {
        item(out, i);
    }
    out.push_str("\n</g>");
}

/// A group's items moved to offsets from its anchor `at`, as they are
/// written in `<defs>` (and compared, to find the repeats).
fn relative_items(g: &Group, at: (i64, i64)) -> String {
    let shift = repeats::offset(at);
    let mut out = String::new();
    for i in &g.items {
        let moved = Item {
            shape: i.shape.moved(&shift),
            ..i.clone()
        };
        item(&mut out, &moved);
    }
    out
}

/// The points `relative_items` prints, on the grid, element by element:
/// a circle's layer and centre; a path's layer, whether it is closed (ends
/// in `z`) and the points of each of its subpaths (the start of each `M`
/// and each command's end). Equal texts print equal points: the coarse key
/// `repeats::find_exact` tells most groups apart by without their text.
fn printed_points(g: &Group, at: (i64, i64)) -> Vec<i64> {
    let shift = repeats::offset(at);
    let q = |p: glam::DVec2| [units(p.x), units(p.y)];
    let mut k = Vec::with_capacity(16 * g.items.len());
    for i in &g.items {
        let layer = i.layer as i64;
        match &i.shape {
            Shape::Circle { center, .. } => {
                repeats::push_points(&mut k, &[0, layer], [q(shift(*center))]);
            }
            Shape::Path {
                start,
                segments,
                closed,
            } => {
                let head = [1, layer, *closed as i64, 1, 1 + segments.len() as i64];
                let ends = segments.iter().map(|s| s.end());
                let points = std::iter::once(*start).chain(ends);
                repeats::push_points(&mut k, &head, points.map(|p| q(shift(p))));
            }
            text @ Shape::Text { .. } => {
                let strokes = crate::drawing::text::strokes(&text.moved(&shift));
                k.extend([1, layer, 0, strokes.len() as i64]);
                for stroke in strokes {
                    repeats::push_points(&mut k, &[stroke.len() as i64], stroke.into_iter().map(q));
                }
            }
        }
    }
    k
}

/// The groups, with each drawing used more than once defined in `<defs>`
/// (`part-1`, `part-2`...) and placed by a `<use>` in each strip's group.
/// Returns whether any drawing is shared (the root then declares xlink).
fn groups(out: &mut String, page: &Page, flat: bool) -> bool {
    let at: Vec<Option<(i64, i64)>> = page.groups.iter().map(repeats::anchor).collect();
    // Flat: no group has a key, so none is shared.
    let keys = if flat {
        vec![None; page.groups.len()]
    } else {
        repeats::page_keys(&page.groups, &at)
    };
    let coarse: Vec<Option<Vec<i64>>> = (page.groups.iter().zip(&at))
        .map(|(g, at)| Some(printed_points(g, (*at)?)))
        .collect();
    let (shared, drawn) = repeats::find_exact(&keys, &coarse, |g| {
        relative_items(&page.groups[g], at[g].expect("a keyed group has an anchor"))
    });
    if !shared.first.is_empty() {
        out.push_str("\n<defs>");
        for (b, drawing) in drawn.iter().enumerate() {
            let _ = write!(out, "\n<g id=\"part-{}\">", b + 1);
            out.push_str(drawing);
            out.push_str("\n</g>");
        }
        out.push_str("\n</defs>");
    }
    for (g, (b, at)) in page.groups.iter().zip(shared.of_group.iter().zip(&at)) {
        match (b, at) {
            (Some(b), Some((x, y))) => {
                let _ = write!(
                    out,
                    "\n<g id=\"{}\"><use x=\"{}\" xlink:href=\"#part-{}\" y=\"{}\"/></g>",
                    attr(&g.id),
                    fixed(*x),
                    b + 1,
                    fixed(*y)
                );
            }
            _ => group(out, g),
        }
    }
    !shared.first.is_empty()
}

/// The page as SVG bytes, written straight into one string (no document
/// tree: the sheets of a big job have hundreds of thousands of elements).
pub fn write(page: &Page) -> Vec<u8> {
    write_with(page, false)
}

/// The page as SVG bytes without `<use>`: every group drawn in full.
pub fn write_flat(page: &Page) -> Vec<u8> {
    write_with(page, true)
}

/// The page as a cutting plotter's SVG: every strip drawn in full, the cut
/// layers (holes, outlines) in the group `cut`, the labels in the group
/// `draw` for the pen, and no reference layer (a plotter cuts whatever it
/// is sent; the test piece checks the scale). Design Space and Silhouette
/// Studio both take a group or a colour as one operation.
pub fn write_plotter(page: &Page) -> Vec<u8> {
    let mut body = String::with_capacity(1024 + 100 * page.groups.len());
    body.push_str("\n<g id=\"cut\">");
    for g in &page.groups {
        let cut: Vec<Item> = g
            .items
            .iter()
            .filter(|i| i.layer.is_cut())
            .cloned()
            .collect();
        if !cut.is_empty() {
            group(
                &mut body,
                &Group {
                    items: cut,
                    ..g.clone()
                },
            );
        }
    }
    body.push_str("\n</g>\n<g id=\"draw\">");
    for i in page.groups.iter().flat_map(|g| &g.items) {
        if i.layer == crate::drawing::Layer::Labels {
            item(&mut body, i);
        }
    }
    body.push_str("\n</g>");
    document(page, &body, "")
}

fn write_with(page: &Page, flat: bool) -> Vec<u8> {
    let mut body = String::with_capacity(1024 + 100 * page.groups.len());
    let xlink = if groups(&mut body, page, flat) {
        " xmlns:xlink=\"http://www.w3.org/1999/xlink\""
    } else {
        ""
    };
    document(page, &body, xlink)
}

/// The root, title and metadata around `body`.
fn document(page: &Page, body: &str, xlink: &str) -> Vec<u8> {
    let text: String = page
        .metadata
        .iter()
        .map(|(k, v)| format!("{}: {}", printable(k), printable(v)))
        .collect::<Vec<_>>()
        .join("\n");
    let mut out = String::with_capacity(1024 + body.len());
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = write!(
        out,
        "<svg fill=\"none\" height=\"{h}mm\" stroke-width=\"{hairline}\" viewBox=\"0 0 {w} {h}\" width=\"{w}mm\" xmlns=\"http://www.w3.org/2000/svg\"{xlink}>\n<title>{}</title>\n<metadata>\n{}\n</metadata>",
        escape(&printable(&page.title)),
        escape(&text),
        w = num(page.width),
        h = num(page.height),
        hairline = num(HAIRLINE),
    );
    out.push_str(body);
    out.push_str("\n</svg>\n");
    out.into_bytes()
}

/// Text content with XML's markup characters escaped.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// An attribute value: text escaped and its quotes too.
fn attr(s: &str) -> String {
    escape(s).replace('"', "&quot;").replace('\'', "&apos;")
}

/// Text with control characters replaced: XML 1.0 forbids most of them
/// even escaped. (Recipes cannot hold them; this keeps the file well formed
/// whatever the caller passes.)
fn printable(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { '\u{FFFD}' } else { c })
        .collect()
}
