//! Rebuilt fronts steered so that their row lands on the target
//! (docs/design.md, "Rows"; docs/math.md 7). A front laid on the target
//! keeps its edge lengths and kappa, but each of its vertices may still
//! turn about the one before it: one free number a vertex. Chosen column
//! by column, that number puts the row's next new vertex on the target,
//! where a front laid nearest the old one leaves the row to stray.

use crate::lattice::{Point, pivot_from_v2, resolve_direction};
use crate::legs::Direction;
use crate::target::Target;
use glam::DVec3;

/// Chord of the scan round each circle of candidate vertices (radians),
/// and how far either way from the laid vertex it looks: a front turned
/// further than a right angle folds back over its row.
const CHORD: f64 = 7.5 * std::f64::consts::PI / 180.0;
const REACH: usize = 12;

/// Bisections of the chord that crosses the target: 2^-20 of 7.5 degrees.
const BISECT: usize = 20;

/// The front `old` (its points with their collapsed coordinates) rebuilt
/// on the target for a row grown in `direction` from its first cell: its
/// first two vertices as `laid` has them, each next vertex `x*[j+2]` the
/// point of the target, one edge from `x*[j+1]` and nearest `laid[j+2]`,
/// that puts the new vertex `x[i+1][j+1]` of cell j on the target too
/// (docs/design.md, "Rows"); with the count of vertices so steered.
/// Where cell j's rod A does not meet the target, or no such point
/// exists, the rest of the front is laid on from the last vertex steered.
pub(super) fn steered(
    t: &Target,
    old: &[Point],
    laid: &[DVec3],
    direction: Direction,
) -> Option<(Vec<DVec3>, usize)> {
    let n = old.len();
    if n < 3 || laid.len() != n {
        return None;
    }
    let at = |x: &[DVec3], j: usize| Point {
        pos: x[j],
        z: old[j].z,
    };
    let mut x = laid[..2].to_vec();
    // The start cell's leg direction, as the grower resolves it.
    let mut v2 = resolve_direction(direction, x[0], x[1], 3).ok()?;
    for j in 0..n - 2 {
        let edge = old[j + 2].pos.distance(old[j + 1].pos);
        let next = pivot_from_v2(at(&x, j), at(&x, j + 1), v2)
            .ok()
            .and_then(|p| landing(t, at(&x, j), p))
            .and_then(|(h, zh)| {
                let rb = zh - old[j + 2].z;
                on_circle(t, (x[j + 1], edge), (h, rb), laid[j + 2]).map(|q| (q, h))
            });
        match next {
            Some((q, h)) => {
                x.push(q);
                v2 = (h - q).normalize();
            }
            None => {
                // The rest laid again from the last vertex steered, with
                // the old front's edges.
                let shift = x[j + 1] - old[j + 1].pos;
                let rest: Vec<DVec3> = old[j + 1..].iter().map(|p| p.pos + shift).collect();
                x.extend_from_slice(&super::refront::laid(t, &rest)[1..]);
                return Some((x, j));
            }
        }
    }
    Some((x, n - 2))
}

/// Where cell j's rod A, from its upper-left corner `ul` through its pivot
/// `p`, meets the target beyond the pivot: the new vertex there, and its
/// collapsed coordinate. (Kept within half the laid front's rod of it,
/// the suite's height field lost the rows over its bump: 7 cells, not 30.)
fn landing(t: &Target, ul: Point, p: Point) -> Option<(DVec3, f64)> {
    let l1 = p.pos.distance(ul.pos);
    let v1 = (p.pos - ul.pos) / l1;
    let s = t.ray(ul.pos, v1, l1 * (1.0 + 1e-9))?;
    Some((ul.pos + s * v1, ul.z + s))
}

/// The point of the target on the circle where the sphere about `a` and
/// the one about `b` (centre, radius) meet, nearest `guess` round it and
/// within `REACH` chords of it either way.
fn on_circle(
    t: &Target,
    (a, ra): (DVec3, f64),
    (b, rb): (DVec3, f64),
    guess: DVec3,
) -> Option<DVec3> {
    let d = a.distance(b);
    if !(rb > 0.0 && d > (ra - rb).abs() && d < ra + rb) {
        return None;
    }
    let u = (b - a) / d;
    let along = (d * d + ra * ra - rb * rb) / (2.0 * d);
    let (c, h) = (a + along * u, (ra * ra - along * along).sqrt());
    let g = guess - c;
    let e1 = (g - g.dot(u) * u).try_normalize()?;
    let e2 = u.cross(e1);
    let point = |th: f64| c + h * (th.cos() * e1 + th.sin() * e2);
    // Whether the chord from angle `from` to `to` crosses the target.
    let crosses = |from: f64, to: f64| {
        let (p, q) = (point(from), point(to));
        t.ray(p, q - p, 0.0).is_some_and(|s| s <= 1.0)
    };
    let bracket = (0..REACH)
        .flat_map(|k| [(k as f64, k as f64 + 1.0), (-(k as f64), -(k as f64) - 1.0)])
        .map(|(s, e)| (s * CHORD, e * CHORD))
        .find(|&(s, e)| crosses(s, e))?;
    let (mut lo, mut hi) = bracket;
    for _ in 0..BISECT {
        let mid = 0.5 * (lo + hi);
        if crosses(lo, mid) { hi = mid } else { lo = mid }
    }
    Some(point(0.5 * (lo + hi)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::{Grower, Kind, RowParams};
    use crate::legs::Leg;

    /// On a sphere cap, a front laid on the cap and steered: every new
    /// vertex of the row but the two end ones (which the end legs place)
    /// lies on the cap, and so does every steered vertex of the front,
    /// which keeps its edge lengths.
    #[test]
    fn a_steered_row_lands_on_a_sphere_cap() {
        let cap = b"[target]\nfamily = \"sphere-cap\"\nradius = 300.0\nheight = 80.0\n";
        let t = crate::target::read("t.toml", cap, None).unwrap();
        // A front across the cap, laid on it, with kappa 0 (z = 0).
        let flat: Vec<DVec3> = (0..6)
            .map(|j| DVec3::new(-125.0 + 50.0 * j as f64, -60.0, 100.0))
            .collect();
        let laid = super::super::refront::laid(&t, &flat);
        let mut grower = Grower::new(Kind::Sheet, 3, &laid, &[0.0; 5]).unwrap();
        let old = grower.front();
        let direction = Direction::Angles {
            // Tilted down the cap's slope, so that each rod A meets it.
            angle_deg: 50.0,
            tilt_deg: -40.0,
        };
        let (x, count) = steered(&t, &old, &laid, direction).unwrap();
        assert_eq!(count, x.len() - 2, "every vertex steered");
        for j in 1..x.len() {
            let (a, b) = (x[j].distance(x[j - 1]), laid[j].distance(laid[j - 1]));
            assert!((a - b).abs() < 1e-9 * a, "edge {j}: {a} {b}");
            // The first two vertices are laid's, on chords of the cap.
            let d = t.closest(x[j]).1;
            assert!(j < 2 || d < 1e-3, "front vertex {j} {d} mm off the cap");
        }
        let moves = super::super::refront::moves(&laid, &x).unwrap();
        let row = RowParams {
            direction: Some(direction),
            left_leg: Leg::Length(30.0),
            right_leg: Leg::Length(30.0),
            front: Some(moves),
            ..RowParams::default()
        };
        grower.grow_row(&row).unwrap();
        let new = grower.front();
        let off: Vec<f64> = new.iter().map(|q| t.closest(q.pos).1).collect();
        assert!(off[1..off.len() - 1].iter().all(|&d| d < 1e-3), "{off:?}");
    }
}
