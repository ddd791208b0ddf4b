//! Human-readable summaries of a build (pure text; the CLI prints it).

use crate::build::Build;
use crate::design::Design;
use crate::lattice::deploy::Deployment;
use crate::lattice::{Joint, Lattice, Report, joints, vertex_eyelets};
use crate::layout::SheetOption;
use serde::Serialize;
use std::fmt::Write as _;

/// The verification report of `karigami check`.
pub fn check_text(
    design: &Design,
    lattice: &Lattice,
    report: &Report,
    deploy: &Deployment,
) -> String {
    let mut out = String::new();
    // An intrinsic lattice is measured as assembled (rows placed onto each other).
    let (lo, hi) = lattice.placed().extent();
    let size = hi - lo;
    let joints = joints(lattice);
    let eyelets = vertex_eyelets(&joints);
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
    if let Some(fit) = &design.fit {
        let (abs, rel) = crate::design::fit::error(fit, lattice);
        let _ = writeln!(
            out,
            "fit to the target: largest vertex distance {abs:.3e} mm ({rel:.2e} of the target's size)"
        );
    }
    out.push_str(&crate::design::measure::measure(design, lattice).text(lattice, design));
    deployment_text(&mut out, lattice, deploy);
    part_types_text(&mut out, design, lattice, &joints);
    let verdict = if report.passed() { "PASS" } else { "FAIL" };
    let _ = writeln!(
        out,
        "verification: {verdict} (tolerance {:.0e}, largest residual {:.2e})",
        report.tolerance,
        report.worst()
    );
    out
}

/// The part types (interchangeable strips) and what is engraved on the
/// strips, when the lattice is small enough to make parts for.
fn part_types_text(out: &mut String, design: &Design, lattice: &Lattice, joints: &[Joint]) {
    if lattice.cells.len() > crate::build::MAX_FABRICATED_CELLS {
        return;
    }
    let Ok(p) = crate::parts::parts(lattice, joints, &design.fabrication) else {
        return;
    };
    let _ = writeln!(out, "{}", crate::parts::types::summary(&p));
}

/// MATH.md 8.4: the intrinsic configuration, the mobility verdict and, in
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
    out.push_str(&check_text(&b.design, &b.lattice, &b.report, &b.deployment));
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
        let steps = match (fab.group_by_step, steps.first(), steps.last()) {
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

// The JSON reports, as the structs they serialise from. Non-finite
// numbers (a residual of a degenerate design can be infinite) serialise as
// null. The keys come out sorted: the reports are handed on as
// `serde_json::Value`, whose maps keep their keys in order.

/// The verification report of `karigami check --json`.
#[derive(Serialize)]
struct CheckJson<'a> {
    design: &'a str,
    kind: &'static str,
    dim: usize,
    extrinsic: bool,
    rows: usize,
    width: usize,
    cells: usize,
    vertices: usize,
    rods: usize,
    tolerance: f64,
    largest_residual: f64,
    passed: bool,
    checks: Vec<CheckLine<'a>>,
    fit: Option<FitJson>,
    shape: serde_json::Value,
    deployment: DeploymentJson,
}

/// One invariant of the verification (those with something to check).
#[derive(Serialize)]
struct CheckLine<'a> {
    invariant: String,
    description: &'static str,
    count: usize,
    max: f64,
    passed: bool,
    site: &'a Option<String>,
}

#[derive(Serialize)]
struct FitJson {
    max_distance_mm: f64,
    relative: f64,
}

#[derive(Serialize)]
struct DeploymentJson {
    theta_design_deg: f64,
    theta_max_deg: f64,
    path_residual: f64,
    design_residual: f64,
    collapse_residual: f64,
    mobility: Option<usize>,
    mechanism: bool,
    planar_misfit: Vec<Misfit>,
    verdict: String,
}

#[derive(Serialize)]
struct Misfit {
    fraction: f64,
    misfit: f64,
}

/// The verification report as JSON, for `karigami check --json`.
pub fn check_json(
    design: &Design,
    lattice: &Lattice,
    report: &Report,
    dep: &Deployment,
) -> serde_json::Value {
    let checks = report
        .checks
        .iter()
        .filter(|c| c.count > 0)
        .map(|c| CheckLine {
            invariant: format!("{:?}", c.invariant),
            description: c.invariant.describe(),
            count: c.count,
            max: c.max,
            passed: c.passed(),
            site: &c.site,
        })
        .collect();
    let fit = design.fit.as_ref().map(|f| {
        let (max_distance_mm, relative) = crate::design::fit::error(f, lattice);
        FitJson {
            max_distance_mm,
            relative,
        }
    });
    let deployment = DeploymentJson {
        theta_design_deg: dep.config.theta_design.to_degrees(),
        theta_max_deg: dep.config.theta_max.to_degrees(),
        path_residual: dep.config.path_residual,
        design_residual: dep.config.design_residual,
        collapse_residual: dep.config.collapse_residual,
        mobility: dep.mobility,
        mechanism: dep.is_mechanism(),
        planar_misfit: dep
            .misfits
            .iter()
            .map(|&(fraction, misfit)| Misfit { fraction, misfit })
            .collect(),
        verdict: dep.verdict(lattice),
    };
    value(&CheckJson {
        design: &design.name,
        kind: lattice.kind.name(),
        dim: lattice.dim,
        extrinsic: lattice.extrinsic(),
        rows: lattice.rows(),
        width: lattice.width,
        cells: report.cells,
        vertices: report.vertices,
        rods: report.rods,
        tolerance: report.tolerance,
        largest_residual: report.worst(),
        passed: report.passed(),
        checks,
        fit,
        shape: crate::design::measure::measure(design, lattice).json(lattice),
        deployment,
    })
}

/// `check_json` of a build's lattice.
pub fn build_check_json(b: &Build) -> serde_json::Value {
    check_json(&b.design, &b.lattice, &b.report, &b.deployment)
}

/// The fabrication summary of `karigami build --json`.
#[derive(Serialize)]
struct BuildJson<'a> {
    strips: usize,
    eyelets: usize,
    vertex_eyelets: usize,
    pivot_eyelets: usize,
    sheets: usize,
    sheet: SheetJson<'a>,
    sheet_lower_bounds: LowerBounds,
    utilisation: f64,
    cut_length_mm: f64,
    part_types: Vec<PartTypeJson<'a>>,
    sheet_advice: Option<SheetOptionJson<'a>>,
    sheet_options: Vec<SheetOptionJson<'a>>,
    sheet_auto: bool,
    group_by_step: bool,
    tabs_mm: f64,
    warnings: Vec<WarningJson<'a>>,
}

#[derive(Serialize)]
struct SheetJson<'a> {
    name: &'a str,
    width_mm: f64,
    height_mm: f64,
}

#[derive(Serialize)]
struct LowerBounds {
    area: usize,
    lanes: usize,
}

/// One sheet preset with the job nested on it (`sheets` null: a strip is
/// longer than the preset).
#[derive(Serialize)]
struct SheetOptionJson<'a> {
    name: &'a str,
    width_mm: f64,
    height_mm: f64,
    sheets: Option<usize>,
    utilisation: f64,
}

impl<'a> SheetOptionJson<'a> {
    fn of(o: &'a SheetOption) -> Self {
        Self {
            name: &o.name,
            width_mm: o.width,
            height_mm: o.height,
            sheets: o.sheets,
            utilisation: o.utilisation,
        }
    }
}

/// Each part type: its code, how many strips, their length and hole
/// pitches, whether it can be turned end for end, and what its strips
/// carry engraved (how many their ID, the type code, the dot code).
#[derive(Serialize)]
struct PartTypeJson<'a> {
    #[serde(rename = "type")]
    code: &'a str,
    count: usize,
    length_mm: f64,
    pitches_mm: [f64; 2],
    turnable: bool,
    engraved: Engraved,
    dots: Option<usize>,
    strips: Vec<&'a str>,
}

#[derive(Serialize)]
struct Engraved {
    id: usize,
    type_code: usize,
    dot_code: usize,
    arrow_only: usize,
}

#[derive(Serialize)]
struct WarningJson<'a> {
    strip: &'a Option<String>,
    message: &'a str,
}

/// The fabrication summary of a build as JSON.
pub fn build_json(b: &Build) -> serde_json::Value {
    let bounds = b.bounds();
    let fab = &b.design.fabrication;
    let options = b.sheet_options();
    value(&BuildJson {
        strips: b.parts.strips.len(),
        eyelets: b.parts.eyelets(),
        vertex_eyelets: b.parts.vertex_eyelets,
        pivot_eyelets: b.parts.pivot_eyelets,
        sheets: b.layout.sheets.len(),
        sheet: SheetJson {
            name: &fab.sheet.name,
            width_mm: fab.sheet.width,
            height_mm: fab.sheet.height,
        },
        sheet_lower_bounds: LowerBounds {
            area: bounds.area,
            lanes: bounds.lanes,
        },
        utilisation: b.layout.utilisation(),
        cut_length_mm: b.cut_length(),
        part_types: part_types_json(&b.parts),
        sheet_advice: b.advice.as_ref().map(SheetOptionJson::of),
        sheet_options: options.iter().map(SheetOptionJson::of).collect(),
        sheet_auto: fab.sheet_auto,
        group_by_step: fab.group_by_step,
        tabs_mm: fab.tabs,
        warnings: b
            .parts
            .warnings
            .iter()
            .map(|w| WarningJson {
                strip: &w.strip,
                message: &w.message,
            })
            .collect(),
    })
}

fn part_types_json(parts: &crate::parts::Parts) -> Vec<PartTypeJson<'_>> {
    use crate::parts::Marking;
    parts
        .types
        .iter()
        .map(|t| {
            let count = |f: &dyn Fn(&Marking) -> bool| {
                t.strips
                    .iter()
                    .filter(|&&i| f(&parts.strips[i].marking))
                    .count()
            };
            PartTypeJson {
                code: &t.code,
                count: t.strips.len(),
                length_mm: t.length,
                pitches_mm: t.legs,
                turnable: t.symmetric,
                engraved: Engraved {
                    id: count(&|m| matches!(m, Marking::Id | Marking::Compact)),
                    type_code: count(&|m| *m == Marking::Type),
                    dot_code: count(&|m| matches!(m, Marking::Dots(_))),
                    arrow_only: count(&|m| *m == Marking::Arrow),
                },
                dots: t.dots,
                strips: t
                    .strips
                    .iter()
                    .map(|&i| parts.strips[i].id.as_str())
                    .collect(),
            }
        })
        .collect()
}

/// A report as a JSON value (a report always serialises).
fn value(report: &impl Serialize) -> serde_json::Value {
    serde_json::to_value(report).expect("a report serialises")
}

/// A few lines for the terminal.
pub fn summary(b: &Build) -> String {
    summary_with(b, false)
}

/// The summary with every warning (for report.txt) or the first few.
pub fn summary_with(b: &Build, full: bool) -> String {
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
pub fn sheet_advice(b: &Build) -> Option<String> {
    let best = b.advice.as_ref()?;
    let fab = &b.design.fabrication;
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
