//! The largest extent D of a point set: the largest distance between two
//! of its points, exactly. Points are binned in a grid; only pairs of bins
//! whose boxes could hold a farther pair than the best found are compared
//! point by point.

use glam::DVec3;

/// Up to this many points, every pair is compared.
const BRUTE: usize = 2048;
/// Bins per axis of the pruning grid.
const BINS: usize = 12;

/// The largest distance between two of `points` (0 for fewer than two).
pub(crate) fn diameter(points: &[DVec3]) -> f64 {
    if points.len() <= BRUTE {
        return brute(points, points);
    }
    let (lo, hi) = bounds(points);
    let size = (hi - lo).max(DVec3::splat(f64::MIN_POSITIVE));
    let bin = |p: DVec3| -> usize {
        let c = ((p - lo) / size * BINS as f64)
            .floor()
            .clamp(DVec3::ZERO, DVec3::splat((BINS - 1) as f64));
        (c.x as usize * BINS + c.y as usize) * BINS + c.z as usize
    };
    let mut bins: Vec<Vec<DVec3>> = vec![Vec::new(); BINS * BINS * BINS];
    for &p in points {
        bins[bin(p)].push(p);
    }
    bins.retain(|b| !b.is_empty());
    let boxes: Vec<(DVec3, DVec3)> = bins.iter().map(|b| bounds(b)).collect();
    let mut best = sweeps(points);
    // Pairs of bins that could beat it, farthest bound first.
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for a in 0..boxes.len() {
        for b in a..boxes.len() {
            let reach = far(boxes[a], boxes[b]);
            if reach > best {
                pairs.push((reach, a, b));
            }
        }
    }
    pairs.sort_by(|x, y| y.0.total_cmp(&x.0).then((x.1, x.2).cmp(&(y.1, y.2))));
    for (reach, a, b) in pairs {
        if reach <= best {
            break;
        }
        best = best.max(brute(&bins[a], &bins[b]));
    }
    best
}

fn bounds(points: &[DVec3]) -> (DVec3, DVec3) {
    points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    )
}

/// The largest distance between a point of box `a` and one of box `b`.
fn far(a: (DVec3, DVec3), b: (DVec3, DVec3)) -> f64 {
    (a.1 - b.0).abs().max((b.1 - a.0).abs()).length()
}

fn brute(a: &[DVec3], b: &[DVec3]) -> f64 {
    let mut best = 0.0f64;
    for p in a {
        for q in b {
            best = best.max(p.distance_squared(*q));
        }
    }
    best.sqrt()
}

/// A lower bound: from the first point to the farthest, and on, a few times.
fn sweeps(points: &[DVec3]) -> f64 {
    let mut from = points[0];
    let mut best = 0.0f64;
    for _ in 0..4 {
        let (far, d) = points
            .iter()
            .map(|&q| (q, from.distance(q)))
            .fold((from, 0.0), |m, x| if x.1 > m.1 { x } else { m });
        best = best.max(d);
        from = far;
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn the_pruned_diameter_is_the_brute_force_one() {
        let mut rng = Rng::new(7);
        for n in [1usize, 2, 50, 3000, 9000] {
            let points: Vec<DVec3> = (0..n)
                .map(|_| {
                    // Points near an ellipsoid's surface, where many pairs
                    // come close to the diameter.
                    let v = DVec3::new(rng.signed(), rng.signed(), rng.signed());
                    v.normalize_or_zero() * DVec3::new(300.0, 280.0, 50.0) + DVec3::X * 40.0
                })
                .collect();
            assert_eq!(diameter(&points), brute(&points, &points), "{n} points");
        }
    }
}
