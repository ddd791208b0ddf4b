//! Helix growth (docs/math.md 6.3): one front wrapping onto itself, one cell a
//! step, fully determined by the seed `y_0 .. y_N` and its kappa.

use super::construct::{Point, lower_right, pivot_from_v2};
use super::grow::{GrowthError, MAX_CELLS, Param, check_cell, fmt_len, seed_front};
use super::{Cell, Kind, Lattice, Vertex, VertexKey};
use crate::diagnostic::ErrorKind;
use glam::DVec3;

/// Relative tolerance of the helix seed condition.
pub(crate) const SEED_TOL: f64 = 1e-9;

/// How far a helix seed is from the seed condition
/// `|y_N - y_1| = z(y_N) - z(y_1)`, relative to `|y_N - y_1|`.
pub fn seed_defect(points: &[DVec3], kappa: &[f64]) -> f64 {
    let n = points.len() - 1;
    let rod = points[n].distance(points[1]);
    let dz = -kappa[1..n].iter().sum::<f64>();
    (rod - dz) / rod
}

/// Grow `cells` cells of a helix of loop length N = `points.len() - 1`.
pub fn grow_helix(
    dim: usize,
    points: &[DVec3],
    kappa: &[f64],
    cells: usize,
) -> Result<Lattice, GrowthError> {
    match grow_helix_partial(dim, points, kappa, cells)? {
        (lattice, None) => Ok(lattice),
        (_, Some(e)) => Err(e),
    }
}

/// As `grow_helix`, but a cell that cannot grow ends the helix there: the
/// cells grown so far, and why the next one failed. Errors of the seed
/// itself are still errors.
pub fn grow_helix_partial(
    dim: usize,
    points: &[DVec3],
    kappa: &[f64],
    cells: usize,
) -> Result<(Lattice, Option<GrowthError>), GrowthError> {
    use ErrorKind as K;
    let n = points.len().saturating_sub(1);
    if n < 2 {
        return Err(GrowthError::of_design(
            K::SeedTooShort,
            Param::SeedPoints,
            format!(
                "a helix seed needs at least 3 points (N >= 2), this one has {}",
                points.len()
            ),
            "give y_0 .. y_N: one turn of N points and the first point of the next",
        ));
    }
    if cells > MAX_CELLS {
        return Err(GrowthError::of_design(
            K::TooLarge,
            Param::Cells,
            format!("{cells} cells is more than the limit of {MAX_CELLS}"),
            "grow fewer cells",
        ));
    }
    let mut lattice = Lattice {
        kind: Kind::Helix,
        dim,
        width: n,
        vertices: Vec::with_capacity(n + 1 + cells),
        cells: Vec::with_capacity(cells),
        fronts: Vec::new(),
        stacking: Default::default(),
    };
    seed_front(&mut lattice, points, kappa)?;
    let defect = seed_defect(points, kappa);
    if !(defect.abs() <= SEED_TOL) {
        let rod = points[n].distance(points[1]);
        return Err(GrowthError::of_design(
            K::HelixSeedNotNull,
            Param::SeedKappa(n),
            format!(
                "rod B of cell 0 runs from y_1 to y_N, so |y_N - y_1| = {} must equal -(kappa_1 + ... + kappa_{}) = {}",
                fmt_len(rod),
                n - 1,
                fmt_len(rod * (1.0 - defect))
            ),
            format!(
                "scale kappa_1 .. kappa_{} so that they sum to -{rod:.9}, or run `karigami tune` on the recipe",
                n - 1
            ),
        ));
    }
    let mut failure = None;
    for k in 0..cells {
        if let Err(e) = grow_cell(&mut lattice, k) {
            failure = Some(e);
            break;
        }
    }
    Ok((lattice, failure))
}

/// Cell k of a helix and its new vertex y_(k+N+1).
fn grow_cell(lattice: &mut Lattice, k: usize) -> Result<(), GrowthError> {
    use ErrorKind as K;
    let n = lattice.width;
    let at = |l: &Lattice, k: usize| {
        let v = &l.vertices[k];
        Point { pos: v.pos, z: v.z }
    };
    {
        let (ul, ur, ll, y2) = (
            at(lattice, k),
            at(lattice, k + 1),
            at(lattice, k + n),
            at(lattice, k + 2),
        );
        let fail = |kind: K, message: String| {
            GrowthError::new(
                kind,
                Param::Cells,
                Some(k / n),
                Some(k % n),
                format!("cell {k}: {message}"),
                "the helix seed grows only so far: run `karigami tune` on the recipe, or grow fewer cells",
            )
        };
        let v2 = (ll.pos - ur.pos).normalize();
        let p = pivot_from_v2(ul, ur, v2).map_err(|_| {
            fail(K::InadmissibleDirection, "the leg direction to the lower-left corner falls outside the cell's admissible cone".into())
        })?;
        if !(ll.z - p.z > 0.0) {
            return Err(fail(
                K::NonPositiveLeg,
                format!("leg l2 would be {}", fmt_len(ll.z - p.z)),
            ));
        }
        let v1 = (p.pos - ul.pos).normalize();
        let lr = lower_right(ul, y2, v1).map_err(|_| {
            fail(
                K::DoubleEdgeNotSpacelike,
                "the right transfer has no admissible corner".into(),
            )
        })?;
        if !(lr.z - p.z > 0.0) {
            return Err(fail(
                K::NonPositiveLeg,
                format!("leg l3 would be {}", fmt_len(lr.z - p.z)),
            ));
        }
        if !(lr.pos.is_finite() && lr.z.is_finite()) {
            return Err(fail(K::NumericalBreakdown, "a non-finite number".into()));
        }
        let m = k + n + 1;
        lattice.vertices.push(Vertex {
            key: VertexKey {
                row: 0,
                col: m as u32,
            },
            pos: lr.pos,
            z: lr.z,
        });
        let cell = Cell {
            row: (k / n) as u32,
            col: (k % n) as u32,
            ul: k as u32,
            ur: (k + 1) as u32,
            ll: (k + n) as u32,
            lr: m as u32,
            pivot: p.pos,
            z_pivot: p.z,
        };
        check_cell(lattice, &cell)?;
        lattice.cells.push(cell);
    }
    Ok(())
}
