//! `deployed.json` and `deployed.obj`: the simulated deployed shape
//! (docs/physics.md). The JSON has every vertex and pivot, every strip's
//! centre line with its face normal and strains; the OBJ has every strip
//! as a bent box of its width and thickness, one object per strip.

use super::number::num;
use crate::sim::results::DeployedStrip;
use glam::DVec3;
use serde::Serialize;
use std::fmt::Write as _;

/// What deployed.json says besides the strips.
pub(crate) struct Summary<'a> {
    pub(crate) design: &'a str,
    pub(crate) verdict: &'a str,
    pub(crate) vertex_joint: &'a str,
    pub(crate) theta_deg: f64,
    pub(crate) energy: [f64; 4],
    pub(crate) eps_max: f64,
    pub(crate) eps_allow: f64,
    pub(crate) eps_rod: &'a str,
    pub(crate) eps_s: f64,
    pub(crate) distance: f64,
    pub(crate) iterations: usize,
    /// What the simulation read, as one number (`pipeline::reuse`): two
    /// files of the same fingerprint hold the same simulation.
    pub(crate) fingerprint: u64,
    /// Vertex names and positions, then pivot names and positions.
    pub(crate) vertices: Vec<(String, DVec3)>,
    pub(crate) pivots: Vec<(String, DVec3)>,
    /// The supports (`[simulation] supports`): each vertex's name, where
    /// it is held and the force on the lattice there (N).
    pub(crate) supports: Vec<(String, DVec3, DVec3)>,
    /// The distance between the farthest two supports (mm).
    pub(crate) support_span: Option<f64>,
}

fn finite(x: f64) -> f64 {
    if x.is_finite() { x } else { 0.0 }
}

fn v3(p: DVec3) -> [f64; 3] {
    [finite(p.x), finite(p.y), finite(p.z)]
}

#[derive(Serialize)]
struct PointJson {
    name: String,
    pos: [f64; 3],
}

#[derive(Serialize)]
struct SupportJson {
    name: String,
    pos: [f64; 3],
    /// The force the support exerts on the lattice (N).
    reaction: [f64; 3],
}

#[derive(Serialize)]
struct StripJson<'a> {
    id: &'a str,
    s: Vec<f64>,
    nodes: Vec<[f64; 3]>,
    d2: Vec<[f64; 3]>,
    strain: Vec<f64>,
    twist_strain: Vec<f64>,
}

#[derive(Serialize)]
struct EnergyJson {
    total: f64,
    stretch: f64,
    bend: f64,
    twist: f64,
}

#[derive(Serialize)]
struct DeployedJson<'a> {
    design: &'a str,
    units: &'static str,
    deployment: &'a str,
    vertex_joint: &'a str,
    theta_deg: f64,
    energy: EnergyJson,
    largest_strain: f64,
    largest_strain_strip: &'a str,
    largest_strain_s: f64,
    allowable_strain: f64,
    distance_from_design: f64,
    newton_iterations: usize,
    fingerprint: String,
    vertices: Vec<PointJson>,
    pivots: Vec<PointJson>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    supports: Vec<SupportJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    support_span: Option<f64>,
    strips: Vec<StripJson<'a>>,
}

pub(crate) fn json(summary: &Summary, strips: &[DeployedStrip]) -> Vec<u8> {
    let points = |v: &[(String, DVec3)]| {
        v.iter()
            .map(|(n, p)| PointJson {
                name: n.clone(),
                pos: v3(*p),
            })
            .collect()
    };
    let doc = DeployedJson {
        design: summary.design,
        units: "mm, N mm; strains are fractions",
        deployment: summary.verdict,
        vertex_joint: summary.vertex_joint,
        theta_deg: finite(summary.theta_deg),
        energy: EnergyJson {
            total: finite(summary.energy.iter().sum()),
            stretch: finite(summary.energy[0]),
            bend: finite(summary.energy[1]),
            twist: finite(summary.energy[2]),
        },
        largest_strain: finite(summary.eps_max),
        largest_strain_strip: summary.eps_rod,
        largest_strain_s: finite(summary.eps_s),
        allowable_strain: summary.eps_allow,
        distance_from_design: finite(summary.distance),
        newton_iterations: summary.iterations,
        fingerprint: format!("{:016x}", summary.fingerprint),
        vertices: points(&summary.vertices),
        pivots: points(&summary.pivots),
        supports: summary
            .supports
            .iter()
            .map(|(n, p, f)| SupportJson {
                name: n.clone(),
                pos: v3(*p),
                reaction: v3(*f),
            })
            .collect(),
        support_span: summary.support_span.map(finite),
        strips: strips
            .iter()
            .map(|s| StripJson {
                id: &s.id,
                s: s.s.iter().map(|x| finite(*x)).collect(),
                nodes: s.centre.iter().map(|p| v3(*p)).collect(),
                d2: s.d2.iter().map(|p| v3(*p)).collect(),
                strain: s.strain.iter().map(|x| finite(*x)).collect(),
                twist_strain: s.gamma.iter().map(|x| finite(*x)).collect(),
            })
            .collect(),
    };
    let mut out = serde_json::to_vec_pretty(&doc).expect("serialisable");
    out.push(b'\n');
    out
}

/// Each strip as a bent box: four corners per node (+-w/2 along d1,
/// +-t/2 along d2), quads between consecutive nodes and at both ends.
pub(crate) fn obj(title: &str, strips: &[DeployedStrip], width: f64, thickness: f64) -> Vec<u8> {
    let mut out = format!(
        "# {title}: simulated deployed shape\n# karigami {}; units mm; one object per strip\n",
        env!("CARGO_PKG_VERSION")
    );
    let mut base = 1;
    for s in strips {
        let _ = writeln!(out, "o {}", s.id);
        for k in 0..s.centre.len() {
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = s.centre[k] + s.d1[k] * (a * width / 2.0) + s.d2[k] * (b * thickness / 2.0);
                let p = v3(p);
                out.push('v');
                for x in p {
                    out.push(' ');
                    out.push_str(num(x).as_str());
                }
                out.push('\n');
            }
        }
        let n = s.centre.len();
        for k in 0..n.saturating_sub(1) {
            let (i, j) = (base + 4 * k, base + 4 * (k + 1));
            for c in 0..4 {
                let c1 = (c + 1) % 4;
                face(&mut out, [i + c, i + c1, j + c1, j + c]);
            }
        }
        if n > 0 {
            let (i, j) = (base, base + 4 * (n - 1));
            face(&mut out, [i + 3, i + 2, i + 1, i]);
            face(&mut out, [j, j + 1, j + 2, j + 3]);
        }
        base += 4 * n;
    }
    out.into_bytes()
}

/// An OBJ face line of four vertex numbers, written by `number::fixed`'s
/// digit loop rather than through `writeln!`'s formatter (the torus's
/// deployed.obj has 21,744 faces and 22,656 vertices).
fn face(out: &mut String, vertices: [usize; 4]) {
    out.push('f');
    for v in vertices {
        out.push(' ');
        // A whole number of ten-thousandths prints without a fraction.
        out.push_str(super::number::fixed(v as i64 * 10_000).as_str());
    }
    out.push('\n');
}
