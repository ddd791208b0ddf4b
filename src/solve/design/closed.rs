//! Closed targets for `karigami design` (docs/design.md, "Design your own
//! object"): a closed surface of revolution (a sphere, a spheroid, an egg)
//! grows a symmetric loop from a small level circle near one pole to one
//! near the other, each ring's vertex put on the target's meridian
//! (docs/math.md 6.2). The polar caps a loop leaves open count against the
//! coverage, which is measured on the whole closed target.

use super::loops::{Seed, along, grow_rings, level_loop};
use super::{DesignAsk, Found};
use crate::target::Target;
use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// Share of D within which the surface's distance from its centre must be
/// the same at every azimuth for it to count as a surface of revolution.
pub(super) const ROUND: f64 = 0.01;

/// Polar and azimuthal rays of the test of revolution.
const POLAR: usize = 24;
const AZIMUTHS: usize = 16;

/// Samples of a closed meridian, pole to pole.
const MERIDIAN: usize = 400;

/// A seed loop's spacing near the pole, as shares of the cell edge: the
/// smaller, the smaller the caps it leaves open.
const POLAR_SPACINGS: [f64; 2] = [0.25, 0.4];

/// How a closed target is, or is not, a surface of revolution.
#[derive(Clone, Copy, Debug)]
pub(super) enum Revolved {
    /// Of revolution about `axis` (a unit vector through the origin, the
    /// centroid), its distance from the centre the same at every azimuth
    /// within `spread` (mm).
    About { axis: DVec3, spread: f64 },
    /// Star-shaped about its centre but round about none of its principal
    /// axes: the least `spread` (mm) found.
    NotRound { spread: f64 },
    /// A ray from the centroid misses it or crosses it more than once: not
    /// star-shaped about its centre, so its meridian is not one curve of
    /// rays.
    NotStar,
}

/// Whether the target (in its own frame, `Target::canonical`: the
/// centroid at the origin, its principal axes along x, y, z) is a surface
/// of revolution about one of its principal axes: rays from the centroid
/// at `POLAR` polar angles and `AZIMUTHS` azimuths about each axis, the
/// distances at one polar angle within `ROUND` of D of each other.
pub(super) fn revolved(t: &Target) -> Revolved {
    let mut best: Option<(DVec3, f64)> = None;
    for axis in [DVec3::Z, DVec3::X, DVec3::Y] {
        let Some(spread) = spread_about(t, axis) else {
            return Revolved::NotStar;
        };
        if best.is_none_or(|(_, s)| spread < s) {
            best = Some((axis, spread));
        }
    }
    let (axis, spread) = best.expect("three axes");
    if spread <= ROUND * t.extent {
        Revolved::About { axis, spread }
    } else {
        Revolved::NotRound { spread }
    }
}

/// The largest spread over azimuth of the distance from the origin to the
/// target along rays at one polar angle about `axis`; None when a ray
/// misses the target or crosses it twice.
fn spread_about(t: &Target, axis: DVec3) -> Option<f64> {
    let (e1, e2) = axis.any_orthonormal_pair();
    let mut worst = 0.0f64;
    for i in 0..POLAR {
        let phi = PI * (i as f64 + 0.5) / POLAR as f64;
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for k in 0..AZIMUTHS {
            let theta = TAU * k as f64 / AZIMUTHS as f64;
            let v = phi.sin() * (theta.cos() * e1 + theta.sin() * e2) + phi.cos() * axis;
            let rho = once(t, v)?;
            lo = lo.min(rho);
            hi = hi.max(rho);
        }
        worst = worst.max(hi - lo);
    }
    Some(worst)
}

/// The distance from the origin to the target along the unit ray `v`, when
/// the ray crosses it exactly once.
fn once(t: &Target, v: DVec3) -> Option<f64> {
    let rho = t.ray(DVec3::ZERO, v, 0.0)?;
    t.ray(DVec3::ZERO, v, rho + 1e-6 * t.extent)
        .is_none()
        .then_some(rho)
}

/// The meridian of a target of revolution about z through the origin, at
/// azimuth `theta`: rays from the origin from near the top pole to near
/// the bottom one, as (arc length, point) pairs; None when a ray misses.
pub(super) fn meridian(t: &Target, theta: f64) -> Option<Vec<(f64, DVec3)>> {
    let mut out: Vec<(f64, DVec3)> = Vec::with_capacity(MERIDIAN + 1);
    for k in 0..=MERIDIAN {
        // Half a step off each pole, where a ray could graze a corner.
        let phi = PI * (k as f64 + 0.5) / (MERIDIAN + 1) as f64;
        let v = DVec3::new(phi.sin() * theta.cos(), phi.sin() * theta.sin(), phi.cos());
        let q = t.ray(DVec3::ZERO, v, 0.0)? * v;
        let walked = out.last().map_or(0.0, |&(s, p)| s + p.distance(q));
        out.push((walked, q));
    }
    Some(out)
}

/// The distance of a point from the z axis.
fn radius(p: DVec3) -> f64 {
    p.truncate().length()
}

/// The arc length from the start of `meridian` at which a loop of `n`
/// points round the axis first spaces them `spacing` apart (a chord of
/// 2 r sin(pi / n)); None when it never does.
fn polar_arc(meridian: &[(f64, DVec3)], n: usize, spacing: f64) -> Option<f64> {
    let r = spacing / (2.0 * (PI / n as f64).sin());
    meridian
        .iter()
        .find(|(_, p)| radius(*p) >= r)
        .map(|&(s, _)| s)
}

/// Symmetric loops on a closed target of revolution about z (the target
/// turned so, `revolved`): for each pole to start from (one, when the two
/// ends of the meridian mirror each other), each loop size (near one edge
/// apart at the widest ring, and two and four fewer) and each spacing at
/// the pole (`POLAR_SPACINGS`), a seed loop on the level circle where the
/// points are that far apart, and rings along the meridian to the circle
/// near the other pole where they are as far apart again.
pub(super) fn loops(
    ask: &DesignAsk<'_>,
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Vec<Found> {
    let t = &ask.target;
    let Some(down) = meridian(t, 0.0) else {
        return Vec::new();
    };
    let widest = down.iter().map(|m| radius(m.1)).fold(0.0, f64::max);
    let mirrored = mirrors(&down, ROUND * t.extent);
    let n0 = ((TAU * widest / ask.edge / 2.0).round() as usize * 2).max(8);
    let mut out = Vec::new();
    for pole in 0..if mirrored { 1 } else { 2 } {
        let label = ["near the top pole", "near the bottom pole"][pole];
        for n in [n0, n0.saturating_sub(2), n0.saturating_sub(4)] {
            if n < 8 {
                continue;
            }
            let theta = TAU / n as f64;
            let Some(mut m) = meridian(t, theta) else {
                continue;
            };
            if pole == 1 {
                m = reversed(&m);
            }
            for spacing in POLAR_SPACINGS {
                let spacing = spacing * ask.edge;
                let total = m.last().map_or(0.0, |x| x.0);
                let (Some(start), Some(end)) = (
                    polar_arc(&m, n, spacing),
                    polar_arc(&reversed(&m), n, spacing),
                ) else {
                    continue;
                };
                let end = total - end;
                if end <= start {
                    continue;
                }
                let at = along(&m, start);
                // Point 1 of the loop lies on the meridian at azimuth theta.
                let points = level_loop(DVec3::new(0.0, 0.0, at.z), radius(at), n);
                let what = format!("{label}, {spacing:.1} mm apart");
                let seed = Seed {
                    points: &points,
                    meridian: &m,
                    span: (start, end),
                    what: &what,
                    closed: true,
                };
                out.extend(grow_rings(ask, &seed, tried, progress));
            }
        }
    }
    out
}

/// Whether the meridian's two halves mirror each other (an ellipsoid, not
/// an egg): its points' radii and heights from each end within `tol`.
fn mirrors(meridian: &[(f64, DVec3)], tol: f64) -> bool {
    let n = meridian.len();
    (0..n / 2).all(|k| {
        let (a, b) = (meridian[k].1, meridian[n - 1 - k].1);
        (radius(a) - radius(b)).abs() <= tol && (a.z + b.z).abs() <= tol
    })
}

/// A meridian walked the other way: arc lengths from its other end.
fn reversed(meridian: &[(f64, DVec3)]) -> Vec<(f64, DVec3)> {
    let total = meridian.last().map_or(0.0, |m| m.0);
    meridian
        .iter()
        .rev()
        .map(|&(s, p)| (total - s, p))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere(text: &str) -> Target {
        crate::target::read("t.toml", text.as_bytes(), None).unwrap()
    }

    /// A spheroid turned and moved is found to be of revolution about its
    /// long axis once in its own frame; its meridian runs pole to pole.
    #[test]
    fn the_axis_of_a_turned_moved_spheroid_is_found() {
        let t = sphere(
            "[target]\nfamily = \"spheroid-cap\"\naxes = [120.0, 120.0, 200.0]\nheight = 400.0\nturn = [30.0, 40.0, 50.0]\nat = [100.0, -50.0, 20.0]\n",
        )
        .canonical();
        let Revolved::About { axis, spread } = revolved(&t) else {
            panic!("not found of revolution");
        };
        assert_eq!(axis, DVec3::X, "the long axis is the largest spread");
        assert!(spread < 0.002 * t.extent, "{spread}");
        let turned = t.levelled(axis);
        let m = meridian(&turned, 0.3).unwrap();
        let (top, bottom) = (m[0].1, m[m.len() - 1].1);
        assert!((top.z - 200.0).abs() < 1.0 && (bottom.z + 200.0).abs() < 1.0);
        assert!(mirrors(&m, ROUND * t.extent));
    }

    /// The egg of the suite (a mesh of uneven rings, turned and moved;
    /// scripts/make-targets) is round about its long axis, its ends not
    /// mirrored; an ellipsoid of three unequal axes is round about none.
    #[test]
    fn an_egg_is_round_and_a_triaxial_ellipsoid_is_not() {
        let path = format!(
            "{}/fixtures/targets/egg-export.stl",
            env!("CARGO_MANIFEST_DIR")
        );
        let t = crate::target::read("egg-export.stl", &std::fs::read(path).unwrap(), None)
            .unwrap()
            .canonical();
        let Revolved::About { axis, .. } = revolved(&t) else {
            panic!("the egg is not found of revolution");
        };
        let m = meridian(&t.levelled(axis), 0.0).unwrap();
        let length = m[m.len() - 1].1.z - m[0].1.z;
        assert!((length.abs() - 400.0).abs() < 4.0, "{length}");
        assert!(!mirrors(&m, ROUND * t.extent));
        let t = sphere(
            "[target]\nfamily = \"spheroid-cap\"\naxes = [200.0, 150.0, 120.0]\nheight = 240.0\n",
        )
        .canonical();
        let Revolved::NotRound { spread } = revolved(&t) else {
            panic!("a triaxial ellipsoid found round");
        };
        assert!(spread > 20.0, "{spread}");
    }

    /// A closed cup (walls 20 mm thick, its profile meeting the axis at the
    /// bottom and at the floor of its hollow) is round, but rays from its
    /// centroid, in the hollow, leave through the mouth: not star-shaped.
    #[test]
    fn a_closed_cup_is_not_star_shaped() {
        let t = sphere(
            "[target]\nfamily = \"revolution\"\nprofile = [[0.0, 0.0], [200.0, 0.0], [200.0, 200.0], [180.0, 200.0], [180.0, 20.0], [0.0, 20.0]]\n",
        );
        assert_eq!(t.topology, crate::target::Topology::Closed { genus: 0 });
        assert!(matches!(revolved(&t.canonical()), Revolved::NotStar));
    }
}
