//! Frames (docs/physics.md, "Strips as discrete elastic rods", "Eyelets"):
//! parallel transport, the time-parallel reference frame of an edge, a
//! joint's tilted frame, and the twist between two edges.

use crate::dual::{Scalar, V3};
use glam::DVec3;
use std::ops::{Add, Sub};

/// The minimal rotation taking unit `t1` to unit `t2`, applied to `v`
/// (smooth while t1.t2 > -1).
#[inline]
pub fn transport<S: Scalar>(t1: V3<S>, t2: V3<S>, v: V3<S>) -> V3<S> {
    let c = t1.dot(t2);
    let b = t1.cross(t2);
    let k = b.dot(v) / (c + 1.0);
    v.scale(c).add(b.cross(v)).add(b.scale(k))
}

/// `transport` from a constant unit `t1` of a constant `v` (the stored
/// reference frame): most products involve a constant, which is cheap.
#[inline]
pub fn transport_c<S: Scalar>(t1: DVec3, t2: V3<S>, v: DVec3) -> V3<S> {
    let c = t2.dotc(t1);
    // b = t1 x t2 = -(t2 x t1)
    let b = t2.crossc(t1).scalef(-1.0);
    let k = b.dotc(v) * (c + 1.0).recip();
    V3::cscale(v, c).add(b.crossc(v)).add(b.scale(k))
}

/// Material frame `(d1, d2)` of an edge with tangent `t`, stored source
/// tangent `ts` and director `as_`, and material angle `theta`.
#[inline]
pub fn material<S: Scalar>(ts: DVec3, as_: DVec3, t: V3<S>, theta: S) -> (V3<S>, V3<S>) {
    let a1 = transport_c(ts, t, as_);
    let a2 = t.cross(a1);
    let (s, c) = (theta.sin(), theta.cos());
    (a1.scale(c).add(a2.scale(s)), a2.scale(c).sub(a1.scale(s)))
}

/// A joint's axis and in-plane basis from its stored frame and the
/// gnomonic tilt (a, b): `n = unit(ns + a ps + b qs)`, p and q transported.
#[inline]
pub fn joint_frame<S: Scalar>(
    ns: DVec3,
    ps: DVec3,
    qs: DVec3,
    a: S,
    b: S,
) -> (V3<S>, V3<S>, V3<S>) {
    if a.val() == 0.0 && b.val() == 0.0 {
        joint_frame_at_rest([ns, ps, qs], a, b)
    } else {
        joint_frame_general([ns, ps, qs], a, b)
    }
}

/// `joint_frame` at any tilt: the reference for `joint_frame_at_rest`.
#[inline]
pub fn joint_frame_general<S: Scalar>(frame: [DVec3; 3], a: S, b: S) -> (V3<S>, V3<S>, V3<S>) {
    let [ns, ps, qs] = frame;
    let n = V3::cst(ns)
        .add(V3::cscale(ps, a))
        .add(V3::cscale(qs, b))
        .unit();
    (n, transport_c(ns, n, ps), transport_c(ns, n, qs))
}

/// Twist between consecutive edges: the angle from the transported `d1`
/// of the first edge to `d1` of the second, about the second tangent.
#[inline]
pub fn twist<S: Scalar>(t0: V3<S>, d10: V3<S>, t1: V3<S>, d11: V3<S>) -> S {
    twist_with(t0.dot(t1), t0.cross(t1), d10, t1, d11)
}

/// `twist` given c = t0.t1 and b = t0 x t1, which the bending term has
/// computed already.
#[inline]
pub fn twist_with<S: Scalar>(c: S, b: V3<S>, d10: V3<S>, t1: V3<S>, d11: V3<S>) -> S {
    // Parallel transport of d10 from t0 to t1 (`transport`).
    let k = b.dot(d10) * (c + 1.0).recip();
    let u = d10.scale(c).add(b.cross(d10)).add(b.scale(k));
    u.cross(d11).dot(t1).atan2(u.dot(d11))
}

/// `joint_frame` where the tilt is zero, which is where the solver takes
/// derivatives (`Model::update_frames` re-bases every joint on its tilt):
/// the second-order Taylor polynomials of n, p and q in (a, b), so value,
/// gradient and Hessian are those of `joint_frame` exactly, with 3 dual
/// products instead of 14, a square root and 3 reciprocals. With
/// ps x qs = ns:
/// n = ns (1 - (a^2 + b^2)/2) + a ps + b qs,
/// p = ps (1 - a^2/2) - a ns - (ab/2) qs,
/// q = qs (1 - b^2/2) - b ns - (ab/2) ps.
#[inline]
pub fn joint_frame_at_rest<S: Scalar>(frame: [DVec3; 3], a: S, b: S) -> (V3<S>, V3<S>, V3<S>) {
    let [ns, ps, qs] = frame;
    let (aa, bb, ab) = (a * a * -0.5, b * b * -0.5, a * b * -0.5);
    let n = V3::cscale(ns, aa + bb + 1.0)
        .add(V3::cscale(ps, a))
        .add(V3::cscale(qs, b));
    let p = V3::cscale(ps, aa + 1.0)
        .add(V3::cscale(ns, -a))
        .add(V3::cscale(qs, ab));
    let q = V3::cscale(qs, bb + 1.0)
        .add(V3::cscale(ns, -b))
        .add(V3::cscale(ps, ab));
    (n, p, q)
}
