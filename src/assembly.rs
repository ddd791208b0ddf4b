//! Assembly steps in growth order (docs/math.md 10.3): one step a row (a cell for
//! helices). Each step
//! pairs the row's strips at their scissor pivots, then closes every vertex
//! joint whose last strip arrives in this row, stacked in layer order.
//!
//! The order is a fact of the lattice, not of the guide that prints it: the
//! pipeline computes it once (`Build::steps`) for the guide, the viewer, the
//! report and cutting by step, so this sits just above `lattice`.

use crate::lattice::{Joint, Kind, Lattice};

/// One assembly step: the strips of one growth row (one cell for a helix)
/// and the vertex joints it closes.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// 1-based.
    pub number: usize,
    /// The growth step: the row, or the helix cell.
    pub(crate) row: u32,
    /// Cells of this step, by index.
    pub cells: Vec<usize>,
    /// Strips of this step (strip index = rod id).
    pub strips: Vec<usize>,
    /// Vertex joints closed in this step (two or more rod ends), each with
    /// its ends sorted bottom to top.
    pub joints: Vec<Joint>,
    /// Eyelets set in this step: one per scissor pivot and per joint.
    pub eyelets: usize,
    /// Eyelets set up to and including this step.
    pub total: usize,
}

/// The steps of `lattice`, whose vertex joints are `joints`
/// (`lattice::joints`).
pub fn steps(lattice: &Lattice, joints: &[Joint]) -> Vec<Step> {
    // Cells by step in one pass (in index order within each step).
    let mut by_step: Vec<Vec<usize>> = vec![Vec::new(); lattice.steps()];
    for c in 0..lattice.cells.len() {
        by_step[lattice.step_of(c)].push(c);
    }
    let mut steps: Vec<Step> = by_step
        .into_iter()
        .enumerate()
        .map(|(i, cells)| Step {
            number: i + 1,
            row: i as u32,
            strips: cells.iter().flat_map(|&c| [2 * c, 2 * c + 1]).collect(),
            cells,
            joints: Vec::new(),
            eyelets: 0,
            total: 0,
        })
        .collect();
    for joint in joints.iter().filter(|j| j.needs_eyelet()) {
        let mut joint = joint.clone();
        // A joint can close once its last strip is in place.
        let row = joint
            .ends
            .iter()
            .map(|e| lattice.step_of(e.rod / 2))
            .max()
            .expect("a joint has ends");
        joint.ends.sort_by_key(|e| e.layer);
        steps[row].joints.push(joint);
    }
    let mut total = 0;
    for s in &mut steps {
        s.eyelets = s.cells.len() + s.joints.len();
        total += s.eyelets;
        s.total = total;
    }
    steps
}

/// Whether a lattice is built flat on the table: planar, or a 3-D sheet
/// whose relief is under a tenth of its size (it is assembled flat and takes
/// its relief as it opens). The guide and the viewer say "from the table
/// up" only for these; other 3-D pieces stack from the inside out.
pub(crate) fn built_flat(lattice: &Lattice) -> bool {
    if lattice.dim == 2 {
        return true;
    }
    if lattice.kind != Kind::Sheet {
        return false;
    }
    let (lo, hi) = lattice.extent();
    let size = hi - lo;
    let mut sorted = size.to_array();
    sorted.sort_by(f64::total_cmp);
    sorted[0] < 0.1 * sorted[2]
}
