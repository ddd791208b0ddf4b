//! PDF cut files: one page per sheet, the page exactly the sheet's size at
//! true scale (mm x 72 / 25.4 pt), hairline strokes in the layer colours.

use crate::design::fnv1a;
use crate::drawing::{Item, Page, Segment, Shape, arc_to_cubics, circle_to_cubics};
use glam::DVec2;
use printpdf::{
    Color, Line, LinePoint, Mm, Op, PdfDocument, PdfPage, PdfSaveOptions, Point, Pt, Rgb,
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

    fn line(&self, shape: &Shape) -> Line {
        let mut points = Vec::new();
        let closed = match shape {
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
        Line {
            points,
            is_closed: closed,
        }
    }
}

fn ops(page: &Page) -> Vec<Op> {
    let to = ToPdf {
        height: page.height,
    };
    let mut ops = vec![Op::SetOutlineThickness {
        pt: Pt((HAIRLINE_MM * PT_PER_MM) as f32),
    }];
    let mut colour = None;
    for Item { layer, shape } in page.groups.iter().flat_map(|g| &g.items) {
        if colour != Some(*layer) {
            let [r, g, b] = layer.rgb();
            ops.push(Op::SetOutlineColor {
                col: Color::Rgb(Rgb {
                    r: r as f32 / 255.0,
                    g: g as f32 / 255.0,
                    b: b as f32 / 255.0,
                    icc_profile: None,
                }),
            });
            colour = Some(*layer);
        }
        ops.push(Op::DrawLine {
            line: to.line(shape),
        });
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
