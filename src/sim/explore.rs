//! Multistability (docs/physics.md, "Multistability"): solve from seeded perturbations of the
//! start and keep the distinct stable equilibria.

use super::model::{Frame, Model, Node};
use super::solver::{Options, System, solve};
use super::strips::LatticeModel;
use super::{Equilibrium, SimError, kabsch_distance};
use crate::budget::{Deadline, Stopped};
use crate::jobs::Jobs;
use std::sync::atomic::{AtomicUsize, Ordering};

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
        if let Frame::Ref { theta, .. } = m.edges[e].frame
            && !m.fixed[theta]
        {
            m.q[theta] += 0.02 * rng.normal();
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

/// The distinct equilibria found, and the seeds left out with why.
pub type Explored = (Vec<Found>, Vec<(u64, String)>);

/// What one start ended in: its equilibrium, or why it was left out
/// (None: not solved, the deadline had passed).
type Outcome = Option<Result<Equilibrium, String>>;

/// Solve from `n` seeds (0 = unperturbed) and group the stable results.
/// Returns the equilibria by increasing energy, and the seeds that failed
/// or ended unstable; adds one to `solved` as each start is solved (the
/// CLI's progress line reads it). The starts are solved `jobs` at a time,
/// each on its own copy of the model, and grouped in seed order
/// (`in_order`), so the result does not depend on `jobs` (the first start
/// to reach an equilibrium is the one reported for it).
pub fn explore(
    base: &LatticeModel,
    n: usize,
    seed: u64,
    jobs: usize,
    finish: &(dyn Fn(&LatticeModel, super::solver::Stats) -> Equilibrium + Sync),
    solved: &AtomicUsize,
) -> Explored {
    let none = Deadline::none();
    explore_until(base, (n, seed), jobs, finish, solved, &none).unwrap_or_default()
}

/// `explore`, stopped at `deadline`: each start checks it before it is
/// solved and its Newton solve once an iteration; an expired one ends the
/// exploration with how many starts were solved (docs/commands.md, "Time
/// limits"). Without a deadline the result is `explore`'s.
pub fn explore_until(
    base: &LatticeModel,
    (n, seed): (usize, u64),
    jobs: usize,
    finish: &(dyn Fn(&LatticeModel, super::solver::Stats) -> Equilibrium + Sync),
    solved: &AtomicUsize,
    deadline: &Deadline,
) -> Result<Explored, Stopped> {
    let sys = System::new(&base.model);
    let scale = base.model.e_scale;
    let mut found: Vec<Found> = Vec::new();
    let mut rejected = Vec::new();
    let mut unsolved = 0;
    let mut group = |k: u64, outcome: Outcome| match outcome {
        None => unsolved += 1,
        Some(Err(why)) => rejected.push((k, why)),
        Some(Ok(eq)) => {
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
    };
    Jobs::new(jobs).in_order(
        n,
        |k| {
            if deadline.expired() {
                return None;
            }
            let outcome = solve_start(base, &sys, k as u64, seed, finish, deadline)?;
            solved.fetch_add(1, Ordering::Relaxed);
            Some(outcome)
        },
        |k, outcome| group(k as u64, outcome),
    );
    if unsolved > 0 {
        return Err(deadline.stopped(n - unsolved, n, "starts"));
    }
    found.sort_by(|a, b| {
        a.equilibrium
            .energy
            .total()
            .total_cmp(&b.equilibrium.energy.total())
    });
    Ok((found, rejected))
}

/// Start `k`: the model perturbed with its seed (start 0 as it is),
/// solved, and kept if it ends at a stable equilibrium; None when the
/// deadline passed during its solve.
fn solve_start(
    base: &LatticeModel,
    sys: &System,
    k: u64,
    seed: u64,
    finish: &(dyn Fn(&LatticeModel, super::solver::Stats) -> Equilibrium + Sync),
    deadline: &Deadline,
) -> Option<Result<Equilibrium, String>> {
    let mut lm = base.clone();
    if k > 0 {
        perturb(
            &mut lm.model,
            seed.wrapping_add(k),
            AMPLITUDES[(k as usize - 1) % AMPLITUDES.len()],
        );
    }
    let opts = Options {
        deadline: deadline.at(),
        ..Options::default()
    };
    let stats = match solve(&mut lm.model, sys, &opts) {
        Ok(stats) => stats,
        Err(super::SolveError::TimeLimit { .. }) => return None,
        Err(e) => return Some(Err(SimError::Solve(e).to_string())),
    };
    if !stats.converged || !(stats.lambda_min > 0.0) {
        return Some(Err(format!(
            "ended unstable or unconverged (lambda_min {:.2e})",
            stats.lambda_min
        )));
    }
    Some(Ok(finish(&lm, stats)))
}
