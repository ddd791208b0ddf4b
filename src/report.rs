//! Human-readable summaries of a build (pure text; the CLI prints it).

use crate::design::Design;
use crate::lattice::{Lattice, Report, TOLERANCE, joints};
use std::fmt::Write as _;

/// The verification report of `karigami check`.
pub fn check_text(design: &Design, lattice: &Lattice, report: &Report) -> String {
    let mut out = String::new();
    let (lo, hi) = lattice.extent();
    let size = hi - lo;
    let eyelets = joints(lattice).iter().filter(|j| j.needs_eyelet()).count();
    let _ = writeln!(out, "design: {}", design.name);
    let _ = writeln!(
        out,
        "lattice: {}, {}-D, {} rows x {} cells = {} cells, {} vertices, {} rods",
        lattice.kind.name(),
        lattice.dim,
        lattice.rows(),
        lattice.width,
        report.cells,
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
    for c in &report.checks {
        let _ = writeln!(
            out,
            "{:<48} {:>10.2e}  {:<6} {}",
            c.invariant.describe(),
            c.max,
            if c.passed() { "ok" } else { "FAIL" },
            c.site.as_deref().unwrap_or("-")
        );
    }
    let verdict = if report.passed() { "PASS" } else { "FAIL" };
    let _ = writeln!(
        out,
        "verification: {verdict} (tolerance {TOLERANCE:.0e}, largest residual {:.2e})",
        report.worst()
    );
    out
}
