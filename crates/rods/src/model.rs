//! The discrete model (docs/physics.md, "Strips as discrete elastic rods",
//! "Eyelets"): variables, nodes, edges with their frames, eyelet joints,
//! and the energy stencils, evaluated with plain f64 (energy) or with duals
//! (gradient and Hessian).

use crate::dual::{Dual, Relative, Scalar, V3, compose_edges};
use crate::frames::{joint_frame, material, transport, transport_c, twist, twist_with};
use glam::DVec3;
use std::ops::{Add, Sub};

/// Stiffness of the strip's cross-section (docs/physics.md, "ABS and the
/// recipe's `[simulation]` table").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Section {
    /// Flatwise bending E w t^3 / 12 (N mm^2): the centre line moves along the face normal.
    pub b_flat: f64,
    /// Edgewise bending E t w^3 / 12 (N mm^2): in the strip's own plane.
    pub b_edge: f64,
    /// Axial E w t (N).
    pub ea: f64,
    /// Torsion G J (N mm^2).
    pub gj: f64,
    pub width: f64,
    pub thickness: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VarKind {
    /// A coordinate in mm.
    Length,
    /// An angle or a tilt coordinate (radians).
    Angle,
}

/// Where a node's position comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Node {
    /// Its own three coordinates, starting at this variable.
    Free(usize),
    /// The hole at a joint: the joint's position.
    Hole(usize),
    /// The tip of a rigid arm: `X_J + r u_{J,slot}` (r < 0 before the hole).
    Arm { joint: usize, slot: usize, r: f64 },
}

/// Where an edge's material frame comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Frame {
    /// Time-parallel reference frame (stored source tangent and director)
    /// turned by the material angle `theta` (a variable).
    Ref { ts: DVec3, as_: DVec3, theta: usize },
    /// A rigid arm: t = u, d2 = sigma n_J.
    Arm {
        joint: usize,
        slot: usize,
        sigma: f64,
    },
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Edge {
    pub a: usize,
    pub b: usize,
    pub frame: Frame,
    /// Rest length (mm).
    pub rest: f64,
}

impl Edge {
    pub fn is_arm(&self) -> bool {
        matches!(self.frame, Frame::Arm { .. })
    }
}

/// A rod's place at a joint: its in-plane angle is the sum of one or two
/// variables (a pivot's second rod: alpha_A + delta).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slot {
    pub angle: [usize; 2],
    pub terms: usize,
    pub rod: usize,
}

/// An eyelet (or, without tilt, a ball joint sharing the position only).
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// First of the three position variables.
    pub x: usize,
    /// First of the two tilt variables (a, b); None for a ball joint.
    pub tilt: Option<usize>,
    /// Stored frame (ns, ps, qs), ps x qs = ns.
    pub frame: [DVec3; 3],
    pub slots: Vec<Slot>,
    /// Lattice vertex index, or None for a scissor pivot.
    pub vertex: Option<u32>,
    /// The cell whose pivot this is.
    pub cell: Option<usize>,
}

/// One strip as a chain of nodes and edges.
#[derive(Clone, Debug, PartialEq)]
pub struct RodPath {
    pub name: String,
    pub nodes: Vec<usize>,
    pub edges: Vec<usize>,
    /// Arc length of every node from the start hole (mm).
    pub s: Vec<f64>,
}

/// One term of the energy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stencil {
    /// Stretching of a non-arm edge.
    Stretch { edge: usize, rod: usize },
    /// Bending and twist at the node shared by two consecutive edges.
    Bend {
        e0: usize,
        e1: usize,
        lbar: f64,
        rod: usize,
    },
    /// A dead load on a node: -F.x.
    Load { node: usize, force: DVec3 },
    /// An end moment about y on an edge: -M atan2(t_z, t_x).
    Moment { edge: usize, m: f64 },
}

impl Stencil {
    pub fn rod(&self) -> Option<usize> {
        match *self {
            Stencil::Stretch { rod, .. } | Stencil::Bend { rod, .. } => Some(rod),
            _ => None,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub section: Section,
    pub q: Vec<f64>,
    pub kinds: Vec<VarKind>,
    pub fixed: Vec<bool>,
    pub nodes: Vec<Node>,
    pub edges: Vec<Edge>,
    pub joints: Vec<Joint>,
    pub rods: Vec<RodPath>,
    pub stencils: Vec<Stencil>,
    /// Variables tied to others (they are also marked fixed).
    pub ties: Vec<Tie>,
    /// Energy scale E_s = B_flat / mean leg (N mm).
    pub e_scale: f64,
}

/// A variable eliminated by a linear constraint: `q[var] = offset + sum
/// coef q[u]` over `terms`. The solver moves the terms and recomputes the
/// variable (exact, no penalty); used to hold the mean opening of all
/// cells (docs/physics.md, "Deployment").
#[derive(Clone, Debug, PartialEq)]
pub struct Tie {
    pub var: usize,
    pub terms: Vec<(usize, f64)>,
    pub offset: f64,
}

/// Parts of the energy (N mm).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    pub stretch: f64,
    pub bend: f64,
    pub twist: f64,
    pub external: f64,
}

impl Energies {
    pub fn total(&self) -> f64 {
        self.stretch + self.bend + self.twist + self.external
    }
}

impl Model {
    pub fn new(section: Section, e_scale: f64) -> Self {
        Model {
            section,
            q: Vec::new(),
            kinds: Vec::new(),
            fixed: Vec::new(),
            nodes: Vec::new(),
            edges: Vec::new(),
            joints: Vec::new(),
            rods: Vec::new(),
            stencils: Vec::new(),
            ties: Vec::new(),
            e_scale,
        }
    }

    /// New variables with initial values; returns the first index.
    pub fn add_vars(&mut self, values: &[f64], kind: VarKind) -> usize {
        let first = self.q.len();
        self.q.extend_from_slice(values);
        self.kinds.extend(values.iter().map(|_| kind));
        self.fixed.extend(values.iter().map(|_| false));
        first
    }

    pub fn add_free_node(&mut self, p: DVec3) -> usize {
        let v = self.add_vars(&[p.x, p.y, p.z], VarKind::Length);
        self.nodes.push(Node::Free(v));
        self.nodes.len() - 1
    }

    /// Fix a free node where it is.
    pub fn fix_node(&mut self, node: usize) {
        if let Node::Free(v) = self.nodes[node] {
            self.fixed[v..v + 3].fill(true);
        }
    }

    /// Node position now.
    pub fn pos(&self, node: usize) -> DVec3 {
        let get = |i: usize| self.q[i];
        node_pos::<f64>(self, &get, self.nodes[node]).val()
    }

    /// Tangent and material frame `(t, d1, d2)` of an edge now.
    pub fn edge_frame(&self, edge: usize) -> (DVec3, DVec3, DVec3) {
        let get = |i: usize| self.q[i];
        let e = &self.edges[edge];
        let a = node_pos::<f64>(self, &get, self.nodes[e.a]);
        let b = node_pos::<f64>(self, &get, self.nodes[e.b]);
        let t = b.sub(a).unit();
        let (d1, d2) = frame_of::<f64>(self, &get, e, t);
        (t.val(), d1.val(), d2.val())
    }

    /// Joint axis and in-plane basis now.
    pub fn joint_basis(&self, j: usize) -> (DVec3, DVec3, DVec3) {
        let get = |i: usize| self.q[i];
        let (n, p, q) = joint_basis::<f64>(self, &get, j);
        (n.val(), p.val(), q.val())
    }

    /// Variables a stencil touches, sorted and without repeats.
    pub fn stencil_vars(&self, s: &Stencil) -> Vec<usize> {
        let mut v = Vec::with_capacity(16);
        let node = |n: usize, v: &mut Vec<usize>| match self.nodes[n] {
            Node::Free(i) => v.extend([i, i + 1, i + 2]),
            Node::Hole(j) => v.extend(self.joint_vars(j, None)),
            Node::Arm { joint, slot, .. } => v.extend(self.joint_vars(joint, Some(slot))),
        };
        let frame = |e: usize, v: &mut Vec<usize>| match self.edges[e].frame {
            Frame::Ref { theta, .. } => v.push(theta),
            Frame::Arm { joint, slot, .. } => {
                let jt = &self.joints[joint];
                if let Some(t) = jt.tilt {
                    v.extend([t, t + 1]);
                }
                let sl = jt.slots[slot];
                v.extend(&sl.angle[..sl.terms]);
            }
        };
        match *s {
            Stencil::Stretch { edge, .. } | Stencil::Moment { edge, .. } => {
                node(self.edges[edge].a, &mut v);
                node(self.edges[edge].b, &mut v);
            }
            Stencil::Bend { e0, e1, .. } => {
                node(self.edges[e0].a, &mut v);
                node(self.edges[e0].b, &mut v);
                node(self.edges[e1].b, &mut v);
                frame(e0, &mut v);
                frame(e1, &mut v);
            }
            Stencil::Load { node: n, .. } => node(n, &mut v),
        }
        v.sort_unstable();
        v.dedup();
        v
    }

    fn joint_vars(&self, j: usize, slot: Option<usize>) -> Vec<usize> {
        let jt = &self.joints[j];
        let mut v = vec![jt.x, jt.x + 1, jt.x + 2];
        if let Some(slot) = slot {
            if let Some(t) = jt.tilt {
                v.extend([t, t + 1]);
            }
            let sl = jt.slots[slot];
            v.extend(&sl.angle[..sl.terms]);
        }
        v
    }

    /// Recompute every tied variable from its terms.
    pub fn apply_ties(&mut self) {
        for t in &self.ties {
            self.q[t.var] = t.offset + t.terms.iter().map(|&(u, c)| c * self.q[u]).sum::<f64>();
        }
    }

    /// Total energy at the current state (frames as stored).
    pub fn energy(&self) -> f64 {
        self.energies().total()
    }

    pub fn energies(&self) -> Energies {
        let get = |i: usize| self.q[i];
        let mut out = Energies::default();
        for s in &self.stencils {
            let e = stencil_energy::<f64>(self, &get, s);
            match s {
                Stencil::Stretch { .. } => out.stretch += e.0,
                Stencil::Bend { .. } => {
                    out.bend += e.0;
                    out.twist += e.1;
                }
                _ => out.external += e.0,
            }
        }
        out
    }

    /// One stencil's energy at the current state.
    pub fn stencil_value(&self, s: &Stencil) -> f64 {
        let get = |i: usize| self.q[i];
        let (a, b) = stencil_energy::<f64>(self, &get, s);
        a + b
    }

    /// Energy, gradient (over `vars`) and the local Hessian (row-major) of
    /// one stencil, for its variables `vars` (as `stencil_vars` lists them).
    pub fn stencil_derivatives(&self, s: &Stencil, vars: &[usize]) -> (f64, Vec<f64>, Vec<f64>) {
        let (mut g, mut h) = (Vec::new(), Vec::new());
        let e = self.stencil_derivatives_memo(s, vars, &mut g, &mut h, &mut Memo::new(), false);
        (e, g, h)
    }

    /// `stencil_derivatives` into the caller's buffers (resized to
    /// vars.len() and its square), with what the last terms of the same
    /// state computed (`Memo`): the solver's assembly reuses two buffers
    /// and the memo for all stencils, the same numbers. With `lower`, a
    /// rod term's Hessian only where row >= column (`Chain::finish`). Rod
    /// terms take the chain rule of `Chain`; a load or a moment (the
    /// analytic checks' terms) takes a dual variable per local variable.
    pub(crate) fn stencil_derivatives_memo(
        &self,
        s: &Stencil,
        vars: &[usize],
        g: &mut Vec<f64>,
        h: &mut Vec<f64>,
        memo: &mut Memo,
        lower: bool,
    ) -> f64 {
        let n = vars.len();
        g.clear();
        g.resize(n, 0.0);
        h.clear();
        h.resize(n * n, 0.0);
        match *s {
            Stencil::Bend { e0, e1, lbar, .. } => {
                bend_local(self, (e0, e1, lbar), vars, (g, h, lower), memo)
            }
            Stencil::Stretch { edge, .. } => stretch_local(self, edge, vars, (g, h, lower), memo),
            Stencil::Load { .. } | Stencil::Moment { .. } => {
                let (e, gf, hf) = self.stencil_derivatives_full(s, vars);
                g.copy_from_slice(&gf);
                h.copy_from_slice(&hf);
                e
            }
        }
    }

    /// The same derivatives with a dual variable for every local variable:
    /// the reference the rod terms' chain rule is tested against.
    pub fn stencil_derivatives_full(
        &self,
        s: &Stencil,
        vars: &[usize],
    ) -> (f64, Vec<f64>, Vec<f64>) {
        match vars.len() {
            0 => (0.0, Vec::new(), Vec::new()),
            1..=3 => self.derivatives_n::<3, 6>(s, vars),
            4..=6 => self.derivatives_n::<6, 21>(s, vars),
            7..=9 => self.derivatives_n::<9, 45>(s, vars),
            10..=11 => self.derivatives_n::<11, 66>(s, vars),
            12..=14 => self.derivatives_n::<14, 105>(s, vars),
            15..=16 => self.derivatives_n::<16, 136>(s, vars),
            17..=20 => self.derivatives_n::<20, 210>(s, vars),
            21..=MAX_LOCAL => {
                self.derivatives_n::<MAX_LOCAL, { MAX_LOCAL * (MAX_LOCAL + 1) / 2 }>(s, vars)
            }
            n => panic!("a stencil with {n} variables"),
        }
    }

    fn derivatives_n<const N: usize, const T: usize>(
        &self,
        s: &Stencil,
        vars: &[usize],
    ) -> (f64, Vec<f64>, Vec<f64>) {
        let locals: Vec<Dual<N, T>> = vars
            .iter()
            .enumerate()
            .map(|(k, &i)| Dual::var(self.q[i], k))
            .collect();
        let get = |i: usize| {
            let k = vars.iter().position(|&v| v == i).expect("stencil variable");
            locals[k]
        };
        let (e, t) = stencil_energy::<Dual<N, T>>(self, &get, s);
        let d = e + t;
        let n = vars.len();
        let g = d.g[..n].to_vec();
        let mut h = vec![0.0; n * n];
        for a in 0..n {
            for b in 0..n {
                h[a * n + b] = d.hess(a, b);
            }
        }
        (d.v, g, h)
    }

    /// After an accepted iterate: re-base every reference frame on its edge
    /// and every joint frame on its tilt (docs/physics.md, "Strips as
    /// discrete elastic rods", "Eyelets"). The energy does not change.
    pub fn update_frames(&mut self) {
        for e in 0..self.edges.len() {
            if let Frame::Ref { ts, as_, theta } = self.edges[e].frame {
                let (t, _, _) = self.edge_frame(e);
                let a1 = transport::<f64>(V3::cst(ts), V3::cst(t), V3::cst(as_)).val();
                // Keep the director exactly unit and normal to t.
                let a1 = (a1 - t * a1.dot(t)).normalize();
                self.edges[e].frame = Frame::Ref {
                    ts: t,
                    as_: a1,
                    theta,
                };
            }
        }
        for j in 0..self.joints.len() {
            if let Some(t) = self.joints[j].tilt {
                let (n, p, _) = self.joint_basis(j);
                let p = (p - n * p.dot(n)).normalize();
                self.joints[j].frame = [n, p, n.cross(p)];
                self.q[t] = 0.0;
                self.q[t + 1] = 0.0;
            }
        }
    }

    /// The stored frames, to save with q (docs/physics.md, "Rebuilds": q means nothing
    /// without them).
    pub fn frames(&self) -> (Vec<Frame>, Vec<[DVec3; 3]>) {
        (
            self.edges.iter().map(|e| e.frame).collect(),
            self.joints.iter().map(|j| j.frame).collect(),
        )
    }

    pub fn set_frames(&mut self, f: &(Vec<Frame>, Vec<[DVec3; 3]>)) {
        for (e, fr) in self.edges.iter_mut().zip(&f.0) {
            e.frame = *fr;
        }
        for (j, fr) in self.joints.iter_mut().zip(&f.1) {
            j.frame = *fr;
        }
    }

    /// Angle of a joint slot now.
    pub fn slot_angle(&self, j: usize, slot: usize) -> f64 {
        let sl = self.joints[j].slots[slot];
        sl.angle[..sl.terms].iter().map(|&i| self.q[i]).sum()
    }
}

fn joint_basis<S: Scalar>(m: &Model, get: &dyn Fn(usize) -> S, j: usize) -> (V3<S>, V3<S>, V3<S>) {
    let jt = &m.joints[j];
    let [ns, ps, qs] = jt.frame;
    match jt.tilt {
        Some(t) => joint_frame(ns, ps, qs, get(t), get(t + 1)),
        None => (V3::cst(ns), V3::cst(ps), V3::cst(qs)),
    }
}

fn slot_dir<S: Scalar>(
    m: &Model,
    get: &dyn Fn(usize) -> S,
    j: usize,
    slot: usize,
) -> (V3<S>, V3<S>) {
    let (n, p, q) = joint_basis(m, get, j);
    let sl = m.joints[j].slots[slot];
    let mut a = get(sl.angle[0]);
    if sl.terms == 2 {
        a = a + get(sl.angle[1]);
    }
    (p.scale(a.cos()).add(q.scale(a.sin())), n)
}

fn node_pos<S: Scalar>(m: &Model, get: &dyn Fn(usize) -> S, node: Node) -> V3<S> {
    node_pos_in(m, get, node, &mut Dirs::new())
}

/// A joint slot (joint, slot) with its directions (u, n).
type SlotDirs<S> = (usize, usize, V3<S>, V3<S>);

/// The directions (u, n) of the joint slots a stencil touches, each
/// computed once: a bend stencil next to a joint needs its slot for an
/// arm tip's position and again for the arm's frame (in the plain-number
/// energies and the dual reference `stencil_derivatives_full`). The same
/// arithmetic, so the same numbers.
struct Dirs<S> {
    known: [Option<SlotDirs<S>>; 4],
}

impl<S: Scalar> Dirs<S> {
    #[inline]
    fn new() -> Self {
        Dirs { known: [None; 4] }
    }

    #[inline]
    fn get(
        &mut self,
        m: &Model,
        get: &dyn Fn(usize) -> S,
        j: usize,
        slot: usize,
    ) -> (V3<S>, V3<S>) {
        for k in self.known.iter().flatten() {
            if k.0 == j && k.1 == slot {
                return (k.2, k.3);
            }
        }
        let (u, n) = slot_dir(m, get, j, slot);
        if let Some(free) = self.known.iter_mut().find(|k| k.is_none()) {
            *free = Some((j, slot, u, n));
        }
        (u, n)
    }
}

fn node_pos_in<S: Scalar>(
    m: &Model,
    get: &dyn Fn(usize) -> S,
    node: Node,
    dirs: &mut Dirs<S>,
) -> V3<S> {
    match node {
        Node::Free(i) => V3::new(get(i), get(i + 1), get(i + 2)),
        Node::Hole(j) => {
            let x = m.joints[j].x;
            V3::new(get(x), get(x + 1), get(x + 2))
        }
        Node::Arm { joint, slot, r } => {
            let x = m.joints[joint].x;
            let (u, _) = dirs.get(m, get, joint, slot);
            V3::new(get(x), get(x + 1), get(x + 2)).add(u.scalef(r))
        }
    }
}

fn frame_of<S: Scalar>(m: &Model, get: &dyn Fn(usize) -> S, e: &Edge, t: V3<S>) -> (V3<S>, V3<S>) {
    frame_of_in(m, get, e, t, &mut Dirs::new())
}

fn frame_of_in<S: Scalar>(
    m: &Model,
    get: &dyn Fn(usize) -> S,
    e: &Edge,
    t: V3<S>,
    dirs: &mut Dirs<S>,
) -> (V3<S>, V3<S>) {
    match e.frame {
        Frame::Ref { ts, as_, theta } => material(ts, as_, t, get(theta)),
        Frame::Arm { joint, slot, sigma } => {
            let (u, n) = dirs.get(m, get, joint, slot);
            let d2 = n.scalef(sigma);
            (d2.cross(u), d2)
        }
    }
}

/// A stencil's energy as (bend or stretch or external, twist).
fn stencil_energy<S: Scalar>(m: &Model, get: &dyn Fn(usize) -> S, s: &Stencil) -> (S, S) {
    let sec = &m.section;
    let zero = S::cst(0.0);
    let pos = |n: usize| node_pos(m, get, m.nodes[n]);
    match *s {
        Stencil::Stretch { edge, .. } => {
            let e = &m.edges[edge];
            let len = pos(e.b).sub(pos(e.a)).norm();
            let strain = len * (1.0 / e.rest) + -1.0;
            (strain * strain * (0.5 * sec.ea * e.rest), zero)
        }
        Stencil::Bend { e0, e1, lbar, .. } => {
            let (a, b) = (&m.edges[e0], &m.edges[e1]);
            let mut dirs = Dirs::new();
            let x0 = node_pos_in(m, get, m.nodes[a.a], &mut dirs);
            let x1 = node_pos_in(m, get, m.nodes[a.b], &mut dirs);
            let x2 = node_pos_in(m, get, m.nodes[b.b], &mut dirs);
            let t0 = x1.sub(x0).unit();
            let t1 = x2.sub(x1).unit();
            let (d10, d20) = frame_of_in(m, get, a, t0, &mut dirs);
            let (d11, d21) = frame_of_in(m, get, b, t1, &mut dirs);
            bend_energy(sec, lbar, [t0, d10, d20], [t1, d11, d21])
        }
        Stencil::Load { node, force } => (-pos(node).dot(V3::cst(force)), zero),
        Stencil::Moment { edge, m: moment } => {
            let e = &m.edges[edge];
            let t = pos(e.b).sub(pos(e.a));
            (-(t.z.atan2(t.x)) * moment, zero)
        }
    }
}

/// Bending and twist energy at a node from the frames `[t, d1, d2]` of
/// its two edges, as (bend, twist).
#[inline]
fn bend_energy<S: Scalar>(sec: &Section, lbar: f64, f0: [V3<S>; 3], f1: [V3<S>; 3]) -> (S, S) {
    let ([t0, d10, d20], [t1, d11, d21]) = (f0, f1);
    let (c, b) = (t0.dot(t1), t0.cross(t1));
    let kb = b.scale((c + 1.0).recip() * 2.0);
    // kb.(d2_0 + d2_1): one dot product instead of two.
    let k_edge = kb.dot(d20.add(d21)) * 0.5;
    let k_flat = kb.dot(d10.add(d11)) * -0.5;
    let tw = twist_with(c, b, d10, t1, d11);
    let w = 0.5 / lbar;
    (
        (k_edge * k_edge * sec.b_edge + k_flat * k_flat * sec.b_flat) * w,
        tw * tw * (sec.gj * w),
    )
}

/// The most local variables a rod term has (three nodes with a joint slot
/// each and two frames: fewer in practice).
const MAX_LOCAL: usize = 24;

/// A joint slot's directions (u, n) over its own three inputs in small
/// duals (tilt a, b and the angle; for a ball joint the angle alone), and
/// which of the term's local variables each input is: one, or two for a
/// pivot's second rod, whose angle is the sum of two variables.
#[derive(Clone, Copy)]
struct LocalSlot {
    key: (usize, usize),
    u: V3<Dual<3, 6>>,
    n: V3<Dual<3, 6>>,
    inputs: [([usize; 2], usize); 3],
}

/// An edge with a reference frame, over its own 4 variables (edge vector
/// and material angle): its frame now, and the rotation from that frame
/// in small duals.
#[derive(Clone, Copy)]
struct EdgeRotation {
    edge: usize,
    base: [DVec3; 3],
    rot: [Dual<4, 10>; 3],
}

/// What consecutive rod terms of one state share, computed by the first
/// and reused by the next: a rod lists its stretch terms, then its bend
/// terms (e_i, e_i+1) in order, so a bend's second edge is the next
/// bend's first, and a joint slot's directions serve the arm tips and arm
/// frames of several terms in a row. The same arithmetic on the same
/// inputs, so the same numbers; valid for one state (q and the stored
/// frames): the assembly makes one per Hessian.
pub(crate) struct Memo {
    edge: Option<EdgeRotation>,
    /// Slot directions (u, n) by (joint, slot), the oldest replaced.
    slots: [Option<SlotDirs<Dual<3, 6>>>; 4],
    next_slot: usize,
}

impl Memo {
    pub(crate) fn new() -> Memo {
        Memo {
            edge: None,
            slots: [None; 4],
            next_slot: 0,
        }
    }
}

/// The last step of a rod term's chain rule, in plain numbers (docs/physics.md,
/// "Solver"): up to 8 intermediates (edge vectors, material angles, slot
/// inputs) over the term's local variables. An edge vector is x_b - x_a,
/// plus r u at an arm tip, the only intermediate with a Hessian (over its
/// slot's 3 inputs); a material angle or a slot input is one variable or
/// a sum of two. So no N-variable duals are made: without making, copying
/// and zeroing them the examples' solves run 17 to 33 % fewer instructions
/// (BENCHMARKS.md, "Simulation speed, seventh round").
struct Chain<'a> {
    m: &'a Model,
    vars: &'a [usize],
    memo: &'a mut Memo,
    /// Row k: the gradient of intermediate k over the local variables.
    jac: [[f64; MAX_LOCAL]; 8],
    /// The arm tips in edge vectors: (the vector's first row, sign times
    /// r, the slot's place in `known`); by index, not copies of the slot.
    tips: [Option<(usize, f64, usize)>; 4],
    known: [Option<LocalSlot>; 4],
}

impl<'a> Chain<'a> {
    fn new(m: &'a Model, vars: &'a [usize], memo: &'a mut Memo) -> Self {
        assert!(
            vars.len() <= MAX_LOCAL,
            "a rod term with {} variables",
            vars.len()
        );
        Chain {
            m,
            vars,
            memo,
            jac: [[0.0; MAX_LOCAL]; 8],
            tips: [None; 4],
            known: [None; 4],
        }
    }

    fn loc(&self, v: usize) -> usize {
        self.vars.binary_search(&v).expect("a stencil variable")
    }

    /// A slot's directions, each computed once per term (`known`: an arm
    /// tip's position and the arm's frame share them), and across
    /// consecutive terms of one state (`Memo`).
    fn slot(&mut self, j: usize, slot: usize) -> usize {
        type D3 = Dual<3, 6>;
        if let Some(i) = self
            .known
            .iter()
            .position(|s| s.as_ref().is_some_and(|s| s.key == (j, slot)))
        {
            return i;
        }
        let m = self.m;
        let jt = &m.joints[j];
        let sl = jt.slots[slot];
        let mut angle = ([self.loc(sl.angle[0]), 0], 1);
        if sl.terms == 2 {
            angle = ([angle.0[0], self.loc(sl.angle[1])], 2);
        }
        let inputs = match jt.tilt {
            Some(t) => [([self.loc(t), 0], 1), ([self.loc(t + 1), 0], 1), angle],
            None => [angle, ([0, 0], 0), ([0, 0], 0)],
        };
        let memo = &mut *self.memo;
        let (u, n) = match memo
            .slots
            .iter()
            .flatten()
            .find(|d| (d.0, d.1) == (j, slot))
        {
            Some(&(_, _, u, n)) => (u, n),
            None => {
                let mut alpha = m.q[sl.angle[0]];
                if sl.terms == 2 {
                    alpha += m.q[sl.angle[1]];
                }
                let [ns, ps, qs] = jt.frame;
                let (u, n) = match jt.tilt {
                    Some(t) => {
                        let (n, p, q) =
                            joint_frame(ns, ps, qs, D3::var(m.q[t], 0), D3::var(m.q[t + 1], 1));
                        let a = D3::var(alpha, 2);
                        (p.scale(a.cos()).add(q.scale(a.sin())), n)
                    }
                    None => {
                        let a = D3::var(alpha, 0);
                        let u = V3::<D3>::cst(ps)
                            .scale(a.cos())
                            .add(V3::cst(qs).scale(a.sin()));
                        (u, V3::cst(ns))
                    }
                };
                memo.slots[memo.next_slot] = Some((j, slot, u, n));
                memo.next_slot = (memo.next_slot + 1) % memo.slots.len();
                (u, n)
            }
        };
        let s = LocalSlot {
            key: (j, slot),
            u,
            n,
            inputs,
        };
        let i = self
            .known
            .iter()
            .position(|k| k.is_none())
            .expect("at most 4 slots in a rod term");
        self.known[i] = Some(s);
        i
    }

    fn known(&self, i: usize) -> &LocalSlot {
        self.known[i].as_ref().expect("a known slot")
    }

    /// A node's position; its coordinates enter rows `row..row + 3` (an
    /// edge vector) with `sign` (-1 at the edge's start, +1 at its end).
    fn place(&mut self, row: usize, node: usize, sign: f64) -> DVec3 {
        let m = self.m;
        let (x, tip) = match m.nodes[node] {
            Node::Free(i) => (i, None),
            Node::Hole(j) => (m.joints[j].x, None),
            Node::Arm { joint, slot, r } => (m.joints[joint].x, Some((self.slot(joint, slot), r))),
        };
        // A position's three variables are consecutive numbers, so they
        // follow each other in the sorted `vars`.
        let l = self.loc(x);
        for c in 0..3 {
            self.jac[row + c][l + c] += sign;
        }
        let p = DVec3::new(m.q[x], m.q[x + 1], m.q[x + 2]);
        let Some((si, r)) = tip else { return p };
        let s = self.known[si].as_ref().expect("a known slot");
        for (c, uc) in [&s.u.x, &s.u.y, &s.u.z].into_iter().enumerate() {
            for (i, &(ls, count)) in s.inputs.iter().enumerate() {
                for &l in &ls[..count] {
                    self.jac[row + c][l] += sign * r * uc.g[i];
                }
            }
        }
        let at = p + s.u.val() * r;
        // An arm tip's own Hessian is added in `finish`: a term with more
        // tips than the array holds would lose one.
        let free = self.tips.iter_mut().find(|k| k.is_none());
        *free.expect("at most four arm tips a term") = Some((row, sign * r, si));
        at
    }

    /// Rows `row..row + 3` as a slot's three inputs (an arm's frame),
    /// instead of the edge vector `place` put there.
    fn inputs(&mut self, row: usize, si: usize) {
        for tip in &mut self.tips {
            if tip.is_some_and(|t| t.0 == row) {
                *tip = None;
            }
        }
        let inputs = self.known(si).inputs;
        for (i, &(ls, count)) in inputs.iter().enumerate() {
            self.jac[row + i].fill(0.0);
            for &l in &ls[..count] {
                self.jac[row + i][l] = 1.0;
            }
        }
    }

    /// g = J^T g_o and H = J^T H_o J + the arm tips' own Hessians times
    /// their rows' g_o, for `outer` over the first M intermediates. With
    /// `lower`, only the entries h[a][b] with b <= a (what the assembly of
    /// a term without fixed or tied variables reads); the others stay 0.
    fn finish<const M: usize, const TM: usize>(
        &self,
        outer: &Dual<M, TM>,
        g: &mut [f64],
        h: &mut [f64],
        lower: bool,
    ) -> f64 {
        let n = self.vars.len();
        let jac = &self.jac[..M];
        // P = H_o J by its columns: P[.][b] = sum_l H_o[.][l] J[l][b] over
        // the few nonzeros of J (a coordinate's +-1 at each end, an arm
        // tip's r du, an angle's 1), a row of H_o at a time (H_o is
        // symmetric: its row l is its column l). Each sum keeps its order
        // over l; a term left out adds a zero.
        let ho = outer.hess_matrix();
        let mut pt = [[0.0; M]; MAX_LOCAL];
        for (jl, hl) in jac.iter().zip(&ho) {
            for (ptb, &c) in pt.iter_mut().zip(&jl[..n]) {
                if c != 0.0 {
                    for (p, &f) in ptb.iter_mut().zip(hl) {
                        *p += f * c;
                    }
                }
            }
        }
        let mut p = [[0.0; MAX_LOCAL]; M];
        for (b, ptb) in pt[..n].iter().enumerate() {
            for (pk, &v) in p.iter_mut().zip(ptb) {
                pk[b] = v;
            }
        }
        for (k, jk) in jac.iter().enumerate() {
            for a in 0..n {
                let c = jk[a];
                if c != 0.0 {
                    g[a] += outer.g[k] * c;
                    let end = if lower { a + 1 } else { n };
                    for (hb, pb) in h[a * n..a * n + end].iter_mut().zip(&p[k][..end]) {
                        *hb += c * pb;
                    }
                }
            }
        }
        for &(row, sr, si) in self.tips.iter().flatten() {
            let s = self.known(si);
            for (c, uc) in [&s.u.x, &s.u.y, &s.u.z].into_iter().enumerate() {
                let f = outer.g[row + c] * sr;
                if f == 0.0 {
                    continue;
                }
                for (i, &(li, ci)) in s.inputs.iter().enumerate() {
                    for (j, &(lj, cj)) in s.inputs.iter().enumerate() {
                        let v = f * uc.hess(i, j);
                        for &a in &li[..ci] {
                            for &b in &lj[..cj] {
                                if !lower || b <= a {
                                    h[a * n + b] += v;
                                }
                            }
                        }
                    }
                }
            }
        }
        outer.v
    }
}

/// A bend stencil's energy with its gradient and Hessian over its local
/// variables `vars` (docs/physics.md, "Solver"): the energy over the two
/// edges' 6 rotation coordinates in closed form, carried to the edges' 8
/// variables (edge vector and material angle, or an arm's 3 slot inputs)
/// in small duals, and from those to the stencil's variables by `Chain`.
fn bend_local(
    m: &Model,
    (e0, e1, lbar): (usize, usize, f64),
    vars: &[usize],
    (g, h, lower): (&mut [f64], &mut [f64], bool),
    memo: &mut Memo,
) -> f64 {
    let mut chain = Chain::new(m, vars, memo);
    let (ea, eb) = (&m.edges[e0], &m.edges[e1]);
    // Consecutive edges of a rod share their middle node: edge b's vector
    // is x2 - x1 below, x1's value taken from edge a's end.
    debug_assert_eq!(ea.b, eb.a, "a bend joins consecutive edges");
    let x0 = chain.place(0, ea.a, -1.0);
    let x1 = chain.place(0, ea.b, 1.0);
    chain.place(4, eb.a, -1.0);
    let x2 = chain.place(4, eb.b, 1.0);
    // Each edge's rotation over its own 4 variables.
    let mut w = [[Dual::<4, 10>::cst(0.0); 3]; 2];
    let mut base = [[DVec3::ZERO; 3]; 2];
    for (k, e, edge, ev) in [(0, e0, ea, x1 - x0), (1, e1, eb, x2 - x1)] {
        match edge.frame {
            Frame::Ref { ts, as_, theta } => {
                let l = chain.loc(theta);
                chain.jac[4 * k + 3][l] = 1.0;
                let r = match chain.memo.edge {
                    Some(r) if r.edge == e => r,
                    _ => {
                        let r = edge_rotation(e, (ts, as_, m.q[theta]), ev);
                        chain.memo.edge = Some(r);
                        r
                    }
                };
                (base[k], w[k]) = (r.base, r.rot);
            }
            Frame::Arm { joint, slot, sigma } => {
                // t = u, d2 = sigma n, d1 = d2 x u, over the slot's inputs.
                let t = V3::<f64>::cst(ev).unit();
                let si = chain.slot(joint, slot);
                chain.inputs(4 * k, si);
                let s = chain.known(si);
                let d2 = s.n.scalef(sigma);
                let d1 = d2.cross(s.u);
                base[k] = [t.val(), d1.val(), d2.val()];
                for (wc, r) in w[k].iter_mut().zip(&rotation([s.u, d1, d2], base[k])) {
                    *wc = widen(r);
                }
            }
        }
    }
    let e8 = compose_edges(&bend_energy_rotations(&m.section, lbar, base), &w);
    chain.finish(&e8, g, h, lower)
}

/// Edge `e` with a reference frame (stored tangent and director, material
/// angle th) and edge vector `ev`: its frame now and the rotation from it
/// over (ev, th). The tangent and the transported director (a1, a2 = t x
/// a1) depend on the edge vector alone, so they are taken over its 3
/// variables, and the angle enters by `turned`: the numbers of the same
/// frame in 4-variable duals (`tests`), without the products of the
/// zeros that the angle's and the edge vector's entries of each other
/// are.
fn edge_rotation(e: usize, (ts, as_, th): (DVec3, DVec3, f64), ev: DVec3) -> EdgeRotation {
    type D3 = Dual<3, 6>;
    let t = V3::<f64>::cst(ev).unit();
    let (d1, d2) = material::<f64>(ts, as_, t, th);
    let base = [t.val(), d1.val(), d2.val()];
    let t3 = V3::new(D3::var(ev.x, 0), D3::var(ev.y, 1), D3::var(ev.z, 2)).unit();
    let a1 = transport_c(ts, t3, as_);
    let a2 = t3.cross(a1);
    // cos and sin of the angle: value, first and second derivative.
    let (s, c) = th.sin_cos();
    let (cos, sin) = ((c, -s, -c), (s, c, -s));
    let turn = |x: V3<D3>, f| V3::new(turned(&x.x, f), turned(&x.y, f), turned(&x.z, f));
    // d1 = a1 cos + a2 sin, d2 = a2 cos - a1 sin (`material`).
    let d14 = turn(a1, cos).add(turn(a2, sin));
    let d24 = turn(a2, cos).sub(turn(a1, sin));
    let t4 = V3::new(widen(&t3.x), widen(&t3.y), widen(&t3.z));
    EdgeRotation {
        edge: e,
        base,
        rot: rotation([t4, d14, d24], base),
    }
}

/// x (over the edge vector) times f(th), the material angle's cosine or
/// sine with its derivatives f1, f2, over the 4 variables: each entry the
/// one nonzero term of the 4-variable dual product x f (x's entries in
/// th and f's in the edge vector being zeros), so the same number.
#[inline]
fn turned(x: &Dual<3, 6>, (f, f1, f2): (f64, f64, f64)) -> Dual<4, 10> {
    let mut out = Dual::<4, 10>::cst(x.v * f);
    for i in 0..3 {
        out.g[i] = f * x.g[i];
        for j in i..3 {
            out.set_hess(i, j, f * x.hess(i, j));
        }
        out.set_hess(i, 3, x.g[i] * f1);
    }
    out.g[3] = x.v * f1;
    out.set_hess(3, 3, x.v * f2);
    out
}

/// An arm's rotation over its slot's 3 inputs as one over 4 variables,
/// the fourth unused.
#[inline]
fn widen(d: &Dual<3, 6>) -> Dual<4, 10> {
    Dual::embed(d, 0)
}

/// A stretch stencil's energy with its derivatives over its local
/// variables: over the edge vector in 3 small duals, then `Chain`.
fn stretch_local(
    m: &Model,
    edge: usize,
    vars: &[usize],
    (g, h, lower): (&mut [f64], &mut [f64], bool),
    memo: &mut Memo,
) -> f64 {
    type D3 = Dual<3, 6>;
    let mut chain = Chain::new(m, vars, memo);
    let e = &m.edges[edge];
    let xa = chain.place(0, e.a, -1.0);
    let ev = chain.place(0, e.b, 1.0) - xa;
    let len = V3::new(D3::var(ev.x, 0), D3::var(ev.y, 1), D3::var(ev.z, 2)).norm();
    let strain = len * (1.0 / e.rest) + -1.0;
    let energy = strain * strain * (0.5 * m.section.ea * e.rest);
    chain.finish(&energy, g, h, lower)
}

/// The derivative of a stretch stencil's gradient (over its local
/// variables `vars`) with respect to its edge's rest length r, exactly:
/// E = EA (L - r)^2 / (2 r), so d/dr dE/dq = -EA L / r^2 dL/dq
/// (docs/physics.md, "Sensitivities"). Into `g`; `h` is scratch.
pub(crate) fn stretch_rest_gradient(
    m: &Model,
    edge: usize,
    vars: &[usize],
    g: &mut Vec<f64>,
    h: &mut Vec<f64>,
) {
    type D3 = Dual<3, 6>;
    let n = vars.len();
    g.clear();
    g.resize(n, 0.0);
    h.clear();
    h.resize(n * n, 0.0);
    let mut memo = Memo::new();
    let mut chain = Chain::new(m, vars, &mut memo);
    let e = &m.edges[edge];
    let xa = chain.place(0, e.a, -1.0);
    let ev = chain.place(0, e.b, 1.0) - xa;
    let len = V3::new(D3::var(ev.x, 0), D3::var(ev.y, 1), D3::var(ev.z, 2)).norm();
    // Only the gradient of this outer function is used (its Hessian
    // lands in the scratch `h`).
    let outer = len * (-m.section.ea * len.v / (e.rest * e.rest));
    chain.finish(&outer, g, h, false);
}

/// The rotation vector w taking the frame f0 to f (to second order):
/// w = (1/2) sum_k f0_k x f_k = -(1/2) sum_k f_k x f0_k.
#[inline]
fn rotation<S: Scalar>(f: [V3<S>; 3], f0: [DVec3; 3]) -> [S; 3] {
    let w = f[0]
        .crossc(f0[0])
        .add(f[1].crossc(f0[1]))
        .add(f[2].crossc(f0[2]))
        .scalef(-0.5);
    [w.x, w.y, w.z]
}

/// The bend and twist energy over the two edges' rotation coordinates
/// (w0, w1) at 0, frames R(w) F0, in closed form: every quantity of
/// `bend_energy` is a function of the nine products M_ij = a_i . b_j of
/// the first edge's frame a = (t0, d10, d20) with the second's b = (t1,
/// d11, d21) (the frames being orthonormal and right-handed), and M's
/// value, gradient and Hessian in w are written out (`rotation_product`).
/// The same numbers as `bend_energy` over `rotated` frames to round-off
/// (`bend_energy_rotations_dual`, the reference tests/sim.rs compares it
/// with), with about a third of the 6-variable dual products.
#[inline]
pub fn bend_energy_rotations(sec: &Section, lbar: f64, [a, b]: [[DVec3; 3]; 2]) -> Dual<6, 21> {
    bend_energy_products(sec, lbar, |i, j| rotation_product(a[i], b[j])).to_dual()
}

/// The bend and twist energy from the products M_ij = `mm(i, j)` of the
/// two edges' frames (`bend_energy_rotations`).
#[inline]
fn bend_energy_products<S: Scalar>(sec: &Section, lbar: f64, mm: impl Fn(usize, usize) -> S) -> S {
    let (m00, m01, m02) = (mm(0, 0), mm(0, 1), mm(0, 2));
    let (m10, m11, m12) = (mm(1, 0), mm(1, 1), mm(1, 2));
    let m20 = mm(2, 0);
    // kb = 2 t0 x t1 / (1 + c); kb.d20 = 2 M10 / (1 + c), kb.d21 = -2 M01
    // / (1 + c), kb.d10 = -2 M20 / (1 + c), kb.d11 = 2 M02 / (1 + c).
    let inv = (m00 + 1.0).recip();
    let k_edge = (m10 - m01) * inv;
    let k_flat = (m20 - m02) * inv;
    // The twist (`twist_with`): u = the transported d10, with b.(d10 x
    // d11) = -M01 M10 and b.(d10 x d21) = -M02 M10 (Binet-Cauchy).
    let k = m20 * inv;
    let m01m10 = m01 * m10;
    let u_d11 = m00 * m11 - m01m10 - k * m02;
    let u_d21 = m00 * m12 - m02 * m10 + k * m01;
    let tw = (-u_d21).atan2(u_d11);
    let w = 0.5 / lbar;
    (k_edge * k_edge * (sec.b_edge * w) + k_flat * k_flat * (sec.b_flat * w))
        + tw * tw * (sec.gj * w)
}

/// `(R(w0) a) . (R(w1) b)` at w = 0 over (w0, w1), written out: the value
/// a.b; d/dw0 = a x b, d/dw1 = -(a x b); d2/dw0_k dw0_l = d2/dw1_k dw1_l
/// = (a_k b_l + a_l b_k) / 2 - a.b delta_kl; d2/dw0_k dw1_l = a.b
/// delta_kl - b_k a_l.
#[inline]
fn rotation_product(a: DVec3, b: DVec3) -> Relative {
    let ab = a.dot(b);
    let x = a.cross(b).to_array();
    let (a, b) = (a.to_array(), b.to_array());
    let mut d = Relative::cst(ab);
    let mut t = 0;
    for k in 0..3 {
        d.g[k] = x[k];
        for l in k..3 {
            let mut v = 0.5 * (a[k] * b[l] + a[l] * b[k]);
            if k == l {
                v -= ab;
            }
            d.h[t] = v;
            t += 1;
        }
        for l in 0..3 {
            d.c[3 * k + l] = if k == l { ab } else { 0.0 } - b[k] * a[l];
        }
    }
    d
}

/// `bend_energy_rotations` by dual products over the rotated frames: the
/// reference the closed form is tested against.
pub fn bend_energy_rotations_dual(
    sec: &Section,
    lbar: f64,
    [a, b]: [[DVec3; 3]; 2],
) -> Dual<6, 21> {
    let f0 = [0, 1, 2].map(|k| rotated(a[k], 0));
    let f1 = [0, 1, 2].map(|k| rotated(b[k], 3));
    let (eb, et) = bend_energy(sec, lbar, f0, f1);
    eb + et
}

/// `R(w) f` at w = 0 over the rotation coordinates w = (z_first, ..,
/// z_first+2) of 6 duals, written out: R f = f + w x f + (1/2) (w (w.f) -
/// f |w|^2), so the value is f, d/dw_i = e_i x f and d2/dw_i dw_j of
/// component c is (delta_ci f_j + delta_cj f_i) / 2 - f_c delta_ij: the
/// numbers the dual products of that formula give, without their
/// arithmetic (tests/sim.rs checks the stencil against direct duals).
#[inline]
fn rotated(f: DVec3, first: usize) -> V3<Dual<6, 21>> {
    let fa = f.to_array();
    let comp = |c: usize| {
        let mut d = Dual::<6, 21>::cst(fa[c]);
        // (e_i x f)_c = eps_{c i k} f_k: nonzero for i != c.
        let (i1, i2) = ((c + 1) % 3, (c + 2) % 3);
        d.g[first + i1] = fa[i2];
        d.g[first + i2] = -fa[i1];
        for i in 0..3 {
            for j in i..3 {
                let mut v = 0.0;
                if i == c {
                    v += 0.5 * fa[j];
                }
                if j == c {
                    v += 0.5 * fa[i];
                }
                if i == j {
                    v -= fa[c];
                }
                d.set_hess(first + i, first + j, v);
            }
        }
        d
    };
    V3::new(comp(0), comp(1), comp(2))
}

/// Per-node curvatures and twist of a bend stencil now:
/// (kappa_flat, kappa_edge, twist), integrated (divide by lbar).
pub fn bend_measures(m: &Model, e0: usize, e1: usize) -> (f64, f64, f64) {
    let get = |i: usize| m.q[i];
    let pos = |n: usize| node_pos::<f64>(m, &get, m.nodes[n]);
    let (a, b) = (&m.edges[e0], &m.edges[e1]);
    let (x0, x1, x2) = (pos(a.a), pos(a.b), pos(b.b));
    let t0 = x1.sub(x0).unit();
    let t1 = x2.sub(x1).unit();
    let (d10, d20) = frame_of::<f64>(m, &get, a, t0);
    let (d11, d21) = frame_of::<f64>(m, &get, b, t1);
    let kb = t0.cross(t1).scale(2.0 / (1.0 + t0.dot(t1)));
    (
        -(kb.dot(d10) + kb.dot(d11)) / 2.0,
        (kb.dot(d20) + kb.dot(d21)) / 2.0,
        twist(t0, d10, t1, d11),
    )
}

impl Model {
    /// A single straight strip through `points` (free nodes), its face
    /// normal `d2` (perpendicular to the strip), rest state as given: for
    /// the analytic checks of tests/sim.rs.
    pub fn strip(section: Section, points: &[DVec3], d2: DVec3) -> Model {
        let length: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
        let mut m = Model::new(section, section.b_flat / length);
        let nodes: Vec<usize> = points.iter().map(|&p| m.add_free_node(p)).collect();
        let mut edges = Vec::new();
        let mut s = vec![0.0];
        for w in nodes.windows(2) {
            let (a, b) = (m.pos(w[0]), m.pos(w[1]));
            let t = (b - a).normalize();
            let n = (d2 - t * d2.dot(t)).normalize();
            let theta = m.add_vars(&[0.0], VarKind::Angle);
            m.edges.push(Edge {
                a: w[0],
                b: w[1],
                frame: Frame::Ref {
                    ts: t,
                    as_: n.cross(t),
                    theta,
                },
                rest: a.distance(b),
            });
            edges.push(m.edges.len() - 1);
            s.push(s.last().copied().unwrap_or(0.0) + a.distance(b));
        }
        for &e in &edges {
            m.stencils.push(Stencil::Stretch { edge: e, rod: 0 });
        }
        for w in edges.windows(2) {
            let lbar = (m.edges[w[0]].rest + m.edges[w[1]].rest) / 2.0;
            m.stencils.push(Stencil::Bend {
                e0: w[0],
                e1: w[1],
                lbar,
                rod: 0,
            });
        }
        m.rods.push(RodPath {
            name: "strip".into(),
            nodes,
            edges,
            s,
        });
        m
    }

    /// The material-angle variable of an edge with a reference frame.
    pub fn theta_var(&self, edge: usize) -> Option<usize> {
        match self.edges[edge].frame {
            Frame::Ref { theta, .. } => Some(theta),
            Frame::Arm { .. } => None,
        }
    }
}

impl Model {
    pub fn pos_of_joint(&self, j: usize) -> Option<DVec3> {
        let x = self.joints.get(j)?.x;
        Some(DVec3::new(self.q[x], self.q[x + 1], self.q[x + 2]))
    }

    /// The variables a node's position depends on (sorted) and its
    /// Jacobian over them, `jac[k]` the derivative by `vars[k]`.
    pub fn node_jacobian(&self, node: usize) -> (Vec<usize>, Vec<DVec3>) {
        type D = Dual<7, 28>;
        let mut vars = match self.nodes[node] {
            Node::Free(i) => vec![i, i + 1, i + 2],
            Node::Hole(j) => self.joint_vars(j, None),
            Node::Arm { joint, slot, .. } => self.joint_vars(joint, Some(slot)),
        };
        vars.sort_unstable();
        vars.dedup();
        let get = |i: usize| {
            let k = vars.iter().position(|&v| v == i).unwrap_or(usize::MAX);
            if k == usize::MAX {
                D::cst(self.q[i])
            } else {
                D::var(self.q[i], k)
            }
        };
        let p = node_pos::<D>(self, &get, self.nodes[node]);
        let jac = (0..vars.len())
            .map(|k| DVec3::new(p.x.g[k], p.y.g[k], p.z.g[k]))
            .collect();
        (vars, jac)
    }

    /// Where a node of this kind would be now.
    pub fn node_value(&mut self, node: Node) -> DVec3 {
        self.nodes.push(node);
        let p = self.pos(self.nodes.len() - 1);
        self.nodes.pop();
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// The bend energy over the rotations with the products stored as
    /// `Relative` equals the same formula in `Dual<6, 21>` to the bit, on
    /// random frame pairs.
    #[test]
    fn bend_energy_relative_equals_the_six_variable_duals_to_the_bit() {
        let sec = Section {
            b_flat: 229.2,
            b_edge: 91667.0,
            ea: 11000.0,
            gj: 328.8,
            width: 10.0,
            thickness: 0.5,
        };
        let mut rng = Rng::new(13);
        let v = |rng: &mut Rng| DVec3::new(rng.normal(), rng.normal(), rng.normal());
        let frame = |t: DVec3, d: DVec3| {
            let t = t.normalize();
            let d1 = (d - t * d.dot(t)).normalize();
            [t, d1, t.cross(d1)]
        };
        for _ in 0..300 {
            let a = frame(v(&mut rng), v(&mut rng));
            let b = frame(a[0] + 0.4 * v(&mut rng), v(&mut rng));
            let lbar = 1.0 + 10.0 * rng.uniform();
            let got = bend_energy_rotations(&sec, lbar, [a, b]);
            let want =
                bend_energy_products(&sec, lbar, |i, j| rotation_product(a[i], b[j]).to_dual());
            assert_eq!(got.v.to_bits(), want.v.to_bits());
            for (x, y) in got.g.iter().zip(&want.g).chain(got.h.iter().zip(&want.h)) {
                assert_eq!(x.to_bits(), y.to_bits(), "{x} vs {y}");
            }
        }
    }

    /// `edge_rotation` equals the rotation of the edge's frame computed in
    /// 4-variable duals throughout (edge vector and angle), entry for
    /// entry (`==`: a zero may differ in sign, which no sum it enters
    /// notices), on random edges, frames and angles.
    #[test]
    fn edge_rotation_equals_the_four_variable_duals() {
        type D4 = Dual<4, 10>;
        let mut rng = Rng::new(9);
        let v = |rng: &mut Rng| DVec3::new(rng.normal(), rng.normal(), rng.normal());
        for _ in 0..300 {
            let ev = v(&mut rng) * (1.0 + 20.0 * rng.uniform());
            let ts = (ev.normalize() + 0.3 * v(&mut rng)).normalize();
            let as_ = ts.any_orthonormal_vector();
            let th = 0.5 * rng.normal();
            let got = edge_rotation(7, (ts, as_, th), ev);
            let e4 = V3::new(D4::var(ev.x, 0), D4::var(ev.y, 1), D4::var(ev.z, 2));
            let t4 = e4.unit();
            let (d14, d24) = material(ts, as_, t4, D4::var(th, 3));
            let want = rotation([t4, d14, d24], got.base);
            for (x, y) in got.rot.iter().zip(&want) {
                assert_eq!(x.v.to_bits(), y.v.to_bits());
                for (a, b) in x.g.iter().zip(&y.g).chain(x.h.iter().zip(&y.h)) {
                    assert!(a == b, "{a} vs {b}");
                }
            }
        }
    }
}
