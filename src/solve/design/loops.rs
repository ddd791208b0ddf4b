//! Loops for `karigami design`: a symmetric loop seeded round a level,
//! circular rim, each ring's vertex put on the target one step further
//! down its meridian (docs/math.md 6.2): towards the axis on a patch, to
//! the other rim on an annulus.

use super::{DesignAsk, Found, Plumb, fit_of};
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
/// design. `what` says where the circle lies, for the recipe's comment.
pub(super) fn loops(
    ask: &DesignAsk<'_>,
    (centre, radius): (DVec3, f64),
    what: &str,
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Vec<Found> {
    let t = &ask.target;
    let rim = Rim {
        centre,
        radius,
        reach: 1.0 - HOLE,
        meridian: &|from| meridian(t, centre, from),
        what,
    };
    rings(ask, &rim, tried, progress)
}

/// A loop's seed rim, how far down its meridian the rings go (a share of
/// its arc length), the meridian from a rim point and where the rim lies.
struct Rim<'a> {
    centre: DVec3,
    radius: f64,
    reach: f64,
    meridian: &'a dyn Fn(DVec3) -> Option<Vec<(f64, DVec3)>>,
    what: &'a str,
}

/// The designs of `loops` and `annulus`: for each loop size, the rings'
/// target points down the meridian of the seed's point 1.
fn rings(
    ask: &DesignAsk<'_>,
    rim: &Rim<'_>,
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Vec<Found> {
    let mut out = Vec::new();
    for n in counts(std::f64::consts::TAU * rim.radius, ask.edge) {
        let points = level_loop(rim.centre, rim.radius, n);
        let Some(meridian) = (rim.meridian)(points[1]) else {
            continue;
        };
        let length = rim.reach * meridian.last().map_or(0.0, |m| m.0);
        let seed = Seed {
            points: &points,
            meridian: &meridian,
            span: (0.0, length),
            what: rim.what,
            closed: false,
        };
        out.extend(grow_rings(ask, &seed, tried, progress));
    }
    out
}

/// The point counts of a loop round a rim `length` long: an even count
/// near one `edge` apart, and two fewer, 8 at least.
pub(super) fn counts(length: f64, edge: f64) -> [usize; 2] {
    let n0 = ((length / edge / 2.0).round() as usize * 2).max(8);
    [n0, n0.saturating_sub(2).max(8)]
}

/// `n` points round the level circle of `radius` about `centre`, the
/// first on +x.
pub(super) fn level_loop(centre: DVec3, radius: f64, n: usize) -> Vec<DVec3> {
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            centre + radius * DVec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect()
}

/// A loop's seed points, the meridian through its point 1 as (arc length,
/// point) pairs, the stretch of it (arc lengths) its rings span, where
/// the seed lies, for the recipe's comment, and whether the target is
/// closed (`grow_rings`).
pub(super) struct Seed<'a> {
    pub points: &'a [DVec3],
    pub meridian: &'a [(f64, DVec3)],
    pub span: (f64, f64),
    pub what: &'a str,
    pub closed: bool,
}

/// Rings a loop on a closed target leaves off at most: each leaves a
/// band of the far cap uncovered, and it is measured on the whole target.
const CLOSED_CUT: usize = 2;

/// For each ring step, the rings' vertices x[i][1] at equal steps of arc
/// length along the seed's span of its meridian, the last at its end; each
/// design with its last rings left off, down to half of them; on a closed
/// target only the most rings that build, `CLOSED_CUT` left off at most.
pub(super) fn grow_rings(
    ask: &DesignAsk<'_>,
    seed: &Seed<'_>,
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Vec<Found> {
    let (t, points, n) = (&ask.target, seed.points, seed.points.len());
    let (from, length) = (seed.span.0, seed.span.1 - seed.span.0);
    let mut out = Vec::new();
    for per_edge in RING_STEPS {
        if ask.deadline.is_some_and(|d| Instant::now() > d) {
            return out;
        }
        *tried += 1;
        let rings = ((length / (per_edge * ask.edge)).round() as usize).clamp(2, MAX_RINGS);
        let targets: Vec<DVec3> = (1..=rings)
            .map(|i| along(seed.meridian, from + length * i as f64 / rings as f64))
            .collect();
        progress(&format!(
            "loop of {n} points {}, {rings} rings {:.1} mm apart down the meridian",
            seed.what,
            length / rings as f64
        ));
        let least = if seed.closed {
            rings.saturating_sub(CLOSED_CUT).max(1)
        } else {
            rings.div_ceil(2).max(1)
        };
        for rows in (least..=rings).rev() {
            let Some(lattice) = buildable_loop(ask.base, points, &targets[..rows]) else {
                continue;
            };
            out.push(Found {
                lattice: loop_toml(points, &targets[..rows]),
                cells: lattice.cells.len(),
                fit: fit_of(t, &lattice),
                seed: format!(
                    "a loop of {n} points {}, {rows} of {rings} rings at equal steps down the meridian",
                    seed.what
                ),
            });
            if seed.closed {
                break;
            }
        }
    }
    out
}

/// The two rims of an annulus (a band, or a plate with a hole), when both
/// are level circles (`circular_rim`) about one vertical axis (their
/// centres within 1 % of the smaller radius of it): the seed rim, the
/// longer boundary loop, first.
pub(super) fn level_rims(t: &Target) -> Option<[(DVec3, f64); 2]> {
    let loops = t.mesh.boundary_loops();
    let [a, b] = loops.as_slice() else {
        return None;
    };
    let rim = |l: &Vec<u32>| {
        let ring: Vec<DVec3> = l.iter().map(|&i| t.mesh.positions[i as usize]).collect();
        circular_rim(&ring, t.extent)
    };
    let (a, b) = (rim(a)?, rim(b)?);
    let off = (a.0 - b.0).truncate().length();
    (off <= 0.01 * a.1.min(b.1) && a.0.distance(b.0) > 0.0).then_some([a, b])
}

/// Symmetric loops on an annulus whose rims are level circles
/// (`level_rims`): seeded round one rim, the rings' vertices at equal
/// steps along the meridian to the other rim, the last on it (docs/math.md
/// 6.2; docs/design.md, "Design your own object").
pub(super) fn annulus(
    ask: &DesignAsk<'_>,
    rims: [(DVec3, f64); 2],
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Vec<Found> {
    let t = &ask.target;
    let [(centre, radius), (other, other_radius)] = rims;
    let across = |from: DVec3| {
        let u = (from - centre).truncate().normalize_or_zero().extend(0.0);
        band_meridian(t, from, other + other_radius * u, DVec3::Z.cross(u))
    };
    let rim = Rim {
        centre,
        radius,
        reach: 1.0,
        meridian: &across,
        what: "round the rim",
    };
    rings(ask, &rim, tried, progress)
}

/// The meridian of a band from the rim point `from` to the point `to` of
/// the other rim at the same azimuth: the chord between them sampled and
/// each sample moved to its closest point on the target (on a surface of
/// revolution the closest point stays in the chord's meridian plane, whose
/// unit normal is `plane`), as (arc length, point) pairs; None when a
/// sample leaves that plane.
fn band_meridian(t: &Target, from: DVec3, to: DVec3, plane: DVec3) -> Option<Vec<(f64, DVec3)>> {
    let mut out = vec![(0.0, from)];
    for k in 1..=MERIDIAN {
        let f = k as f64 / MERIDIAN as f64;
        let q = if k == MERIDIAN {
            to
        } else {
            t.closest(from.lerp(to, f)).0
        };
        if (q - from).dot(plane).abs() > 0.01 * t.extent {
            return None;
        }
        let (walked, last) = *out.last().expect("one point");
        out.push((walked + q.distance(last), q));
    }
    Some(out)
}

/// The loop's lattice, when it grows and `build` would take its strips
/// (`buildable`, with columns stacked).
fn buildable_loop(base: &Design, points: &[DVec3], targets: &[DVec3]) -> Option<Lattice> {
    buildable(&symmetric_loop(base, points, loop_rows(targets)))
}

/// A symmetric loop on `points` (kappa 0, columns in alternate layers)
/// with `rows`, the rest of `base` kept.
pub(super) fn symmetric_loop(base: &Design, points: &[DVec3], rows: Vec<RowParams>) -> Design {
    let mut d = base.clone();
    d.kind = Kind::Loop;
    d.dim = 3;
    d.points = points.to_vec();
    d.kappa = vec![0.0; points.len()];
    d.rows = rows;
    d.fit = None;
    d.clash.stacking = crate::lattice::Stacking::Columns;
    d
}

/// The design's lattice, when it grows and `build` would take its strips
/// (`cost::refused`: parts and the clash rule).
pub(super) fn buildable(d: &Design) -> Option<Lattice> {
    let lattice = d.grow().ok()?;
    let m = crate::measure::measure(d, &lattice);
    crate::solve::cost::refused(d, &lattice, &m)
        .is_none()
        .then_some(lattice)
}

/// Ring steps tried, as shares of the cell edge.
const RING_STEPS: [f64; 3] = [0.5, 0.7, 0.9];

/// The share of the meridian left open at the axis.
pub(super) const HOLE: f64 = 0.1;

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
pub(super) fn meridian(t: &Target, centre: DVec3, from: DVec3) -> Option<Vec<(f64, DVec3)>> {
    let plumb = Plumb::new(t);
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
        let p = centre.truncate() + s * u;
        // A coarse mesh's rim is a polygon inside the circle: lines
        // between it and the circle miss, and are skipped.
        let Some(z) = plumb.height(p) else {
            if out.len() == 1 {
                continue;
            }
            return None;
        };
        let q = p.extend(z);
        let (walked, last) = *out.last().expect("one point");
        out.push((walked + q.distance(last), q));
    }
    Some(out)
}

/// The meridian's point at arc length `s` (straight between samples).
pub(super) fn along(meridian: &[(f64, DVec3)], s: f64) -> DVec3 {
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
    let mut s = seed_toml(points);
    for p in targets {
        s.push_str(&format!(
            "\n[[lattice.rows]]\ntarget = [{:?}, {:?}, {:?}]\n",
            p.x, p.y, p.z
        ));
    }
    s
}

/// A symmetric loop's `[clash]` and `[lattice]` tables: columns in
/// alternate layers, kappa 0 and the seed's points at full precision.
pub(super) fn seed_toml(points: &[DVec3]) -> String {
    let mut s = String::from(
        "[clash]\nstacking = \"columns\"    # neighbouring columns in alternate layers\n\n[lattice]\nseed = \"loop\"\nkappa = 0.0\npoints = [\n",
    );
    for p in points {
        s.push_str(&format!("    [{:?}, {:?}, {:?}],\n", p.x, p.y, p.z));
    }
    s.push_str("]\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn target(name: &str) -> Target {
        let path = format!("{}/fixtures/targets/{name}", env!("CARGO_MANIFEST_DIR"));
        crate::target::read(name, &std::fs::read(path).unwrap(), None).unwrap()
    }

    /// The saddle band's rims are level circles of radius a cosh(130 /
    /// 200) = 146.26 mm about the z axis, 252.6 mm apart (scripts/make-targets);
    /// its meridian runs from one to the other, 260 mm of arc; a cap has no
    /// two rims.
    #[test]
    fn a_bands_rims_and_meridian_are_found() {
        let t = target("saddle-band.toml");
        let [(a, ra), (b, rb)] = level_rims(&t).expect("two level rims");
        for r in [ra, rb] {
            assert!((r - 146.2552).abs() < 0.01 * r, "{r}");
        }
        assert!((a.z - b.z).abs() > 250.0 && (a - b).truncate().length() < 1.0);
        let from = a + ra * DVec3::X;
        let m = band_meridian(&t, from, b + rb * DVec3::X, DVec3::Y).unwrap();
        let length = m.last().unwrap().0;
        assert!((length - 260.0).abs() < 2.6, "{length}");
        assert!(
            m.iter()
                .all(|(_, p)| p.y.abs() < 1e-6 && t.closest(*p).1 < 0.5)
        );
        assert!(level_rims(&target("bowl.toml")).is_none());
    }
}
