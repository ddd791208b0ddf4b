//! The labels of a step's picture: joint keys, the new strips' types or
//! IDs, column numbers and a loop's seam, placed off the lattice's lines.

use super::NEW;
use super::labels::{Label, Placer};
use super::step_text::joint_key;
use crate::assembly::Step;
use crate::drawing::flow::{BLACK, GREY};
use crate::drawing::picture::{Fit, VERTEX};
use crate::drawing::{Ink, Item, Shape};
use crate::pipeline::Build;
use glam::DVec2;

/// Room above and below a step picture for labels set off the lattice (mm).
pub(super) const LABEL_ROOM: f64 = 2.5;

/// What one picture of a step shows and labels: the step's cells and
/// joints in it, and the first row its seam line starts at.
pub(super) struct Shown<'a> {
    pub(super) cells: &'a [usize],
    pub(super) joints: Vec<&'a crate::lattice::Joint>,
    pub(super) first_row: u32,
    /// The vertices in the picture, sorted (None: all).
    pub(super) vertices: Option<&'a [usize]>,
}

/// The labels of a step's picture: joint keys, what is engraved on each new
/// strip (its ID where the text names strips by joint), column numbers, and a loop's seam.
pub(super) fn step_labels(
    b: &Build,
    step: &Step,
    fit: &Fit,
    placer: &mut Placer,
    named: &[usize],
    shown: &Shown,
) -> Vec<Item> {
    let l = &b.assembled;
    let strips = &b.parts.strips;
    let mut extra = Vec::new();
    // A loop's seam: the column where the ring closes, on every row shown.
    if l.kind == crate::lattice::Kind::Loop {
        let seam: Vec<DVec2> = l
            .vertices
            .iter()
            .enumerate()
            .filter(|(i, v)| {
                v.key.col == 0
                    && v.key.row >= shown.first_row
                    && v.key.row <= step.row + 1
                    && shown.vertices.is_none_or(|vs| vs.binary_search(i).is_ok())
            })
            .map(|(_, v)| fit.map(v.pos))
            .collect();
        if seam.len() >= 2 {
            extra.push(Item::art(
                Ink::line(BLACK, 0.5),
                Shape::polyline(&seam, false),
            ));
        }
    }
    for j in &shown.joints {
        placer.place(&Label {
            anchor: fit.map(l.vertex(j.vertex).pos),
            text: joint_key(&b.lattice, j.vertex),
            colour: VERTEX,
            bold: false,
            toward: DVec2::Y,
        });
    }
    // Where a strip is named: the middle of its leg next to `vertex`.
    let leg_middle = |rod: usize, start: bool| {
        let r = l.cell_rods(rod / 2)[rod % 2];
        let [a, p, e] = r.hole_pos;
        fit.map((if start { a } else { e } + p) / 2.0)
    };
    let mut labelled = std::collections::BTreeSet::new();
    for &s in named {
        if !labelled.insert(s) {
            continue;
        }
        let new = step.strips.contains(&s);
        let end = step
            .joints
            .iter()
            .flat_map(|j| &j.ends)
            .find(|e| e.rod == s)
            .map_or(crate::lattice::RodEnd::Start, |e| e.end);
        let code = &b.parts.types[strips[s].part_type].code;
        placer.place(&Label {
            anchor: leg_middle(s, end == crate::lattice::RodEnd::Start),
            text: if new {
                format!("{} ({code})", strips[s].id)
            } else {
                strips[s].id.clone()
            },
            colour: if new { NEW } else { GREY },
            bold: new,
            toward: DVec2::new(if s % 2 == 0 { -1.0 } else { 1.0 }, -0.3),
        });
    }
    for &c in shown.cells {
        for s in [2 * c, 2 * c + 1] {
            if labelled.contains(&s) {
                continue;
            }
            let m = leg_middle(s, true);
            let other = leg_middle(s ^ 1, true);
            placer.place(&Label {
                anchor: m,
                text: super::finding::picture_label(&strips[s], &b.parts.types),
                colour: NEW,
                bold: true,
                toward: m - other,
            });
        }
    }
    if l.kind != crate::lattice::Kind::Helix {
        for &c in shown.cells {
            let cell = &l.cells[c];
            let top = (fit.map(l.vertex(cell.ul).pos)
                + fit.map(l.vertex(cell.ur).pos)
                + fit.map(cell.pivot))
                / 3.0;
            placer.place(&Label {
                anchor: top,
                text: cell.col.to_string(),
                colour: GREY,
                bold: false,
                toward: DVec2::NEG_Y,
            });
        }
    }
    if l.kind == crate::lattice::Kind::Loop
        && let Some(v) = l.vertices.iter().find(|v| {
            v.key.col == 0
                && v.key.row == step.row
                && shown.cells.iter().any(|&c| l.cells[c].col == 0)
        })
    {
        placer.place(&Label {
            anchor: fit.map(v.pos),
            text: "seam".into(),
            colour: BLACK,
            bold: true,
            toward: DVec2::NEG_X,
        });
    }
    extra
}
