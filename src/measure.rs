//! Every shape and fit number of a grown design in one place, for
//! `check`, report.txt, `--json`, the optimiser's objectives and the
//! gallery's tests: curvature, regularity, target fit and coverage, the
//! bending of intrinsic rows, strip clashes and identical strips.

use crate::design::Design;
use crate::design::fit::{self, Coverage};
use crate::lattice::shape::{CurvatureSummary, Shape, survey};
use crate::lattice::{Kind, Lattice};
use crate::parts::clash::bent::bent_clashes;
use crate::parts::clash::{Clashes, Scratch, clashes_in};
use serde::Serialize;

/// Every shape and fit number of a grown design (see the module comment).
#[derive(Clone, Debug, PartialEq)]
pub struct Measures {
    /// Shape measures that need no target: curvature, regularity, strips.
    pub shape: Shape,
    /// Summary of the angle defects; None without interior vertices.
    pub curvature: Option<CurvatureSummary>,
    /// Largest vertex distance to the target surface (mm).
    pub fit_distance: Option<f64>,
    /// The same relative to the target's size.
    pub fit_relative: Option<f64>,
    /// Largest boundary-vertex distance to the target's boundary curve (mm).
    pub boundary_distance: Option<f64>,
    /// How much of the fit target the cells cover; None without a target or for
    /// a free revolution profile.
    pub coverage: Option<Coverage>,
    /// Same-layer strips closer than the strip width plus the clearance.
    pub clashes: Clashes,
    /// Helix: each complete turn's mean radius, mean height and largest
    /// relative departure of a vertex's radius from that mean.
    pub turns: Vec<Turn>,
    /// Distinct rows and columns holding a vertex with defect >= +3 deg.
    pub bump_rows: usize,
    /// Distinct columns holding such a vertex.
    pub bump_cols: usize,
    /// Shares of interior vertices with defect >= +3 deg and <= -3 deg.
    pub bumps: f64,
    /// Share of interior vertices with defect <= -3 deg.
    pub dimples: f64,
    /// The size and eyelets of the whole lattice, for the report's head.
    pub(crate) whole: Whole,
}

/// The size and the vertex eyelets of a lattice, for the check report's
/// head lines: two passes over every vertex and cell, measured with the
/// rest (in parallel with the shape in `pipeline::check_on`) rather than as the
/// report is written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Whole {
    /// The box of the lattice as assembled (`Lattice::extent`).
    pub(crate) extent: (glam::DVec3, glam::DVec3),
    /// Vertices holding an eyelet (`lattice::vertex_eyelet_count`).
    pub(crate) vertex_eyelets: usize,
}

/// The `Whole` of `lattice`, as assembled `assembled`.
pub(crate) fn whole(lattice: &Lattice, assembled: &Lattice) -> Whole {
    Whole {
        extent: assembled.extent(),
        vertex_eyelets: crate::lattice::vertex_eyelet_count(lattice),
    }
}

/// One complete turn of a helix, about the axis through the mean of the
/// first turn's points, along z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Turn {
    /// Mean distance of the turn's vertices from the axis (mm).
    pub radius: f64,
    /// Mean z of the turn's vertices (mm).
    pub height: f64,
    /// max |r - mean| / mean over the turn's vertices.
    pub spread: f64,
}

/// A defect of at least this (degrees) is a bump of an eggbox.
pub const BUMP_DEG: f64 = 3.0;

/// Measure a grown design: shape, curvature, target fit and coverage,
/// strip clashes, helix turns and bumps.
pub fn measure(design: &Design, lattice: &Lattice) -> Measures {
    measure_assembled(design, lattice, &lattice.placed())
}

/// `measure` with the lattice as assembled (`Lattice::placed`) at hand: the
/// pipeline places it once and measures once (`pipeline::Checked`).
pub fn measure_assembled(design: &Design, lattice: &Lattice, assembled: &Lattice) -> Measures {
    // The clash search first: its buffers are freed before the shape's
    // are taken, and the shape's curvature list (kept) is not held while
    // the search runs (one peak of memory, not their sum, on 4 M cells).
    let clashes = strip_clashes(design, assembled);
    let whole = whole(lattice, assembled);
    measure_with(design, lattice, lattice.shape(), clashes, whole)
}

/// The strip clashes of a design's lattice as assembled (an intrinsic
/// lattice meets itself as assembled: rows placed onto each other).
pub(crate) fn strip_clashes(design: &Design, assembled: &Lattice) -> Clashes {
    let fab = &design.fabrication;
    clashes_in(
        assembled,
        fab.material.width,
        fab.end_margin,
        design.clash.clearance,
        Scratch::default(),
    )
}

/// The strip clashes of a simulated deployed shape, measured on every
/// strip's bent centre line (`clash::bent`; docs/physics.md, Limits): the
/// straight search's rule on the strips as the simulation bends them.
pub(crate) fn simulated_clashes(
    design: &Design,
    lattice: &Lattice,
    lm: &crate::sim::LatticeModel,
) -> Clashes {
    let fab = &design.fabrication;
    bent_clashes(
        lattice,
        &lm.centre_lines(),
        fab.material.width,
        fab.end_margin,
        design.clash.clearance,
    )
}

/// `measure_assembled` with the shape (`Lattice::shape`), the clashes
/// (`strip_clashes`) and the `whole` given: the pipeline measures them in
/// parallel (`pipeline::check_on`).
pub(crate) fn measure_with(
    design: &Design,
    lattice: &Lattice,
    shape: Shape,
    clashes: Clashes,
    whole: Whole,
) -> Measures {
    let (curvature, (domes, saddles), (bump_rows, bump_cols)) =
        survey(lattice, &shape.curvature, BUMP_DEG);
    let (fit_distance, fit_relative, boundary_distance, coverage) = match &design.fit {
        Some(f) => {
            let (abs, rel) = fit::error(f, lattice);
            (
                Some(abs),
                Some(rel),
                fit::boundary_error(f, lattice),
                fit::coverage(f, lattice),
            )
        }
        None => (None, None, None, None),
    };
    let n = shape.curvature.len().max(1) as f64;
    let (bumps, dimples) = (domes as f64 / n, saddles as f64 / n);
    let turns = turns(lattice);
    Measures {
        clashes,
        turns,
        shape,
        curvature,
        fit_distance,
        fit_relative,
        boundary_distance,
        coverage,
        bump_rows,
        bump_cols,
        bumps,
        dimples,
        whole,
    }
}

/// A helix's vertices turn by turn (N a turn, only complete turns), about
/// the axis through the mean of the first turn's points, along z.
fn turns(lattice: &Lattice) -> Vec<Turn> {
    if lattice.kind != Kind::Helix || lattice.width == 0 {
        return Vec::new();
    }
    let n = lattice.width;
    let pts: Vec<_> = lattice.vertices.iter().map(|v| v.pos).collect();
    let centre = pts[..n].iter().copied().sum::<glam::DVec3>() / n as f64;
    pts.chunks_exact(n)
        .map(|turn| {
            let r: Vec<f64> = turn
                .iter()
                .map(|p| (*p - centre).truncate().length())
                .collect();
            let radius = r.iter().sum::<f64>() / n as f64;
            Turn {
                radius,
                height: turn.iter().map(|p| p.z).sum::<f64>() / n as f64,
                spread: r.iter().map(|x| (x - radius).abs()).fold(0.0, f64::max) / radius,
            }
        })
        .collect()
}

/// `x` to two decimals, without the minus of a value that rounds to zero
/// (a flat sheet's defects are round-off either side of 0: "-0.00" read
/// as a shape that is not there).
fn hundredths(x: f64) -> String {
    let s = format!("{x:.2}");
    if s == "-0.00" { "0.00".to_string() } else { s }
}

impl Measures {
    /// The shape section of `check` and report.txt.
    pub(crate) fn text(&self, lattice: &Lattice, design: &Design) -> String {
        use std::fmt::Write as _;
        let mut out = String::from("shape, measured from each cell's own corners:\n");
        let s = &self.shape;
        match &self.curvature {
            Some(c) => {
                let _ = writeln!(
                    out,
                    "  angle defect at {} interior vertices: min {} deg at {}, mean {} deg, max {} deg at {}",
                    c.interior,
                    hundredths(c.min_deg),
                    lattice.vertex_name(c.min_at),
                    hundredths(c.mean_deg),
                    hundredths(c.max_deg),
                    lattice.vertex_name(c.max_at)
                );
                let _ = writeln!(
                    out,
                    "  curved beyond +-{} deg: {:.0}% positive, {:.0}% negative; K mean {:.3e} /mm^2, std {:.3e}",
                    crate::lattice::shape::CURVED_DEG,
                    100.0 * c.positive,
                    100.0 * c.negative,
                    c.k_mean,
                    c.k_std
                );
            }
            None => out.push_str("  no interior vertex (none is shared by four cells)\n"),
        }
        let _ = writeln!(
            out,
            "  regularity: cell areas {:.2}x largest/smallest, legs {:.2}x (shortest {:.1} mm), leg ratio within a cell median {:.2}, largest {:.2}",
            s.area_ratio, s.leg_ratio, s.min_leg, s.cell_leg_ratio_median, s.cell_leg_ratio_max
        );
        let _ = writeln!(
            out,
            "  strip shapes: {} distinct of {} strips (leg pairs in either order, equal within {} mm; the part types below also keep each strip's start end and length)",
            s.distinct_strips,
            s.strips,
            crate::lattice::shape::SAME_STRIP_MM
        );
        if let Some(g) = &s.front_gaps {
            let _ = writeln!(
                out,
                "  rebuilt fronts miss their rows by up to {:.2} mm ({:.0}% of an edge, row {}), {:.2} mm ({:.0}%) on average: the bending the strips take",
                g.max,
                100.0 * g.max_rel,
                g.worst_row,
                g.mean,
                100.0 * g.mean_rel
            );
        }
        if self.bumps > 0.0 || self.dimples > 0.0 {
            let _ = writeln!(
                out,
                "  bumps (defect >= +{BUMP_DEG} deg): {:.0}% over {} rows and {} columns; dimples (<= -{BUMP_DEG} deg): {:.0}%",
                100.0 * self.bumps,
                self.bump_rows,
                self.bump_cols,
                100.0 * self.dimples
            );
        }
        if let Some(d) = self.boundary_distance {
            let _ = writeln!(out, "  boundary vertices on the target's rim to {d:.2e} mm");
        }
        if let Some(c) = &self.coverage {
            match c.degrees {
                Some(deg) => {
                    let _ = writeln!(
                        out,
                        "  coverage: {deg:.1} deg of {} ({:.1}%)",
                        c.of,
                        100.0 * c.share
                    );
                }
                None => {
                    let _ = writeln!(out, "  coverage: {:.1}% of {}", 100.0 * c.share, c.of);
                }
            }
        }
        for (k, t) in self.turns.iter().enumerate() {
            let _ = writeln!(
                out,
                "  turn {k}: mean radius {:.1} mm, mean height {:.1} mm, radii within {:.0}% of the mean",
                t.radius,
                t.height,
                100.0 * t.spread
            );
        }
        let fab = &design.fabrication;
        match self.clashes.first() {
            None => {
                let _ = writeln!(
                    out,
                    "  strip clashes: none (same-layer strips at least {} mm + {} mm clearance apart)",
                    fab.material.width, design.clash.clearance
                );
            }
            Some(c) => {
                let _ = writeln!(
                    out,
                    "  strip clashes: {} pairs{}; closest {} and {}, {:.2} mm apart at ({:.1}, {:.1}, {:.1})",
                    self.clashes.len(),
                    if design.clash.allow {
                        " (allowed by [clash])"
                    } else {
                        ""
                    },
                    crate::parts::clash::rod_name(lattice, c.rods[0]),
                    crate::parts::clash::rod_name(lattice, c.rods[1]),
                    c.distance,
                    c.at.x,
                    c.at.y,
                    c.at.z
                );
            }
        }
        out
    }

    /// The same numbers for `--json` (`ShapeJson`).
    pub(crate) fn json<'a>(&'a self, lattice: &'a Lattice) -> ShapeJson<'a> {
        use crate::parts::clash::rod_name;
        let s = &self.shape;
        ShapeJson {
            curvature: self.curvature.map(|c| CurvatureJson {
                interior_vertices: c.interior,
                defect_min_deg: c.min_deg,
                defect_min_at: lattice.vertex_name(c.min_at),
                defect_mean_deg: c.mean_deg,
                defect_max_deg: c.max_deg,
                defect_max_at: lattice.vertex_name(c.max_at),
                threshold_deg: crate::lattice::shape::CURVED_DEG,
                positive_share: c.positive,
                negative_share: c.negative,
                k_mean: c.k_mean,
                k_std: c.k_std,
                bump_deg: BUMP_DEG,
                bumps_share: self.bumps,
                dimples_share: self.dimples,
                bump_rows: self.bump_rows,
                bump_cols: self.bump_cols,
            }),
            area_ratio: s.area_ratio,
            leg_ratio: s.leg_ratio,
            shortest_leg_mm: s.min_leg,
            cell_leg_ratio_median: s.cell_leg_ratio_median,
            cell_leg_ratio_max: s.cell_leg_ratio_max,
            distinct_strips: s.distinct_strips,
            strips: s.strips,
            front_gaps: s.front_gaps.map(|g| FrontGapsJson {
                max_mm: g.max,
                mean_mm: g.mean,
                max_relative: g.max_rel,
                mean_relative: g.mean_rel,
                worst_row: g.worst_row,
            }),
            fit_distance_mm: self.fit_distance,
            boundary_distance_mm: self.boundary_distance,
            coverage: self.coverage.map(|c| CoverageJson {
                share: c.share,
                of: c.of,
                degrees: c.degrees,
            }),
            turns: self
                .turns
                .iter()
                .map(|t| TurnJson {
                    radius_mm: t.radius,
                    height_mm: t.height,
                    spread: t.spread,
                })
                .collect(),
            clashes: self
                .clashes
                .iter()
                .take(100)
                .map(|c| ClashJson {
                    strips: [rod_name(lattice, c.rods[0]), rod_name(lattice, c.rods[1])],
                    distance_mm: c.distance,
                    at: c.at.to_array(),
                })
                .collect(),
            clash_count: self.clashes.len(),
        }
    }

    /// The clash refusal of `build` and `check`, unless the recipe allows them.
    pub(crate) fn clash_error(
        &self,
        lattice: &Lattice,
        design: &Design,
    ) -> Option<crate::diagnostic::Diagnostic> {
        let c = self.clashes.first()?;
        if design.clash.allow {
            return None;
        }
        let fab = &design.fabrication;
        let (a, b) = (
            crate::parts::clash::rod_name(lattice, c.rods[0]),
            crate::parts::clash::rod_name(lattice, c.rods[1]),
        );
        Some(
            crate::diagnostic::Diagnostic::new(
                crate::diagnostic::ErrorKind::StripClash,
                format!(
                    "strips {a} and {b} lie in the same stacking layer and their centre lines come {:.2} mm apart at ({:.1}, {:.1}, {:.1}), closer than the strip width {} mm plus {} mm clearance: they overlap ({} clashing pairs in all)",
                    c.distance, c.at.x, c.at.y, c.at.z, fab.material.width, design.clash.clearance, self.clashes.len()
                ),
            )
            .at_opt(design.clash.span.clone().or(Some(design.size_span())))
            .site(format!("strips {a} and {b}"))
            .hint("open the cells there (other leg angles or fewer rows), use narrower strips, or accept the overlap with [clash] allow = true"),
        )
    }
}

/// The "shape" section of `check --json`: `Measures` with its vertices and
/// strips named. Non-finite numbers serialise as null (serde_json's rule).
#[derive(Serialize)]
pub(crate) struct ShapeJson<'a> {
    curvature: Option<CurvatureJson>,
    area_ratio: f64,
    leg_ratio: f64,
    shortest_leg_mm: f64,
    cell_leg_ratio_median: f64,
    cell_leg_ratio_max: f64,
    distinct_strips: usize,
    strips: usize,
    front_gaps: Option<FrontGapsJson>,
    fit_distance_mm: Option<f64>,
    boundary_distance_mm: Option<f64>,
    coverage: Option<CoverageJson<'a>>,
    turns: Vec<TurnJson>,
    /// The first hundred clashing pairs; `clash_count` counts them all.
    clashes: Vec<ClashJson>,
    clash_count: usize,
}

#[derive(Serialize)]
struct CurvatureJson {
    interior_vertices: usize,
    defect_min_deg: f64,
    defect_min_at: String,
    defect_mean_deg: f64,
    defect_max_deg: f64,
    defect_max_at: String,
    threshold_deg: f64,
    positive_share: f64,
    negative_share: f64,
    k_mean: f64,
    k_std: f64,
    /// The eggbox's numbers: shares of interior vertices at or beyond
    /// +-`bump_deg`, and the rows and columns the bumps spread over.
    bump_deg: f64,
    bumps_share: f64,
    dimples_share: f64,
    bump_rows: usize,
    bump_cols: usize,
}

#[derive(Serialize)]
struct FrontGapsJson {
    max_mm: f64,
    mean_mm: f64,
    max_relative: f64,
    mean_relative: f64,
    worst_row: usize,
}

#[derive(Serialize)]
struct CoverageJson<'a> {
    share: f64,
    of: &'a str,
    degrees: Option<f64>,
}

#[derive(Serialize)]
struct TurnJson {
    radius_mm: f64,
    height_mm: f64,
    spread: f64,
}

#[derive(Serialize)]
struct ClashJson {
    strips: [String; 2],
    distance_mm: f64,
    at: [f64; 3],
}

#[cfg(test)]
mod tests {
    use super::hundredths;

    #[test]
    fn hundredths_drop_the_minus_of_a_zero_only() {
        assert_eq!(hundredths(-1e-15), "0.00");
        assert_eq!(hundredths(-0.0049), "0.00");
        assert_eq!(hundredths(-0.0051), "-0.01");
        assert_eq!(hundredths(-3.846), "-3.85");
        assert_eq!(hundredths(0.0), "0.00");
    }
}
