//! Frames (PHYSICS.md 3, 5): parallel transport, the time-parallel
//! reference frame of an edge, a joint's tilted frame, and the twist
//! between two edges.

use super::dual::{Scalar, V3};

/// The minimal rotation taking unit `t1` to unit `t2`, applied to `v`
/// (smooth while t1.t2 > -1).
pub fn transport<S: Scalar>(t1: V3<S>, t2: V3<S>, v: V3<S>) -> V3<S> {
    let c = t1.dot(t2);
    let b = t1.cross(t2);
    let k = b.dot(v) / (c + 1.0);
    v.scale(c).add(b.cross(v)).add(b.scale(k))
}

/// Material frame `(d1, d2)` of an edge with tangent `t`, stored source
/// tangent `ts` and director `as_`, and material angle `theta`.
pub fn material<S: Scalar>(ts: V3<S>, as_: V3<S>, t: V3<S>, theta: S) -> (V3<S>, V3<S>) {
    let a1 = transport(ts, t, as_);
    let a2 = t.cross(a1);
    let (s, c) = (theta.sin(), theta.cos());
    (a1.scale(c).add(a2.scale(s)), a2.scale(c).sub(a1.scale(s)))
}

/// A joint's axis and in-plane basis from its stored frame and the
/// gnomonic tilt (a, b): `n = unit(ns + a ps + b qs)`, p and q transported.
pub fn joint_frame<S: Scalar>(
    ns: V3<S>,
    ps: V3<S>,
    qs: V3<S>,
    a: S,
    b: S,
) -> (V3<S>, V3<S>, V3<S>) {
    let n = ns.add(ps.scale(a)).add(qs.scale(b)).unit();
    (n, transport(ns, n, ps), transport(ns, n, qs))
}

/// Twist between consecutive edges: the angle from the transported `d1`
/// of the first edge to `d1` of the second, about the second tangent.
pub fn twist<S: Scalar>(t0: V3<S>, d10: V3<S>, t1: V3<S>, d11: V3<S>) -> S {
    let u = transport(t0, t1, d10);
    u.cross(d11).dot(t1).atan2(u.dot(d11))
}
