//! Pinning the lattice to its base (`[simulation] supports`, docs/physics.md
//! "Supports"): which vertices to hold, the span the base must give, where
//! each goes and what it holds. Nothing for a lattice that stands free.

use crate::drawing::flow::{BLACK, BODY, GREY, PageFlow};
use crate::pipeline::Build;
use crate::sim::supports::span;

/// The block, for a build whose simulation holds supports.
pub(super) fn supports(w: &mut PageFlow, b: &Build) {
    let Some(run) = &b.simulation else { return };
    let pins = &run.equilibrium.supports;
    let Some((a, z, span)) = span(pins) else {
        return;
    };
    let name = |v: u32| b.lattice.vertex_name(v);
    let first = pins[0].at;
    let places: Vec<String> = pins
        .iter()
        .map(|p| {
            // Whole millimetres, never "-0".
            let d = ((p.at - first).round() + glam::DVec3::ZERO).to_array();
            format!(
                "{} at ({}, {}, {}) mm, {:.1} N",
                name(p.vertex),
                d[0],
                d[1],
                d[2],
                p.force.length()
            )
        })
        .collect();
    let text = format!(
        "This design keeps its shape only when its feet are held: open it to its design opening, then pin these {} vertices \
         to the table or a base, each where the design has it. The pins push and pull (some hold their foot down, others \
         keep it from spreading), so fix each both ways: a screw or a clamp through the eyelet, not a peg it rests on. \
         The farthest two, {} and {}, are {span:.0} mm apart: the base must give that span. The simulation holds them \
         there; left free, the lattice may settle into another shape (a vault's relaxes flat).",
        pins.len(),
        name(a),
        name(z),
    );
    w.need(40.0);
    w.y += 4.0;
    w.heading("Pin it to the base");
    w.paragraph(&text, BODY, BLACK);
    w.paragraph(
        &format!(
            "Each vertex, where it goes measured from {} (in the design's axes) and the force its pin holds: {}.",
            name(pins[0].vertex),
            places.join("; ")
        ),
        BODY,
        BLACK,
    );
    w.paragraph(
        "From the simulation of the strips held at these vertices (report.txt, supports).",
        BODY,
        GREY,
    );
}
