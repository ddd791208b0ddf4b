//! The checklist at the end of the guide.

use super::rect;
use crate::assembly::Step;
use crate::drawing::flow::{BLACK, BODY, GREY, MARGIN, PageFlow};
use crate::drawing::{Font, Ink, Item};
use crate::pipeline::Build;

pub(super) fn checklist(w: &mut PageFlow, b: &Build, steps: &[Step]) {
    w.need(90.0);
    w.y += 4.0;
    w.heading("Checklist");
    let pivot = b.parts.pivot_eyelets;
    let vertex = b.parts.vertex_eyelets;
    let items = [
        format!(
            "All {} strips cut, each with its engraving legible (ID, type code or dot code, as the bill of materials lists).",
            b.parts.strips.len()
        ),
        format!("{pivot} scissor-pivot eyelets set, rod A under rod B in every cell."),
        format!("{vertex} vertex eyelets set, each stack in the order its step lists."),
        "Every eyelet lets its strips turn: none is crimped tight.".to_string(),
        format!("All {} steps done; no strip left over.", steps.len()),
        "Folded flat, the holes lie on the ticks of the inspection gauge (at the end of the guide)."
            .to_string(),
        "Open the lattice slowly from one corner; stop at any joint that binds.".to_string(),
    ];
    for item in items {
        w.need(8.0);
        let y = w.y;
        w.push(vec![Item::art(
            Ink::line(BLACK, 0.3),
            rect(MARGIN, y, 4.0, 4.0),
        )]);
        w.text_at(MARGIN + 7.0, &item, BODY, Font::Regular, BLACK);
        w.y += 8.0;
    }
    w.y += 4.0;
    let note = if b.lattice.width == 1 {
        "This chain is a true mechanism: it opens and closes through every angle without bending a strip."
    } else {
        "A lattice of several rows generally reaches its deployed shape by bending its strips slightly on the way \
         (docs/verification.md, Deployment): that is expected, not a fault."
    };
    w.paragraph(note, BODY, GREY);
}
