//! Strip clashes: two strips that share no joint, lie in the same stacking
//! layer (MATH.md 10.2) and whose centre lines (hole to hole, plus the end
//! margins) come closer than the strip width plus a clearance overlap in
//! the built piece. Found with a uniform grid over the strips' bounding
//! boxes, so a lattice of n strips costs about n log n, not n^2.

use crate::lattice::{Lattice, Rod};
use glam::DVec3;
use std::collections::{BTreeSet, HashMap};

/// Clearance (mm) added to the strip width unless the recipe sets one.
pub const DEFAULT_CLEARANCE: f64 = 1.0;

#[derive(Clone, Debug, PartialEq)]
pub struct Clash {
    /// Rod ids (lattice.json order), the smaller first.
    pub rods: [usize; 2],
    /// Distance between the two centre lines (mm).
    pub distance: f64,
    /// Midpoint of the closest points: where they meet.
    pub at: DVec3,
}

/// A strip's centre line: the rod from tip to tip.
struct Line {
    rod: Rod,
    layer: u32,
    a: DVec3,
    b: DVec3,
    /// The joints it goes through: its two vertices and its cell's pivot.
    joints: [u64; 3],
}

/// The clashes of `lattice` (for an intrinsic lattice, pass the assembled
/// one: the rows placed onto each other), strips `width` wide with
/// `margin` beyond the end holes, closest first.
pub fn clashes(lattice: &Lattice, width: f64, margin: f64, clearance: f64) -> Vec<Clash> {
    let reach = width + clearance;
    let lines: Vec<Line> = lattice
        .rods()
        .map(|rod| {
            let cell = &lattice.cells[rod.cell];
            let [s, _, e] = rod.hole_pos;
            let dir = (e - s).normalize_or_zero();
            Line {
                layer: lattice.layer(cell, rod.kind),
                a: s - margin * dir,
                b: e + margin * dir,
                // Vertices are numbered below 2^32, pivots above.
                joints: [
                    rod.start as u64,
                    rod.end as u64,
                    (1 << 32) + rod.cell as u64,
                ],
                rod,
            }
        })
        .collect();
    if lines.is_empty() {
        return Vec::new();
    }
    // Grid cells about one strip long, so each strip touches a few.
    let mut lengths: Vec<f64> = lines.iter().map(|l| l.a.distance(l.b)).collect();
    lengths.sort_by(f64::total_cmp);
    let h = (lengths[lengths.len() / 2] + reach).max(1e-6);
    let key = |p: DVec3| {
        let q = (p / h).floor();
        (q.x as i64, q.y as i64, q.z as i64)
    };
    let mut grid: HashMap<(i64, i64, i64), Vec<u32>> = HashMap::new();
    // A strip far longer than the median would fill its whole bounding box
    // with grid cells (a runaway design tried by the optimiser: billions);
    // such strips are checked against every strip instead.
    let mut long: Vec<u32> = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        let (lo, hi) = (
            key(l.a.min(l.b) - DVec3::splat(reach / 2.0)),
            key(l.a.max(l.b) + DVec3::splat(reach / 2.0)),
        );
        let span = |a: i64, b: i64| b.saturating_sub(a) as f64 + 1.0;
        if span(lo.0, hi.0) * span(lo.1, hi.1) * span(lo.2, hi.2) > 512.0 {
            long.push(i as u32);
            continue;
        }
        for x in lo.0..=hi.0 {
            for y in lo.1..=hi.1 {
                for z in lo.2..=hi.2 {
                    grid.entry((x, y, z)).or_default().push(i as u32);
                }
            }
        }
    }
    let mut pairs: BTreeSet<(u32, u32)> = BTreeSet::new();
    for list in grid.values() {
        for (n, &i) in list.iter().enumerate() {
            for &j in &list[n + 1..] {
                let (li, lj) = (&lines[i as usize], &lines[j as usize]);
                if li.layer == lj.layer && !li.joints.iter().any(|x| lj.joints.contains(x)) {
                    pairs.insert((i.min(j), i.max(j)));
                }
            }
        }
    }
    for &i in &long {
        for j in 0..lines.len() as u32 {
            let (li, lj) = (&lines[i as usize], &lines[j as usize]);
            if i != j && li.layer == lj.layer && !li.joints.iter().any(|x| lj.joints.contains(x)) {
                pairs.insert((i.min(j), i.max(j)));
            }
        }
    }
    let mut out: Vec<Clash> = pairs
        .into_iter()
        .filter_map(|(i, j)| {
            let (li, lj) = (&lines[i as usize], &lines[j as usize]);
            let (p, q) = closest_points(li.a, li.b, lj.a, lj.b);
            let d = p.distance(q);
            (d < reach).then(|| Clash {
                rods: [li.rod.id.min(lj.rod.id), li.rod.id.max(lj.rod.id)],
                distance: d,
                at: (p + q) / 2.0,
            })
        })
        .collect();
    out.sort_by(|a, b| a.distance.total_cmp(&b.distance).then(a.rods.cmp(&b.rods)));
    out
}

/// The closest points of segments `p0 p1` and `q0 q1` (Ericson, Real-Time
/// Collision Detection, 5.1.9).
pub fn closest_points(p0: DVec3, p1: DVec3, q0: DVec3, q1: DVec3) -> (DVec3, DVec3) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    let eps = 1e-18;
    let (s, t);
    if a <= eps && e <= eps {
        return (p0, q0);
    }
    if a <= eps {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(r);
        if e <= eps {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > eps * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    (p0 + d1 * s, q0 + d2 * t)
}

/// A rod as the reports name it: its strip id in parts.csv.
pub fn rod_name(lattice: &Lattice, rod: usize) -> String {
    let cell = &lattice.cells[rod / 2];
    let kind = if rod % 2 == 0 {
        crate::lattice::RodType::A
    } else {
        crate::lattice::RodType::B
    };
    let max_row = lattice.cells.iter().map(|c| c.row).max().unwrap_or(0);
    let max_col = lattice.cells.iter().map(|c| c.col).max().unwrap_or(0);
    let digits = |m: u32| m.to_string().len().max(2);
    super::strip_id(cell.row, cell.col, kind, digits(max_row), digits(max_col))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Direction, Leg};
    use crate::lattice::{Kind, RowParams, grow};

    #[test]
    fn closest_points_of_crossing_parallel_and_skew_segments() {
        let o = DVec3::ZERO;
        let (p, q) = closest_points(
            o,
            DVec3::X * 2.0,
            DVec3::new(1.0, -1.0, 3.0),
            DVec3::new(1.0, 1.0, 3.0),
        );
        assert!(p.distance(DVec3::X) < 1e-12 && q.distance(DVec3::new(1.0, 0.0, 3.0)) < 1e-12);
        let (p, q) = closest_points(
            o,
            DVec3::X,
            DVec3::new(0.5, 2.0, 0.0),
            DVec3::new(3.0, 2.0, 0.0),
        );
        assert!((p.distance(q) - 2.0).abs() < 1e-12);
        let (p, q) = closest_points(
            o,
            DVec3::X,
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(5.0, 0.0, 0.0),
        );
        assert!((p.distance(q) - 2.0).abs() < 1e-12);
    }

    /// A sheet of `rows` rows of 40 mm cells, legs at `angle` degrees.
    fn sheet(rows: usize, angle: f64) -> Lattice {
        let points: Vec<DVec3> = (0..5)
            .map(|j| DVec3::new(40.0 * j as f64, 0.0, 0.0))
            .collect();
        let row = RowParams {
            direction: Some(Direction::Angles {
                angle_deg: angle,
                tilt_deg: 0.0,
            }),
            left_leg: Leg::Match,
            right_leg: Leg::Match,
            ..RowParams::default()
        };
        grow(Kind::Sheet, 2, &points, &[0.0; 4], &vec![row; rows]).unwrap()
    }

    #[test]
    fn an_open_sheet_has_no_clash() {
        // Square cells of 40 mm: neighbouring parallel strips 28 mm apart.
        assert!(clashes(&sheet(4, 45.0), 10.0, 6.0, 1.0).is_empty());
    }

    #[test]
    fn a_constructed_clash_and_a_near_miss() {
        // Two rows only, so rows i and i+2 never meet: the clashes are the
        // parallel strips of one row. With the legs 5 deg from the cone axis (the
        // front) the cells are nearly collapsed; neighbouring parallel
        // strips are about 40 sin(5 deg) = 3.5 mm apart.
        let flat = sheet(1, 5.0);
        let found = clashes(&flat, 10.0, 6.0, 1.0);
        assert!(!found.is_empty());
        for c in &found {
            let (a, b) = (c.rods[0], c.rods[1]);
            assert_eq!(a % 2, b % 2, "same layer: both A or both B");
            assert!(c.distance < 11.0);
        }
        // The near miss: with the cells this shape, the gap between
        // neighbouring parallel strips is exactly computable; a strip just
        // narrower than it (less the clearance) does not clash.
        let lat = sheet(1, 30.0);
        let rods: Vec<Rod> = lat.rods().collect();
        let (a0, a1) = (rods[0], rods[2]);
        let (p, q) = closest_points(
            a0.hole_pos[0],
            a0.hole_pos[2],
            a1.hole_pos[0],
            a1.hole_pos[2],
        );
        let gap = p.distance(q);
        assert!(gap > 15.0, "{gap}");
        assert!(clashes(&lat, gap - 1.0 - 1e-6, 0.0, 1.0).is_empty());
        let hit = clashes(&lat, gap - 1.0 + 1e-6, 0.0, 1.0);
        assert!(hit.iter().any(|c| c.rods == [0, 2]), "{hit:?}");
    }

    #[test]
    fn the_grid_finds_what_all_pairs_find() {
        let lat = sheet(6, 15.0);
        let found = clashes(&lat, 10.0, 6.0, 1.0);
        let lines: Vec<Rod> = lat.rods().collect();
        let mut brute = 0;
        for i in 0..lines.len() {
            for j in i + 1..lines.len() {
                let (a, b) = (&lines[i], &lines[j]);
                let (ca, cb) = (&lat.cells[a.cell], &lat.cells[b.cell]);
                let shared = [a.start, a.end]
                    .iter()
                    .any(|v| [b.start, b.end].contains(v))
                    || a.cell == b.cell;
                if lat.layer(ca, a.kind) != lat.layer(cb, b.kind) || shared {
                    continue;
                }
                let da = (a.hole_pos[2] - a.hole_pos[0]).normalize();
                let db = (b.hole_pos[2] - b.hole_pos[0]).normalize();
                let (p, q) = closest_points(
                    a.hole_pos[0] - 6.0 * da,
                    a.hole_pos[2] + 6.0 * da,
                    b.hole_pos[0] - 6.0 * db,
                    b.hole_pos[2] + 6.0 * db,
                );
                if p.distance(q) < 11.0 {
                    brute += 1;
                }
            }
        }
        assert!(brute > 0);
        assert_eq!(found.len(), brute);
    }
}
