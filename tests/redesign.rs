//! The examples redesigned with `karigami design` (issue 32 item 5;
//! docs/lattices.md, "Designed examples"): each must measured from the cut
//! geometry (the designed cells) and from the simulated deployed shape of
//! the gallery's shared build, by the functions below.

use crate::util::example;
use glam::DVec3;
use karigami::{Build, Lattice};

const BOWL: &str = "bowl";

/// A loop lattice's rings: each row's vertex positions in column order.
fn rings(l: &Lattice) -> Vec<Vec<DVec3>> {
    let rows = l
        .vertices
        .iter()
        .map(|v| v.key.row)
        .max()
        .map_or(0, |r| r + 1);
    let mut out = vec![Vec::new(); rows as usize];
    let mut keyed: Vec<_> = l
        .vertices
        .iter()
        .map(|v| (v.key.row, v.key.col, v.pos))
        .collect();
    keyed.sort_by_key(|&(r, c, _)| (r, c));
    for (r, _, p) in keyed {
        out[r as usize].push(p);
    }
    out
}

/// A closed ring's centroid and the unit normal of its mean plane
/// (Newell's), pointing the same way for every ring grown one way.
fn plane(ring: &[DVec3]) -> (DVec3, DVec3) {
    let c = ring.iter().sum::<DVec3>() / ring.len() as f64;
    let n: DVec3 = (0..ring.len())
        .map(|k| (ring[k] - c).cross(ring[(k + 1) % ring.len()] - c))
        .sum();
    (c, n.normalize())
}

/// A ring's mean radius about its own axis (the line through its centroid
/// along its normal) and its roundness, the largest departure of a radius
/// from the mean as a share of the mean (as `check` measures a helix's turns).
fn radius(ring: &[DVec3]) -> (f64, f64) {
    let (c, n) = plane(ring);
    let r: Vec<f64> = ring
        .iter()
        .map(|p| (*p - c).reject_from_normalized(n).length())
        .collect();
    let mean = r.iter().sum::<f64>() / r.len() as f64;
    let spread = r.iter().map(|x| (x - mean).abs()).fold(0.0, f64::max) / mean;
    (mean, spread)
}

/// Height over width: every vertex's span along the rim's axis, over the
/// largest distance between two vertices seen along that axis.
fn aspect(rings: &[Vec<DVec3>]) -> f64 {
    let (_, n) = plane(&rings[0]);
    let all: Vec<DVec3> = rings.iter().flatten().copied().collect();
    let h = all.iter().map(|p| p.dot(n));
    let height = h.clone().fold(f64::NEG_INFINITY, f64::max) - h.fold(f64::INFINITY, f64::min);
    let mut width: f64 = 0.0;
    for (k, a) in all.iter().enumerate() {
        for b in &all[k + 1..] {
            width = width.max((*a - *b).reject_from_normalized(n).length());
        }
    }
    height / width
}

/// The longest leg over the median leg, every leg of every cell.
fn leg_ratio(l: &Lattice) -> f64 {
    let mut legs: Vec<f64> = l.cells.iter().flat_map(|c| l.legs(c)).collect();
    legs.sort_by(f64::total_cmp);
    legs[legs.len() - 1] / legs[legs.len() / 2]
}

/// An extrinsic lattice with every vertex and pivot where the build's
/// simulation put them (as the preview shows it).
fn simulated(b: &Build) -> Lattice {
    assert!(b.lattice.extrinsic(), "cells read the vertices' positions");
    let points = karigami::viewer_scene(b).simulated.expect("simulated");
    let mut l = b.lattice.clone();
    let nv = l.vertices.len();
    for (v, vertex) in l.vertices.iter_mut().enumerate() {
        vertex.pos = points[v];
    }
    for (c, cell) in l.cells.iter_mut().enumerate() {
        cell.pivot = points[nv + c];
    }
    l
}

/// The smallest angle between a cell's two rods (degrees): its opening phi
/// (docs/math.md 1.3) or, near flat open, 180 deg less phi; either way a
/// cell whose rods nearly lie along one line.
fn min_opening(l: &Lattice) -> f64 {
    l.cells
        .iter()
        .map(|c| {
            let phi = l.phi(c).to_degrees();
            phi.min(180.0 - phi)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Each ring's mean Gaussian curvature K (angle defect over area) over its
/// interior vertices, ring by ring; and whether every one is negative.
fn ring_k(l: &Lattice) -> (Vec<f64>, bool) {
    let c = l.curvature();
    let rows = c
        .iter()
        .map(|v| l.vertex(v.vertex).key.row)
        .max()
        .map_or(0, |r| r + 1);
    let mut sum = vec![(0.0, 0usize); rows as usize];
    for v in &c {
        let s = &mut sum[l.vertex(v.vertex).key.row as usize];
        s.0 += v.k;
        s.1 += 1;
    }
    let k = sum
        .iter()
        .filter(|s| s.1 > 0)
        .map(|s| s.0 / s.1 as f64)
        .collect();
    (k, !c.is_empty() && c.iter().all(|v| v.defect < 0.0))
}

/// The largest ring-mean K over the smallest, in size.
fn k_ratio(k: &[f64]) -> f64 {
    let size = k.iter().map(|x| x.abs());
    size.clone().fold(0.0, f64::max) / size.fold(f64::INFINITY, f64::min)
}

/// The fit of a shape's vertices and cells to a target of the suite.
fn fit(l: &Lattice, target: &str) -> karigami::targets::Fit {
    let path = crate::cli::repo().join("fixtures/targets").join(target);
    let bytes = std::fs::read(&path).expect("target");
    let t = karigami::targets::read(target, &bytes, None).expect("reads");
    let facets: Vec<[u32; 4]> = l.cells.iter().map(|c| [c.ul, c.ur, c.lr, c.ll]).collect();
    let points: Vec<DVec3> = l.vertices.iter().map(|v| v.pos).collect();
    t.fit(&points, &facets)
}

/// Issue 32's goal for a simulated shape: rms at most 1.5 % of D, largest
/// at most 4 %, at least 85 % of the target's area within 3 % of D.
#[track_caller]
fn meets_the_goal(f: &karigami::targets::Fit, what: &str) {
    let (rms, largest) = (f.rms / f.extent, f.largest / f.extent);
    let covered = f.coverage.expect("facets");
    println!(
        "{what}: rms {:.2} %, largest {:.2} %, covered {:.1} %",
        100.0 * rms,
        100.0 * largest,
        100.0 * covered
    );
    assert!(
        rms <= 0.015 && largest <= 0.04 && covered >= 0.85,
        "{what}: {f:?}"
    );
}

/// The bowl's musts: lower than 0.75 of its width, every turn (a loop's
/// ring) round within 30 % about its own axis, the last turn at most 0.6
/// of the first's radius, the longest leg at most 4 x the median; on the
/// cut geometry and on the simulated shape.
#[test]
fn the_bowl_is_a_bowl_designed_and_simulated() {
    let b = example(BOWL);
    assert!(b.design.target.is_some(), "made by karigami design");
    for (what, l) in [("design", b.assembled.clone()), ("simulated", simulated(b))] {
        let rings = rings(&l);
        let turns: Vec<(f64, f64)> = rings.iter().map(|r| radius(r)).collect();
        let (first, last) = (turns[0].0, turns[turns.len() - 1].0);
        let round = turns.iter().map(|t| t.1).fold(0.0, f64::max);
        println!(
            "bowl {what}: height/width {:.3}, turns {turns:.1?}, roundness at most {round:.2e}, last/first {:.3}, legs max/median {:.2}",
            aspect(&rings),
            last / first,
            leg_ratio(&l)
        );
        assert!(aspect(&rings) <= 0.75, "{what}");
        assert!(turns.iter().all(|t| t.1 <= 0.30), "{what}: {turns:?}");
        assert!(last <= 0.6 * first, "{what}: {turns:?}");
        assert!(leg_ratio(&l) <= 4.0, "{what}");
    }
}

/// The bowl's simulated shape fits its target to issue 32's goal.
#[test]
fn the_bowls_simulated_shape_fits_its_target() {
    meets_the_goal(
        &fit(&simulated(example(BOWL)), "bowl.toml"),
        "bowl simulated",
    );
}

/// An annulus whose rims are level circles, a waisted band of constant
/// negative curvature (fixtures/targets/saddle-band.toml): the design
/// `karigami design` writes for it (fixtures/designs/saddle-band.toml, a
/// symmetric loop grown from one rim to the other) meets the saddle ring's
/// musts but one, on the cut geometry and on the simulated shape: every
/// interior vertex negative, ring-mean K within 1.6 x from ring to ring,
/// the longest leg at most 3 x the median, no opening under 20 deg, and the
/// simulated fit to issue 32's goal. The one it cannot meet: an extrinsic
/// loop has no rebuilt fronts to carry the curvature (docs/lattices.md,
/// "Designed examples").
#[test]
fn the_designed_saddle_band_is_negatively_curved_evenly() {
    let b = example("fixtures/designs/saddle-band.toml");
    assert!(b.design.target.is_some(), "made by karigami design");
    assert_eq!(b.design.kind, karigami::Kind::Loop);
    for (what, l) in [("design", b.lattice.clone()), ("simulated", simulated(b))] {
        let (k, negative) = ring_k(&l);
        println!(
            "band {what}: {} cells, ring-mean K {k:?}, ratio {:.2}, legs max/median {:.2}, smallest opening {:.1} deg",
            l.cells.len(),
            k_ratio(&k),
            leg_ratio(&l),
            min_opening(&l)
        );
        assert!(negative, "{what}: every interior vertex negative");
        assert!(k_ratio(&k) <= 1.6, "{what}: {k:?}");
        assert!(leg_ratio(&l) <= 3.0, "{what}");
        assert!(min_opening(&l) >= 20.0, "{what}");
    }
    meets_the_goal(&fit(&simulated(b), "saddle-band.toml"), "band simulated");
}

/// The mean angle defect of a lattice's interior vertices (degrees).
fn mean_defect(l: &Lattice) -> f64 {
    let c = l.curvature();
    c.iter().map(|v| v.defect.to_degrees()).sum::<f64>() / c.len() as f64
}

/// The saddle ring, whose rebuilt fronts carry its curvature
/// (examples/saddle-ring.toml; docs/lattices.md, "Designed examples"),
/// as `karigami design` writes it for fixtures/targets/saddle-ring.toml
/// at a 90 mm edge: a loop whose every front is laid again on a
/// hyperbolic paraboloid, four sub-units alike, keeping its edge lengths,
/// its rings polished (docs/design.md, "Polished rings"). It meets the
/// saddle ring's musts on the cut geometry and on the simulated shape:
/// every interior vertex negative, ring-mean K within 1.6 x from ring to
/// ring, the longest leg at most 3 x the median, no opening under 20 deg.
/// The fronts carry the curvature: the same rows grown on their fronts as
/// grown (none laid) are not negatively curved on average.
#[test]
fn the_saddle_rings_fronts_carry_negative_curvature() {
    let path = crate::cli::repo().join("examples/saddle-ring.toml");
    let text = std::fs::read_to_string(&path).expect("recipe");
    let d = karigami::parse(&text, "saddle-ring").expect("parses");
    let designed = d.grow().expect("grows");
    assert!(!designed.extrinsic(), "grown on rebuilt fronts");
    // Every front is laid on a saddle, four sub-units alike: each ring's
    // vertices keep their distances under the mirrors through vertices 1
    // and 1 + N/4 (j -> 2 - j) and the half turn (j -> j + N/2).
    let n = d.points.len();
    for (i, row) in d.rows.iter().enumerate() {
        let front = row.front.as_ref().expect("rebuilt");
        assert!(front.saddle.is_some(), "row {i}: laid on a saddle");
    }
    let rings = designed.vertices.iter().map(|v| v.key.row).max().unwrap() + 1;
    for r in 0..rings {
        let ring: Vec<glam::DVec3> = (0..n as u32)
            .map(|c| {
                designed
                    .vertices
                    .iter()
                    .find(|v| v.key.row == r && v.key.col == c)
                    .expect("vertex")
                    .pos
            })
            .collect();
        for map in [
            |j: usize, n: usize| (2 + n - j) % n,
            |j: usize, n: usize| (j + n / 2) % n,
        ] {
            for j in 0..n {
                for k in 0..n {
                    let (a, b) = (
                        ring[j].distance(ring[k]),
                        ring[map(j, n)].distance(ring[map(k, n)]),
                    );
                    assert!((a - b).abs() < 1e-6, "ring {r}: {j}-{k} {a} against {b}");
                }
            }
        }
    }
    let mut plain = d.clone();
    for row in &mut plain.rows {
        row.front = None;
    }
    let plain = plain.grow().expect("grows on plain fronts");
    let (laid, plain) = (mean_defect(&designed), mean_defect(&plain));
    println!("saddle ring: mean defect {laid:.3} deg rebuilt, {plain:.3} deg plain");
    assert!(plain > 0.0, "plain fronts curve negatively: {plain} deg");
    assert!(laid <= -0.25, "{laid}");
    let deploy = karigami::deploy::deployment(&designed);
    let m = &d.fabrication.material;
    let run =
        karigami::simulation::simulate(&designed, &deploy, m.width, m.thickness, &d.simulation)
            .expect("simulates");
    // The state solved from the design, which is the one `build` reports
    // (its deployment path comes back to it).
    assert!(run.equilibrium.stats.lambda_min > 0.0, "stable");
    let simulated = karigami::simulation::placed_lattice(&designed, &run.lm);
    for (what, l) in [("design", &designed), ("simulated", &simulated)] {
        let (k, negative) = ring_k(l);
        println!(
            "saddle ring {what}: mean defect {:.2} deg, ring-mean K {k:?}, ratio {:.2}, legs max/median {:.2}, smallest opening {:.1} deg",
            mean_defect(l),
            k_ratio(&k),
            leg_ratio(l),
            min_opening(l)
        );
        assert!(negative, "{what}: every interior vertex negative");
        assert!(k_ratio(&k) <= 1.6, "{what}: {k:?}");
        assert!(leg_ratio(l) <= 3.0, "{what}");
        assert!(min_opening(l) >= 20.0, "{what}");
    }
}

/// A saddle front the recipe gets wrong is refused with what to change:
/// three amplitudes where one or two go, one not finite, and a saddle too
/// steep for the front to be laid on keeping its edges.
#[test]
fn a_saddle_front_given_wrong_is_refused() {
    let recipe = |saddle: &str| {
        format!(
            "[lattice]\nseed = \"loop\"\nkappa = 0.0\n\n[lattice.circle]\ncenter = [0.0, 0.0, 0.0]\nradius = 60.0\npoints = 12\n\n[[lattice.rows]]\nangle = [44.0, 23.0]\nfront = {{ saddle = {saddle} }}\n"
        )
    };
    let e = karigami::parse(&recipe("[0.001, 0.0, 0.0]"), "s").expect_err("three");
    assert!(
        e.message.contains(
            "front.saddle of row 0 has 3 amplitudes, but takes one or two finite amplitudes"
        ),
        "{}",
        e.message
    );
    assert_eq!(e.kind, karigami::ErrorKind::FrontSaddleAmplitudes);
    assert!(e.span.is_some(), "located");
    let e = karigami::parse(&recipe("nan"), "s").expect_err("nan");
    assert!(
        e.message.contains("not a finite number") && e.span.is_some(),
        "{}",
        e.message
    );
    let steep = karigami::parse(&recipe("1.0"), "s").expect("parses");
    let e = steep.grow().expect_err("too steep to lay");
    assert!(e.message.contains("front.saddle"), "{}", e.message);
    let fine = karigami::parse(&recipe("[0.003, -1e-5]"), "s").expect("parses");
    assert!(!fine.grow().expect("grows").extrinsic());
}

/// A front's turn, bend or twist given no angle is refused naming the row
/// it is given for, with line and column.
#[test]
fn a_front_with_no_angle_names_its_row() {
    let recipe = "[lattice]\nseed = \"loop\"\nkappa = 0.0\n\n[lattice.circle]\ncenter = [0.0, 0.0, 0.0]\nradius = 60.0\npoints = 12\n\n[[lattice.rows]]\nangle = [44.0, 23.0]\n\n[[lattice.rows]]\nangle = [44.0, 23.0]\nfront = { bend = [] }\n";
    let e = karigami::parse(recipe, "s").expect_err("no angle");
    assert_eq!(e.kind, karigami::ErrorKind::FrontAnglesNotFinite);
    assert!(
        e.message
            .contains("front.bend of row 1 needs finite angles"),
        "{}",
        e.message
    );
    assert_eq!(e.site.as_deref(), Some("row 1"));
    assert!(e.span.is_some(), "located");
}
