//! SVG cut files: root size in mm with a matching viewBox (one user unit is
//! one millimetre), hairline strokes, one pure colour per layer, holes before
//! outlines, true circles, each strip in a `<g>` named by its ID.

use super::number::num;
use crate::drawing::{Group, Item, Page, Segment, Shape};
use svg::Document;
use svg::node::element::{Circle, Element, Group as SvgGroup, Path, Title};
use svg::node::{Node, Text};

/// Stroke width in mm: a hairline that laser software reads as a cut line.
pub const HAIRLINE: f64 = 0.025;

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

/// One item, painted with its ink (cut layers: a hairline in the layer colour).
fn item(item: &Item) -> Element {
    let mut el: Element = match &item.shape {
        Shape::Circle { center, radius } => Circle::new()
            .set("cx", num(center.x))
            .set("cy", num(center.y))
            .set("r", num(*radius))
            .into(),
        Shape::Path {
            start,
            segments,
            closed,
        } => Path::new()
            .set("d", path_data(*start, segments, *closed))
            .into(),
        // Text as single strokes: no fonts needed, and a laser scores it in one pass.
        text @ Shape::Text { .. } => {
            let d: Vec<String> = crate::drawing::text::strokes(text)
                .iter()
                .map(|s| {
                    let segments: Vec<Segment> = s[1..].iter().map(|&p| Segment::Line(p)).collect();
                    path_data(s[0], &segments, false)
                })
                .collect();
            Path::new().set("d", d.join(" ")).into()
        }
    };
    let ink = item.ink;
    let is_text = matches!(item.shape, Shape::Text { .. });
    el.assign(
        "fill",
        if is_text {
            "none".into()
        } else {
            ink.fill.map_or("none".into(), hex)
        },
    );
    match ink.stroke.or(if is_text { ink.fill } else { None }) {
        Some(c) => {
            el.assign("stroke", hex(c));
            el.assign(
                "stroke-width",
                num(if is_text {
                    ink.width.max(HAIRLINE)
                } else {
                    ink.width
                }),
            );
        }
        None => el.assign("stroke", "none"),
    }
    el.assign("class", item.layer.name());
    el
}

fn group(g: &Group) -> SvgGroup {
    g.items
        .iter()
        .fold(SvgGroup::new().set("id", g.id.as_str()), |acc, i| {
            acc.add(item(i))
        })
}

/// The page as SVG bytes.
pub fn write(page: &Page) -> Vec<u8> {
    let mut metadata = Element::new("metadata");
    let text: String = page
        .metadata
        .iter()
        .map(|(k, v)| format!("{}: {}", printable(k), printable(v)))
        .collect::<Vec<_>>()
        .join("\n");
    metadata.append(Text::new(format!("\n{text}\n")));
    let doc = page.groups.iter().fold(
        Document::new()
            .set("width", format!("{}mm", num(page.width)))
            .set("height", format!("{}mm", num(page.height)))
            .set(
                "viewBox",
                format!("0 0 {} {}", num(page.width), num(page.height)),
            )
            .add(Title::new(printable(&page.title)))
            .add(metadata),
        |doc, g| doc.add(group(g)),
    );
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    out.push_str(&doc.to_string());
    out.push('\n');
    out.into_bytes()
}

/// Text with control characters replaced: XML 1.0 forbids most of them
/// even escaped. (Recipes cannot hold them; this keeps the file well formed
/// whatever the caller passes.)
fn printable(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { '\u{FFFD}' } else { c })
        .collect()
}
