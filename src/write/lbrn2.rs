//! LightBurn projects (.lbrn2): one per sheet, with its layers set up so the
//! sheet cuts as it should without any setup: labels scored first while the
//! sheet is whole, then the holes, then the outlines (a part falls free only
//! after its holes are cut), and the reference on a layer that is not output.
//!
//! The format is LightBurn's XML: a `LightBurnProject` root, one
//! `CutSetting` per layer (its `index` is also the layer's colour in
//! LightBurn's palette, and it carries the stock preset's speed, power and
//! passes) and the shapes: holes are `Ellipse` shapes (LightBurn's own
//! circles, centred by their `XForm`); paths and a part's labels together
//! (its ID and arrow strokes) are `Path` shapes whose `VertList`
//! holds the vertices (with Bezier control points `c0` leaving and `c1`
//! arriving) and whose `PrimList` joins them with lines (`L a b`) or cubic
//! Beziers (`B a b`), their coordinates relative to the shape's `XForm`.
//! Identical geometry is written once, as LightBurn saves copies: later
//! shapes name its `VertID`/`PrimID` (see `Shared`), so a sheet of copies of
//! a few strip types stays small. One shape a line, no indentation.
//! LightBurn's y axis points up, so y is flipped. The
//! test piece is a `Group` shape whose `Children` are its holes, outline and
//! labels.

use super::number::{fixed, num, units};
use super::repeats::KeyMap;
use crate::drawing::{
    Item, Layer, Page, Segment, Shape, TEST_PIECE_ID, arc_to_cubics, path_end, text, walk,
};
use crate::fabrication::MachineSettings;
use glam::DVec2;
use std::collections::hash_map::Entry;
use std::fmt::Write as _;

/// LightBurn's first palette entries (layer index = colour), for choosing
/// the layer index whose colour matches the item's.
const PALETTE: [[u8; 3]; 4] = [[0, 0, 0], [0, 0, 255], [255, 0, 0], [0, 224, 0]];

/// The layers in the order LightBurn runs them, with what each does.
const ORDER: [(Layer, &str); 4] = [
    (Layer::Labels, "labels: score or engrave"),
    (Layer::Holes, "holes: cut (inner)"),
    (Layer::Outlines, "outlines: cut (outer)"),
    (Layer::Reference, "reference: do not output"),
];

/// The palette index nearest a colour.
fn palette_index(c: [u8; 3]) -> usize {
    let d = |p: [u8; 3]| -> i32 { (0..3).map(|k| (p[k] as i32 - c[k] as i32).pow(2)).sum() };
    (0..PALETTE.len())
        .min_by_key(|&i| d(PALETTE[i]))
        .expect("a palette")
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Vertices and primitives of a path, which may hold several strokes (a
/// LightBurn path's primitives join any of its vertices).
#[derive(Default)]
struct PathData {
    verts: Vec<(DVec2, Option<DVec2>, Option<DVec2>)>,
    prims: Vec<(bool, usize, usize)>,
    /// The first vertex of the stroke being added.
    start: usize,
}

impl PathData {
    /// Begin a stroke at `p`.
    fn move_to(&mut self, p: DVec2) {
        self.start = self.verts.len();
        self.verts.push((p, None, None));
    }

    fn line_to(&mut self, p: DVec2, close_to_start: bool) {
        let from = self.verts.len() - 1;
        let to = if close_to_start {
            self.start
        } else {
            self.verts.push((p, None, None));
            self.verts.len() - 1
        };
        self.prims.push((false, from, to));
    }

    fn cubic_to(&mut self, c1: DVec2, c2: DVec2, p: DVec2, close_to_start: bool) {
        let from = self.verts.len() - 1;
        self.verts[from].1 = Some(c1);
        let to = if close_to_start {
            self.verts[self.start].2 = Some(c2);
            self.start
        } else {
            self.verts.push((p, None, Some(c2)));
            self.verts.len() - 1
        };
        self.prims.push((true, from, to));
    }
}

/// Path geometry already written, keyed by its text relative to its first
/// vertex. This is how LightBurn itself saves copies: the first shape holds
/// the `VertList`/`PrimList` under a `VertID`/`PrimID`, and every later shape
/// with the same geometry names those IDs and is placed by its `XForm` alone.
/// A sheet of identical strips then costs one short line a shape.
#[derive(Default)]
struct Shared {
    verts: KeyMap<String, usize>,
    prims: KeyMap<String, usize>,
}

impl Shared {
    /// The ID of `text` in `table`, and whether it is new (to be written).
    fn id(table: &mut KeyMap<String, usize>, text: String) -> (usize, Option<String>) {
        let next = table.len();
        match table.entry(text) {
            Entry::Occupied(e) => (*e.get(), None),
            Entry::Vacant(e) => {
                let text = e.key().clone();
                e.insert(next);
                (next, Some(text))
            }
        }
    }
}

fn path_shape(out: &mut String, cut: usize, data: &PathData, shared: &mut Shared) {
    // The first vertex is placed by the XForm, on the 0.1 um grid; the
    // others are their offsets from it, rounded to the grid (so that copies
    // read the same: each vertex is within 0.1 um of where it belongs).
    let origin = data.verts[0].0;
    let rel = |p: DVec2| {
        let d = p - origin;
        (fixed(units(d.x)), fixed(units(d.y)))
    };
    let mut verts = String::new();
    for &(p, c0, c1) in &data.verts {
        let (x, y) = rel(p);
        let _ = write!(verts, "V{x} {y}");
        if let Some(c) = c0 {
            let (x, y) = rel(c);
            let _ = write!(verts, "c0x{x}c0y{y}");
        }
        if let Some(c) = c1 {
            let (x, y) = rel(c);
            let _ = write!(verts, "c1x{x}c1y{y}");
        }
    }
    let mut prims = String::with_capacity(8 * data.prims.len());
    for &(bezier, a, b) in &data.prims {
        let _ = write!(prims, "{}{a} {b}", if bezier { 'B' } else { 'L' });
    }
    let (vid, verts) = Shared::id(&mut shared.verts, verts);
    let (pid, prims) = Shared::id(&mut shared.prims, prims);
    let _ = write!(
        out,
        "<Shape Type=\"Path\" CutIndex=\"{cut}\" VertID=\"{vid}\" PrimID=\"{pid}\"><XForm>1 0 0 1 {} {}</XForm>",
        num(origin.x),
        num(origin.y)
    );
    if let Some(v) = verts {
        let _ = write!(out, "<VertList>{v}</VertList>");
    }
    if let Some(p) = prims {
        let _ = write!(out, "<PrimList>{p}</PrimList>");
    }
    out.push_str("</Shape>\n");
}

/// A circle as a LightBurn `Ellipse`.
fn ellipse(out: &mut String, cut: usize, center: DVec2, radius: f64) {
    let _ = writeln!(
        out,
        "<Shape Type=\"Ellipse\" CutIndex=\"{cut}\" Rx=\"{r}\" Ry=\"{r}\"><XForm>1 0 0 1 {} {}</XForm></Shape>",
        num(center.x),
        num(center.y),
        r = num(radius)
    );
}

/// Add a path or text item's strokes (y flipped) to `data`.
fn add_strokes(data: &mut PathData, shape: &Shape, flip: &dyn Fn(DVec2) -> DVec2) {
    match shape {
        Shape::Circle { .. } => unreachable!("circles are ellipses"),
        Shape::Path {
            start,
            segments,
            closed,
        } => {
            data.move_to(flip(*start));
            let n = segments.len();
            for (k, (from, s)) in walk(*start, segments).enumerate() {
                // A closed path whose last segment ends on its start closes onto it.
                let last = k + 1 == n;
                match s {
                    Segment::Line(p) => {
                        data.line_to(flip(p), last && *closed && p.distance(*start) < 1e-9);
                    }
                    Segment::Arc {
                        to,
                        center,
                        clockwise,
                    } => {
                        let pieces = arc_to_cubics(from, to, center, clockwise);
                        let m = pieces.len();
                        for (j, [c1, c2, p]) in pieces.into_iter().enumerate() {
                            let closing =
                                last && j + 1 == m && *closed && p.distance(*start) < 1e-9;
                            data.cubic_to(flip(c1), flip(c2), flip(p), closing);
                        }
                    }
                }
            }
            if *closed && path_end(*start, segments).distance(*start) >= 1e-9 {
                data.line_to(flip(*start), true);
            }
        }
        t @ Shape::Text { .. } => {
            for stroke in text::strokes(t) {
                data.move_to(flip(stroke[0]));
                for &p in &stroke[1..] {
                    data.line_to(flip(p), false);
                }
            }
        }
    }
}

/// A group's items as shapes: each circle (a hole) one `Ellipse`, as
/// LightBurn draws circles itself; each path one `Path`; each run of
/// labels one `Path` of all their strokes (a strip's ID and arrow: one
/// shape, not one a stroke).
fn shapes(
    out: &mut String,
    items: &[&Item],
    index: &[usize; 5],
    flip: &dyn Fn(DVec2) -> DVec2,
    shared: &mut Shared,
) {
    let mut k = 0;
    while k < items.len() {
        let item = items[k];
        let cut = index[item.layer as usize];
        if let Shape::Circle { center, radius } = item.shape {
            ellipse(out, cut, flip(center), radius);
            k += 1;
            continue;
        }
        // Only labels join: an outline cut in pieces (tabs) keeps a path
        // a piece, as LightBurn's own tab tools leave them.
        let mut data = PathData::default();
        add_strokes(&mut data, &item.shape, flip);
        k += 1;
        while item.layer == Layer::Labels
            && k < items.len()
            && items[k].layer == Layer::Labels
            && !matches!(items[k].shape, Shape::Circle { .. })
        {
            add_strokes(&mut data, &items[k].shape, flip);
            k += 1;
        }
        if !data.verts.is_empty() {
            path_shape(out, cut, &data, shared);
        }
    }
}

/// A layer's settings: the stock's starting speed, power and passes for its
/// operation, or none (power 0) where the stock has none on this machine,
/// so nothing is cut until the maker sets it (the guide says why).
fn cut_setting(
    out: &mut String,
    layer: Layer,
    i: usize,
    priority: usize,
    laser: Option<MachineSettings>,
) {
    let name = ORDER.iter().find(|o| o.0 == layer).expect("a layer").1;
    let op = laser.map(|s| {
        if layer == Layer::Labels {
            s.mark
        } else {
            s.cut
        }
    });
    let (speed, power, passes) = op.map_or((100.0, 0.0, 1), |o| (o.speed, o.power, o.passes));
    let name = if op.is_none() && layer != Layer::Reference {
        format!("{name} (no preset settings: set power)")
    } else {
        name.to_string()
    };
    let _ = writeln!(
        out,
        "    <CutSetting type=\"Cut\">\n        <index Value=\"{i}\"/>\n        <name Value=\"{}\"/>\n        \
         <minPower Value=\"{p}\"/>\n        <maxPower Value=\"{p}\"/>\n        <speed Value=\"{}\"/>\n        \
         <numPasses Value=\"{passes}\"/>\n        <priority Value=\"{priority}\"/>\n        <doOutput Value=\"{}\"/>\n    </CutSetting>",
        escape(&name),
        num(speed),
        (layer != Layer::Reference) as u8,
        p = num(power),
    );
}

/// A cut sheet page as a LightBurn project.
pub fn write(page: &Page) -> Vec<u8> {
    let h = page.height;
    let flip = move |p: DVec2| DVec2::new(p.x, h - p.y);
    // Each layer's colour as drawn (the preset already applied).
    let colour = |layer: Layer| {
        page.groups
            .iter()
            .flat_map(|g| &g.items)
            .find(|i| i.layer == layer)
            .and_then(|i| i.ink.stroke)
            .unwrap_or(layer.rgb())
    };
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    out.push_str(
        "<LightBurnProject AppVersion=\"1.7.00\" FormatVersion=\"1\" MaterialHeight=\"0\" MirrorX=\"False\" MirrorY=\"False\">\n",
    );
    let mut index = [0usize; 5];
    let mut used: Vec<usize> = Vec::new();
    for (priority, (layer, _)) in ORDER.iter().enumerate() {
        let mut i = palette_index(colour(*layer));
        // Two layers never share a LightBurn layer: take the next free index.
        while used.contains(&i) {
            i += 1;
        }
        used.push(i);
        index[*layer as usize] = i;
        cut_setting(&mut out, *layer, i, priority, page.laser);
    }
    let mut shared = Shared::default();
    // Holes before outlines within each part, as in the SVG. The test piece
    // is one LightBurn group, so one click selects it to cut it alone.
    for g in &page.groups {
        let grouped = g.id == TEST_PIECE_ID;
        if grouped {
            out.push_str("<Shape Type=\"Group\"><XForm>1 0 0 1 0 0</XForm><Children>\n");
        }
        let items: Vec<&Item> = g.items.iter().filter(|i| i.layer != Layer::Art).collect();
        shapes(&mut out, &items, &index, &flip, &mut shared);
        if grouped {
            out.push_str("</Children></Shape>\n");
        }
    }
    let notes: Vec<String> = page
        .metadata
        .iter()
        .map(|(k, v)| format!("{k}: {v}"))
        .collect();
    let _ = writeln!(
        out,
        "    <Notes ShowOnLoad=\"0\" Notes=\"{}\"/>",
        escape(&format!("{}&#10;{}", page.title, notes.join("&#10;")))
            .replace("&amp;#10;", "&#10;")
    );
    out.push_str("</LightBurnProject>\n");
    out.into_bytes()
}
