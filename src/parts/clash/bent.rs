//! The clash rule of `clash` (two strips of one stacking layer, sharing no
//! joint, whose centre lines come closer than the strip width plus the
//! clearance) on strips that are not straight: each strip's centre line a
//! polyline (the simulated strips' nodes, docs/physics.md), with the end
//! margins beyond its end holes along its end segments.
//!
//! A bent strip can come closer to another than its chord does (the saddle
//! ring's R00-C08-B bows 20.6 mm off its chord), so the straight search
//! cannot stand in for this one. The segments are put in a uniform grid
//! (sorted entries, so the search is the same on every run); each strip is
//! then measured against the segments in the grid cells its own segments
//! touch, and the closest pair of segments is kept per pair of strips.
//! Memory is linear in the segments; the clashes are counted and kept as
//! `clashes` keeps them (`Clashes`).

use super::{Clash, Clashes, KEPT, closest_points};
use crate::lattice::{Lattice, RodType};
use glam::DVec3;

/// One segment of a strip's centre line.
#[derive(Clone, Copy)]
struct Segment {
    a: DVec3,
    b: DVec3,
    rod: u32,
}

/// A segment whose widened box covers more grid cells than this is
/// measured against every segment instead of listed in all of them (a
/// runaway strip of a failed solve).
const MOST_CELLS: i64 = 64;

/// The clashes of `lattice`'s strips with centre line `centres[r]` for rod
/// id `r` (its first hole to its last, at least two points), strips `width`
/// wide with `margin` beyond the end holes. The same rule and the same
/// order as `clashes`: a pair sharing a joint or a cell never clashes.
pub(crate) fn bent_clashes(
    lattice: &Lattice,
    centres: &[Vec<DVec3>],
    width: f64,
    margin: f64,
    clearance: f64,
) -> Clashes {
    let reach = width + clearance;
    let mut found = Clashes::keeping(KEPT);
    let segments = segments(centres, margin);
    if segments.len() < 2 {
        found.finish();
        return found;
    }
    let info: Vec<(u32, [u32; 2])> = (0..centres.len()).map(|r| rod_info(lattice, r)).collect();
    let grid = Grid::new(&segments, reach);
    // Per strip: the strips it clashes with, the closest segments' distance
    // and midpoint; cleared for the next strip.
    let mut best: Vec<(u32, f64, DVec3)> = Vec::new();
    let mut near: Vec<u32> = Vec::new();
    let mut first = 0;
    while first < segments.len() {
        let rod = segments[first].rod;
        let end = first + segments[first..].partition_point(|s| s.rod == rod);
        best.clear();
        for s in &segments[first..end] {
            grid.near(s, &mut near);
            for &k in &near {
                let t = &segments[k as usize];
                if t.rod <= rod || !may_clash(&info, rod, t.rod) {
                    continue;
                }
                let (p, q) = closest_points(s.a, s.b, t.a, t.b);
                let d = p.distance(q);
                if !(d < reach) {
                    continue;
                }
                match best.iter_mut().find(|b| b.0 == t.rod) {
                    Some(b) if d < b.1 => *b = (t.rod, d, (p + q) / 2.0),
                    Some(_) => {}
                    None => best.push((t.rod, d, (p + q) / 2.0)),
                }
            }
        }
        best.sort_by_key(|b| b.0);
        for &(other, distance, at) in &best {
            found.add(Clash {
                rods: [rod as usize, other as usize],
                distance,
                at,
            });
        }
        first = end;
    }
    found.finish();
    found
}

/// Every strip's segments in rod order, the end segments lengthened by
/// `margin`; a strip with a non-finite point is left out (it never clashes,
/// as in `clashes`).
fn segments(centres: &[Vec<DVec3>], margin: f64) -> Vec<Segment> {
    let mut out = Vec::new();
    for (r, line) in centres.iter().enumerate() {
        if line.len() < 2 || line.iter().any(|p| !p.is_finite()) {
            continue;
        }
        let mut points = line.clone();
        let n = points.len();
        let start = (points[0] - points[1]).normalize_or_zero();
        let end = (points[n - 1] - points[n - 2]).normalize_or_zero();
        points[0] += margin * start;
        points[n - 1] += margin * end;
        out.extend(points.windows(2).map(|w| Segment {
            a: w[0],
            b: w[1],
            rod: r as u32,
        }));
    }
    out
}

/// A rod's stacking layer and its two vertices.
fn rod_info(lattice: &Lattice, r: usize) -> (u32, [u32; 2]) {
    let cell = &lattice.cells[r / 2];
    if r.is_multiple_of(2) {
        (lattice.layer(cell, RodType::A), [cell.ul, cell.lr])
    } else {
        (lattice.layer(cell, RodType::B), [cell.ur, cell.ll])
    }
}

/// Rods `i` and `j` of one layer that share no vertex and no cell.
fn may_clash(info: &[(u32, [u32; 2])], i: u32, j: u32) -> bool {
    let ((li, vi), (lj, vj)) = (info[i as usize], info[j as usize]);
    li == lj && i / 2 != j / 2 && !vi.iter().any(|v| vj.contains(v))
}

/// The segments by grid cell: each listed in every cell its box, widened by
/// half the reach, touches. Two segments closer than the reach have
/// widened boxes that meet, so they share a cell.
struct Grid {
    lo: DVec3,
    inv_h: f64,
    half: DVec3,
    /// (cell key, segment), sorted.
    entries: Vec<([i32; 3], u32)>,
    /// Segments measured against every segment.
    long: Vec<u32>,
    count: u32,
}

impl Grid {
    fn new(segments: &[Segment], reach: f64) -> Grid {
        let half = DVec3::splat(reach / 2.0);
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for s in segments {
            (lo, hi) = (lo.min(s.a.min(s.b)), hi.max(s.a.max(s.b)));
        }
        let (lo, hi) = (lo - half, hi + half);
        let mut lengths: Vec<f64> = segments.iter().map(|s| s.a.distance(s.b)).collect();
        let mid = lengths.len() / 2;
        let median = *lengths.select_nth_unstable_by(mid, f64::total_cmp).1;
        // About two segments a cell along a strip; never more than 2^20
        // cells along an axis.
        let h = (2.0 * median + reach)
            .max(1e-6)
            .max((hi - lo).max_element() / (1u64 << 20) as f64);
        let mut grid = Grid {
            lo,
            inv_h: 1.0 / h,
            half,
            entries: Vec::new(),
            long: Vec::new(),
            count: segments.len() as u32,
        };
        for (k, s) in segments.iter().enumerate() {
            let (a, b) = grid.span(s);
            if grid.cells(a, b) > MOST_CELLS {
                grid.long.push(k as u32);
                continue;
            }
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for x in a[0]..=b[0] {
                        grid.entries.push(([x, y, z], k as u32));
                    }
                }
            }
        }
        grid.entries.sort_unstable();
        grid
    }

    fn key(&self, p: DVec3) -> [i32; 3] {
        let q = (p - self.lo) * self.inv_h;
        [q.x as i32, q.y as i32, q.z as i32]
    }

    /// The grid cells of a segment's widened box, lowest and highest.
    fn span(&self, s: &Segment) -> ([i32; 3], [i32; 3]) {
        (
            self.key(s.a.min(s.b) - self.half),
            self.key(s.a.max(s.b) + self.half),
        )
    }

    fn cells(&self, a: [i32; 3], b: [i32; 3]) -> i64 {
        (0..3).map(|k| i64::from(b[k] - a[k]) + 1).product()
    }

    /// The segments that may come within the reach of `s` (each once,
    /// in index order), into `out`.
    fn near(&self, s: &Segment, out: &mut Vec<u32>) {
        out.clear();
        let (a, b) = self.span(s);
        if self.cells(a, b) > MOST_CELLS {
            out.extend(0..self.count);
            return;
        }
        for z in a[2]..=b[2] {
            for y in a[1]..=b[1] {
                for x in a[0]..=b[0] {
                    let key = [x, y, z];
                    let from = self.entries.partition_point(|e| e.0 < key);
                    let to = from + self.entries[from..].partition_point(|e| e.0 == key);
                    out.extend(self.entries[from..to].iter().map(|e| e.1));
                }
            }
        }
        out.extend(&self.long);
        out.sort_unstable();
        out.dedup();
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::sheet;
    use super::*;

    /// Each rod's chord as a polyline of `n` equal segments.
    fn chords(lat: &Lattice, n: usize) -> Vec<Vec<DVec3>> {
        lat.rods()
            .map(|r| {
                let (a, b) = (r.hole_pos[0], r.hole_pos[2]);
                (0..=n).map(|k| a.lerp(b, k as f64 / n as f64)).collect()
            })
            .collect()
    }

    #[test]
    fn straight_polylines_clash_as_the_straight_search_finds() {
        // Strips as polylines along their chords: the same pairs, the same
        // distances (to rounding), the same order.
        for (rows, angle) in [(6, 15.0), (4, 45.0), (1, 5.0)] {
            let lat = sheet(rows, angle);
            let straight = super::super::clashes(&lat, 10.0, 6.0, 1.0);
            for n in [1, 4] {
                let bent = bent_clashes(&lat, &chords(&lat, n), 10.0, 6.0, 1.0);
                assert_eq!(bent.len(), straight.len(), "{rows} rows at {angle}, {n}");
                assert!(rows > 1 || !bent.is_empty());
                let by_rods = |c: &Clashes| {
                    let mut v: Vec<([usize; 2], f64)> =
                        c.iter().map(|c| (c.rods, c.distance)).collect();
                    v.sort_by_key(|x| x.0);
                    v
                };
                for (b, s) in by_rods(&bent).iter().zip(&by_rods(&straight)) {
                    assert_eq!(b.0, s.0);
                    assert!((b.1 - s.1).abs() < 1e-9, "{b:?} {s:?}");
                }
            }
        }
    }

    #[test]
    fn a_bow_that_reaches_a_neighbour_clashes_where_the_chords_do_not() {
        // An open sheet (no chord clash); one strip bowed sideways in its
        // middle until it reaches its parallel neighbour's chord.
        let lat = sheet(4, 45.0);
        assert!(super::super::clashes(&lat, 10.0, 6.0, 1.0).is_empty());
        let mut lines = chords(&lat, 8);
        let straight = bent_clashes(&lat, &lines, 10.0, 6.0, 1.0);
        assert!(straight.is_empty());
        // Rod 0 (an A rod) and rod 2, its neighbour in the row.
        let (a, b) = (lines[2][0], lines[2][8]);
        let mid = (a + b) / 2.0;
        let towards = mid - (lines[0][0] + lines[0][8]) / 2.0;
        for (k, p) in lines[0].iter_mut().enumerate().take(8).skip(1) {
            let f = (k as f64 / 8.0 * std::f64::consts::PI).sin();
            *p += towards * 0.9 * f;
        }
        let found = bent_clashes(&lat, &lines, 10.0, 6.0, 1.0);
        assert!(found.iter().any(|c| c.rods == [0, 2]), "{found:?}");
    }
}
