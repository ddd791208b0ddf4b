//! The elementary constructions of docs/math.md section 4, all built on one
//! primitive: the intersection of a ray with a null cone (formula P).

use super::finite;
use glam::DVec3;

/// A point with its collapsed coordinate.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Point {
    pub(crate) pos: DVec3,
    pub(crate) z: f64,
}

/// Why a construction step has no admissible answer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Refusal {
    /// `|b - a| <= |zb - za|`: the pair is not spacelike.
    NotSpacelike,
    /// The denominator of P has the wrong sign or is too close to 0: the
    /// ray never meets the hyperboloid (pivot at or beyond infinity).
    MissesCone,
}

/// Relative tolerance for "too close to 0" in the constructions.
pub(crate) const EPS_REL: f64 = 1e-12;

/// Formula P (docs/math.md 4.1): the distance `r > 0` along the unit ray `b + r v`
/// to the point `q` with `z(q) = zb + r = za + |q - a|`.
pub(crate) fn null_ray(a: Point, b: Point, v: DVec3) -> Result<f64, Refusal> {
    let dx = b.pos - a.pos;
    let dz = b.z - a.z;
    let len = dx.length();
    if len - dz.abs() <= EPS_REL * len {
        return Err(Refusal::NotSpacelike);
    }
    let den = dx.dot(v) - dz;
    if den >= -EPS_REL * len {
        return Err(Refusal::MissesCone);
    }
    let r = (dz * dz - len * len) / (2.0 * den);
    if finite(r) {
        Ok(r)
    } else {
        Err(Refusal::MissesCone)
    }
}

/// The point formula P finds: `b + r v` at collapsed coordinate `zb + r`.
fn null_point(a: Point, b: Point, v: DVec3) -> Result<Point, Refusal> {
    let r = null_ray(a, b, v)?;
    Ok(Point {
        pos: b.pos + r * v,
        z: b.z + r,
    })
}

/// Paper eq. 4 (docs/math.md 4.2): a cell's pivot from its top corners and `v2`,
/// the unit direction from UR towards the pivot. Its legs are
/// `l4 = z(p) - z(UR)` and `l1 = z(p) - z(UL)`.
pub(crate) fn pivot_from_v2(ul: Point, ur: Point, v2: DVec3) -> Result<Point, Refusal> {
    null_point(ul, ur, v2)
}

/// Mirror form of eq. 4: the pivot from `v1`, the unit direction from UL.
pub(crate) fn pivot_from_v1(ul: Point, ur: Point, v1: DVec3) -> Result<Point, Refusal> {
    null_point(ur, ul, v1)
}

/// Right transfer (4.3): the lower-right corner of cell j on rod A, from the
/// direction `v1` of that rod, null-related to the vertex two steps right.
pub(crate) fn lower_right(x_j: Point, x_j2: Point, v1: DVec3) -> Result<Point, Refusal> {
    null_point(x_j2, x_j, v1)
}

/// Left transfer (4.4): the lower-left corner of cell j on rod B, from the
/// direction `v2` of that rod, null-related to the vertex one step left of UL.
pub(crate) fn lower_left(x_jm1: Point, x_j1: Point, v2: DVec3) -> Result<Point, Refusal> {
    null_point(x_jm1, x_j1, v2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(x: f64, y: f64, z: f64, zc: f64) -> Point {
        Point {
            pos: DVec3::new(x, y, z),
            z: zc,
        }
    }

    #[test]
    fn single_cell_3d_golden() {
        // docs/math.md 5: UL = 0, UR = (2,0,0), kappa = 0.5, v2 = unit(-1,-1,-0.5).
        let ul = pt(0.0, 0.0, 0.0, 0.0);
        let ur = pt(2.0, 0.0, 0.0, -0.5);
        let v2 = DVec3::new(-1.0, -1.0, -0.5).normalize();
        let p = pivot_from_v2(ul, ur, v2).unwrap();
        assert!((p.z - ur.z - 2.25).abs() < 1e-12, "l4");
        assert!((p.z - ul.z - 1.75).abs() < 1e-12, "l1");
        assert!(
            (p.pos.distance(ur.pos) - 2.25).abs() < 1e-12,
            "l4 as a distance"
        );
        assert!(
            (p.pos.distance(ul.pos) - 1.75).abs() < 1e-12,
            "l1 as a distance"
        );
        assert!(p.pos.distance(DVec3::new(0.5, -1.5, -0.75)) < 1e-12);
        // The mirror form from the resulting v1 lands on the same pivot.
        let v1 = (p.pos - ul.pos).normalize();
        let mirror = pivot_from_v1(ul, ur, v1).unwrap();
        assert!(mirror.pos.distance(p.pos) < 1e-12);
    }

    #[test]
    fn refuses_directions_outside_the_cone() {
        let ul = pt(0.0, 0.0, 0.0, 0.0);
        let ur = pt(2.0, 0.0, 0.0, 0.0);
        // Pointing away from UL: the ray never meets the hyperbola.
        assert_eq!(
            pivot_from_v2(ul, ur, DVec3::X).unwrap_err(),
            Refusal::MissesCone
        );
        // Perpendicular with kappa = 0 is exactly on the cone boundary.
        assert_eq!(
            pivot_from_v2(ul, ur, DVec3::NEG_Y).unwrap_err(),
            Refusal::MissesCone
        );
        let timelike = pt(2.0, 0.0, 0.0, -2.5);
        assert_eq!(
            pivot_from_v2(ul, timelike, DVec3::NEG_X).unwrap_err(),
            Refusal::NotSpacelike
        );
    }
}
