//! The mobility of the ideal linkage at the design state: the nullity of
//! the constraint Jacobian by a banded elimination.

use super::super::Lattice;
use glam::DVec3;

/// Lattices up to this many cells get a mobility count (a dense-ish
/// elimination over every point of the linkage).
pub const MOBILITY_MAX_CELLS: usize = 2_000;

/// Internal degrees of freedom of the ideal linkage at the design state:
/// rods are rigid, scissor pivots revolute, vertex pivots revolute (2-D) or
/// spherical (3-D). Modelled on points (vertices and pivots): per rod two
/// hole distances and D - 1 collinearity conditions; the nullity of their
/// Jacobian minus the rigid motions. None for lattices larger than
/// `MOBILITY_MAX_CELLS` or with bent facets (no single deployed state).
pub fn mobility(lattice: &Lattice) -> Option<usize> {
    if lattice.cells.len() > MOBILITY_MAX_CELLS || !lattice.extrinsic() {
        return None;
    }
    let d = lattice.dim;
    let nv = lattice.vertices.len();
    // Columns ordered by lattice row (a pivot between its two rows) so that
    // the elimination stays banded.
    let mut points: Vec<(u64, usize)> = lattice
        .vertices
        .iter()
        .enumerate()
        .map(|(i, v)| ((v.key.row as u64 * 2) << 32 | i as u64, i))
        .collect();
    points.extend(
        lattice
            .cells
            .iter()
            .enumerate()
            .map(|(i, c)| ((c.row as u64 * 2 + 1) << 32 | i as u64, nv + i)),
    );
    points.sort_unstable();
    let mut column = vec![0; points.len()];
    for (k, &(_, p)) in points.iter().enumerate() {
        column[p] = k * d;
    }
    let n = points.len() * d;
    let mut rows: Vec<Vec<(usize, f64)>> = Vec::new();
    let push = |rows: &mut Vec<Vec<(usize, f64)>>, terms: &[(usize, DVec3, f64)]| {
        let mut row = Vec::new();
        for &(point, dir, weight) in terms {
            for axis in 0..d {
                let v = dir[axis] * weight;
                if v != 0.0 {
                    row.push((column[point] + axis, v));
                }
            }
        }
        rows.push(row);
    };
    for rod in lattice.rods() {
        let [s, p, e] = rod.hole_pos;
        let (si, pi, ei) = (rod.start as usize, nv + rod.cell, rod.end as usize);
        let u = (s - p).normalize();
        let w = (e - p).normalize();
        push(&mut rows, &[(si, u, 1.0), (pi, u, -1.0)]);
        push(&mut rows, &[(ei, w, 1.0), (pi, w, -1.0)]);
        let t = rod.legs[0] / rod.length();
        let axis = (e - s).normalize();
        for normal in normals(axis, d) {
            push(
                &mut rows,
                &[
                    (pi, normal, 1.0),
                    (si, normal, -(1.0 - t)),
                    (ei, normal, -t),
                ],
            );
        }
    }
    let rank = rank(rows, n);
    let rigid = if d == 2 { 3 } else { 6 };
    Some((n - rank).saturating_sub(rigid))
}

/// D - 1 unit vectors perpendicular to `axis` (in the plane when D = 2).
fn normals(axis: DVec3, d: usize) -> Vec<DVec3> {
    if d == 2 {
        return vec![DVec3::new(-axis.y, axis.x, 0.0)];
    }
    let helper = if axis.x.abs() < 0.9 {
        DVec3::X
    } else {
        DVec3::Y
    };
    let n1 = axis.cross(helper).normalize();
    vec![n1, axis.cross(n1)]
}

/// Numerical rank by Gaussian elimination with partial pivoting over sparse
/// rows (a pivot below 1e-9 of the largest entry counts as zero; rows are
/// unit-scaled geometric constraints).
fn rank(rows: Vec<Vec<(usize, f64)>>, n: usize) -> usize {
    // Rows as dense spans [lo, lo + len) so that banded rows stay short.
    let mut spans: Vec<Span> = rows
        .into_iter()
        .filter(|r| !r.is_empty())
        .map(|r| {
            let lo = r.iter().map(|t| t.0).min().unwrap_or(0);
            let hi = r.iter().map(|t| t.0).max().unwrap_or(0);
            let mut dense = vec![0.0; hi + 1 - lo];
            for (c, v) in r {
                dense[c - lo] += v;
            }
            Span {
                lo,
                values: dense,
                kept_by: None,
            }
        })
        .collect();
    spans.sort_by_key(|s| s.lo);
    let scale = spans
        .iter()
        .flat_map(|s| s.values.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let tol = 1e-9 * scale.max(f64::MIN_POSITIVE);
    let mut rank = 0;
    let mut active: Vec<Span> = Vec::new();
    let mut spans = spans.into_iter().peekable();
    for col in 0..n {
        // Rows whose first possible non-zero is at or before this column.
        while let Some(s) = spans.next_if(|s| s.lo <= col) {
            active.push(s);
        }
        // The largest entry in this column; the last of equals, as
        // `Iterator::max_by` picks.
        let mut best: Option<(usize, f64)> = None;
        for (i, r) in active.iter().enumerate() {
            let e = r.entry(col).abs();
            if best.is_none_or(|(_, b)| e.total_cmp(&b).is_ge()) {
                best = Some((i, e));
            }
        }
        let Some((best, largest)) = best else {
            continue;
        };
        if largest <= tol {
            continue;
        }
        let pivot = active.swap_remove(best);
        rank += 1;
        let pv = pivot.entry(col);
        let end = pivot.lo + pivot.values.len();
        let tail = &pivot.values[col - pivot.lo..];
        for r in &mut active {
            let v = r.entry(col);
            if v == 0.0 {
                continue;
            }
            let factor = v / pv;
            if r.lo + r.values.len() < end {
                // Entries before this column are never read again: drop
                // them before the row grows rather than copy them.
                r.values.drain(..col - r.lo);
                r.lo = col;
                r.values.resize(end - col, 0.0);
            }
            for (x, p) in r.values[col - r.lo..end - r.lo].iter_mut().zip(tail) {
                *x -= factor * p;
            }
            r.kept_by = None;
        }
        // Rows that are now zero from here on can be dropped.
        active.retain_mut(|r| r.nonzero_from(col, tol));
    }
    rank
}

/// A row of the elimination: its values from column `lo` on.
struct Span {
    lo: usize,
    values: Vec<f64>,
    /// A column at or after the last one checked whose value is above the
    /// tolerance (None: not checked since the row last changed), so that a
    /// row that elimination did not touch is not scanned again.
    kept_by: Option<usize>,
}

impl Span {
    /// The value in column `col` (at or after `lo`).
    fn entry(&self, col: usize) -> f64 {
        self.values.get(col - self.lo).copied().unwrap_or(0.0)
    }

    /// Whether any value from column `col` on is above `tol`.
    fn nonzero_from(&mut self, col: usize, tol: f64) -> bool {
        if self.kept_by.is_some_and(|k| k >= col) {
            return true;
        }
        let from = (col - self.lo).min(self.values.len());
        self.kept_by = self.values[from..]
            .iter()
            .position(|v| v.abs() > tol)
            .map(|i| self.lo + from + i);
        self.kept_by.is_some()
    }
}
