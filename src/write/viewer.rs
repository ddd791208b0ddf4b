//! viewer.html: one self-contained page to turn the lattice in 3-D at the
//! workbench (steps, part finder, cut sheets, deployment). The page's HTML,
//! CSS and JavaScript live beside this file and are inlined with the build's
//! data as JSON, so the page needs no network. Same build -> same bytes.

use super::number::num;
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
use std::fmt::Write as _;

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
        }
    }
}

/// The page as bytes.
pub fn write(scene: &Scene) -> Vec<u8> {
    let data = data_json(scene);
    // Inside <script>, "</" could end the element early; JSON allows "<\/".
    let data = data.replace("</", "<\\/");
    let title = html_escape(&scene.design.name);
    // Fill the template's slots in order, never searching inserted text.
    let mut out = String::new();
    let mut rest = PAGE;
    for (slot, value) in [
        ("{{TITLE}}", title.as_str()),
        ("/*{{STYLE}}*/", STYLE),
        ("{{TITLE}}", title.as_str()),
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

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A JSON string literal.
fn text(s: &str) -> String {
    serde_json::to_string(s).expect("strings serialise")
}

/// Positions to 0.001 mm: a micrometre is far below what a screen shows,
/// and three decimals keep a 10,000-cell page small.
fn coord(x: f64) -> String {
    let mut s = format!("{x:.3}");
    if s.contains('.') {
        s = s.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    if s == "-0" { "0".into() } else { s }
}

fn points(out: &mut String, ps: impl Iterator<Item = DVec3>) {
    out.push('[');
    for (i, p) in ps.enumerate() {
        if i > 0 {
            out.push(',');
        }
        let _ = write!(out, "{},{},{}", coord(p.x), coord(p.y), coord(p.z));
    }
    out.push(']');
}

fn vec3(p: DVec3) -> String {
    format!("[{},{},{}]", num(p.x), num(p.y), num(p.z))
}

/// The data block: one line per record family, plain arrays for the bulk.
fn data_json(s: &Scene) -> String {
    let lattice = s.lattice;
    let fab: &Fabrication = &s.design.fabrication;
    let mut out = String::from("{\n");
    let _ = writeln!(
        out,
        "\"name\":{},\"version\":{},\"kind\":\"{}\",\"dim\":{},\"extrinsic\":{},\"width\":{},",
        text(&s.design.name),
        text(env!("CARGO_PKG_VERSION")),
        lattice.kind.name(),
        lattice.dim,
        lattice.extrinsic(),
        lattice.width
    );
    let _ = writeln!(
        out,
        "\"fab\":{{\"material\":{},\"thickness\":{},\"width\":{},\"end_margin\":{},\"eyelet\":{},\"hole\":{},\"flange\":{},\"sheet\":{},\"sheet_width\":{},\"sheet_height\":{},\"part_width\":{}}},",
        text(&fab.material.name),
        num(fab.material.thickness),
        num(fab.material.width),
        num(fab.end_margin),
        text(&fab.eyelet.name),
        num(fab.eyelet.hole),
        num(fab.eyelet.flange),
        text(&fab.sheet.name),
        num(fab.sheet.width),
        num(fab.sheet.height),
        num(s.layout.part_width)
    );
    let camera = Camera::for_lattice(s.assembled);
    let _ = writeln!(
        out,
        "\"camera\":{{\"right\":{},\"up\":{},\"forward\":{}}},",
        vec3(camera.right),
        vec3(camera.up),
        vec3(camera.forward)
    );
    // Designed shape: the vertices, then one pivot per cell.
    let shown = s.assembled;
    out.push_str("\"points\":");
    points(
        &mut out,
        shown
            .vertices
            .iter()
            .map(|v| v.pos)
            .chain(shown.cells.iter().map(|c| c.pivot)),
    );
    out.push_str(",\n\"simulated\":");
    match &s.simulated {
        Some(ps) => points(&mut out, ps.iter().copied()),
        None => out.push_str("null"),
    }
    // Cells: corners UL, UR, LL, LR, the layers of rods A and B, the step.
    out.push_str(",\n\"cells\":[");
    for (i, c) in lattice.cells.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        let _ = write!(
            out,
            "{},{},{},{},{},{},{}",
            c.ul,
            c.ur,
            c.ll,
            c.lr,
            lattice.layer(c, RodType::A),
            lattice.layer(c, RodType::B),
            lattice.step_of(i)
        );
    }
    out.push_str("],\n");
    strips_json(&mut out, s);
    steps_json(&mut out, s);
    deploy_json(&mut out, s);
    out.push_str("}\n");
    out
}

/// Per strip (rod order): ID, rod type, tip-to-tip length, the two hole
/// pitches, its sheet (1-based), the top-left of its box there, whether it
/// is turned, its cut length and its part type code.
fn strips_json(out: &mut String, s: &Scene) {
    let mut place = vec![None; s.parts.strips.len()];
    for (i, sheet) in s.layout.sheets.iter().enumerate() {
        for p in &sheet.placements {
            place[p.part] = Some((i + 1, *p));
        }
    }
    let fab = &s.design.fabrication;
    let _ = writeln!(out, "\"sheets\":{},", s.layout.sheets.len());
    out.push_str("\"strips\":[");
    for (i, (strip, place)) in s.parts.strips.iter().zip(place).enumerate() {
        if i > 0 {
            out.push_str(",\n");
        }
        let (sheet, p) = place.expect("every strip is placed");
        let _ = write!(
            out,
            "[{},\"{}\",{},{},{},{},{},{},{},{},{}]",
            text(&strip.id),
            strip.kind.letter(),
            num(strip.length),
            num(strip.legs[0]),
            num(strip.legs[1]),
            sheet,
            num(p.x),
            num(p.y),
            p.rotated as u8,
            num(Outline::of(strip.length, fab).length),
            text(&s.parts.types[strip.part_type].code)
        );
    }
    out.push_str("],\n");
}

/// The vertex as the guide names it, `[row,col]`.
fn vertex_key(lattice: &Lattice, v: u32) -> String {
    let k = lattice.vertex(v).key;
    format!("[{},{}]", k.row, k.col)
}

/// Steps with the guide's sentences; the strip lists are indices so that
/// the page can make every ID clickable.
fn steps_json(out: &mut String, s: &Scene) {
    let lattice = s.lattice;
    let total = s.parts.eyelets();
    let unit = if lattice.kind == Kind::Helix {
        "Cell"
    } else {
        "Row"
    };
    out.push_str("\"steps\":[");
    for (i, step) in s.steps.iter().enumerate() {
        if i > 0 {
            out.push_str(",\n");
        }
        let title = format!(
            "{unit} {}: {}, {}, {}",
            step.row,
            plural(step.cells.len(), "cell"),
            plural(step.strips.len(), "strip"),
            plural(step.eyelets, "eyelet")
        );
        let close = if step.joints.is_empty() {
            "2. No vertex joint closes in this step."
        } else {
            "2. Close these vertex joints, strips stacked from the table up, one eyelet each:"
        };
        let eyelets = format!(
            "Eyelets in this step: {}. Set so far: {} of {total}.",
            step.eyelets, step.total
        );
        let _ = write!(
            out,
            "{{\"title\":{},\"pair\":{},\"close\":{},\"eyelets\":{},\"cells\":{:?},\"joints\":[",
            text(&title),
            text(
                "1. Pair the two strips of each cell at its scissor pivot, A under B, and set an eyelet:"
            ),
            text(close),
            text(&eyelets),
            step.cells
        );
        for (k, j) in step.joints.iter().enumerate() {
            if k > 0 {
                out.push(',');
            }
            let rods: Vec<usize> = j.ends.iter().map(|e| e.rod).collect();
            let _ = write!(
                out,
                "[{},{},{:?}]",
                j.vertex,
                text(&vertex_key(lattice, j.vertex)),
                rods
            );
        }
        out.push_str("]}");
    }
    out.push_str("],\n");
}

/// C(theta) for a planar true mechanism: per cell cos(phi) = a + b cos(theta)
/// with its legs and the side its rod B turns to, so that the page can
/// place the cells at any opening (as `planar_misfit` does); null otherwise,
/// with the verdict saying why.
fn deploy_json(out: &mut String, s: &Scene) {
    let lattice = s.lattice;
    let d = s.deployment;
    let _ = write!(
        out,
        "\"verdict\":{},\n\"deploy\":",
        text(&d.verdict(lattice))
    );
    let config = &d.config;
    let planar = lattice.dim == 2 && lattice.extrinsic() && d.is_mechanism();
    let (t1, t2) = (0.25 * config.theta_max, 0.75 * config.theta_max);
    let (Some(c1), Some(c2)) = (config.angles(t1), config.angles(t2)) else {
        out.push_str("null\n");
        return;
    };
    if !planar || (t1.cos() - t2.cos()).abs() < 1e-9 {
        out.push_str("null\n");
        return;
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
        out.push_str("null\n");
        return;
    }
    let _ = write!(
        out,
        "{{\"theta_design\":{},\"theta_max\":{},\"cells\":[",
        config.theta_design, config.theta_max
    );
    for (i, cell) in lattice.cells.iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        let (a, b) = affine[i];
        let [ul, ur, _, _] = lattice.corners(cell);
        let (u, v) = (ul - cell.pivot, ur - cell.pivot);
        let side = if u.x * v.y - u.y * v.x < 0.0 { -1 } else { 1 };
        let legs = lattice.legs(cell);
        // Full precision: the page rebuilds the shape from these.
        let _ = write!(
            out,
            "{},{},{},{},{},{},{}",
            a, b, legs[0], legs[1], legs[2], legs[3], side
        );
    }
    out.push_str("]}\n");
}
