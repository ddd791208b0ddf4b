//! Which way strips stack at the joints, said in words a maker can follow.
//!
//! Every joint's strips go on in increasing layer order (docs/assembly.md).
//! The *stacking side* is the side the top of every stack faces: up, away
//! from the table, for a lattice built flat; the outside (away from the
//! axis, along the surface normal) for a loop or helix; for another 3-D
//! sheet, the side its mean surface normal points to, which is the side the
//! guide's pictures show. Whether a step's new row goes on top of the work
//! or under it follows from the layers and is computed per step.

use crate::assembly::Step;
use crate::lattice::{Joint, Kind, Lattice, RodType};

/// The stacking side of a lattice, in words.
#[derive(Clone, Debug, PartialEq)]
pub struct Side {
    /// Short name: "up", "the outside", "the pictured side".
    pub name: &'static str,
    /// Where each stack starts: "on the table", "innermost".
    pub first: &'static str,
    /// Where it ends: "on top", "outermost".
    pub last: &'static str,
    /// One sentence for the cover.
    pub explain: &'static str,
}

/// Whether a lattice is built flat on the table: planar, or a 3-D sheet
/// whose relief is under a tenth of its size (it is assembled flat and takes
/// its relief as it opens).
pub fn built_flat(lattice: &Lattice) -> bool {
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

pub fn side(lattice: &Lattice) -> Side {
    if built_flat(lattice) {
        Side {
            name: "up",
            first: "on the table",
            last: "on top",
            explain: "Build on a flat table. At every joint the first strip listed lies on the table and the \
                      last on top; the pictures look down on the work from above.",
        }
    } else if lattice.kind == Kind::Sheet {
        Side {
            name: "the pictured side",
            first: "farthest from you",
            last: "nearest you",
            explain: "The stacking side is the side the surface normal points to, which is the side the pictures \
                      show: keep it towards you. At every joint the first strip listed is farthest from you and \
                      the last nearest.",
        }
    } else {
        Side {
            name: "the outside",
            first: "innermost",
            last: "outermost",
            explain: "The stacking side is the outside (away from the axis, along the surface normal). At every \
                      joint the first strip listed is innermost and the last outermost: work with the outside \
                      towards you.",
        }
    }
}

/// How a step's new strips meet the work at its joints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Place {
    /// No joint of this step joins strips of earlier steps.
    First,
    /// Every new strip goes under every earlier one it joins.
    Under,
    /// Every new strip goes on top of every earlier one it joins.
    Over,
    /// Some under, some over.
    Between,
}

pub fn place(lattice: &Lattice, step: &Step) -> Place {
    let (mut under, mut over) = (false, false);
    for j in &step.joints {
        let (new, old): (Vec<&crate::lattice::JointEnd>, Vec<_>) = j
            .ends
            .iter()
            .partition(|e| lattice.step_of(e.rod / 2) + 1 == step.number);
        for n in &new {
            for o in &old {
                if n.layer < o.layer {
                    under = true;
                } else {
                    over = true;
                }
            }
        }
    }
    match (under, over) {
        (false, false) => Place::First,
        (true, false) => Place::Under,
        (false, true) => Place::Over,
        (true, true) => Place::Between,
    }
}

/// A strip's role at a joint of a step: from an earlier step or new, A or B.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Role {
    pub new: bool,
    pub kind: RodType,
}

impl Role {
    pub fn name(self, helix: bool) -> String {
        let letter = self.kind.letter();
        match (self.new, helix) {
            (true, false) => format!("this row's {letter}"),
            (false, false) => format!("the row above's {letter}"),
            (true, true) => format!("this cell's {letter}"),
            (false, true) => format!("an earlier cell's {letter}"),
        }
    }
}

fn role(lattice: &Lattice, step: &Step, e: &crate::lattice::JointEnd) -> Role {
    Role {
        new: lattice.step_of(e.rod / 2) + 1 == step.number,
        kind: e.kind,
    }
}

/// One order of roles that every joint of the step follows (each joint's
/// ends in layer order are a subsequence of it), when there is one: then
/// the step's stacking can be said once for all its joints.
pub fn common_order(lattice: &Lattice, step: &Step) -> Option<Vec<Role>> {
    let mut order: Vec<(u32, Role)> = Vec::new();
    for j in &step.joints {
        for e in &j.ends {
            let r = role(lattice, step, e);
            match order.iter().find(|o| o.1 == r) {
                Some(o) if o.0 != e.layer => return None,
                Some(_) => {}
                None => order.push((e.layer, r)),
            }
        }
    }
    order.sort_by_key(|o| o.0);
    // Two roles on one layer could not be ordered.
    if order.windows(2).any(|w| w[0].0 == w[1].0) {
        return None;
    }
    Some(order.into_iter().map(|(_, r)| r).collect())
}

/// The roles of a joint's ends, bottom to top.
pub fn roles(lattice: &Lattice, step: &Step, joint: &Joint) -> Vec<Role> {
    joint.ends.iter().map(|e| role(lattice, step, e)).collect()
}
