//! viewer.html: one self-contained page to turn the lattice in 3-D at the
//! workbench (steps, part finder, cut sheets, deployment). The page's HTML,
//! CSS and JavaScript live beside this file and are inlined with the build's
//! data as JSON, so the page needs no network. Same build -> same bytes.

use super::number::{Text, fixed, num, units};
use crate::assembly::Step;
use crate::design::Design;
use crate::drawing::picture::Camera;
use crate::fabrication::Fabrication;
use crate::lattice::deploy::Deployment;
use crate::lattice::{Kind, Lattice, RodType};
use crate::layout::Layout;
use crate::parts::{Outline, Parts};
use crate::words::plural;
use glam::DVec3;
use serde::{Serialize, Serializer};
use serde_json::value::RawValue;
use std::collections::HashMap;
use std::io;

const PAGE: &str = include_str!("viewer/page.html");
const STYLE: &str = include_str!("viewer/viewer.css");
const SCRIPT: &str = include_str!("viewer/viewer.js");

/// Everything the page shows, borrowed from one build.
pub struct Scene<'a> {
    pub(crate) design: &'a Design,
    /// The lattice as grown (steps, joints, layers, C(theta)).
    pub(crate) lattice: &'a Lattice,
    /// The lattice as assembled (`Lattice::placed`): what the page draws.
    pub(crate) assembled: &'a Lattice,
    pub(crate) parts: &'a Parts,
    pub(crate) layout: &'a Layout,
    pub(crate) deployment: &'a Deployment,
    pub(crate) steps: &'a [Step],
    /// A simulated deployed shape (one position per vertex, then one per
    /// cell pivot, like the designed one), when a simulation exists.
    pub simulated: Option<Vec<DVec3>>,
    /// The deployment path, drawn below the views as path.png draws it.
    pub(crate) path: Option<&'a crate::sim::path::Path>,
}

impl<'a> Scene<'a> {
    /// A scene of one build, without a simulated shape (set `simulated` to add one).
    pub fn new(
        design: &'a Design,
        lattice: &'a Lattice,
        assembled: &'a Lattice,
        parts: &'a Parts,
        layout: &'a Layout,
        deployment: &'a Deployment,
        steps: &'a [Step],
    ) -> Self {
        Self {
            design,
            lattice,
            assembled,
            parts,
            layout,
            deployment,
            steps,
            simulated: None,
            path: None,
        }
    }
}

/// The page as bytes.
pub fn write(scene: &Scene) -> Vec<u8> {
    let data = data_json(scene);
    // Inside <script>, "</" could end the element early; JSON allows "<\/".
    let data = data.replace("</", "<\\/");
    let title = html_escape(&scene.design.name);
    let path = scene
        .path
        .map_or(String::new(), |p| path_figure(scene.design, p));
    // Fill the template's slots in order, never searching inserted text.
    let mut out = String::new();
    let mut rest = PAGE;
    for (slot, value) in [
        ("{{TITLE}}", title.as_str()),
        ("/*{{STYLE}}*/", STYLE),
        ("{{TITLE}}", title.as_str()),
        ("<!--{{PATH}}-->", path.as_str()),
        ("{{DATA}}", data.as_str()),
        ("/*{{SCRIPT}}*/", SCRIPT),
    ] {
        let (before, after) = rest.split_once(slot).expect("the page has every slot");
        out.push_str(before);
        out.push_str(value);
        rest = after;
    }
    out.push_str(rest);
    out.into_bytes()
}

/// The deployment path's plot (`path_png`'s page) as inline SVG: no XML
/// declaration and no namespace, which HTML does not need (the page
/// names no URL).
fn path_figure(design: &Design, path: &crate::sim::path::Path) -> String {
    let page = super::path_png::page(
        path,
        design.simulation.material.eps_allow,
        &format!("{}: the deployment path", design.name),
    );
    let svg = String::from_utf8(super::svg::write(&page)).expect("SVG is UTF-8");
    let svg = svg
        .split_once('\n')
        .map_or(svg.as_str(), |(_, rest)| rest)
        .replace(" xmlns=\"http://www.w3.org/2000/svg\"", "")
        .replace(
            &format!("height=\"{}mm\"", num(super::path_png::HEIGHT)),
            "",
        )
        .replace(
            &format!("width=\"{}mm\"", num(super::path_png::WIDTH)),
            "style=\"max-width:40em;width:100%\"",
        );
    format!(
        "<section id=\"path-plot\" aria-label=\"The deployment path: energy and largest strain against the held opening\">\n{svg}</section>\n"
    )
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Number text written as it is, a JSON number: `num`'s 4 decimals,
/// `Micro`'s 3, or Rust's shortest round-trip text.
fn raw<S: Serializer>(text: String, s: S) -> Result<S::Ok, S::Error> {
    RawValue::from_string(text)
        .expect("a finite number is JSON")
        .serialize(s)
}

/// A length or direction to 0.0001 (`num`).
#[derive(Clone, Copy)]
struct Num(f64);

impl Serialize for Num {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        raw(num(self.0).to_string(), s)
    }
}

/// A difference of positions in micrometres, written in mm: positions
/// are kept to 0.001 mm (far below what a screen shows) and written as the
/// difference from the point before, which the page sums in whole
/// micrometres, so no rounding error accumulates.
#[derive(Clone, Copy)]
struct Micro(i64);

impl Serialize for Micro {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        raw(fixed(10 * self.0).to_string(), s)
    }
}

/// Positions, x, y, z each, as differences from the point before.
fn coords(ps: impl Iterator<Item = DVec3>) -> Vec<Micro> {
    let mut before = [0i64; 3];
    let mut out = Vec::new();
    for p in ps {
        for (k, x) in [p.x, p.y, p.z].into_iter().enumerate() {
            let now = (x * 1e3).round() as i64;
            out.push(Micro(now - before[k]));
            before[k] = now;
        }
    }
    out
}

/// Full precision (the page rebuilds the deployed shape from these), as
/// Rust prints it: shortest round trip, no exponent.
#[derive(Clone, Copy)]
struct Full(f64);

impl Serialize for Full {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        raw(self.0.to_string(), s)
    }
}

fn vec3(p: DVec3) -> [Num; 3] {
    [Num(p.x), Num(p.y), Num(p.z)]
}

/// The data block: one line per record family, one per strip and step,
/// plain arrays for the bulk.
#[derive(Serialize)]
struct Data<'a> {
    name: &'a str,
    version: &'static str,
    kind: &'static str,
    dim: usize,
    extrinsic: bool,
    width: usize,
    fab: FabJson<'a>,
    camera: CameraJson,
    /// Designed shape: the vertices, then one pivot per cell, x, y, z each
    /// (`coords`: differences, to 0.001 mm).
    points: Vec<Micro>,
    /// The simulated shape, the same way; null without a simulation.
    simulated: Option<Vec<Micro>>,
    /// Per cell: corners UL, UR, LL, LR, the layers of rods A and B, the
    /// step; each written as its difference from the same number of the
    /// cell before (neighbours differ by 1 or 0: half the bytes).
    cells: Vec<i64>,
    sheets: usize,
    strips: StripsJson<'a>,
    /// The vertices' keys ([row,col] in the guide): per run of vertices in
    /// one row with consecutive columns, row, first column, count.
    keys: Vec<u32>,
    say: SayJson,
    steps: Vec<StepJson>,
    verdict: String,
    deploy: Option<DeployJson>,
}

#[derive(Serialize)]
struct FabJson<'a> {
    material: &'a str,
    thickness: Num,
    width: Num,
    end_margin: Num,
    eyelet: &'a str,
    hole: Num,
    flange: Num,
    sheet: &'a str,
    sheet_width: Num,
    sheet_height: Num,
    part_width: Num,
}

#[derive(Serialize)]
struct CameraJson {
    right: [Num; 3],
    up: [Num; 3],
    forward: [Num; 3],
}

/// The strips, written compactly: a strip's ID follows from its cell and
/// rod (`R{row}-C{col}-{A|B}`, strips in rod order, A then B per cell), and
/// what a strip type shares (lengths, pitches, part code) is written once.
#[derive(Serialize)]
struct StripsJson<'a> {
    /// Digits of the row and column numbers in IDs, then per run of cells
    /// in one row with consecutive columns: row, first column, cell count.
    ids: Vec<u32>,
    /// Per distinct strip shape (as written): tip-to-tip length, the two
    /// hole pitches, the cut length and the part type code.
    shapes: Vec<ShapeJson<'a>>,
    /// Per strip, five numbers: its shape, its sheet (1-based), the
    /// top-left of its box there (x, y, to 0.0001 mm, each written as the
    /// difference from the strip before, summed by the page in whole
    /// ten-thousandths) and whether it is turned.
    place: Vec<Field>,
}

#[derive(Serialize)]
struct ShapeJson<'a>(Num, Num, Num, Num, &'a str);

/// A whole number or a difference of lengths in ten-thousandths of a mm,
/// in one flat array of numbers.
enum Field {
    Int(i64),
    Step(i64),
}

impl Serialize for Field {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match *self {
            Field::Int(n) => n.serialize(s),
            Field::Step(n) => raw(fixed(n).to_string(), s),
        }
    }
}

/// The guide's sentences that every step shares, written once.
#[derive(Serialize)]
struct SayJson {
    pair: &'static str,
    /// The second instruction of a step that closes joints, and of one that
    /// closes none.
    close: &'static str,
    none: &'static str,
}

/// A step with the guide's sentences; the strip lists are indices so that
/// the page can make every ID clickable. The step's cells are those whose
/// step (in `cells`) is this one.
#[derive(Serialize)]
struct StepJson {
    title: String,
    eyelets: String,
    /// Per joint closed: its vertex (as the difference from the joint
    /// before's; the guide names it by its key, from `keys`), the number of
    /// rods closed there, then the rods bottom to top, the first as it is
    /// and the others as differences from the rod before.
    joints: Vec<i64>,
}

/// C(theta) of a planar true mechanism (`deploy`).
#[derive(Serialize)]
struct DeployJson {
    theta_design: Full,
    theta_max: Full,
    /// Per cell: a, b, the four legs, the side rod B turns to.
    cells: Vec<Full>,
}

/// How a step's joints are stacked, in the guide's words: from the table up
/// only for a piece built flat, from the inside out on a loop or helix
/// (docs/assembly.md, Stacking side).
fn close_words(lattice: &crate::lattice::Lattice) -> &'static str {
    if crate::assembly::built_flat(lattice) {
        "2. Close these vertex joints, strips stacked from the table up, one eyelet each:"
    } else if lattice.kind == crate::lattice::Kind::Sheet {
        "2. Close these vertex joints, strips stacked from the far side to the pictured side, one eyelet each:"
    } else {
        "2. Close these vertex joints, strips stacked from the inside out, one eyelet each:"
    }
}

fn data_json(s: &Scene) -> String {
    let lattice = s.lattice;
    let fab: &Fabrication = &s.design.fabrication;
    let camera = Camera::for_lattice(s.assembled);
    let shown = s.assembled;
    let data = Data {
        name: &s.design.name,
        version: env!("CARGO_PKG_VERSION"),
        kind: lattice.kind.name(),
        dim: lattice.dim,
        extrinsic: lattice.extrinsic(),
        width: lattice.width,
        fab: FabJson {
            material: &fab.material.name,
            thickness: Num(fab.material.thickness),
            width: Num(fab.material.width),
            end_margin: Num(fab.end_margin),
            eyelet: &fab.eyelet.name,
            hole: Num(fab.eyelet.hole),
            flange: Num(fab.eyelet.flange),
            sheet: &fab.sheet.name,
            sheet_width: Num(fab.sheet.width),
            sheet_height: Num(fab.sheet.height),
            part_width: Num(s.layout.part_width),
        },
        camera: CameraJson {
            right: vec3(camera.right),
            up: vec3(camera.up),
            forward: vec3(camera.forward),
        },
        points: coords(
            shown
                .vertices
                .iter()
                .map(|v| v.pos)
                .chain(shown.cells.iter().map(|c| c.pivot)),
        ),
        simulated: s.simulated.as_ref().map(|ps| coords(ps.iter().copied())),
        cells: cells_json(lattice),
        sheets: s.layout.sheets.len(),
        strips: strips_json(s),
        keys: runs(lattice.vertices.iter().map(|v| (v.key.row, v.key.col))),
        say: SayJson {
            pair: pair_words(lattice),
            close: close_words(lattice),
            none: "2. No vertex joint closes in this step.",
        },
        steps: steps_json(s),
        verdict: s.deployment.verdict(lattice),
        deploy: deploy_json(s),
    };
    let mut out = Vec::new();
    let mut writer = serde_json::Serializer::with_formatter(&mut out, Lines::default());
    data.serialize(&mut writer).expect("the data serialises");
    out.push(b'\n');
    String::from_utf8(out).expect("JSON is UTF-8")
}

/// `Data::cells`: the cells' seven numbers as differences.
fn cells_json(lattice: &Lattice) -> Vec<i64> {
    let mut before = [0i64; 7];
    let mut out = Vec::with_capacity(7 * lattice.cells.len());
    for (i, c) in lattice.cells.iter().enumerate() {
        let now = [
            i64::from(c.ul),
            i64::from(c.ur),
            i64::from(c.ll),
            i64::from(c.lr),
            i64::from(lattice.layer(c, RodType::A)),
            i64::from(lattice.layer(c, RodType::B)),
            lattice.step_of(i) as i64,
        ];
        out.extend(now.iter().zip(before).map(|(n, b)| n - b));
        before = now;
    }
    out
}

fn strips_json<'a>(s: &Scene<'a>) -> StripsJson<'a> {
    let mut place = vec![None; s.parts.strips.len()];
    for (i, sheet) in s.layout.sheets.iter().enumerate() {
        for p in &sheet.placements {
            place[p.part] = Some((i + 1, *p));
        }
    }
    let fab = &s.design.fabrication;
    // Shapes keyed by their written text, numbered in order of first use,
    // so that the page shows each strip's own numbers exactly.
    let mut shapes = Vec::new();
    let mut shape_of: HashMap<(Text, Text, Text, Text, &str), usize> = HashMap::new();
    let mut flat = Vec::with_capacity(5 * s.parts.strips.len());
    let mut before = (0, 0);
    for (strip, place) in s.parts.strips.iter().zip(place) {
        let (sheet, p) = place.expect("every strip is placed");
        let cut = Outline::of(strip.length, fab).length;
        let code = s.parts.types[strip.part_type].code.as_str();
        let key = (
            num(strip.length),
            num(strip.legs[0]),
            num(strip.legs[1]),
            num(cut),
            code,
        );
        let next = shapes.len();
        let shape = *shape_of.entry(key).or_insert_with(|| {
            shapes.push(ShapeJson(
                Num(strip.length),
                Num(strip.legs[0]),
                Num(strip.legs[1]),
                Num(cut),
                code,
            ));
            next
        });
        let at = (units(p.x), units(p.y));
        flat.extend([
            Field::Int(shape as i64),
            Field::Int(sheet as i64),
            Field::Step(at.0 - before.0),
            Field::Step(at.1 - before.1),
            Field::Int(i64::from(p.rotated)),
        ]);
        before = at;
    }
    StripsJson {
        ids: id_runs(s.parts),
        shapes,
        place: flat,
    }
}

/// (row, column) pairs as runs of one row with consecutive columns: row,
/// first column, count per run.
fn runs(keys: impl Iterator<Item = (u32, u32)>) -> Vec<u32> {
    let mut out: Vec<u32> = Vec::new();
    for (row, col) in keys {
        let n = out.len();
        if n >= 3 && out[n - 3] == row && out[n - 2].checked_add(out[n - 1]) == Some(col) {
            out[n - 1] += 1;
        } else {
            out.extend([row, col, 1]);
        }
    }
    out
}

/// The strip IDs as runs of cells (see `StripsJson::ids`). Strips come two
/// per cell, rod A then rod B, so the cell of strip `i` is `i / 2`.
fn id_runs(parts: &Parts) -> Vec<u32> {
    // The digit counts are those of the IDs themselves ("R007-C12-A").
    let digits = |id: &str| {
        let (row, rest) = id[1..].split_once("-C").unwrap_or(("00", "00-"));
        let col = rest.split_once('-').map_or("00", |(c, _)| c);
        (row.len(), col.len())
    };
    let (rd, cd) = parts.strips.first().map_or((2, 2), |s| digits(&s.id));
    debug_assert!(parts.strips.chunks(2).all(|pair| {
        let (row, col) = (pair[0].row, pair[0].col);
        pair.iter()
            .zip(["A", "B"])
            .all(|(s, k)| s.id == format!("R{row:0rd$}-C{col:0cd$}-{k}"))
    }));
    let mut out = vec![rd as u32, cd as u32];
    out.extend(runs(parts.strips.chunks(2).map(|p| (p[0].row, p[0].col))));
    out
}

/// Steps with the guide's sentences.
fn steps_json(s: &Scene) -> Vec<StepJson> {
    let lattice = s.lattice;
    let total = s.parts.eyelets();
    let unit = if lattice.kind == Kind::Helix {
        "Cell"
    } else {
        "Row"
    };
    s.steps
        .iter()
        .map(|step| StepJson {
            title: format!(
                "{unit} {}: {}, {}, {}",
                step.row,
                plural(step.cells.len(), "cell"),
                plural(step.strips.len(), "strip"),
                plural(step.eyelets, "eyelet")
            ),
            eyelets: format!(
                "Eyelets in this step: {}. Set so far: {} of {total}.",
                step.eyelets, step.total
            ),
            joints: {
                let mut out = Vec::new();
                let mut before = 0;
                for j in &step.joints {
                    out.extend([i64::from(j.vertex) - before, j.ends.len() as i64]);
                    before = i64::from(j.vertex);
                    let mut rod = 0;
                    for e in &j.ends {
                        out.push(e.rod as i64 - rod);
                        rod = e.rod as i64;
                    }
                }
                out
            },
        })
        .collect()
}

/// C(theta) for a planar true mechanism: per cell cos(phi) = a + b cos(theta)
/// with its legs and the side its rod B turns to, so that the page can
/// place the cells at any opening (as `planar_misfit` does); None otherwise,
/// with the verdict saying why.
fn deploy_json(s: &Scene) -> Option<DeployJson> {
    let lattice = s.lattice;
    let d = s.deployment;
    let config = &d.config;
    let planar = lattice.dim == 2 && lattice.extrinsic() && d.is_mechanism();
    let (t1, t2) = (0.25 * config.theta_max, 0.75 * config.theta_max);
    let (c1, c2) = (config.angles(t1)?, config.angles(t2)?);
    if !planar || (t1.cos() - t2.cos()).abs() < 1e-9 {
        return None;
    }
    let affine: Vec<(f64, f64)> = c1
        .iter()
        .zip(&c2)
        .map(|(p1, p2)| {
            let b = (p1.cos() - p2.cos()) / (t1.cos() - t2.cos());
            (p1.cos() - b * t1.cos(), b)
        })
        .collect();
    // Never NaN or inf in a file: no slider rather than a broken one.
    if affine.iter().any(|(a, b)| !a.is_finite() || !b.is_finite()) {
        return None;
    }
    let cells = lattice
        .cells
        .iter()
        .zip(affine)
        .flat_map(|(cell, (a, b))| {
            let [ul, ur, _, _] = lattice.corners(cell);
            let (u, v) = (ul - cell.pivot, ur - cell.pivot);
            // The side rod B turns to: the sign of u x v.
            let side = if u.x * v.y < u.y * v.x { -1.0 } else { 1.0 };
            let legs = lattice.legs(cell);
            [a, b, legs[0], legs[1], legs[2], legs[3], side].map(Full)
        })
        .collect();
    Some(DeployJson {
        theta_design: Full(config.theta_design),
        theta_max: Full(config.theta_max),
        cells,
    })
}

/// serde_json's compact output with line breaks where the hand-written
/// block had them, so that the page's source stays readable: one line per
/// member of the data object, and one per record of its arrays of records
/// (strips, steps).
#[derive(Default)]
struct Lines {
    /// Per open array or object: whether it is an array, and for an array
    /// whether the value now starting is its first.
    open: Vec<(bool, bool)>,
}

impl Lines {
    /// Open an array (`[`) or an object (`{`). A record starting as a later
    /// value of an array that is a member of the data object goes on a new
    /// line.
    fn open<W: ?Sized + io::Write>(&mut self, w: &mut W, bracket: &[u8]) -> io::Result<()> {
        if let [(false, _), (true, false)] = self.open.as_slice() {
            w.write_all(b"\n")?;
        }
        self.open.push((bracket == b"[", true));
        w.write_all(bracket)
    }
}

impl serde_json::ser::Formatter for Lines {
    fn begin_array<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open(w, b"[")
    }

    fn end_array<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open.pop();
        w.write_all(b"]")
    }

    fn begin_array_value<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> io::Result<()> {
        if let Some(top) = self.open.last_mut() {
            top.1 = first;
        }
        if first { Ok(()) } else { w.write_all(b",") }
    }

    fn begin_object<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open(w, b"{")
    }

    fn end_object<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open.pop();
        w.write_all(if self.open.is_empty() { b"\n}" } else { b"}" })
    }

    fn begin_object_key<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> io::Result<()> {
        match (self.open.len(), first) {
            (1, true) => w.write_all(b"\n"),
            (1, false) => w.write_all(b",\n"),
            (_, true) => Ok(()),
            (_, false) => w.write_all(b","),
        }
    }
}

/// The pivot step in the viewer's words: "under" only on a piece built flat;
/// on a 3-D one, B goes on the stacking side of A (docs/assembly.md).
fn pair_words(lattice: &Lattice) -> &'static str {
    if crate::assembly::built_flat(lattice) {
        "1. Pair the two strips of each cell at its scissor pivot, A under B, and set an eyelet:"
    } else {
        "1. Pair the two strips of each cell at its scissor pivot, B on the stacking side of A, and set an eyelet:"
    }
}
