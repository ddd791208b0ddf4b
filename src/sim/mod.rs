//! Deployed shape by simulation (docs/physics.md): every strip a discrete
//! elastic rod, every eyelet a joint, the deployed state the minimum of the
//! elastic energy with the opening of the reference cell prescribed.
//!
//! Layers: `dual` (derivatives), `frames`, `model` (variables, energy),
//! `strips` (a lattice's model; its openings read and set in `opening`),
//! `solver` (Newton), `explore` (multistability), `results` (strains,
//! reactions, distances), `path` (the deployment path and the state it
//! chooses), `states` (what tells one equilibrium from another).

mod cost;
pub mod explore;
mod opening;
pub mod path;
pub(crate) mod results;
pub mod sensitivity;
pub mod states;
pub(crate) mod strips;
pub mod supports;
pub mod warm;

pub use crate::design::settings::{Actuation, Material, Settings, VertexJoint};
pub(crate) use cost::Work;
pub use cost::{Cost, DEFAULT_MEMORY, estimate, seconds};
pub(crate) use cost::{edge_within, edge_within_time};
pub(crate) use karigami_rods::{model, solver};
pub(crate) use model::Energies;
pub use model::Section;
pub(crate) use results::StrainPeak;
pub use results::{ShapeDistance, kabsch_distance, shape_distance};
pub use solver::Stats;
pub(crate) use solver::{Options, SolveError, System};
pub use strips::{Hold, LatticeModel, Mesh};
pub use supports::Reaction;
pub use warm::resolve;

use crate::budget::{Deadline, Stopped, duration};
use crate::lattice::Lattice;
use crate::lattice::deploy::Deployment;
use glam::DVec3;
use std::time::Instant;

/// The stiffness of a `width` x `thickness` rectangular strip of `material`.
pub fn section(material: &Material, width: f64, thickness: f64) -> Section {
    let (e, w, t) = (material.youngs, width, thickness);
    let j = w * t.powi(3) / 3.0 * (1.0 - 0.63 * t / w);
    Section {
        b_flat: e * w * t.powi(3) / 12.0,
        b_edge: e * t * w.powi(3) / 12.0,
        ea: e * w * t,
        gj: material.shear() * j,
        width,
        thickness,
    }
}

/// Largest continuation step of the prescribed opening (docs/physics.md, "Deployment").
pub(crate) const STEP: f64 = 2.0 * std::f64::consts::PI / 180.0;

/// Why a simulation found no equilibrium.
#[derive(Clone, Debug, PartialEq)]
pub enum SimError {
    /// The Newton solver failed: a stalled line search or a non-finite value.
    Solve(SolveError),
    /// Newton ran out of iterations.
    NotConverged {
        /// Newton iterations of the step that failed.
        iterations: usize,
    },
    /// `symmetry` does not fit the lattice: a row's cells do not split
    /// into that many copies, or the copies' designed openings differ.
    Symmetry {
        /// The symmetry asked for.
        copies: u32,
        /// What does not fit.
        why: String,
    },
    /// The requested opening is outside C(theta)'s valid range.
    Theta {
        /// The requested opening (radians).
        theta: f64,
        /// The largest opening of the deployment range, `theta_max` (radians).
        max: f64,
    },
    /// The mesh would take more memory than allowed (`cost::estimate`):
    /// refused before any of it is made.
    TooLarge {
        /// Its estimated rod nodes and bytes.
        cost: Cost,
        /// The memory allowed (bytes).
        limit: u64,
    },
    /// The solve is reckoned to take longer than allowed (`cost::seconds`):
    /// refused before the model is made.
    TooLong {
        /// Its estimated rod nodes and bytes.
        cost: Cost,
        /// Its estimated seconds.
        seconds: f64,
        /// The seconds allowed (`Deadline::ceiling`).
        limit: f64,
    },
    /// The run's deadline passed: how far it got.
    TimeLimit(Stopped),
}

/// A memory size as `--memory` and the docs give it: MiB below a GiB.
fn bytes(b: f64) -> String {
    const MIB: f64 = (1u64 << 20) as f64;
    if b < 1024.0 * MIB {
        format!("{:.0} MiB", b / MIB)
    } else {
        format!("{:.1} GiB", b / (1024.0 * MIB))
    }
}

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SimError::Solve(e) => write!(f, "{e}"),
            SimError::NotConverged { iterations } => {
                write!(f, "Newton did not converge in {iterations} iterations")
            }
            SimError::Symmetry { copies, why } => write!(
                f,
                "[simulation] symmetry = {copies} does not fit the lattice: {why}"
            ),
            SimError::Theta { theta, max } => write!(
                f,
                "theta {} deg is outside the deployment range (0, {}) deg",
                crate::diagnostic::shown(theta.to_degrees()),
                crate::diagnostic::shown(max.to_degrees())
            ),
            SimError::TooLarge { cost, limit } => write!(
                f,
                "the simulation would take about {} of memory ({} rod nodes), more than the {} allowed",
                bytes(cost.bytes),
                crate::diagnostic::shown(cost.nodes.round()),
                bytes(*limit as f64)
            ),
            SimError::TooLong {
                cost,
                seconds,
                limit,
            } => write!(
                f,
                "the simulation would take about {} ({} rod nodes), longer than the {} allowed",
                duration(*seconds),
                crate::diagnostic::shown(cost.nodes.round()),
                duration(*limit)
            ),
            SimError::TimeLimit(stopped) => write!(f, "the simulation {stopped}"),
        }
    }
}

/// An equilibrium and what it says.
#[derive(Clone, Debug)]
pub struct Equilibrium {
    /// Elastic energy by term (N mm).
    pub energy: Energies,
    /// The largest strain of the strips and where it occurs.
    pub strain: StrainPeak,
    /// Largest joint reaction (N), the joint index and the rod.
    pub reaction: (f64, usize, String),
    /// Every vertex, then every pivot.
    pub points: Vec<DVec3>,
    /// Largest distance from the start placement after the best rigid fit (mm).
    pub distance: f64,
    /// The same fit's rms and largest distance, and where the largest is
    /// (an index of `points`).
    pub fit: ShapeDistance,
    /// Opening of every cell (radians).
    pub openings: Vec<f64>,
    /// Statistics of the last Newton solve.
    pub stats: Stats,
    /// The reaction at every support (`[simulation] supports`), in the
    /// recipe's order; empty for a lattice that stands free.
    pub supports: Vec<Reaction>,
}

/// A simulation run: the model at equilibrium and its report.
#[derive(Clone, Debug)]
pub struct Simulation {
    /// The lattice's rod model, at equilibrium.
    pub lm: LatticeModel,
    /// The equilibrium and what it says.
    pub equilibrium: Equilibrium,
    /// The reference cell's opening reached (radians).
    pub theta: f64,
    /// Newton iterations over all continuation steps.
    pub iterations: usize,
    /// Solves made: the start, then one per continuation step of the opening.
    pub steps: usize,
    /// Wall-clock time of the run (seconds).
    pub seconds: f64,
}

/// Evaluate an equilibrium of a lattice model.
pub fn equilibrium(lm: &LatticeModel, stats: Stats, material: &Material) -> Equilibrium {
    let m = &lm.model;
    let points = lm.points();
    let fit = shape_distance(&points, &lm.start);
    Equilibrium {
        fit,
        energy: m.energies(),
        strain: results::strain_peak(m, material.youngs, material.shear()),
        reaction: results::largest_reaction(m),
        distance: fit.max,
        openings: (0..lm.delta.len()).map(|c| lm.opening(c)).collect(),
        points,
        stats,
        supports: lm.reactions(),
    }
}

/// The lattice's model, anchored at cell 0's pivot (or held at its
/// supports, `Settings::supports`), with the held opening
/// (`Settings::actuation`) prescribed at the design value.
pub fn prepare(lattice: &Lattice, width: f64, thickness: f64, settings: &Settings) -> LatticeModel {
    let derived = Derived {
        placed: &lattice.placed(),
        joints: &crate::lattice::joints(lattice),
    };
    prepare_with(lattice, &derived, width, thickness, settings)
}

/// What `build` has computed already and the simulation reuses.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Derived<'a> {
    /// `lattice.placed()`: the rigid-fit placement of a bent-facet lattice.
    pub placed: &'a Lattice,
    /// `lattice::joints(lattice)`: the joint of every vertex.
    pub joints: &'a [crate::lattice::Joint],
}

/// `prepare` with the placement and the joints given.
pub(crate) fn prepare_with(
    lattice: &Lattice,
    derived: &Derived<'_>,
    width: f64,
    thickness: f64,
    settings: &Settings,
) -> LatticeModel {
    prepare_meshed(lattice, derived, (width, thickness), settings, None)
}

/// `prepare_with`, its legs cut into `counts` edges if given
/// (`LatticeModel::with_counts`).
pub(crate) fn prepare_meshed(
    lattice: &Lattice,
    derived: &Derived<'_>,
    (width, thickness): (f64, f64),
    settings: &Settings,
    counts: Option<&[Vec<usize>]>,
) -> LatticeModel {
    let section = section(&settings.material, width, thickness);
    let mesh = Mesh {
        h_max: settings.h_max,
        arm: width / 2.0,
        vertex_joint: settings.vertex_joint,
    };
    let mut lm = LatticeModel::with_counts(
        lattice,
        derived.placed,
        derived.joints,
        section,
        mesh,
        counts,
    );
    if let Ok(classes) = copies(lattice, settings.symmetry) {
        lm.share = classes;
    }
    if !lm.pivot.is_empty() {
        // Supports fix the rigid motion themselves (`supports.rs`).
        lm.pin_supports(lattice, &settings.supports);
        match settings.actuation {
            Actuation::Mean => {
                let phi = lm.mean_opening();
                lm.set_mean_opening(phi);
            }
            Actuation::FirstCell => {
                let phi = lm.opening(0);
                lm.set_opening(0, phi);
            }
        }
    }
    lm
}

/// Solve at the current prescribed opening, then step the held opening
/// (one cell's or the mean) to `theta` (at most `STEP` a step), solving
/// after each step.
pub fn deploy(
    lm: &mut LatticeModel,
    theta: Option<f64>,
    opts: &Options,
) -> Result<(Stats, usize, usize), SimError> {
    let sys = System::new(&lm.model);
    let mut total = 0;
    let mut stats = solve_checked(lm, &sys, opts, &mut total)?;
    let mut steps = 1;
    if let Some(target) = theta {
        let start = lm.held_opening();
        let n = ((target - start).abs() / STEP).ceil() as usize;
        walk(lm, &sys, target, n, opts, &mut total, &mut |_, s| {
            stats = s;
            steps += 1;
            true
        })?;
    }
    Ok((stats, total, steps))
}

/// Step the held opening from where it is to `target` in `n` equal steps,
/// solving after each (continuation: each solve starts from the last
/// equilibrium, from the second step on moved by the last step's change),
/// and hand each step's equilibrium to `visit`, which says whether to go
/// on. Newton iterations are added to `total`; the first step that finds
/// no equilibrium ends the walk with its error.
pub(crate) fn walk(
    lm: &mut LatticeModel,
    sys: &System,
    target: f64,
    n: usize,
    opts: &Options,
    total: &mut usize,
    visit: &mut dyn FnMut(&LatticeModel, Stats) -> bool,
) -> Result<(), SimError> {
    let start = lm.held_opening();
    // The equilibrium one step back, for the secant predictor.
    let mut before: Option<Vec<f64>> = None;
    for k in 1..=n {
        if opts.deadline.is_some_and(|d| Instant::now() >= d) {
            return Err(SimError::TimeLimit(Stopped {
                done: k - 1,
                of: n,
                what: "continuation steps".into(),
                seconds: 0.0,
                limit: 0.0,
            }));
        }
        let phi = start + (target - start) * k as f64 / n as f64;
        let here = lm.model.q.clone();
        let frames = lm.model.frames();
        if let Some(back) = &before {
            // The steps are equal: start the next solve where the last
            // step's change, continued, lands (positions and angles;
            // the frames follow), not at the last equilibrium. Newton
            // then corrects a small error instead of a whole step.
            predict(&mut lm.model, back, &here);
        }
        lm.set_held_opening(phi);
        let stats = match solve_checked(lm, sys, opts, total) {
            Ok(s) => s,
            // A prediction that overshoots (a fold of the path) is
            // dropped: the step is solved again from the last
            // equilibrium, as without a predictor.
            Err(_) if before.is_some() => {
                lm.model.q.clone_from(&here);
                lm.model.set_frames(&frames);
                lm.set_held_opening(phi);
                solve_checked(lm, sys, opts, total)?
            }
            Err(e) => return Err(e),
        };
        if !visit(lm, stats) {
            break;
        }
        before = Some(here);
    }
    Ok(())
}

/// Move the free variables of `m` from `here` by the change from `back`
/// to `here` (a secant step along the deployment path).
fn predict(m: &mut model::Model, back: &[f64], here: &[f64]) {
    for (i, q) in m.q.iter_mut().enumerate() {
        if !m.fixed[i] {
            *q = here[i] + (here[i] - back[i]);
        }
    }
    m.apply_ties();
    m.update_frames();
}

fn solve_checked(
    lm: &mut LatticeModel,
    sys: &System,
    opts: &Options,
    total: &mut usize,
) -> Result<Stats, SimError> {
    let s = solver::solve(&mut lm.model, sys, opts).map_err(|e| match e {
        SolveError::TimeLimit { iteration } => SimError::TimeLimit(Stopped {
            done: *total + iteration,
            of: 0,
            what: "Newton iterations".into(),
            seconds: 0.0,
            limit: 0.0,
        }),
        e => SimError::Solve(e),
    })?;
    *total += s.iterations;
    if !s.converged {
        return Err(SimError::NotConverged {
            iterations: s.iterations,
        });
    }
    Ok(s)
}

/// Simulate a lattice deployed to `settings.theta` (or its design angle).
pub fn simulate(
    lattice: &Lattice,
    deployment: &Deployment,
    width: f64,
    thickness: f64,
    settings: &Settings,
) -> Result<Simulation, SimError> {
    let derived = Derived {
        placed: &lattice.placed(),
        joints: &crate::lattice::joints(lattice),
    };
    let deadline = Deadline::none();
    simulate_with(
        lattice, deployment, &derived, width, thickness, settings, &deadline,
    )
}

/// `simulate`, refused up front when reckoned longer than `deadline`
/// allows (`within_time`) and stopped with `SimError::TimeLimit` when it
/// passes (docs/commands.md, "Time limits").
pub fn simulate_until(
    lattice: &Lattice,
    deployment: &Deployment,
    width: f64,
    thickness: f64,
    settings: &Settings,
    deadline: &Deadline,
) -> Result<Simulation, SimError> {
    let derived = Derived {
        placed: &lattice.placed(),
        joints: &crate::lattice::joints(lattice),
    };
    simulate_with(
        lattice, deployment, &derived, width, thickness, settings, deadline,
    )
}

/// The continuation steps a simulation to `settings.theta` is reckoned
/// at before its model tells the design's opening: a quarter turn.
pub(crate) fn steps_to(settings: &Settings) -> usize {
    settings
        .theta
        .map_or(0, |_| (std::f64::consts::FRAC_PI_2 / STEP).ceil() as usize)
}

/// The simulation's estimated size, work and seconds, its deployment path
/// included (`cost::estimate`, `cost::work`, `cost::seconds`).
pub(crate) fn reckoned(lattice: &Lattice, settings: &Settings) -> (Cost, Work, f64) {
    let cost = estimate(lattice, settings.h_max);
    let work = cost::work(lattice, settings);
    (
        cost,
        work,
        crate::budget::reckoned_low(seconds(&cost, work.iterations)),
    )
}

/// The simulation's estimated nodes and seconds (`cost::estimate`,
/// `cost::seconds`), refused when longer than `deadline` allows.
pub fn within_time(
    lattice: &Lattice,
    settings: &Settings,
    deadline: &Deadline,
) -> Result<(Cost, f64), SimError> {
    let (cost, _, seconds) = reckoned(lattice, settings);
    if !deadline.allows(seconds) {
        return Err(SimError::TooLong {
            cost,
            seconds,
            limit: deadline.ceiling(),
        });
    }
    Ok((cost, seconds))
}

/// Refuse a simulation whose mesh would take more memory than the settings
/// allow (`cost::estimate`), before any of it is made.
pub fn within_memory(lattice: &Lattice, settings: &Settings) -> Result<(), SimError> {
    let cost = estimate(lattice, settings.h_max);
    if cost.bytes > settings.memory as f64 || !cost.bytes.is_finite() {
        return Err(SimError::TooLarge {
            cost,
            limit: settings.memory,
        });
    }
    Ok(())
}

/// `simulate` with the placement and the joints the build has already.
pub(crate) fn simulate_with(
    lattice: &Lattice,
    deployment: &Deployment,
    derived: &Derived<'_>,
    width: f64,
    thickness: f64,
    settings: &Settings,
    deadline: &Deadline,
) -> Result<Simulation, SimError> {
    let clock = Instant::now();
    if let Some(t) = settings.theta {
        let max = deployment.config.theta_max;
        if !(t > 0.0 && t < max) {
            return Err(SimError::Theta { theta: t, max });
        }
    }
    within_memory(lattice, settings)?;
    within_time(lattice, settings, deadline)?;
    let mut lm = prepare_with(lattice, derived, width, thickness, settings);
    check_symmetry(lattice, &lm, settings.symmetry)?;
    let opts = Options {
        deadline: deadline.at(),
        ..Options::default()
    };
    let (stats, iterations, steps) =
        deploy(&mut lm, settings.theta, &opts).map_err(|e| match e {
            SimError::TimeLimit(s) => SimError::TimeLimit(Stopped {
                seconds: deadline.elapsed(),
                limit: deadline.limit().unwrap_or(0.0),
                ..s
            }),
            e => e,
        })?;
    let theta = lm.held_opening();
    let equilibrium = equilibrium(&lm, stats, &settings.material);
    Ok(Simulation {
        lm,
        equilibrium,
        theta,
        iterations,
        steps,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

/// The lattice with every vertex and pivot where the simulation put them
/// (rows of a bent-facet lattice all share the simulated vertices): for
/// pictures of the deployed shape, e.g. the preview and the guide's cover.
pub fn placed_lattice(lattice: &Lattice, lm: &LatticeModel) -> Lattice {
    placed_at(lattice, lm, &lm.points())
}

/// `placed_lattice` at `points`, every vertex then every pivot as in
/// `Equilibrium::points` (e.g. another equilibrium of the same model).
pub fn placed_at(lattice: &Lattice, lm: &LatticeModel, points: &[DVec3]) -> Lattice {
    let nv = lattice.vertices.len();
    let mut out = lattice.clone();
    for (v, vertex) in out.vertices.iter_mut().enumerate() {
        if lm.vertex[v] != strips::VertexPlace::None {
            vertex.pos = points[v];
        }
    }
    for (c, cell) in out.cells.iter_mut().enumerate() {
        cell.pivot = points[nv + c];
    }
    let by_key: std::collections::HashMap<(u32, u32), usize> = lattice
        .vertices
        .iter()
        .enumerate()
        .map(|(i, v)| ((v.key.row, v.key.col), i))
        .collect();
    for (row, front) in out.fronts.iter_mut().enumerate() {
        for (col, p) in front.iter_mut().enumerate() {
            if let Some(&v) = by_key.get(&(row as u32, col as u32)) {
                *p = points[v];
            }
        }
    }
    out
}

/// The class of every cell under an n-fold symmetry of a loop lattice:
/// cells at the same row and the same column modulo (cells in the row / n)
/// are copies of one another.
fn copies(lattice: &Lattice, n: u32) -> Result<Vec<usize>, String> {
    let n = n.max(1) as usize;
    let rows = lattice
        .cells
        .iter()
        .map(|c| c.row as usize + 1)
        .max()
        .unwrap_or(0);
    let mut count = vec![0usize; rows];
    for c in &lattice.cells {
        count[c.row as usize] += 1;
    }
    let mut first = vec![0usize; rows];
    let mut acc = 0;
    for r in 0..rows {
        if count[r] % n != 0 {
            return Err(format!(
                "row {r} has {} cells, not a multiple of {n}",
                count[r]
            ));
        }
        first[r] = acc;
        acc += count[r] / n;
    }
    Ok(lattice
        .cells
        .iter()
        .map(|c| {
            let period = count[c.row as usize] / n;
            first[c.row as usize] + c.col as usize % period
        })
        .collect())
}

/// Refuse a symmetry the lattice does not have: copies whose openings in
/// the start placement differ by more than 0.01 degree.
fn check_symmetry(lattice: &Lattice, lm: &LatticeModel, n: u32) -> Result<(), SimError> {
    if n <= 1 {
        return Ok(());
    }
    let err = |why: String| SimError::Symmetry { copies: n, why };
    let classes = copies(lattice, n).map_err(err)?;
    let start = &lm.start_openings;
    let mut seen: Vec<Option<usize>> = vec![None; lattice.cells.len()];
    for (c, &k) in classes.iter().enumerate() {
        match seen[k] {
            None => seen[k] = Some(c),
            Some(first) if (start[c] - start[first]).abs() > 0.01f64.to_radians() => {
                return Err(err(format!(
                    "{} opens {:.3} deg in the design but its copy {} opens {:.3} deg",
                    lattice.cell_name(&lattice.cells[c]),
                    start[c].to_degrees(),
                    lattice.cell_name(&lattice.cells[first]),
                    start[first].to_degrees()
                )));
            }
            Some(_) => {}
        }
    }
    Ok(())
}

/// Lattices above this many cells are not simulated by `build`.
pub(crate) const MAX_SIMULATED_CELLS: usize = 2_000;

/// Whether a lattice's deployed shape needs the simulation: unless it is
/// a planar true mechanism (its design is its deployed shape, strips
/// straight). Eyelets make 3-D designs twist where cells in different
/// planes meet, so those need it too.
pub(crate) fn needed(lattice: &Lattice, deployment: &Deployment) -> bool {
    let planar_mechanism = lattice.dim == 2 && lattice.extrinsic() && deployment.is_mechanism();
    !planar_mechanism && !lattice.cells.is_empty()
}

/// Whether `build` simulates a lattice: when it is `needed` and not too
/// large.
pub(crate) fn wanted(lattice: &Lattice, deployment: &Deployment) -> bool {
    needed(lattice, deployment) && lattice.cells.len() <= MAX_SIMULATED_CELLS
}
