//! The optimiser's cost: the recipe's weighted objectives of a grown
//! design, plus each hard constraint's shortfall.

use super::*;

/// The cost of a grown design and each hard constraint's shortfall
/// (name, measured value, bound, shortfall > 0 when it fails).
pub(crate) fn cost(
    d: &Design,
    lattice: &Lattice,
    opt: &Optimise,
    m: &Measures,
) -> (f64, Vec<(&'static str, f64, f64, f64)>) {
    let w = &opt.weights;
    let mut c = 0.0;
    // The simulated strips' strain beyond the allowable (`shape = "simulated"`).
    let mut c_over = 0.0;
    let size = d.fit.as_ref().map_or(1.0, |f| f.surface.size());
    if w.surface > 0.0 {
        c += w.surface * m.fit_distance.unwrap_or(0.0) / size;
    }
    if w.boundary > 0.0 {
        c += w.boundary * m.boundary_distance.unwrap_or(0.0) / size;
    }
    if w.coverage > 0.0 {
        c += w.coverage * (1.0 - m.coverage.map_or(1.0, |c| c.share));
    }
    if w.regularity > 0.0 {
        c += w.regularity * (m.shape.area_ratio.ln() + m.shape.cell_leg_ratio_max.ln());
    }
    let min_leg = d.fabrication.eyelet.flange + 2.0 * MIN_WALL;
    if w.legs > 0.0 {
        c += w.legs * ((min_leg - m.shape.min_leg) / min_leg).max(0.0);
    }
    if w.clashes > 0.0 {
        let reach = d.fabrication.material.width + d.clash.clearance;
        // Those not kept (beyond the closest `clash::KEPT`) summed alike.
        let (dropped, distance) = m.clashes.dropped();
        c += w.clashes
            * (m.clashes
                .iter()
                .map(|k| 1.0 + (reach - k.distance) / reach)
                .sum::<f64>()
                + if dropped > 0 {
                    dropped as f64 * 2.0 - distance / reach
                } else {
                    0.0
                });
    }
    if w.curvature > 0.0 && !m.shape.curvature.is_empty() {
        let scale = opt.defect_deg.abs().max(1.0);
        let simulated;
        let curvature = if opt.simulated {
            simulated = simulated_shape(d, lattice);
            match &simulated {
                Some((c, eps)) => {
                    // Strips the build would refuse: a cost as for a hard
                    // constraint, so the search keeps to buildable designs.
                    let allow = d.simulation.material.eps_allow;
                    if !d.simulation.accept_overstrain && *eps > allow {
                        c_over = PENALTY * (eps - allow) / allow;
                    }
                    c
                }
                // No equilibrium: as far from the target as a design can be.
                None => return (UNGROWN, constraints(opt, m)),
            }
        } else {
            &m.shape.curvature
        };
        let err: f64 = curvature
            .iter()
            .map(|v| {
                let key = lattice.vertex(v.vertex).key;
                let want = match opt.pattern {
                    Pattern::Constant => opt.defect_deg,
                    Pattern::Checkerboard if (key.row + key.col).is_multiple_of(2) => {
                        opt.defect_deg
                    }
                    Pattern::Checkerboard => -opt.defect_deg,
                };
                ((v.defect.to_degrees() - want) / scale).powi(2)
            })
            .sum();
        c += w.curvature * err / m.shape.curvature.len() as f64;
    }
    if w.rings > 0.0 && !m.turns.is_empty() {
        // Turns round within 12 % (the bowl asks 15 %), each narrower and
        // lower than the one before by at least 3 % of its radius.
        let mut r = 10.0
            * m.turns
                .iter()
                .map(|t| (t.spread - 0.12).max(0.0))
                .sum::<f64>();
        for p in m.turns.windows(2) {
            r += 10.0 * ((p[1].radius - p[0].radius) / p[0].radius + 0.03).max(0.0);
            r += 10.0 * ((p[1].height - p[0].height) / p[0].radius + 0.03).max(0.0);
        }
        // How far the interior vertices fall short of a clearly positive
        // defect (1.5 deg, three times the counting threshold): smooth,
        // where the positive share itself is a staircase.
        let want = 3.0 * crate::lattice::shape::CURVED_DEG;
        if !m.shape.curvature.is_empty() {
            r += 3.0
                * m.shape
                    .curvature
                    .iter()
                    .map(|v| (want - v.defect.to_degrees()).max(0.0) / want)
                    .sum::<f64>()
                / m.shape.curvature.len() as f64;
        }
        // A bowl is a cap of a sphere: the vertices' mean distance from
        // their best-fit sphere (20 x, relative to its radius), and a
        // sphere no flatter than 1.5 x the first turn's radius.
        let pts: Vec<DVec3> = lattice.vertices.iter().map(|v| v.pos).collect();
        r += match sphere_fit(&pts) {
            Some((centre, radius)) => {
                20.0 * pts
                    .iter()
                    .map(|p| (p.distance(centre) - radius).abs())
                    .sum::<f64>()
                    / pts.len() as f64
                    / radius
                    + (radius / m.turns[0].radius - 1.5).max(0.0)
            }
            None => 10.0,
        };
        c += w.rings * r;
    }
    if w.bending > 0.0 {
        c += w.bending * m.shape.front_gaps.map_or(0.0, |g| g.max_rel);
    }
    let checks = constraints(opt, m);
    c += c_over + PENALTY * checks.iter().map(|k| k.3).sum::<f64>();
    if refused(d, lattice, m).is_some() {
        c += PENALTY;
    }
    (c, checks)
}

/// Why `build` would refuse the grown design before its simulation, by
/// the functions `build` runs: the strips and eyelets (`parts::parts`: a
/// strip longer than the sheet, holes too close, legs too short) and the
/// clash rule (`Measures::clash_error`); None when it would not. A hard
/// constraint of every search, whatever `[optimise.require]` says.
pub(crate) fn refused(d: &Design, lattice: &Lattice, m: &Measures) -> Option<String> {
    let joints = crate::lattice::joints(lattice);
    if let Err(e) = crate::parts::parts(lattice, &joints, &d.fabrication) {
        return Some(e.message);
    }
    m.clash_error(lattice, d).map(|e| e.message)
}

/// The angle defects of the design's simulated deployed shape (its own
/// strips and `[simulation]` settings) and its largest strain, or None when
/// the simulation finds no equilibrium.
fn simulated_shape(
    d: &Design,
    lattice: &Lattice,
) -> Option<(Vec<crate::lattice::shape::VertexCurvature>, f64)> {
    let deployment = crate::lattice::deploy::deployment(lattice);
    let m = &d.fabrication.material;
    let run =
        crate::sim::simulate(lattice, &deployment, m.width, m.thickness, &d.simulation).ok()?;
    let curvature = crate::sim::placed_lattice(lattice, &run.lm).curvature();
    Some((curvature, run.equilibrium.strain.eps))
}

/// The least-squares sphere through `pts` (algebraic fit:
/// |p|^2 + d.p + e = 0), as centre and radius; None when degenerate.
pub(super) fn sphere_fit(pts: &[DVec3]) -> Option<(DVec3, f64)> {
    let (mut a, mut b) = (glam::DMat4::ZERO, glam::DVec4::ZERO);
    for p in pts {
        let row = p.extend(1.0);
        a += glam::DMat4::from_cols(row * row.x, row * row.y, row * row.z, row * row.w);
        b += row * -p.length_squared();
    }
    if a.determinant().abs() < 1e-12 {
        return None;
    }
    let x = a.inverse() * b;
    let centre = -0.5 * x.truncate();
    let r2 = centre.length_squared() - x.w;
    (r2 > 0.0 && r2.is_finite()).then(|| (centre, r2.sqrt()))
}

/// Each hard constraint: its name, the measured value, the bound and the
/// shortfall (0 when met), scaled so that a shortfall of 1 is large.
pub(super) fn constraints(opt: &Optimise, m: &Measures) -> Vec<(&'static str, f64, f64, f64)> {
    let k = m.curvature;
    opt.require
        .iter()
        .map(|r| {
            let (value, at_most) = match r.name {
                "max_distance" => (m.fit_distance.unwrap_or(0.0), true),
                "max_boundary_distance" => (m.boundary_distance.unwrap_or(0.0), true),
                "min_coverage" => (m.coverage.map_or(0.0, |c| c.share), false),
                "max_area_ratio" => (m.shape.area_ratio, true),
                "min_positive" => (k.map_or(0.0, |k| k.positive), false),
                "min_negative" => (k.map_or(0.0, |k| k.negative), false),
                "max_mean_defect" => (k.map_or(0.0, |k| k.mean_deg), true),
                "min_mean_defect" => (k.map_or(0.0, |k| k.mean_deg), false),
                "max_k_spread" => (k.map_or(f64::INFINITY, |k| k.k_std / k.k_mean.abs()), true),
                "max_front_gap" => (m.shape.front_gaps.map_or(0.0, |g| g.max_rel), true),
                "max_turn_spread" => (m.turns.iter().map(|t| t.spread).fold(0.0, f64::max), true),
                "max_clashes" => (m.clashes.len() as f64, true),
                "min_bumps" => (m.bumps, false),
                "min_leg" => (m.shape.min_leg, false),
                "min_dimples" => (m.dimples, false),
                other => unreachable!("unknown requirement {other}"),
            };
            let miss = if at_most {
                value - r.bound
            } else {
                r.bound - value
            };
            // Shares, counts, degrees and mm alike: a shortfall of 1 (or of
            // the bound, when larger) weighs 1.
            let scale = r.bound.abs().max(1.0);
            let short = if miss > 0.0 && value.is_finite() {
                miss / scale
            } else if value.is_finite() {
                0.0
            } else {
                1.0
            };
            (r.name, value, r.bound, short)
        })
        .collect()
}
