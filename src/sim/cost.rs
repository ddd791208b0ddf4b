//! What a simulation will cost, read off the lattice before its model is
//! built (docs/physics.md, "Limits"): the rod nodes its mesh makes, the
//! memory they take, and the Newton iterations of its solve and of the
//! deployment path `build`, `check` and `simulate` follow after it. A
//! simulation estimated above the memory ceiling is refused before any of
//! it is allocated, so a recipe can never make the solver run out of
//! memory.

use super::path::{COLLAPSED, PATH_STEP, Path};
use crate::design::settings::{Actuation, Settings};
use crate::lattice::Lattice;

/// Memory a simulation takes for each rod node, measured on the saddle ring
/// meshed at 10, 5 and 2.5 mm (4,944, 8,976 and 16,896 nodes as `estimate`
/// counts them: 38, 62 and 109 MB of peak memory, 5.9 KB a node beyond a
/// 10 MB base), and on a 24-cell sheet of metre-long legs at 0.5 mm
/// (220,881 nodes: 1.57 GB, 7.1 KB a node): 8 KiB leaves room for the
/// factor's fill growing faster than the nodes.
pub(crate) const BYTES_PER_NODE: f64 = 8192.0;

pub use crate::design::settings::DEFAULT_MEMORY;

/// Seconds a Newton iteration takes for each rod node: the assembly and
/// the rods' chains of nodes, linear in the mesh. Fitted with
/// `SECONDS_PER_FILL` to the CPU time an iteration takes (a simulation's
/// whole time over its iterations, each solve's stability check one
/// more), release build of e65e310's solver on the 2-core machine of
/// BENCHMARKS.md ("Bounded work"): 3.9e-6 s a node on the sheet one cell
/// wide (54,002 nodes, band 4.2), 4.6e-6 to 7.6e-6 on the examples (480
/// to 5,664 nodes, band 20 to 60), 5.4e-6 on a 400-cell sheet (7,200,
/// band 85), 1.1e-5 on a 1,980-cell sheet (35,640, band 187).
pub(crate) const SECONDS_PER_NODE: f64 = 3.7e-6;

/// Seconds a Newton iteration takes for each unit of the sparse factor's
/// work, `nodes x band` (`Cost::band`): `nodes^1.5` on a square sheet,
/// little more than the nodes on a lattice one cell wide, whose factor
/// is banded. Fitted with `SECONDS_PER_NODE` (the tall and the 1,980-cell
/// sheets set the two; the examples lie within 0.8 to 1.6 times the fit).
pub(crate) const SECONDS_PER_FILL: f64 = 4.0e-8;

/// Newton iterations a solve from the design is reckoned at before it
/// runs: the examples take 1 (planar sheets, at rest as designed) to 69
/// (the helix bowl); most take 11 to 40. Reckoned low, so that an
/// estimate refuses only what is surely too long; the deadline stops the
/// rest.
pub(crate) const ITERATIONS_PER_SOLVE: f64 = 10.0;

/// Newton iterations a continuation step to `--theta` is reckoned at.
pub(crate) const ITERATIONS_PER_STEP: f64 = 5.0;

/// Newton iterations a step of the deployment path is reckoned at, its
/// splits included, when it covers at most `PATH_STEP`: measured 5.2
/// (curved-sheet) to 20.6 (the helix bowl), 12 to 14.6 on most examples,
/// planar sheets as bent ones, 10.3 to 13 on sheets of 400 to 3,000
/// cells (BENCHMARKS.md, "Bounded work"); reckoned low. Each solve's
/// stability check costs about one more.
pub(crate) const ITERATIONS_PER_PATH_STEP: f64 = 10.0;

/// Newton iterations a path step is reckoned at when `MAX_STEPS` makes it
/// longer than `PATH_STEP`: `ITERATIONS_PER_PATH_STEP` times the square
/// of its length over `PATH_STEP` (the secant predictor's error grows so).
/// Measured: the eggbox's 5.2 deg steps 15.9 iterations (reckoned 16.8),
/// the torus's 5.6 deg steps 39.8 (reckoned 19.3; its path folds, and
/// the steps that find no equilibrium are halved four times).
fn path_step_iterations(opening: f64, steps: usize) -> f64 {
    let step = opening * (1.0 - COLLAPSED) / steps.max(1) as f64;
    ITERATIONS_PER_PATH_STEP * (step / PATH_STEP).powi(2).max(1.0)
}

/// Seconds one Newton iteration of a mesh of `cost` is reckoned at.
pub(crate) fn iteration_seconds(cost: &Cost) -> f64 {
    let nodes = cost.nodes.max(1.0);
    SECONDS_PER_NODE * nodes + SECONDS_PER_FILL * nodes * cost.band.max(1.0)
}

/// A simulation's work reckoned before it runs: its Newton iterations
/// and the deployment path's steps each way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Work {
    /// Newton iterations, each solve's stability check one more.
    pub(crate) iterations: f64,
    /// Steps each way of the deployment path (`Path::step_count`).
    pub(crate) path_steps: usize,
}

/// The work of simulating `lattice` under `settings` and following its
/// deployment path (docs/physics.md, "The deployment path"), as `build`,
/// `check` and `simulate` do: the solve from the design (one iteration
/// for a planar lattice at rest as designed, `ITERATIONS_PER_SOLVE`
/// else), `ITERATIONS_PER_STEP` a step to `settings.theta`, and the path
/// from there, `Path::step_count` steps each way (the count the path
/// takes, from the opening the model will hold) at
/// `path_step_iterations` each; every solve's stability check one
/// iteration more.
pub(crate) fn work(lattice: &Lattice, settings: &Settings) -> Work {
    let walk = super::steps_to(settings);
    let solve = if lattice.dim == 2 && walk == 0 {
        1.0
    } else {
        ITERATIONS_PER_SOLVE
    };
    let opening = settings
        .theta
        .unwrap_or_else(|| held_opening(lattice, settings.actuation));
    let path_steps = Path::step_count(0, opening);
    let iterations = solve
        + 1.0
        + walk as f64 * (ITERATIONS_PER_STEP + 1.0)
        + 2.0 * path_steps as f64 * (path_step_iterations(opening, path_steps) + 1.0);
    Work {
        iterations,
        path_steps,
    }
}

/// The opening the model holds at the design (radians), read off the
/// lattice as the model reads it: each cell's the angle between its rods
/// at the pivot (rod A from UL, rod B from UR); the mean of all cells',
/// or the first cell's (`Actuation`).
fn held_opening(lattice: &Lattice, actuation: Actuation) -> f64 {
    let opening = |cell: &crate::lattice::Cell| {
        let [ul, ur, _, _] = lattice.corners(cell);
        (ul - cell.pivot)
            .normalize_or_zero()
            .dot((ur - cell.pivot).normalize_or_zero())
            .clamp(-1.0, 1.0)
            .acos()
    };
    match actuation {
        Actuation::FirstCell => lattice.cells.first().map_or(0.0, opening),
        Actuation::Mean => {
            let n = lattice.cells.len().max(1) as f64;
            lattice.cells.iter().map(opening).sum::<f64>() / n
        }
    }
}

/// Seconds a simulation of `cost` is reckoned at when it takes
/// `iterations` Newton iterations (`work`).
pub fn seconds(cost: &Cost, iterations: f64) -> f64 {
    iteration_seconds(cost) * iterations
}

/// A simulation's estimated size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cost {
    /// Rod nodes of its mesh (a real number: a lattice a million metres
    /// long does not overflow the count).
    pub nodes: f64,
    /// Memory it takes (bytes).
    pub bytes: f64,
    /// The sparse factor's band: the lattice's width in cells (its rows or
    /// the most cells a row has, the fewer) times the square root of the
    /// nodes a cell has; `nodes^0.5` on a square sheet.
    pub band: f64,
}

/// The cost of simulating `lattice` with rod edges of at most `h_max` mm:
/// each leg meshed into `ceil(leg / h_max)` edges, and each rod's two ends
/// and pivot a node more, as `strips::with_derived` meshes them (within a
/// few nodes a rod; the test below holds it to the model's own count).
pub fn estimate(lattice: &Lattice, h_max: f64) -> Cost {
    let per_leg = |leg: f64| (leg / h_max).ceil().max(1.0);
    let nodes: f64 = lattice
        .cells
        .iter()
        .map(|cell| lattice.legs(cell).iter().map(|&l| per_leg(l)).sum::<f64>() + 6.0)
        .sum();
    let cells = lattice.cells.len().max(1) as f64;
    Cost {
        nodes,
        bytes: nodes * BYTES_PER_NODE,
        band: width(lattice) * (nodes / cells).sqrt(),
    }
}

/// The lattice's width in cells: its rows or the most cells a row has,
/// the fewer (at least one).
fn width(lattice: &Lattice) -> f64 {
    let mut rows = std::collections::BTreeMap::<u32, usize>::new();
    for cell in &lattice.cells {
        *rows.entry(cell.row).or_default() += 1;
    }
    let widest = rows.values().copied().max().unwrap_or(1);
    rows.len().min(widest).max(1) as f64
}

/// The coarsest rod edge (mm) that brings `lattice`'s simulation under
/// `memory` bytes, for the message that refuses a finer one; None when even
/// one edge a leg is too much.
pub(crate) fn edge_within(lattice: &Lattice, memory: u64) -> Option<f64> {
    edge_for(lattice, memory as f64 / BYTES_PER_NODE)
}

/// The coarsest rod edge (mm) whose simulation under `settings` is
/// reckoned within `limit` seconds (`work`, `seconds`): the most nodes
/// whose iterations fit, found by bisection (the seconds grow with the
/// nodes), and the edge that meshes the lattice in them.
pub(crate) fn edge_within_time(lattice: &Lattice, limit: f64, settings: &Settings) -> Option<f64> {
    let iterations = work(lattice, settings).iterations;
    let width = width(lattice);
    let cells = lattice.cells.len().max(1) as f64;
    let fits = |nodes: f64| {
        let cost = Cost {
            nodes,
            bytes: 0.0,
            band: width * (nodes / cells).sqrt(),
        };
        seconds(&cost, iterations) <= limit
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    while fits(hi) && hi < 1e15 {
        (lo, hi) = (hi, 2.0 * hi);
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if fits(mid) { lo = mid } else { hi = mid }
    }
    edge_for(lattice, lo)
}

/// The coarsest rod edge (mm) that meshes `lattice` in at most `nodes`.
fn edge_for(lattice: &Lattice, nodes: f64) -> Option<f64> {
    let legs: f64 = lattice
        .cells
        .iter()
        .map(|cell| lattice.legs(cell).iter().sum::<f64>())
        .sum();
    let fixed = 10.0 * lattice.cells.len() as f64;
    let room = nodes - fixed;
    (room > 0.0 && legs.is_finite()).then(|| legs / room)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chain template (a plain sheet, grown without a search), its
    /// lattice and deployment: built here from the layers below `sim`.
    struct Chain {
        design: crate::design::Design,
        lattice: Lattice,
        deployment: crate::lattice::deploy::Deployment,
    }

    fn chain() -> Chain {
        let text = include_str!("../../templates/chain.toml");
        let design = crate::design::parse(text, "chain").expect("parses");
        let d = &design;
        let mut lattice =
            crate::lattice::grow(d.kind, d.dim, &d.points, &d.kappa, &d.rows).expect("grows");
        lattice.stacking = d.clash.stacking;
        let deployment = crate::lattice::deploy::deployment(&lattice);
        Chain {
            design,
            lattice,
            deployment,
        }
    }

    /// The estimate counts the deployment path as the simulation follows
    /// it: the same steps each way, and iterations within a factor of 3 of
    /// those the solve and the path take (each solve's stability check one
    /// more); the path alone is most of them.
    #[test]
    fn the_estimate_counts_the_deployment_path_the_simulation_follows() {
        let c = chain();
        let (d, lattice) = (&c.design, &c.lattice);
        let m = &d.fabrication.material;
        let settings = &d.simulation;
        let run = crate::sim::simulate(lattice, &c.deployment, m.width, m.thickness, settings)
            .expect("simulates");
        let solve = run.iterations + 1;
        let (_, path) = crate::sim::path::chosen(run, &settings.material);
        let path = path.expect("a path");
        let reckoned = work(lattice, settings);
        assert_eq!(reckoned.path_steps, path.steps);
        let taken = (solve + path.iterations + 2 * path.steps) as f64;
        assert!(
            reckoned.iterations > taken / 3.0 && reckoned.iterations < 3.0 * taken,
            "reckoned {} iterations, taken {taken}",
            reckoned.iterations
        );
        assert!(path.iterations as f64 > 0.5 * taken, "{path:?}");
        // `--theta`: the path from the opening asked, after the steps there.
        let mut wider = settings.clone();
        wider.theta = Some(100f64.to_radians());
        let there = work(lattice, &wider);
        assert_eq!(there.path_steps, Path::step_count(0, 100f64.to_radians()));
        assert!(there.iterations > reckoned.iterations);
    }

    /// A lattice one cell wide has a banded factor: its iterations are
    /// reckoned nearly linear in the nodes, a square sheet's as
    /// `nodes^1.5`, and the coarsest edge that fits a limit is found for
    /// both.
    #[test]
    fn a_narrow_lattice_is_reckoned_by_its_band() {
        let c = chain();
        let lattice = &c.lattice;
        let cost = estimate(lattice, c.design.simulation.h_max);
        let cells = lattice.cells.len() as f64;
        assert!(width(lattice) < cells.sqrt(), "{}", width(lattice));
        let square = Cost {
            band: cost.nodes.sqrt(),
            ..cost
        };
        assert!(iteration_seconds(&cost) < iteration_seconds(&square));
        let settings = &c.design.simulation;
        let limit = seconds(&cost, work(lattice, settings).iterations);
        let h = edge_within_time(lattice, 0.5 * limit, settings).expect("an edge");
        assert!(h > settings.h_max, "{h} mm");
        let coarser = estimate(lattice, h);
        let fits = seconds(&coarser, work(lattice, settings).iterations);
        assert!(fits <= 0.5 * limit * 1.01, "{fits} s against {limit} s");
    }
}
