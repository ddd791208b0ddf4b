//! Second-order forward-mode automatic differentiation for the stencil
//! energies: a value with its gradient and Hessian over N local variables.
//! Written here rather than taken from num-dual, which brings nalgebra (a
//! long compile) for what is a few hundred lines; checked against finite
//! differences in tests/sim.rs. `Relative` is the same arithmetic over the
//! two rotations of a bend, stored in fewer numbers; `compose_edges` the
//! chain rule from a bend's rotations to its edges' variables.
//!
//! The arithmetic is `#[inline]`, not `#[inline(always)]`: forcing every
//! operation inline made this crate's release build take 79 s of CPU
//! (15 s now) for 1.6 % fewer instructions in a solve (callgrind,
//! `karigami simulate` of the eggbox: 2.735 G against 2.779 G).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// What the stencil energies compute with: plain f64 (energy only) or a
/// `Dual` (energy, gradient and Hessian).
pub trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Mul<f64, Output = Self>
{
    fn cst(v: f64) -> Self;
    fn val(&self) -> f64;
    fn sqrt(self) -> Self;
    /// 1 / self (cheaper than dividing a constant by a dual).
    fn recip(self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn atan2(self, x: Self) -> Self;
}

impl Scalar for f64 {
    #[inline]
    fn cst(v: f64) -> Self {
        v
    }
    #[inline]
    fn val(&self) -> f64 {
        *self
    }
    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline]
    fn recip(self) -> Self {
        1.0 / self
    }
    #[inline]
    fn sin(self) -> Self {
        f64::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        f64::cos(self)
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
}

/// Value, gradient and Hessian over N variables. The Hessian is stored as
/// its upper triangle, packed row by row (`T` = N (N + 1) / 2 entries):
/// half the arithmetic and half the bytes to copy, which is what these
/// small values mostly cost.
#[derive(Clone, Copy, Debug)]
pub struct Dual<const N: usize, const T: usize> {
    pub v: f64,
    pub g: [f64; N],
    pub h: [f64; T],
}

/// Packed index of (i, j), i <= j < n.
#[inline]
const fn packed(n: usize, i: usize, j: usize) -> usize {
    i * n - i * (i + 1) / 2 + j
}

impl<const N: usize, const T: usize> Dual<N, T> {
    const SIZE_OK: () = assert!(T == N * (N + 1) / 2, "T must be N (N + 1) / 2");

    /// Local variable `i` at value `v`.
    #[inline]
    pub fn var(v: f64, i: usize) -> Self {
        let mut d = Self::cst(v);
        d.g[i] = 1.0;
        d
    }

    /// Hessian entry (i, j) of either triangle.
    #[inline]
    pub fn hess(&self, i: usize, j: usize) -> f64 {
        if j >= i {
            self.h[packed(N, i, j)]
        } else {
            self.h[packed(N, j, i)]
        }
    }

    /// Set Hessian entry (i, j) (and so (j, i)).
    #[inline]
    pub fn set_hess(&mut self, i: usize, j: usize, v: f64) {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        self.h[packed(N, i, j)] = v;
    }

    /// The whole Hessian, both triangles (row k is column k).
    #[inline]
    pub fn hess_matrix(&self) -> [[f64; N]; N] {
        let mut out = [[0.0; N]; N];
        for (k, row) in out.iter_mut().enumerate() {
            for (l, f) in row.iter_mut().enumerate() {
                *f = self.hess(k, l);
            }
        }
        out
    }

    /// `d`, over M of this dual's variables, as a dual over all N: its
    /// variables at `offset`.., no dependence on the others.
    #[inline]
    pub fn embed<const M: usize, const TM: usize>(d: &Dual<M, TM>, offset: usize) -> Self {
        let mut out = Self::cst(d.v);
        for i in 0..M {
            out.g[offset + i] = d.g[i];
            for j in i..M {
                out.set_hess(offset + i, offset + j, d.hess(i, j));
            }
        }
        out
    }

    /// f(self) from f, f', f'' at the value (the chain rule).
    #[inline]
    fn chain(mut self, f: f64, f1: f64, f2: f64) -> Self {
        let mut k = 0;
        for i in 0..N {
            let gi = f2 * self.g[i];
            for j in i..N {
                self.h[k] = f1 * self.h[k] + gi * self.g[j];
                k += 1;
            }
        }
        for i in 0..N {
            self.g[i] *= f1;
        }
        self.v = f;
        self
    }
}

/// Where edge e's packed 4 x 4 Hessian block lies in the packed 8 x 8 one.
const EDGE_BLOCK: [[usize; 10]; 2] = {
    let mut out = [[0; 10]; 2];
    let mut e = 0;
    while e < 2 {
        let (mut a, mut t) = (0, 0);
        while a < 4 {
            let mut b = a;
            while b < 4 {
                out[e][t] = packed(8, 4 * e + a, 4 * e + b);
                t += 1;
                b += 1;
            }
            a += 1;
        }
        e += 1;
    }
    out
};

/// The second-order chain rule of a bend term (`bend_local`): `outer`
/// is its energy over the two edges' rotations (w0, w1), `inner[e]` edge
/// e's rotation over the edge's own 4 variables (edge vector and material
/// angle, or an arm's slot inputs and a zero); the result is the energy
/// over the 8 variables, g = sum_k f_k w_k' and H = J^T F J + sum_k f_k
/// w_k''. Edge 0's rotation does not depend on edge 1's variables nor the
/// other way round, so the products with those zeros are left out: each
/// sum keeps the order and the other terms of the chain rule over the
/// rotations as 8-variable duals (`tests::compose_full`), and so its
/// value to the bit while the derivatives are finite (a product left out
/// is then +-0, and a sum that starts at +0 is never -0, so adding it
/// changes nothing; an infinite one would have made NaN there).
pub fn compose_edges(outer: &Dual<6, 21>, inner: &[[Dual<4, 10>; 3]; 2]) -> Dual<8, 36> {
    let f = outer.hess_matrix();
    // p[k][a] = sum_l F_kl w_l'(a), over the rotations l of a's edge.
    let mut p = [[0.0; 8]; 6];
    for (pk, fk) in p.iter_mut().zip(&f) {
        for (e, rot) in inner.iter().enumerate() {
            for (w, &fkl) in rot.iter().zip(&fk[3 * e..3 * e + 3]) {
                if fkl != 0.0 {
                    for a in 0..4 {
                        pk[4 * e + a] += fkl * w.g[a];
                    }
                }
            }
        }
    }
    let mut out = Dual::<8, 36>::cst(outer.v);
    for (e, rot) in inner.iter().enumerate() {
        // sum_k f_k w_k'' over the edge's own 4 variables, then into place.
        let mut block = [0.0; 10];
        for (w, &fk) in rot.iter().zip(&outer.g[3 * e..3 * e + 3]) {
            if fk != 0.0 {
                for a in 0..4 {
                    out.g[4 * e + a] += fk * w.g[a];
                }
                for (b, &h) in block.iter_mut().zip(&w.h) {
                    *b += fk * h;
                }
            }
        }
        for (&t, b) in EDGE_BLOCK[e].iter().zip(block) {
            out.h[t] = b;
        }
    }
    let mut t = 0;
    for a in 0..8 {
        let (e, i) = (a / 4, a % 4);
        let rot = &inner[e];
        for b in a..8 {
            let mut s = 0.0;
            for (k, w) in rot.iter().enumerate() {
                s += w.g[i] * p[3 * e + k][b];
            }
            out.h[t] += s;
            t += 1;
        }
    }
    out
}

/// `Scalar`'s value and elementary functions of a dual type with a field
/// `v` (its value) and a method `chain(f, f', f'')` (the chain rule of a
/// function of it), written once for `Dual` and `Relative`.
macro_rules! elementary_functions {
    () => {
        #[inline]
        fn val(&self) -> f64 {
            self.v
        }
        #[inline]
        fn sqrt(self) -> Self {
            let s = self.v.sqrt();
            let v = self.v;
            self.chain(s, 0.5 / s, -0.25 / (s * v))
        }
        #[inline]
        fn recip(self) -> Self {
            let inv = 1.0 / self.v;
            self.chain(inv, -inv * inv, 2.0 * inv * inv * inv)
        }
        #[inline]
        fn sin(self) -> Self {
            let (s, c) = self.v.sin_cos();
            self.chain(s, c, -s)
        }
        #[inline]
        fn cos(self) -> Self {
            let (s, c) = self.v.sin_cos();
            self.chain(c, -s, -c)
        }
    };
}

/// One second-derivative entry of atan2(y, x) over the dual's variables
/// (i, j): from y's and x's entries (yh, xh) and gradient entries (yi, yj),
/// (xi, xj), with `atan2_derivatives` d.
#[inline]
fn atan2_entry(
    d: &[f64; 5],
    (yh, xh): (f64, f64),
    (yi, yj): (f64, f64),
    (xi, xj): (f64, f64),
) -> f64 {
    let [ay, ax, hyy, hxx, hxy] = *d;
    ay * yh + ax * xh + hyy * yi * yj + hxx * xi * xj + hxy * (yi * xj + xi * yj)
}

/// The derivatives of atan2(y, x) at (y, x): first in y and x, then the
/// second in (y, y), (x, x) and (y, x).
#[inline]
fn atan2_derivatives(y: f64, x: f64) -> [f64; 5] {
    let r2 = x * x + y * y;
    let r4 = r2 * r2;
    [
        x / r2,
        -y / r2,
        -2.0 * x * y / r4,
        2.0 * x * y / r4,
        (y * y - x * x) / r4,
    ]
}

impl<const N: usize, const T: usize> Scalar for Dual<N, T> {
    #[inline]
    fn cst(v: f64) -> Self {
        let () = Self::SIZE_OK;
        Dual {
            v,
            g: [0.0; N],
            h: [0.0; T],
        }
    }
    elementary_functions!();
    /// atan2(y, x) with y = self: d = (x dy - y dx) / r2.
    #[inline]
    fn atan2(self, x: Self) -> Self {
        let (y, d) = (self, atan2_derivatives(self.v, x.v));
        let mut out = Self::cst(y.v.atan2(x.v));
        let mut k = 0;
        for i in 0..N {
            out.g[i] = d[0] * y.g[i] + d[1] * x.g[i];
            for j in i..N {
                out.h[k] = atan2_entry(&d, (y.h[k], x.h[k]), (y.g[i], y.g[j]), (x.g[i], x.g[j]));
                k += 1;
            }
        }
        out
    }
}

impl<const N: usize, const T: usize> Add for Dual<N, T> {
    type Output = Self;
    #[inline]
    fn add(mut self, o: Self) -> Self {
        self.v += o.v;
        for i in 0..N {
            self.g[i] += o.g[i];
        }
        for k in 0..T {
            self.h[k] += o.h[k];
        }
        self
    }
}

impl<const N: usize, const T: usize> Sub for Dual<N, T> {
    type Output = Self;
    #[inline]
    fn sub(mut self, o: Self) -> Self {
        self.v -= o.v;
        for i in 0..N {
            self.g[i] -= o.g[i];
        }
        for k in 0..T {
            self.h[k] -= o.h[k];
        }
        self
    }
}

impl<const N: usize, const T: usize> Mul for Dual<N, T> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let mut out = Self::cst(self.v * o.v);
        let mut k = 0;
        for i in 0..N {
            out.g[i] = self.v * o.g[i] + o.v * self.g[i];
            for j in i..N {
                out.h[k] =
                    self.v * o.h[k] + o.v * self.h[k] + self.g[i] * o.g[j] + o.g[i] * self.g[j];
                k += 1;
            }
        }
        out
    }
}

impl<const N: usize, const T: usize> Div for Dual<N, T> {
    type Output = Self;
    #[inline]
    // A quotient is the product with the reciprocal: one dual product.
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, o: Self) -> Self {
        self * o.recip()
    }
}

impl<const N: usize, const T: usize> Neg for Dual<N, T> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self * -1.0
    }
}

impl<const N: usize, const T: usize> Add<f64> for Dual<N, T> {
    type Output = Self;
    #[inline]
    fn add(mut self, o: f64) -> Self {
        self.v += o;
        self
    }
}

impl<const N: usize, const T: usize> Mul<f64> for Dual<N, T> {
    type Output = Self;
    #[inline]
    fn mul(mut self, o: f64) -> Self {
        self.v *= o;
        for i in 0..N {
            self.g[i] *= o;
        }
        for k in 0..T {
            self.h[k] *= o;
        }
        self
    }
}

/// A dual over the two edges' rotations (w0, w1) of a bend term's
/// quantity whose gradient over w1 is minus that over w0 and whose
/// Hessian's (w1, w1) block equals its (w0, w0) block, to the bit: true of
/// every product M_ij = a_i . b_j of the two frames (`rotation_product`
/// in model.rs) and kept by sums, products and functions of them (each
/// w1 entry is the w0 entry's formula with its two gradient factors
/// negated, and (-x)(-y) = xy, -x - y = -(x + y) exactly). So those parts
/// are stored once: 19 numbers for `Dual<6, 21>`'s 28, and the same
/// arithmetic, in the same order, for the rest (`to_dual`).
#[derive(Clone, Copy, Debug)]
pub struct Relative {
    pub v: f64,
    /// Gradient over w0 (over w1: its negative).
    pub g: [f64; 3],
    /// The (w0, w0) block, packed (= the (w1, w1) block).
    pub h: [f64; 6],
    /// The (w0, w1) block, c[3 i + j] = d2 / dw0_i dw1_j.
    pub c: [f64; 9],
}

impl Relative {
    /// The same numbers as a dual over (w0, w1).
    pub fn to_dual(&self) -> Dual<6, 21> {
        let mut d = Dual::<6, 21>::cst(self.v);
        let mut t = 0;
        for i in 0..3 {
            d.g[i] = self.g[i];
            d.g[3 + i] = -self.g[i];
            for j in i..3 {
                d.set_hess(i, j, self.h[t]);
                d.set_hess(3 + i, 3 + j, self.h[t]);
                t += 1;
            }
            for j in 0..3 {
                d.set_hess(i, 3 + j, self.c[3 * i + j]);
            }
        }
        d
    }

    /// `Dual::chain`'s arithmetic on the stored parts.
    #[inline]
    fn chain(mut self, f: f64, f1: f64, f2: f64) -> Self {
        let mut k = 0;
        for i in 0..3 {
            let gi = f2 * self.g[i];
            for j in i..3 {
                self.h[k] = f1 * self.h[k] + gi * self.g[j];
                k += 1;
            }
            for j in 0..3 {
                self.c[3 * i + j] = f1 * self.c[3 * i + j] + gi * -self.g[j];
            }
        }
        for i in 0..3 {
            self.g[i] *= f1;
        }
        self.v = f;
        self
    }
}

/// `Dual`'s arithmetic on the stored parts, function for function.
impl Scalar for Relative {
    #[inline]
    fn cst(v: f64) -> Self {
        Relative {
            v,
            g: [0.0; 3],
            h: [0.0; 6],
            c: [0.0; 9],
        }
    }
    elementary_functions!();
    #[inline]
    fn atan2(self, x: Self) -> Self {
        let d = atan2_derivatives(self.v, x.v);
        let mut out = Self::cst(self.v.atan2(x.v));
        let (y, mut k) = (self, 0);
        for i in 0..3 {
            for j in i..3 {
                out.h[k] = atan2_entry(&d, (y.h[k], x.h[k]), (y.g[i], y.g[j]), (x.g[i], x.g[j]));
                k += 1;
            }
            // Over w1, the gradients' second factor is negated.
            for j in 0..3 {
                let t = 3 * i + j;
                out.c[t] = atan2_entry(&d, (y.c[t], x.c[t]), (y.g[i], -y.g[j]), (x.g[i], -x.g[j]));
            }
            out.g[i] = d[0] * y.g[i] + d[1] * x.g[i];
        }
        out
    }
}

impl Add for Relative {
    type Output = Self;
    #[inline]
    fn add(mut self, o: Self) -> Self {
        self.v += o.v;
        for i in 0..3 {
            self.g[i] += o.g[i];
        }
        for k in 0..6 {
            self.h[k] += o.h[k];
        }
        for t in 0..9 {
            self.c[t] += o.c[t];
        }
        self
    }
}

impl Sub for Relative {
    type Output = Self;
    #[inline]
    fn sub(mut self, o: Self) -> Self {
        self.v -= o.v;
        for i in 0..3 {
            self.g[i] -= o.g[i];
        }
        for k in 0..6 {
            self.h[k] -= o.h[k];
        }
        for t in 0..9 {
            self.c[t] -= o.c[t];
        }
        self
    }
}

impl Mul for Relative {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let mut out = Self::cst(self.v * o.v);
        let mut k = 0;
        for i in 0..3 {
            out.g[i] = self.v * o.g[i] + o.v * self.g[i];
            for j in i..3 {
                out.h[k] =
                    self.v * o.h[k] + o.v * self.h[k] + self.g[i] * o.g[j] + o.g[i] * self.g[j];
                k += 1;
            }
            for j in 0..3 {
                let t = 3 * i + j;
                out.c[t] =
                    self.v * o.c[t] + o.v * self.c[t] + self.g[i] * -o.g[j] + o.g[i] * -self.g[j];
            }
        }
        out
    }
}

impl Div for Relative {
    type Output = Self;
    #[inline]
    // A quotient is the product with the reciprocal: one dual product.
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, o: Self) -> Self {
        self * o.recip()
    }
}

impl Neg for Relative {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self * -1.0
    }
}

impl Add<f64> for Relative {
    type Output = Self;
    #[inline]
    fn add(mut self, o: f64) -> Self {
        self.v += o;
        self
    }
}

impl Mul<f64> for Relative {
    type Output = Self;
    #[inline]
    fn mul(mut self, o: f64) -> Self {
        self.v *= o;
        for i in 0..3 {
            self.g[i] *= o;
        }
        for k in 0..6 {
            self.h[k] *= o;
        }
        for t in 0..9 {
            self.c[t] *= o;
        }
        self
    }
}

/// A 3-vector over any scalar.
#[derive(Clone, Copy, Debug)]
pub struct V3<S> {
    pub x: S,
    pub y: S,
    pub z: S,
}

impl<S: Scalar> V3<S> {
    #[inline]
    pub fn new(x: S, y: S, z: S) -> Self {
        V3 { x, y, z }
    }
    #[inline]
    pub fn cst(v: glam::DVec3) -> Self {
        V3::new(S::cst(v.x), S::cst(v.y), S::cst(v.z))
    }
    #[inline]
    pub fn val(&self) -> glam::DVec3 {
        glam::DVec3::new(self.x.val(), self.y.val(), self.z.val())
    }
    #[inline]
    pub fn dot(self, o: Self) -> S {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline]
    pub fn cross(self, o: Self) -> Self {
        V3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    #[inline]
    pub fn scale(self, s: S) -> Self {
        V3::new(self.x * s, self.y * s, self.z * s)
    }
    #[inline]
    pub fn scalef(self, s: f64) -> Self {
        V3::new(self.x * s, self.y * s, self.z * s)
    }
    /// Dot with a constant vector (cheap: no products of derivatives).
    #[inline]
    pub fn dotc(self, c: glam::DVec3) -> S {
        self.x * c.x + self.y * c.y + self.z * c.z
    }
    /// Cross with a constant vector on the right.
    #[inline]
    pub fn crossc(self, c: glam::DVec3) -> Self {
        V3::new(
            self.y * c.z + self.z * -c.y,
            self.z * c.x + self.x * -c.z,
            self.x * c.y + self.y * -c.x,
        )
    }
    /// A constant vector times a scalar.
    #[inline]
    pub fn cscale(c: glam::DVec3, s: S) -> Self {
        V3::new(s * c.x, s * c.y, s * c.z)
    }
    #[inline]
    pub fn norm(self) -> S {
        self.dot(self).sqrt()
    }
    #[inline]
    pub fn unit(self) -> Self {
        // One reciprocal and three products: a dual division costs a
        // chain rule and a product.
        let inv = self.norm().recip();
        self.scale(inv)
    }
}

impl<S: Scalar> Add for V3<S> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        V3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<S: Scalar> Sub for V3<S> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        V3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// The general second-order chain rule, `outer` over M intermediates
    /// y, `inner` the intermediates over N variables: g = sum_k f_k y_k',
    /// H = J^T F J + sum_k f_k y_k'' (the bend terms' chain rule before
    /// `compose_edges`, kept as its reference).
    fn compose_full<const M: usize, const TM: usize, const N: usize, const T: usize>(
        outer: &Dual<M, TM>,
        inner: &[Dual<N, T>; M],
    ) -> Dual<N, T> {
        let mut out = Dual::<N, T>::cst(outer.v);
        let mut p = [[0.0; N]; M];
        for (k, pk) in p.iter_mut().enumerate() {
            for (l, y) in inner.iter().enumerate() {
                let f = outer.hess(k, l);
                if f != 0.0 {
                    for a in 0..N {
                        pk[a] += f * y.g[a];
                    }
                }
            }
        }
        for (k, y) in inner.iter().enumerate() {
            let fk = outer.g[k];
            if fk != 0.0 {
                for a in 0..N {
                    out.g[a] += fk * y.g[a];
                }
                for t in 0..T {
                    out.h[t] += fk * y.h[t];
                }
            }
        }
        let mut t = 0;
        for a in 0..N {
            for b in a..N {
                let mut s = 0.0;
                for k in 0..M {
                    s += inner[k].g[a] * p[k][b];
                }
                out.h[t] += s;
                t += 1;
            }
        }
        out
    }

    fn random<const N: usize, const T: usize>(rng: &mut Rng, zeros: bool) -> Dual<N, T> {
        let mut d = Dual::<N, T>::cst(rng.normal());
        // Some exact zeros, as an arm's unused fourth variable and a
        // zero-curvature term give.
        let mut x = || {
            let v = rng.normal();
            if zeros && v.abs() < 0.3 { 0.0 } else { v }
        };
        d.g.iter_mut().for_each(|g| *g = x());
        d.h.iter_mut().for_each(|h| *h = x());
        d
    }

    /// `compose_edges` equals the full chain rule over the rotations as
    /// 8-variable duals to the bit: value, gradient and Hessian.
    #[test]
    fn compose_edges_equals_the_full_chain_rule_to_the_bit() {
        let mut rng = Rng::new(3);
        for case in 0..200 {
            let zeros = case % 2 == 1;
            let outer = random::<6, 21>(&mut rng, zeros);
            let inner: [[Dual<4, 10>; 3]; 2] =
                std::array::from_fn(|_| std::array::from_fn(|_| random(&mut rng, zeros)));
            // Edge e's rotations as 8-variable duals, its variables at 4 e..
            let full: [Dual<8, 36>; 6] = std::array::from_fn(|k| {
                let e = k / 3;
                Dual::<8, 36>::embed(&inner[e][k % 3], 4 * e)
            });
            let want = compose_full(&outer, &full);
            let got = compose_edges(&outer, &inner);
            assert_eq!(got.v.to_bits(), want.v.to_bits());
            for (x, y) in got.g.iter().zip(&want.g).chain(got.h.iter().zip(&want.h)) {
                assert_eq!(x.to_bits(), y.to_bits(), "case {case}: {x} vs {y}");
            }
        }
    }
}
