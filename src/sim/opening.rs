//! A built lattice model read and driven: where its vertices and pivots
//! are now, each cell's opening, the opening held (one cell's or the mean)
//! and anchored joints; joints named for messages.

use super::strips::{Hold, LatticeModel, VertexPlace};
use crate::lattice::Lattice;
use glam::DVec3;

impl LatticeModel {
    /// Every vertex, then every pivot, where the model has them now.
    pub fn points(&self) -> Vec<DVec3> {
        let m = &self.model;
        self.vertex
            .iter()
            .map(|v| match *v {
                VertexPlace::Joint(j) => m.pos_of_joint(j).expect("joint"),
                VertexPlace::Node(n) => m.pos(n),
                VertexPlace::None => DVec3::ZERO,
            })
            .chain(
                self.pivot
                    .iter()
                    .map(|&j| m.pos_of_joint(j).expect("joint")),
            )
            .collect()
    }

    /// Every strip's centre line now, by rod id: its nodes from the first
    /// hole to the last (the bent strips, for the clash search on them).
    pub(crate) fn centre_lines(&self) -> Vec<Vec<DVec3>> {
        let m = &self.model;
        m.rods
            .iter()
            .map(|path| path.nodes.iter().map(|&n| m.pos(n)).collect())
            .collect()
    }

    /// Point `i` of `points` as reports name it: a vertex, or (after the
    /// vertices) a cell's pivot.
    pub fn point_name(&self, lattice: &Lattice, i: usize) -> String {
        let nv = self.vertex.len();
        match lattice.cells.get(i.wrapping_sub(nv)) {
            Some(cell) if i >= nv => format!("the pivot of {}", lattice.cell_name(cell)),
            _ => format!("vertex {}", lattice.vertex_name(i as u32)),
        }
    }

    /// Opening angle phi of cell c now (docs/math.md 1.3).
    pub fn opening(&self, c: usize) -> f64 {
        let (v, s) = self.delta[c];
        s * self.model.q[v]
    }

    /// Prescribe the opening of cell c (its delta becomes fixed).
    pub fn set_opening(&mut self, c: usize, phi: f64) {
        if self.hold == Hold::Mean {
            // Back from the mean hold: the openings become free variables
            // again and the z variables of the mean, now unused, are fixed.
            let m = &mut self.model;
            for t in std::mem::take(&mut m.ties) {
                m.fixed[t.var] = false;
                for (u, _) in t.terms {
                    m.fixed[u] = true;
                }
            }
            self.hold = Hold::Nothing;
        }
        let (v, s) = self.delta[c];
        self.model.q[v] = s * phi;
        self.model.fixed[v] = true;
        self.hold = Hold::Cell(c);
    }

    /// Mean opening of all cells now.
    pub fn mean_opening(&self) -> f64 {
        let n = self.delta.len().max(1) as f64;
        (0..self.delta.len()).map(|c| self.opening(c)).sum::<f64>() / n
    }

    /// Prescribe the mean opening of all cells, each cell free to differ
    /// from it, and cells of one class (`share`: copies under the lattice's
    /// symmetry) opening alike. The constraint is eliminated exactly
    /// (`Model::ties`): with one new variable z_k per class k of m_k cells
    /// (z of the last class fixed at 0, a gauge), a cell of class k opens
    /// phi + (z_k - z_(k-1)) / m_k, cyclically, so the deviations sum to
    /// zero over all cells whatever the z. Each opening depends on two z
    /// only, which keeps the Hessian sparse (eliminating one cell's
    /// opening instead would couple it to every other cell).
    pub fn set_mean_opening(&mut self, phi: f64) {
        let n = self.delta.len();
        if n == 0 {
            return;
        }
        if self.hold != Hold::Mean {
            let mean = self.mean_opening();
            let classes = self.share.iter().max().map_or(0, |k| k + 1);
            let mut size = vec![0usize; classes];
            let mut dev = vec![0.0; classes];
            for (c, &k) in self.share.iter().enumerate() {
                size[k] += 1;
                dev[k] += self.opening(c) - mean;
            }
            let delta = self.delta.clone();
            let m = &mut self.model;
            m.ties.retain(|t| !delta.iter().any(|d| d.0 == t.var));
            // z_k from the openings now: partial sums of the classes'
            // deviations (a class's cells take their mean).
            let mut z = vec![0.0; classes];
            let mut acc = 0.0;
            for k in 0..classes - 1 {
                acc += dev[k];
                z[k] = acc;
            }
            let first = m.add_vars(&z, super::model::VarKind::Angle);
            m.fixed[first + classes - 1] = true;
            for (c, &(v, s)) in delta.iter().enumerate() {
                let k = self.share[c];
                let prev = first + (k + classes - 1) % classes;
                let w = s / size[k] as f64;
                m.fixed[v] = true;
                m.ties.push(super::model::Tie {
                    var: v,
                    terms: vec![(first + k, w), (prev, -w)],
                    offset: s * mean,
                });
            }
            self.hold = Hold::Mean;
        }
        let m = &mut self.model;
        for t in &mut m.ties {
            if let Some(&(_, s)) = self.delta.iter().find(|d| d.0 == t.var) {
                t.offset = s * phi;
            }
        }
        m.apply_ties();
    }

    /// The held measure now: the held cell's or the mean opening.
    pub fn held_opening(&self) -> f64 {
        match self.hold {
            Hold::Mean => self.mean_opening(),
            Hold::Cell(c) => self.opening(c),
            Hold::Nothing => self.opening(0),
        }
    }

    /// Prescribe the held measure (cell 0 when nothing is held yet).
    pub(crate) fn set_held_opening(&mut self, phi: f64) {
        match self.hold {
            Hold::Mean => self.set_mean_opening(phi),
            Hold::Cell(c) => self.set_opening(c, phi),
            Hold::Nothing => self.set_opening(0, phi),
        }
    }

    /// Remove the rigid motions: fix the position, tilt and first rod's
    /// angle of cell c's pivot (docs/physics.md, "Deployment").
    pub fn anchor(&mut self, c: usize) {
        let j = &self.model.joints[self.pivot[c]];
        let (x, t, a) = (j.x, j.tilt, j.slots[0].angle[0]);
        self.model.fixed[x..x + 3].fill(true);
        if let Some(t) = t {
            self.model.fixed[t..t + 2].fill(true);
        }
        self.model.fixed[a] = true;
    }

    /// A joint as messages name it: the vertex or the cell's pivot.
    pub fn joint_name(&self, lattice: &Lattice, j: usize) -> String {
        let jt = &self.model.joints[j];
        match (jt.vertex, jt.cell) {
            (Some(v), _) => format!("vertex {}", lattice.vertex_name(v)),
            (_, Some(c)) => format!("the pivot of {}", lattice.cell_name(&lattice.cells[c])),
            _ => format!("joint {j}"),
        }
    }
}
