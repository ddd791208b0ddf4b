//! Warm re-solves for design loops (docs/physics.md, "Sensitivities"): a
//! slightly changed design of the same topology starts from the last
//! equilibrium (its free variables and stored frames) instead of the
//! design placement, and needs a few Newton iterations instead of a
//! deployment.

use super::model::{Model, Stencil};
use super::{
    Derived, Options, SimError, Simulation, System, check_symmetry, equilibrium, prepare_meshed,
    solve_checked, within_memory,
};
use crate::lattice::Lattice;
use karigami_rods::adjoint::{Direction, Linearisation};
use std::time::Instant;

/// Whether two models have the same variables, nodes, edges and terms in
/// the same order (the same lattice topology and mesh), so that one's
/// state means the same in the other.
pub fn same_topology(a: &Model, b: &Model) -> bool {
    a.q.len() == b.q.len()
        && a.fixed == b.fixed
        && a.kinds == b.kinds
        && a.nodes.len() == b.nodes.len()
        && a.edges.len() == b.edges.len()
        && a.stencils.len() == b.stencils.len()
        && a.joints.len() == b.joints.len()
        && a.ties.len() == b.ties.len()
        && a.edges
            .iter()
            .zip(&b.edges)
            .all(|(x, y)| (x.a, x.b) == (y.a, y.b))
}

/// The parameters' change from `from` to `to`, two models of the same
/// topology: rest lengths, bends' lbar, fixed values and ties' offsets.
pub fn difference(from: &Model, to: &Model) -> Direction {
    let rest = (from.edges.iter().zip(&to.edges).enumerate())
        .map(|(e, (a, b))| (e, b.rest - a.rest))
        .filter(|d| d.1 != 0.0)
        .collect();
    let lbar = (from.stencils.iter().zip(&to.stencils).enumerate())
        .filter_map(|(s, pair)| match pair {
            (Stencil::Bend { lbar: a, .. }, Stencil::Bend { lbar: b, .. }) if a != b => {
                Some((s, b - a))
            }
            _ => None,
        })
        .collect();
    let offset = |m: &Model, v: usize| m.ties.iter().find(|t| t.var == v).map(|t| t.offset);
    let fixed = (0..to.q.len())
        .filter(|&v| to.fixed[v])
        .map(|v| match (offset(from, v), offset(to, v)) {
            (Some(a), Some(b)) => (v, b - a),
            _ => (v, to.q[v] - from.q[v]),
        })
        .filter(|d| d.1 != 0.0)
        .collect();
    Direction { rest, lbar, fixed }
}

/// Start `lm` from `previous`'s state (its free variables and frames)
/// moved by the first-order response to the design's change (`difference`,
/// the adjoint's tangent with `sys`, the system of either): Newton then
/// corrects a second-order error. Fixed variables, the anchor and the
/// held opening, stay `lm`'s own. False, and `lm` untouched, when their
/// topologies differ.
pub fn warm_start(
    lm: &mut super::LatticeModel,
    previous: &super::LatticeModel,
    sys: &System,
) -> bool {
    let p = &previous.model;
    if !same_topology(&lm.model, p) || lm.hold != previous.hold {
        return false;
    }
    let dir = difference(p, &lm.model);
    // An unstable last state (no tangent) is started from as it is.
    let dq = Linearisation::new(sys, p).ok().map(|lin| {
        let dq = lin.tangent(p, &dir);
        lin.release();
        dq
    });
    let m = &mut lm.model;
    for (i, q) in m.q.iter_mut().enumerate() {
        if !m.fixed[i] {
            *q = p.q[i] + dq.as_ref().map_or(0.0, |d| d[i]);
        }
    }
    m.set_frames(&p.frames());
    m.apply_ties();
    true
}

/// The equilibrium of `lattice` (a small change of the design whose
/// equilibrium `previous` is) at `settings.theta` or its design opening,
/// solved once from `previous`'s state. A design of another topology is
/// simulated from the start (`simulate`). Returns the run and whether it
/// started warm.
pub fn resolve(
    previous: &super::LatticeModel,
    lattice: &Lattice,
    deployment: &crate::lattice::deploy::Deployment,
    (width, thickness): (f64, f64),
    settings: &super::Settings,
) -> Result<(Simulation, bool), SimError> {
    let clock = Instant::now();
    let derived = Derived {
        placed: &lattice.placed(),
        joints: &crate::lattice::joints(lattice),
    };
    within_memory(lattice, settings)?;
    // The last model's mesh: a leg whose length crosses a multiple of
    // h_max would otherwise gain an edge and change the topology.
    let counts = Some(&previous.leg_counts[..]);
    let mut lm = prepare_meshed(lattice, &derived, (width, thickness), settings, counts);
    if let Some(t) = settings.theta {
        let max = deployment.config.theta_max;
        if !(t > 0.0 && t < max) {
            return Err(SimError::Theta { theta: t, max });
        }
        lm.set_held_opening(t);
    }
    let sys = previous.system.for_model(&lm.model);
    lm.system = super::strips::KeptSystem::new(sys.clone());
    if !warm_start(&mut lm, previous, &sys) {
        // A warm re-solve is one step of a caller's loop, which checks its
        // own deadline between steps (src/budget.rs).
        let none = crate::budget::Deadline::none();
        let run = super::simulate_with(
            lattice, deployment, &derived, width, thickness, settings, &none,
        )?;
        return Ok((run, false));
    }
    check_symmetry(lattice, &lm, settings.symmetry)?;
    let mut iterations = 0;
    let stats = solve_checked(&mut lm, &sys, &Options::default(), &mut iterations)?;
    let theta = lm.held_opening();
    let equilibrium = equilibrium(&lm, stats, &settings.material);
    let run = Simulation {
        lm,
        equilibrium,
        theta,
        iterations,
        steps: 1,
        seconds: clock.elapsed().as_secs_f64(),
    };
    Ok((run, true))
}
