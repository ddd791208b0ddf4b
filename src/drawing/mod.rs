//! The drawing model: what a page shows, in millimetres, with y pointing
//! down from the top-left corner. Every writer (SVG, PDF, DXF, PNG) renders
//! this model and nothing else, so no writer re-derives geometry.

pub mod colours;
pub mod flow;
pub mod picture;
mod sheet;
pub mod tabs;
pub mod text;

pub use sheet::{Meta, TEST_PIECE_ID, sheet_page};

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
    pub const ALL: [Layer; 4] = [
        Layer::Holes,
        Layer::Outlines,
        Layer::Labels,
        Layer::Reference,
    ];

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
    pub fn rgb(self) -> [u8; 3] {
        match self {
            Layer::Holes => [0, 0, 255],
            Layer::Outlines => [255, 0, 0],
            Layer::Labels => [0, 0, 0],
            Layer::Reference => [0, 255, 0],
            Layer::Art => [0, 0, 0],
        }
    }

    pub fn hex(self) -> String {
        let [r, g, b] = self.rgb();
        format!("#{r:02X}{g:02X}{b:02X}")
    }

    /// AutoCAD colour index with the same meaning (DXF).
    pub fn aci(self) -> u8 {
        match self {
            Layer::Holes => 5,
            Layer::Outlines => 1,
            Layer::Labels => 7,
            Layer::Reference => 3,
            Layer::Art => 7,
        }
    }

    pub fn operation(self) -> &'static str {
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
    Line(DVec2),
    /// A circular arc to `to` around `center`, turning clockwise as seen on
    /// the page (y down) when `clockwise`.
    Arc {
        to: DVec2,
        center: DVec2,
        clockwise: bool,
    },
}

/// Built-in PDF fonts (no font files); other writers draw text with the
/// single-stroke font.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Font {
    Regular,
    Bold,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Align {
    Left,
    Center,
    Right,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Circle {
        center: DVec2,
        radius: f64,
    },
    Path {
        start: DVec2,
        segments: Vec<Segment>,
        closed: bool,
    },
    /// A line of text; `at` is on the baseline, `size` the font size in mm.
    Text {
        at: DVec2,
        size: f64,
        text: String,
        font: Font,
        align: Align,
    },
}

/// How an item is painted: stroke colour and width (mm), optional fill.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ink {
    pub stroke: Option<[u8; 3]>,
    pub width: f64,
    pub fill: Option<[u8; 3]>,
}

impl Ink {
    /// A hairline in a layer's colour: how cut sheets are drawn.
    pub const HAIRLINE: f64 = 0.025;

    pub fn line(colour: [u8; 3], width: f64) -> Self {
        Self {
            stroke: Some(colour),
            width,
            fill: None,
        }
    }

    pub fn fill(colour: [u8; 3]) -> Self {
        Self {
            stroke: None,
            width: 0.0,
            fill: Some(colour),
        }
    }

    pub fn of(layer: Layer) -> Self {
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
                let mut current = *start;
                let mut total = 0.0;
                for s in segments {
                    let to = match *s {
                        Segment::Line(p) => {
                            total += current.distance(p);
                            p
                        }
                        Segment::Arc {
                            to,
                            center,
                            clockwise,
                        } => {
                            let (_, sweep) = arc_angles(current, to, center, clockwise);
                            total += sweep.abs() * current.distance(center);
                            to
                        }
                    };
                    current = to;
                }
                if *closed {
                    total += current.distance(*start);
                }
                total
            }
        }
    }

    /// An open or closed polyline.
    pub fn polyline(points: &[DVec2], closed: bool) -> Shape {
        Shape::Path {
            start: points[0],
            segments: points[1..].iter().map(|&p| Segment::Line(p)).collect(),
            closed,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Item {
    pub layer: Layer,
    pub ink: Ink,
    pub shape: Shape,
}

impl Item {
    /// An item painted in its layer's own colour, as a hairline.
    pub fn on(layer: Layer, shape: Shape) -> Self {
        Self {
            layer,
            ink: Ink::of(layer),
            shape,
        }
    }

    pub fn art(ink: Ink, shape: Shape) -> Self {
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
    pub id: String,
    /// Shared drawings placed before the items (guide pages only: the PDF
    /// writer places them; cut sheets and pictures have none).
    pub symbols: Vec<Place>,
    pub items: Vec<Item>,
}

impl Group {
    pub fn new(id: impl Into<String>, items: Vec<Item>) -> Self {
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
    pub uses: Vec<usize>,
    pub items: Vec<Item>,
}

/// Symbol `symbol` (an index into the document's symbols) drawn with its
/// origin at `at` on the page.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Place {
    pub symbol: usize,
    pub at: DVec2,
}

impl Layer {
    /// Layers the laser cuts through.
    pub fn is_cut(self) -> bool {
        matches!(self, Layer::Holes | Layer::Outlines)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Page {
    pub width: f64,
    pub height: f64,
    pub title: String,
    /// Key-value provenance written into each file's metadata.
    pub metadata: Vec<(String, String)>,
    pub groups: Vec<Group>,
}

impl Page {
    /// Total length of the cut layers on this page (mm).
    pub fn cut_length(&self) -> f64 {
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
pub fn arc_angles(from: DVec2, to: DVec2, center: DVec2, clockwise: bool) -> (f64, f64) {
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
pub fn arc_to_cubics(from: DVec2, to: DVec2, center: DVec2, clockwise: bool) -> Vec<[DVec2; 3]> {
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
pub fn circle_to_cubics(center: DVec2, radius: f64) -> (DVec2, Vec<[DVec2; 3]>) {
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
        assert!(pieces[0][2].x > 0.9, "{:?}", pieces);
        let (_, sweep) = arc_angles(DVec2::new(0.0, -1.0), DVec2::new(0.0, 1.0), c, false);
        assert!((sweep + PI).abs() < 1e-12);
    }
}
