//! SVG cut files: root size in mm with a matching viewBox (one user unit is
//! one millimetre), hairline strokes, one pure colour per layer, holes before
//! outlines, true circles, each strip in a `<g>` named by its ID. Compact:
//! `fill="none"` and the hairline width set once on the root and inherited,
//! paths in relative commands (see `path_data`).

use super::number::{fixed, num, units};
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

/// The page as SVG bytes, written straight into one string (no document
/// tree: the sheets of a big job have hundreds of thousands of elements).
pub fn write(page: &Page) -> Vec<u8> {
    let text: String = page
        .metadata
        .iter()
        .map(|(k, v)| format!("{}: {}", printable(k), printable(v)))
        .collect::<Vec<_>>()
        .join("\n");
    let mut out = String::with_capacity(1024 + 400 * page.groups.len());
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = write!(
        out,
        "<svg fill=\"none\" height=\"{h}mm\" stroke-width=\"{hairline}\" viewBox=\"0 0 {w} {h}\" width=\"{w}mm\" xmlns=\"http://www.w3.org/2000/svg\">\n<title>{}</title>\n<metadata>\n{}\n</metadata>",
        escape(&printable(&page.title)),
        escape(&text),
        w = num(page.width),
        h = num(page.height),
        hairline = num(HAIRLINE),
    );
    for g in &page.groups {
        group(&mut out, g);
    }
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
