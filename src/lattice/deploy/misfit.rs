//! How far a rigid placement of a planar lattice's cells misses at other
//! openings than the design's (docs/math.md 8.4).

use super::super::shape::legs_of;
use super::super::{Cell, Lattice, Legs};
use super::Configuration;
use super::configuration::Affine;
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
    let valid = |t: f64| lattice.dim == 2 && config.holds(t);
    // The openings tried, with their own placements (vertex by vertex).
    let tried: Vec<(usize, f64)> = (0..thetas.len())
        .filter(|&k| valid(thetas[k]))
        .map(|k| (k, thetas[k].cos()))
        .collect();
    let mut out = vec![None; thetas.len()];
    if tried.is_empty() {
        return out;
    }
    // The placements live in a ring of vertices (`Lattice::vertex_rings`;
    // on 4 M cells 190 MB fewer than a slot each).
    let (window, full) = lattice.vertex_rings();
    for chunk in tried.chunks(LANES) {
        // Unused lanes repeat the first opening; their results are dropped.
        let cos = std::array::from_fn(|k| chunk.get(k).unwrap_or(&chunk[0]).1);
        let misfit = (window < full)
            .then(|| misfits_in(lattice, config, cos, window))
            .flatten()
            .unwrap_or_else(|| {
                misfits_in(lattice, config, cos, full).expect("a slot for every vertex")
            });
        for (&(k, _), m) in chunk.iter().zip(misfit) {
            out[k] = Some(m.sqrt());
        }
    }
    out
}

/// Openings placed side by side in one pass (`MISFIT_FRACTIONS` has three):
/// each lane's square roots and divisions wait on the cell before, so the
/// lanes are computed stage by stage, each stage's three independent.
pub(super) const LANES: usize = 3;

/// The largest squared miss over the squared mean leg at each opening
/// whose cosine is in `cos`, the placements held in a ring of `window`
/// vertices (a power of two); None when some cell's corners lie too far
/// apart in vertex order for it.
fn misfits_in(
    lattice: &Lattice,
    config: &Configuration,
    cos: [f64; LANES],
    window: usize,
) -> Option<[f64; LANES]> {
    let mut placements = Placements::new(cos, window);
    for (cell, &f) in lattice.cells.iter().zip(&config.cos_phi) {
        // From the corners at hand: 4 square roots a cell are no slower
        // than storing every cell's legs (128 MB on 4 M cells) and reading
        // them back.
        let corners = lattice.corners(cell);
        if !placements.add(cell, corners, legs_of(corners, cell.pivot), f) {
            return None;
        }
    }
    Some(placements.finish())
}

/// The planar misfits' running state, fed the cells in order
/// (`misfits_in`, or C(theta) as it takes a grid's cells in order, with
/// their corners and legs at hand: `deployment`): each opening's
/// placements of the vertices in a ring of `window` slots (vertex v in slot
/// v mod window), and its largest squared miss over the squared mean leg.
///
/// Why the ring holds what a slot per vertex would: every cell's corners
/// lie in `(high - window, high]`, `high` the largest corner index so far.
/// A corner read at a cell and another index of its slot written after it
/// would both lie in the window of that later write (the indices only
/// grow), which holds no two indices of one slot.
pub(super) struct Placements {
    cos: [f64; LANES],
    mask: usize,
    placed: Vec<[DVec2; LANES]>,
    /// Which vertex each slot holds (placed by an earlier cell); which
    /// vertices are placed depends on the cells only, not on theta.
    holds: Vec<u32>,
    high: usize,
    /// The largest squared miss over the squared mean leg, per opening.
    misfit: [f64; LANES],
}

impl Placements {
    /// Placements at the openings whose cosines are `cos`, in a ring of
    /// `window` slots (a power of two).
    pub(super) fn new(cos: [f64; LANES], window: usize) -> Self {
        Self {
            cos,
            mask: window - 1,
            placed: vec![[DVec2::ZERO; LANES]; window],
            holds: vec![u32::MAX; window],
            high: 0,
            misfit: [0.0; LANES],
        }
    }

    /// Place the next cell, with its corners, legs and `cos(phi)` as a
    /// function of the reference opening; false when its corners lie too
    /// far apart in vertex order for the ring.
    #[inline]
    pub(super) fn add(&mut self, cell: &Cell, corners: [DVec3; 4], legs: Legs, f: Affine) -> bool {
        let ids = cell.corner_ids();
        let (lo, hi) = ids
            .iter()
            .fold((u32::MAX, 0), |(l, h), &v| (l.min(v), h.max(v)));
        self.high = self.high.max(hi as usize);
        if lo as usize + self.mask < self.high {
            return false;
        }
        let side = side(corners, cell.pivot);
        let scale = legs.iter().sum::<f64>() / 4.0;
        // Misses compared squared, over the squared scale: one square
        // root per opening at the end, not one per corner.
        let inv_scale2 = 1.0 / (scale * scale);
        // `from_fn` rather than `map` on the arrays of this loop: the same
        // values, and the compiler inlines it (`map` went through a drain
        // guard in some builds, 12 % more instructions in this loop).
        let slots: [usize; 4] = std::array::from_fn(|c| ids[c] as usize & self.mask);
        // The fit uses the corners placed before this cell; a corner
        // repeated in the cell is placed by its first occurrence.
        let before: [bool; 4] = std::array::from_fn(|c| self.holds[slots[c]] == ids[c]);
        let mut known = before;
        for c in 1..4 {
            known[c] |= ids[..c].contains(&ids[c]);
        }
        let cos = self.cos;
        let local: [[DVec2; 4]; LANES] =
            std::array::from_fn(|k| cell_at(legs, side, f.at(cos[k]).clamp(-1.0, 1.0)));
        let mut pairs = [[(DVec2::ZERO, DVec2::ZERO); LANES]; 4];
        let mut m = 0;
        for c in 0..4 {
            if before[c] {
                let at = &self.placed[slots[c]];
                pairs[m] = std::array::from_fn(|k| (local[k][c], at[k]));
                m += 1;
            }
        }
        let fits = rigid_fits(&pairs[..m]);
        for c in 0..4 {
            let slot = &mut self.placed[slots[c]];
            for k in 0..LANES {
                let q = fits[k].apply(local[k][c]);
                if known[c] {
                    self.misfit[k] = self.misfit[k].max(slot[k].distance_squared(q) * inv_scale2);
                } else {
                    slot[k] = q;
                }
            }
        }
        for c in 0..4 {
            self.holds[slots[c]] = ids[c];
        }
        true
    }

    /// The largest squared miss over the squared mean leg, per opening.
    pub(super) fn finish(self) -> [f64; LANES] {
        self.misfit
    }
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

/// A proper rigid motion of the plane: `p -> cq + rot (p - cp)`.
#[derive(Clone, Copy)]
struct Fit {
    cp: DVec2,
    cq: DVec2,
    rot: DVec2,
}

impl Fit {
    #[inline]
    fn apply(&self, p: DVec2) -> DVec2 {
        self.cq + self.rot.rotate(p - self.cp)
    }
}

/// The proper rigid motion taking the first points of `pairs` onto the
/// second (least squares); the identity when there are none.
#[cfg(test)]
fn rigid_fit(pairs: &[(DVec2, DVec2)]) -> impl Fn(DVec2) -> DVec2 + use<> {
    let lanes: Vec<[(DVec2, DVec2); 1]> = pairs.iter().map(|&p| [p]).collect();
    let [fit] = rigid_fits(&lanes);
    move |p: DVec2| fit.apply(p)
}

/// `rigid_fit` of every lane: `pairs[j][k]` is pair j of lane k. The lanes
/// are independent and computed stage by stage, so that their divisions
/// and square roots overlap.
#[inline]
fn rigid_fits<const L: usize>(pairs: &[[(DVec2, DVec2); L]]) -> [Fit; L] {
    let n = pairs.len().max(1) as f64;
    let (mut cp, mut cq) = ([DVec2::ZERO; L], [DVec2::ZERO; L]);
    for lanes in pairs {
        for k in 0..L {
            let (p, q) = lanes[k];
            (cp[k], cq[k]) = (cp[k] + p, cq[k] + q);
        }
    }
    let cp: [DVec2; L] = std::array::from_fn(|k| cp[k] / n);
    let cq: [DVec2; L] = std::array::from_fn(|k| cq[k] / n);
    // The rotation maximising sum q'.R p' (2-D Kabsch): the direction of
    // (c, s), normalised (no angle taken and turned back into a vector).
    let (mut s, mut c) = ([0.0; L], [0.0; L]);
    for lanes in pairs {
        for k in 0..L {
            let (p, q) = lanes[k];
            let (p, q) = (p - cp[k], q - cq[k]);
            c[k] += p.dot(q);
            s[k] += p.x * q.y - p.y * q.x;
        }
    }
    std::array::from_fn(|k| {
        let h = (c[k] * c[k] + s[k] * s[k]).sqrt();
        let rot = if pairs.len() < 2 || h == 0.0 {
            DVec2::X
        } else {
            DVec2::new(c[k] / h, s[k] / h)
        };
        Fit {
            cp: cp[k],
            cq: cq[k],
            rot,
        }
    })
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

    /// The ring of placements measures what a slot per vertex does, bit
    /// for bit, down to the smallest ring the corners allow; a ring too
    /// small for them says so, and a lattice stored out of order is
    /// measured with a slot per vertex.
    #[test]
    fn the_ring_of_placements_measures_what_a_slot_per_vertex_does() {
        let mut rng = crate::rng::Rng::new(5);
        let mut measured = 0;
        for trial in 0..24 {
            let Some(lattice) = crate::lattice::shape::random_sheet(&mut rng, trial, 2) else {
                continue;
            };
            let config = super::super::configuration(&lattice);
            let cos = [0.99, 0.9, 0.5].map(|f: f64| (f * config.theta_design).cos());
            let nv = lattice.vertices.len();
            let every = misfits_in(&lattice, &config, cos, nv.next_power_of_two())
                .expect("a slot for every vertex");
            assert!(every.iter().all(|m| m.is_finite()));
            let (usual, _) = lattice.vertex_rings();
            let ring = misfits_in(&lattice, &config, cos, usual).expect("a sheet fits");
            assert_eq!(ring.map(f64::to_bits), every.map(f64::to_bits));
            // Smaller rings wrap around every few cells: each that takes
            // the corners gives the same bits; the smallest is refused.
            let mut smallest = usual;
            for window in [4, 8, 16, 32].into_iter().filter(|&w| w < usual) {
                if let Some(ring) = misfits_in(&lattice, &config, cos, window) {
                    assert_eq!(ring.map(f64::to_bits), every.map(f64::to_bits));
                    smallest = smallest.min(window);
                }
            }
            assert!(misfits_in(&lattice, &config, cos, 2).is_none());
            assert!(smallest <= (lattice.width + 3).next_power_of_two());
            measured += 1;
            // Out of order (the cells reversed): too spread for a small
            // ring, and measured as with a slot per vertex.
            let mut reversed = lattice.clone();
            reversed.cells.reverse();
            let config = super::super::configuration(&reversed);
            let thetas = [0.9 * config.theta_design];
            let cos = [thetas[0].cos(); LANES];
            assert!(misfits_in(&reversed, &config, cos, 8).is_none());
            let every = misfits_in(&reversed, &config, cos, nv.next_power_of_two())
                .expect("a slot for every vertex");
            let got = planar_misfits(&reversed, &config, &thetas)[0].expect("planar");
            assert_eq!(got.to_bits(), every[0].sqrt().to_bits());
        }
        assert!(measured >= 12, "{measured} lattices grew");
    }

    /// `deployment` places a grown sheet's cells as C(theta) takes them
    /// (every cell, in order: that path is the one taken) and out of order
    /// measures them by the second pass: its misfits are the second pass's
    /// bit for bit either way.
    #[test]
    fn the_misfits_placed_with_c_theta_are_the_second_passes() {
        let sheets = crate::lattice::shape::random_sheets(23, 24, |_| 2);
        assert!(sheets.len() >= 12, "{} lattices grew", sheets.len());
        for lattice in sheets {
            let mut reversed = lattice.clone();
            reversed.cells.reverse();
            for (lattice, grid) in [(&lattice, true), (&reversed, false)] {
                let mut taken = 0;
                let (_, in_order) =
                    super::super::configuration::configuration_with(lattice, |_, _, _, _| {
                        taken += 1;
                    });
                assert_eq!(in_order, grid);
                assert_eq!(taken == lattice.cells.len(), grid);
                let d = super::super::deployment(lattice);
                let thetas = super::super::MISFIT_FRACTIONS.map(|f| f * d.config.theta_design);
                let apart: Vec<(f64, f64)> = super::super::MISFIT_FRACTIONS
                    .iter()
                    .zip(planar_misfits(lattice, &d.config, &thetas))
                    .filter_map(|(&f, m)| Some((f, m?)))
                    .collect();
                let as_bits = |m: &[(f64, f64)]| {
                    m.iter()
                        .map(|(f, m)| (f.to_bits(), m.to_bits()))
                        .collect::<Vec<_>>()
                };
                assert_eq!(as_bits(&d.misfits), as_bits(&apart));
                assert!(!d.misfits.is_empty());
            }
        }
    }
}
