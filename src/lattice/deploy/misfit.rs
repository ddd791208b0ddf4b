//! How far a rigid placement of a planar lattice's cells misses at other
//! openings than the design's (MATH.md 8.4).

use super::super::Lattice;
use super::Configuration;
use glam::{DVec2, DVec3};

/// The largest misfit (relative to the mean leg) of placing a planar
/// lattice's cells rigidly, in grid order, at the reference opening theta.
/// None for 3-D lattices and thetas outside the valid range.
pub fn planar_misfit(lattice: &Lattice, config: &Configuration, theta: f64) -> Option<f64> {
    planar_misfits(lattice, config, &[theta])[0]
}

/// `planar_misfit` at several openings in one pass over the lattice: a
/// cell's corners, legs and side are read and measured once for all.
pub fn planar_misfits(
    lattice: &Lattice,
    config: &Configuration,
    thetas: &[f64],
) -> Vec<Option<f64>> {
    let valid = |t: f64| lattice.dim == 2 && (0.0..=config.theta_max).contains(&t);
    // The openings tried, with their own placements (vertex by vertex).
    let tried: Vec<(usize, f64)> = (0..thetas.len())
        .filter(|&k| valid(thetas[k]))
        .map(|k| (k, thetas[k].cos()))
        .collect();
    let mut out = vec![None; thetas.len()];
    if tried.is_empty() {
        return out;
    }
    let t = tried.len();
    let nv = lattice.vertices.len();
    let mut placed = vec![DVec2::ZERO; nv * t];
    // Which vertices are placed depends on the cells only, not on theta.
    let mut is_placed = vec![false; nv];
    // The largest squared miss over the squared mean leg, per opening.
    let mut misfit = vec![0.0f64; t];
    for (i, cell) in lattice.cells.iter().enumerate() {
        let corners = lattice.corners(cell);
        let p = cell.pivot;
        let [ul, ur, ll, lr] = corners;
        let legs = [
            p.distance(ul),
            p.distance(ll),
            p.distance(lr),
            p.distance(ur),
        ];
        let side = side(corners, p);
        let scale = legs.iter().sum::<f64>() / 4.0;
        // Misses compared squared, over the squared scale: one square
        // root per opening at the end, not one per corner.
        let inv_scale2 = 1.0 / (scale * scale);
        let ids = [cell.ul, cell.ur, cell.ll, cell.lr].map(|v| v as usize);
        // The fit uses the corners placed before this cell; a corner
        // repeated in the cell is placed by its first occurrence.
        let before = ids.map(|v| is_placed[v]);
        let mut known = before;
        for c in 1..4 {
            known[c] |= ids[..c].contains(&ids[c]);
        }
        for (k, &(_, cos_theta)) in tried.iter().enumerate() {
            let cos_phi = config.cos_phi[i].at(cos_theta).clamp(-1.0, 1.0);
            let local = cell_at(legs, side, cos_phi);
            let mut pairs = [(DVec2::ZERO, DVec2::ZERO); 4];
            let mut m = 0;
            for c in 0..4 {
                if before[c] {
                    pairs[m] = (local[c], placed[ids[c] * t + k]);
                    m += 1;
                }
            }
            let fit = rigid_fit(&pairs[..m]);
            for c in 0..4 {
                let q = fit(local[c]);
                let slot = &mut placed[ids[c] * t + k];
                if known[c] {
                    misfit[k] = misfit[k].max(slot.distance_squared(q) * inv_scale2);
                } else {
                    *slot = q;
                }
            }
        }
        for v in ids {
            is_placed[v] = true;
        }
    }
    for (&(k, _), m) in tried.iter().zip(misfit) {
        out[k] = Some(m.sqrt());
    }
    out
}

/// Which way a cell turns from the leg to UL to the leg to UR: +1 or -1.
fn side(corners: [DVec3; 4], pivot: DVec3) -> f64 {
    let [ul, ur, _, _] = corners;
    let (a, b) = (ul - pivot, ur - pivot);
    if a.x * b.y - a.y * b.x < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// A cell's corners [UL, UR, LL, LR] at the opening whose cosine is
/// `cos_phi`, in its own frame: the leg to UL along +x from the pivot at
/// the origin, the leg to UR turned by phi to `side`. `sin(phi)` is
/// `sqrt(1 - cos^2)` (phi is in [0, pi]): no inverse and direct cosines.
fn cell_at(legs: [f64; 4], side: f64, cos_phi: f64) -> [DVec2; 4] {
    let [l1, l2, l3, l4] = legs;
    let sin_phi = (1.0 - cos_phi * cos_phi).max(0.0).sqrt();
    let dir_a = DVec2::X;
    let dir_b = DVec2::new(cos_phi, side * sin_phi);
    [dir_a * l1, dir_b * l4, -dir_b * l2, -dir_a * l3]
}

/// The proper rigid motion taking the first points of `pairs` onto the
/// second (least squares); the identity when there are none.
fn rigid_fit(pairs: &[(DVec2, DVec2)]) -> impl Fn(DVec2) -> DVec2 + use<> {
    let n = pairs.len().max(1) as f64;
    let (cp, cq) = pairs
        .iter()
        .fold((DVec2::ZERO, DVec2::ZERO), |(a, b), (p, q)| {
            (a + *p, b + *q)
        });
    let (cp, cq) = (cp / n, cq / n);
    // The rotation maximising sum q'.R p' (2-D Kabsch): the direction of
    // (c, s), normalised (no angle taken and turned back into a vector).
    let (mut s, mut c) = (0.0, 0.0);
    for (p, q) in pairs {
        let (p, q) = (*p - cp, *q - cq);
        c += p.dot(q);
        s += p.x * q.y - p.y * q.x;
    }
    let h = (c * c + s * s).sqrt();
    let rot = if pairs.len() < 2 || h == 0.0 {
        DVec2::X
    } else {
        DVec2::new(c / h, s / h)
    };
    move |p: DVec2| cq + rot.rotate(p - cp)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed forms give the rotation and the cell the angles gave.
    #[test]
    fn closed_forms_match_the_angles() {
        let phi = 1.1f64;
        let cell = cell_at([3.0, 4.0, 5.0, 6.0], -1.0, phi.cos());
        let b = DVec2::new(phi.cos(), -phi.sin());
        assert!((cell[1] - 6.0 * b).length() < 1e-14);
        assert!((cell[2] + 4.0 * b).length() < 1e-14);
        let rot = DVec2::from_angle(0.7);
        let ps = [
            DVec2::new(1.0, 2.0),
            DVec2::new(-3.0, 0.5),
            DVec2::new(0.2, -1.0),
        ];
        let pairs: Vec<_> = ps
            .iter()
            .map(|&p| (p, rot.rotate(p) + DVec2::new(4.0, -2.0)))
            .collect();
        let fit = rigid_fit(&pairs);
        for (p, q) in pairs {
            assert!(fit(p).distance(q) < 1e-14);
        }
        assert_eq!(rigid_fit(&[])(DVec2::new(1.0, 2.0)), DVec2::new(1.0, 2.0));
    }
}
