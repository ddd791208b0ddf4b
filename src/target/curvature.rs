//! The target's tightest bend at the scale of a cell (docs/design.md,
//! "Curvature the strips reach"): the largest normal curvature between two
//! points of the surface `scale / 2` to `scale` apart. For two points of a
//! circle or sphere of radius R with their unit normals, (n_q - n_p) .
//! (q - p) / |q - p|^2 is exactly 1 / R at any distance, so the estimate is
//! the curvature of a smooth target and, over a crease or a mesh's facets
//! finer than a cell, the bend a strip spanning it would take.

use super::Target;
use glam::DVec3;
use rustc_hash::FxHashMap;

/// The tightest bend found: its curvature (1/mm) and where (in the
/// target's frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bend {
    /// 1/mm: one over the radius.
    pub curvature: f64,
    /// Midway between the two points that bend most.
    pub at: DVec3,
}

impl Target {
    /// The largest normal curvature over distances of `scale / 2` to
    /// `scale` (mm): between one corner off the boundary of each bin of
    /// `scale / 2`, with the area-weighted normals of the mesh oriented
    /// consistently.
    pub fn tightest_bend(&self, scale: f64) -> Bend {
        let normals = self.vertex_normals();
        let bin = scale / 2.0;
        let key = |p: DVec3| {
            let k = (p / bin).floor();
            [k.x as i64, k.y as i64, k.z as i64]
        };
        // The lowest-numbered corner of each bin (deterministic) off the
        // boundary, where a corner's triangles lie all on one side and
        // tilt its normal.
        let rim = self.mesh.on_boundary();
        let mut firsts: FxHashMap<[i64; 3], usize> = FxHashMap::default();
        for (i, &p) in self.mesh.positions.iter().enumerate() {
            if !rim[i] {
                firsts.entry(key(p)).or_insert(i);
            }
        }
        let mut bins: Vec<([i64; 3], usize)> = firsts.iter().map(|(&k, &i)| (k, i)).collect();
        bins.sort_unstable();
        let mut best = Bend {
            curvature: 0.0,
            at: DVec3::ZERO,
        };
        for &(k, i) in &bins {
            let (p, np) = (self.mesh.positions[i], normals[i]);
            for dk in near(2) {
                let Some(&j) = firsts.get(&[k[0] + dk[0], k[1] + dk[1], k[2] + dk[2]]) else {
                    continue;
                };
                let (q, nq) = (self.mesh.positions[j], normals[j]);
                let d2 = p.distance_squared(q);
                if d2 < bin * bin || d2 > scale * scale {
                    continue;
                }
                let c = ((nq - np).dot(q - p) / d2).abs();
                if c > best.curvature {
                    best = Bend {
                        curvature: c,
                        at: 0.5 * (p + q),
                    };
                }
            }
        }
        best
    }

    /// Unit normals at the corners: each triangle's normal weighted by its
    /// angle at the corner (even where a corner's triangles are uneven, as
    /// round a cap's apex), the triangles turned to one orientation across
    /// their shared edges (`orientation`).
    fn vertex_normals(&self) -> Vec<DVec3> {
        let m = &self.mesh;
        let flip = orientation(&m.triangles);
        let mut n = vec![DVec3::ZERO; m.positions.len()];
        for (t, tri) in m.triangles.iter().enumerate() {
            let c = m.corners(t);
            let sign = if flip[t] { -1.0 } else { 1.0 };
            let normal = sign * (c[1] - c[0]).cross(c[2] - c[0]).normalize_or_zero();
            for k in 0..3 {
                let angle = (c[(k + 1) % 3] - c[k]).angle_between(c[(k + 2) % 3] - c[k]);
                n[tri[k] as usize] += angle * normal;
            }
        }
        n.into_iter().map(|v| v.normalize_or_zero()).collect()
    }
}

impl super::Mesh {
    /// Whether each corner lies on the boundary (an edge of one triangle).
    fn on_boundary(&self) -> Vec<bool> {
        let mut rim = vec![false; self.positions.len()];
        for l in self.boundary_loops() {
            for v in l {
                rim[v as usize] = true;
            }
        }
        rim
    }
}

/// The bin offsets within `r` bins each way.
fn near(r: i64) -> impl Iterator<Item = [i64; 3]> {
    (-r..=r).flat_map(move |x| (-r..=r).flat_map(move |y| (-r..=r).map(move |z| [x, y, z])))
}

/// Which triangles to turn over so that every two sharing an edge run it
/// opposite ways (a mesh file need not say its triangles alike): a walk
/// across the edges from the first triangle of each piece. A surface that
/// cannot be oriented (a Moebius band) keeps the walk's choice.
fn orientation(triangles: &[[u32; 3]]) -> Vec<bool> {
    let mut by_edge: FxHashMap<(u32, u32), Vec<(usize, bool)>> = FxHashMap::default();
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            by_edge
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push((t, a < b));
        }
    }
    let mut flip = vec![false; triangles.len()];
    let mut seen = vec![false; triangles.len()];
    let mut stack = Vec::new();
    for start in 0..triangles.len() {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        while let Some(t) = stack.pop() {
            let tri = triangles[t];
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let runs_up = (a < b) != flip[t];
                for &(n, up) in &by_edge[&(a.min(b), a.max(b))] {
                    if !seen[n] {
                        seen[n] = true;
                        // n runs the edge the other way once turned.
                        flip[n] = up == runs_up;
                        stack.push(n);
                    }
                }
            }
        }
    }
    flip
}

#[cfg(test)]
mod tests {
    fn target(text: &str) -> super::Target {
        crate::target::read("t.toml", text.as_bytes(), None).unwrap()
    }

    /// A sphere cap and a cylinder bend to their radius (within 2 %: the
    /// corners' normals of a mesh), a disk not at all, at any scale under
    /// the target's size.
    #[test]
    fn a_smooth_target_bends_to_its_radius() {
        let cap = target("[target]\nfamily = \"sphere-cap\"\nradius = 200.0\nheight = 80.0\n");
        let vault = target(
            "[target]\nfamily = \"cylinder\"\nradius = 25.0\nlength = 300.0\nangle = 180.0\n",
        );
        for scale in [30.0, 60.0] {
            let r = 1.0 / cap.tightest_bend(scale).curvature;
            assert!((r - 200.0).abs() < 4.0, "{scale}: {r}");
            let r = 1.0 / vault.tightest_bend(scale).curvature;
            assert!((r - 25.0).abs() < 0.5, "{scale}: {r}");
            println!(
                "scale {scale}: cap {:.1}, vault {r:.2}",
                1.0 / cap.tightest_bend(scale).curvature
            );
        }
        let disk = target("[target]\nfamily = \"disk\"\nradius = 200.0\n");
        assert!(disk.tightest_bend(60.0).curvature < 1e-9);
    }

    /// A crease finer than the scale is the bend over the scale: a
    /// revolution's profile turning 55 degrees at a corner.
    #[test]
    fn a_crease_bends_over_the_scale() {
        let t = target(
            "[target]\nfamily = \"revolution\"\nprofile = [[0.0, 0.0], [150.0, 20.0], [220.0, 90.0], [200.0, 200.0], [230.0, 300.0]]\n",
        );
        let r60 = 1.0 / t.tightest_bend(60.0).curvature;
        let r30 = 1.0 / t.tightest_bend(30.0).curvature;
        println!("revolution: {r30:.1} mm over 30 mm, {r60:.1} over 60");
        assert!(r60 > 40.0 && r60 < 200.0, "{r60}");
        assert!(r30 < r60, "{r30} {r60}");
    }

    /// Triangles written with either orientation give the same normals.
    #[test]
    fn the_triangles_are_turned_to_one_orientation() {
        let tris = [[0, 1, 2], [1, 3, 2], [3, 4, 2]];
        let mixed = [[0, 1, 2], [2, 3, 1], [3, 4, 2]];
        let flip = super::orientation(&mixed);
        assert_eq!(flip, [false, true, false]);
        assert_eq!(super::orientation(&tris), [false; 3]);
    }
}
