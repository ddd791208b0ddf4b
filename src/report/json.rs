//! The `--json` reports of a check and a build, as the structs they
//! serialise from. Non-finite numbers (a residual of a degenerate design
//! can be infinite) serialise as null. The keys come out sorted: the
//! reports are handed on as `serde_json::Value`, whose maps keep their keys
//! in order.

use crate::lattice::Invariant;
use crate::layout::SheetOption;
use crate::measure::ShapeJson;
use crate::pipeline::{Build, Verified};
use serde::Serialize;

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
    shape: ShapeJson<'a>,
    deployment: DeploymentJson,
}

/// One invariant of the verification (those with something to check).
#[derive(Serialize)]
struct CheckLine<'a> {
    invariant: Invariant,
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
pub fn check_json(v: &Verified) -> serde_json::Value {
    let Verified {
        design,
        lattice,
        report,
        deployment: dep,
        measures,
        ..
    } = *v;
    let checks = report
        .checks
        .iter()
        .filter(|c| c.count > 0)
        .map(|c| CheckLine {
            invariant: c.invariant,
            description: c.invariant.describe(),
            count: c.count,
            max: c.max,
            passed: c.passed(),
            site: &c.site,
        })
        .collect();
    let fit =
        measures
            .fit_distance
            .zip(measures.fit_relative)
            .map(|(max_distance_mm, relative)| FitJson {
                max_distance_mm,
                relative,
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
        shape: measures.json(lattice),
        deployment,
    })
}

/// `check_json` of a build's lattice.
pub fn build_check_json(b: &Build) -> serde_json::Value {
    check_json(&b.verified())
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
        group_by_step: b.layout.by_step,
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
