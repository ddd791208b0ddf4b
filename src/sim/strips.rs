//! The model of a lattice (docs/physics.md, "Strips as discrete elastic
//! rods", "Eyelets"): every rod a chain of nodes with rigid arms at its
//! holes, every pivot and every shared vertex an eyelet joint (or, for
//! vertices, a ball joint). Stack offsets (strip thickness at a joint) are
//! neglected: all strips at a joint meet at one point.

use super::model::{Edge, Frame, Joint, Model, Node, RodPath, Section, Slot, Stencil, VarKind};
use crate::lattice::{Joint as LatticeJoint, Lattice, joints};
use glam::DVec3;

/// How rod ends at a shared vertex are joined (docs/physics.md, "Eyelets").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VertexJoint {
    /// Centre lines meet and faces stay stacked; each strip turns freely
    /// about the eyelet's axis.
    Eyelet,
    /// Position only (the ideal linkage's spherical joint).
    Ball,
}

impl VertexJoint {
    /// The recipe's name for it (`[simulation] vertex_joint`): `eyelet` or `ball`.
    pub fn name(self) -> &'static str {
        match self {
            VertexJoint::Eyelet => "eyelet",
            VertexJoint::Ball => "ball",
        }
    }
}

/// Discretisation settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mesh {
    /// Longest interior edge (mm).
    pub h_max: f64,
    /// Rigid arm length each side of a hole (mm), normally w/2.
    pub arm: f64,
    /// How rod ends at a shared vertex are joined.
    pub vertex_joint: VertexJoint,
}

/// A lattice's model with the bookkeeping that maps it back to the lattice.
#[derive(Clone, Debug)]
pub struct LatticeModel {
    /// The discrete elastic rods, their joints and energy.
    pub model: Model,
    /// Joint of each cell's pivot.
    pub(crate) pivot: Vec<usize>,
    /// Per cell: the variable delta = alpha_B - alpha_A at its pivot, and
    /// the sign s_c with phi_c = s_c delta.
    pub(crate) delta: Vec<(usize, f64)>,
    /// Per vertex: its joint, or (a corner) the node of the single rod end.
    pub(crate) vertex: Vec<VertexPlace>,
    /// The starting placement of every vertex and pivot (the design, or
    /// for bent-facet lattices the rigid-fit placement).
    pub(crate) start: Vec<DVec3>,
    /// What deployment holds (`hold_cell`, `hold_mean`).
    pub hold: Hold,
    /// Per cell: its class under the lattice's symmetry
    /// (`Settings::symmetry`); the mean hold gives a class one opening.
    /// Every cell its own class unless a symmetry is set.
    pub(crate) share: Vec<usize>,
    /// Opening of every cell in the start placement (radians).
    pub(crate) start_openings: Vec<f64>,
}

/// The measure of the deployment that is prescribed (docs/physics.md,
/// "Deployment").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Hold {
    /// Nothing yet: only rigid motions are removed.
    Nothing,
    /// The opening of one cell.
    Cell(usize),
    /// The mean opening of all cells, each cell free to differ from it.
    Mean,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum VertexPlace {
    Joint(usize),
    Node(usize),
    /// A vertex no rod reaches.
    None,
}

/// Per rod end: (joint, slot) where it sits.
type EndSlot = Option<(usize, usize)>;

impl LatticeModel {
    /// Build the model of `lattice` in its design state (bent-facet
    /// lattices: their rigid-fit placement, shared vertices halfway).
    pub fn new(lattice: &Lattice, section: Section, mesh: Mesh) -> LatticeModel {
        Self::with_derived(lattice, &lattice.placed(), &joints(lattice), section, mesh)
    }

    /// `new` with what the build has computed already: `placed` is
    /// `lattice.placed()` and `vertex_joints` is `lattice::joints(lattice)`.
    pub fn with_derived(
        lattice: &Lattice,
        placed: &Lattice,
        vertex_joints: &[LatticeJoint],
        section: Section,
        mesh: Mesh,
    ) -> LatticeModel {
        let cut: Vec<_> = lattice.rods().collect();
        let geo: Vec<_> = placed.rods().collect();
        let nv = lattice.vertices.len();
        let mean_leg =
            cut.iter().map(|r| r.length()).sum::<f64>() / (2.0 * cut.len().max(1) as f64);
        let mut model = Model::new(section, section.b_flat / mean_leg.max(1e-9));
        // Face normal of every rod: its cell's plane.
        let normals: Vec<DVec3> = geo
            .iter()
            .map(|r| {
                if lattice.dim == 2 {
                    return DVec3::Z;
                }
                let c = &placed.cells[r.cell];
                let [ul, ur, _, _] = placed.corners(c);
                let n = (c.pivot - ul).cross(c.pivot - ur);
                if n.length() > 1e-12 {
                    n.normalize()
                } else {
                    DVec3::Z
                }
            })
            .collect();
        let tangent = |r: usize, hole: usize| -> DVec3 {
            let h = geo[r].hole_pos;
            let t = match hole {
                0 => h[1] - h[0],
                1 => h[2] - h[0],
                _ => h[2] - h[1],
            };
            t.normalize()
        };
        let add_joint = |model: &mut Model,
                         x: DVec3,
                         rods: &[(usize, usize)],
                         tilt: bool,
                         vertex,
                         cell|
         -> (usize, Vec<f64>) {
            // Axis: the mean of the incident faces' normals, signed alike.
            let n0 = normals[rods[0].0];
            let mut n = DVec3::ZERO;
            for &(r, _) in rods {
                let nr = normals[r];
                n += if nr.dot(n0) < 0.0 { -nr } else { nr };
            }
            let n = n.normalize();
            let helper = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
            let p = (helper - n * helper.dot(n)).normalize();
            let q = n.cross(p);
            let xv = model.add_vars(&[x.x, x.y, x.z], VarKind::Length);
            let tv = tilt.then(|| model.add_vars(&[0.0, 0.0], VarKind::Angle));
            let sigmas = rods
                .iter()
                .map(|&(r, _)| if normals[r].dot(n) < 0.0 { -1.0 } else { 1.0 })
                .collect();
            model.joints.push(Joint {
                x: xv,
                tilt: tv,
                frame: [n, p, q],
                slots: Vec::new(),
                vertex,
                cell,
            });
            (model.joints.len() - 1, sigmas)
        };
        let angle_of = |model: &Model, j: usize, t: DVec3| {
            let [_, p, q] = model.joints[j].frame;
            t.dot(q).atan2(t.dot(p))
        };
        // Pivots.
        let mut pivot = Vec::with_capacity(lattice.cells.len());
        let mut delta = Vec::with_capacity(lattice.cells.len());
        let mut sigma_at: Vec<[f64; 3]> = vec![[1.0; 3]; cut.len()];
        let mut slot_at: Vec<[EndSlot; 3]> = vec![[None; 3]; cut.len()];
        for (c, cell) in placed.cells.iter().enumerate() {
            let (ra, rb) = (2 * c, 2 * c + 1);
            let (j, sig) = add_joint(
                &mut model,
                cell.pivot,
                &[(ra, 1), (rb, 1)],
                true,
                None,
                Some(c),
            );
            let aa = angle_of(&model, j, tangent(ra, 1));
            let ab = angle_of(&model, j, tangent(rb, 1));
            let mut d = ab - aa;
            while d > std::f64::consts::PI {
                d -= std::f64::consts::TAU;
            }
            while d <= -std::f64::consts::PI {
                d += std::f64::consts::TAU;
            }
            let av = model.add_vars(&[aa], VarKind::Angle);
            let dv = model.add_vars(&[d], VarKind::Angle);
            model.joints[j].slots.push(Slot {
                angle: [av, 0],
                terms: 1,
                rod: ra,
            });
            model.joints[j].slots.push(Slot {
                angle: [av, dv],
                terms: 2,
                rod: rb,
            });
            sigma_at[ra][1] = sig[0];
            sigma_at[rb][1] = sig[1];
            slot_at[ra][1] = Some((j, 0));
            slot_at[rb][1] = Some((j, 1));
            pivot.push(j);
            delta.push((dv, d.signum()));
        }
        // Vertices.
        let mut vertex = vec![VertexPlace::None; nv];
        for jt in vertex_joints {
            if jt.ends.len() < 2 {
                continue;
            }
            let ends: Vec<(usize, usize)> = jt
                .ends
                .iter()
                .map(|e| {
                    (
                        e.rod,
                        if e.end == crate::lattice::RodEnd::Start {
                            0
                        } else {
                            2
                        },
                    )
                })
                .collect();
            let x =
                ends.iter().map(|&(r, h)| geo[r].hole_pos[h]).sum::<DVec3>() / ends.len() as f64;
            let eyelet = mesh.vertex_joint == VertexJoint::Eyelet;
            let (j, sig) = add_joint(&mut model, x, &ends, eyelet, Some(jt.vertex), None);
            for (k, &(r, h)) in ends.iter().enumerate() {
                if eyelet {
                    let a = angle_of(&model, j, tangent(r, h));
                    let av = model.add_vars(&[a], VarKind::Angle);
                    model.joints[j].slots.push(Slot {
                        angle: [av, 0],
                        terms: 1,
                        rod: r,
                    });
                    slot_at[r][h] = Some((j, model.joints[j].slots.len() - 1));
                } else {
                    slot_at[r][h] = Some((j, usize::MAX));
                }
                sigma_at[r][h] = sig[k];
            }
            vertex[jt.vertex as usize] = VertexPlace::Joint(j);
        }
        let width_of = |m: u32| m.to_string().len().max(2);
        let digits = (
            width_of(lattice.cells.iter().map(|c| c.row).max().unwrap_or(0)),
            width_of(lattice.cells.iter().map(|c| c.col).max().unwrap_or(0)),
        );
        // Rods.
        for (r, rod) in cut.iter().enumerate() {
            let holes = rod.holes();
            let n_r = normals[r];
            // Anchor sequence: (node, s, Some((joint, slot, sigma)) for an arm edge after it).
            let mut nodes: Vec<usize> = Vec::new();
            let mut s: Vec<f64> = Vec::new();
            let mut edges: Vec<usize> = Vec::new();
            let push_edge = |model: &mut Model,
                             nodes: &[usize],
                             frame: Frame,
                             rest: f64,
                             edges: &mut Vec<usize>| {
                let (a, b) = (nodes[nodes.len() - 2], nodes[nodes.len() - 1]);
                model.edges.push(Edge { a, b, frame, rest });
                edges.push(model.edges.len() - 1);
            };
            let arm_len = |leg: f64| {
                if leg >= 2.0 * mesh.arm + 1.0 {
                    mesh.arm
                } else {
                    leg / 3.0
                }
            };
            let leg_arm = [arm_len(rod.legs[0]), arm_len(rod.legs[1])];
            // Interior edges from the last node to a node at s_b (its position given).
            let interior = |model: &mut Model,
                            nodes: &mut Vec<usize>,
                            s: &mut Vec<f64>,
                            edges: &mut Vec<usize>,
                            sb: f64,
                            xb: DVec3,
                            end: Node| {
                let sa = *s.last().expect("a first node");
                let xa = model.pos(*nodes.last().expect("a first node"));
                let count = ((sb - sa) / mesh.h_max).ceil().max(1.0) as usize;
                let rest = (sb - sa) / count as f64;
                for k in 1..=count {
                    let f = k as f64 / count as f64;
                    let node = if k == count {
                        model.nodes.push(end);
                        model.nodes.len() - 1
                    } else {
                        model.add_free_node(xa.lerp(xb, f))
                    };
                    nodes.push(node);
                    s.push(sa + rest * k as f64);
                    let t = (xb - xa).normalize();
                    let d2 = (n_r - t * n_r.dot(t)).normalize();
                    let theta = model.add_vars(&[0.0], VarKind::Angle);
                    push_edge(
                        model,
                        nodes,
                        Frame::Ref {
                            ts: t,
                            as_: d2.cross(t),
                            theta,
                        },
                        rest,
                        edges,
                    );
                }
            };
            for hole in 0..3 {
                let sh = holes[hole];
                match slot_at[r][hole] {
                    None => {
                        // A corner: a free end node at the hole.
                        let x = geo[r].hole_pos[hole];
                        if hole == 0 {
                            let n = model.add_free_node(x);
                            nodes.push(n);
                            s.push(sh);
                        } else {
                            let n = Node::Free(model.add_vars(&[x.x, x.y, x.z], VarKind::Length));
                            interior(&mut model, &mut nodes, &mut s, &mut edges, sh, x, n);
                        }
                    }
                    Some((j, usize::MAX)) => {
                        let x = geo[r].hole_pos[hole];
                        let x = model.pos_of_joint(j).unwrap_or(x);
                        if hole == 0 {
                            model.nodes.push(Node::Hole(j));
                            nodes.push(model.nodes.len() - 1);
                            s.push(sh);
                        } else {
                            interior(
                                &mut model,
                                &mut nodes,
                                &mut s,
                                &mut edges,
                                sh,
                                x,
                                Node::Hole(j),
                            );
                        }
                    }
                    Some((j, slot)) => {
                        let sigma = sigma_at[r][hole];
                        let frame = Frame::Arm {
                            joint: j,
                            slot,
                            sigma,
                        };
                        if hole > 0 {
                            let ra = leg_arm[hole - 1];
                            let tip = Node::Arm {
                                joint: j,
                                slot,
                                r: -ra,
                            };
                            let xt = model.node_value(tip);
                            interior(&mut model, &mut nodes, &mut s, &mut edges, sh - ra, xt, tip);
                            model.nodes.push(Node::Hole(j));
                            nodes.push(model.nodes.len() - 1);
                            s.push(sh);
                            push_edge(&mut model, &nodes, frame, ra, &mut edges);
                        } else {
                            model.nodes.push(Node::Hole(j));
                            nodes.push(model.nodes.len() - 1);
                            s.push(sh);
                        }
                        if hole < 2 {
                            let ra = leg_arm[hole];
                            model.nodes.push(Node::Arm {
                                joint: j,
                                slot,
                                r: ra,
                            });
                            nodes.push(model.nodes.len() - 1);
                            s.push(sh + ra);
                            push_edge(&mut model, &nodes, frame, ra, &mut edges);
                        }
                    }
                }
            }
            // Energy stencils.
            for &e in &edges {
                if !model.edges[e].is_arm() {
                    model.stencils.push(Stencil::Stretch { edge: e, rod: r });
                }
            }
            for w in edges.windows(2) {
                let (e0, e1) = (&model.edges[w[0]], &model.edges[w[1]]);
                let same_joint = match (e0.frame, e1.frame) {
                    (Frame::Arm { joint: a, .. }, Frame::Arm { joint: b, .. }) => a == b,
                    _ => false,
                };
                if same_joint {
                    continue; // collinear arms through a pivot: identically 0
                }
                let lbar = (e0.rest + e1.rest) / 2.0;
                model.stencils.push(Stencil::Bend {
                    e0: w[0],
                    e1: w[1],
                    lbar,
                    rod: r,
                });
            }
            // The strip's engraved id (parts::strip_id), so a maker finds it.
            let cell = &lattice.cells[rod.cell];
            let name = crate::parts::strip_id(cell.row, cell.col, rod.kind, digits.0, digits.1);
            model.rods.push(RodPath {
                name,
                nodes,
                edges,
                s,
            });
        }
        // Corner vertices: the node at the single rod end.
        for (r, rod) in cut.iter().enumerate() {
            for (hole, v) in [(0usize, rod.start), (2, rod.end)] {
                if vertex[v as usize] == VertexPlace::None {
                    let path = &model.rods[r];
                    let node = if hole == 0 {
                        path.nodes[0]
                    } else {
                        *path.nodes.last().expect("nodes")
                    };
                    vertex[v as usize] = VertexPlace::Node(node);
                }
            }
        }
        let mut lm = LatticeModel {
            model,
            pivot,
            delta,
            vertex,
            start: Vec::new(),
            hold: Hold::Nothing,
            share: (0..lattice.cells.len()).collect(),
            start_openings: Vec::new(),
        };
        lm.start = lm.points();
        lm.start_openings = (0..lm.delta.len()).map(|c| lm.opening(c)).collect();
        lm
    }
}
