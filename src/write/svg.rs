//! SVG cut files: root size in mm with a matching viewBox (one user unit is
//! one millimetre), hairline strokes, one pure colour per layer, holes before
//! outlines, true circles, each strip in a `<g>` named by its ID.

use super::number::num;
use crate::drawing::{Group, Item, Page, Segment, Shape};
use std::fmt::Write as _;

/// Stroke width in mm: a hairline that laser software reads as a cut line.
pub(crate) const HAIRLINE: f64 = 0.025;

fn path_data(start: glam::DVec2, segments: &[Segment], closed: bool) -> String {
    let mut d = format!("M{} {}", num(start.x), num(start.y));
    let mut current = start;
    for s in segments {
        match *s {
            Segment::Line(p) => d.push_str(&format!(" L{} {}", num(p.x), num(p.y))),
            Segment::Arc {
                to,
                center,
                clockwise,
            } => {
                let (_, sweep) = crate::drawing::arc_angles(current, to, center, clockwise);
                let r = num((current - center).length());
                let large = if sweep.abs() > std::f64::consts::PI + 1e-9 {
                    1
                } else {
                    0
                };
                // SVG's sweep flag 1 turns towards positive angles: clockwise on a y-down page.
                d.push_str(&format!(
                    " A{r} {r} 0 {large} {} {} {}",
                    clockwise as u8,
                    num(to.x),
                    num(to.y)
                ));
            }
        }
        current = match *s {
            Segment::Line(p) | Segment::Arc { to: p, .. } => p,
        };
    }
    if closed {
        d.push_str(" Z");
    }
    d
}

fn hex([r, g, b]: [u8; 3]) -> String {
    format!("#{r:02X}{g:02X}{b:02X}")
}

/// One item, painted with its ink (cut layers: a hairline in the layer
/// colour), as one element on a line of its own. Attributes in name order.
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
            let _ = write!(
                out,
                "\n<path class=\"{}\" d=\"{}\"",
                attr(class),
                path_data(*start, segments, *closed)
            );
        }
        // Text as single strokes: no fonts needed, and a laser scores it in one pass.
        text @ Shape::Text { .. } => {
            let d: Vec<String> = crate::drawing::text::strokes(text)
                .iter()
                .map(|s| {
                    let segments: Vec<Segment> = s[1..].iter().map(|&p| Segment::Line(p)).collect();
                    path_data(s[0], &segments, false)
                })
                .collect();
            let _ = write!(
                out,
                "\n<path class=\"{}\" d=\"{}\"",
                attr(class),
                d.join(" ")
            );
        }
    }
    let ink = item.ink;
    let is_text = matches!(item.shape, Shape::Text { .. });
    let fill = if is_text {
        "none".into()
    } else {
        ink.fill.map_or("none".into(), hex)
    };
    let _ = write!(out, " fill=\"{fill}\"");
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
            let _ = write!(
                out,
                " stroke=\"{}\" stroke-width=\"{}\"/>",
                hex(c),
                num(width)
            );
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
        "<svg height=\"{h}mm\" viewBox=\"0 0 {w} {h}\" width=\"{w}mm\" xmlns=\"http://www.w3.org/2000/svg\">\n<title>{}</title>\n<metadata>\n{}\n</metadata>",
        escape(&printable(&page.title)),
        escape(&text),
        w = num(page.width),
        h = num(page.height),
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
