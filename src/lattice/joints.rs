//! Joints at the vertex pivots: which rod ends meet there and in what
//! stacking order (docs/math.md 10.2).

use super::{Lattice, RodType};

/// Which end of a rod meets a vertex joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RodEnd {
    /// The rod's start vertex: UL for rod A, UR for rod B.
    Start,
    /// The rod's end vertex: LR for rod A, LL for rod B.
    End,
}

/// One rod end at a joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct JointEnd {
    /// The rod's id: `2 * cell index`, plus 1 for rod B (lattice.json order).
    pub rod: usize,
    pub(crate) kind: RodType,
    pub(crate) end: RodEnd,
    /// Stacking index: strips go on in increasing layer order.
    pub layer: u32,
}

/// A vertex pivot and the rod ends it joins.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Joint {
    /// The vertex pivot, an index into `Lattice::vertices`.
    pub vertex: u32,
    /// In the order of docs/math.md 10.2: A(i,j) start, B(i,j-1) start,
    /// B(i-1,j) end, A(i-1,j-1) end.
    pub ends: Vec<JointEnd>,
}

impl Joint {
    /// Corners (a single rod end) need no eyelet.
    pub fn needs_eyelet(&self) -> bool {
        self.ends.len() >= 2
    }
}

/// How many vertex pivots take an eyelet (the joints that are not corners).
pub(crate) fn vertex_eyelets(joints: &[Joint]) -> usize {
    joints.iter().filter(|j| j.needs_eyelet()).count()
}

/// `vertex_eyelets(&joints(lattice))` without building the joints (a heap
/// list a vertex: half a gigabyte at 4 M cells): a vertex's filled slots
/// as bits of one byte.
pub(crate) fn vertex_eyelet_count(lattice: &Lattice) -> usize {
    let mut slots = vec![0u8; lattice.vertices.len()];
    for cell in &lattice.cells {
        slots[cell.ul as usize] |= 1;
        slots[cell.ur as usize] |= 2;
        slots[cell.ll as usize] |= 4;
        slots[cell.lr as usize] |= 8;
    }
    slots.iter().filter(|s| s.count_ones() >= 2).count()
}

/// The joint of every vertex, in vertex order.
pub fn joints(lattice: &Lattice) -> Vec<Joint> {
    let n = lattice.vertices.len();
    // Slots in the order of docs/math.md 10.2, filled from the cells' corners.
    let mut slots: Vec<[Option<JointEnd>; 4]> = vec![[None; 4]; n];
    for (index, cell) in lattice.cells.iter().enumerate() {
        let end = |kind, end| {
            Some(JointEnd {
                rod: 2 * index + (kind == RodType::B) as usize,
                kind,
                end,
                layer: lattice.layer(cell, kind),
            })
        };
        slots[cell.ul as usize][0] = end(RodType::A, RodEnd::Start);
        slots[cell.ur as usize][1] = end(RodType::B, RodEnd::Start);
        slots[cell.ll as usize][2] = end(RodType::B, RodEnd::End);
        slots[cell.lr as usize][3] = end(RodType::A, RodEnd::End);
    }
    slots
        .into_iter()
        .enumerate()
        .map(|(v, s)| Joint {
            vertex: v as u32,
            ends: s.into_iter().flatten().collect(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::fixtures;

    #[test]
    fn eyelet_count_matches_the_joints() {
        let sheet = fixtures::sheet(&fixtures::line(4), &[0.0; 4], 1, 45.0, 3);
        let count = vertex_eyelet_count(&sheet);
        assert_eq!(count, vertex_eyelets(&joints(&sheet)));
        // The seed's and the last row's end vertices hold one rod end.
        assert_eq!(count, sheet.vertices.len() - 4);
    }
}
