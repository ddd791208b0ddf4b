//! The best rigid fit of a point set to a target (docs/design.md, "Fit
//! measures"): Kabsch's problem solved by Horn's quaternion, iterated over
//! closest points from a few starts, and the distances left after it.

use super::{COVERED_WITHIN, Target};
use glam::{DMat3, DQuat, DVec3};

/// Iterations of one closest-point run at most; each lowers the rms, and
/// runs stop when it falls by less than `SETTLED` of D.
const MAX_ITERATIONS: usize = 200;
const SETTLED: f64 = 1e-10;
/// Times a step is doubled at most in the line search.
const MAX_DOUBLINGS: usize = 8;

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
    fn after(&self, first: &Rigid) -> Rigid {
        Rigid {
            rotation: (self.rotation * first.rotation).normalize(),
            translation: self.rotation * first.translation + self.translation,
        }
    }

    fn inverse(&self) -> Rigid {
        let r = self.rotation.inverse();
        Rigid {
            rotation: r,
            translation: -(r * self.translation),
        }
    }
}

/// How well a point set fits a target after the best rigid fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// The motion that takes the points onto the target.
    pub motion: Rigid,
    /// Root-mean-square distance of the moved points to the target (mm).
    pub rms: f64,
    /// Largest distance of a moved point to the target (mm).
    pub largest: f64,
    /// The target's largest extent D (mm), the scale of the shares.
    pub extent: f64,
    /// Share of the target's area within `COVERED_WITHIN` of D of the
    /// facets, 0 to 1; None when no facets were given.
    pub coverage: Option<f64>,
    /// Points fitted.
    pub points: usize,
}

impl Fit {
    /// One line for reports: the distances in mm and as shares of D, and
    /// the coverage.
    pub fn summary(&self, what: &str) -> String {
        let share = |x: f64| 100.0 * x / self.extent;
        let mut line = format!(
            "{} {what}: rms {:.2} mm ({:.2} % of D), largest {:.2} mm ({:.2} % of D)",
            self.points,
            self.rms,
            share(self.rms),
            self.largest,
            share(self.largest)
        );
        if let Some(c) = self.coverage {
            line.push_str(&format!(
                "; {:.1} % of the target's area within {:.1} mm ({} % of D) of the cells",
                100.0 * c,
                COVERED_WITHIN * self.extent,
                100.0 * COVERED_WITHIN
            ));
        }
        line
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
    let [[xx, xy, xz], [yx, yy, yz], [zx, zy, zz]] = s;
    let m = [
        [xx + yy + zz, yz - zy, zx - xz, xy - yx],
        [yz - zy, xx - yy - zz, xy + yx, zx + xz],
        [zx - xz, xy + yx, -xx + yy - zz, yz + zy],
        [xy - yx, zx + xz, yz + zy, -xx - yy + zz],
    ];
    let (values, vectors) = jacobi(m);
    let k = (0..4).fold(0, |k, i| if values[i] > values[k] { i } else { k });
    let q =
        DQuat::from_xyzw(vectors[1][k], vectors[2][k], vectors[3][k], vectors[0][k]).normalize();
    Rigid {
        rotation: q,
        translation: cb - q * ca,
    }
}

/// Eigenvalues and eigenvectors (columns) of a symmetric matrix, by cyclic
/// Jacobi rotations: deterministic and accurate to rounding.
fn jacobi<const N: usize>(mut a: [[f64; N]; N]) -> ([f64; N], [[f64; N]; N]) {
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

/// The rms distance of `points` moved by `m` to the target, and the feet.
fn distances(target: &Target, points: &[DVec3], m: &Rigid) -> (f64, f64, Vec<DVec3>) {
    let mut sum = 0.0;
    let mut largest = 0.0f64;
    let feet = points
        .iter()
        .map(|&p| {
            let (q, d) = target.closest(m.apply(p));
            sum += d * d;
            largest = largest.max(d);
            q
        })
        .collect();
    ((sum / points.len().max(1) as f64).sqrt(), largest, feet)
}

/// Iterated closest points from `start`: each step moves the points by the
/// Kabsch fit to their feet on the target, which never raises the rms.
/// Where the points slide along the target (a cap on its sphere) the
/// steps shrink; each step is then repeated, doubling, while the rms falls
/// (Besl and McKay's accelerated iteration, as a line search).
fn icp(target: &Target, points: &[DVec3], start: Rigid, iterations: usize) -> (Rigid, f64) {
    let mut m = start;
    let (mut rms, _, mut feet) = distances(target, points, &m);
    for _ in 0..iterations {
        let mut next = kabsch(points, &feet);
        let (mut r, _, mut f) = distances(target, points, &next);
        if !(r < rms) {
            break;
        }
        let mut step = next.after(&m.inverse());
        for _ in 0..MAX_DOUBLINGS {
            let further = step.after(&next);
            let (r2, _, f2) = distances(target, points, &further);
            if !(r2 < r) {
                break;
            }
            (next, r, f) = (further, r2, f2);
            step = step.after(&step);
        }
        let settled = rms - r <= SETTLED * target.extent;
        (m, rms, feet) = (next, r, f);
        if settled {
            break;
        }
    }
    (m, rms)
}

/// Principal axes (columns, largest spread first) and centre of weighted
/// points.
pub(crate) fn principal(points: impl Iterator<Item = (DVec3, f64)> + Clone) -> (DMat3, DVec3) {
    let total: f64 = points
        .clone()
        .map(|(_, w)| w)
        .sum::<f64>()
        .max(f64::MIN_POSITIVE);
    let centre = points.clone().map(|(p, w)| p * w).sum::<DVec3>() / total;
    let mut c = [[0.0f64; 3]; 3];
    for (p, w) in points {
        let d = p - centre;
        for i in 0..3 {
            for j in 0..3 {
                c[i][j] += w * d[i] * d[j];
            }
        }
    }
    let (values, vectors) = jacobi(c);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| values[b].total_cmp(&values[a]).then(a.cmp(&b)));
    let col = |k: usize| DVec3::new(vectors[0][k], vectors[1][k], vectors[2][k]);
    (
        DMat3::from_cols(col(order[0]), col(order[1]), col(order[2])),
        centre,
    )
}

/// Starts of the closest-point runs: the points where they are, and their
/// principal axes laid on the target's in each of the four proper ways,
/// then with their first two axes swapped: a nearly square patch's two
/// spreads are nearly equal, so which of them comes first is no guide (a
/// vault 400 mm long and 383 mm across fitted a design lying on it at
/// 7.3 % of D from the unswapped starts alone).
fn starts(target: &Target, points: &[DVec3]) -> Vec<Rigid> {
    let mut out = vec![Rigid::IDENTITY];
    if points.len() < 3 {
        return out;
    }
    let mesh = &target.mesh;
    let (axes_t, centre_t) = principal((0..mesh.triangles.len()).map(|t| {
        (
            mesh.corners(t).iter().sum::<DVec3>() / 3.0,
            mesh.triangle_area(t),
        )
    }));
    let (axes_p, centre_p) = principal(points.iter().map(|&p| (p, 1.0)));
    let swapped = DMat3::from_cols(axes_p.y_axis, axes_p.x_axis, axes_p.z_axis);
    for (axes_p, signs) in [axes_p, swapped].into_iter().flat_map(|a| {
        [
            [1.0, 1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
        ]
        .map(|signs| (a, signs))
    }) {
        let mut s = DVec3::from_array(signs);
        let r = axes_t * DMat3::from_diagonal(s) * axes_p.transpose();
        if r.determinant() < 0.0 {
            s.z = -s.z;
        }
        let r = axes_t * DMat3::from_diagonal(s) * axes_p.transpose();
        let q = DQuat::from_mat3(&r).normalize();
        out.push(Rigid {
            rotation: q,
            translation: centre_t - q * centre_p,
        });
    }
    out
}

pub(crate) fn fit(target: &Target, points: &[DVec3], facets: &[[u32; 4]]) -> Fit {
    let finite: Vec<DVec3> = points.iter().copied().filter(|p| p.is_finite()).collect();
    // The lowest run wins; of equals, the first.
    let (motion, _) = starts(target, &finite)
        .into_iter()
        .map(|s| icp(target, &finite, s, MAX_ITERATIONS))
        .fold(None, |best: Option<(Rigid, f64)>, run| match best {
            Some(b) if b.1 <= run.1 => Some(b),
            _ => Some(run),
        })
        .unwrap_or((Rigid::IDENTITY, 0.0));
    let (rms, largest, _) = distances(target, &finite, &motion);
    let coverage = (!facets.is_empty()).then(|| {
        let moved: Vec<DVec3> = points.iter().map(|&p| motion.apply(p)).collect();
        super::coverage::covered(target, &moved, facets, COVERED_WITHIN * target.extent)
    });
    Fit {
        motion,
        rms,
        largest,
        extent: target.extent,
        coverage,
        points: finite.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn kabsch_recovers_a_random_rigid_motion() {
        let mut rng = Rng::new(32);
        for _ in 0..50 {
            let axis = DVec3::new(rng.signed(), rng.signed(), rng.signed()).normalize();
            let motion = Rigid {
                rotation: DQuat::from_axis_angle(axis, 3.0 * rng.signed()),
                translation: DVec3::new(rng.signed(), rng.signed(), rng.signed()) * 500.0,
            };
            let from: Vec<DVec3> = (0..20)
                .map(|_| DVec3::new(rng.signed(), rng.signed(), rng.signed()) * 300.0)
                .collect();
            let to: Vec<DVec3> = from.iter().map(|&p| motion.apply(p)).collect();
            let got = kabsch(&from, &to);
            for (p, q) in from.iter().zip(&to) {
                assert!(got.apply(*p).distance(*q) < 1e-9, "{got:?} vs {motion:?}");
            }
        }
    }
}
