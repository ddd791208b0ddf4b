//! Sheets for `karigami design`: seeds along stretches of the target's
//! boundary, grown row by row by the fit's search (docs/math.md 6.1).

use super::DesignAsk;
use crate::design::fit::Fit;
use crate::lattice::{Kind, Lattice, RowParams, grow};
use crate::target::Target;
use glam::DVec3;

/// Leg angles a row's scan tries (and a tilt for every four, docs/recipe.md).
const SAMPLES: usize = 31;

/// Rows tried per seed over every backtrack of its search.
const ROW_BUDGET: usize = 40;

/// The seed stretches tried: shares of the boundary, and starts round it.
const SHARES: [f64; 2] = [0.25, 1.0 / 3.0];

const STARTS: usize = 4;

/// The target's longest boundary loop, running so that a sheet seeded on
/// it grows into the patch: clockwise seen from +z, because a front's
/// growth side is to its right (docs/recipe.md, "Row tables").
pub(super) fn inward_boundary(t: &Target) -> Vec<DVec3> {
    let loops = t.mesh.boundary_loops();
    let Some(first) = loops.first() else {
        return Vec::new();
    };
    let mut pts: Vec<DVec3> = first
        .iter()
        .map(|&i| t.mesh.positions[i as usize])
        .collect();
    let area: f64 = (0..pts.len())
        .map(|k| {
            let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
            a.x * b.y - b.x * a.y
        })
        .sum();
    if area > 0.0 {
        pts.reverse();
    }
    pts
}

/// Points round a closed polyline at equal arc lengths near `edge`.
pub(super) fn resample(ring: &[DVec3], edge: f64) -> Vec<DVec3> {
    let n = ring.len();
    let len: Vec<f64> = (0..n)
        .map(|k| ring[k].distance(ring[(k + 1) % n]))
        .collect();
    let total: f64 = len.iter().sum();
    let count = ((total / edge).round() as usize).max(4);
    let step = total / count as f64;
    let (mut out, mut k, mut walked) = (Vec::with_capacity(count), 0, 0.0);
    for j in 0..count {
        let want = j as f64 * step;
        while k + 1 < n && walked + len[k] < want {
            walked += len[k];
            k += 1;
        }
        let u = ((want - walked) / len[k].max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        out.push(ring[k].lerp(ring[(k + 1) % n], u));
    }
    out
}

/// The rows the fit's search reaches from one seed (with kappa 0) on the
/// target, and their lattice; None when no row grows.
pub(super) fn grow_seed(
    ask: &DesignAsk<'_>,
    points: &[DVec3],
    rows: usize,
) -> Option<(Vec<RowParams>, Lattice)> {
    let mut d = ask.base.clone();
    d.kind = Kind::Sheet;
    d.dim = 3;
    d.points = points.to_vec();
    d.kappa = vec![0.0; points.len() - 1];
    d.rows.clear();
    let fit = Fit::on_target(ask.target.clone(), rows, SAMPLES);
    let found = crate::solve::fit::deepest_rows(&d, &fit, ROW_BUDGET).ok()?;
    let lattice = grow(Kind::Sheet, 3, &d.points, &d.kappa, &found).ok()?;
    d.rows.clone_from(&found);
    let m = crate::measure::measure(&d, &lattice);
    crate::solve::cost::refused(&d, &lattice, &m)
        .is_none()
        .then_some((found, lattice))
}

/// A sheet's `[lattice]`: its seed points and one row table per row,
/// every number in full so that it grows as the search grew it.
pub(super) fn sheet_toml(points: &[DVec3], rows: &[RowParams]) -> String {
    let mut s = String::from("[lattice]\nseed = \"sheet\"\nkappa = 0.0\npoints = [\n");
    for p in points {
        s.push_str(&format!("    [{:?}, {:?}, {:?}],\n", p.x, p.y, p.z));
    }
    s.push_str("]\n");
    for r in rows {
        s.push_str("\n[[lattice.rows]]\n");
        if let Some(crate::legs::Direction::Angles {
            angle_deg,
            tilt_deg,
        }) = r.direction
        {
            s.push_str(&format!("angle = [{angle_deg:?}, {tilt_deg:?}]\n"));
        }
        for (key, leg) in [("left_leg", r.left_leg), ("right_leg", r.right_leg)] {
            if let crate::legs::Leg::Length(l) = leg {
                s.push_str(&format!("{key} = {l:?}\n"));
            }
        }
    }
    s
}

/// The seeds a sheet may grow from: stretches of the resampled boundary
/// `ring`, each a share of it from one of a few starts, with a line
/// saying where it lies.
pub(super) fn seeds(ring: &[DVec3]) -> Vec<(Vec<DVec3>, String)> {
    SHARES
        .iter()
        .flat_map(|&share| (0..STARTS).map(move |k| (share, k)))
        .map(|(share, k)| {
            let n = ring.len();
            let cells = ((share * n as f64).round() as usize).clamp(2, n - 1);
            let start = k * n / STARTS;
            let pts = (0..=cells).map(|j| ring[(start + j) % n]).collect();
            (
                pts,
                format!(
                    "{cells} cells along {:.0} % of the boundary from its point {start} of {n}",
                    100.0 * cells as f64 / n as f64
                ),
            )
        })
        .collect()
}
