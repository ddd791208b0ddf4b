//! The drawing model: what a page shows, in millimetres, with y pointing
//! down from the top-left corner. Every writer (SVG, PDF, DXF, PNG) renders
//! this model and nothing else, so no writer re-derives geometry.

pub(crate) mod colours;
pub(crate) mod flow;
pub mod picture;
mod sheet;
pub mod tabs;
pub mod text;
pub(crate) mod winansi;

pub use sheet::TEST_PIECE_ID;
pub(crate) use sheet::{Meta, sheet_page};

use glam::DVec2;
use std::f64::consts::{FRAC_PI_2, PI};

/// What a laser does with a layer. One pure colour per layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Layer {
    /// Inner cuts: eyelet holes (cut first).
    Holes,
    /// Outer cuts: strip outlines.
    Outlines,
    /// Score/engrave: IDs and orientation arrows.
    Labels,
    /// Not for cutting: the scale bar and the sheet caption.
    Reference,
    /// Pictures and text of guides and previews; never on a cut sheet.
    Art,
}

impl Layer {
    /// The layers of a cut sheet (all but `Art`), holes first: the order the
    /// legend and DXF list them.
    pub const ALL: [Layer; 4] = [
        Layer::Holes,
        Layer::Outlines,
        Layer::Labels,
        Layer::Reference,
    ];

    /// The layer's name in files: the SVG class, the DXF layer and the legend.
    pub fn name(self) -> &'static str {
        match self {
            Layer::Holes => "holes",
            Layer::Outlines => "outlines",
            Layer::Labels => "labels",
            Layer::Reference => "reference",
            Layer::Art => "art",
        }
    }

    /// Pure RGB colour of the layer.
    pub(crate) fn rgb(self) -> [u8; 3] {
        match self {
            Layer::Holes => [0, 0, 255],
            Layer::Outlines => [255, 0, 0],
            Layer::Labels => [0, 0, 0],
            Layer::Reference => [0, 255, 0],
            Layer::Art => [0, 0, 0],
        }
    }

    pub(crate) fn hex(self) -> String {
        hex(self.rgb())
    }

    /// AutoCAD colour index with the same meaning (DXF).
    pub(crate) fn aci(self) -> u8 {
        match self {
            Layer::Holes => 5,
            Layer::Outlines => 1,
            Layer::Labels => 7,
            Layer::Reference => 3,
            Layer::Art => 7,
        }
    }

    pub(crate) fn operation(self) -> &'static str {
        match self {
            Layer::Holes => "cut (inner: eyelet holes)",
            Layer::Outlines => "cut (outer: strip outlines)",
            Layer::Labels => "score or engrave (strip IDs and arrows)",
            Layer::Reference => "do not output (100 mm scale bar, caption)",
            Layer::Art => "picture (never cut)",
        }
    }
}

/// One piece of a path after its current point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    /// A straight line to this point (page mm).
    Line(DVec2),
    /// A circular arc to `to` around `center`, turning clockwise as seen on
    /// the page (y down) when `clockwise`.
    Arc {
        /// End point (page mm).
        to: DVec2,
        /// Centre of the circle the arc lies on (page mm).
        center: DVec2,
        /// Turning clockwise on the page (y down); counter-clockwise otherwise.
        clockwise: bool,
    },
}

impl Segment {
    /// The point the segment ends on (page mm).
    pub(crate) fn end(self) -> DVec2 {
        match self {
            Segment::Line(p) | Segment::Arc { to: p, .. } => p,
        }
    }

    /// The signed angle the segment turns through from `from` (rad,
    /// positive clockwise on the page); 0 for a line.
    pub(crate) fn sweep(self, from: DVec2) -> f64 {
        match self {
            Segment::Line(_) => 0.0,
            Segment::Arc {
                to,
                center,
                clockwise,
            } => arc_angles(from, to, center, clockwise).1,
        }
    }
}

/// `#RRGGBB` of an RGB colour (SVG and the viewer).
pub(crate) fn hex([r, g, b]: [u8; 3]) -> String {
    format!("#{r:02X}{g:02X}{b:02X}")
}

/// A path's segments in order, each with the point it starts from.
pub(crate) fn walk(
    start: DVec2,
    segments: &[Segment],
) -> impl Iterator<Item = (DVec2, Segment)> + '_ {
    segments.iter().scan(start, |current, &s| {
        let from = std::mem::replace(current, s.end());
        Some((from, s))
    })
}

/// The point a path ends on: its last segment's end, or `start` if it has none.
pub(crate) fn path_end(start: DVec2, segments: &[Segment]) -> DVec2 {
    segments.last().map_or(start, |s| s.end())
}

/// Built-in PDF fonts (no font files); other writers draw text with the
/// single-stroke font.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Font {
    /// Helvetica in PDF.
    Regular,
    /// Helvetica-Bold in PDF.
    Bold,
}

/// How a line of text sits on its anchor point `at`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Align {
    /// The text starts at `at`.
    Left,
    /// The text is centred on `at`.
    Center,
    /// The text ends at `at`.
    Right,
}

/// What an item draws, in page mm.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A full circle, e.g. an eyelet hole.
    Circle {
        /// Centre (page mm).
        center: DVec2,
        /// Radius (mm).
        radius: f64,
    },
    /// A path of lines and arcs, e.g. a strip outline.
    Path {
        /// First point (page mm).
        start: DVec2,
        /// The pieces after `start`, in order.
        segments: Vec<Segment>,
        /// A line joins the last point back to `start`.
        closed: bool,
    },
    /// A line of text; `at` is on the baseline, `size` the font size in mm.
    Text {
        /// Anchor point on the baseline (page mm), placed per `align`.
        at: DVec2,
        /// Font size (mm).
        size: f64,
        /// The characters of the line.
        text: String,
        /// Regular or bold.
        font: Font,
        /// Where `at` lies along the line.
        align: Align,
    },
}

/// How an item is painted: stroke colour and width (mm), optional fill.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ink {
    /// Stroke colour (RGB); None strokes nothing.
    pub stroke: Option<[u8; 3]>,
    pub(crate) width: f64,
    pub(crate) fill: Option<[u8; 3]>,
}

impl Ink {
    /// A hairline in a layer's colour: how cut sheets are drawn.
    pub(crate) const HAIRLINE: f64 = 0.025;

    pub(crate) fn line(colour: [u8; 3], width: f64) -> Self {
        Self {
            stroke: Some(colour),
            width,
            fill: None,
        }
    }

    pub(crate) fn fill(colour: [u8; 3]) -> Self {
        Self {
            stroke: None,
            width: 0.0,
            fill: Some(colour),
        }
    }

    pub(crate) fn of(layer: Layer) -> Self {
        Self::line(layer.rgb(), Self::HAIRLINE)
    }
}

impl Shape {
    /// Length of the shape's path (mm): what a laser travels cutting it.
    pub fn length(&self) -> f64 {
        match self {
            Shape::Text { .. } => 0.0,
            Shape::Circle { radius, .. } => 2.0 * PI * radius,
            Shape::Path {
                start,
                segments,
                closed,
            } => {
                let mut total = 0.0;
                for (from, s) in walk(*start, segments) {
                    total += match s {
                        Segment::Line(p) => from.distance(p),
                        Segment::Arc { center, .. } => s.sweep(from).abs() * from.distance(center),
                    };
                }
                if *closed {
                    total += path_end(*start, segments).distance(*start);
                }
                total
            }
        }
    }

    /// The shape moved by `f`, a motion that keeps lengths and handedness
    /// (a translation or a turn: radii, sizes and arc directions stay):
    /// each point, centre and anchor mapped.
    pub(crate) fn moved(&self, f: &dyn Fn(DVec2) -> DVec2) -> Shape {
        match self {
            Shape::Circle { center, radius } => Shape::Circle {
                center: f(*center),
                radius: *radius,
            },
            Shape::Path {
                start,
                segments,
                closed,
            } => Shape::Path {
                start: f(*start),
                segments: segments
                    .iter()
                    .map(|s| match *s {
                        Segment::Line(p) => Segment::Line(f(p)),
                        Segment::Arc {
                            to,
                            center,
                            clockwise,
                        } => Segment::Arc {
                            to: f(to),
                            center: f(center),
                            clockwise,
                        },
                    })
                    .collect(),
                closed: *closed,
            },
            Shape::Text { at, .. } => {
                let mut text = self.clone();
                if let Shape::Text { at: moved, .. } = &mut text {
                    *moved = f(*at);
                }
                text
            }
        }
    }

    /// An open or closed polyline.
    pub(crate) fn polyline(points: &[DVec2], closed: bool) -> Shape {
        Shape::Path {
            start: points[0],
            segments: points[1..].iter().map(|&p| Segment::Line(p)).collect(),
            closed,
        }
    }
}

/// One shape on a layer, with the ink that paints it.
#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    /// The layer: what a laser does with the shape.
    pub layer: Layer,
    /// How the shape is painted.
    pub ink: Ink,
    /// What is drawn (page mm).
    pub shape: Shape,
}

impl Item {
    /// An item painted in its layer's own colour, as a hairline.
    pub(crate) fn on(layer: Layer, shape: Shape) -> Self {
        Self {
            layer,
            ink: Ink::of(layer),
            shape,
        }
    }

    pub(crate) fn art(ink: Ink, shape: Shape) -> Self {
        Self {
            layer: Layer::Art,
            ink,
            shape,
        }
    }
}

/// Items that belong together (one strip), named by `id`.
#[derive(Clone, Debug, PartialEq)]
pub struct Group {
    /// The group's name, written as the SVG group id: the strip ID on cut
    /// sheets, `reference` for the scale bar and caption.
    pub id: String,
    /// Shared drawings placed before the items (guide pages only: the PDF
    /// writer places them; cut sheets and pictures have none).
    pub(crate) symbols: Vec<Place>,
    /// The drawn items, in painting order.
    pub items: Vec<Item>,
}

impl Group {
    pub(crate) fn new(id: impl Into<String>, items: Vec<Item>) -> Self {
        Self {
            id: id.into(),
            symbols: Vec::new(),
            items,
        }
    }
}

/// A drawing shared by several pages of one document (a row of the
/// lattice on every later step page of the guide): written once and placed
/// by reference, so that the document grows with the drawing, not with the
/// pages times the drawing. Coordinates are page mm relative to the point
/// where it is placed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Symbol {
    /// Symbols drawn first, by index; each earlier in the list than this one.
    pub(crate) uses: Vec<usize>,
    /// The drawing's items, relative to the point where it is placed (page mm).
    pub items: Vec<Item>,
}

/// Symbol `symbol` (an index into the document's symbols) drawn with its
/// origin at `at` on the page.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Place {
    pub(crate) symbol: usize,
    pub(crate) at: DVec2,
}

impl Layer {
    /// Layers the laser cuts through.
    pub fn is_cut(self) -> bool {
        matches!(self, Layer::Holes | Layer::Outlines)
    }
}

/// One page of a document, in mm with y down from the top-left corner: a cut
/// sheet, a guide page or a picture.
#[derive(Clone, Debug, PartialEq)]
pub struct Page {
    /// Page width (mm).
    pub width: f64,
    /// Page height (mm).
    pub height: f64,
    pub(crate) title: String,
    /// Key-value provenance written into each file's metadata.
    pub(crate) metadata: Vec<(String, String)>,
    /// A cut sheet's starting laser settings, for the files that carry them
    /// (LightBurn's layers); None for other pages, and for stock that has
    /// none on this machine.
    pub(crate) laser: Option<crate::fabrication::MachineSettings>,
    /// Everything drawn, group by group in painting order.
    pub groups: Vec<Group>,
}

impl Page {
    /// Total length of the cut layers on this page (mm).
    pub(crate) fn cut_length(&self) -> f64 {
        self.groups
            .iter()
            .flat_map(|g| &g.items)
            .filter(|i| i.layer.is_cut())
            .map(|i| i.shape.length())
            .sum()
    }
}

/// Start angle and signed sweep (radians, y-down page angles: positive is
/// clockwise on the page) of an arc from `from`.
pub(crate) fn arc_angles(from: DVec2, to: DVec2, center: DVec2, clockwise: bool) -> (f64, f64) {
    let a0 = (from - center).to_angle();
    let a1 = (to - center).to_angle();
    let mut sweep = a1 - a0;
    if clockwise {
        while sweep <= 0.0 {
            sweep += 2.0 * PI;
        }
    } else {
        while sweep >= 0.0 {
            sweep -= 2.0 * PI;
        }
    }
    (a0, sweep)
}

/// Cubic Bezier pieces `[c1, c2, end]` approximating an arc, each at most a
/// quarter turn (radial error below 3e-4 of the radius).
pub(crate) fn arc_to_cubics(
    from: DVec2,
    to: DVec2,
    center: DVec2,
    clockwise: bool,
) -> Vec<[DVec2; 3]> {
    let (a0, sweep) = arc_angles(from, to, center, clockwise);
    let radius = (from - center).length();
    let n = (sweep.abs() / FRAC_PI_2 - 1e-9).ceil().max(1.0) as usize;
    let step = sweep / n as f64;
    let k = 4.0 / 3.0 * (step / 4.0).tan();
    (0..n)
        .map(|i| {
            let (s, e) = (a0 + i as f64 * step, a0 + (i + 1) as f64 * step);
            let p0 = center + radius * DVec2::from_angle(s);
            let p3 = if i + 1 == n {
                to
            } else {
                center + radius * DVec2::from_angle(e)
            };
            let t0 = DVec2::new(-s.sin(), s.cos());
            let t3 = DVec2::new(-e.sin(), e.cos());
            [p0 + k * radius * t0, p3 - k * radius * t3, p3]
        })
        .collect()
}

/// A full circle as four quarter-turn cubics from its rightmost point.
pub(crate) fn circle_to_cubics(center: DVec2, radius: f64) -> (DVec2, Vec<[DVec2; 3]>) {
    let start = center + DVec2::new(radius, 0.0);
    let half = center - DVec2::new(radius, 0.0);
    let mut pieces = arc_to_cubics(start, half, center, true);
    pieces.extend(arc_to_cubics(half, start, center, true));
    (start, pieces)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_arcs_stay_on_the_circle() {
        let c = DVec2::new(3.0, 4.0);
        let (start, pieces) = circle_to_cubics(c, 2.0);
        assert_eq!(pieces.len(), 4);
        let mut p0 = start;
        for [c1, c2, p3] in pieces {
            for t in [0.25, 0.5, 0.75] {
                let u = 1.0 - t;
                let p =
                    u * u * u * p0 + 3.0 * u * u * t * c1 + 3.0 * u * t * t * c2 + t * t * t * p3;
                assert!(((p - c).length() - 2.0).abs() < 2.0 * 3e-4, "{p}");
            }
            p0 = p3;
        }
        assert!((p0 - start).length() < 1e-12);
    }

    #[test]
    fn arc_direction_follows_the_page() {
        // From the top of a circle to its bottom, clockwise on a y-down page
        // passes through the right-hand side.
        let c = DVec2::ZERO;
        let pieces = arc_to_cubics(DVec2::new(0.0, -1.0), DVec2::new(0.0, 1.0), c, true);
        assert!(pieces[0][2].x > 0.9, "{pieces:?}");
        let (_, sweep) = arc_angles(DVec2::new(0.0, -1.0), DVec2::new(0.0, 1.0), c, false);
        assert!((sweep + PI).abs() < 1e-12);
    }
}
