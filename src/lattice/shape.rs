//! The shape the cut strips make, measured from each cell's own corners
//! (what the strips physically fix), never from a picture's placement:
//! discrete Gaussian curvature (angle defects), regularity of the cells,
//! how far rebuilt fronts miss the rows they join, and how many different
//! strips there are. Target fit and coverage depend on the recipe's target
//! and live with it (`design::fit`).

use super::{Kind, Lattice, angle_between};
use glam::DVec3;
use std::f64::consts::TAU;

/// An angle defect beyond this (degrees) counts as curved, positive or
/// negative; below it a vertex is flat (a planar grid's defects are ~1e-14).
pub const CURVED_DEG: f64 = 0.5;
/// Strips whose hole-to-hole legs agree within this (mm) are the same strip.
pub(crate) const SAME_STRIP_MM: f64 = 0.05;

/// The discrete curvature at one interior vertex (shared by four cells).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexCurvature {
    /// Index into `Lattice::vertices`.
    pub vertex: u32,
    /// 2 pi minus the four corner angles, each from its own cell (radians).
    pub defect: f64,
    /// A quarter of the four cells' areas (mm^2).
    pub(crate) area: f64,
    /// Gaussian curvature `defect / area` (1/mm^2).
    pub k: f64,
}

/// How far the rebuilt fronts of an intrinsic lattice miss the rows they
/// join, after the best rigid placement: the bending the strips must take.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrontGaps {
    /// Largest and mean miss (mm).
    pub(crate) max: f64,
    pub(crate) mean: f64,
    /// The same, relative to the mean front edge of their rows.
    pub max_rel: f64,
    pub(crate) mean_rel: f64,
    /// The row whose front misses most.
    pub(crate) worst_row: usize,
}

/// Every shape measure of a lattice that needs no target.
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    pub(crate) curvature: Vec<VertexCurvature>,
    /// Largest / smallest cell area.
    pub(crate) area_ratio: f64,
    /// Longest / shortest leg of the whole lattice.
    pub(crate) leg_ratio: f64,
    /// Shortest leg of the whole lattice (mm).
    pub min_leg: f64,
    /// Longest / shortest leg within a cell: the median and the largest.
    pub(crate) cell_leg_ratio_median: f64,
    pub(crate) cell_leg_ratio_max: f64,
    /// How far rebuilt fronts miss the rows they join; None for an extrinsic
    /// lattice.
    pub front_gaps: Option<FrontGaps>,
    /// Distinct strips (legs equal within `SAME_STRIP_MM`), and all strips.
    pub distinct_strips: usize,
    pub(crate) strips: usize,
}

/// The four corner angles of a cell, in corner order `[UL, UR, LL, LR]`,
/// from its own (planar) corners.
pub(crate) fn corner_angles(c: [DVec3; 4]) -> [f64; 4] {
    let [ul, ur, ll, lr] = c;
    let at = |p: DVec3, a: DVec3, b: DVec3| angle_between((a - p).normalize(), (b - p).normalize());
    [
        at(ul, ur, ll),
        at(ur, ul, lr),
        at(ll, ul, lr),
        at(lr, ur, ll),
    ]
}

/// Area of a cell: half the cross product of its diagonals (the rods cross,
/// so the quad is planar and convex).
pub(crate) fn cell_area(c: [DVec3; 4]) -> f64 {
    let [ul, ur, ll, lr] = c;
    0.5 * (lr - ul).cross(ll - ur).length()
}

impl Lattice {
    /// The angle defect and Gaussian curvature at every vertex shared by
    /// four cells, in vertex order.
    pub fn curvature(&self) -> Vec<VertexCurvature> {
        // vertex -> (cells seen, angle sum, area sum), indexed by vertex.
        let mut at: Vec<(u32, f64, f64)> = vec![(0, 0.0, 0.0); self.vertices.len()];
        for cell in &self.cells {
            let corners = self.corners(cell);
            let angles = corner_angles(corners);
            let area = cell_area(corners);
            for (v, a) in [cell.ul, cell.ur, cell.ll, cell.lr].into_iter().zip(angles) {
                let e = &mut at[v as usize];
                e.0 += 1;
                e.1 += a;
                e.2 += area;
            }
        }
        at.into_iter()
            .zip(0u32..)
            .map(|(e, v)| (v, e))
            .filter(|(_, (n, _, _))| *n == 4)
            .map(|(vertex, (_, sum, area))| {
                let defect = TAU - sum;
                let area = area / 4.0;
                VertexCurvature {
                    vertex,
                    defect,
                    area,
                    k: defect / area.max(f64::MIN_POSITIVE),
                }
            })
            .collect()
    }

    /// Every target-free shape measure.
    pub(crate) fn shape(&self) -> Shape {
        let mut areas = Vec::with_capacity(self.cells.len());
        let mut cell_ratios = Vec::with_capacity(self.cells.len());
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        let mut strips: Vec<(f64, f64)> = Vec::with_capacity(2 * self.cells.len());
        for cell in &self.cells {
            areas.push(cell_area(self.corners(cell)));
            let legs = self.legs(cell);
            let (l, h) = legs
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
            lo = lo.min(l);
            hi = hi.max(h);
            cell_ratios.push(h / l);
            let [l1, l2, l3, l4] = legs;
            // A strip turned end for end is the same strip.
            strips.push((l1.min(l3), l1.max(l3)));
            strips.push((l4.min(l2), l4.max(l2)));
        }
        let (amin, amax) = areas
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        cell_ratios.sort_by(f64::total_cmp);
        Shape {
            curvature: self.curvature(),
            area_ratio: amax / amin,
            leg_ratio: hi / lo,
            min_leg: lo,
            cell_leg_ratio_median: cell_ratios
                .get(cell_ratios.len() / 2)
                .copied()
                .unwrap_or(1.0),
            cell_leg_ratio_max: cell_ratios.last().copied().unwrap_or(1.0),
            front_gaps: self.front_gaps(),
            distinct_strips: distinct(&mut strips),
            strips: strips.len(),
        }
    }

    /// How far each rebuilt front misses its row (None for an extrinsic lattice).
    pub(crate) fn front_gaps(&self) -> Option<FrontGaps> {
        if self.extrinsic() {
            return None;
        }
        let (_, gaps) = self.placed_with_gaps();
        let mut out = FrontGaps {
            max: 0.0,
            mean: 0.0,
            max_rel: 0.0,
            mean_rel: 0.0,
            worst_row: 0,
        };
        let (mut n, mut sum, mut sum_rel) = (0usize, 0.0, 0.0);
        for (row, g) in gaps.iter().enumerate() {
            let Some(front) = self.fronts.get(row).filter(|f| !f.is_empty()) else {
                continue;
            };
            let edges = if self.kind == Kind::Loop {
                front.len()
            } else {
                front.len() - 1
            };
            let edge = (0..edges)
                .map(|j| front[j].distance(front[(j + 1) % front.len()]))
                .sum::<f64>()
                / edges.max(1) as f64;
            for &d in g {
                if d > out.max {
                    out.max = d;
                    out.worst_row = row;
                }
                out.max_rel = out.max_rel.max(d / edge);
                sum += d;
                sum_rel += d / edge;
                n += 1;
            }
        }
        out.mean = sum / n.max(1) as f64;
        out.mean_rel = sum_rel / n.max(1) as f64;
        Some(out)
    }
}

/// The number of distinct strips among `(short leg, long leg)` pairs.
fn distinct(strips: &mut [(f64, f64)]) -> usize {
    strips.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    // Greedy classes: a strip joins a class when both legs are within the
    // tolerance of the class's first strip.
    let mut classes: Vec<(f64, f64)> = Vec::new();
    for &(a, b) in strips.iter() {
        let found = classes
            .iter()
            .rev()
            .take_while(|c| a - c.0 <= SAME_STRIP_MM)
            .any(|c| (b - c.1).abs() <= SAME_STRIP_MM);
        if !found {
            classes.push((a, b));
        }
    }
    classes.len()
}

/// Summary statistics of the curvature, for reports and objectives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvatureSummary {
    /// Number of interior vertices measured.
    pub interior: usize,
    /// Defects in degrees.
    pub min_deg: f64,
    /// Mean angle defect (degrees).
    pub mean_deg: f64,
    /// Largest angle defect (degrees).
    pub max_deg: f64,
    /// Share of interior vertices with defect beyond +-`CURVED_DEG`.
    pub positive: f64,
    /// Share of interior vertices with defect below -`CURVED_DEG`.
    pub negative: f64,
    /// Mean and standard deviation of K (1/mm^2).
    pub k_mean: f64,
    /// Standard deviation of K over the interior vertices (1/mm^2).
    pub k_std: f64,
    /// Where the extremes are (indices into `Lattice::vertices`).
    pub(crate) min_at: u32,
    pub(crate) max_at: u32,
}

/// Defect and Gaussian-curvature statistics of the interior vertices `c`;
/// None when there are none.
pub fn summary(c: &[VertexCurvature]) -> Option<CurvatureSummary> {
    if c.is_empty() {
        return None;
    }
    let n = c.len() as f64;
    let deg: Vec<f64> = c.iter().map(|v| v.defect.to_degrees()).collect();
    let (mut min_i, mut max_i) = (0, 0);
    for i in 0..deg.len() {
        if deg[i] < deg[min_i] {
            min_i = i;
        }
        if deg[i] > deg[max_i] {
            max_i = i;
        }
    }
    let k_mean = c.iter().map(|v| v.k).sum::<f64>() / n;
    let k_var = c.iter().map(|v| (v.k - k_mean).powi(2)).sum::<f64>() / n;
    Some(CurvatureSummary {
        interior: c.len(),
        min_deg: deg[min_i],
        mean_deg: deg.iter().sum::<f64>() / n,
        max_deg: deg[max_i],
        positive: deg.iter().filter(|&&d| d > CURVED_DEG).count() as f64 / n,
        negative: deg.iter().filter(|&&d| d < -CURVED_DEG).count() as f64 / n,
        k_mean,
        k_std: k_var.sqrt(),
        min_at: c[min_i].vertex,
        max_at: c[max_i].vertex,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::{RowParams, grow};
    use crate::legs::{Direction, Leg};

    fn grid(rows: usize) -> Lattice {
        let points: Vec<DVec3> = (0..6)
            .map(|j| DVec3::new(40.0 * j as f64, 0.0, 0.0))
            .collect();
        let row = RowParams {
            direction: Some(Direction::Angles {
                angle_deg: 45.0,
                tilt_deg: 0.0,
            }),
            left_leg: Leg::Match,
            right_leg: Leg::Match,
            ..RowParams::default()
        };
        grow(Kind::Sheet, 2, &points, &[0.0; 5], &vec![row; rows]).unwrap()
    }

    #[test]
    fn a_planar_grid_is_flat_everywhere() {
        let lattice = grid(5);
        let c = lattice.curvature();
        // 4 interior rows of front vertices x 4 interior columns.
        assert_eq!(c.len(), 16);
        for v in &c {
            assert!(v.defect.abs() < 1e-12, "{v:?}");
            assert!(v.area > 0.0);
        }
        let s = lattice.shape();
        assert!((s.area_ratio - 1.0).abs() < 1e-9, "{}", s.area_ratio);
        assert_eq!(s.distinct_strips, 1);
        assert_eq!(s.strips, 50);
        assert!(s.front_gaps.is_none());
        let sum = summary(&c).unwrap();
        assert_eq!((sum.positive, sum.negative), (0.0, 0.0));
    }

    #[test]
    fn corner_angles_of_a_square_and_a_kite() {
        let sq = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, -2.0, 0.0),
            DVec3::new(2.0, -2.0, 0.0),
        ];
        for a in corner_angles(sq) {
            assert!((a - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        }
        assert!((cell_area(sq) - 4.0).abs() < 1e-12);
        let kite = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(3.0, 0.0, 0.0),
        ];
        let s: f64 = corner_angles(kite).iter().sum();
        assert!((s - TAU).abs() < 1e-12);
    }

    #[test]
    fn distinct_strips_merge_within_the_tolerance_only() {
        let mut s = vec![(10.0, 20.0), (10.04, 20.0), (10.0, 20.2), (10.1, 20.0)];
        assert_eq!(distinct(&mut s), 3);
    }
}
