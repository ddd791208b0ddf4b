//! What a simulation will cost, read off the lattice before its model is
//! built (docs/physics.md, "Limits"): the rod nodes its mesh makes and the
//! memory they take. A simulation estimated above the memory ceiling is
//! refused before any of it is allocated, so a recipe can never make the
//! solver run out of memory.

use crate::lattice::Lattice;

/// Memory a simulation takes for each rod node, measured on the saddle ring
/// meshed at 10, 5 and 2.5 mm (4,944, 8,976 and 16,896 nodes as `estimate`
/// counts them: 38, 62 and 109 MB of peak memory, 5.9 KB a node beyond a
/// 10 MB base), and on a 24-cell sheet of metre-long legs at 0.5 mm
/// (220,881 nodes: 1.57 GB, 7.1 KB a node): 8 KiB leaves room for the
/// factor's fill growing faster than the nodes.
pub(crate) const BYTES_PER_NODE: f64 = 8192.0;

pub use crate::design::settings::DEFAULT_MEMORY;

/// Seconds a Newton iteration takes per `nodes^1.5` (the sparse factor's
/// fill grows so on sheets and rings), release build on the 2-core
/// machine of BENCHMARKS.md: the saddle ring (4,944 nodes) 40 iterations
/// in 4.26 s, 3.0e-7; a 1,980-cell sheet (35,640 nodes) one iteration and
/// the stability check in 3.67 s, 2.7e-7; a 20,000-cell sheet (360,000
/// nodes) one in 67.6 to 84.5 s, 1.6e-7 to 2.0e-7 (docs/physics.md,
/// "Limits").
pub(crate) const SECONDS_PER_ITERATION: f64 = 3.1e-7;

/// Newton iterations a solve is reckoned at before it runs: the examples
/// take 1 (planar sheets, at rest as designed) to 69 (the bowl); the
/// stability check at the end costs about one more. Reckoned low, so that
/// an estimate refuses only what is surely too long; the deadline stops
/// the rest.
pub(crate) const ITERATIONS_PER_SOLVE: f64 = 10.0;

/// Newton iterations a continuation step of the opening is reckoned at.
pub(crate) const ITERATIONS_PER_STEP: f64 = 5.0;

/// Seconds one Newton iteration of a mesh of `nodes` is reckoned at.
pub(crate) fn iteration_seconds(nodes: f64) -> f64 {
    SECONDS_PER_ITERATION * nodes.max(1.0).powf(1.5)
}

/// Newton iterations a simulation of `lattice` is reckoned at: one for a
/// planar lattice at its design opening (at rest as designed: the 1,980-
/// and 20,000-cell sheets take one), `ITERATIONS_PER_SOLVE` else, and
/// `ITERATIONS_PER_STEP` a continuation step.
pub(crate) fn iterations(lattice: &Lattice, steps: usize) -> f64 {
    let solve = if lattice.dim == 2 && steps == 0 {
        1.0
    } else {
        ITERATIONS_PER_SOLVE
    };
    solve + ITERATIONS_PER_STEP * steps as f64
}

/// Seconds a simulation of `cost` is reckoned at when its Newton solves
/// take `iterations` (`estimate` counts the nodes; the stability check is
/// one more).
pub fn seconds(cost: &Cost, iterations: f64) -> f64 {
    iteration_seconds(cost.nodes) * (iterations + 1.0)
}

/// A simulation's estimated size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cost {
    /// Rod nodes of its mesh (a real number: a lattice a million metres
    /// long does not overflow the count).
    pub nodes: f64,
    /// Memory it takes (bytes).
    pub bytes: f64,
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
    Cost {
        nodes,
        bytes: nodes * BYTES_PER_NODE,
    }
}

/// The coarsest rod edge (mm) that brings `lattice`'s simulation under
/// `memory` bytes, for the message that refuses a finer one; None when even
/// one edge a leg is too much.
pub(crate) fn edge_within(lattice: &Lattice, memory: u64) -> Option<f64> {
    edge_for(lattice, memory as f64 / BYTES_PER_NODE)
}

/// The coarsest rod edge (mm) whose simulation with `steps` continuation
/// steps is reckoned within `limit` seconds (`seconds`).
pub(crate) fn edge_within_time(lattice: &Lattice, limit: f64, steps: usize) -> Option<f64> {
    let one = Cost {
        nodes: 1.0,
        bytes: 0.0,
    };
    let per_node = seconds(&one, iterations(lattice, steps));
    edge_for(lattice, (limit / per_node).powf(2.0 / 3.0))
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
