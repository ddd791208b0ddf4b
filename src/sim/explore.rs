//! Multistability (docs/physics.md, "Multistability"): solve from seeded perturbations of the
//! start and keep the distinct stable equilibria.

use super::model::{Frame, Model, Node};
use super::solver::{Options, System, solve};
use super::strips::LatticeModel;
use super::{Equilibrium, SimError, kabsch_distance};

pub use karigami_rods::rng::Rng;

/// Seed amplitudes (mm), cycled: seed 0 is the unperturbed start.
pub(crate) const AMPLITUDES: [f64; 3] = [1.0, 3.0, 10.0];

/// Perturb every free node along its rod's face normal by `amplitude` xi
/// and every material angle by 0.02 xi rad.
pub fn perturb(m: &mut Model, seed: u64, amplitude: f64) {
    let mut rng = Rng::new(seed);
    for r in 0..m.rods.len() {
        for k in 0..m.rods[r].nodes.len() {
            let node = m.rods[r].nodes[k];
            if let Node::Free(v) = m.nodes[node] {
                if m.fixed[v] {
                    continue;
                }
                let e = m.rods[r].edges[k.min(m.rods[r].edges.len() - 1)];
                let (_, _, d2) = m.edge_frame(e);
                let xi = rng.normal();
                for a in 0..3 {
                    m.q[v + a] += amplitude * xi * d2[a];
                }
            }
        }
    }
    for e in 0..m.edges.len() {
        if let Frame::Ref { theta, .. } = m.edges[e].frame {
            if !m.fixed[theta] {
                m.q[theta] += 0.02 * rng.normal();
            }
        }
    }
}

/// One distinct equilibrium found by exploration.
#[derive(Clone, Debug)]
pub struct Found {
    /// The equilibrium as first reached.
    pub equilibrium: Equilibrium,
    /// Seeds that reached it.
    pub hits: Vec<u64>,
}

/// Solve from `n` seeds (0 = unperturbed) and group the stable results.
/// Returns the equilibria by increasing energy, and the seeds that failed
/// or ended unstable.
pub fn explore(
    base: &LatticeModel,
    n: usize,
    seed: u64,
    finish: &dyn Fn(&LatticeModel, super::solver::Stats) -> Equilibrium,
) -> (Vec<Found>, Vec<(u64, String)>) {
    let sys = System::new(&base.model);
    let mut found: Vec<Found> = Vec::new();
    let mut rejected = Vec::new();
    for k in 0..n as u64 {
        let mut lm = base.clone();
        if k > 0 {
            perturb(
                &mut lm.model,
                seed.wrapping_add(k),
                AMPLITUDES[(k as usize - 1) % AMPLITUDES.len()],
            );
        }
        let stats = match solve(&mut lm.model, &sys, &Options::default()) {
            Ok(s) => s,
            Err(e) => {
                rejected.push((k, SimError::Solve(e).to_string()));
                continue;
            }
        };
        if !stats.converged || !(stats.lambda_min > 0.0) {
            rejected.push((
                k,
                format!(
                    "ended unstable or unconverged (lambda_min {:.2e})",
                    stats.lambda_min
                ),
            ));
            continue;
        }
        let eq = finish(&lm, stats);
        let scale = lm.model.e_scale;
        let same = found.iter_mut().find(|f| {
            let (e1, e2) = (f.equilibrium.energy.total(), eq.energy.total());
            (e1 - e2).abs() <= 1e-6 * scale.max(e1.abs())
                && kabsch_distance(&f.equilibrium.points, &eq.points) <= 1e-3
        });
        match same {
            Some(f) => f.hits.push(k),
            None => found.push(Found {
                equilibrium: eq,
                hits: vec![k],
            }),
        }
    }
    found.sort_by(|a, b| {
        a.equilibrium
            .energy
            .total()
            .total_cmp(&b.equilibrium.energy.total())
    });
    (found, rejected)
}
