//! PDF cut files: one page per sheet, the page exactly the sheet's size at
//! true scale (mm x 72 / 25.4 pt), hairline strokes in the layer colours.

use crate::design::fnv1a;
use crate::drawing::{
    Font, Ink, Item, Page, Segment, Shape, arc_to_cubics, circle_to_cubics, text,
};
use glam::DVec2;
use printpdf::{
    BuiltinFont, Color, Line, LinePoint, Mm, Op, PaintMode, PdfDocument, PdfFontHandle, PdfPage,
    PdfSaveOptions, Point, Polygon, PolygonRing, Pt, Rgb, TextItem, WindingOrder,
};

/// Points per millimetre.
pub const PT_PER_MM: f64 = 72.0 / 25.4;
/// Hairline width in mm (0.025 mm = 0.07 pt; print drivers for lasers treat
/// anything at or below 0.001 in as a vector cut).
pub const HAIRLINE_MM: f64 = 0.025;

/// Page coordinates (mm, y down) to PDF points (y up).
struct ToPdf {
    height: f64,
}

impl ToPdf {
    fn point(&self, p: DVec2) -> Point {
        Point {
            x: Pt((p.x * PT_PER_MM) as f32),
            y: Pt(((self.height - p.y) * PT_PER_MM) as f32),
        }
    }

    fn plain(&self, p: DVec2) -> LinePoint {
        LinePoint {
            p: self.point(p),
            bezier: false,
        }
    }

    fn cubics(&self, out: &mut Vec<LinePoint>, pieces: &[[DVec2; 3]]) {
        for [c1, c2, end] in pieces {
            out.push(LinePoint {
                p: self.point(*c1),
                bezier: true,
            });
            out.push(LinePoint {
                p: self.point(*c2),
                bezier: true,
            });
            out.push(self.plain(*end));
        }
    }

    /// A path or circle as a line; None for text.
    fn line(&self, shape: &Shape) -> Option<Line> {
        let mut points = Vec::new();
        let closed = match shape {
            Shape::Text { .. } => return None,
            Shape::Circle { center, radius } => {
                let (start, pieces) = circle_to_cubics(*center, *radius);
                points.push(self.plain(start));
                self.cubics(&mut points, &pieces);
                true
            }
            Shape::Path {
                start,
                segments,
                closed,
            } => {
                points.push(self.plain(*start));
                let mut current = *start;
                for s in segments {
                    match *s {
                        Segment::Line(p) => {
                            points.push(self.plain(p));
                            current = p;
                        }
                        Segment::Arc {
                            to,
                            center,
                            clockwise,
                        } => {
                            self.cubics(
                                &mut points,
                                &arc_to_cubics(current, to, center, clockwise),
                            );
                            current = to;
                        }
                    }
                }
                *closed
            }
        };
        Some(Line {
            points,
            is_closed: closed,
        })
    }
}

fn colour([r, g, b]: [u8; 3]) -> Color {
    Color::Rgb(Rgb {
        r: r as f32 / 255.0,
        g: g as f32 / 255.0,
        b: b as f32 / 255.0,
        icc_profile: None,
    })
}

/// Text the built-in fonts can show (their widths table is ASCII).
fn ascii(s: &str) -> String {
    s.chars()
        .map(|c| if (' '..='~').contains(&c) { c } else { '?' })
        .collect()
}

/// Drawing ops for one page; paint state is set only when it changes.
fn ops(page: &Page) -> Vec<Op> {
    let to = ToPdf {
        height: page.height,
    };
    let mut ops = Vec::new();
    let (mut stroke, mut fill, mut width) = (None, None, None);
    for Item { ink, shape, .. } in page.groups.iter().flat_map(|g| &g.items) {
        let Ink {
            stroke: s,
            fill: f,
            width: w,
        } = *ink;
        if let Some(c) = s.filter(|_| !matches!(shape, Shape::Text { .. })) {
            if stroke != Some(c) {
                ops.push(Op::SetOutlineColor { col: colour(c) });
                stroke = Some(c);
            }
            if width != Some(w) {
                ops.push(Op::SetOutlineThickness {
                    pt: Pt((w * PT_PER_MM) as f32),
                });
                width = Some(w);
            }
        }
        let fill_colour = match shape {
            Shape::Text { .. } => f.or(s),
            _ => f,
        };
        if let Some(c) = fill_colour {
            if fill != Some(c) {
                ops.push(Op::SetFillColor { col: colour(c) });
                fill = Some(c);
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
            let builtin = match font {
                Font::Regular => BuiltinFont::Helvetica,
                Font::Bold => BuiltinFont::HelveticaBold,
            };
            ops.extend([
                Op::StartTextSection,
                Op::SetFont {
                    font: PdfFontHandle::Builtin(builtin),
                    size: Pt((size * PT_PER_MM) as f32),
                },
                Op::SetTextCursor {
                    pos: to.point(start),
                },
                Op::ShowText {
                    items: vec![TextItem::Text(t)],
                },
                Op::EndTextSection,
            ]);
            continue;
        }
        let line = to.line(shape).expect("not text");
        match (f.is_some(), s.is_some()) {
            (true, stroked) => ops.push(Op::DrawPolygon {
                polygon: Polygon {
                    rings: vec![PolygonRing {
                        points: line.points,
                    }],
                    mode: if stroked {
                        PaintMode::FillStroke
                    } else {
                        PaintMode::Fill
                    },
                    winding_order: WindingOrder::NonZero,
                },
            }),
            (false, true) => ops.push(Op::DrawLine { line }),
            (false, false) => {}
        }
    }
    ops
}

/// All pages in one PDF.
pub fn write(title: &str, pages: &[Page]) -> Vec<u8> {
    let mut doc = PdfDocument::new(title);
    if let Some(first) = pages.first() {
        let info = &mut doc.metadata.info;
        info.creator = format!("karigami {}", env!("CARGO_PKG_VERSION"));
        info.producer = info.creator.clone();
        info.subject = first
            .metadata
            .iter()
            .map(|(k, v)| format!("{k}: {v}"))
            .collect::<Vec<_>>()
            .join("; ");
    }
    let pdf_pages = pages
        .iter()
        .map(|p| PdfPage::new(Mm(p.width as f32), Mm(p.height as f32), ops(p)))
        .collect();
    doc.with_pages(pdf_pages);
    let mut warnings = Vec::new();
    let bytes = doc.save(&PdfSaveOptions::default(), &mut warnings);
    stable_id(bytes)
}

/// printpdf fills the trailer's /ID with strings from a process-wide counter,
/// so two identical documents differ. Overwrite both 32-character strings
/// with a hash of the rest of the file: same length, so no offset moves.
pub fn stable_id(mut bytes: Vec<u8>) -> Vec<u8> {
    let Some(at) = find_last(&bytes, b"/ID") else {
        return bytes;
    };
    let mut spans = Vec::new();
    let mut i = at;
    while spans.len() < 2 && i < bytes.len() {
        if bytes[i] == b'(' {
            let end = bytes[i..].iter().position(|&b| b == b')').map(|e| i + e);
            match end {
                Some(e) if e - i - 1 == 32 => {
                    spans.push(i + 1..e);
                    i = e;
                }
                _ => return bytes,
            }
        }
        i += 1;
    }
    if spans.len() != 2 {
        return bytes;
    }
    for s in &spans {
        bytes[s.clone()].fill(b'0');
    }
    let h = fnv1a(&bytes);
    let id = format!("{:016x}{:016x}", h, fnv1a(&h.to_le_bytes()));
    for s in spans {
        bytes[s].copy_from_slice(id.as_bytes());
    }
    bytes
}

fn find_last(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).rposition(|w| w == needle)
}
