//! Loop closure (docs/math.md 6.2): the holonomy of a periodic front as a product
//! of Lorentz reflections, the symmetric case, and the closing directions as
//! fixed points of the Moebius map it induces on the sphere of directions.

use super::construct::Point;
use glam::{DVec3, DVec4};

/// `max|Lambda - I|` below this: every direction closes (symmetric front).
pub(crate) const FREE_TOL: f64 = 1e-10;
/// `max|Lambda - I|` below this (but above `FREE_TOL`): closing directions
/// exist but are ill-conditioned, roughly like `1 / |Lambda - I|`.
pub(crate) const ILL_TOL: f64 = 1e-6;

/// Minkowski product of R^(3,1), the last coordinate being z.
fn mdot(a: DVec4, b: DVec4) -> f64 {
    a.x * b.x + a.y * b.y + a.z * b.z - a.w * b.w
}

/// Lorentz reflection `S_W v = v - 2 W <W, v> / <W, W>` for spacelike W.
fn reflect(w: DVec4, v: DVec4) -> DVec4 {
    v - w * (2.0 * mdot(w, v) / mdot(w, w))
}

fn lift(p: &Point) -> DVec4 {
    p.pos.extend(p.z)
}

/// The holonomy of a closed front `x[0..N]` (indices mod N), applied to a
/// lifted vector: `S_U(N-1) S_T(N-1) ... S_U(0) S_T(0)`.
pub(crate) struct Holonomy {
    /// The reflection vectors in the order they apply.
    walls: Vec<DVec4>,
}

impl Holonomy {
    pub(crate) fn new(front: &[Point]) -> Self {
        let n = front.len();
        let t = |j: usize| lift(&front[(j + 1) % n]) - lift(&front[j % n]);
        let walls = (0..n).flat_map(|j| [t(j), t(j) + t(j + 1)]).collect();
        Self { walls }
    }

    pub(crate) fn apply(&self, v: DVec4) -> DVec4 {
        self.walls.iter().fold(v, |v, &w| reflect(w, v))
    }

    /// `max|Lambda - I|` over the matrix entries.
    pub(crate) fn distance_from_identity(&self) -> f64 {
        [DVec4::X, DVec4::Y, DVec4::Z, DVec4::W]
            .iter()
            .map(|&e| (self.apply(e) - e).abs().max_element())
            .fold(0.0, f64::max)
    }

    /// The loop map F on unit directions: where `(v, 1)` goes.
    pub(crate) fn map(&self, v: DVec3) -> DVec3 {
        let n = self.apply(v.extend(1.0));
        n.truncate() / n.w
    }
}

/// A minimal complex number for the Moebius algebra.
#[derive(Clone, Copy, Debug, PartialEq)]
struct C {
    re: f64,
    im: f64,
}

impl C {
    const ZERO: C = C { re: 0.0, im: 0.0 };
    fn new(re: f64, im: f64) -> Self {
        Self { re, im }
    }
    fn add(self, o: C) -> C {
        C::new(self.re + o.re, self.im + o.im)
    }
    fn sub(self, o: C) -> C {
        C::new(self.re - o.re, self.im - o.im)
    }
    fn mul(self, o: C) -> C {
        C::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    fn div(self, o: C) -> C {
        let d = o.re * o.re + o.im * o.im;
        C::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
    fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
    fn sqrt(self) -> C {
        let r = self.abs();
        let re = ((r + self.re) / 2.0).max(0.0).sqrt();
        let im = ((r - self.re) / 2.0).max(0.0).sqrt().copysign(self.im);
        C::new(re, im)
    }
}

/// 2x2 complex matrix `[[a, b], [c, d]]`: the Moebius map `(a z + b) / (c z + d)`.
#[derive(Clone, Copy, Debug)]
struct Moebius {
    a: C,
    b: C,
    c: C,
    d: C,
}

impl Moebius {
    /// The map sending `z1, z2, z3` to `0, 1, inf` (cross-ratio normalisation).
    fn normalising(z1: C, z2: C, z3: C) -> Self {
        let p = z2.sub(z3);
        let q = z2.sub(z1);
        Self {
            a: p,
            b: C::ZERO.sub(z1.mul(p)),
            c: q,
            d: C::ZERO.sub(z3.mul(q)),
        }
    }
    fn inverse(self) -> Self {
        Self {
            a: self.d,
            b: C::ZERO.sub(self.b),
            c: C::ZERO.sub(self.c),
            d: self.a,
        }
    }
    fn compose(self, o: Self) -> Self {
        Self {
            a: self.a.mul(o.a).add(self.b.mul(o.c)),
            b: self.a.mul(o.b).add(self.b.mul(o.d)),
            c: self.c.mul(o.a).add(self.d.mul(o.c)),
            d: self.c.mul(o.b).add(self.d.mul(o.d)),
        }
    }
}

/// Stereographic frame at cell 0: `e3 = -u0` (u0 the cone axis), `e2` out of
/// the plane for planar lattices, so planar directions have real zeta.
struct Stereo {
    e1: DVec3,
    e2: DVec3,
    e3: DVec3,
}

impl Stereo {
    fn new(axis: DVec3, dim: usize) -> Self {
        let e3 = -axis;
        let e2 = if dim == 2 {
            DVec3::Z
        } else {
            e3.any_orthonormal_vector()
        };
        let e1 = e2.cross(e3).normalize();
        Self { e1, e2, e3 }
    }
    fn zeta(&self, v: DVec3) -> C {
        let den = 1.0 - v.dot(self.e3);
        C::new(v.dot(self.e1) / den, v.dot(self.e2) / den)
    }
    fn direction(&self, z: C) -> DVec3 {
        let r2 = z.re * z.re + z.im * z.im;
        ((2.0 * z.re) * self.e1 + (2.0 * z.im) * self.e2 + (r2 - 1.0) * self.e3) / (r2 + 1.0)
    }
}

/// What the holonomy of a row's front says about closing it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Closure {
    /// Lambda = I: every direction closes; the row needs a direction or target.
    Free,
    /// The directions that close, 0 to 2 of them, before admissibility checks.
    /// `ill_conditioned` when Lambda is close to, but not, the identity.
    Fixed {
        directions: Vec<DVec3>,
        ill_conditioned: bool,
    },
}

/// Closing directions of a front (docs/math.md 6.2, closure algorithm). `axis`
/// is the cone axis of cell 0, `-unit(t[0])`.
pub(crate) fn closure(holonomy: &Holonomy, axis: DVec3, dim: usize) -> Closure {
    let dist = holonomy.distance_from_identity();
    if dist < FREE_TOL {
        return Closure::Free;
    }
    let frame = Stereo::new(axis, dim);
    // Three sample directions at 0 and +-2 rad from the axis, in the plane
    // of e1 (real zeta, so a planar holonomy gives a real Moebius map).
    let samples = [0.0f64, 2.0, -2.0].map(|a| a.cos() * axis + a.sin() * frame.e1);
    let z = samples.map(|v| frame.zeta(v));
    let w = samples.map(|v| frame.zeta(holonomy.map(v)));
    let m = Moebius::normalising(w[0], w[1], w[2])
        .inverse()
        .compose(Moebius::normalising(z[0], z[1], z[2]));
    // Fixed points: c z^2 + (d - a) z - b = 0.
    let (qa, qb, qc) = (m.c, m.d.sub(m.a), C::ZERO.sub(m.b));
    let scale = m.a.abs() + m.b.abs() + m.c.abs() + m.d.abs();
    let mut roots = Vec::new();
    if qa.abs() <= 1e-14 * scale {
        // One fixed point at infinity (the direction along +t, never admissible).
        if qb.abs() > 1e-14 * scale {
            roots.push(C::ZERO.sub(qc).div(qb));
        }
    } else {
        let disc = qb.mul(qb).sub(C::new(4.0, 0.0).mul(qa).mul(qc));
        if dim == 2 && disc.re < -1e-12 * disc.abs().max(qb.abs() * qb.abs()) {
            // Elliptic planar holonomy: no real fixed point, no planar closure.
            return Closure::Fixed {
                directions: Vec::new(),
                ill_conditioned: dist < ILL_TOL,
            };
        }
        let sq = if dim == 2 {
            C::new(disc.re.max(0.0).sqrt(), 0.0)
        } else {
            disc.sqrt()
        };
        let two_a = C::new(2.0, 0.0).mul(qa);
        for s in [sq, C::ZERO.sub(sq)] {
            roots.push(C::ZERO.sub(qb).add(s).div(two_a));
        }
    }
    let mut directions: Vec<DVec3> = roots
        .into_iter()
        .map(|r| {
            let r = if dim == 2 { C::new(r.re, 0.0) } else { r };
            frame.direction(r)
        })
        .filter(|v| v.is_finite())
        .collect();
    directions.dedup_by(|a, b| a.distance(*b) < 1e-12);
    Closure::Fixed {
        directions,
        ill_conditioned: dist < ILL_TOL,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring(n: usize, r: f64) -> Vec<Point> {
        (0..n)
            .map(|j| {
                let a = std::f64::consts::TAU * j as f64 / n as f64;
                Point {
                    pos: DVec3::new(r * a.cos(), r * a.sin(), 0.0),
                    z: 0.0,
                }
            })
            .collect()
    }

    #[test]
    fn a_symmetric_ring_has_the_identity_holonomy() {
        let h = Holonomy::new(&ring(12, 50.0));
        assert!(h.distance_from_identity() < 1e-12);
        let axis = -(DVec3::new(1.0, 0.0, 0.0)).normalize();
        assert_eq!(closure(&h, axis, 3), Closure::Free);
    }

    #[test]
    fn moebius_fixed_points_are_fixed_by_the_map() {
        // A perturbed ring in space: generic holonomy.
        let mut front = ring(7, 40.0);
        for (j, p) in front.iter_mut().enumerate() {
            p.pos.z = 3.0 * ((j * j) as f64).sin();
            p.pos.x += 2.0 * (j as f64).cos();
        }
        let h = Holonomy::new(&front);
        let axis = -(front[1].pos - front[0].pos).normalize();
        let Closure::Fixed { directions, .. } = closure(&h, axis, 3) else {
            panic!("a generic front is not free");
        };
        assert!(!directions.is_empty());
        for v in directions {
            assert!(h.map(v).distance(v) < 1e-9, "{v} -> {}", h.map(v));
        }
    }
}
