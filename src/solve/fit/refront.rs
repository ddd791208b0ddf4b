//! Rebuilt fronts laid on a target (docs/math.md 7, docs/design.md
//! "Rows"): a sheet's front keeps its edge lengths and kappa but is laid
//! back onto the target before the next row grows on it, so that each
//! row starts on the target however far the rows before it strayed.

use crate::lattice::{FrontMoves, PivotMove};
use crate::target::Target;
use glam::{DQuat, DVec3};

/// Steps of the walk that puts each vertex on the target one edge from
/// the one before.
const WALK: usize = 8;

/// `front` laid on the target from its first vertex (which stays, as a
/// rebuilt front's does): each next vertex the point of the target one
/// edge from the last, nearest the old vertex's closest point on it.
pub(super) fn laid(t: &Target, front: &[DVec3]) -> Vec<DVec3> {
    let mut out = vec![front[0]];
    for j in 1..front.len() {
        let (prev, l) = (out[j - 1], front[j].distance(front[j - 1]));
        let mut p = t.closest(front[j]).0;
        for _ in 0..WALK {
            p = t
                .closest(prev + l * (p - prev).normalize_or(front[j] - front[j - 1]))
                .0;
        }
        out.push(prev + l * (p - prev).normalize_or((front[j] - front[j - 1]) / l));
    }
    out
}

/// The moves that rebuild `front` as `laid` (the same edge lengths and
/// first vertex): bend and twist at each interior vertex in the frame
/// `lattice::front` transports (docs/recipe.md, rebuilt fronts), then a
/// pivot at vertex 0 that turns the first edge onto `laid`'s. None for a
/// front of one edge, which has no interior vertex.
pub(super) fn moves(front: &[DVec3], laid: &[DVec3]) -> Option<FrontMoves> {
    if front.len() < 3 {
        return None;
    }
    let unit = |p: &[DVec3], j: usize| (p[j + 1] - p[j]).normalize();
    let e0 = unit(front, 0);
    let turn = DQuat::from_rotation_arc(e0, unit(laid, 0));
    let back = turn.inverse();
    // As lattice::front starts its frame.
    let mut normal = e0.cross(DVec3::Z);
    normal = if normal.length() > 1e-9 {
        normal.normalize()
    } else {
        e0.any_orthonormal_vector()
    };
    let (mut e, mut bend, mut twist) = (e0, Vec::new(), Vec::new());
    for j in 1..front.len() - 1 {
        let g = back * unit(laid, j);
        let binormal = e.cross(normal);
        let across = g - g.dot(e) * e;
        let b = g.dot(e).clamp(-1.0, 1.0).acos().to_degrees();
        let w = across.dot(binormal).atan2(across.dot(normal)).to_degrees();
        bend.push(b);
        twist.push(w);
        // The direction lattice::front will build from the angles written.
        let (b, w) = (b.to_radians(), w.to_radians());
        let next = (b.cos() * e + b.sin() * (w.cos() * normal + w.sin() * binormal)).normalize();
        normal = DQuat::from_rotation_arc(e, next) * normal;
        e = next;
    }
    let (axis, angle) = turn.to_axis_angle();
    let pivots = if angle.abs() > 1e-12 && axis.length() > 0.5 {
        vec![PivotMove {
            at: 0,
            axis: Some(axis),
            angle_deg: angle.to_degrees(),
        }]
    } else {
        Vec::new()
    };
    Some(FrontMoves {
        bend: Some(bend),
        twist: Some(twist),
        pivots,
        ..FrontMoves::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A front 10 mm above a flat target is laid onto it: every vertex on
    /// the target, every edge its old length, the first vertex kept.
    #[test]
    fn a_front_above_a_plate_is_laid_on_it() {
        let t = crate::target::read(
            "t.toml",
            b"[target]\nfamily = \"disk\"\nradius = 200.0\n",
            None,
        )
        .unwrap();
        let front: Vec<DVec3> = (0..5)
            .map(|j| DVec3::new(-120.0 + 50.0 * j as f64, 10.0 * (j % 2) as f64, 10.0))
            .collect();
        let laid = laid(&t, &front);
        assert_eq!(laid[0], front[0]);
        for j in 1..front.len() {
            assert!(laid[j].z.abs() < 1e-9, "{}", laid[j]);
            let (a, b) = (
                front[j].distance(front[j - 1]),
                laid[j].distance(laid[j - 1]),
            );
            assert!((a - b).abs() < 1e-9, "{a} {b}");
        }
    }

    /// The moves rebuild the front as laid, to rounding: the recipe's
    /// angles grow the front the search chose.
    #[test]
    fn the_moves_rebuild_the_laid_front() {
        let front: Vec<DVec3> = (0..6)
            .map(|j| DVec3::new(50.0 * j as f64, 0.0, 0.0))
            .collect();
        // The same edge lengths along a gentle curve in space.
        let mut laid = vec![front[0]];
        for j in 1..front.len() {
            let a = 0.1 * j as f64;
            let d = DVec3::new(a.cos(), 0.5 * a.sin(), 0.05 * j as f64).normalize();
            laid.push(laid[j - 1] + 50.0 * d);
        }
        let m = moves(&front, &laid).unwrap();
        let mut grower =
            crate::lattice::Grower::new(crate::lattice::Kind::Sheet, 3, &front, &[0.0; 5]).unwrap();
        let row = crate::lattice::RowParams {
            direction: Some(crate::legs::Direction::Angles {
                angle_deg: 45.0,
                tilt_deg: 0.0,
            }),
            left_leg: crate::legs::Leg::Length(30.0),
            right_leg: crate::legs::Leg::Length(30.0),
            front: Some(m),
            ..Default::default()
        };
        grower.grow_row(&row).unwrap();
        let rebuilt = &grower.lattice().fronts[0];
        for (a, b) in rebuilt.iter().zip(&laid) {
            assert!(a.distance(*b) < 1e-9, "{a} {b}");
        }
    }
}
