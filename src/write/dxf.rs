//! DXF cut files, R2000 (AC1015): the oldest version that declares its units
//! ($INSUNITS = 4, millimetres), so importers need not guess the scale. Holes
//! are CIRCLE entities; outlines are closed LWPOLYLINEs of lines and
//! semicircular arcs (bulges), one closed path per strip; engraving and the
//! scale bar are open LWPOLYLINEs on their own layers. No SPLINE, no TEXT.
//! y points up in DXF, so page coordinates are flipped (y' = height - y).
//!
//! A strip drawing placed more than once (the same holes, outline and
//! engraving, up to a translation) is written once as a BLOCK and placed by
//! one INSERT per strip, as CAD programs store repeated parts: a sheet of
//! 10,000 identical strips holds one drawing, not 10,000. The block's
//! entities keep their own layers and colours; its coordinates are offsets
//! on the 0.1 um grid from the insertion point, so that insertion point plus
//! offset is exactly the point a flat file would print.

use super::number::{fixed, num, on_grid, units};
use super::repeats::{self, Repeats};
use crate::drawing::{Group, Item, Layer, Page, Segment, Shape, walk};
use glam::DVec2;
use std::fmt::Write as _;

/// Writes group-code/value pairs and hands out entity handles.
struct Dxf {
    out: String,
    next_handle: u32,
}

impl Dxf {
    fn pair(&mut self, code: u16, value: impl std::fmt::Display) {
        let _ = write!(self.out, "{code}\n{value}\n");
    }

    fn handle(&mut self) -> String {
        let h = format!("{:X}", self.next_handle);
        self.next_handle += 1;
        h
    }

    /// A table's header: its name, its handle and how many entries follow.
    fn table_head(&mut self, name: &str, handle: &str, entries: usize) {
        self.pair(0, "TABLE");
        self.pair(2, name);
        self.pair(5, handle);
        self.pair(330, "0");
        self.pair(100, "AcDbSymbolTable");
        self.pair(70, entries);
    }

    /// A table entry's header: type, handle, owner, record class and name
    /// (with no flags).
    fn record(&mut self, kind: &str, owner: &str, class: &str, name: &str) {
        self.head(kind, owner);
        self.pair(100, "AcDbSymbolTableRecord");
        self.pair(100, class);
        self.pair(2, name);
        self.pair(70, 0);
    }

    /// A table entry or entity header: type, its handle, its owner.
    fn head(&mut self, kind: &str, owner: &str) -> String {
        self.pair(0, kind);
        let h = self.handle();
        self.pair(5, &h);
        self.pair(330, owner);
        h
    }

    fn table(&mut self, name: &str, entries: impl FnOnce(&mut Dxf, &str) -> usize) {
        let h = self.handle();
        // Entries are written after the count, so count them on a copy first.
        let mut probe = Dxf {
            out: String::new(),
            next_handle: self.next_handle,
        };
        let n = entries(&mut probe, &h);
        self.table_head(name, &h, n);
        self.out.push_str(&probe.out);
        self.next_handle = probe.next_handle;
        self.pair(0, "ENDTAB");
    }
}

/// A path's vertices, each with the bulge of the segment that leaves it.
fn bulged(start: DVec2, segments: &[Segment], closed: bool) -> Vec<(DVec2, f64)> {
    let mut vertices: Vec<(DVec2, f64)> = vec![(start, 0.0)];
    for (from, s) in walk(start, segments) {
        if let Segment::Arc { .. } = s {
            // Clockwise on the y-down page is counter-clockwise once
            // flipped, and DXF bulges are positive counter-clockwise.
            vertices.last_mut().expect("a start vertex").1 = (s.sweep(from) / 4.0).tan();
        }
        vertices.push((s.end(), 0.0));
    }
    if closed && vertices.len() > 1 && vertices.last().expect("vertices").0.distance(start) < 1e-9 {
        // The closing segment is implied; the last bulge stays on its vertex.
        vertices.pop();
    }
    vertices
}

fn lwpolyline(
    d: &mut Dxf,
    owner: &str,
    layer: Layer,
    aci: u8,
    vertices: &[(DVec2, f64)],
    closed: bool,
    flip: &dyn Fn(DVec2) -> DVec2,
) {
    d.head("LWPOLYLINE", owner);
    d.pair(100, "AcDbEntity");
    d.pair(8, layer.name());
    d.pair(62, aci);
    d.pair(100, "AcDbPolyline");
    d.pair(90, vertices.len());
    d.pair(70, if closed { 1 } else { 0 });
    for &(p, bulge) in vertices {
        let p = flip(p);
        d.pair(10, num(p.x));
        d.pair(20, num(p.y));
        if bulge != 0.0 {
            d.pair(42, num(bulge));
        }
    }
}

/// The AutoCAD colour index of a pure colour (R2000 has no true colour);
/// ACI 7 is black on a white background.
fn aci_of(rgb: [u8; 3]) -> Option<u8> {
    match rgb {
        [255, 0, 0] => Some(1),
        [255, 255, 0] => Some(2),
        [0, 255, 0] => Some(3),
        [0, 255, 255] => Some(4),
        [0, 0, 255] => Some(5),
        [255, 0, 255] => Some(6),
        [0, 0, 0] => Some(7),
        _ => None,
    }
}

/// Handles fixed up front so tables, blocks and objects can refer to them.
const MODEL_RECORD: &str = "1A";
const PAPER_RECORD: &str = "1B";
const ROOT_DICT: &str = "C";
const GROUP_DICT: &str = "D";

/// Each layer's colour as drawn (the colour preset already applied).
struct Colours([Option<u8>; 5]);

impl Colours {
    fn of(page: &Page) -> Colours {
        let mut colours: [Option<u8>; 5] = [None; 5];
        for item in page.groups.iter().flat_map(|g| &g.items) {
            let slot = &mut colours[item.layer as usize];
            if slot.is_none() {
                *slot = item.ink.stroke.and_then(aci_of);
            }
        }
        Colours(colours)
    }

    fn aci(&self, layer: Layer) -> u8 {
        self.0[layer as usize].unwrap_or(layer.aci())
    }
}

/// The page as DXF (R2000) bytes: comments, then one function per section.
pub fn write(page: &Page) -> Vec<u8> {
    write_with(page, false)
}

/// The page as DXF without blocks: every entity on its layer, no INSERT.
pub fn write_flat(page: &Page) -> Vec<u8> {
    write_with(page, true)
}

fn write_with(page: &Page, flat: bool) -> Vec<u8> {
    let mut d = Dxf {
        out: String::new(),
        next_handle: 0x20,
    };
    let colours = Colours::of(page);
    let mut plan = Blocks::plan(page, &colours, flat);
    plan.records = plan.names.iter().map(|_| d.handle()).collect();
    comments(&mut d, page);
    header(&mut d, page);
    tables(&mut d, page, &colours, &plan);
    blocks(&mut d, page, &colours, &plan);
    entities(&mut d, page, &colours, &plan);
    objects(&mut d);
    // Fix the handle seed now that every handle is known.
    let seed = format!("{:X}", d.next_handle);
    d.out
        .replacen(
            "$HANDSEED\n5\nFFFF\n",
            &format!("$HANDSEED\n5\n{seed}\n"),
            1,
        )
        .into_bytes()
}

/// The title and metadata as 999 comments.
fn comments(d: &mut Dxf, page: &Page) {
    // A line break in a value would end the group early and shift every
    // code after it: comments hold one line of printable text.
    let line = |s: &str| -> String {
        s.chars()
            .map(|c| if c.is_control() { '?' } else { c })
            .collect()
    };
    d.pair(
        999,
        line(&format!(
            "karigami {}: {}",
            env!("CARGO_PKG_VERSION"),
            page.title
        )),
    );
    for (k, v) in &page.metadata {
        d.pair(999, line(&format!("{k}: {v}")));
    }
}

/// HEADER: version, handle seed (fixed at the end), units and extent.
fn header(d: &mut Dxf, page: &Page) {
    d.pair(0, "SECTION");
    d.pair(2, "HEADER");
    d.pair(9, "$ACADVER");
    d.pair(1, "AC1015");
    d.pair(9, "$HANDSEED");
    d.pair(5, "FFFF");
    d.pair(9, "$INSUNITS");
    d.pair(70, 4);
    d.pair(9, "$MEASUREMENT");
    d.pair(70, 1);
    d.pair(9, "$EXTMIN");
    d.pair(10, 0);
    d.pair(20, 0);
    d.pair(30, 0);
    d.pair(9, "$EXTMAX");
    d.pair(10, num(page.width));
    d.pair(20, num(page.height));
    d.pair(30, 0);
    d.pair(0, "ENDSEC");
}

/// TABLES: viewport, line types, layers (with their colours), text style,
/// app ID, dimension style and block records.
fn tables(d: &mut Dxf, page: &Page, colours: &Colours, plan: &Blocks) {
    d.pair(0, "SECTION");
    d.pair(2, "TABLES");
    d.table("VPORT", |d, owner| {
        d.record("VPORT", owner, "AcDbViewportTableRecord", "*Active");
        for (code, v) in [(10, 0.0), (20, 0.0), (11, 1.0), (21, 1.0)] {
            d.pair(code, num(v));
        }
        d.pair(12, num(page.width / 2.0));
        d.pair(22, num(page.height / 2.0));
        d.pair(40, num(page.height * 1.05));
        d.pair(41, num(page.width / page.height));
        1
    });
    d.table("LTYPE", |d, owner| {
        for name in ["ByBlock", "ByLayer", "Continuous"] {
            d.record("LTYPE", owner, "AcDbLinetypeTableRecord", name);
            d.pair(
                3,
                if name == "Continuous" {
                    "Solid line"
                } else {
                    ""
                },
            );
            d.pair(72, 65);
            d.pair(73, 0);
            d.pair(40, "0.0");
        }
        3
    });
    d.table("LAYER", |d, owner| {
        // Layer "0" must exist; ours follow, the reference layer not plotted.
        let layers: Vec<(&str, u8, bool)> = std::iter::once(("0", 7, true))
            .chain(
                Layer::ALL
                    .iter()
                    .map(|l| (l.name(), colours.aci(*l), *l != Layer::Reference)),
            )
            .collect();
        for &(name, colour, plot) in &layers {
            d.record("LAYER", owner, "AcDbLayerTableRecord", name);
            d.pair(62, colour);
            d.pair(6, "Continuous");
            d.pair(290, plot as u8);
            d.pair(370, -3);
            d.pair(390, "0");
        }
        layers.len()
    });
    d.table("STYLE", |d, owner| {
        d.record("STYLE", owner, "AcDbTextStyleTableRecord", "Standard");
        d.pair(40, "0.0");
        d.pair(41, "1.0");
        d.pair(50, "0.0");
        d.pair(71, 0);
        d.pair(42, "2.5");
        d.pair(3, "txt");
        d.pair(4, "");
        1
    });
    d.table("VIEW", |_, _| 0);
    d.table("UCS", |_, _| 0);
    d.table("APPID", |d, owner| {
        d.record("APPID", owner, "AcDbRegAppTableRecord", "ACAD");
        1
    });
    dimstyle_table(d);
    block_record_table(d, plan);
    d.pair(0, "ENDSEC");
}

/// The DIMSTYLE table, written out: it uses 105 for its entries' handles.
fn dimstyle_table(d: &mut Dxf) {
    let dimstyle = d.handle();
    d.table_head("DIMSTYLE", &dimstyle, 1);
    d.pair(100, "AcDbDimStyleTable");
    d.pair(0, "DIMSTYLE");
    let std_dim = d.handle();
    d.pair(105, &std_dim);
    d.pair(330, &dimstyle);
    d.pair(100, "AcDbSymbolTableRecord");
    d.pair(100, "AcDbDimStyleTableRecord");
    d.pair(2, "Standard");
    d.pair(70, 0);
    d.pair(0, "ENDTAB");
}

/// The block records: model and paper space, with the fixed handles the
/// blocks refer to, then one per strip drawing (handles `plan.records`).
fn block_record_table(d: &mut Dxf, plan: &Blocks) {
    let records = d.handle();
    d.table_head("BLOCK_RECORD", &records, 2 + plan.names.len());
    let fixed = [
        (MODEL_RECORD, "*Model_Space"),
        (PAPER_RECORD, "*Paper_Space"),
    ];
    let named = plan
        .records
        .iter()
        .zip(&plan.names)
        .map(|(h, n)| (h.as_str(), n.as_str()));
    for (handle, name) in fixed.into_iter().chain(named) {
        d.pair(0, "BLOCK_RECORD");
        d.pair(5, handle);
        d.pair(330, &records);
        d.pair(100, "AcDbSymbolTableRecord");
        d.pair(100, "AcDbBlockTableRecord");
        d.pair(2, name);
    }
    d.pair(0, "ENDTAB");
}

/// BLOCKS: the model and paper space blocks, then each strip drawing that
/// is placed more than once, relative to its insertion point.
fn blocks(d: &mut Dxf, page: &Page, colours: &Colours, plan: &Blocks) {
    d.pair(0, "SECTION");
    d.pair(2, "BLOCKS");
    let fixed = [
        (MODEL_RECORD, "*Model_Space"),
        (PAPER_RECORD, "*Paper_Space"),
    ];
    for (record, name) in fixed {
        block_begin(d, record, name);
        block_end(d, record);
    }
    for (b, (record, name)) in plan.records.iter().zip(&plan.names).enumerate() {
        let first = plan.repeats.first[b];
        let at = plan.at[first].expect("a block's first group has items");
        block_begin(d, record, name);
        for item in &page.groups[first].items {
            item_entities(d, record, item, colours, &relative(page.height, at));
        }
        block_end(d, record);
    }
    d.pair(0, "ENDSEC");
}

fn block_begin(d: &mut Dxf, record: &str, name: &str) {
    d.head("BLOCK", record);
    d.pair(100, "AcDbEntity");
    d.pair(8, "0");
    d.pair(100, "AcDbBlockBegin");
    d.pair(2, name);
    d.pair(70, 0);
    for code in [10, 20, 30] {
        d.pair(code, "0.0");
    }
    d.pair(3, name);
    d.pair(1, "");
}

fn block_end(d: &mut Dxf, record: &str) {
    d.head("ENDBLK", record);
    d.pair(100, "AcDbEntity");
    d.pair(8, "0");
    d.pair(100, "AcDbBlockEnd");
}

/// Which groups are written as blocks (see `repeats`), with each block's
/// name and record handle and each group's flipped insertion point.
struct Blocks {
    repeats: Repeats,
    at: Vec<Option<(i64, i64)>>,
    names: Vec<String>,
    records: Vec<String>,
}

impl Blocks {
    fn plan(page: &Page, colours: &Colours, flat: bool) -> Blocks {
        // A group's drawing written relative to its anchor with throwaway
        // handles: equal texts are equal drawings.
        let at: Vec<Option<(i64, i64)>> = page
            .groups
            .iter()
            .map(|g| repeats::anchor(g).map(|(x, y)| (x, units(page.height) - y)))
            .collect();
        // Each keyed group's key and coarse key (`repeats::find_exact`).
        // Flat: no group has a key, so none becomes a block.
        let (keys, coarse): (Vec<_>, Vec<_>) = (page.groups.iter().zip(&at))
            .map(|(g, at)| match *at {
                Some(at) if !flat => (
                    Some(drawing_key(g, page.height, at)),
                    Some(printed_points(g, page.height, at)),
                ),
                _ => (None, None),
            })
            .unzip();
        let (repeats, _) = repeats::find_exact(&keys, &coarse, |g| {
            let at = at[g].expect("a keyed group has an anchor");
            let mut probe = Dxf {
                out: String::new(),
                next_handle: 0,
            };
            for item in &page.groups[g].items {
                item_entities(&mut probe, "0", item, colours, &relative(page.height, at));
            }
            probe.out
        });
        let names = (1..=repeats.first.len())
            .map(|b| format!("part-{b}"))
            .collect();
        Blocks {
            repeats,
            at,
            names,
            records: Vec::new(),
        }
    }
}

/// What a group's entities print relative to the insertion point `at`, as
/// integers (see `repeats::find_exact`): each point on the grid, each other
/// number on the grid where `num` prints it so, else by its bits.
fn drawing_key(g: &Group, height: f64, at: (i64, i64)) -> Vec<i64> {
    let map = relative(height, at);
    let grid = |p: DVec2| {
        let q = map(p);
        [units(q.x), units(q.y)]
    };
    let printed = |x: f64| on_grid(x).map_or([1, x.to_bits() as i64], |u| [0, u]);
    let mut k = Vec::with_capacity(16 * g.items.len());
    for item in &g.items {
        k.push(item.layer as i64);
        match &item.shape {
            Shape::Circle { center, radius } => {
                k.push(0);
                k.extend(grid(*center));
                k.extend(printed(*radius));
            }
            Shape::Path {
                start,
                segments,
                closed,
            } => {
                let vertices = bulged(*start, segments, *closed);
                k.extend([1, *closed as i64, vertices.len() as i64]);
                for (p, bulge) in vertices {
                    k.extend(grid(p));
                    // A zero bulge is not written.
                    if bulge == 0.0 {
                        k.push(2);
                    } else {
                        k.extend(printed(bulge));
                    }
                }
            }
            text @ Shape::Text { .. } => {
                let strokes = crate::drawing::text::strokes(text);
                k.extend([2, strokes.len() as i64]);
                for stroke in strokes {
                    k.push(stroke.len() as i64);
                    for p in stroke {
                        k.extend(grid(p));
                    }
                }
            }
        }
    }
    k
}

/// The points a group's entities print relative to the insertion point
/// `at`, on the grid, entity by entity: a CIRCLE's layer and centre, an
/// LWPOLYLINE's layer, closed flag and vertices (an outline's, or one text
/// stroke's). Equal texts print equal points: the coarse key
/// `repeats::find_exact` tells most groups apart by without their text.
fn printed_points(g: &Group, height: f64, at: (i64, i64)) -> Vec<i64> {
    let map = relative(height, at);
    let q = |p: DVec2| {
        let m = map(p);
        [units(m.x), units(m.y)]
    };
    let mut k = Vec::with_capacity(16 * g.items.len());
    for i in &g.items {
        let layer = i.layer as i64;
        match &i.shape {
            Shape::Circle { center, .. } => repeats::push_points(&mut k, &[0, layer], [q(*center)]),
            path @ Shape::Path { closed, .. } => {
                let vertices = path_vertices(path);
                let head = [1, layer, *closed as i64, vertices.len() as i64];
                repeats::push_points(&mut k, &head, vertices.into_iter().map(|(p, _)| q(p)));
            }
            text @ Shape::Text { .. } => {
                for stroke in crate::drawing::text::strokes(text) {
                    let head = [1, layer, 0, stroke.len() as i64];
                    repeats::push_points(&mut k, &head, stroke.into_iter().map(q));
                }
            }
        }
    }
    k
}

/// A path's LWPOLYLINE vertices (`bulged`); none for other shapes.
fn path_vertices(path: &Shape) -> Vec<(DVec2, f64)> {
    match path {
        Shape::Path {
            start,
            segments,
            closed,
        } => bulged(*start, segments, *closed),
        _ => Vec::new(),
    }
}

/// Page points to a block's coordinates: flipped (about the page height on
/// the grid), then offset from the insertion point `at` in grid steps.
fn relative(height: f64, at: (i64, i64)) -> impl Fn(DVec2) -> DVec2 {
    let h = units(height) as f64 / 1e4;
    let shift = repeats::offset(at);
    move |p: DVec2| shift(DVec2::new(p.x, h - p.y))
}

/// One item's entities: a hole as a CIRCLE, an outline or stroke as an
/// LWPOLYLINE, text as one LWPOLYLINE per stroke; points through `map`.
fn item_entities(
    d: &mut Dxf,
    owner: &str,
    item: &Item,
    colours: &Colours,
    map: &dyn Fn(DVec2) -> DVec2,
) {
    let layer = item.layer;
    match &item.shape {
        Shape::Circle { center, radius } => {
            d.head("CIRCLE", owner);
            d.pair(100, "AcDbEntity");
            d.pair(8, layer.name());
            d.pair(62, colours.aci(layer));
            d.pair(100, "AcDbCircle");
            let c = map(*center);
            d.pair(10, num(c.x));
            d.pair(20, num(c.y));
            d.pair(30, "0.0");
            d.pair(40, num(*radius));
        }
        Shape::Path {
            start,
            segments,
            closed,
        } => {
            lwpolyline(
                d,
                owner,
                layer,
                colours.aci(layer),
                &bulged(*start, segments, *closed),
                *closed,
                map,
            );
        }
        // No TEXT entities: text is drawn with the single-stroke font.
        text @ Shape::Text { .. } => {
            for stroke in crate::drawing::text::strokes(text) {
                let vertices: Vec<(DVec2, f64)> = stroke.into_iter().map(|p| (p, 0.0)).collect();
                lwpolyline(d, owner, layer, colours.aci(layer), &vertices, false, map);
            }
        }
    }
}

/// ENTITIES: an INSERT for each group drawn as a block, the entities of
/// every other group, y flipped.
fn entities(d: &mut Dxf, page: &Page, colours: &Colours, plan: &Blocks) {
    let h = page.height;
    let flip = |p: DVec2| DVec2::new(p.x, h - p.y);
    d.pair(0, "SECTION");
    d.pair(2, "ENTITIES");
    for (g, (shared, at)) in page
        .groups
        .iter()
        .zip(plan.repeats.of_group.iter().zip(&plan.at))
    {
        match (shared, at) {
            (Some(b), Some((x, y))) => {
                d.head("INSERT", MODEL_RECORD);
                d.pair(100, "AcDbEntity");
                d.pair(8, "0");
                d.pair(100, "AcDbBlockReference");
                d.pair(2, &plan.names[*b]);
                d.pair(10, fixed(*x));
                d.pair(20, fixed(*y));
                d.pair(30, "0.0");
            }
            _ => {
                for item in &g.items {
                    item_entities(d, MODEL_RECORD, item, colours, &flip);
                }
            }
        }
    }
    d.pair(0, "ENDSEC");
}

/// OBJECTS: the root dictionary and the (empty) group dictionary.
fn objects(d: &mut Dxf) {
    d.pair(0, "SECTION");
    d.pair(2, "OBJECTS");
    d.pair(0, "DICTIONARY");
    d.pair(5, ROOT_DICT);
    d.pair(330, "0");
    d.pair(100, "AcDbDictionary");
    d.pair(281, 1);
    d.pair(3, "ACAD_GROUP");
    d.pair(350, GROUP_DICT);
    d.pair(0, "DICTIONARY");
    d.pair(5, GROUP_DICT);
    d.pair(330, ROOT_DICT);
    d.pair(100, "AcDbDictionary");
    d.pair(281, 1);
    d.pair(0, "ENDSEC");
    d.pair(0, "EOF");
}
