//! A cut sheet as a page: each strip's holes, outline and engraving moved
//! from the strip's frame to its place on the sheet, and a scale bar.

use super::{Group, Item, Layer, Page, Segment, Shape};
use crate::fabrication::Fabrication;
use crate::font;
use crate::layout::{Layout, Placement};
use crate::parts::{Outline, Strip, TestPiece, test_piece};
use glam::DVec2;

/// Provenance for the files' metadata.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Meta {
    pub(crate) design: String,
    pub(crate) recipe_hash: u64,
}

/// Maps a strip's frame (x along the axis from the start tip, y across,
/// down) onto the sheet: a translation, plus a quarter turn clockwise for
/// strips that run down the sheet. Both keep handedness, so engraved text
/// is never mirrored.
struct Frame {
    origin: DVec2,
    rotated: bool,
}

impl Frame {
    fn of(p: &Placement, outline: &Outline) -> Self {
        let half = outline.width / 2.0;
        let (x, y) = if p.rotated {
            (p.x + half, p.y + outline.grow)
        } else {
            (p.x + outline.grow, p.y + half)
        };
        Frame {
            origin: DVec2::new(x, y),
            rotated: p.rotated,
        }
    }

    fn map(&self, local: DVec2) -> DVec2 {
        self.origin
            + if self.rotated {
                DVec2::new(-local.y, local.x)
            } else {
                local
            }
    }
}

/// The outline as cut: the closed stadium, or its pieces between holding
/// tabs when `tab` > 0 (see `tabs`).
fn outline_items(length: f64, outline: &Outline, frame: &Frame, tab: f64) -> Vec<Item> {
    let r = outline.width / 2.0;
    let pieces = super::tabs::pieces(-outline.grow + r, length + outline.grow - r, r, tab);
    if pieces.is_empty() {
        return vec![Item::on(Layer::Outlines, stadium(length, outline, frame))];
    }
    let m = |p: DVec2| frame.map(p);
    pieces
        .into_iter()
        .map(|(start, segments)| {
            let local = Shape::Path {
                start,
                segments,
                closed: false,
            };
            Item::on(Layer::Outlines, local.moved(&m))
        })
        .collect()
}

/// The closed stadium outline of a strip in its own frame, as cut.
fn stadium(length: f64, outline: &Outline, frame: &Frame) -> Shape {
    let r = outline.width / 2.0;
    let left = -outline.grow + r;
    let right = length + outline.grow - r;
    let m = |x: f64, y: f64| frame.map(DVec2::new(x, y));
    Shape::Path {
        start: m(left, -r),
        segments: vec![
            Segment::Line(m(right, -r)),
            Segment::Arc {
                to: m(right, r),
                center: m(right, 0.0),
                clockwise: true,
            },
            Segment::Line(m(left, r)),
            Segment::Arc {
                to: m(left, -r),
                center: m(left, 0.0),
                clockwise: true,
            },
        ],
        closed: true,
    }
}

fn strip_group(strip: &Strip, placement: &Placement, fab: &Fabrication) -> Group {
    let outline = Outline::of(strip.length, fab);
    let frame = Frame::of(placement, &outline);
    // Holes first: a laser that cuts in file order frees no part before its holes.
    let mut items: Vec<Item> = strip
        .holes
        .iter()
        .map(|&s| {
            Item::on(
                Layer::Holes,
                Shape::Circle {
                    center: frame.map(DVec2::new(s, 0.0)),
                    radius: outline.hole / 2.0,
                },
            )
        })
        .collect();
    items.extend(outline_items(strip.length, &outline, &frame, fab.tabs));
    items.extend(strip.engraving.iter().map(|stroke| {
        let points: Vec<DVec2> = stroke.iter().map(|&p| frame.map(p)).collect();
        Item::on(Layer::Labels, Shape::polyline(&points, false))
    }));
    Group::new(strip.id.clone(), items)
}

/// The test piece: its stepped holes (each offset by the kerf like the
/// strips' holes), its outline and labels, cut holes first like a strip.
fn test_piece_group(piece: &TestPiece, placement: &Placement, fab: &Fabrication) -> Group {
    let outline = Outline::of(piece.length, fab);
    let frame = Frame::of(placement, &outline);
    let shrink = fab.eyelet.hole - outline.hole;
    let mut items: Vec<Item> = piece
        .holes
        .iter()
        .map(|&(x, d)| {
            let center = frame.map(DVec2::new(x, 0.0));
            Item::on(
                Layer::Holes,
                Shape::Circle {
                    center,
                    radius: (d - shrink) / 2.0,
                },
            )
        })
        .collect();
    items.extend(outline_items(piece.length, &outline, &frame, fab.tabs));
    items.extend(piece.engraving.iter().map(|stroke| {
        let points: Vec<DVec2> = stroke.iter().map(|&p| frame.map(p)).collect();
        Item::on(Layer::Labels, Shape::polyline(&points, false))
    }));
    Group::new(TEST_PIECE_ID, items)
}

/// The group id of the test piece on sheet 1.
pub const TEST_PIECE_ID: &str = "test-piece";

/// Text strokes with the baseline starting at `origin` on a y-down page.
fn caption(text: &str, origin: DVec2, height: f64) -> Vec<Item> {
    font::text(text, height)
        .into_iter()
        .map(|stroke| {
            let points: Vec<DVec2> = stroke
                .iter()
                .map(|p| origin + DVec2::new(p.x, -p.y))
                .collect();
            Item::on(Layer::Reference, Shape::polyline(&points, false))
        })
        .collect()
}

/// A scale bar with end ticks and its caption, in the bottom margin.
fn reference(page_w: f64, page_h: f64, margin: f64, title: &str) -> Group {
    let bar = if page_w >= 140.0 {
        100.0
    } else if page_w >= 80.0 {
        50.0
    } else {
        10.0
    };
    let y = page_h - margin / 2.0;
    let tick = (margin * 0.3).clamp(0.3, 2.0);
    let x0 = margin.max(2.0);
    // Never smaller than anything else karigami prints: on a sheet with a
    // margin under 5 mm the caption reaches into the margin's edge or over
    // the parts, on the reference layer, which is never cut.
    let text_h = 2.5;
    let mut items = vec![
        Item::on(
            Layer::Reference,
            Shape::polyline(&[DVec2::new(x0, y), DVec2::new(x0 + bar, y)], false),
        ),
        Item::on(
            Layer::Reference,
            Shape::polyline(&[DVec2::new(x0, y - tick), DVec2::new(x0, y + tick)], false),
        ),
        Item::on(
            Layer::Reference,
            Shape::polyline(
                &[
                    DVec2::new(x0 + bar, y - tick),
                    DVec2::new(x0 + bar, y + tick),
                ],
                false,
            ),
        ),
    ];
    // A long name is cut at the sheet's right margin, not run off it.
    let start = x0 + bar + 3.0;
    let label = font::fitted(&format!("{bar} mm   {title}"), text_h, page_w - x0 - start);
    items.extend(caption(
        &label,
        DVec2::new(start, (y + text_h / 2.0).min(page_h - 0.2)),
        text_h,
    ));
    Group::new("reference", items)
}

/// The page of sheet `index` (0-based) of a layout.
pub(crate) fn sheet_page(
    strips: &[Strip],
    layout: &Layout,
    index: usize,
    fab: &Fabrication,
    meta: &Meta,
) -> Page {
    let spec = &layout.sheet;
    let count = layout.sheets.len();
    let title = format!("{} sheet {:02}/{:02}", meta.design, index + 1, count);
    let mut groups: Vec<Group> = layout.sheets[index]
        .placements
        .iter()
        .map(|p| strip_group(&strips[p.part], p, fab))
        .collect();
    if let (Some(p), Some(piece)) = (layout.sheets[index].test_piece, test_piece(fab)) {
        groups.push(test_piece_group(&piece, &p, fab));
    }
    let caption = format!(
        "{}  {} x {} mm",
        title.to_uppercase(),
        spec.width,
        spec.height
    );
    groups.push(reference(spec.width, spec.height, spec.margin, &caption));
    let kerf = if fab.compensate_kerf {
        format!(
            "{} mm, compensated (outlines offset out and holes in by {} mm)",
            fab.kerf,
            fab.kerf / 2.0
        )
    } else {
        format!(
            "{} mm, not compensated (nominal geometry: set the offset in the laser software)",
            fab.kerf
        )
    };
    let mut page = Page {
        width: spec.width,
        height: spec.height,
        title,
        metadata: vec![
            (
                "generator".into(),
                format!("karigami {}", env!("CARGO_PKG_VERSION")),
            ),
            ("design".into(), meta.design.clone()),
            (
                "recipe-hash".into(),
                format!("fnv1a64:{:016x}", meta.recipe_hash),
            ),
            ("units".into(), "mm".into()),
            ("kerf".into(), kerf),
            (
                "material".into(),
                format!(
                    "{} {} mm, strips {} mm wide",
                    fab.material.name, fab.material.thickness, fab.material.width
                ),
            ),
            (
                "eyelet".into(),
                format!(
                    "{}: hole {} mm, flange {} mm",
                    fab.eyelet.name, fab.eyelet.hole, fab.eyelet.flange
                ),
            ),
            (
                "layers".into(),
                Layer::ALL
                    .iter()
                    .map(|l| format!("{} {} = {}", l.name(), l.hex(), l.operation()))
                    .collect::<Vec<_>>()
                    .join("; "),
            ),
        ],
        laser: fab.laser_settings(),
        groups,
    };
    // A plotter's SVG groups the layers by tool (docs/fabrication.md,
    // Cutting plotters); the laser files' metadata stays as it was.
    if let Some(p) = &fab.plotter {
        page.metadata.push((
            "machine".into(),
            format!(
                "{} on the {} mat: group \"cut\" (holes, outlines) for the blade, group \"draw\" (labels) for a pen",
                p.plotter.describe(),
                p.mat
            ),
        ));
    }
    page
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::{Segment, Shape};

    /// The caption's height on the page (its strokes' extent in y).
    fn caption_height(group: &Group) -> f64 {
        let ys: Vec<f64> = group.items[3..]
            .iter()
            .flat_map(|i| match &i.shape {
                Shape::Path {
                    start, segments, ..
                } => std::iter::once(start.y)
                    .chain(segments.iter().map(|s| match s {
                        Segment::Line(p) => p.y,
                        Segment::Arc { to, .. } => to.y,
                    }))
                    .collect::<Vec<_>>(),
                _ => Vec::new(),
            })
            .collect();
        let max = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let min = ys.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(max <= 400.0, "the caption stays on the page: {max}");
        max - min
    }

    #[test]
    fn the_caption_is_never_under_2_5_mm_even_with_a_thin_margin() {
        for margin in [0.5, 2.0, 5.0, 10.0] {
            let g = reference(600.0, 400.0, margin, "x sheet 01/01");
            // Capitals and digits are 0.7 of the font size or more.
            let h = caption_height(&g);
            assert!(h >= 2.5 * 0.7 - 1e-9, "margin {margin}: caption {h} mm");
            let thin = reference(600.0, 400.0, 10.0, "x sheet 01/01");
            assert!(
                (caption_height(&thin) - h).abs() < 1e-9,
                "one size for all margins"
            );
        }
    }
}
