//! How much of a fit's target the cells cover: the disk's area, the
//! ellipsoid's half in plan, the torus's tube circumference.

use super::{Fit, Surface};
use crate::lattice::Lattice;
use glam::{DVec2, DVec3};

/// How much of the target the cells cover, measured from the cells' own
/// corners.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coverage {
    /// Covered share, 0 to 1.
    pub share: f64,
    /// What is covered: "the disk's area", "the half's area in plan",
    /// "the tube's circumference".
    pub(crate) of: &'static str,
    /// For a torus: the tube angle covered (degrees).
    pub degrees: Option<f64>,
}

/// Samples per axis of the area coverage grid (a 1/300 of the target's width).
const COVERAGE_SAMPLES: usize = 300;

/// The share of the target the lattice covers: the disk's area, the
/// ellipsoid's half in plan (projected onto z = 0), or the torus's tube
/// circumference. None for a free revolution profile.
pub fn coverage(fit: &Fit, lattice: &Lattice) -> Option<Coverage> {
    match &fit.surface {
        Surface::Disk { radius } => Some(Coverage {
            share: plan_coverage(lattice, *radius, *radius),
            of: "the disk's area",
            degrees: None,
        }),
        Surface::Ellipsoid { axes } => Some(Coverage {
            share: plan_coverage(lattice, axes.x, axes.y),
            of: "the half's area in plan",
            degrees: None,
        }),
        Surface::Torus { major, .. } => {
            let deg = tube_coverage(lattice, *major);
            Some(Coverage {
                share: deg / 360.0,
                of: "the tube's circumference",
                degrees: Some(deg),
            })
        }
        Surface::Revolution { .. } | Surface::Target(_) => None,
    }
}

/// The share of the ellipse x^2/a^2 + y^2/b^2 <= 1 under the cells,
/// projected onto the xy-plane: the centres of a square grid of samples,
/// each tested against the cells that a bin grid says are near it.
fn plan_coverage(lattice: &Lattice, a: f64, b: f64) -> f64 {
    let n = COVERAGE_SAMPLES;
    let h = 2.0 * a.max(b) / n as f64;
    let quads: Vec<[DVec2; 4]> = lattice
        .cells
        .iter()
        .map(|c| {
            let [ul, ur, ll, lr] = lattice.corners(c);
            // In order round the quad.
            [ul, ur, lr, ll].map(|p| p.truncate())
        })
        .collect();
    // Bins of 8 x 8 samples hold the cells whose boxes reach them.
    let bin = 8;
    let bins = n.div_ceil(bin);
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); bins * bins];
    let origin = DVec2::new(-a.max(b), -a.max(b));
    let index = |x: f64| ((x / (h * bin as f64)).floor().max(0.0) as usize).min(bins - 1);
    for (q, quad) in quads.iter().enumerate() {
        let lo = quad
            .iter()
            .fold(DVec2::splat(f64::INFINITY), |m, p| m.min(*p))
            - origin;
        let hi = quad
            .iter()
            .fold(DVec2::splat(f64::NEG_INFINITY), |m, p| m.max(*p))
            - origin;
        if !(lo.is_finite() && hi.is_finite()) {
            continue;
        }
        for y in index(lo.y)..=index(hi.y) {
            for x in index(lo.x)..=index(hi.x) {
                grid[y * bins + x].push(q as u32);
            }
        }
    }
    let (mut inside, mut covered) = (0usize, 0usize);
    for iy in 0..n {
        for ix in 0..n {
            let p = origin + h * DVec2::new(ix as f64 + 0.5, iy as f64 + 0.5);
            if (p.x / a).powi(2) + (p.y / b).powi(2) > 1.0 {
                continue;
            }
            inside += 1;
            let cell = &grid[(iy / bin) * bins + ix / bin];
            if cell.iter().any(|&q| in_quad(&quads[q as usize], p)) {
                covered += 1;
            }
        }
    }
    covered as f64 / inside.max(1) as f64
}

/// Inside (or on) a convex quad given in order round it, either orientation.
fn in_quad(q: &[DVec2; 4], p: DVec2) -> bool {
    let mut sign = 0.0f64;
    for k in 0..4 {
        let (a, b) = (q[k], q[(k + 1) % 4]);
        let c = (b - a).perp_dot(p - a);
        if c != 0.0 {
            if sign * c < 0.0 {
                return false;
            }
            sign = c;
        }
    }
    true
}

/// Degrees of the tube's circumference under the cells: each cell spans
/// the tube angles of its corners (psi = atan2(rho - R, z), 0 at the top);
/// the union of those arcs.
fn tube_coverage(lattice: &Lattice, major: f64) -> f64 {
    let psi = |p: DVec3| (p.truncate().length() - major).atan2(p.z).to_degrees();
    let mut arcs: Vec<(f64, f64)> = Vec::new();
    for c in &lattice.cells {
        let angles = lattice.corners(c).map(psi);
        // The shortest arc holding all four: unwrap about the first.
        let a0 = angles[0];
        let rel: Vec<f64> = angles
            .iter()
            .map(|a| (a - a0 + 540.0).rem_euclid(360.0) - 180.0)
            .collect();
        let lo = (rel.iter().copied().fold(f64::INFINITY, f64::min) + a0).rem_euclid(360.0);
        let span = rel.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - rel.iter().copied().fold(f64::INFINITY, f64::min);
        if lo + span > 360.0 {
            arcs.push((lo, 360.0));
            arcs.push((0.0, lo + span - 360.0));
        } else {
            arcs.push((lo, lo + span));
        }
    }
    arcs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut total, mut end) = (0.0, f64::NEG_INFINITY);
    for (a, b) in arcs {
        if b <= end {
            continue;
        }
        total += b - a.max(end);
        end = b;
    }
    total
}
