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
    let legs: f64 = lattice
        .cells
        .iter()
        .map(|cell| lattice.legs(cell).iter().sum::<f64>())
        .sum();
    let fixed = 10.0 * lattice.cells.len() as f64;
    let room = memory as f64 / BYTES_PER_NODE - fixed;
    (room > 0.0 && legs.is_finite()).then(|| legs / room)
}
