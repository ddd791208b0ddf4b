//! A loop front laid on a saddle (docs/recipe.md, "Rebuilt fronts"):
//! every edge length kept (and so kappa), on the hyperbolic paraboloid
//! z' = r^2 (c cos 2t + d cos 6t) in the front's own frame, placed back
//! by the best rigid fit onto the front as grown.

use super::front::{FrontError, refuse};
use crate::rigid::kabsch;
use glam::DVec3;

/// The saddle's amplitudes (1/mm): z' = r^2 (c cos 2t + d cos 6t).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Saddle {
    /// The amplitude of cos 2t: four sub-units, two up and two down.
    pub c: f64,
    /// The amplitude of cos 6t, the next term of the four-fold symmetry.
    pub d: f64,
}

/// Gauss-Newton steps at most; a laid front converges in a handful.
const MAX_STEPS: usize = 50;
/// Laid edges within this share of their length count as kept.
const KEPT: f64 = 1e-9;

/// The front's own frame: centroid, unit normal (Newell's, the mean
/// plane's) and the in-plane axes, t = 0 towards vertex 1 (the mirror
/// vertex of the sub-units).
struct Frame {
    centre: DVec3,
    normal: DVec3,
    e1: DVec3,
    e2: DVec3,
}

impl Frame {
    fn of(front: &[DVec3]) -> Option<Frame> {
        let n = front.len();
        let centre = front.iter().copied().sum::<DVec3>() / n as f64;
        let newell: DVec3 = (0..n)
            .map(|j| (front[j] - centre).cross(front[(j + 1) % n] - centre))
            .sum();
        let normal = newell.try_normalize()?;
        let d1 = front[1] - centre;
        let e1 = (d1 - d1.dot(normal) * normal).try_normalize()?;
        Some(Frame {
            centre,
            normal,
            e1,
            e2: normal.cross(e1),
        })
    }

    /// Polar coordinates (r, t) of `p`'s projection on the frame's plane.
    fn polar(&self, p: DVec3) -> (f64, f64) {
        let d = p - self.centre;
        let (x, y) = (d.dot(self.e1), d.dot(self.e2));
        (x.hypot(y), y.atan2(x))
    }
}

impl Saddle {
    /// The height c cos 2t + d cos 6t per r^2, and its t-derivative.
    fn height(&self, t: f64) -> (f64, f64) {
        let h = self.c * (2.0 * t).cos() + self.d * (6.0 * t).cos();
        let dh = -2.0 * self.c * (2.0 * t).sin() - 6.0 * self.d * (6.0 * t).sin();
        (h, dh)
    }

    /// The saddle's point above (r, t), and its r- and t-derivatives.
    fn at(&self, f: &Frame, r: f64, t: f64) -> [DVec3; 3] {
        let (h, dh) = self.height(t);
        let (s, c) = t.sin_cos();
        let radial = c * f.e1 + s * f.e2;
        let across = -s * f.e1 + c * f.e2;
        [
            f.centre + r * radial + r * r * h * f.normal,
            radial + 2.0 * r * h * f.normal,
            r * across + r * r * dh * f.normal,
        ]
    }
}

/// `front` (closed) laid on `saddle`, keeping every edge length, then
/// placed by the best rigid fit onto `front` and moved so that vertex 0
/// stays where it grew (every rebuilt loop front keeps its closing vertex).
pub(crate) fn lay(front: &[DVec3], saddle: Saddle) -> Result<Vec<DVec3>, FrontError> {
    let (_, laid) = on_saddle(front, saddle)?;
    let fit = kabsch(&laid, front);
    let placed: Vec<DVec3> = laid.iter().map(|p| fit.apply(*p)).collect();
    let shift = front[0] - placed[0];
    Ok(placed.into_iter().map(|p| p + shift).collect())
}

/// `front` laid on `saddle` in its own frame (returned with it), by
/// Gauss-Newton from the front's own polar coordinates.
fn on_saddle(front: &[DVec3], saddle: Saddle) -> Result<(Frame, Vec<DVec3>), FrontError> {
    let n = front.len();
    let frame = (n >= 3)
        .then(|| Frame::of(front))
        .flatten()
        .ok_or_else(|| {
            refuse(
                "front.saddle needs a front that spans a plane (its centroid, normal and vertex 1)"
                    .into(),
                "grow the saddle on a loop whose front is not degenerate",
            )
        })?;
    let lens: Vec<f64> = (0..n)
        .map(|j| front[j].distance(front[(j + 1) % n]))
        .collect();
    let (mut rho, mut theta): (Vec<f64>, Vec<f64>) = front.iter().map(|p| frame.polar(*p)).unzip();
    for _ in 0..MAX_STEPS {
        if !step(&frame, saddle, &lens, &mut rho, &mut theta) {
            break;
        }
    }
    let laid: Vec<DVec3> = (0..n)
        .map(|j| saddle.at(&frame, rho[j], theta[j])[0])
        .collect();
    admissible(&frame, &laid, &lens)?;
    Ok((frame, laid))
}

/// One Gauss-Newton step on the edge-length equations
/// |q_{j+1} - q_j|^2 = l_j^2 in the unknowns (rho_j, theta_j): the least
/// change (angles weighted by the radius, so both move in mm) that zeroes
/// the linearised residuals. False when the residuals are already zero
/// to rounding, or the step cannot be taken.
fn step(frame: &Frame, s: Saddle, lens: &[f64], rho: &mut [f64], theta: &mut [f64]) -> bool {
    let n = lens.len();
    let pts: Vec<[DVec3; 3]> = (0..n).map(|j| s.at(frame, rho[j], theta[j])).collect();
    let f: Vec<f64> = (0..n)
        .map(|j| pts[(j + 1) % n][0].distance_squared(pts[j][0]) - lens[j] * lens[j])
        .collect();
    if f.iter().zip(lens).all(|(r, l)| r.abs() <= 1e-15 * l * l) {
        return false;
    }
    // jac[j][2k], jac[j][2k + 1]: d f_j / d(rho_k, theta_k), k = j, j + 1.
    let mut jac = vec![vec![0.0; 2 * n]; n];
    for j in 0..n {
        let k = (j + 1) % n;
        let d = pts[k][0] - pts[j][0];
        jac[j][2 * j] -= 2.0 * d.dot(pts[j][1]);
        jac[j][2 * j + 1] -= 2.0 * d.dot(pts[j][2]);
        jac[j][2 * k] += 2.0 * d.dot(pts[k][1]);
        jac[j][2 * k + 1] += 2.0 * d.dot(pts[k][2]);
    }
    let w2: Vec<f64> = (0..2 * n)
        .map(|u| {
            if u % 2 == 0 {
                1.0
            } else {
                1.0 / (rho[u / 2] * rho[u / 2])
            }
        })
        .collect();
    let mut normal = vec![vec![0.0; n]; n];
    for a in 0..n {
        for b in 0..n {
            normal[a][b] = (0..2 * n).map(|u| jac[a][u] * w2[u] * jac[b][u]).sum();
        }
    }
    let Some(y) = solve(normal, f) else {
        return false;
    };
    for u in 0..2 * n {
        let change = (0..n).map(|a| jac[a][u] * y[a]).sum::<f64>() * w2[u];
        if u % 2 == 0 {
            rho[u / 2] -= change;
        } else {
            theta[u / 2] -= change;
        }
    }
    true
}

/// `a x = b` by Gaussian elimination with partial pivoting; None when
/// `a` is singular or the answer is not finite.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for k in 0..n {
        let p = (k..n).max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))?;
        a.swap(k, p);
        b.swap(k, p);
        if a[k][k] == 0.0 {
            return None;
        }
        let (above, below) = a.split_at_mut(k + 1);
        let pivot = &above[k];
        for (i, row) in below.iter_mut().enumerate() {
            let f = row[k] / pivot[k];
            for (x, p) in row[k..].iter_mut().zip(&pivot[k..]) {
                *x -= f * p;
            }
            b[k + 1 + i] -= f * b[k];
        }
    }
    let mut x = vec![0.0; n];
    for k in (0..n).rev() {
        let s: f64 = (k + 1..n).map(|j| a[k][j] * x[j]).sum();
        x[k] = (b[k] - s) / a[k][k];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The laid front keeps its edges, and goes once round the saddle's axis
/// in the front's order (no vertex through the axis, none doubling back):
/// its angles about the axis rise, or fall, from vertex to vertex, by 2 pi in all.
fn admissible(frame: &Frame, laid: &[DVec3], lens: &[f64]) -> Result<(), FrontError> {
    let n = laid.len();
    let theta: Vec<f64> = laid.iter().map(|p| frame.polar(*p).1).collect();
    let worst = (0..n)
        .map(|j| (laid[j].distance(laid[(j + 1) % n]) - lens[j]).abs() / lens[j])
        .fold(
            0.0f64,
            |m, e| if e.is_nan() { f64::INFINITY } else { m.max(e) },
        );
    if !(worst <= KEPT) {
        return Err(refuse(
            format!(
                "front.saddle cannot lay the front keeping its edge lengths: they miss by {} of an edge after {MAX_STEPS} Newton steps",
                if worst.is_finite() {
                    format!("{worst:.2e}")
                } else {
                    "an unbounded share".into()
                }
            ),
            "lower the saddle's amplitudes c and d (1/mm)",
        ));
    }
    let turns: Vec<f64> = (0..n)
        .map(|j| {
            (theta[(j + 1) % n] - theta[j] + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI
        })
        .collect();
    let sense = turns.iter().sum::<f64>().signum();
    let once = (turns.iter().sum::<f64>().abs() - std::f64::consts::TAU).abs() < 1e-6;
    if !once || turns.iter().any(|t| t * sense <= 0.0) {
        return Err(refuse(
            "front.saddle lays the front folded: it no longer goes once round the saddle's axis in order".into(),
            "lower the saddle's amplitudes c and d (1/mm)",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn circle(n: usize, r: f64) -> Vec<DVec3> {
        (0..n)
            .map(|j| {
                let a = std::f64::consts::TAU * j as f64 / n as f64;
                DVec3::new(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect()
    }

    /// A tilted, uneven loop: the frame is not the world's.
    fn wobbly() -> Vec<DVec3> {
        let q = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
        (0..12)
            .map(|j| {
                let a = std::f64::consts::TAU * j as f64 / 12.0 + 0.05 * (j as f64).sin();
                let r = 60.0 + 4.0 * (3.0 * a).cos();
                q * DVec3::new(r * a.cos(), r * a.sin(), 2.0 * (2.0 * a).sin())
                    + DVec3::new(5.0, -3.0, 40.0)
            })
            .collect()
    }

    fn edges(p: &[DVec3]) -> Vec<f64> {
        (0..p.len())
            .map(|j| p[j].distance(p[(j + 1) % p.len()]))
            .collect()
    }

    #[test]
    fn the_laid_front_keeps_its_edges_and_lies_on_the_saddle() {
        let front = wobbly();
        let s = Saddle { c: 0.003, d: -1e-4 };
        let (f, on) = on_saddle(&front, s).unwrap();
        // On the saddle in the front's own frame: z' = r^2 (c cos 2t + d cos 6t).
        let mut highest = 0.0f64;
        for p in &on {
            let (r, t) = f.polar(*p);
            let z = (*p - f.centre).dot(f.normal);
            let want = r * r * s.height(t).0;
            assert!((z - want).abs() < 1e-9, "{z} vs {want}");
            highest = highest.max(z.abs());
        }
        assert!(highest > 1.0, "the laid front is flat: {highest} mm");
        // Placed rigidly, every edge kept, vertex 0 where it grew.
        let laid = lay(&front, s).unwrap();
        for (a, b) in edges(&front).iter().zip(edges(&laid)) {
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
        for i in 0..on.len() {
            for j in 0..on.len() {
                let (a, b) = (on[i].distance(on[j]), laid[i].distance(laid[j]));
                assert!((a - b).abs() < 1e-9, "{i}-{j}: {a} vs {b}");
            }
        }
        assert!(laid[0].distance(front[0]) < 1e-12, "vertex 0 moved");
    }

    #[test]
    fn a_flat_saddle_leaves_a_planar_circle_planar() {
        let front = circle(12, 60.0);
        let laid = lay(&front, Saddle { c: 0.0, d: 0.0 }).unwrap();
        for (p, q) in front.iter().zip(&laid) {
            assert!(p.distance(*q) < 1e-9, "{p} -> {q}");
        }
    }

    #[test]
    fn too_steep_a_saddle_is_refused() {
        let front = circle(12, 60.0);
        let e = lay(&front, Saddle { c: 1.0, d: 0.0 }).unwrap_err();
        assert!(e.message.starts_with("front.saddle"), "{}", e.message);
    }
}
