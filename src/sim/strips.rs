//! The model of a lattice (docs/physics.md, "Strips as discrete elastic
//! rods", "Eyelets"): every rod a chain of nodes with rigid arms at its
//! holes, every pivot and every shared vertex an eyelet joint (or, for
//! vertices, a ball joint). Stack offsets (strip thickness at a joint) are
//! neglected: all strips at a joint meet at one point.

use super::VertexJoint;
use super::model::{Edge, Frame, Joint, Model, Node, RodPath, Section, Slot, Stencil, VarKind};
use crate::lattice::{Joint as LatticeJoint, Lattice, Rod, RodEnd, joints};
use glam::DVec3;
use karigami_rods::solver::System;
use std::sync::Arc;

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
    /// Per rod: the number of interior edges of each of its legs, in
    /// order (`with_counts` meshes a changed design alike).
    pub(crate) leg_counts: Vec<Vec<usize>>,
    /// The solver's system this model was last solved with, kept by
    /// `resolve` and `keep_system` (not by `deploy`: a build's path solves
    /// on a system of its own, and two at once would pass the memory that
    /// `cost::BYTES_PER_NODE` allows).
    pub(crate) system: KeptSystem,
    /// The vertices held at their start positions (`[simulation]
    /// supports`, `supports.rs`), each with its three position variables.
    pub(crate) pins: Vec<super::supports::Pin>,
}

/// A solver's system kept with its model: a warm re-solve of a changed
/// design that it still fits (`System::fits`) skips the ordering and
/// symbolic analysis (docs/physics.md, "Sensitivities").
#[derive(Clone, Default)]
pub(crate) struct KeptSystem(Option<Arc<System>>);

impl KeptSystem {
    pub(crate) fn new(sys: Arc<System>) -> KeptSystem {
        KeptSystem(Some(sys))
    }

    /// The kept system if it fits `model`, else a new one.
    pub(crate) fn for_model(&self, model: &Model) -> Arc<System> {
        match &self.0 {
            Some(sys) if sys.fits(model) => Arc::clone(sys),
            _ => Arc::new(System::new(model)),
        }
    }
}

impl std::fmt::Debug for KeptSystem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let n = self.0.as_ref().map(|s| s.n());
        f.debug_tuple("KeptSystem").field(&n).finish()
    }
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
    /// The solver's system for this model: the one it was last solved
    /// with if that still fits it (`System::fits`), else a new one. A
    /// design loop's warm re-solves and adjoints share it.
    pub fn system(&self) -> Arc<System> {
        self.system.for_model(&self.model)
    }

    /// `system`, kept with the model from now on: a design loop's first
    /// step, after a cold simulation, keeps it for the re-solves after it.
    pub fn keep_system(&mut self) -> Arc<System> {
        let sys = self.system();
        self.system = KeptSystem::new(Arc::clone(&sys));
        sys
    }

    /// Build the model of `lattice` in its design state (bent-facet
    /// lattices: their rigid-fit placement, shared vertices halfway).
    pub fn new(lattice: &Lattice, section: Section, mesh: Mesh) -> LatticeModel {
        Self::with_derived(lattice, &lattice.placed(), &joints(lattice), section, mesh)
    }

    /// `new` with what the build has computed already: `placed` is
    /// `lattice.placed()` and `vertex_joints` is `lattice::joints(lattice)`.
    /// Built in order: a joint at every pivot, one at every shared vertex,
    /// then each rod's chain of nodes and edges between its holes (the
    /// variables' order, and so the solver's, follows this order).
    pub fn with_derived(
        lattice: &Lattice,
        placed: &Lattice,
        vertex_joints: &[LatticeJoint],
        section: Section,
        mesh: Mesh,
    ) -> LatticeModel {
        Self::with_counts(lattice, placed, vertex_joints, section, mesh, None)
    }

    /// `with_derived`, each leg cut into as many edges as `counts` gives
    /// (`leg_counts` of a model of the same topology) instead of by
    /// `h_max`: a small change of the design keeps its mesh, so a warm
    /// re-solve starts from the last state (`warm`).
    pub fn with_counts(
        lattice: &Lattice,
        placed: &Lattice,
        vertex_joints: &[LatticeJoint],
        section: Section,
        mesh: Mesh,
        counts: Option<&[Vec<usize>]>,
    ) -> LatticeModel {
        let mut b = Builder::new(lattice, placed, section, mesh);
        b.forced = counts.map(<[Vec<usize>]>::to_vec);
        let (pivot, delta) = b.add_pivots();
        let mut vertex = b.add_vertex_joints(vertex_joints);
        let width_of = |m: u32| m.to_string().len().max(2);
        let digits = (
            width_of(lattice.cells.iter().map(|c| c.row).max().unwrap_or(0)),
            width_of(lattice.cells.iter().map(|c| c.col).max().unwrap_or(0)),
        );
        let mut leg_counts = Vec::with_capacity(b.cut.len());
        for r in 0..b.cut.len() {
            leg_counts.push(b.add_rod(r, digits));
        }
        b.corner_vertices(&mut vertex);
        let mut lm = LatticeModel {
            model: b.model,
            pivot,
            delta,
            vertex,
            start: Vec::new(),
            hold: Hold::Nothing,
            share: (0..lattice.cells.len()).collect(),
            start_openings: Vec::new(),
            leg_counts,
            system: KeptSystem::default(),
            pins: Vec::new(),
        };
        lm.start = lm.points();
        lm.start_openings = (0..lm.delta.len()).map(|c| lm.opening(c)).collect();
        lm
    }
}

/// A lattice's model as it is built (`LatticeModel::with_derived`): the
/// rods as cut (their legs) and as placed (their holes in space), each
/// rod's face normal, and where each of its three holes sits on a joint.
struct Builder<'a> {
    lattice: &'a Lattice,
    placed: &'a Lattice,
    mesh: Mesh,
    cut: Vec<Rod>,
    geo: Vec<Rod>,
    normals: Vec<DVec3>,
    model: Model,
    /// Per rod and hole: the sign of the rod's face against its joint's axis.
    sigma_at: Vec<[f64; 3]>,
    /// Per rod and hole: the joint and slot it sits in.
    slot_at: Vec<[EndSlot; 3]>,
    /// Per rod: its legs' edge counts to keep (`with_counts`).
    forced: Option<Vec<Vec<usize>>>,
}

impl<'a> Builder<'a> {
    fn new(lattice: &'a Lattice, placed: &'a Lattice, section: Section, mesh: Mesh) -> Self {
        let cut: Vec<_> = lattice.rods().collect();
        let geo: Vec<_> = placed.rods().collect();
        let mean_leg =
            cut.iter().map(|r| r.length()).sum::<f64>() / (2.0 * cut.len().max(1) as f64);
        let model = Model::new(section, section.b_flat / mean_leg.max(1e-9));
        let normals = geo
            .iter()
            .map(|r| face_normal(lattice, placed, r))
            .collect();
        let rods = cut.len();
        Builder {
            lattice,
            placed,
            mesh,
            cut,
            geo,
            normals,
            model,
            sigma_at: vec![[1.0; 3]; rods],
            slot_at: vec![[None; 3]; rods],
            forced: None,
        }
    }

    /// Rod r's direction at `hole` (0 start, 1 pivot, 2 end).
    fn tangent(&self, r: usize, hole: usize) -> DVec3 {
        let h = self.geo[r].hole_pos;
        let t = match hole {
            0 => h[1] - h[0],
            1 => h[2] - h[0],
            _ => h[2] - h[1],
        };
        t.normalize()
    }

    /// A joint at `x` holding the rod holes `rods` (rod, hole), turning
    /// about the mean of their faces' normals; with `tilt`, free to tilt
    /// as an eyelet is. Returns it and each rod's sign against its axis.
    fn add_joint(
        &mut self,
        x: DVec3,
        rods: &[(usize, usize)],
        tilt: bool,
        vertex: Option<u32>,
        cell: Option<usize>,
    ) -> (usize, Vec<f64>) {
        let normals = &self.normals;
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
        let model = &mut self.model;
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
    }

    /// The angle of direction `t` about joint j's axis.
    fn angle_of(&self, j: usize, t: DVec3) -> f64 {
        let [_, p, q] = self.model.joints[j].frame;
        t.dot(q).atan2(t.dot(p))
    }

    /// A joint at every cell's pivot holding both its rods, with the
    /// variable delta = alpha_B - alpha_A: (pivot joints, (delta, sign)).
    fn add_pivots(&mut self) -> (Vec<usize>, Vec<(usize, f64)>) {
        let cells = self.placed.cells.len();
        let mut pivot = Vec::with_capacity(cells);
        let mut delta = Vec::with_capacity(cells);
        for c in 0..cells {
            let (ra, rb) = (2 * c, 2 * c + 1);
            let at = self.placed.cells[c].pivot;
            let (j, sig) = self.add_joint(at, &[(ra, 1), (rb, 1)], true, None, Some(c));
            let aa = self.angle_of(j, self.tangent(ra, 1));
            let ab = self.angle_of(j, self.tangent(rb, 1));
            let mut d = ab - aa;
            while d > std::f64::consts::PI {
                d -= std::f64::consts::TAU;
            }
            while d <= -std::f64::consts::PI {
                d += std::f64::consts::TAU;
            }
            let av = self.model.add_vars(&[aa], VarKind::Angle);
            let dv = self.model.add_vars(&[d], VarKind::Angle);
            let slots = &mut self.model.joints[j].slots;
            slots.push(Slot {
                angle: [av, 0],
                terms: 1,
                rod: ra,
            });
            slots.push(Slot {
                angle: [av, dv],
                terms: 2,
                rod: rb,
            });
            self.sigma_at[ra][1] = sig[0];
            self.sigma_at[rb][1] = sig[1];
            self.slot_at[ra][1] = Some((j, 0));
            self.slot_at[rb][1] = Some((j, 1));
            pivot.push(j);
            delta.push((dv, d.signum()));
        }
        (pivot, delta)
    }

    /// A joint at every vertex two or more rod ends share, at the mean of
    /// their holes; each vertex's place in the model.
    fn add_vertex_joints(&mut self, vertex_joints: &[LatticeJoint]) -> Vec<VertexPlace> {
        let mut vertex = vec![VertexPlace::None; self.lattice.vertices.len()];
        let eyelet = self.mesh.vertex_joint == VertexJoint::Eyelet;
        for jt in vertex_joints {
            if jt.ends.len() < 2 {
                continue;
            }
            let ends: Vec<(usize, usize)> = jt
                .ends
                .iter()
                .map(|e| (e.rod, if e.end == RodEnd::Start { 0 } else { 2 }))
                .collect();
            let x = ends
                .iter()
                .map(|&(r, h)| self.geo[r].hole_pos[h])
                .sum::<DVec3>()
                / ends.len() as f64;
            let (j, sig) = self.add_joint(x, &ends, eyelet, Some(jt.vertex), None);
            for (k, &(r, h)) in ends.iter().enumerate() {
                if eyelet {
                    let a = self.angle_of(j, self.tangent(r, h));
                    let av = self.model.add_vars(&[a], VarKind::Angle);
                    let slots = &mut self.model.joints[j].slots;
                    slots.push(Slot {
                        angle: [av, 0],
                        terms: 1,
                        rod: r,
                    });
                    self.slot_at[r][h] = Some((j, slots.len() - 1));
                } else {
                    self.slot_at[r][h] = Some((j, usize::MAX));
                }
                self.sigma_at[r][h] = sig[k];
            }
            vertex[jt.vertex as usize] = VertexPlace::Joint(j);
        }
        vertex
    }

    /// Rod r's chain from its start hole to its end hole, with its energy
    /// stencils and its engraved name; returns its legs' edge counts.
    fn add_rod(&mut self, r: usize, digits: (usize, usize)) -> Vec<usize> {
        let rod = &self.cut[r];
        let holes = rod.holes();
        let arm_len = |leg: f64| {
            if leg >= 2.0 * self.mesh.arm + 1.0 {
                self.mesh.arm
            } else {
                leg / 3.0
            }
        };
        let leg_arm = [arm_len(rod.legs[0]), arm_len(rod.legs[1])];
        let mut chain = Chain {
            normal: self.normals[r],
            h_max: self.mesh.h_max,
            nodes: Vec::new(),
            s: Vec::new(),
            edges: Vec::new(),
            forced: self
                .forced
                .as_ref()
                .and_then(|f| f.get(r))
                .map(|c| c.iter().rev().copied().collect())
                .unwrap_or_default(),
            counts: Vec::new(),
        };
        let model = &mut self.model;
        for (hole, &sh) in holes.iter().enumerate() {
            let x = self.geo[r].hole_pos[hole];
            match self.slot_at[r][hole] {
                // A corner: a free end node at the hole.
                None if hole == 0 => {
                    let n = model.add_free_node(x);
                    chain.push_node(n, sh);
                }
                None => {
                    let n = Node::Free(model.add_vars(&[x.x, x.y, x.z], VarKind::Length));
                    chain.interior(model, sh, x, n);
                }
                // A ball joint: the rod's end node is the joint's.
                Some((j, usize::MAX)) => {
                    let x = model.pos_of_joint(j).unwrap_or(x);
                    if hole == 0 {
                        model.nodes.push(Node::Hole(j));
                        chain.push_node(model.nodes.len() - 1, sh);
                    } else {
                        chain.interior(model, sh, x, Node::Hole(j));
                    }
                }
                // An eyelet: rigid arms either side of the hole.
                Some((j, slot)) => {
                    let arm = Arm {
                        joint: j,
                        slot,
                        sigma: self.sigma_at[r][hole],
                        before: (hole > 0).then(|| leg_arm[hole - 1]),
                        after: (hole < 2).then(|| leg_arm[hole]),
                    };
                    chain.through_eyelet(model, sh, arm);
                }
            }
        }
        add_stencils(model, r, &chain.edges);
        // The strip's engraved id (parts::strip_id), so a maker finds it.
        let cell = &self.lattice.cells[rod.cell];
        let name = crate::parts::strip_id(cell.row, cell.col, rod.kind, digits.0, digits.1);
        model.rods.push(RodPath {
            name,
            nodes: chain.nodes,
            edges: chain.edges,
            s: chain.s,
        });
        chain.counts
    }

    /// Corner vertices, which no joint holds: the node at the single rod end.
    fn corner_vertices(&self, vertex: &mut [VertexPlace]) {
        for (r, rod) in self.cut.iter().enumerate() {
            for (hole, v) in [(0usize, rod.start), (2, rod.end)] {
                if vertex[v as usize] == VertexPlace::None {
                    let path = &self.model.rods[r];
                    let node = if hole == 0 {
                        path.nodes[0]
                    } else {
                        *path.nodes.last().expect("nodes")
                    };
                    vertex[v as usize] = VertexPlace::Node(node);
                }
            }
        }
    }
}

/// Face normal of a rod: its cell's plane as placed (z in 2-D).
fn face_normal(lattice: &Lattice, placed: &Lattice, r: &Rod) -> DVec3 {
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
}

/// An eyelet a rod passes through: its joint and slot, the rod's sign
/// against the axis, and the rigid arm's length before and after the hole
/// (none at the rod's start or end).
#[derive(Clone, Copy)]
struct Arm {
    joint: usize,
    slot: usize,
    sigma: f64,
    before: Option<f64>,
    after: Option<f64>,
}

/// One rod's chain as it is built: its nodes with their arc length s from
/// the start hole, and its edges.
struct Chain {
    normal: DVec3,
    h_max: f64,
    nodes: Vec<usize>,
    s: Vec<f64>,
    edges: Vec<usize>,
    /// Edge counts still to use, the next last (`with_counts`).
    forced: Vec<usize>,
    /// Each leg's edge count so far.
    counts: Vec<usize>,
}

impl Chain {
    /// A node at arc length `s`, with no edge to it yet.
    fn push_node(&mut self, node: usize, s: f64) {
        self.nodes.push(node);
        self.s.push(s);
    }

    /// An edge from the chain's last-but-one node to its last.
    fn push_edge(&mut self, model: &mut Model, frame: Frame, rest: f64) {
        let (a, b) = (
            self.nodes[self.nodes.len() - 2],
            self.nodes[self.nodes.len() - 1],
        );
        model.edges.push(Edge { a, b, frame, rest });
        self.edges.push(model.edges.len() - 1);
    }

    /// Interior edges of at most `h_max` from the last node to `end`, a
    /// node at arc length `sb` and position `xb`.
    fn interior(&mut self, model: &mut Model, sb: f64, xb: DVec3, end: Node) {
        let sa = *self.s.last().expect("a first node");
        let xa = model.pos(*self.nodes.last().expect("a first node"));
        let count = match self.forced.pop() {
            Some(k) => k.max(1),
            None => ((sb - sa) / self.h_max).ceil().max(1.0) as usize,
        };
        self.counts.push(count);
        let rest = (sb - sa) / count as f64;
        let n_r = self.normal;
        for k in 1..=count {
            let f = k as f64 / count as f64;
            let node = if k == count {
                model.nodes.push(end);
                model.nodes.len() - 1
            } else {
                model.add_free_node(xa.lerp(xb, f))
            };
            self.nodes.push(node);
            self.s.push(sa + rest * k as f64);
            let t = (xb - xa).normalize();
            let d2 = (n_r - t * n_r.dot(t)).normalize();
            let theta = model.add_vars(&[0.0], VarKind::Angle);
            let frame = Frame::Ref {
                ts: t,
                as_: d2.cross(t),
                theta,
            };
            self.push_edge(model, frame, rest);
        }
    }

    /// Through the eyelet at arc length `sh`: interior edges to the arm's
    /// near tip, the arm to the hole, and the arm on to its far tip.
    fn through_eyelet(&mut self, model: &mut Model, sh: f64, arm: Arm) {
        let (joint, slot) = (arm.joint, arm.slot);
        let frame = Frame::Arm {
            joint,
            slot,
            sigma: arm.sigma,
        };
        if let Some(ra) = arm.before {
            let tip = Node::Arm {
                joint,
                slot,
                r: -ra,
            };
            let xt = model.node_value(tip);
            self.interior(model, sh - ra, xt, tip);
            model.nodes.push(Node::Hole(joint));
            self.push_node(model.nodes.len() - 1, sh);
            self.push_edge(model, frame, ra);
        } else {
            model.nodes.push(Node::Hole(joint));
            self.push_node(model.nodes.len() - 1, sh);
        }
        if let Some(ra) = arm.after {
            model.nodes.push(Node::Arm { joint, slot, r: ra });
            self.push_node(model.nodes.len() - 1, sh + ra);
            self.push_edge(model, frame, ra);
        }
    }
}

/// Rod r's energy stencils: stretching of every edge but the rigid arms,
/// bending at every pair of edges in a row but two arms through one joint.
fn add_stencils(model: &mut Model, r: usize, edges: &[usize]) {
    for &e in edges {
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
}
