//! The words of a step: which strips to take, the scissor pivots to pair,
//! and each joint to close with its stack in order.

use super::stacking;
use super::{NEW, bent_facets, key, mm};
use crate::assembly::Step;
use crate::drawing::flow::{BLACK, GREY};
use crate::lattice::Joint;
use crate::pipeline::Build;
use crate::words::plural;

/// A joint as the guide names it: `[row,col]`, or `[k]` on a helix.
pub(super) fn joint_key(l: &crate::lattice::Lattice, vertex: u32) -> String {
    let k = l.vertex(vertex).key;
    if l.kind == crate::lattice::Kind::Helix {
        format!("[{}]", k.col)
    } else {
        key(k)
    }
}

/// A line of a step's words: (text, bold, colour).
type Line = (String, bool, [u8; 3]);

/// The step's words: (text, bold, colour), each wrapped later.
pub(super) fn step_text(
    b: &Build,
    step: &Step,
    side: &stacking::Side,
    orders: Option<&[stacking::StackOrder]>,
    spots: &super::finding::Spots,
) -> Vec<Line> {
    let l = &b.lattice;
    let t = b.design.fabrication.material.thickness;
    let helix = l.kind == crate::lattice::Kind::Helix;
    let what = if helix { "cell" } else { "row" };
    let mut lines = vec![(
        super::finding::take_line(b, spots, &step.strips),
        true,
        BLACK,
    )];
    place_lines(b, step, side, what, &mut lines);
    lines.push((pivots_line(b, step, t, helix), false, BLACK));
    if step.joints.is_empty() {
        lines.push(("2. No joint closes in this step.".into(), false, BLACK));
    } else if let Some(orders) = orders {
        order_lines(l, orders, t, helix, &mut lines);
    } else {
        listed_joint_lines(b, step, t, &mut lines);
    }
    lines.push((
        format!(
            "Eyelets: {} now, {} of {} so far.",
            step.eyelets,
            step.total,
            b.parts.eyelets()
        ),
        true,
        NEW,
    ));
    lines
}

/// Where the step goes: the stacking side, and a bent-facets note.
fn place_lines(b: &Build, step: &Step, side: &stacking::Side, what: &str, lines: &mut Vec<Line>) {
    let l = &b.lattice;
    let place = match stacking::place(l, step) {
        stacking::Place::First => format!("This is the first {what}: lay it out as pictured."),
        stacking::Place::Over => format!("This {what} {}.", side.over),
        stacking::Place::Under => format!("This {what} {}.", side.under),
        stacking::Place::Between => format!(
            "This {what}'s strips go between strips of the work: follow each joint's order."
        ),
    };
    lines.push((
        format!(
            "Stacking side {}: first strip {}, last {}. {place}",
            side.name, side.first, side.last
        ),
        false,
        BLACK,
    ));
    if bent_facets(b) && step.number > 1 {
        lines.push((
            format!(
                "Bent facets: where this {what} joins the work its strips will bend as the lattice opens; join them straight now."
            ),
            false,
            GREY,
        ));
    }
}

/// "1. Pivots (orange): ...", with the rod types by column.
fn pivots_line(b: &Build, step: &Step, t: f64, helix: bool) -> String {
    let l = &b.lattice;
    let strips = &b.parts.strips;
    let mut pivots = format!(
        "1. Pivots (orange): rod A, then rod B {} (as drawn); {}, grip {}, loose enough to turn.",
        stacking::side(l).beyond,
        plural(step.cells.len(), "eyelet"),
        mm(2.0 * t)
    );
    if !helix {
        let pairs: Vec<String> = step
            .cells
            .iter()
            .map(|&c| {
                let code = |s: usize| b.parts.types[strips[s].part_type].code.as_str();
                format!("{}: {}+{}", l.cells[c].col, code(2 * c), code(2 * c + 1))
            })
            .collect();
        pivots.push_str(&format!(" Rod A + rod B by column: {}.", pairs.join(", ")));
    } else if let [c] = step.cells[..] {
        let code = |s: usize| b.parts.types[strips[s].part_type].code.as_str();
        pivots.push_str(&format!(
            " Rod A is type {}, rod B type {}.",
            code(2 * c),
            code(2 * c + 1)
        ));
    }
    pivots
}

/// Joint keys by grip, largest first.
fn by_grip(l: &crate::lattice::Lattice, joints: &[&Joint]) -> Vec<(usize, Vec<String>)> {
    let mut by_grip: std::collections::BTreeMap<usize, Vec<String>> = Default::default();
    for j in joints {
        by_grip
            .entry(j.ends.len())
            .or_default()
            .push(joint_key(l, j.vertex));
    }
    by_grip
        .into_iter()
        .rev()
        .collect::<Vec<(usize, Vec<String>)>>()
}

/// The joints by stacking order: one line, or one per order.
fn order_lines(
    l: &crate::lattice::Lattice,
    orders: &[stacking::StackOrder],
    t: f64,
    helix: bool,
    lines: &mut Vec<Line>,
) {
    // "4 strips, grip 4 mm: [1,0] [3,0]; 2 strips, ...".
    let grips = |joints: &[&Joint]| {
        by_grip(l, joints)
            .iter()
            .map(|(k, keys)| format!("{k} strips, grip {}: {}", mm(*k as f64 * t), keys.join(" ")))
            .collect::<Vec<String>>()
            .join("; ")
    };
    let stack = |order: &[stacking::Role]| {
        order
            .iter()
            .map(|r| r.name(helix))
            .collect::<Vec<String>>()
            .join(", then ")
    };
    if let [(order, joints)] = orders {
        lines.push((
            format!(
                "2. Joints (blue): stack {} (fewer at an edge); one eyelet each. {}.",
                stack(order),
                grips(joints)
            ),
            false,
            BLACK,
        ));
    } else {
        lines.push((
            format!(
                "2. Joints (blue), one eyelet each; {} stacking orders (fewer at an edge):",
                orders.len()
            ),
            false,
            BLACK,
        ));
        for (order, joints) in orders {
            // "[1,0] [1,2] (4 strips, grip 4 mm): stack ...".
            let keys: Vec<String> = by_grip(l, joints)
                .iter()
                .map(|(k, keys)| {
                    format!(
                        "{} ({k} strips, grip {})",
                        keys.join(" "),
                        mm(*k as f64 * t)
                    )
                })
                .collect();
            lines.push((
                format!("- {}: stack {}.", keys.join("; "), stack(order)),
                false,
                BLACK,
            ));
        }
    }
}

/// The joints with no stacking orders: each listed with its stack.
fn listed_joint_lines(b: &Build, step: &Step, t: f64, lines: &mut Vec<Line>) {
    let l = &b.lattice;
    let strips = &b.parts.strips;
    lines.push((
        "2. Joints (blue), stacked first to last as listed:".into(),
        false,
        BLACK,
    ));
    for j in &step.joints {
        let stack: Vec<&str> = j.ends.iter().map(|e| strips[e.rod].id.as_str()).collect();
        lines.push((
            format!(
                "{}  {}  (grip {})",
                joint_key(l, j.vertex),
                stack.join(" / "),
                mm(j.ends.len() as f64 * t)
            ),
            false,
            BLACK,
        ));
    }
}
