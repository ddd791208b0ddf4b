//! How much of a target a set of quad facets covers (docs/design.md): the
//! target sampled by area, deterministically, and each sample counted
//! covered when a facet comes within the tolerance of it.

use super::Target;
use super::bvh::Bvh;
use glam::DVec3;

/// About this many samples over the whole target.
const SAMPLES: f64 = 40_000.0;
/// Sub-triangles per side of one target triangle at most.
const MAX_SPLIT: usize = 64;

/// Share of the target's area within `within` (mm) of the facets: quads of
/// indices into `points`, in order round each (non-planar ones split along
/// the first diagonal).
pub(crate) fn covered(target: &Target, points: &[DVec3], facets: &[[u32; 4]], within: f64) -> f64 {
    covered_part(target, (points, facets), within, None)
}

/// The share of the target's triangles marked in `part` (all when None)
/// within `within` (mm) of the facets, by area, as `covered` counts it.
pub(crate) fn covered_part(
    target: &Target,
    (points, facets): (&[DVec3], &[[u32; 4]]),
    within: f64,
    part: Option<&[bool]>,
) -> f64 {
    let triangles: Vec<[u32; 3]> = facets
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .filter(|t| {
            let [a, b, c] = t.map(|i| points.get(i as usize).copied().unwrap_or(DVec3::NAN));
            let n = (b - a).cross(c - a).length();
            n.is_finite() && n > 0.0
        })
        .collect();
    let tree = Bvh::new(points, &triangles);
    let mesh = &target.mesh;
    let spacing = target.area / SAMPLES;
    let (mut near, mut total) = (0.0, 0.0);
    for t in 0..mesh.triangles.len() {
        if part.is_some_and(|p| !p.get(t).copied().unwrap_or(false)) {
            continue;
        }
        let area = mesh.triangle_area(t);
        let k = ((area / spacing).sqrt().ceil() as usize).clamp(1, MAX_SPLIT);
        let weight = area / (k * k) as f64;
        for p in samples(mesh.corners(t), k) {
            total += weight;
            if tree
                .closest(points, &triangles, p, within * within)
                .is_some()
            {
                near += weight;
            }
        }
    }
    if total > 0.0 { near / total } else { 0.0 }
}

/// The centroids of the k^2 equal sub-triangles of a triangle split k
/// times along each side.
fn samples([a, b, c]: [DVec3; 3], k: usize) -> impl Iterator<Item = DVec3> {
    let (u, v) = ((b - a) / k as f64, (c - a) / k as f64);
    (0..k).flat_map(move |i| {
        (0..k - i).flat_map(move |j| {
            let corner = a + u * i as f64 + v * j as f64;
            let up = corner + (u + v) / 3.0;
            // The downward sub-triangle beside it, where there is one.
            let down = (i + j + 1 < k).then(|| corner + (u + v) * (2.0 / 3.0));
            std::iter::once(up).chain(down)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_split_triangle_has_k_squared_samples_centred_on_its_centroid() {
        let t = [DVec3::ZERO, DVec3::X * 3.0, DVec3::Y * 3.0];
        for k in 1..6 {
            let s: Vec<DVec3> = samples(t, k).collect();
            assert_eq!(s.len(), k * k);
            let mean = s.iter().sum::<DVec3>() / s.len() as f64;
            assert!(mean.distance(DVec3::new(1.0, 1.0, 0.0)) < 1e-12);
        }
    }
}
