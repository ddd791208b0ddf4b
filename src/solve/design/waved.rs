//! Loops on a band whose rims are circles in plan about one vertical
//! axis but are not level, such as a ring cut from a saddle (a pringle
//! band; docs/design.md, "Saddle rings"). The seed lies on the longer rim;
//! every front, the seed's included, is laid on the saddle
//! z' = r^2 (c cos 2t + d cos 6t) fitted to the target at its radius
//! (src/lattice/saddle.rs), so the rebuilt fronts carry the band's
//! curvature, and each ring's tilt is chosen so that its new vertices lie
//! nearest the target.

use super::{DesignAsk, Found, Plumb, fit_of};
use crate::design::Design;
use crate::lattice::{FrontMoves, Lattice, RowParams, Saddle};
use crate::target::Target;
use glam::DVec3;
use std::f64::consts::TAU;
use std::time::Instant;

/// A waved band's axis (a point on it; the axis is vertical), its seed
/// rim's radius in plan, the other rim's, and the azimuth of the seed
/// rim's high points (where cos 2 t of its heights peaks).
#[derive(Clone, Copy, Debug)]
pub(super) struct Band {
    pub axis: DVec3,
    pub radius: f64,
    pub other: f64,
    pub phase: f64,
}

/// The band, when the target's two boundary loops are circles in plan
/// (every corner within 1 % of the radius) about one vertical axis (the
/// centres within 1 % of the smaller radius), the longer rim first and at
/// least 5 % wider, so that the rings have somewhere to step; None for any
/// other annulus.
pub(super) fn band(t: &Target) -> Option<Band> {
    let loops = t.mesh.boundary_loops();
    let [a, b] = loops.as_slice() else {
        return None;
    };
    let plan = |l: &Vec<u32>| -> Option<(DVec3, f64)> {
        let ring: Vec<DVec3> = l.iter().map(|&i| t.mesh.positions[i as usize]).collect();
        let c = ring.iter().sum::<DVec3>() / ring.len().max(1) as f64;
        let r = ring
            .iter()
            .map(|p| (p - c).truncate().length())
            .sum::<f64>()
            / ring.len() as f64;
        let round = ring
            .iter()
            .all(|p| ((p - c).truncate().length() - r).abs() <= 0.01 * r);
        (round && r > 0.0 && ring.len() >= 8).then_some((c, r))
    };
    let (mut a, mut b) = (plan(a)?, plan(b)?);
    if b.1 > a.1 {
        std::mem::swap(&mut a, &mut b);
    }
    if (a.0 - b.0).truncate().length() > 0.01 * b.1 || a.1 - b.1 < 0.05 * a.1 {
        return None;
    }
    let axis = a.0;
    let heights = heights(t, axis, a.1 * (1.0 - RIM_INSIDE), 0.0)?;
    let (c2, s2) = harmonic(&heights, 2);
    Some(Band {
        axis,
        radius: a.1,
        other: b.1,
        phase: s2.atan2(c2) / 2.0,
    })
}

/// How far inside a rim (a share of its radius) its heights are sampled:
/// a vertical line on the rim itself may pass beside a coarse mesh.
const RIM_INSIDE: f64 = 0.002;

/// Azimuths sampled round a circle for its heights.
const AZIMUTHS: usize = 72;

/// The target's heights above the circle of `radius` about `axis`, at
/// `AZIMUTHS` azimuths from `phase`; None where a vertical line misses it.
fn heights(t: &Target, axis: DVec3, radius: f64, phase: f64) -> Option<Vec<f64>> {
    let plumb = Plumb::new(t);
    (0..AZIMUTHS)
        .map(|k| {
            let a = phase + TAU * k as f64 / AZIMUTHS as f64;
            plumb.height(axis.truncate() + radius * glam::DVec2::from_angle(a))
        })
        .collect()
}

/// The cos and sin coefficients of harmonic `m` of heights sampled at
/// equal steps round a circle.
fn harmonic(z: &[f64], m: usize) -> (f64, f64) {
    let n = z.len() as f64;
    z.iter().enumerate().fold((0.0, 0.0), |(c, s), (k, h)| {
        let a = TAU * (m * k) as f64 / n;
        (c + 2.0 * h * a.cos() / n, s + 2.0 * h * a.sin() / n)
    })
}

/// The saddle fitted to the target round the circle of `radius`: c and d
/// from its heights' harmonics 2 and 6 about the band's high azimuth.
fn saddle_at(t: &Target, b: &Band, radius: f64) -> Option<Saddle> {
    let z = heights(t, b.axis, radius, b.phase)?;
    let r2 = radius * radius;
    Some(Saddle {
        c: harmonic(&z, 2).0 / r2,
        d: harmonic(&z, 6).0 / r2,
    })
}

/// The seed: `n` points of a level circle, point 1 at the high azimuth
/// (the saddle's t = 0 runs through vertex 1), laid on the saddle fitted
/// to the seed rim, the circle sized so that the laid points' mean radius
/// in plan is the rim's, and then moved so that their centroid stands on
/// the axis at the rim's mean height. Its edges are equal and it is four
/// sub-units alike, so every ring grown on it, and on fronts laid in turn,
/// closes for every direction (docs/math.md 6.2); row 0's front is laid on
/// the same saddle, which leaves it where it is. With that saddle; None when
/// the rim's heights cannot be read or the laying fails.
fn seed(t: &Target, b: &Band, n: usize) -> Option<(Vec<DVec3>, Saddle)> {
    let rim = b.radius * (1.0 - RIM_INSIDE);
    let saddle = saddle_at(t, b, rim)?;
    let mean = heights(t, b.axis, rim, b.phase)?.iter().sum::<f64>() / AZIMUTHS as f64;
    let circle = |radius: f64, z: f64| -> Vec<DVec3> {
        (0..n)
            .map(|j| {
                let a = b.phase + TAU * (j as f64 - 1.0) / n as f64;
                DVec3::new(b.axis.x + radius * a.cos(), b.axis.y + radius * a.sin(), z)
            })
            .collect()
    };
    // Laying keeps vertex 0 where it was, so the laid front stands off
    // the axis: it is measured about its own centroid, and moved back.
    let laid_about = |radius: f64| -> Option<(Vec<DVec3>, DVec3)> {
        let laid = crate::lattice::lay_on_saddle(&circle(radius, 0.0), saddle).ok()?;
        let centre = laid.iter().sum::<DVec3>() / n as f64;
        Some((laid, centre))
    };
    let mut radius = rim;
    for _ in 0..SIZING {
        let (laid, centre) = laid_about(radius)?;
        let r = laid
            .iter()
            .map(|p| (p - centre).truncate().length())
            .sum::<f64>()
            / n as f64;
        radius *= rim / r;
    }
    let (laid, centre) = laid_about(radius)?;
    let shift = DVec3::new(b.axis.x - centre.x, b.axis.y - centre.y, mean - centre.z);
    Some((laid.into_iter().map(|p| p + shift).collect(), saddle))
}

/// Rounds of sizing the seed's circle.
const SIZING: usize = 6;

/// Loops on a waved band: for each seed size (a multiple of four, so that
/// the saddle's four sub-units are alike) and ring step, rings grown one
/// at a time, each on its front laid on the fitted saddle and tilted so
/// that its new vertices lie nearest the target; each design with its last
/// rings left off, down to half of them. First the best of them polished
/// (`polish`), when polishing helps; then every one as grown.
pub(super) fn loops(
    ask: &DesignAsk<'_>,
    b: Band,
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> (Vec<Found>, Vec<Found>) {
    let t = &ask.target;
    let n0 = ((TAU * b.radius / ask.edge / 4.0).round() as usize * 4).max(8);
    let mut out = Vec::new();
    let mut best: Option<(f64, Vec<DVec3>, Vec<Ring>)> = None;
    'sizes: for n in [n0, n0.saturating_sub(4).max(8)] {
        let Some((points, first)) = seed(t, &b, n) else {
            continue;
        };
        for per_edge in RING_STEPS {
            if ask.deadline.is_some_and(|d| Instant::now() > d) {
                break 'sizes;
            }
            *tried += 1;
            let span = b.radius - b.other;
            let rings = ((span / (per_edge * ask.edge)).round() as usize).clamp(2, MAX_RINGS);
            progress(&format!(
                "loop of {n} points round the seed rim, {rings} rings {:.1} mm apart in plan, fronts laid on the fitted saddle",
                span / rings as f64
            ));
            let rows = grow(ask, &b, (&points, first), rings);
            for k in (rings.div_ceil(2).max(1)..=rows.len()).rev() {
                let Some(lattice) = buildable(ask.base, &points, &rows[..k]) else {
                    continue;
                };
                let fit = fit_of(t, &lattice);
                let miss = super::miss(&fit);
                if best.as_ref().is_none_or(|b| miss < b.0) {
                    best = Some((miss, points.clone(), rows[..k].to_vec()));
                }
                out.push(Found {
                    lattice: toml(&points, &rows[..k]),
                    cells: lattice.cells.len(),
                    fit,
                    seed: format!(
                        "a loop of {n} points round the seed rim, {k} of {rings} rings, every front laid on the saddle fitted to the target"
                    ),
                });
            }
        }
    }
    let mut first = Vec::new();
    match best.and_then(|(_, points, rows)| polished(ask, &b, &points, &rows, progress)) {
        Some((found, true)) => first.push(found),
        Some((found, false)) => out.push(found),
        None => {}
    }
    (first, out)
}

/// The best loop's rings polished (`polish`), when polishing helps and
/// `build` would take its strips; and whether every interior vertex is
/// negative, design and simulated (then it is built first, whatever its
/// fit; else ranked by its fit with the rest).
fn polished(
    ask: &DesignAsk<'_>,
    b: &Band,
    points: &[DVec3],
    rows: &[Ring],
    progress: &mut dyn FnMut(&str),
) -> Option<(Found, bool)> {
    let p = super::polish::polish(ask, (b, points, rows), progress)?;
    let lattice = buildable(ask.base, points, &p.rows)?;
    progress(&format!(
        "polished in {} designs: largest angle defect {:+.2} deg designed, {:+.2} deg simulated",
        p.evaluations, p.design.largest, p.simulated.largest
    ));
    let found = Found {
        lattice: toml(points, &p.rows),
        cells: lattice.cells.len(),
        fit: fit_of(&ask.target, &lattice),
        seed: format!(
            "a loop of {} points round the seed rim, {} rings, every front laid on the saddle fitted to the target, then each ring's aim and saddle polished over {} designs (docs/design.md, \"Polished rings\"): interior angle defects at most {:+.2} deg designed and {:+.2} deg simulated, ring-mean K within {:.2} x and {:.2} x ring to ring",
            points.len(),
            p.rows.len(),
            p.evaluations,
            p.design.largest,
            p.simulated.largest,
            p.design.k_ratio,
            p.simulated.k_ratio
        ),
    };
    Some((found, p.negative()))
}

/// A ring's target for x[i+1][1] and its front's saddle.
#[derive(Clone, Copy, Debug)]
pub(super) struct Ring {
    pub target: DVec3,
    pub saddle: Saddle,
}

/// Rings one at a time, as many as grow: ring i's vertex x[i+1][1]
/// aimed at the band's high azimuth at its planned radius, at the height
/// (scanned over an edge, then refined) that puts the new ring's vertices
/// nearest the target.
fn grow(ask: &DesignAsk<'_>, b: &Band, seed: (&[DVec3], Saddle), rings: usize) -> Vec<Ring> {
    let (points, first) = seed;
    let t = &ask.target;
    let mut rows: Vec<Ring> = Vec::new();
    let mut front_radius = b.radius * (1.0 - RIM_INSIDE);
    let u = DVec3::new(b.phase.cos(), b.phase.sin(), 0.0);
    for i in 1..=rings {
        let saddle = if i == 1 {
            Some(first)
        } else {
            saddle_at(t, b, front_radius)
        };
        let radius = b.radius - (b.radius - b.other) * i as f64 / rings as f64;
        let base = heights(t, b.axis, radius, b.phase).map(|z| z[0]);
        let (Some(saddle), Some(base)) = (saddle, base) else {
            break;
        };
        let at = |z: f64| Ring {
            target: b.axis.truncate().extend(0.0) + radius * u + z * DVec3::Z,
            saddle,
        };
        let Some((z, r)) = nearest_height(ask, b, points, &rows, &at, base) else {
            break;
        };
        rows.push(at(z));
        front_radius = r;
    }
    rows
}

/// The height of the next ring's target, scanned an edge either way of
/// `base` and refined, whose ring's vertices lie nearest the target (rms),
/// with that ring's mean radius in plan; None when no height grows.
fn nearest_height(
    ask: &DesignAsk<'_>,
    b: &Band,
    points: &[DVec3],
    rows: &[Ring],
    at: &dyn Fn(f64) -> Ring,
    base: f64,
) -> Option<(f64, f64)> {
    let t = &ask.target;
    let n = points.len();
    let score = |z: f64| -> Option<(f64, f64)> {
        let mut trial = rows.to_vec();
        trial.push(at(z));
        let l = grown(ask.base, points, &trial)?;
        let ring = &l.vertices[l.vertices.len() - n..];
        let ms = ring.iter().map(|v| t.closest(v.pos).1.powi(2)).sum::<f64>() / n as f64;
        let r = ring
            .iter()
            .map(|v| (v.pos - b.axis).truncate().length())
            .sum::<f64>()
            / n as f64;
        Some((ms.sqrt(), r))
    };
    let mut best: Option<(f64, f64, f64)> = None;
    let (mut step, mut centre) = (ask.edge / SCAN as f64, base);
    for _ in 0..REFINE {
        for k in -(SCAN as i64)..=SCAN as i64 {
            let z = centre + step * k as f64;
            if let Some((miss, r)) = score(z)
                && best.is_none_or(|bst| miss < bst.1)
            {
                best = Some((z, miss, r));
            }
        }
        centre = best?.0;
        step /= SCAN as f64;
    }
    best.map(|(z, _, r)| (z, r))
}

/// Heights scanned either way of a ring's start, and rounds of refining.
const SCAN: usize = 5;
const REFINE: usize = 3;

/// Ring steps tried, as shares of the cell edge (as `loops.rs`).
const RING_STEPS: [f64; 3] = [0.5, 0.7, 0.9];

/// Rings a loop grows at most.
const MAX_RINGS: usize = 40;

/// The loop's design: seed and rings.
pub(super) fn design(base: &Design, points: &[DVec3], rows: &[Ring]) -> Design {
    let rows = rows
        .iter()
        .map(|r| RowParams {
            target: Some(r.target),
            front: Some(FrontMoves {
                turn: None,
                bend: None,
                twist: None,
                saddle: Some(r.saddle),
                pivots: Vec::new(),
                cranks: Vec::new(),
            }),
            ..RowParams::default()
        })
        .collect();
    super::loops::symmetric_loop(base, points, rows)
}

/// The loop grown, when it grows.
fn grown(base: &Design, points: &[DVec3], rows: &[Ring]) -> Option<Lattice> {
    design(base, points, rows).grow().ok()
}

/// The loop, when it grows and `build` would take its strips.
fn buildable(base: &Design, points: &[DVec3], rows: &[Ring]) -> Option<Lattice> {
    super::loops::buildable(&design(base, points, rows))
}

/// The recipe's tables: the seed (`loops::seed_toml`), and each ring's
/// target point and saddle, at full precision.
fn toml(points: &[DVec3], rows: &[Ring]) -> String {
    let mut s = super::loops::seed_toml(points);
    for r in rows {
        let p = r.target;
        s.push_str(&format!(
            "\n[[lattice.rows]]\ntarget = [{:?}, {:?}, {:?}]\nfront = {{ saddle = [{:?}, {:?}] }}\n",
            p.x, p.y, p.z, r.saddle.c, r.saddle.d
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn target(text: &str) -> Target {
        crate::target::read("ring.toml", text.as_bytes(), None)
            .unwrap()
            .canonical()
    }

    /// The suite's saddle ring, z = 60 (r / 240)^2 cos 2t between r = 90
    /// and 240 (scripts/make-targets): its rims are found, the saddle
    /// fitted round any circle is c = 60 / 240^2 with no cos 6t, and the
    /// seed, laid on it, lies on the outer rim with equal edges.
    #[test]
    fn a_saddle_rings_band_saddle_and_seed_are_found() {
        let text =
            "[target]\nfamily = \"saddle-ring\"\nradius = 240.0\nhole = 90.0\nheight = 60.0\n";
        let t = target(text);
        let b = band(&t).expect("a waved band");
        assert!(
            (b.radius - 240.0).abs() < 0.5 && (b.other - 90.0).abs() < 0.5,
            "{b:?}"
        );
        let k = 60.0 / 240.0f64.powi(2);
        for r in [100.0, 170.0, 239.0] {
            let s = saddle_at(&t, &b, r).expect("heights");
            assert!(
                (s.c - k).abs() < 0.01 * k && s.d.abs() < 0.01 * k,
                "{r}: {s:?}"
            );
        }
        let (seed, _) = seed(&t, &b, 24).expect("a seed");
        let edge = seed[0].distance(seed[1]);
        for (j, p) in seed.iter().enumerate() {
            // On the saddle, which carries on past the rim where the laid
            // front draws out beyond it (in the target's own frame, the
            // band's high azimuth at b.phase).
            let q = *p - b.axis;
            let (r, a) = (q.truncate().length(), q.y.atan2(q.x) - b.phase);
            let z = k * r * r * (2.0 * a).cos();
            assert!(
                (p.z - b.axis.z - z).abs() < 0.5,
                "seed point {j}: z {} against {z}",
                p.z
            );
            // The laid front is no circle in plan: where it climbs, it
            // draws in.
            assert!(
                (r - 240.0).abs() < 0.02 * 240.0,
                "seed point {j} at radius {r}"
            );
            let e = p.distance(seed[(j + 1) % seed.len()]);
            assert!((e - edge).abs() < 1e-9 * edge, "edge {j}");
        }
    }

    /// A negative height puts the high points a quarter turn round: the
    /// fitted saddle about them is the same, c = |height| / radius^2.
    #[test]
    fn a_negative_height_turns_the_high_azimuth_a_quarter_turn() {
        let up = target(
            "[target]\nfamily = \"saddle-ring\"\nradius = 200.0\nhole = 80.0\nheight = 40.0\n",
        );
        let down = target(
            "[target]\nfamily = \"saddle-ring\"\nradius = 200.0\nhole = 80.0\nheight = -40.0\n",
        );
        let (a, b) = (band(&up).unwrap(), band(&down).unwrap());
        let turn = (a.phase - b.phase).rem_euclid(std::f64::consts::PI);
        assert!(
            (turn - std::f64::consts::FRAC_PI_2).abs() < 1e-3,
            "{a:?} {b:?}"
        );
        let k = 40.0 / 200.0f64.powi(2);
        for (t, band) in [(&up, a), (&down, b)] {
            let s = saddle_at(t, &band, 150.0).unwrap();
            assert!((s.c - k).abs() < 0.01 * k, "{s:?}");
        }
    }

    /// A level band (the suite's saddle band) is also a waved band's
    /// shape in plan; a cap has one rim, and a band whose rims are not
    /// about one axis none.
    #[test]
    fn only_a_band_round_in_plan_about_one_axis_is_waved() {
        let cap = target("[target]\nfamily = \"sphere-cap\"\nradius = 300.0\nheight = 120.0\n");
        assert!(band(&cap).is_none());
        let tube = target(
            "[target]\nfamily = \"cylinder\"\nradius = 150.0\nlength = 300.0\nangle = 360.0\n",
        );
        assert!(band(&tube).is_none(), "a tube's rims stand side by side");
    }
}
