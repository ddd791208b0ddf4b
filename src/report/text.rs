//! The human-readable reports of a check and a build: `karigami check`'s
//! verification report, report.txt and the terminal summary.

use crate::lattice::Lattice;
use crate::lattice::deploy::Deployment;
use crate::pipeline::{Build, Verified};
use std::fmt::Write as _;

/// The verification report of `karigami check`.
pub fn check_text(v: &Verified) -> String {
    let Verified {
        design,
        lattice,
        report,
        ..
    } = *v;
    let mut out = String::new();
    // An intrinsic lattice is measured as assembled (rows placed onto each other).
    let (lo, hi) = v.measures.whole.extent;
    let size = hi - lo;
    let eyelets = v.measures.whole.vertex_eyelets;
    let _ = writeln!(out, "design: {}", design.name);
    let shape = match lattice.kind {
        crate::lattice::Kind::Helix => {
            format!("loop length {}, {} cells", lattice.width, report.cells)
        }
        _ => format!(
            "{} rows x {} cells = {} cells",
            lattice.rows(),
            lattice.width,
            report.cells
        ),
    };
    let _ = writeln!(
        out,
        "lattice: {}, {}-D, {}, {shape}, {} vertices, {} rods",
        lattice.kind.name(),
        lattice.dim,
        if lattice.extrinsic() {
            "extrinsic"
        } else {
            "intrinsic (bent facets)"
        },
        report.vertices,
        report.rods
    );
    let extent = &size.to_array()[..lattice.dim];
    let extent: Vec<String> = extent.iter().map(|x| format!("{x:.1}")).collect();
    let _ = writeln!(out, "deployed size: {} mm", extent.join(" x "));
    let _ = writeln!(
        out,
        "eyelets: {} at vertex pivots, {} at scissor pivots",
        eyelets, report.cells
    );
    let _ = writeln!(
        out,
        "checked: {} horizontal pores, {} vertical pores, {} interior vertices",
        report.horizontal_pores, report.vertical_pores, report.interior_vertices
    );
    let _ = writeln!(
        out,
        "{:<48} {:>10}  {:<6} at",
        "invariant (relative residual)", "max", ""
    );
    // Checks with nothing to check (no loop rows, say) are left out.
    for c in report.checks.iter().filter(|c| c.count > 0) {
        let _ = writeln!(
            out,
            "{:<48} {:>10.2e}  {:<6} {}",
            c.invariant.describe(),
            c.max,
            if c.passed() { "ok" } else { "FAIL" },
            c.site.as_deref().unwrap_or("-")
        );
    }
    if let (Some(abs), Some(rel)) = (v.measures.fit_distance, v.measures.fit_relative) {
        let _ = writeln!(
            out,
            "fit to the target: largest vertex distance {abs:.3e} mm ({rel:.2e} of the target's size)"
        );
    }
    out.push_str(&v.measures.text(lattice, design));
    deployment_text(&mut out, lattice, v.deployment);
    // The part types (interchangeable strips) and what is engraved on the
    // strips, when the lattice is small enough to make parts for.
    if let Some(parts) = v.parts {
        let _ = writeln!(out, "{}", crate::parts::types::summary(parts));
    }
    let verdict = if report.passed() { "PASS" } else { "FAIL" };
    let _ = writeln!(
        out,
        "verification: {verdict} (tolerance {:.0e}, largest residual {:.2e})",
        report.tolerance,
        report.worst()
    );
    out
}

/// docs/math.md 8.4: the intrinsic configuration, the mobility verdict and, in
/// the plane, the placement misfit.
fn deployment_text(out: &mut String, lattice: &Lattice, d: &Deployment) {
    let c = &d.config;
    let _ = writeln!(
        out,
        "deployment C(theta), theta = opening of {}: design {:.2} deg, valid for 0 < theta < {:.2} deg; residuals: paths {:.1e}, design {:.1e}, theta = 0 collapsed {:.1e}",
        lattice
            .cells
            .first()
            .map_or("cell 0".into(), |c| lattice.cell_name(c)),
        c.theta_design.to_degrees(),
        c.theta_max.to_degrees(),
        c.path_residual,
        c.design_residual,
        c.collapse_residual
    );
    if !d.misfits.is_empty() {
        let parts: Vec<String> = d
            .misfits
            .iter()
            .map(|(f, m)| format!("{m:.1e} at {f} theta"))
            .collect();
        let _ = writeln!(
            out,
            "planar placement misfit (largest corner miss / mean leg): {}",
            parts.join(", ")
        );
    }
    let _ = writeln!(out, "mechanism: {}", d.verdict(lattice));
}

/// report.txt: the verification report, the fabrication summary with its
/// warnings, the sheets, and the eyelets of each assembly step.
pub fn build_text(b: &Build) -> String {
    let mut out = format!("karigami {} build report\n\n", env!("CARGO_PKG_VERSION"));
    out.push_str(&check_text(&b.verified()));
    out.push('\n');
    out.push_str(&summary_with(b, true));
    let fab = &b.design.fabrication;
    let _ = writeln!(
        out,
        "\nmaterial: {} {} mm, strips {} mm wide, end margin {} mm; eyelet {} (hole {} mm, flange {} mm)",
        fab.material.name,
        fab.material.thickness,
        fab.material.width,
        fab.end_margin,
        fab.eyelet.name,
        fab.eyelet.hole,
        fab.eyelet.flange
    );
    let _ = writeln!(
        out,
        "kerf: {} mm, {}",
        fab.kerf,
        if fab.compensate_kerf {
            "compensated in the geometry"
        } else {
            "not compensated (set it in the laser software)"
        }
    );
    if let Some(path) = &b.path {
        let free = b
            .simulation
            .as_ref()
            .is_some_and(|run| !run.equilibrium.supports.is_empty());
        let walked = crate::sim::path::Walked {
            held: b.design.simulation.actuation,
            free,
        };
        out.push_str(&path.text(b.design.simulation.material.eps_allow, false, walked));
        if let Some(run) = &b.simulation {
            out.push_str(&crate::sim::states::known(
                &b.lattice,
                &run.lm,
                &run.equilibrium,
                path,
            ));
        }
    }
    for (i, sheet) in b.layout.sheets.iter().enumerate() {
        let piece = if sheet.test_piece.is_some() {
            " and the test piece"
        } else {
            ""
        };
        let mut steps: Vec<usize> = sheet
            .placements
            .iter()
            .map(|p| b.lattice.step_of(b.parts.strips[p.part].rod / 2) + 1)
            .collect();
        steps.sort_unstable();
        steps.dedup();
        let steps = match (b.layout.by_step, steps.first(), steps.last()) {
            (true, Some(a), Some(z)) if a == z => format!(", step {a}"),
            (true, Some(a), Some(z)) => format!(", steps {a} to {z}"),
            _ => String::new(),
        };
        let _ = writeln!(
            out,
            "sheet {:02}: {} strips{piece}{steps}",
            i + 1,
            sheet.placements.len()
        );
    }
    out.push_str("\nassembly steps (eyelets this step / running total):\n");
    for s in &b.steps {
        let _ = writeln!(
            out,
            "step {:>3}: row {:>3}, {:>4} strips, {:>4} / {}",
            s.number,
            s.row,
            s.strips.len(),
            s.eyelets,
            s.total
        );
    }
    out
}

/// A few lines for the terminal.
pub fn summary(b: &Build) -> String {
    summary_with(b, false)
}

/// The summary with every warning (for report.txt) or the first few.
fn summary_with(b: &Build, full: bool) -> String {
    let mut out = String::new();
    let bounds = b.bounds();
    let fab = &b.design.fabrication;
    let _ = writeln!(
        out,
        "{}: {} cells, {} strips, {} eyelets ({} at vertices, {} at pivots); verified (largest residual {:.1e})",
        b.design.name,
        b.lattice.cells.len(),
        b.parts.strips.len(),
        b.parts.eyelets(),
        b.parts.vertex_eyelets,
        b.parts.pivot_eyelets,
        b.report.worst()
    );
    let _ = writeln!(
        out,
        "sheets: {} of {} x {} mm ({}), lower bounds {} (area) and {} (lanes), utilisation {:.1}%, cut length {:.2} m",
        b.layout.sheets.len(),
        fab.sheet.width,
        fab.sheet.height,
        fab.sheet.name,
        bounds.area,
        bounds.lanes,
        100.0 * b.layout.utilisation(),
        b.cut_length() / 1000.0
    );
    if let Some(advice) = sheet_advice(b) {
        let _ = writeln!(out, "{advice}");
    }
    // The predicted shape, for `check` and report.txt alike.
    if let Some(sim) = &b.simulation {
        out.push_str(&simulation_text(sim, &b.lattice, &b.design.simulation));
        out.push_str(&supports_text(&sim.equilibrium.supports, &b.lattice));
    }
    // A terminal gets the first few warnings; report.txt has them all.
    let shown = if full { b.parts.warnings.len() } else { 5 };
    for w in b.parts.warnings.iter().take(shown) {
        let _ = writeln!(
            out,
            "warning: {}{}",
            w.strip
                .as_ref()
                .map(|s| format!("strip {s}: "))
                .unwrap_or_default(),
            w.message
        );
    }
    if b.parts.warnings.len() > shown {
        let _ = writeln!(
            out,
            "warning: ... and {} more (every warning is in report.txt)",
            b.parts.warnings.len() - shown
        );
    }
    out
}

/// One line of sheet advice: the smallest preset that holds the job and
/// its utilisation, against the sheet used.
fn sheet_advice(b: &Build) -> Option<String> {
    let fab = &b.design.fabrication;
    // The presets are laser beds: a plotter's sheet is its mat.
    if fab.plotter.is_some() {
        return None;
    }
    let best = b.advice.as_ref()?;
    let sheets = |n: usize| {
        if n == 1 {
            "1 sheet".to_string()
        } else {
            format!("{n} sheets")
        }
    };
    let n = best.sheets.expect("a preset that holds the job");
    let what = format!(
        "{} ({} x {} mm), {} at {:.1}% utilisation",
        best.name,
        best.width,
        best.height,
        sheets(n),
        100.0 * best.utilisation
    );
    Some(if fab.sheet_auto {
        format!("sheet advice: --sheet auto picked the smallest preset that holds the job: {what}")
    } else if fab.sheet.name == best.name
        && fab.sheet.width == best.width
        && fab.sheet.height == best.height
    {
        format!("sheet advice: the sheet is the smallest preset that holds the job: {what}")
    } else {
        format!(
            "sheet advice: the smallest preset that holds the job is {what} (--sheet {} or --sheet auto)",
            best.name
        )
    })
}

/// report.txt's line on the simulated deployed shape (docs/physics.md).
/// Fixed decimals: the noise of a zero-energy shape prints as 0.
fn simulation_text(
    sim: &crate::sim::Simulation,
    lattice: &Lattice,
    settings: &crate::sim::Settings,
) -> String {
    let e = &sim.equilibrium;
    let allow = settings.material.eps_allow;
    let at = if 100.0 * e.strain.eps >= 0.005 {
        format!(" ({}, strip {})", e.strain.term, e.strain.rod)
    } else {
        String::new()
    };
    // Where the shape lies farthest, unless that is round-off.
    let where_ = if e.fit.max >= 0.05 {
        format!("; largest at {}", sim.lm.point_name(lattice, e.fit.at))
    } else {
        String::new()
    };
    let verdict = if e.strain.eps > allow {
        "ABOVE it, accepted by the recipe ([simulation] accept_overstrain)"
    } else {
        "within it"
    };
    format!(
        "simulated deployed shape (deployed.obj): energy {:.3} N mm; largest strain {:.2} %{at}, allowable {:.2} %: {verdict}; {:.1} mm from the design after the best rigid fit (rms {:.1} mm{where_})\n",
        e.energy.total(),
        100.0 * e.strain.eps,
        100.0 * allow,
        e.fit.max,
        e.fit.rms,
    )
}

/// The supports (`[simulation] supports`, docs/physics.md "Supports"): the
/// vertices pinned, the span between the farthest two and the reaction
/// at each; nothing for a lattice that stands free.
fn supports_text(supports: &[crate::sim::Reaction], lattice: &Lattice) -> String {
    let Some((a, b, span)) = crate::sim::supports::span(supports) else {
        return String::new();
    };
    let reactions: Vec<String> = supports
        .iter()
        .map(|r| format!("{} {:.3}", lattice.vertex_name(r.vertex), r.force.length()))
        .collect();
    format!(
        "supports: {} vertices pinned to the base at their design positions, {span:.1} mm between the farthest two ({} and {}); reaction at each (N): {}\n",
        supports.len(),
        lattice.vertex_name(a),
        lattice.vertex_name(b),
        reactions.join(", ")
    )
}
