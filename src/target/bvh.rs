//! A bounding-volume hierarchy of triangles for closest-point queries: a
//! binary tree of boxes split at the median of the longest axis, leaves of
//! a few triangles. Memory is bounded by the triangles: fewer than two
//! nodes per leaf, one index per triangle.

use glam::DVec3;

/// Triangles per leaf at most.
const LEAF: usize = 4;

#[derive(Clone, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// A leaf: its triangles are `order[start..start + count]`; else its
    /// children are nodes `start` and `start + 1`.
    start: u32,
    count: u32,
}

#[derive(Clone, Debug, Default)]
pub(crate) struct Bvh {
    nodes: Vec<Node>,
    /// Triangle indices, leaf by leaf.
    order: Vec<u32>,
}

impl Bvh {
    pub(crate) fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> Self {
        let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
        let centre = |t: u32| -> DVec3 {
            triangles[t as usize]
                .iter()
                .map(|&i| positions[i as usize])
                .sum::<DVec3>()
                / 3.0
        };
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * triangles.len() / LEAF + 1),
            order: Vec::new(),
        };
        if triangles.is_empty() {
            return bvh;
        }
        bvh.nodes.push(node_of(positions, triangles, &order, 0));
        // Split nodes breadth first; each split appends the two children.
        let mut next = 0;
        while next < bvh.nodes.len() {
            let (start, count) = (
                bvh.nodes[next].start as usize,
                bvh.nodes[next].count as usize,
            );
            if count > LEAF {
                let slice = &mut order[start..start + count];
                let (lo, hi) = slice.iter().fold(
                    (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                    |(lo, hi), &t| (lo.min(centre(t)), hi.max(centre(t))),
                );
                let axis = (hi - lo).max_position();
                let half = count / 2;
                slice.select_nth_unstable_by(half, |&a, &b| {
                    centre(a)[axis].total_cmp(&centre(b)[axis]).then(a.cmp(&b))
                });
                let first = bvh.nodes.len() as u32;
                let left = node_of(positions, triangles, &order[start..start + half], start);
                let right = node_of(
                    positions,
                    triangles,
                    &order[start + half..start + count],
                    start + half,
                );
                bvh.nodes.push(left);
                bvh.nodes.push(right);
                bvh.nodes[next].start = first;
                bvh.nodes[next].count = 0;
            }
            next += 1;
        }
        bvh.order = order;
        bvh
    }

    /// The closest point of the triangles to `p` and its squared distance,
    /// if one lies within `sqrt(limit)`.
    pub(crate) fn closest(
        &self,
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        p: DVec3,
        limit: f64,
    ) -> Option<(DVec3, f64)> {
        let mut best: Option<(DVec3, f64)> = None;
        let mut bound = limit;
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        if !self.nodes.is_empty() {
            stack.push(0);
        }
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if box_distance2(node, p) > bound {
                continue;
            }
            if node.count > 0 {
                let (s, c) = (node.start as usize, node.count as usize);
                for &t in &self.order[s..s + c] {
                    let [a, b, c] = triangles[t as usize].map(|i| positions[i as usize]);
                    let q = closest_on_triangle(p, a, b, c);
                    let d2 = p.distance_squared(q);
                    if d2 <= bound && best.is_none_or(|(_, b)| d2 < b) {
                        best = Some((q, d2));
                        bound = d2;
                    }
                }
            } else {
                // The nearer child is searched first (pushed last).
                let (l, r) = (node.start, node.start + 1);
                let (dl, dr) = (
                    box_distance2(&self.nodes[l as usize], p),
                    box_distance2(&self.nodes[r as usize], p),
                );
                if dl <= dr {
                    stack.push(r);
                    stack.push(l);
                } else {
                    stack.push(l);
                    stack.push(r);
                }
            }
        }
        best
    }
}

impl Bvh {
    /// The first `t` in `(tmin, limit)` where the ray `p + t v` meets a
    /// triangle (Moeller-Trumbore), nearest first; None when it misses.
    pub(crate) fn ray(
        &self,
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        p: DVec3,
        v: DVec3,
        tmin: f64,
        limit: f64,
    ) -> Option<f64> {
        let mut best = limit;
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        if !self.nodes.is_empty() {
            stack.push(0);
        }
        let inv = v.recip();
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if !box_hit(node, p, inv, best) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.start);
                stack.push(node.start + 1);
                continue;
            }
            let (s, c) = (node.start as usize, node.count as usize);
            for &t in &self.order[s..s + c] {
                let [a, b, c] = triangles[t as usize].map(|i| positions[i as usize]);
                if let Some(h) = ray_triangle(p, v, a, b, c)
                    && h > tmin
                    && h < best
                {
                    best = h;
                }
            }
        }
        (best < limit).then_some(best)
    }
}

/// Whether the ray `p + t v` (`inv` = 1 / v) enters the node's box before
/// `tmax` (the slab test; a zero component gives infinities that compare right).
fn box_hit(node: &Node, p: DVec3, inv: DVec3, tmax: f64) -> bool {
    let (mut lo, mut hi) = (0.0f64, tmax);
    for k in 0..3 {
        let (a, b) = ((node.lo[k] - p[k]) * inv[k], (node.hi[k] - p[k]) * inv[k]);
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        // NaN (0 * inf, a ray in the slab's plane) keeps the interval.
        if a > lo {
            lo = a;
        }
        if b < hi {
            hi = b;
        }
    }
    lo <= hi
}

/// The ray parameter where `p + t v` crosses triangle abc (Moeller and
/// Trumbore), None when it misses or runs parallel to it.
fn ray_triangle(p: DVec3, v: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let h = v.cross(e2);
    let det = e1.dot(h);
    if det.abs() <= 1e-12 * e1.length() * e2.length() * v.length() {
        return None;
    }
    let s = p - a;
    let u = s.dot(h) / det;
    if !(-1e-12..=1.0 + 1e-12).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let w = v.dot(q) / det;
    if w < -1e-12 || u + w > 1.0 + 1e-12 {
        return None;
    }
    Some(e2.dot(q) / det)
}

fn node_of(positions: &[DVec3], triangles: &[[u32; 3]], tris: &[u32], start: usize) -> Node {
    let (lo, hi) = tris
        .iter()
        .flat_map(|&t| triangles[t as usize])
        .map(|i| positions[i as usize])
        .fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), q| (lo.min(q), hi.max(q)),
        );
    Node {
        lo,
        hi,
        start: start as u32,
        count: tris.len() as u32,
    }
}

fn box_distance2(node: &Node, p: DVec3) -> f64 {
    let d = (node.lo - p).max(p - node.hi).max(DVec3::ZERO);
    d.length_squared()
}

/// The point of triangle abc closest to p (Ericson, Real-Time Collision
/// Detection 5.1.5: by the Voronoi region of p).
pub(crate) fn closest_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closest_point_is_on_the_triangle_and_no_corner_is_nearer() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X * 2.0, DVec3::Y * 2.0);
        // Above the face: straight down.
        assert_eq!(
            closest_on_triangle(DVec3::new(0.5, 0.5, 3.0), a, b, c),
            DVec3::new(0.5, 0.5, 0.0)
        );
        // Beyond an edge and beyond a corner.
        assert_eq!(
            closest_on_triangle(DVec3::new(1.0, -1.0, 0.0), a, b, c),
            DVec3::X
        );
        assert_eq!(closest_on_triangle(DVec3::new(-1.0, -1.0, 1.0), a, b, c), a);
        assert_eq!(
            closest_on_triangle(DVec3::new(2.0, 2.0, 0.0), a, b, c),
            DVec3::new(1.0, 1.0, 0.0)
        );
    }
}

#[cfg(test)]
mod property {
    use super::*;
    use crate::rng::Rng;

    fn random_point(rng: &mut Rng, scale: f64) -> DVec3 {
        DVec3::new(rng.signed(), rng.signed(), rng.signed()) * scale
    }

    /// The tree's first hit is the brute-force nearest crossing.
    #[test]
    fn the_tree_finds_the_brute_force_first_ray_hit() {
        let mut rng = Rng::new(7);
        let positions: Vec<DVec3> = (0..60).map(|_| random_point(&mut rng, 100.0)).collect();
        let triangles: Vec<[u32; 3]> = (0..20).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
        let bvh = Bvh::new(&positions, &triangles);
        for _ in 0..200 {
            let (p, v) = (random_point(&mut rng, 100.0), random_point(&mut rng, 1.0));
            let brute = triangles
                .iter()
                .filter_map(|t| {
                    let [a, b, c] = t.map(|i| positions[i as usize]);
                    ray_triangle(p, v, a, b, c).filter(|&h| h > 0.0)
                })
                .fold(None, |m: Option<f64>, h| Some(m.map_or(h, |m| m.min(h))));
            assert_eq!(
                bvh.ray(&positions, &triangles, p, v, 0.0, f64::INFINITY),
                brute
            );
        }
    }

    #[test]
    fn the_tree_finds_the_brute_force_closest_point_on_random_meshes() {
        let mut rng = Rng::new(11);
        for case in 0..40 {
            let n = 1 + rng.next_u64() as usize % 300;
            let positions: Vec<DVec3> = (0..3 * n).map(|_| random_point(&mut rng, 200.0)).collect();
            let triangles: Vec<[u32; 3]> = (0..n as u32)
                .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
                .collect();
            let tree = Bvh::new(&positions, &triangles);
            for _ in 0..50 {
                let p = random_point(&mut rng, 400.0);
                let brute = triangles
                    .iter()
                    .map(|t| {
                        let [a, b, c] = t.map(|i| positions[i as usize]);
                        p.distance_squared(closest_on_triangle(p, a, b, c))
                    })
                    .fold(f64::INFINITY, f64::min);
                let (q, d2) = tree
                    .closest(&positions, &triangles, p, f64::INFINITY)
                    .unwrap();
                assert!(
                    (d2 - brute).abs() <= 1e-9 * brute.max(1.0),
                    "case {case}: {d2} vs {brute}"
                );
                assert!((p.distance_squared(q) - d2).abs() <= 1e-9 * d2.max(1.0));
            }
        }
    }

    #[test]
    fn no_sampled_point_of_a_triangle_is_nearer_than_its_closest_point() {
        let mut rng = Rng::new(12);
        for _ in 0..200 {
            let [a, b, c] = [0; 3].map(|_| random_point(&mut rng, 100.0));
            let p = random_point(&mut rng, 200.0);
            let d = p.distance(closest_on_triangle(p, a, b, c));
            let k = 40;
            for i in 0..=k {
                for j in 0..=k - i {
                    let (s, t) = (i as f64 / k as f64, j as f64 / k as f64);
                    let q = a + (b - a) * s + (c - a) * t;
                    assert!(p.distance(q) >= d - 1e-9);
                }
            }
        }
    }
}
