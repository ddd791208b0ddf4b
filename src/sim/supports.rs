//! Supports (docs/physics.md, "Supports"): vertices held at their start
//! positions, as pins to a table or base hold a vault's feet
//! (`[simulation] supports`). Their position variables are fixed, so every
//! solve of the model (continuation, warm re-solves, the exploration of
//! other states, the sensitivities) holds them; three not on one line fix
//! the rigid motion, and cell 0's anchor, which would over-constrain the
//! lattice, is left out. The deployment path is walked with the pins
//! released (`released`): a maker deploys the lattice, then pins its feet.

use super::model::Node;
use super::strips::{LatticeModel, VertexPlace};
use crate::lattice::Lattice;
use glam::DVec3;
use std::collections::HashMap;

/// A vertex held where it starts: its index and its first position
/// variable (the other two follow it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Pin {
    pub(crate) vertex: u32,
    pub(crate) x: usize,
}

/// The force a support exerts on the lattice at equilibrium.
#[derive(Clone, Debug, PartialEq)]
pub struct Reaction {
    /// The vertex held (an index of `Lattice::vertices`).
    pub vertex: u32,
    /// Where it is held (mm).
    pub at: DVec3,
    /// The force on the lattice (N): the elastic energy's gradient over
    /// the vertex's position, dE/dX, which the pin balances.
    pub force: DVec3,
}

impl LatticeModel {
    /// Hold `vertices` (of `lattice`'s, by key `[row, column]`) where the
    /// model has them, and anchor cell 0's pivot unless they fix the
    /// rigid motion themselves (three or more, not on one line). A key
    /// the lattice lacks, or a vertex no rod reaches, is not held: the
    /// recipe's supports are checked against the lattice before
    /// (`Design::check_supports`).
    pub(crate) fn pin_supports(&mut self, lattice: &Lattice, keys: &[[u32; 2]]) {
        let found = crate::design::supports::supported(lattice, keys);
        for v in found.into_iter().flatten() {
            let x = match self.vertex[v as usize] {
                VertexPlace::Joint(j) => Some(self.model.joints[j].x),
                VertexPlace::Node(n) => match self.model.nodes[n] {
                    Node::Free(x) => Some(x),
                    Node::Hole(j) => Some(self.model.joints[j].x),
                    Node::Arm { .. } => None,
                },
                VertexPlace::None => None,
            };
            if let Some(x) = x {
                self.model.fixed[x..x + 3].fill(true);
                self.pins.push(Pin { vertex: v, x });
            }
        }
        if !self.pins_fix_rigid_motion() {
            self.anchor(0);
        }
    }

    /// Whether the pins alone fix the lattice in space.
    fn pins_fix_rigid_motion(&self) -> bool {
        let at: Vec<DVec3> = self.pins.iter().map(|p| self.pin_position(p)).collect();
        at.len() >= crate::design::supports::MIN_SUPPORTS
            && crate::design::supports::off_line(&at)
                .is_some_and(|(_, _, off)| off > crate::design::supports::COLLINEAR)
    }

    fn pin_position(&self, p: &Pin) -> DVec3 {
        let q = &self.model.q;
        DVec3::new(q[p.x], q[p.x + 1], q[p.x + 2])
    }

    /// The supports' vertices (indices of `Lattice::vertices`), in order.
    pub fn supports(&self) -> Vec<u32> {
        self.pins.iter().map(|p| p.vertex).collect()
    }

    /// The model with its pins released and cell 0's pivot anchored
    /// instead: the lattice standing free, for its deployment path.
    pub(crate) fn released(&self) -> LatticeModel {
        let mut free = self.clone();
        for p in std::mem::take(&mut free.pins) {
            free.model.fixed[p.x..p.x + 3].fill(false);
        }
        if !free.pivot.is_empty() {
            free.anchor(0);
        }
        free
    }

    /// The reaction at every support now (`Reaction`), in the pins' order.
    pub fn reactions(&self) -> Vec<Reaction> {
        let m = &self.model;
        let mut owner: HashMap<usize, (usize, usize)> = HashMap::new();
        for (k, p) in self.pins.iter().enumerate() {
            for a in 0..3 {
                owner.insert(p.x + a, (k, a));
            }
        }
        let mut force = vec![DVec3::ZERO; self.pins.len()];
        super::results::owned_gradients(m, &owner, |_, k, a, g| force[k][a] += g);
        self.pins
            .iter()
            .zip(force)
            .map(|(p, force)| Reaction {
                vertex: p.vertex,
                at: self.pin_position(p),
                force,
            })
            .collect()
    }
}

/// The two supports farthest apart and their distance (mm): the span the
/// base must give. None for fewer than two.
pub fn span(reactions: &[Reaction]) -> Option<(u32, u32, f64)> {
    let at: Vec<DVec3> = reactions.iter().map(|r| r.at).collect();
    crate::design::supports::farthest(&at).map(|(a, b)| {
        (
            reactions[a].vertex,
            reactions[b].vertex,
            at[a].distance(at[b]),
        )
    })
}
