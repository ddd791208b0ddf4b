//! Loops round rounded boxes, for a bump on a sheet longer than wide or
//! with the bump off its middle. A circle about the bump's axis covers
//! only the disk inside the sheet's nearest sides; a superellipse
//! inscribed in the sheet's least box reaches into its corners. Its
//! points at equal chords at one height close every ring as a level
//! rim's do (`level::loops`; docs/design.md, "Rounded boxes").

use super::{DesignAsk, Found, Plumb, level};
use crate::design::fit::segment_distance;
use crate::target::{COVERED_WITHIN, Target};
use glam::{DVec2, DVec3};

/// Superellipse exponents tried: 2 is the ellipse inscribed in the box,
/// 4 comes near its corners.
const EXPONENTS: [f64; 3] = [2.0, 3.0, 4.0];

/// Corners of a rounded box's polygon (its chords are 1 % of a cell's
/// at most on a 600 mm sheet).
const CORNERS: usize = 400;

/// The share of a rounded box's vertical lines, a hair inside it, that
/// must meet the target (a line through a mesh's edge may miss it).
const OVER: f64 = 0.9;

/// The least-area rectangle about a plan polygon: its centre, the unit
/// direction of its first side and its half sides along that and across.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Frame {
    pub centre: DVec2,
    pub u: DVec2,
    pub half: DVec2,
}

/// The least-area rectangle about `plan`: one of its sides lies along an
/// edge of the convex hull (Freeman and Shapira), so each edge is tried.
pub(super) fn least_box(plan: &[DVec2]) -> Option<Frame> {
    let hull = hull(plan);
    let mut best: Option<(f64, Frame)> = None;
    for k in 0..hull.len() {
        let Some(u) = (hull[(k + 1) % hull.len()] - hull[k]).try_normalize() else {
            continue;
        };
        let v = u.perp();
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for p in &hull {
            let q = DVec2::new(p.dot(u), p.dot(v));
            lo = lo.min(q);
            hi = hi.max(q);
        }
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        let frame = Frame {
            centre: mid.x * u + mid.y * v,
            u,
            half,
        };
        let area = half.x * half.y;
        // Ties (a rectangle's opposite sides) keep the first edge found.
        if best.is_none_or(|(a, _)| area < a * (1.0 - 1e-9)) {
            best = Some((area, frame));
        }
    }
    best.map(|(_, f)| f).filter(|f| f.half.min_element() > 0.0)
}

/// The convex hull of `points`, counterclockwise (Andrew's monotone
/// chain); collinear points are left out.
fn hull(points: &[DVec2]) -> Vec<DVec2> {
    let mut p = points.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let turn = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut h: Vec<DVec2> = Vec::with_capacity(2 * p.len());
    for pass in [&p[..], &p.iter().rev().copied().collect::<Vec<_>>()[..]] {
        let start = h.len();
        for &q in pass {
            while h.len() >= start + 2 && turn(h[h.len() - 2], h[h.len() - 1], q) <= 0.0 {
                h.pop();
            }
            h.push(q);
        }
        h.pop();
    }
    h
}

/// The superellipse |x / a|^p + |y / b|^p = 1 inscribed in `frame`, as
/// `CORNERS` plan points counterclockwise.
pub(super) fn superellipse(frame: &Frame, p: f64) -> Vec<DVec2> {
    let v = frame.u.perp();
    let bend = |c: f64| c.signum() * c.abs().powf(2.0 / p);
    (0..CORNERS)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / CORNERS as f64;
            frame.centre + frame.half.x * bend(t.cos()) * frame.u + frame.half.y * bend(t.sin()) * v
        })
        .collect()
}

/// A rounded box over the target: its exponent, its plan polygon and the
/// target's mean height round it, where the seed is laid.
pub(super) struct Rounded {
    pub exponent: f64,
    pub ring: Vec<DVec2>,
    pub z: f64,
}

/// The rounded boxes inscribed in the least box about the patch's
/// `boundary` whose vertical lines meet the target (an L-shaped sheet's
/// do not), with the box.
pub(super) fn boxes(t: &Target, boundary: &[DVec3]) -> Option<(Frame, Vec<Rounded>)> {
    let plan: Vec<DVec2> = boundary.iter().map(|p| p.truncate()).collect();
    let frame = least_box(&plan)?;
    let plumb = Plumb::new(t);
    let mut out = Vec::new();
    for exponent in EXPONENTS {
        let ring = superellipse(&frame, exponent);
        let heights: Vec<f64> = ring
            .iter()
            .filter_map(|&q| plumb.height(frame.centre.lerp(q, 0.99)))
            .collect();
        if (heights.len() as f64) < OVER * ring.len() as f64 {
            continue;
        }
        let z = heights.iter().sum::<f64>() / heights.len() as f64;
        out.push(Rounded { exponent, ring, z });
    }
    Some((frame, out))
}

/// The box's sides, the longer first, for the recipe's comments: "480 x
/// 320 mm".
pub(super) fn sides(frame: &Frame) -> String {
    let (a, b) = (frame.half.max_element(), frame.half.min_element());
    format!("{:.0} x {:.0} mm", 2.0 * a, 2.0 * b)
}

/// Loops at equal chords round each rounded box, their rings stepping
/// down the meridian towards the bump's `axis` (`level::loops`): a bump
/// off the box's middle is climbed where it stands.
pub(super) fn loops(
    ask: &DesignAsk<'_>,
    (frame, boxes): (&Frame, &[Rounded]),
    axis: DVec2,
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Vec<Found> {
    let mut out = Vec::new();
    for b in boxes {
        let what = format!(
            "at equal chords round the rounded box (a superellipse of exponent {}) inscribed in the sheet's least box, {}",
            b.exponent,
            sides(frame)
        );
        let rim: Vec<DVec3> = b.ring.iter().map(|p| p.extend(b.z)).collect();
        let grown = level::loops(ask, (&rim, b.z), Some(axis), &what, tried, progress);
        let exponent = format!("the rounded box of exponent {}", b.exponent);
        progress(&super::bump::grown_line(&exponent, &grown));
        out.extend(grown);
    }
    out
}

/// The share of the target's area (by its triangles' centres) that lies,
/// in plan, within the closed polygon `ring` or within `COVERED_WITHIN`
/// of D of it.
pub(super) fn share(t: &Target, ring: &[DVec2]) -> f64 {
    let band = COVERED_WITHIN * t.extent;
    area_share(t, |c| encloses(ring, c) || distance(ring, c) <= band)
}

/// The share of the target's area whose triangles' centres, in plan,
/// `inside` takes.
pub(super) fn area_share(t: &Target, inside: impl Fn(DVec2) -> bool) -> f64 {
    let (mut within, mut all) = (0.0, 0.0);
    for k in 0..t.mesh.triangles.len() {
        let c = (t.mesh.corners(k).iter().sum::<DVec3>() / 3.0).truncate();
        let a = t.mesh.triangle_area(k);
        all += a;
        if inside(c) {
            within += a;
        }
    }
    if all > 0.0 { within / all } else { 0.0 }
}

/// Whether the closed polygon `ring` encloses `p` (crossings of a ray
/// along +x).
fn encloses(ring: &[DVec2], p: DVec2) -> bool {
    let mut inside = false;
    for k in 0..ring.len() {
        let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

/// The plan distance from `p` to the closed polygon `ring`.
pub(super) fn distance(ring: &[DVec2], p: DVec2) -> f64 {
    (0..ring.len())
        .map(|k| segment_distance(p, ring[k], ring[(k + 1) % ring.len()]))
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The least box about a rectangle turned by any angle, with points
    /// along its sides and inside, is the rectangle itself; about a
    /// right triangle, twice its area.
    #[test]
    fn the_least_box_about_a_turned_rectangle_is_the_rectangle() {
        for k in 0..24 {
            let a = 0.13 + 0.27 * k as f64;
            let (u, v) = (DVec2::from_angle(a), DVec2::from_angle(a).perp());
            let at = |x: f64, y: f64| DVec2::new(30.0, -20.0) + x * u + y * v;
            let mut plan = Vec::new();
            for i in 0..=8 {
                let f = -1.0 + 0.25 * i as f64;
                plan.extend([at(240.0 * f, -160.0), at(240.0, 160.0 * f)]);
                plan.extend([at(-240.0 * f, 160.0), at(-240.0, -160.0 * f)]);
                plan.push(at(100.0 * f, 50.0 * f));
            }
            let f = least_box(&plan).expect("a box");
            let halves = [f.half.max_element(), f.half.min_element()];
            assert!(
                (halves[0] - 240.0).abs() < 1e-9 && (halves[1] - 160.0).abs() < 1e-9,
                "{f:?}"
            );
            assert!(f.centre.distance(DVec2::new(30.0, -20.0)) < 1e-9, "{f:?}");
            let along = if f.half.x > f.half.y { f.u } else { f.u.perp() };
            assert!(along.perp_dot(u).abs() < 1e-9, "{f:?}");
        }
        let f = least_box(&[DVec2::ZERO, DVec2::new(4.0, 0.0), DVec2::new(0.0, 3.0)]).unwrap();
        assert!((4.0 * f.half.x * f.half.y - 12.0).abs() < 1e-9, "{f:?}");
    }

    /// A superellipse's points lie on it, inside its box, touching each
    /// side; exponent 2 is the ellipse, whose area it encloses.
    #[test]
    fn a_rounded_box_lies_on_its_superellipse_inside_its_box() {
        let frame = Frame {
            centre: DVec2::new(10.0, 5.0),
            u: DVec2::from_angle(0.4),
            half: DVec2::new(240.0, 160.0),
        };
        for p in EXPONENTS {
            let ring = superellipse(&frame, p);
            let local = |q: DVec2| {
                let d = q - frame.centre;
                DVec2::new(d.dot(frame.u) / 240.0, d.dot(frame.u.perp()) / 160.0)
            };
            for q in &ring {
                let l = local(*q);
                assert!((l.x.abs().powf(p) + l.y.abs().powf(p) - 1.0).abs() < 1e-9);
            }
            let reach = ring
                .iter()
                .map(|q| local(*q).abs())
                .fold(DVec2::ZERO, DVec2::max);
            assert!((reach - DVec2::ONE).length() < 1e-9, "{reach}");
        }
        let ellipse = superellipse(&frame, 2.0);
        let area: f64 = (0..CORNERS)
            .map(|k| 0.5 * ellipse[k].perp_dot(ellipse[(k + 1) % CORNERS]))
            .sum();
        let exact = std::f64::consts::PI * 240.0 * 160.0;
        assert!((area - exact).abs() < 1e-3 * exact, "{area}");
    }

    /// The share inside a polygon and the band about it: a square of
    /// side 200 on a plate of side 400 holds a quarter of its area, and
    /// the band of 3 % of D (17 mm) about it no more of its triangles.
    #[test]
    fn the_share_of_a_plate_within_a_square_and_its_band() {
        let text = "[target]\nfamily = \"height-field\"\nwidth = 400.0\nlength = 400.0\nheights = [[0, 0, 0, 0, 0], [0, 0, 0, 0, 0], [0, 0, 0, 0, 0], [0, 0, 0, 0, 0], [0, 0, 0, 0, 0]]\n";
        let t = crate::target::read("t.toml", text.as_bytes(), None)
            .unwrap()
            .canonical();
        let c = t.mesh.positions.iter().sum::<DVec3>().truncate() / t.mesh.positions.len() as f64;
        let square: Vec<DVec2> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .iter()
            .map(|&(x, y)| c + 100.0 * DVec2::new(x, y))
            .collect();
        // Triangles on a grid of squares of side 100: those inside the
        // square of side 200 are a quarter of them, and the next ones'
        // centres lie a third of a square or more past its sides.
        let s = share(&t, &square);
        assert!((s - 0.25).abs() < 1e-9, "{s}");
        assert!(encloses(&square, c) && !encloses(&square, c + DVec2::new(110.0, 0.0)));
        assert!((distance(&square, c + DVec2::new(150.0, 30.0)) - 50.0).abs() < 1e-9);
    }
}
