//! Sheets for `karigami design`: seeds along stretches of the target's
//! boundary, grown row by row by the fit's search (docs/math.md 6.1).

use super::DesignAsk;
use crate::design::fit::Fit;
use crate::lattice::{Kind, Lattice, RowParams, grow};
use crate::target::Target;
use glam::DVec3;

/// Leg angles a row's scan tries (and a tilt for every four, docs/recipe.md),
/// one search of each seed per count. Which branch a row's search takes
/// turns on small differences in its scores, and whether the sheet it
/// reaches holds its shape only the simulation tells (docs/design.md,
/// "What it reaches": on the saddle the 31-angle scan's sheets fold
/// shut in their last rows, the 29-angle scan's 35 cells meet the goal),
/// so each seed is searched with two scans whose angles interleave, and
/// `design` builds the best of them all.
pub(super) const SCANS: [usize; 2] = [31, 29];

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
/// target, each row's scan of `samples` leg angles, and their lattice; why
/// not when no row grows or `build`'s checks refuse the rows reached.
pub(super) fn grow_seed(
    ask: &DesignAsk<'_>,
    points: &[DVec3],
    (rows, samples): (usize, usize),
    refront: bool,
) -> Result<(Vec<RowParams>, Lattice), String> {
    let mut d = ask.base.clone();
    d.kind = Kind::Sheet;
    d.dim = 3;
    d.points = points.to_vec();
    d.kappa = vec![0.0; points.len() - 1];
    d.rows.clear();
    let fit = Fit::on_target(ask.target.clone(), rows, samples);
    let found = crate::solve::fit::deepest_rows(&d, &fit, ROW_BUDGET, refront)
        .map_err(|e| format!("no row grows: {}", e.message))?;
    // The deepest sheet first, then with its last rows left off: a row
    // that clashes or cannot be cut loses that row, not the seed.
    let mut first_refusal = None;
    for rows in (1..=found.len()).rev() {
        let lattice = grow(Kind::Sheet, 3, &d.points, &d.kappa, &found[..rows])
            .map_err(|e| format!("no row grows: {}", e.message))?;
        d.rows = found[..rows].to_vec();
        let m = crate::measure::measure(&d, &lattice);
        match crate::solve::cost::refused(&d, &lattice, &m) {
            None => return Ok((d.rows, lattice)),
            Some(why) => {
                first_refusal
                    .get_or_insert_with(|| format!("{} rows, refused: {why}", found.len()));
            }
        }
    }
    Err(first_refusal.unwrap_or_else(|| "no row grows".into()))
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
        if let Some(f) = &r.front {
            s.push_str(&front_toml(f));
        }
    }
    s
}

/// A row's `front = { ... }`: the bend, twist and pivot a laid front takes
/// (docs/recipe.md, rebuilt fronts), every angle in full.
fn front_toml(f: &crate::lattice::FrontMoves) -> String {
    let list = |v: &Option<Vec<f64>>| {
        let v = v.as_deref().unwrap_or(&[]);
        v.iter()
            .map(|a| format!("{a:?}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut s = format!(
        "front = {{ bend = [{}], twist = [{}]",
        list(&f.bend),
        list(&f.twist)
    );
    let pivots: Vec<String> = f
        .pivots
        .iter()
        .map(|p| {
            let a = p.axis.unwrap_or(DVec3::Z);
            format!(
                "{{ at = {}, angle = {:?}, axis = [{:?}, {:?}, {:?}] }}",
                p.at, p.angle_deg, a.x, a.y, a.z
            )
        })
        .collect();
    if !pivots.is_empty() {
        s.push_str(&format!(", pivot = [{}]", pivots.join(", ")));
    }
    s.push_str(" }\n");
    s
}

/// How sharply (degrees, in plan) the boundary must turn within
/// `CORNER_SPAN` of D for a corner.
const CORNER_TURN: f64 = 45.0;

const CORNER_SPAN: f64 = 0.04;

/// The sides of the target's boundary `ring` (clockwise, docs/design.md
/// "Seed"): the stretches between its corners, each from corner to corner
/// resampled at about `edge` apart, longest first; none when the boundary
/// has fewer than three corners (a round rim).
pub(super) fn sides(ring: &[DVec3], extent: f64, edge: f64) -> Vec<Vec<DVec3>> {
    let n = ring.len();
    if n < 3 {
        return Vec::new();
    }
    let len: Vec<f64> = (0..n)
        .map(|k| ring[k].distance(ring[(k + 1) % n]))
        .collect();
    let span = CORNER_SPAN * extent;
    // The plan point `s` of arc length from vertex k, either way round.
    let walk = |k: usize, forward: bool| {
        let (mut at, mut left) = (k, span);
        for _ in 0..n {
            let (next, l) = if forward {
                ((at + 1) % n, len[at])
            } else {
                ((at + n - 1) % n, len[(at + n - 1) % n])
            };
            if l >= left {
                return ring[at].lerp(ring[next], left / l).truncate();
            }
            left -= l;
            at = next;
        }
        ring[at].truncate()
    };
    let turn: Vec<f64> = (0..n)
        .map(|k| {
            let (a, b) = (
                ring[k].truncate() - walk(k, false),
                walk(k, true) - ring[k].truncate(),
            );
            a.angle_to(b).abs().to_degrees()
        })
        .collect();
    // A corner: a turn past CORNER_TURN, the sharpest within the span.
    let mut corners: Vec<usize> = (0..n)
        .filter(|&k| turn[k] >= CORNER_TURN)
        .filter(|&k| {
            let (mut back, mut ahead, mut j) = (0.0, 0.0, k);
            let mut sharpest = true;
            while back < span && sharpest {
                j = (j + n - 1) % n;
                back += len[j];
                sharpest = turn[j] < turn[k] || turn[j] == turn[k] && j > k;
            }
            j = k;
            while ahead < span && sharpest {
                ahead += len[j];
                j = (j + 1) % n;
                sharpest = turn[j] < turn[k] || turn[j] == turn[k] && j > k;
            }
            sharpest
        })
        .collect();
    corners.dedup();
    if corners.len() < 3 {
        return Vec::new();
    }
    let mut out: Vec<Vec<DVec3>> = (0..corners.len())
        .map(|c| {
            let (a, b) = (corners[c], corners[(c + 1) % corners.len()]);
            let count = (b + n - a) % n;
            let side: Vec<DVec3> = (0..=count).map(|j| ring[(a + j) % n]).collect();
            along_open(&side, edge)
        })
        .collect();
    let length = |s: &Vec<DVec3>| s.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>();
    // A stable sort: of equal sides, the first round the boundary.
    out.sort_by(|a, b| length(b).total_cmp(&length(a)));
    out
}

/// Points along an open polyline from its first point to its last, at
/// equal arc lengths near `edge` apart.
fn along_open(line: &[DVec3], edge: f64) -> Vec<DVec3> {
    let len: Vec<f64> = line.windows(2).map(|w| w[0].distance(w[1])).collect();
    let total: f64 = len.iter().sum();
    let count = ((total / edge).round() as usize).max(2);
    let (mut out, mut k, mut walked) = (Vec::with_capacity(count + 1), 0, 0.0);
    for j in 0..=count {
        let want = total * j as f64 / count as f64;
        while k + 1 < len.len() && walked + len[k] < want {
            walked += len[k];
            k += 1;
        }
        let u = ((want - walked) / len[k].max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        out.push(line[k].lerp(line[k + 1], u));
    }
    out
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A rectangle's boundary, finely sampled, has four sides from corner
    /// to corner, the longest first; a circle has none.
    #[test]
    fn a_rectangle_has_four_sides_and_a_circle_none() {
        let corners = [
            DVec3::new(-200.0, 150.0, 0.0),
            DVec3::new(200.0, 150.0, 0.0),
            DVec3::new(200.0, -150.0, 0.0),
            DVec3::new(-200.0, -150.0, 0.0),
        ];
        let ring: Vec<DVec3> = (0..4)
            .flat_map(|k| {
                let (a, b) = (corners[k], corners[(k + 1) % 4]);
                (0..20).map(move |j| a.lerp(b, j as f64 / 20.0))
            })
            .collect();
        let sides = sides(&ring, 500.0, 60.0);
        assert_eq!(sides.len(), 4);
        let ends: Vec<(DVec3, DVec3)> = sides.iter().map(|s| (s[0], s[s.len() - 1])).collect();
        assert!(ends[0].0.distance(corners[0]) < 1e-9 && ends[0].1.distance(corners[1]) < 1e-9);
        assert_eq!(sides[0].len(), 8, "400 mm at about 60 mm: 7 cells");
        assert_eq!(sides[2].len(), 6, "300 mm: 5 cells");
        for s in &sides {
            let l: Vec<f64> = s.windows(2).map(|w| w[0].distance(w[1])).collect();
            assert!(l.iter().all(|x| (x - l[0]).abs() < 1e-9), "{l:?}");
        }
        let circle: Vec<DVec3> = (0..80)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 80.0;
                DVec3::new(200.0 * a.cos(), 200.0 * a.sin(), 0.0)
            })
            .collect();
        assert!(super::sides(&circle, 400.0, 60.0).is_empty());
    }
}
