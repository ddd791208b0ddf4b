//! What to expect when opening the lattice, from its simulated deployment
//! path (docs/physics.md, "The deployment path", "The chosen
//! equilibrium"), and how to pop a bump into the side the design has it.

use crate::drawing::flow::{BLACK, BODY, GREY, PageFlow};
use crate::pipeline::Build;
use crate::sim::path::Path;
use crate::sim::states::{self, Change};

/// The block, for a build that followed the deployment path; nothing
/// otherwise (a planar mechanism opens without bending: the checklist
/// says so).
pub(super) fn expect(w: &mut PageFlow, b: &Build) {
    let (Some(path), Some(run)) = (&b.path, &b.simulation) else {
        return;
    };
    let popped = states::against_design(&b.lattice, &run.lm, &run.equilibrium);
    let allow = b.design.simulation.material.eps_allow;
    let mut lines = vec![opening(path, allow)];
    lines.push(snapping(path));
    lines.extend(bumps(&popped));
    w.need(40.0);
    w.y += 4.0;
    w.heading("What to expect when you open it");
    for line in &lines {
        w.paragraph(line, BODY, BLACK);
    }
    w.paragraph(
        "From the simulation of the strips (report.txt, deployment path; path.png plots it).",
        BODY,
        GREY,
    );
}

/// How opening feels: the energy it takes and the strain on the way.
fn opening(path: &Path, allow: f64) -> String {
    let deg = f64::to_degrees;
    let (Some(low), Some(top)) = (path.deploy.first(), path.deploy.last()) else {
        return format!(
            "The simulation could not follow the lattice from nearly closed ({:.0} deg) to its design opening ({:.0} deg): \
             open it slowly and stop at any joint that binds.",
            deg(path.low),
            deg(path.design)
        );
    };
    let peak = path.peak_strain().map_or(0.0, |p| p.strain);
    let feel = if top.energy.abs() <= 1e-6 && low.energy.abs() <= 1e-6 {
        "it opens freely, the strips staying straight".to_string()
    } else {
        format!(
            "the strips bend on the way, storing {} N mm at the design opening and {} N mm nearly closed",
            nmm(top.energy),
            nmm(low.energy)
        )
    };
    let strain = if peak > allow {
        format!(
            "the strips strain up to {:.2} % on the way, above the {:.2} % they are rated for: open it slowly and watch for whitening",
            100.0 * peak,
            100.0 * allow
        )
    } else {
        format!("the strips strain at most {:.2} % on the way", 100.0 * peak)
    };
    let reached = if path.failed.is_some() {
        format!(
            " The simulation followed it only to {:.0} deg of the design's {:.0}.",
            deg(top.theta),
            deg(path.design)
        )
    } else {
        String::new()
    };
    format!(
        "Open it from nearly closed ({:.0} deg) to the design opening ({:.0} deg): {feel}; {strain}.{reached}",
        deg(path.low),
        deg(path.design)
    )
}

/// Whether it snaps on the way, and whether it folds flat again.
fn snapping(path: &Path) -> String {
    let deg = f64::to_degrees;
    let snaps: Vec<String> = path
        .snaps()
        .into_iter()
        .filter(|s| s.0 == 1)
        .map(|(_, i)| format!("{:.0} deg", deg(path.deploy[i].theta)))
        .collect();
    let how = if snaps.is_empty() {
        "It opens smoothly, without snapping.".to_string()
    } else {
        format!(
            "Expect it to snap (a sudden jump of the shape) near {}.",
            snaps.join(", ")
        )
    };
    let flat = if path.folds_flat() {
        " It folds flat again when you close it."
    } else {
        ""
    };
    format!("{how}{flat}")
}

/// The bumps that stand out the other way from the design's, and how to
/// turn them.
fn bumps(popped: &[Change]) -> Option<String> {
    if popped.is_empty() {
        return None;
    }
    Some(format!(
        "Opened this way, {} stand{} out to the other side of the sheet from the design's (the vertex, by row and column, \
         with its height over its neighbours as simulated and as designed): {}. To pop one into its designed side, hold the \
         lattice at its design opening, support the strips around the vertex and press the vertex from the side it bulges \
         toward until it clicks through; it then stays there (the lattice has several stable shapes; docs/physics.md, \
         Multistability).",
        if popped.len() == 1 {
            "1 bump".to_string()
        } else {
            format!("{} bumps", popped.len())
        },
        if popped.len() == 1 { "s" } else { "" },
        designed(popped)
    ))
}

/// `[2, 4] -3.8 mm (designed +1.2 mm)`, every one listed.
fn designed(popped: &[Change]) -> String {
    popped
        .iter()
        .map(|c| format!("{} {:+.1} mm (designed {:+.1} mm)", c.vertex, c.to, c.from))
        .collect::<Vec<_>>()
        .join(", ")
}

/// An energy (N mm) to two decimals below 10, whole above.
fn nmm(e: f64) -> String {
    if e.abs() < 10.0 {
        format!("{e:.2}")
    } else {
        format!("{e:.0}")
    }
}
