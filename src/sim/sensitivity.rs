//! Design sensitivities of the deployed shape (docs/physics.md,
//! "Sensitivities"): the derivative of the simulated joint positions
//! (`LatticeModel::points`) with respect to the design parameters, by the
//! adjoint of the equilibrium (`karigami_rods::adjoint`).
//!
//! The design parameters are what the simulation takes from the lattice:
//! every leg's length (a strip's arc length from one hole to the next;
//! its interior edges share it less the rigid arms, so each edge's rest
//! length moves by 1/count of it and each bend's lbar, the mean of its
//! two edges' rests, by the mean of theirs) and the held opening (one
//! cell's or the mean, radians). A recipe's parameters reach these
//! through the grown lattice: a seed point or a row's legs change the leg
//! lengths `lattice.rods()` gives, and its opening the held opening; the
//! chain rule through the growth is the caller's. Derivatives are in the
//! gauge the anchor (cell 0's pivot) sets, or with the supports
//! (`supports.rs`) held where they are: a pin does not follow the design.

use super::System;
use super::model::{Model, Node, Stencil};
use super::strips::{Hold, LatticeModel, VertexPlace};
use glam::DVec3;
use karigami_rods::adjoint::{AdjointError, Direction, Linearisation};

/// A design parameter (module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    /// Leg `k` of `LatticeModel::legs`.
    Leg(usize),
    /// The held opening.
    Opening,
}

/// The gradient of an objective over the design parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct DesignGradient {
    /// The objective's value.
    pub value: f64,
    /// d/d leg length, by `LatticeModel::legs`.
    pub legs: Vec<f64>,
    /// d/d held opening (per radian).
    pub opening: f64,
}

impl LatticeModel {
    /// Every leg: the interior (non-arm) edges between two holes of a
    /// strip, rod by rod, in order along it.
    pub fn legs(&self) -> Vec<Vec<usize>> {
        let m = &self.model;
        let mut legs = Vec::new();
        for rod in &m.rods {
            let mut run: Vec<usize> = Vec::new();
            for &e in &rod.edges {
                if m.edges[e].is_arm() {
                    if !run.is_empty() {
                        legs.push(std::mem::take(&mut run));
                    }
                } else {
                    run.push(e);
                }
            }
            if !run.is_empty() {
                legs.push(run);
            }
        }
        legs
    }

    /// The model's parameter change for a unit change of `p`.
    pub fn direction(&self, p: Param) -> Direction {
        match p {
            Param::Leg(k) => {
                let legs = self.legs();
                let Some(leg) = legs.get(k) else {
                    return Direction::default();
                };
                let mut rest = vec![0.0; self.model.edges.len()];
                for &e in leg {
                    rest[e] = 1.0 / leg.len() as f64;
                }
                leg_direction(&self.model, &rest)
            }
            Param::Opening => Direction {
                fixed: self.opening_vars(),
                ..Direction::default()
            },
        }
    }

    /// The variables the held opening sets, each with its rate (the
    /// cells' delta variables: a tie's offset, or the held cell's value).
    fn opening_vars(&self) -> Vec<(usize, f64)> {
        match self.hold {
            Hold::Mean => self
                .delta
                .iter()
                .filter(|d| self.model.ties.iter().any(|t| t.var == d.0))
                .copied()
                .collect(),
            Hold::Cell(c) => vec![self.delta[c]],
            Hold::Nothing => Vec::new(),
        }
    }
}

/// Edge rest-length rates `rest` with the bends' lbar rates they imply.
fn leg_direction(m: &Model, rest: &[f64]) -> Direction {
    let lbar = m
        .stencils
        .iter()
        .enumerate()
        .filter_map(|(s, st)| match *st {
            Stencil::Bend { e0, e1, .. } if rest[e0] != 0.0 || rest[e1] != 0.0 => {
                Some((s, (rest[e0] + rest[e1]) / 2.0))
            }
            _ => None,
        })
        .collect();
    Direction {
        rest: (0..rest.len())
            .filter(|&e| rest[e] != 0.0)
            .map(|e| (e, rest[e]))
            .collect(),
        lbar,
        fixed: Vec::new(),
    }
}

/// How every point of `LatticeModel::points` moves with the variables:
/// (variable, d point / d variable) for each.
fn point_jacobians(lm: &LatticeModel) -> Vec<Vec<(usize, DVec3)>> {
    let m = &lm.model;
    let joint = |j: usize| {
        let x = m.joints[j].x;
        vec![(x, DVec3::X), (x + 1, DVec3::Y), (x + 2, DVec3::Z)]
    };
    let node = |n: usize| match m.nodes[n] {
        Node::Hole(j) => joint(j),
        _ => {
            let (vars, jac) = m.node_jacobian(n);
            vars.into_iter().zip(jac).collect()
        }
    };
    lm.vertex
        .iter()
        .map(|v| match *v {
            VertexPlace::Joint(j) => joint(j),
            VertexPlace::Node(n) => node(n),
            VertexPlace::None => Vec::new(),
        })
        .chain(lm.pivot.iter().map(|&j| joint(j)))
        .collect()
}

/// d points / d p at the equilibrium `lm` is at (`sys` its system).
pub fn point_tangent(
    lm: &LatticeModel,
    sys: &System,
    p: Param,
) -> Result<Vec<DVec3>, AdjointError> {
    let lin = Linearisation::new(sys, &lm.model)?;
    let dq = lin.tangent(&lm.model, &lm.direction(p));
    lin.release();
    Ok(point_jacobians(lm)
        .iter()
        .map(|jac| jac.iter().map(|&(v, d)| d * dq[v]).sum())
        .collect())
}

/// J = sum over points of |point - target|^2 (points `LatticeModel::points`
/// lists; a vertex no rod reaches is left out) and its gradient over
/// every design parameter, by one adjoint solve.
pub fn objective_gradient(
    lm: &LatticeModel,
    sys: &System,
    targets: &[DVec3],
) -> Result<DesignGradient, AdjointError> {
    let m = &lm.model;
    let points = lm.points();
    let mut dj = vec![0.0; m.q.len()];
    let mut value = 0.0;
    for ((jac, p), t) in point_jacobians(lm).iter().zip(&points).zip(targets) {
        if jac.is_empty() {
            continue;
        }
        let r = *p - *t;
        value += r.length_squared();
        for &(v, d) in jac {
            dj[v] += 2.0 * r.dot(d);
        }
    }
    let lin = Linearisation::new(sys, m)?;
    let g = lin.gradient(m, &dj);
    lin.release();
    // Each bend's lbar rate by edge: half of it to each of its edges.
    let mut by_edge = g.rest.clone();
    for (s, st) in m.stencils.iter().enumerate() {
        if let Stencil::Bend { e0, e1, .. } = *st {
            by_edge[e0] += 0.5 * g.lbar[s];
            by_edge[e1] += 0.5 * g.lbar[s];
        }
    }
    let legs = lm
        .legs()
        .iter()
        .map(|leg| leg.iter().map(|&e| by_edge[e]).sum::<f64>() / leg.len() as f64)
        .collect();
    let opening = lm.opening_vars().iter().map(|&(v, s)| s * g.fixed[v]).sum();
    Ok(DesignGradient {
        value,
        legs,
        opening,
    })
}
