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
pub(crate) struct Side {
    /// Short name: "up", "the outside", "the pictured side".
    pub(crate) name: &'static str,
    /// Where each stack starts: "on the table", "innermost".
    pub(crate) first: &'static str,
    /// Where it ends: "on top", "outermost".
    pub(crate) last: &'static str,
    /// One sentence for the cover.
    pub(crate) explain: &'static str,
    /// Where a row goes that stacks after the work: "on top of the work".
    pub(crate) over: &'static str,
    /// Where a row goes that stacks before it, said so it is not missed.
    pub(crate) under: &'static str,
    /// Where a pivot's rod B lies against its rod A: "over it", "outside it".
    pub(crate) beyond: &'static str,
}

pub(crate) use crate::assembly::built_flat;

pub(crate) fn side(lattice: &Lattice) -> Side {
    if built_flat(lattice) {
        Side {
            name: "up",
            first: "on the table",
            last: "on top",
            explain: "Build on a flat table. At every joint the first strip listed lies on the table and the \
                      last on top; the pictures look down on the work from above.",
            over: "goes on top of the work",
            under: "goes UNDER the work: slide its strips under the strips already there",
            beyond: "over it",
        }
    } else if lattice.kind == Kind::Sheet {
        Side {
            name: "the pictured side",
            first: "farthest from you",
            last: "nearest you",
            explain: "The stacking side is the side the surface normal points to, which is the side the pictures \
                      show: keep it towards you. At every joint the first strip listed is farthest from you and \
                      the last nearest.",
            over: "goes on the pictured side of the work, nearest you",
            under: "goes BEHIND the work, farthest from you: slide its strips behind the strips already there",
            beyond: "nearer you than it",
        }
    } else {
        Side {
            name: "the outside",
            first: "innermost",
            last: "outermost",
            explain: "The stacking side is the outside (away from the axis, along the surface normal). At every \
                      joint the first strip listed is innermost and the last outermost: work with the outside \
                      towards you.",
            over: "goes outside the work: its strips lie outermost at the joints",
            under: "goes INSIDE the work: slide its strips inside the strips already there, nearer the axis",
            beyond: "outside it",
        }
    }
}

/// How a step's new strips meet the work at its joints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Place {
    /// No joint of this step joins strips of earlier steps.
    First,
    /// Every new strip goes under every earlier one it joins.
    Under,
    /// Every new strip goes on top of every earlier one it joins.
    Over,
    /// Some under, some over.
    Between,
}

pub(crate) fn place(lattice: &Lattice, step: &Step) -> Place {
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
pub(crate) struct Role {
    pub(crate) new: bool,
    pub(crate) kind: RodType,
}

impl Role {
    pub(crate) fn name(self, helix: bool) -> String {
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

/// The joints of a step grouped by the order of roles they stack in (each
/// joint's ends in layer order are a subsequence of its group's order), in
/// the order the groups first appear: then each group's stacking can be said
/// once for all its joints. `None` when more than `MAX_ORDERS` groups would
/// be needed (then each joint is listed with its own stack).
pub(crate) fn orders<'a>(lattice: &Lattice, step: &'a Step) -> Option<Vec<StackOrder<'a>>> {
    // Each group: (layer, role) pairs sorted by layer, and its joints.
    type Group<'j> = (Vec<(u32, Role)>, Vec<&'j Joint>);
    let mut groups: Vec<Group> = Vec::new();
    for j in &step.joints {
        match groups
            .iter_mut()
            .find_map(|g| with_joint(lattice, step, &g.0, j).map(|o| (g, o)))
        {
            Some((g, order)) => {
                g.0 = order;
                g.1.push(j);
            }
            None => {
                let order = with_joint(lattice, step, &[], j)?;
                groups.push((order, vec![j]));
            }
        }
        if groups.len() > MAX_ORDERS {
            return None;
        }
    }
    Some(
        groups
            .into_iter()
            .map(|(order, joints)| (order.into_iter().map(|(_, r)| r).collect(), joints))
            .collect(),
    )
}

/// One order of roles, bottom to top, and the joints that stack in it.
pub(crate) type StackOrder<'a> = (Vec<Role>, Vec<&'a Joint>);

/// At most this many stacking orders are said per step; beyond it the
/// joints are listed one by one.
const MAX_ORDERS: usize = 3;

/// `order` (layer, role pairs sorted by layer) extended by `joint`'s ends,
/// or `None` if the joint puts a role on another layer than `order` does or
/// two roles would share a layer.
fn with_joint(
    lattice: &Lattice,
    step: &Step,
    order: &[(u32, Role)],
    joint: &Joint,
) -> Option<Vec<(u32, Role)>> {
    let mut order = order.to_vec();
    for e in &joint.ends {
        let r = role(lattice, step, e);
        match order.iter().find(|o| o.1 == r) {
            Some(o) if o.0 != e.layer => return None,
            Some(_) => {}
            None => order.push((e.layer, r)),
        }
    }
    order.sort_by_key(|o| o.0);
    if order.windows(2).any(|w| w[0].0 == w[1].0) {
        return None;
    }
    Some(order)
}
