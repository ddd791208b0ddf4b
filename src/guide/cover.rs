//! The cover page: what the lattice is, what it takes, and how to read
//! the guide.

use super::bumps;
use super::stacking;
use crate::assembly::Step;
use crate::drawing::Font;
use crate::drawing::flow::{BLACK, BODY, GREY, MARGIN, PageFlow};
use crate::drawing::picture::{Camera, Fit, RodStyle, lattice_picture};
use crate::lattice::Lattice;
use crate::pipeline::Build;
use crate::words::plural;
use glam::DVec2;

/// The safety note's colour: a dark red that prints legibly in grey.
const SAFETY: [u8; 3] = [150, 20, 20];

pub(super) fn cover(
    w: &mut PageFlow,
    b: &Build,
    simulated: Option<&Lattice>,
    steps: &[Step],
    side: &stacking::Side,
) {
    // A long name wraps (and is cut after three lines) rather than run
    // off the page.
    let room = w.width();
    for line in super::fit_text::lines(&b.design.name, Font::Bold, 10.0, room, 3) {
        w.text(&line, 10.0, Font::Bold, BLACK);
    }
    w.text("Scissor lattice - assembly guide", 5.0, Font::Regular, GREY);
    w.y += 4.0;
    // The shape the strips take: simulated where the build simulated it
    // (bent strips), else as designed (a true mechanism, or not simulated).
    let shown = simulated.unwrap_or(&b.assembled);
    cover_picture(w, b, shown, simulated.is_some());
    cover_facts(w, b, shown, steps, room);
    sheets_and_tools(w, b, room);
    w.y += 3.0;
    w.paragraph(
        &format!("Stacking side: {}. {}", side.name, side.explain),
        BODY,
        BLACK,
    );
    if let Some(bumps) = bumps(b, simulated) {
        w.paragraph(&bumps, BODY, BLACK);
    }
    for note in [open_gap(b), clash_warning(b)].into_iter().flatten() {
        w.paragraph(&note, BODY, BLACK);
    }
    w.paragraph(
        "Strips are picked by part type: strips of one type are the same part. A strip is engraved with its ID \
         (R03-C05-A: row 3, column 5, rod A) where it fits, else its type code or a dot code (see the bill of \
         materials). The arrow < points to the strip's upper end, the one joined to the row above. In every \
         cell rod A runs from its upper left corner to its lower right one and rod B crosses over it. Each step's \
         picture shows the work so far in grey and the new strips in red, labelled with their types, the joints \
         to close with their keys, and the columns in grey.",
        BODY,
        GREY,
    );
    // The bill of materials follows on the same page when there is room:
    // a cover that runs a few lines over leaves no near-empty page.
    w.y += 4.0;
}

/// The deployed shape, drawn across the page, and its caption.
fn cover_picture(w: &mut PageFlow, b: &Build, shown: &Lattice, simulated: bool) {
    let fab = &b.design.fabrication;
    let box_size = DVec2::new(w.width(), 120.0);
    let fit = Fit::new(
        shown,
        Camera::for_lattice(shown),
        DVec2::new(MARGIN, w.y),
        box_size,
    );
    let width = (0.6 * fit.scale() * fab.material.width).clamp(0.3, 1.6);
    w.push(lattice_picture(
        shown,
        &fit,
        |_| {
            Some(RodStyle {
                colour: [60, 60, 60],
                width,
            })
        },
        width * 0.9,
    ));
    w.y += box_size.y + 2.0;
    w.text(
        if simulated {
            "Shown: the simulated deployed shape, elastic strips joined by eyelets (deployed.obj)"
        } else {
            "Shown: the deployed shape as designed"
        },
        BODY,
        Font::Regular,
        GREY,
    );
    w.y += 6.0;
}

/// The facts: size, cells, strips, eyelets and steps.
fn cover_facts(w: &mut PageFlow, b: &Build, shown: &Lattice, steps: &[Step], room: f64) {
    let fab = &b.design.fabrication;
    let (lo, hi) = shown.extent();
    let size = hi - lo;
    let dims: Vec<String> = size.to_array()[..b.lattice.dim]
        .iter()
        .map(|x| format!("{x:.0}"))
        .collect();
    let vertex = b.parts.vertex_eyelets;
    let pivot = b.parts.pivot_eyelets;
    let helix = b.lattice.kind == crate::lattice::Kind::Helix;
    let facts = [
        format!("Deployed size: {} mm", dims.join(" x ")),
        if helix {
            format!(
                "Cells: {} on a helix, {} to a turn",
                b.lattice.cells.len(),
                b.lattice.width
            )
        } else {
            format!(
                "Cells: {} in {} rows of {}",
                b.lattice.cells.len(),
                b.lattice.rows(),
                b.lattice.width
            )
        },
        format!(
            "Strips: {} of {} {} mm, {} mm wide, cut from {} of {} x {} mm",
            b.parts.strips.len(),
            fab.material.name,
            fab.material.thickness,
            fab.material.width,
            plural(b.layout.sheets.len(), "sheet"),
            fab.sheet.width,
            fab.sheet.height
        ),
        format!(
            "Eyelets ({}): {} ({pivot} at scissor pivots, {vertex} at vertex pivots)",
            fab.eyelet.name,
            pivot + vertex
        ),
        format!(
            "Steps: {}, one for each {}, in the order the lattice was grown",
            steps.len(),
            if helix { "cell" } else { "row" }
        ),
    ];
    // A long material name wraps too.
    for f in &facts {
        for line in super::fit_text::lines(f, Font::Regular, BODY, room, 3) {
            w.text(&line, BODY, Font::Regular, BLACK);
        }
    }
}

/// Where the strips are cut, the safety note and the tools.
fn sheets_and_tools(w: &mut PageFlow, b: &Build, room: f64) {
    let fab = &b.design.fabrication;
    // Which sheets each run of steps is cut from (docs/assembly.md).
    let spots = super::finding::Spots::new(b);
    w.paragraph(
        &format!(
            "Where the strips are: {}. Each sheet has a map after the bill of materials.",
            super::finding::steps_by_sheet(b, &spots).join("; ")
        ),
        BODY,
        BLACK,
    );
    w.y += 1.0;
    // The safety note for this stock on this machine, before anything is cut.
    let name = super::fit_text::shortened(&fab.material.name, Font::Regular, BODY, 0.5 * room);
    w.paragraph(&fab.safety_note(&name), BODY, SAFETY);
    w.y += 2.0;
    w.text("Tools", 4.5, Font::Bold, BLACK);
    let machine = match &fab.plotter {
        // What to click so the labels are drawn, not cut (docs/fabrication.md).
        Some(p) => format!(
            "{}, with the SVGs in sheets/ (one a mat): {}. Put a fine pen in the pen clamp for the labels.",
            crate::fabrication::capitalised(p.plotter.describe()),
            p.plotter.draw_steps()
        ),
        None => format!(
            "A laser cutter ({}), with cut.pdf or the files in sheets/ (LightBurn .lbrn2 with its layers set, SVG or DXF).",
            fab.machine.describe()
        ),
    };
    for t in [
        machine,
        format!(
            "An eyelet setter for {} eyelets and a small hammer or an eyelet press.",
            fab.eyelet.name
        ),
        "A flat table, and this guide printed at 100 % (actual size): its gauges are 1:1."
            .to_string(),
    ] {
        for line in w.wrap(&format!("-  {t}"), BODY) {
            w.text(&line, BODY, Font::Regular, BLACK);
        }
    }
}

/// A fit that leaves part of its target open on purpose (a torus covering
/// 342 deg of its tube): named with its size, so nobody tries to close it.
fn open_gap(b: &Build) -> Option<String> {
    let covered = b.measures.coverage?.degrees?;
    let gap = 360.0 - covered;
    (gap >= 0.5).then(|| {
        format!(
            "Open on purpose: the strips cover {covered:.0} deg of the tube, so the piece has a {gap:.0} deg gap \
             between its first and last rows. Leave it open: the lattice does not close across it."
        )
    })
}

/// Strips that press on each other in the deployed shape (report.txt's
/// strip clashes), said where the maker reads before building.
fn clash_warning(b: &Build) -> Option<String> {
    let c = b.measures.clashes.first()?;
    let name = |r: usize| crate::parts::clash::rod_name(&b.lattice, r);
    Some(format!(
        "Warning: {} pairs of strips press on each other in the deployed shape (the closest, {} and {}, come \
         within {:.1} mm of each other's centre lines; report.txt lists the check). They bend around each \
         other as the piece opens: open it slowly and check those strips are not forced apart at their eyelets.",
        b.measures.clashes.len(),
        name(c.rods[0]),
        name(c.rods[1]),
        c.distance
    ))
}
