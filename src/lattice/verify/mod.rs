//! Verification of a grown lattice (docs/verification.md, docs/math.md 8.0-8.3).
//! Every residual is recomputed from the stored positions and z values,
//! never copied from the construction, and made relative (lengths over the
//! cell's mean leg).
//!
//! Each invariant's residual is written once, in `residuals.rs`. Two
//! traversals feed those formulas, side by side:
//!
//! - `cells.rs`, one pass over the cells of any lattice, its neighbours
//!   found through an `Incidence` (`incidence.rs`): helices, intrinsic
//!   lattices (rows grown on rebuilt fronts), damaged ones;
//! - `rows.rs`, a regular, extrinsic sheet or loop row by row, each row's
//!   legs measured once into arrays and each residual compared with its
//!   check's largest as it is computed. It is the same report bit for bit
//!   (the same formulas on the same operands, in the same order; a unit
//!   test holds the two together on good and damaged lattices) at less than
//!   half the cost, which is why both stay. Measured 2026-12-02 with the
//!   rows' pass switched off in `verify` against on (release builds, the
//!   growth bench `target/release/deps/growth-*`): verification of a
//!   300 x 300 sheet executed 120.1 M instructions by the cells against
//!   54.3 M by rows (`valgrind --tool=callgrind
//!   --toggle-collect=karigami::lattice::verify::verify growth-* 300`), and
//!   of a 1000 x 1000 sheet took 0.113 and 0.154 s of CPU against 0.061 and
//!   0.066 s (`growth-* 1000`, two runs each on the loaded 2-core machine).
//!
//! The collapsed state (`collapsed.rs`) is swept by either traversal, a
//! cell or a row at a time; the public face (`Invariant`, `Check`,
//! `Report`) is in `report.rs`.

mod cells;
mod collapsed;
mod incidence;
mod report;
mod residuals;
mod row;
mod rows;
#[cfg(test)]
mod tests;
mod watch;

pub use report::{Check, Invariant, Report};

use super::{Lattice, Legs, Vertex};
use collapsed::Collapsed;
use incidence::{Grid, Incidence};

/// A lattice passes when every relative residual is at most this (or, for
/// a lattice of enormous extent, `tolerance`).
pub const TOLERANCE: f64 = 1e-9;

/// Rounding drift of a relative residual per leg of distance from the
/// origin. docs/math.md 8.5 measured f64 residuals growing linearly with the
/// extent: 4e-13 at 200 rows, about 2e-15 (9 ulp) per leg; this allows
/// seven times that.
pub const DRIFT_PER_LEG: f64 = 64.0 * f64::EPSILON;

/// Check every invariant of docs/verification.md (docs/math.md 8.0-8.3): by rows
/// for a regular, extrinsic sheet or loop (`rows::verify_rows`), in one pass
/// over the cells for anything else (`cells::verify_with`); the same report
/// either way.
pub fn verify(lattice: &Lattice) -> Report {
    // The rows' pass checks each row's corner indices as it measures the
    // row (no pass of its own over the cells), and gives up on the first
    // row that is not its grid's.
    if let Some(grid) = Grid::of(lattice).filter(|_| lattice.extrinsic())
        && let Some(report) = rows::verify_rows(lattice, &grid)
    {
        return report;
    }
    cells::verify_with(lattice, &Incidence::new(lattice))
}

/// How far a vertex is from the origin, coordinate- and z-wise.
#[inline]
fn vertex_extent(v: &Vertex) -> f64 {
    v.pos.abs().max_element().max(v.z.abs())
}

/// The tolerance `lattice` is verified against, given the sum over its
/// cells of their mean legs and its largest `vertex_extent`: `TOLERANCE`, or
/// `DRIFT_PER_LEG` times its extent in mean legs when that is larger (only
/// beyond about 70,000 legs from the origin, e.g. a sheet of more than
/// 70,000 rows), since rounding of absolute coordinates alone then reaches
/// 1e-9 in exact constructions.
fn tolerance_of(lattice: &Lattice, legs: f64, extent: f64) -> f64 {
    let leg = legs / lattice.cells.len().max(1) as f64;
    if !(leg > 0.0) || !extent.is_finite() {
        return TOLERANCE;
    }
    TOLERANCE.max(DRIFT_PER_LEG * extent / leg)
}

/// The name of vertex `v` in a check's site.
fn vertex_site(lattice: &Lattice, v: usize) -> String {
    format!("vertex {}", lattice.vertex_name(v as u32))
}

/// A cell's mean leg, the scale of its relative residuals.
fn mean(legs: &Legs) -> f64 {
    legs.iter().sum::<f64>() / 4.0
}

/// The report of a traversal: its ten checks in `Invariant` order, then
/// the collapsed state's three, all held to the tolerance (`leg_sum` the
/// sum of the cells' mean legs, in cell order).
fn report(lattice: &Lattice, leg_sum: f64, checks: [Check; 10], collapsed: Collapsed) -> Report {
    let (collapsed, extent) = collapsed.finish(lattice, leg_sum);
    let tolerance = tolerance_of(lattice, leg_sum, extent);
    let count = |k: usize| checks[k].count;
    Report {
        tolerance,
        cells: lattice.cells.len(),
        vertices: lattice.vertices.len(),
        rods: 2 * lattice.cells.len(),
        horizontal_pores: count(3),
        vertical_pores: count(4),
        interior_vertices: count(7),
        checks: checks
            .into_iter()
            .chain(collapsed)
            .map(|c| Check { tolerance, ..c })
            .collect(),
    }
}
