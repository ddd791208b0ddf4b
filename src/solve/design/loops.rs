//! Loops for `karigami design`: a symmetric loop seeded round a level,
//! circular rim, each ring's vertex put on the target one step further
//! down its meridian (docs/math.md 6.2).

use super::{DesignAsk, Found, fit_of};
use crate::design::Design;
use crate::lattice::{Kind, Lattice, RowParams};
use crate::target::Target;
use glam::DVec3;
use std::time::Instant;

/// A level, circular rim: its centre and radius, when every boundary
/// corner lies within 1 % of the radius of one circle in a plane z = const.
pub(super) fn circular_rim(ring: &[DVec3], extent: f64) -> Option<(DVec3, f64)> {
    let n = ring.len() as f64;
    let c = ring.iter().sum::<DVec3>() / n.max(1.0);
    let r = ring
        .iter()
        .map(|p| (p - c).truncate().length())
        .sum::<f64>()
        / n.max(1.0);
    let level = ring.iter().all(|p| (p.z - c.z).abs() <= 0.002 * extent);
    let round = ring
        .iter()
        .all(|p| ((p - c).truncate().length() - r).abs() <= 0.01 * r);
    (level && round && r > 0.0 && ring.len() >= 8).then_some((c, r))
}

/// Loops of an even number of points round the rim (near one cell edge
/// apart, and two fewer), with a few ring counts: the rings' vertices
/// x[i][1] at equal steps of arc length down the target's meridian, the
/// last short of the axis by `HOLE` of it. Each count, and the same less
/// its last one or two rings (the likeliest to clash at the pole), is a
/// design.
pub(super) fn loops(
    ask: &DesignAsk<'_>,
    centre: DVec3,
    radius: f64,
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Vec<Found> {
    let t = &ask.target;
    let n0 = ((std::f64::consts::TAU * radius / ask.edge / 2.0).round() as usize * 2).max(8);
    let mut out = Vec::new();
    for n in [n0, n0.saturating_sub(2).max(8)] {
        let points: Vec<DVec3> = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                centre + radius * DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let Some(meridian) = meridian(t, centre, points[1]) else {
            continue;
        };
        let length = meridian.last().map_or(0.0, |m| m.0);
        for per_edge in RING_STEPS {
            if ask.deadline.is_some_and(|d| Instant::now() > d) {
                return out;
            }
            *tried += 1;
            let rings = ((length / (per_edge * ask.edge)).round() as usize).clamp(2, MAX_RINGS);
            let targets: Vec<DVec3> = (1..=rings)
                .map(|i| along(&meridian, (1.0 - HOLE) * length * i as f64 / rings as f64))
                .collect();
            progress(&format!(
                "loop of {n} points round the rim, {rings} rings {:.1} mm apart down the meridian",
                (1.0 - HOLE) * length / rings as f64
            ));
            for rows in (rings.div_ceil(2).max(1)..=rings).rev() {
                let Some(lattice) = buildable_loop(ask.base, &points, &targets[..rows]) else {
                    continue;
                };
                out.push(Found {
                    lattice: loop_toml(&points, &targets[..rows]),
                    cells: lattice.cells.len(),
                    fit: fit_of(t, &lattice),
                    seed: format!(
                        "a loop of {n} points round the rim, {rows} of {rings} rings at equal steps down the meridian"
                    ),
                });
            }
        }
    }
    out
}

/// The loop's lattice, when it grows and `build` would take its strips
/// (`cost::refused`: parts and the clash rule, with columns stacked).
fn buildable_loop(base: &Design, points: &[DVec3], targets: &[DVec3]) -> Option<Lattice> {
    let mut d = base.clone();
    d.kind = Kind::Loop;
    d.dim = 3;
    d.points = points.to_vec();
    d.kappa = vec![0.0; points.len()];
    d.rows = loop_rows(targets);
    d.fit = None;
    d.clash.stacking = crate::lattice::Stacking::Columns;
    let lattice = d.grow().ok()?;
    let m = crate::measure::measure(&d, &lattice);
    crate::solve::cost::refused(&d, &lattice, &m)
        .is_none()
        .then_some(lattice)
}

/// Ring steps tried, as shares of the cell edge.
const RING_STEPS: [f64; 3] = [0.5, 0.7, 0.9];

/// The share of the meridian left open at the axis.
const HOLE: f64 = 0.1;

/// Rings a loop grows at most.
const MAX_RINGS: usize = 40;

/// Samples of a meridian.
const MERIDIAN: usize = 400;

/// Symmetric loop rows: each ring's vertex x[i+1][1] on the target point.
fn loop_rows(targets: &[DVec3]) -> Vec<RowParams> {
    targets
        .iter()
        .map(|&p| RowParams {
            target: Some(p),
            ..RowParams::default()
        })
        .collect()
}

/// The target's meridian from the rim point `from` to the axis through
/// `centre` along z, sampled where vertical lines meet it: (arc length,
/// point) pairs; None when a line misses the target.
fn meridian(t: &Target, centre: DVec3, from: DVec3) -> Option<Vec<(f64, DVec3)>> {
    let top = t
        .mesh
        .positions
        .iter()
        .map(|p| p.z)
        .fold(f64::NEG_INFINITY, f64::max)
        + 1.0;
    let d = (from - centre).truncate();
    let s0 = d.length();
    if !(s0 > 0.0) {
        return None;
    }
    let u = d / s0;
    let mut out = vec![(0.0, from)];
    for k in 1..=MERIDIAN {
        // A hair inside the rim, where the first line could miss.
        let s = s0 * (1.0 - k as f64 / MERIDIAN as f64);
        let p = DVec3::new(centre.x + s * u.x, centre.y + s * u.y, top);
        // A coarse mesh's rim is a polygon inside the circle: lines
        // between it and the circle miss, and are skipped.
        let Some(h) = t.ray(p, -DVec3::Z, 0.0) else {
            if out.len() == 1 {
                continue;
            }
            return None;
        };
        let q = p - h * DVec3::Z;
        let (walked, last) = *out.last().expect("one point");
        out.push((walked + q.distance(last), q));
    }
    Some(out)
}

/// The meridian's point at arc length `s` (straight between samples).
fn along(meridian: &[(f64, DVec3)], s: f64) -> DVec3 {
    let k = meridian
        .partition_point(|m| m.0 < s)
        .clamp(1, meridian.len() - 1);
    let ((a, p), (b, q)) = (meridian[k - 1], meridian[k]);
    p.lerp(
        q,
        ((s - a) / (b - a).max(f64::MIN_POSITIVE)).clamp(0.0, 1.0),
    )
}

/// A symmetric loop's recipe tables: columns in alternate layers (an even
/// loop; docs/assembly.md), the seed and each ring's target point.
fn loop_toml(points: &[DVec3], targets: &[DVec3]) -> String {
    let mut s = String::from(
        "[clash]\nstacking = \"columns\"    # neighbouring columns in alternate layers\n\n[lattice]\nseed = \"loop\"\nkappa = 0.0\npoints = [\n",
    );
    for p in points {
        s.push_str(&format!("    [{:?}, {:?}, {:?}],\n", p.x, p.y, p.z));
    }
    s.push_str("]\n");
    for p in targets {
        s.push_str(&format!(
            "\n[[lattice.rows]]\ntarget = [{:?}, {:?}, {:?}]\n",
            p.x, p.y, p.z
        ));
    }
    s
}
