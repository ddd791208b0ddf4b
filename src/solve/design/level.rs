//! Loops round a level rim that is not a circle, such as an oval cap's
//! (a bump's rectangular sheet is tried too, but its corner cells fold:
//! docs/design.md, "Level rims"). Points at equal chords
//! round any level closed polygon, with kappa 0, close every ring for
//! every direction, as points evenly round a circle do (docs/design.md,
//! "Level rims"), so each ring's vertex x[i+1][1] is put on the target
//! one step further down its meridian, as on a round rim.

use super::loops::{HOLE, Seed, counts, grow_rings, meridian};
use super::{DesignAsk, Found};
use glam::{DVec2, DVec3};

/// A level rim: every boundary corner within this share of D of the
/// corners' mean height, where the seed is laid (a bump's sheet rises a
/// little at the middle of its sides: height-field.toml 0.6 %).
const LEVEL: f64 = 0.01;

/// The rim's mean height, when the boundary (at least 8 corners) is level.
pub(super) fn level(boundary: &[DVec3], extent: f64) -> Option<f64> {
    let z = boundary.iter().map(|p| p.z).sum::<f64>() / boundary.len().max(1) as f64;
    let level = boundary.iter().all(|p| (p.z - z).abs() <= LEVEL * extent);
    (level && boundary.len() >= 8).then_some(z)
}

/// A cap on a level rim: the rim's height, when the boundary is level
/// and the target stands more than 3 % of D off it (a plate does not;
/// `cells_per_square` counts a cap's loops).
pub(super) fn cap(t: &crate::target::Target, boundary: &[DVec3]) -> Option<f64> {
    let z = level(boundary, t.extent)?;
    (depth(t, z) > 0.03 * t.extent).then_some(z)
}

/// How far the target stands off the plane z = `z` at most.
fn depth(t: &crate::target::Target, z: f64) -> f64 {
    t.mesh
        .positions
        .iter()
        .map(|p| (p.z - z).abs())
        .fold(0.0, f64::max)
}

/// Loops of an even number of points at equal chords round the level
/// `boundary` at height `z` (near one cell edge apart, and two fewer),
/// their rings stepping down the meridian from the seed's point 1
/// towards the plan point `towards`, or the rim's centroid
/// (`loops::grow_rings`); `what` says where the seed lies, for the
/// recipe's comment.
pub(super) fn loops(
    ask: &DesignAsk<'_>,
    (boundary, z): (&[DVec3], f64),
    towards: Option<DVec2>,
    what: &str,
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Vec<Found> {
    // Counterclockwise seen from +z, as `loops::level_loop`'s circles.
    let mut plan: Vec<DVec2> = boundary.iter().map(|p| p.truncate()).collect();
    if signed_area(&plan) < 0.0 {
        plan.reverse();
    }
    let centre = towards.unwrap_or_else(|| centroid(&plan)).extend(z);
    let mut out = Vec::new();
    for n in counts(Polyline::new(&plan).length(), ask.edge) {
        let Some(points) = equal_chords(&plan, n) else {
            continue;
        };
        let points: Vec<DVec3> = points.iter().map(|p| p.extend(z)).collect();
        let Some(meridian) = meridian(&ask.target, centre, points[1]) else {
            continue;
        };
        let length = (1.0 - HOLE) * meridian.last().map_or(0.0, |m| m.0);
        let seed = Seed {
            points: &points,
            meridian: &meridian,
            span: (0.0, length),
            what,
            closed: false,
        };
        out.extend(grow_rings(ask, &seed, tried, progress));
    }
    out
}

/// A cap on a level rim that is not a circle (an oval cap's), in mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OvalRim {
    /// The longer side of the rim's least box in plan.
    pub long: f64,
    /// The shorter side.
    pub short: f64,
    /// How far the cap stands off the rim's plane.
    pub depth: f64,
}

/// How many times as long as wide an oval rim may be before a design
/// that misses is told to take a rounder or shallower cap: caps met the
/// goal up to 1.6 times at any depth measured (200 x 125 x 80 mm semi-axes,
/// 1.44 % of D rms), and 1.67 (250 x 150 x 60) when shallow;
/// 200 x 118 x 80 (1.69 times) missed (docs/design.md, "Level rims").
const LONG: f64 = 1.6;

/// How deep, as a share of its half width, a cap on a rim twice as long
/// as wide met the goal: 200 x 100 mm semi-axes 40 mm deep did (1.34 % of
/// D rms), 60 and 80 mm deep missed.
const SHALLOW: f64 = 0.4;

impl OvalRim {
    /// The rim of the cap `t` (level at `z`, `boundary` in plan).
    pub(super) fn of(t: &crate::target::Target, boundary: &[DVec3], z: f64) -> Option<OvalRim> {
        let plan: Vec<DVec2> = boundary.iter().map(|p| p.truncate()).collect();
        let frame = super::rounded::least_box(&plan)?;
        Some(OvalRim {
            long: 2.0 * frame.half.max_element(),
            short: 2.0 * frame.half.min_element(),
            depth: depth(t, z),
        })
    }

    /// What to try when a loop round this rim misses the goal: on a rim
    /// more than `LONG` times as long as wide, a rounder rim, or a
    /// shallower cap when this one is deeper than `SHALLOW` of its half
    /// width (thinner strips and a smaller edge, the goal's own hints,
    /// measured no better); None on a rounder rim, for the goal's own
    /// hints. The caller asks only of a loop (a sheet's rows stop for
    /// their own reasons).
    pub fn remedy(&self) -> Option<String> {
        let ratio = self.long / self.short;
        if ratio <= LONG {
            return None;
        }
        let shallow = SHALLOW * self.short / 2.0;
        let shallower = if self.depth > shallow {
            format!(", or a cap on this rim at most about {shallow:.0} mm deep,")
        } else {
            String::new()
        };
        Some(format!(
            "the cap's rim is {:.0} x {:.0} mm, {ratio:.1} times as long as wide, and the cap stands {:.0} mm deep: a loop's rings step in from the rim at one pace, so they meet along its long sides while its ends are still open, and the strips settle away from the cap there; thinner strips and a smaller edge measured no better on such a cap (docs/design.md, \"Level rims\"); a rim at most about {LONG} times as long as wide, such as {:.0} x {:.0} mm{shallower} is designed within the goal",
            self.long,
            self.short,
            self.depth,
            self.long,
            self.long / LONG,
        ))
    }
}

/// The recipe's `# Topology:` line when loops round a level rim grew:
/// after a round bump's (`bump`) it is said as well; else it replaces
/// the sheets' line.
pub(super) fn topology(before: &str, bump: bool) -> String {
    const LOOPS: &str = "loops of points at equal chords round its level boundary close every ring as points evenly round a circle do, so their rings step down the target from the rim as on a cap (docs/design.md, \"Level rims\")";
    if bump {
        format!("{before}; and {LOOPS}")
    } else {
        format!(
            "loop or sheet (the seed below says which): the target is an open patch whose boundary is level but not a circle: {LOOPS}, and sheets grow from stretches of its boundary across it (docs/math.md 6.1)"
        )
    }
}

/// Twice the signed area of a closed polygon (positive counterclockwise).
fn signed_area(p: &[DVec2]) -> f64 {
    (0..p.len())
        .map(|k| p[k].perp_dot(p[(k + 1) % p.len()]))
        .sum()
}

/// The centroid of a closed polygon's area.
fn centroid(p: &[DVec2]) -> DVec2 {
    let (mut c, mut a) = (DVec2::ZERO, 0.0);
    for k in 0..p.len() {
        let (u, v) = (p[k], p[(k + 1) % p.len()]);
        let w = u.perp_dot(v);
        c += (u + v) * w;
        a += w;
    }
    if a.abs() > 0.0 {
        c / (3.0 * a)
    } else {
        p.iter().sum::<DVec2>() / p.len().max(1) as f64
    }
}

/// A closed polyline walked by arc length.
struct Polyline<'a> {
    corners: &'a [DVec2],
    /// Arc length at each corner, and the whole length last.
    at: Vec<f64>,
}

impl<'a> Polyline<'a> {
    fn new(corners: &'a [DVec2]) -> Self {
        let n = corners.len();
        let mut at = Vec::with_capacity(n + 1);
        at.push(0.0);
        for k in 0..n {
            let walked = at[k] + corners[k].distance(corners[(k + 1) % n]);
            at.push(walked);
        }
        Polyline { corners, at }
    }

    fn length(&self) -> f64 {
        *self.at.last().expect("a corner")
    }

    /// The point at arc length `s` (taken round the loop).
    fn point(&self, s: f64) -> DVec2 {
        let n = self.corners.len();
        let s = s.rem_euclid(self.length());
        let k = (self.at.partition_point(|&a| a <= s) - 1).min(n - 1);
        let span = self.at[k + 1] - self.at[k];
        let u = if span > 0.0 {
            (s - self.at[k]) / span
        } else {
            0.0
        };
        self.corners[k].lerp(self.corners[(k + 1) % n], u)
    }

    /// The first arc length past `from` whose point lies `chord` from
    /// `from`'s, found by steps of an eighth of the chord, then halving.
    fn next(&self, from: f64, chord: f64) -> Option<f64> {
        let p = self.point(from);
        let step = chord / 8.0;
        let mut lo = from;
        loop {
            let hi = lo + step;
            if hi > from + self.length() {
                return None;
            }
            if self.point(hi).distance(p) >= chord {
                let mut lo = lo;
                let mut hi = hi;
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if self.point(mid).distance(p) >= chord {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return Some(hi);
            }
            lo = hi;
        }
    }

    /// Where `n` chords of length `chord` from arc length `start` end.
    fn walk(&self, start: f64, chord: f64, n: usize) -> Option<Vec<f64>> {
        let mut s = vec![start];
        for _ in 0..n {
            s.push(self.next(*s.last().expect("a start"), chord)?);
        }
        Some(s)
    }
}

/// `n` points round the closed polygon `ring` with equal chords, the
/// first at the corner farthest from its centroid (an oval's end): the
/// chord is halved until `n` of them come back to the first point.
pub(super) fn equal_chords(ring: &[DVec2], n: usize) -> Option<Vec<DVec2>> {
    let line = Polyline::new(ring);
    let total = line.length();
    if ring.len() < 3 || n < 3 || !(total > 0.0) {
        return None;
    }
    let c = centroid(ring);
    let first = (0..ring.len())
        .max_by(|&a, &b| ring[a].distance(c).total_cmp(&ring[b].distance(c)))
        .expect("corners");
    let start = line.at[first];
    let end = start + total;
    // A chord no longer than its arc: n arcs of total / n reach the end.
    let (mut lo, mut hi) = (0.0, total / n as f64);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        match line.walk(start, mid, n) {
            Some(s) if s[n] <= end => lo = mid,
            _ => hi = mid,
        }
    }
    let s = line.walk(start, lo, n - 1)?;
    let points: Vec<DVec2> = s.iter().map(|&s| line.point(s)).collect();
    // The last chord, back to the first point, as long as the others.
    let last = points[n - 1].distance(points[0]);
    ((last - lo).abs() <= 1e-9 * lo).then_some(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` corners round the ellipse of semi-axes `a` and `b`.
    fn oval(a: f64, b: f64, n: usize) -> Vec<DVec2> {
        (0..n)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                DVec2::new(a * t.cos(), b * t.sin())
            })
            .collect()
    }

    /// Points at equal chords round an ellipse and round a rectangle: n of
    /// them, every chord the same to 1e-9 of it; on the rectangle each
    /// lies on a side.
    #[test]
    fn points_at_equal_chords_round_an_oval_and_a_rectangle() {
        let oval = oval(200.0, 150.0, 400);
        let rectangle = [
            DVec2::new(-240.0, -160.0),
            DVec2::new(240.0, -160.0),
            DVec2::new(240.0, 160.0),
            DVec2::new(-240.0, 160.0),
        ];
        for (ring, n) in [(&oval[..], 20), (&oval[..], 9), (&rectangle[..], 26)] {
            let p = equal_chords(ring, n).expect("points");
            assert_eq!(p.len(), n);
            let chords: Vec<f64> = (0..n).map(|k| p[k].distance(p[(k + 1) % n])).collect();
            let c = chords[0];
            assert!(
                chords.iter().all(|d| (d - c).abs() <= 1e-9 * c),
                "{chords:?}"
            );
            let line = Polyline::new(ring);
            // Near the arc's share: a chord is a little shorter than its arc.
            assert!(c <= line.length() / n as f64 && c > 0.95 * line.length() / n as f64);
        }
        let on_a_side = |p: &DVec2| {
            (p.x.abs() - 240.0).abs() < 1e-9 && p.y.abs() <= 160.0 + 1e-9
                || (p.y.abs() - 160.0).abs() < 1e-9 && p.x.abs() <= 240.0 + 1e-9
        };
        assert!(equal_chords(&rectangle, 26).unwrap().iter().all(on_a_side));
        // The first point at an end of the oval's long axis.
        let p = equal_chords(&oval, 20).unwrap();
        assert!(
            (p[0].x.abs() - 200.0).abs() < 1e-9 && p[0].y.abs() < 1e-9,
            "{:?}",
            p[0]
        );
    }

    /// docs/design.md, "Level rims": kappa 0 and every chord the same make
    /// each cell's reflections a turn about the rim plane's normal by the
    /// turning at a corner, 2 pi round the loop, so a loop at equal chords
    /// round any oval closes for every direction, as points evenly round a
    /// circle do; and its rings, grown towards targets down an ellipsoid,
    /// close so too. Over random ovals and point counts.
    #[test]
    fn loops_at_equal_chords_round_an_oval_close_for_every_direction() {
        let mut rng = crate::rng::Rng::new(7);
        for _ in 0..40 {
            let (a, b) = (150.0 + 100.0 * rng.uniform(), 80.0 + 70.0 * rng.uniform());
            let c = 60.0 + 80.0 * rng.uniform();
            let n = 2 * (8 + (rng.uniform() * 8.0) as usize);
            let points: Vec<DVec3> = equal_chords(&oval(a, b, 240), n)
                .expect("points")
                .iter()
                .map(|p| p.extend(0.0))
                .collect();
            let mut g =
                crate::lattice::Grower::new(crate::lattice::Kind::Loop, 3, &points, &vec![0.0; n])
                    .unwrap();
            // Two rings, each vertex 1 aimed 0.15 and 0.3 of the way in,
            // on the ellipsoid below the rim.
            for f in [0.85, 0.7] {
                let p = points[1] * f;
                let z = -c
                    * (1.0 - (p.x / a).powi(2) - (p.y / b).powi(2))
                        .max(0.0)
                        .sqrt();
                let row = crate::lattice::RowParams {
                    target: Some(DVec3::new(p.x, p.y, z)),
                    ..Default::default()
                };
                g.grow_row(&row)
                    .unwrap_or_else(|e| panic!("{a} {b} {c} {n}: {}", e.message));
            }
            assert_eq!(g.closures.len(), 2);
            assert!(g.closures.iter().all(|r| r.free), "{a} {b} {n}");
        }
    }

    /// An oval cap's rim, read from its target: 200 x 100 mm semi-axes
    /// give a 400 x 200 mm box, 80 mm deep. Twice as long as wide, a miss
    /// is told to take a rim 1.6 times as long as wide or a cap 40 mm deep
    /// (both measured within the goal), a shallow one only the rounder
    /// rim; a rim 1.33 times is left to the goal's own hints.
    #[test]
    fn a_long_oval_caps_rim_and_what_to_try() {
        let rim = |axes: &str| {
            let text = format!("[target]\nfamily = \"spheroid-cap\"\naxes = [{axes}]\n");
            let t = crate::target::read("t.toml", text.as_bytes(), None)
                .unwrap()
                .canonical();
            let boundary = super::super::sheets::inward_boundary(&t);
            let z = cap(&t, &boundary).expect("a cap on a level rim");
            OvalRim::of(&t, &boundary, z).expect("a box")
        };
        let long = rim("200.0, 100.0, 80.0");
        assert!(
            (long.long - 400.0).abs() < 4.0
                && (long.short - 200.0).abs() < 2.0
                && (long.depth - 80.0).abs() < 1.0,
            "{long:?}"
        );
        let hint = long.remedy().expect("a rounder or shallower cap");
        assert!(
            hint.starts_with("the cap's rim is 400 x 200 mm, 2.0 times as long as wide")
                && hint.contains(
                    "such as 400 x 250 mm, or a cap on this rim at most about 40 mm deep"
                ),
            "{hint}"
        );
        assert_eq!(rim("200.0, 150.0, 100.0").remedy(), None);
        // Shallow already: only the rounder rim.
        let shallow = rim("250.0, 80.0, 30.0");
        let hint = shallow.remedy().expect("a rounder rim");
        assert!(
            hint.contains("such as 500 x 312 mm is designed") && !hint.contains("deep,"),
            "{hint}"
        );
    }
}
