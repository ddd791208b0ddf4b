//! The best rigid motion between two point sets in correspondence
//! (Kabsch's problem, solved by Horn's quaternion): the target fit's step
//! and the placement of a front laid on a saddle (docs/recipe.md).

use glam::DQuat;
use glam::DVec3;

/// A proper rigid motion: `p -> rotation * p + translation`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rigid {
    /// A unit quaternion.
    pub rotation: DQuat,
    /// mm.
    pub translation: DVec3,
}

impl Rigid {
    /// The motion that moves nothing.
    pub const IDENTITY: Rigid = Rigid {
        rotation: DQuat::IDENTITY,
        translation: DVec3::ZERO,
    };

    /// `p` moved.
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.rotation * p + self.translation
    }

    /// This motion after `first`.
    pub(crate) fn after(&self, first: &Rigid) -> Rigid {
        Rigid {
            rotation: (self.rotation * first.rotation).normalize(),
            translation: self.rotation * first.translation + self.translation,
        }
    }

    pub(crate) fn inverse(&self) -> Rigid {
        let r = self.rotation.inverse();
        Rigid {
            rotation: r,
            translation: -(r * self.translation),
        }
    }
}

/// The proper rigid motion that takes `from[i]` closest to `to[i]` in the
/// least-squares sense (Horn 1987: the quaternion is the eigenvector of the
/// largest eigenvalue of a 4 x 4 matrix of the cross-covariance).
pub fn kabsch(from: &[DVec3], to: &[DVec3]) -> Rigid {
    let n = from.len().min(to.len());
    if n == 0 {
        return Rigid::IDENTITY;
    }
    let ca = from[..n].iter().sum::<DVec3>() / n as f64;
    let cb = to[..n].iter().sum::<DVec3>() / n as f64;
    // s[i][j] = sum of a_i b_j over the centred points.
    let mut s = [[0.0f64; 3]; 3];
    for (a, b) in from[..n].iter().zip(&to[..n]) {
        let (a, b) = (*a - ca, *b - cb);
        for i in 0..3 {
            for j in 0..3 {
                s[i][j] += a[i] * b[j];
            }
        }
    }
    let q = horn_rotation(s);
    Rigid {
        rotation: q,
        translation: cb - q * ca,
    }
}

/// Horn's rotation (a unit quaternion; NaN when `s` is) maximising
/// sum q.Rp, from the cross-covariance `s[i][j] = sum p_i q_j` of centred
/// points: the eigenvector of the largest eigenvalue of a 4 x 4 matrix.
pub(crate) fn horn_rotation(s: [[f64; 3]; 3]) -> DQuat {
    let [[xx, xy, xz], [yx, yy, yz], [zx, zy, zz]] = s;
    let m = [
        [xx + yy + zz, yz - zy, zx - xz, xy - yx],
        [yz - zy, xx - yy - zz, xy + yx, zx + xz],
        [zx - xz, xy + yx, -xx + yy - zz, yz + zy],
        [xy - yx, zx + xz, yz + zy, -xx - yy + zz],
    ];
    let (values, vectors) = jacobi(m);
    let k = (0..4).fold(0, |k, i| if values[i] > values[k] { i } else { k });
    DQuat::from_xyzw(vectors[1][k], vectors[2][k], vectors[3][k], vectors[0][k]).normalize()
}

/// Eigenvalues and eigenvectors (columns) of a symmetric matrix, by cyclic
/// Jacobi rotations: deterministic and accurate to rounding.
pub(crate) fn jacobi<const N: usize>(mut a: [[f64; N]; N]) -> ([f64; N], [[f64; N]; N]) {
    let mut v = [[0.0; N]; N];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for _ in 0..100 {
        let off: f64 = (0..N)
            .flat_map(|i| (0..N).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        let scale: f64 = (0..N).map(|i| a[i][i] * a[i][i]).sum::<f64>() + off;
        if off <= 1e-32 * scale || off == 0.0 {
            break;
        }
        for p in 0..N {
            for q in p + 1..N {
                if a[p][q] == 0.0 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                // The smaller root of t^2 + 2 theta t - 1 = 0 (Numerical
                // Recipes 11.1): the rotation that zeroes a[p][q].
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                // a <- J^T a J, v <- v J.
                turn_columns(&mut a, p, q, c, s);
                let (rp, rq) = (a[p], a[q]);
                for (k, (x, y)) in rp.iter().zip(&rq).enumerate() {
                    a[p][k] = c * x - s * y;
                    a[q][k] = s * x + c * y;
                }
                turn_columns(&mut v, p, q, c, s);
            }
        }
    }
    (std::array::from_fn(|i| a[i][i]), v)
}

/// Columns p and q of `m` turned by the rotation (c, s) in their plane.
fn turn_columns<const N: usize>(m: &mut [[f64; N]; N], p: usize, q: usize, c: f64, s: f64) {
    for row in m {
        let (x, y) = (row[p], row[q]);
        row[p] = c * x - s * y;
        row[q] = s * x + c * y;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kabsch_recovers_a_random_rigid_motion() {
        // Deterministic scattered numbers in -1..1.
        let mut k = 0.0f64;
        let mut signed = || {
            k += 1.0;
            (k * 12.9898).sin() * 0.999
        };
        for _ in 0..50 {
            let axis = DVec3::new(signed(), signed(), signed()).normalize();
            let motion = Rigid {
                rotation: DQuat::from_axis_angle(axis, 3.0 * signed()),
                translation: DVec3::new(signed(), signed(), signed()) * 500.0,
            };
            let from: Vec<DVec3> = (0..20)
                .map(|_| DVec3::new(signed(), signed(), signed()) * 300.0)
                .collect();
            let to: Vec<DVec3> = from.iter().map(|&p| motion.apply(p)).collect();
            let got = kabsch(&from, &to);
            for (p, q) in from.iter().zip(&to) {
                assert!(got.apply(*p).distance(*q) < 1e-9, "{got:?} vs {motion:?}");
            }
        }
    }
}
