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

pub(super) fn cover(
    w: &mut PageFlow,
    b: &Build,
    simulated: Option<&Lattice>,
    steps: &[Step],
    side: &stacking::Side,
) {
    let fab = &b.design.fabrication;
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
        if simulated.is_some() {
            "Shown: the simulated deployed shape, elastic strips joined by eyelets (deployed.obj)"
        } else {
            "Shown: the deployed shape as designed"
        },
        BODY,
        Font::Regular,
        GREY,
    );
    w.y += 6.0;
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
    w.y += 3.0;
    w.text("Tools", 4.5, Font::Bold, BLACK);
    for t in [
        "A laser cutter, with cut.pdf or the files in sheets/ (SVG or DXF).".to_string(),
        format!(
            "An eyelet setter for {} eyelets and a small hammer or an eyelet press.",
            fab.eyelet.name
        ),
        "A flat table, and this guide printed at 100 % (actual size): its gauges are 1:1."
            .to_string(),
    ] {
        w.text(&format!("-  {t}"), BODY, Font::Regular, BLACK);
    }
    w.y += 3.0;
    w.paragraph(
        &format!("Stacking side: {}. {}", side.name, side.explain),
        BODY,
        BLACK,
    );
    if let Some(bumps) = bumps(b, simulated) {
        w.paragraph(&bumps, BODY, BLACK);
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
    w.new_page();
}
