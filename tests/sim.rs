//! The elastic simulation (docs/physics.md) against analytic beams, finite
//! differences, ideal linkages and the reference numbers of the model's
//! specification.

use glam::{DVec2, DVec3};
use karigami::testing::perturb;
use karigami::{Lattice, deploy::configuration};
use karigami::{
    simulation as sim,
    simulation::{Actuation, Material, Settings, VertexJoint, kabsch_distance},
};
use karigami_rods::model::Model;
use karigami_rods::model::Node;
use karigami_rods::model::Stencil;
use karigami_rods::rng::Rng;
use karigami_rods::solver::Options;
use karigami_rods::solver::System;
use karigami_rods::solver::solve;

fn abs_section() -> karigami::simulation::Section {
    karigami::simulation::section(&Material::ABS, 10.0, 1.0)
}

/// Nodes at s = (j - 1/2) h, j = 0..=n, along x.
fn straight(n: usize, h: f64) -> Vec<DVec3> {
    (0..=n)
        .map(|j| DVec3::new((j as f64 - 0.5) * h, 0.0, 0.0))
        .collect()
}

/// Clamp edge 0: its two nodes and its material angle.
fn clamp_first(m: &mut Model) {
    m.fix_node(0);
    m.fix_node(1);
    let t = m.theta_var(0).unwrap();
    m.fixed[t] = true;
}

fn node_var(m: &Model, node: usize) -> usize {
    match m.nodes[node] {
        Node::Free(v) => v,
        _ => panic!("free node"),
    }
}

fn equilibrate(m: &mut Model) -> karigami::simulation::Stats {
    let sys = System::new(m);
    let stats = solve(m, &sys, &Options::default()).expect("solves");
    assert!(stats.converged, "converged: {stats:?}");
    stats
}

fn cantilever_tip(p: f64) -> (f64, usize) {
    let (l, n) = (200.0, 20);
    let h = l / (n as f64 - 0.5);
    let mut m = Model::strip(abs_section(), &straight(n, h), DVec3::Z);
    clamp_first(&mut m);
    m.stencils.push(Stencil::Load {
        node: n,
        force: DVec3::new(0.0, 0.0, p),
    });
    let stats = equilibrate(&mut m);
    (m.pos(n).z, stats.iterations)
}

#[test]
fn cantilever_tip_load_matches_the_beam_formula() {
    let b = abs_section().b_flat;
    for p in [0.001, 0.01] {
        let (tip, iterations) = cantilever_tip(p);
        let linear = p * 200f64.powi(3) / (3.0 * b);
        let ratio = tip / linear;
        assert!(
            (ratio - 1.0).abs() < 0.01,
            "P = {p}: tip {tip} vs {linear} ({ratio})"
        );
        assert!(iterations <= 15, "{iterations} Newton iterations");
    }
    // The prototype's figure at N = 20, P = 0.01 N: 14.4572 mm.
    let (tip, _) = cantilever_tip(0.01);
    assert!((tip - 14.4572).abs() < 2e-3, "tip {tip}");
}

/// Least-squares circle through points in the x-z plane: (centre, radius, residual).
fn fit_circle(points: &[DVec3]) -> (DVec2, f64, f64) {
    // x^2 + z^2 + D x + E z + F = 0, normal equations.
    let mut a = [[0.0f64; 3]; 3];
    let mut r = [0.0f64; 3];
    for p in points {
        let row = [p.x, p.z, 1.0];
        let rhs = -(p.x * p.x + p.z * p.z);
        for i in 0..3 {
            for j in 0..3 {
                a[i][j] += row[i] * row[j];
            }
            r[i] += row[i] * rhs;
        }
    }
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    let mut sol = [0.0; 3];
    for k in 0..3 {
        let mut m = a;
        for i in 0..3 {
            m[i][k] = r[i];
        }
        sol[k] = det(m) / d;
    }
    let c = DVec2::new(-sol[0] / 2.0, -sol[1] / 2.0);
    let radius = (c.length_squared() - sol[2]).sqrt();
    let residual = points
        .iter()
        .map(|p| ((DVec2::new(p.x, p.z) - c).length() - radius).abs())
        .fold(0.0, f64::max);
    (c, radius, residual)
}

#[test]
fn end_moment_bends_an_arc_of_radius_ei_over_m() {
    let (l, n) = (200.0, 20);
    let h = l / (n as f64 - 0.5);
    let sec = abs_section();
    let moment = sec.b_flat * std::f64::consts::FRAC_PI_2 / l;
    let mut m = Model::strip(sec, &straight(n, h), DVec3::Z);
    clamp_first(&mut m);
    let last = m.edges.len() - 1;
    m.stencils.push(Stencil::Moment {
        edge: last,
        m: -moment,
    });
    let stats = equilibrate(&mut m);
    let points: Vec<DVec3> = (0..=n).map(|k| m.pos(k)).collect();
    let (_, radius, residual) = fit_circle(&points);
    let expected = sec.b_flat / moment;
    let ratio = radius / expected;
    assert!(
        (ratio - 1.0).abs() < 0.01,
        "R {radius} vs {expected} ({ratio})"
    );
    assert!(
        (ratio - 1.0024).abs() < 5e-4,
        "the prototype's 1.0024, got {ratio}"
    );
    assert!(residual < 1e-6, "nodes off the circle by {residual}");
    assert!(stats.iterations <= 20, "{} iterations", stats.iterations);
}

#[test]
fn twist_torque_is_gj_phi_over_l() {
    let sec = abs_section();
    for (n, phi_deg) in [(5, 22.5f64), (20, 90.0)] {
        let h = 10.0;
        let mut m = Model::strip(sec, &straight(n, h), DVec3::Z);
        clamp_first(&mut m);
        m.fix_node(n - 1);
        m.fix_node(n);
        let last = m.theta_var(m.edges.len() - 1).unwrap();
        let phi = phi_deg.to_radians();
        m.q[last] = phi;
        m.fixed[last] = true;
        let mut rng = Rng::new(3);
        for k in 2..n - 1 {
            let v = node_var(&m, k);
            for a in 0..3 {
                m.q[v + a] += 0.3 * rng.normal();
            }
        }
        equilibrate(&mut m);
        let sys = System::new(&m);
        let (_, g, _) = sys.assemble(&m);
        let length = (n - 1) as f64 * h;
        let expected = sec.gj * phi / length;
        let rel = (g[last] - expected).abs() / expected;
        assert!(
            rel < 1e-6,
            "N = {n}, phi = {phi_deg}: torque {} vs {expected}",
            g[last]
        );
    }
    // The prototype's 19.9879 N mm at 90 degrees over 200 mm.
    let expected = sec.gj * std::f64::consts::FRAC_PI_2 / 200.0;
    assert!((expected - 19.9879).abs() < 1e-3, "{expected}");
}

#[test]
fn clamped_strip_pushed_2mm_shorter_has_two_mirror_states() {
    let (l, n, push) = (200.0, 40, 2.0);
    // Edges 0 and n-1 clamped, their midpoints l apart.
    let h = l / (n as f64 - 1.0);
    let mut base = Model::strip(abs_section(), &straight(n, h), DVec3::Z);
    clamp_first(&mut base);
    for k in [n - 1, n] {
        let v = node_var(&base, k);
        base.q[v] -= push;
        base.fix_node(k);
    }
    let last = base.theta_var(base.edges.len() - 1).unwrap();
    base.fixed[last] = true;
    // Interior nodes compressed uniformly: the straight saddle.
    for k in 2..n - 1 {
        let v = node_var(&base, k);
        base.q[v] -= push * (k as f64 - 1.0) / (n as f64 - 2.0);
    }
    let sys = System::new(&base);
    let mut found: Vec<(f64, f64, usize)> = Vec::new();
    for seed in 0..12u64 {
        let mut m = base.clone();
        let amplitude = [0.0, 1.0, 3.0][seed as usize % 3];
        if amplitude > 0.0 {
            perturb(&mut m, 100 + seed, amplitude);
        }
        let stats = solve(&mut m, &sys, &Options::default()).expect("solves");
        assert!(stats.converged);
        assert!(
            stats.lambda_min > 0.0,
            "seed {seed} ended on a saddle: {stats:?}"
        );
        let mid = m.pos(n / 2).z;
        let e = stats.energy;
        match found
            .iter_mut()
            .find(|f| (f.0 - e).abs() < 1e-6 * e && (f.1 - mid).abs() < 1e-3)
        {
            Some(f) => f.2 += 1,
            None => found.push((e, mid, 1)),
        }
    }
    assert_eq!(found.len(), 2, "equilibria {found:?}");
    let first_order = 4.0 * std::f64::consts::PI.powi(2) * abs_section().b_flat * push / (l * l);
    for &(e, mid, _) in &found {
        assert!(
            (e - first_order).abs() < 0.01 * first_order,
            "E {e} vs {first_order}"
        );
        assert!(
            (e - 3.6063).abs() < 0.01,
            "the prototype's 3.6063 N mm, got {e}"
        );
        assert!((mid.abs() - 12.635).abs() < 0.05, "mid-span {mid}");
    }
    assert!(found[0].1 * found[1].1 < 0.0, "mirror images: {found:?}");
}

fn load(path: &str) -> Lattice {
    let text = std::fs::read_to_string(path).expect("recipe");
    karigami::parse(&text, "t")
        .expect("parses")
        .grow()
        .expect("grows")
}

fn uniform_grid() -> Lattice {
    let text = r#"
[lattice]
seed = "sheet"
points = [[0.0, 0.0], [80.0, 0.0], [160.0, 0.0], [240.0, 0.0]]
kappa = [0.0, 0.0, 0.0]
[lattice.grow]
rows = 3
angle = 60.0
left_leg = 80.0
right_leg = "match"
"#;
    karigami::parse(text, "grid")
        .expect("parses")
        .grow()
        .expect("grows")
}

/// Gradient and Hessian of every third stencil (of every kind) against
/// central differences at random states of a lattice model with eyelets
/// (docs/physics.md, "Solver").
#[test]
fn gradient_and_hessian_match_finite_differences() {
    for (lattice, joint) in [
        (uniform_grid(), VertexJoint::Eyelet),
        (load("examples/torus.toml"), VertexJoint::Eyelet),
        (load("examples/torus.toml"), VertexJoint::Ball),
    ] {
        let settings = Settings {
            vertex_joint: joint,
            ..Settings::default()
        };
        // Also with the frames re-based on the random state (tilts 0), where
        // the solver takes derivatives: the joint frames' Taylor form.
        for rebase in [false, true] {
            let mut lm = sim::prepare(&lattice, 10.0, 1.0, &settings);
            let m = &mut lm.model;
            let mut rng = Rng::new(11);
            for (i, kind) in m.kinds.clone().iter().enumerate() {
                m.q[i] += match kind {
                    karigami_rods::model::VarKind::Length => 0.3 * rng.normal(),
                    karigami_rods::model::VarKind::Angle => 0.05 * rng.normal(),
                };
            }
            if rebase {
                m.apply_ties();
                m.update_frames();
            }
            let (mut worst_g, mut worst_h) = (0.0f64, 0.0f64);
            let mut checked = 0;
            // A sample of stencils of every kind (all of them is slow unoptimised).
            let picks: Vec<usize> = (0..m.stencils.len()).step_by(3).collect();
            for &s in &picks {
                let st = m.stencils[s];
                let vars = m.stencil_vars(&st);
                let (e, g, h) = m.stencil_derivatives(&st, &vars);
                let k = vars.len();
                // The solver's derivatives (a rod term's chain rule in plain
                // numbers, `Chain`) against a dual variable for every local
                // variable. (Loads and moments have no chain rule: there both
                // sides are the duals, and only the finite differences below
                // check them.)
                let (ef, gf, hf) = m.stencil_derivatives_full(&st, &vars);
                let close = |a: &[f64], b: &[f64]| {
                    let scale = b.iter().fold(1e-300f64, |s, x| s.max(x.abs()));
                    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-9 * scale)
                };
                assert!(
                    (e - ef).abs() <= 1e-12 * ef.abs().max(1e-300),
                    "energy {e} vs {ef}"
                );
                assert!(
                    close(&g, &gf),
                    "chain-rule gradient differs: {g:?} vs {gf:?}"
                );
                assert!(close(&h, &hf), "chain-rule Hessian differs");
                checked += 1;
                let step = |i: usize| match m.kinds[vars[i]] {
                    karigami_rods::model::VarKind::Length => 1e-6,
                    karigami_rods::model::VarKind::Angle => 2e-7,
                };
                let gscale = g.iter().fold(1e-12f64, |a, b| a.max(b.abs()));
                let hscale = h.iter().fold(1e-12f64, |a, b| a.max(b.abs()));
                for i in 0..k {
                    let hi = step(i);
                    let x0 = m.q[vars[i]];
                    m.q[vars[i]] = x0 + hi;
                    let (ep, gp) = (m.stencil_value(&st), m.stencil_derivatives(&st, &vars).1);
                    m.q[vars[i]] = x0 - hi;
                    let (em, gm) = (m.stencil_value(&st), m.stencil_derivatives(&st, &vars).1);
                    m.q[vars[i]] = x0;
                    let fd = (ep - em) / (2.0 * hi);
                    worst_g = worst_g.max((fd - g[i]).abs() / gscale);
                    for j in 0..k {
                        let fdh = (gp[j] - gm[j]) / (2.0 * hi);
                        worst_h = worst_h.max((fdh - h[i * k + j]).abs() / hscale);
                    }
                }
            }
            assert!(checked > 0);
            assert!(worst_g < 1e-6, "gradient error {worst_g}");
            assert!(worst_h < 1e-6, "Hessian error {worst_h}");
        }
    }
}

/// A joint's frame at zero tilt from its Taylor polynomials against the
/// general formula (a unit vector and two parallel transports in duals):
/// value, gradient and Hessian alike to 1e-12, on random stored frames.
#[test]
fn joint_frame_at_rest_equals_the_general_formula() {
    use karigami_rods::dual::{Dual, Scalar};
    use karigami_rods::frames::{joint_frame_at_rest, joint_frame_general};
    let mut rng = Rng::new(5);
    for _ in 0..50 {
        let n = DVec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
        let p = n.any_orthonormal_vector();
        let p = (p * rng.normal() + n.cross(p) * rng.normal()).normalize();
        let q = n.cross(p);
        let (a, b) = (Dual::<2, 3>::var(0.0, 0), Dual::<2, 3>::var(0.0, 1));
        let rest = joint_frame_at_rest([n, p, q], a, b);
        let general = joint_frame_general([n, p, q], a, b);
        for (x, y) in [
            (rest.0, general.0),
            (rest.1, general.1),
            (rest.2, general.2),
        ] {
            for (u, v) in [(x.x, y.x), (x.y, y.y), (x.z, y.z)] {
                assert!((u.val() - v.val()).abs() < 1e-12, "{u:?} vs {v:?}");
                for k in 0..2 {
                    assert!((u.g[k] - v.g[k]).abs() < 1e-12, "{u:?} vs {v:?}");
                }
                for k in 0..3 {
                    assert!((u.h[k] - v.h[k]).abs() < 1e-12, "{u:?} vs {v:?}");
                }
            }
        }
    }
}

/// The bend stencil's energy over the two edges' rotations in closed form
/// against the reference by dual products over the rotated frames: value,
/// gradient and Hessian alike to 1e-9 of their largest entry, on random
/// frame pairs from nearly straight to 100 degrees apart, with a random
/// twist.
#[test]
fn bend_energy_over_rotations_closed_form_equals_the_duals() {
    use karigami_rods::model::{bend_energy_rotations, bend_energy_rotations_dual};
    let sec = abs_section();
    let mut rng = Rng::new(17);
    let mut checked = 0;
    for case in 0..400 {
        let t0 = DVec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
        let d10 = t0.any_orthonormal_vector();
        let d10 = (d10 * rng.normal() + t0.cross(d10) * rng.normal()).normalize();
        let a = [t0, d10, t0.cross(d10)];
        // The second frame: the first turned by a random rotation.
        let axis = DVec3::new(rng.normal(), rng.normal(), rng.normal()).normalize();
        let angle = match case % 4 {
            0 => 1e-4 * rng.normal(),
            1 => 0.05 * rng.normal(),
            _ => (0.6 * rng.normal()).clamp(-1.75, 1.75),
        };
        let r = glam::DQuat::from_axis_angle(axis, angle);
        let b = [r * a[0], r * a[1], r * a[2]];
        let lbar = 2.0 + rng.normal().abs();
        let closed = bend_energy_rotations(&sec, lbar, [a, b]);
        let dual = bend_energy_rotations_dual(&sec, lbar, [a, b]);
        let scale = dual
            .g
            .iter()
            .chain(&dual.h)
            .fold(dual.v.abs(), |s, x| s.max(x.abs()))
            .max(1e-300);
        assert!(
            (closed.v - dual.v).abs() <= 1e-9 * scale,
            "case {case}: energy {} vs {}",
            closed.v,
            dual.v
        );
        for (x, y) in closed
            .g
            .iter()
            .chain(&closed.h)
            .zip(dual.g.iter().chain(&dual.h))
        {
            assert!(
                (x - y).abs() <= 1e-9 * scale,
                "case {case}: {closed:?} vs {dual:?}"
            );
        }
        checked += 1;
    }
    assert_eq!(checked, 400);
}

/// The ideal linkage of a planar lattice at reference opening theta:
/// every cell rigid at its C(theta) angle, placed in grid order by a
/// rigid fit to the vertices already placed (docs/math.md 8.4). Vertices,
/// then pivots.
fn ideal_linkage(lattice: &Lattice, theta: f64) -> Vec<DVec3> {
    let phis = configuration(lattice).angles(theta).expect("in range");
    let nv = lattice.vertices.len();
    let mut placed: Vec<Option<DVec2>> = vec![None; nv];
    let mut pivots = Vec::new();
    for (i, cell) in lattice.cells.iter().enumerate() {
        let [ul, ur, _, _] = lattice.corners(cell);
        let (a, b) = (ul - cell.pivot, ur - cell.pivot);
        let side = if a.x * b.y - a.y * b.x < 0.0 {
            -1.0
        } else {
            1.0
        };
        let [l1, l2, l3, l4] = lattice.legs(cell);
        let phi = phis[i];
        let (da, db) = (DVec2::X, DVec2::new(phi.cos(), side * phi.sin()));
        let local = [da * l1, db * l4, -db * l2, -da * l3];
        let ids = cell.corner_ids();
        let pairs: Vec<(DVec2, DVec2)> = ids
            .iter()
            .zip(local)
            .filter_map(|(&v, p)| placed[v as usize].map(|q| (p, q)))
            .collect();
        let n = pairs.len().max(1) as f64;
        let cp = pairs.iter().map(|p| p.0).sum::<DVec2>() / n;
        let cq = pairs.iter().map(|p| p.1).sum::<DVec2>() / n;
        let (mut s, mut c) = (0.0, 0.0);
        for (p, q) in &pairs {
            let (p, q) = (*p - cp, *q - cq);
            c += p.dot(q);
            s += p.perp_dot(q);
        }
        let rot = DVec2::from_angle(if pairs.len() < 2 { 0.0 } else { s.atan2(c) });
        let fit = |p: DVec2| cq + rot.rotate(p - cp);
        for (&v, p) in ids.iter().zip(local) {
            placed[v as usize].get_or_insert(fit(p));
        }
        pivots.push(fit(DVec2::ZERO));
    }
    placed
        .into_iter()
        .map(|p| p.expect("placed"))
        .chain(pivots)
        .map(|p| DVec3::new(p.x, p.y, 0.0))
        .collect()
}

/// Opened by 10 degrees, holding either the first cell's opening or the
/// mean opening of all cells: no energy, and the joints where the ideal
/// linkage puts them at the first cell's opening reached. Under the mean
/// hold, the mean is the target while the cells differ (a 1-dof linkage).
fn mechanism_follows_the_linkage(lattice: &Lattice, perturbed: bool, actuation: Actuation) {
    let settings = Settings {
        actuation,
        ..Settings::default()
    };
    let mut lm = sim::prepare(lattice, 10.0, 1.0, &settings);
    let target = lm.held_opening() - 10f64.to_radians();
    if perturbed {
        perturb(&mut lm.model, 5, 1.0);
    }
    let (stats, _, _) = sim::deploy(&mut lm, Some(target), &Options::default()).expect("deploys");
    let e_s = lm.model.e_scale;
    assert!(
        stats.energy.abs() < 1e-9 * e_s,
        "E = {} (E_s {e_s})",
        stats.energy
    );
    assert!(
        (lm.held_opening() - target).abs() < 1e-9,
        "{actuation:?}: held {} vs {target}",
        lm.held_opening()
    );
    let theta = lm.opening(0);
    let ideal = ideal_linkage(lattice, theta);
    let d = kabsch_distance(&lm.points(), &ideal);
    assert!(d < 1e-6, "joints {d} mm from the ideal linkage");
    assert!(stats.lambda_min > 0.0, "stable: {stats:?}");
}

#[test]
fn chain_follows_the_ideal_linkage() {
    let chain = load("examples/mirror-arm.toml");
    for actuation in [Actuation::FirstCell, Actuation::Mean] {
        mechanism_follows_the_linkage(&chain, false, actuation);
        mechanism_follows_the_linkage(&chain, true, actuation);
    }
}

#[test]
fn uniform_grid_follows_the_ideal_linkage() {
    let grid = uniform_grid();
    for actuation in [Actuation::FirstCell, Actuation::Mean] {
        mechanism_follows_the_linkage(&grid, false, actuation);
        mechanism_follows_the_linkage(&grid, true, actuation);
    }
}

/// The symmetric torus, a 3-D mechanism: with ball vertex joints it opens
/// without energy, every cell following C(theta); with eyelets its strips
/// must twist where cells in different planes meet (docs/physics.md, "Eyelets").
#[test]
fn torus_with_ball_joints_opens_freely_and_with_eyelets_twists() {
    let torus = load("examples/torus.toml");
    let ball = Settings {
        vertex_joint: VertexJoint::Ball,
        actuation: Actuation::FirstCell,
        ..Settings::default()
    };
    let mut lm = sim::prepare(&torus, 10.0, 1.0, &ball);
    let design = lm.opening(0);
    let theta = design - 4f64.to_radians();
    let (stats, _, _) = sim::deploy(&mut lm, Some(theta), &Options::default()).expect("deploys");
    let e_s = lm.model.e_scale;
    assert!(
        stats.energy.abs() < 1e-9 * e_s,
        "E = {} (E_s {e_s})",
        stats.energy
    );
    let phis = configuration(&torus).angles(theta).expect("in range");
    for (c, phi) in phis.iter().enumerate() {
        assert!(
            (lm.opening(c) - phi).abs() < 1e-6,
            "cell {c}: {} vs C(theta) {phi}",
            lm.opening(c)
        );
    }
    // Strips straight between their holes: hole distances are the cut legs.
    for (r, rod) in torus.rods().enumerate() {
        let path = &lm.model.rods[r];
        let first = lm.model.pos(path.nodes[0]);
        let last = lm.model.pos(*path.nodes.last().unwrap());
        assert!(
            (first.distance(last) - rod.length()).abs() < 1e-6,
            "rod {r} bent"
        );
    }

    let eyelet = Settings::default();
    let run = sim::simulate(
        &torus,
        &karigami::deploy::deployment(&torus),
        10.0,
        1.0,
        &eyelet,
    )
    .expect("simulates");
    let eq = &run.equilibrium;
    println!(
        "torus with eyelets: E = {:.4} N mm (twist {:.4}), largest twist shear strain {:.3} %, largest strain {:.3} % in {}",
        eq.energy.total(),
        eq.energy.twist,
        100.0 * eq.strain.gamma,
        100.0 * eq.strain.eps,
        eq.strain.rod
    );
    assert!(
        eq.energy.total() > 1.0 * run.lm.model.e_scale,
        "eyelets leave the torus stress-free?"
    );
    assert!(
        eq.energy.twist > 0.1 * eq.energy.total(),
        "little twist: {:?}",
        eq.energy
    );
    assert!(eq.strain.gamma > 1e-3, "gamma {}", eq.strain.gamma);
    assert!(eq.stats.lambda_min > 0.0);
}

/// Halving the edge length moves the reported equilibrium of the cheaper
/// examples (docs/physics.md, "Mesh refinement") by less than 1 % of the
/// piece's size, the same state at both meshes. `examples_converge_under_
/// refinement` (scripts/refinement) measures every example.
#[test]
fn cheap_examples_converge_under_refinement() {
    for (name, moved) in [("mirror-arm", 0.0), ("curved-sheet", 0.0)] {
        let r = refinement(&format!("examples/{name}.toml"));
        assert!(r.popped.is_empty(), "{name}: {:?}", r.popped);
        assert!(r.like_with_like < 0.01 * r.size, "{name}: {r:?}");
        // Golden: the measured move (mm), to 1e-3 mm.
        assert!((r.moved - moved).abs() < 1e-3, "{name}: {r:?}");
    }
}

/// Every example's refinement (docs/physics.md, "Mesh refinement"): the
/// table scripts/refinement prints, and each within 1 % like with like.
#[test]
#[ignore]
fn examples_converge_under_refinement() {
    let mut names: Vec<String> = std::fs::read_dir("examples")
        .expect("examples")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter_map(|n| n.strip_suffix(".toml").map(str::to_string))
        .collect();
    names.sort();
    println!(
        "| example | size (mm) | edge (mm) | E coarse / fine (N mm) | moved (mm, %) | bumps that flip | like with like (mm, %) |"
    );
    let mut worst = Vec::new();
    for name in names {
        let r = refinement(&format!("examples/{name}.toml"));
        println!(
            "| {name} | {:.0} | {} -> {} | {:.3} / {:.3} | {:.3}, {:.2} % | {} | {:.3}, {:.2} % | {:.3}, {:.2} % |",
            r.size,
            r.h,
            r.h / 2.0,
            r.energy.0,
            r.energy.1,
            r.moved,
            100.0 * r.moved / r.size,
            if r.popped.is_empty() {
                "none".to_string()
            } else {
                r.popped.join(", ")
            },
            r.like_with_like,
            100.0 * r.like_with_like / r.size,
            r.solved_from_design,
            100.0 * r.solved_from_design / r.size
        );
        // The saddle ring is held by its states solved from the design:
        // the ring before issue 32 (the cranked ring, docs/physics.md,
        // "Mesh refinement") deployed onto its soft mode, another state
        // at each mesh; today's deploys back to the state solved from
        // its design (`karigami simulate`), so that is its reported one.
        let compared = match name.as_str() {
            "saddle-ring" => r.solved_from_design,
            _ => r.like_with_like,
        };
        if !(compared < 0.01 * r.size) {
            worst.push(name);
        }
    }
    assert!(worst.is_empty(), "over 1 %: {worst:?}");
}

/// One example's mesh refinement: its reported equilibrium (the state
/// deploying reaches) at the recipe's edge length and at half of it.
#[derive(Debug)]
struct Refined {
    /// The design's diagonal (mm).
    size: f64,
    /// The coarse edge length (mm).
    h: f64,
    /// The reported states' energies, coarse and fine (N mm).
    energy: (f64, f64),
    /// Largest joint distance between the two reported states (mm).
    moved: f64,
    /// Bumps popped through between them (another equilibrium).
    popped: Vec<String>,
    /// The distance between the coarse state and the fine state with the
    /// same bumps (the reported one, or the closest that `explore` finds
    /// when the reported ones differ in bumps or by 1 % or more).
    like_with_like: f64,
    /// The same for the states solved from the design (the path's start).
    solved_from_design: f64,
}

fn refinement(path: &str) -> Refined {
    let text = std::fs::read_to_string(path).expect("recipe");
    let d = karigami::parse(&text, "t").expect("parses");
    let lattice = d.grow().expect("grows");
    let deploy = karigami::deploy::deployment(&lattice);
    let m = &d.fabrication.material;
    let solve_at = |h: f64| {
        let settings = Settings {
            h_max: h,
            ..d.simulation.clone()
        };
        let run = sim::simulate(&lattice, &deploy, m.width, m.thickness, &settings)
            .unwrap_or_else(|e| panic!("{path} at {h} mm: {e}"));
        let (run, path) = sim::path::chosen(run, &settings.material);
        let start = path.and_then(|p| p.collapse.first().map(|q| q.points.clone()));
        (run, start.unwrap_or_default())
    };
    let h = d.simulation.h_max;
    let ((coarse, coarse_start), (fine, fine_start)) = (solve_at(h), solve_at(h / 2.0));
    let (lo, hi) = lattice.extent();
    let size = (hi - lo).length();
    let moved = kabsch_distance(&coarse.equilibrium.points, &fine.equilibrium.points);
    let relief = |run: &sim::Simulation, points: &[DVec3]| {
        sim::states::Relief::at(&lattice, &run.lm, points)
    };
    let base = relief(&coarse, &coarse.equilibrium.points);
    let popped_at = |points: &[DVec3]| base.popped(&relief(&fine, points), &lattice);
    let popped: Vec<String> = popped_at(&fine.equilibrium.points)
        .into_iter()
        .map(|c| c.vertex)
        .collect();
    let solved_from_design = if coarse_start.is_empty() {
        moved
    } else {
        kabsch_distance(&coarse_start, &fine_start)
    };
    let like_with_like = if popped.is_empty() && moved < 0.01 * size {
        moved
    } else {
        // The fine mesh's states near the reported one; the closest to the
        // coarse state among those with its bumps.
        let solved = std::sync::atomic::AtomicUsize::new(0);
        let material = d.simulation.material;
        let (found, _) = sim::explore::explore(
            &fine.lm,
            24,
            2024,
            2,
            &|lm, stats| sim::equilibrium(lm, stats, &material),
            &solved,
        );
        found
            .iter()
            .map(|f| &f.equilibrium.points)
            .filter(|p| popped_at(p).is_empty())
            .map(|p| kabsch_distance(&coarse.equilibrium.points, p))
            .fold(moved, f64::min)
    };
    Refined {
        size,
        h,
        energy: (
            coarse.equilibrium.energy.total(),
            fine.equilibrium.energy.total(),
        ),
        moved,
        popped,
        like_with_like,
        solved_from_design,
    }
}

/// The simulated shape of a gallery recipe with its own strip and
/// `[simulation]` settings: the lattice with every vertex where the strips
/// put it, measured by lattice::shape like any design.
fn simulated_shape(path: &str) -> (Lattice, Lattice, sim::Simulation) {
    let text = std::fs::read_to_string(path).expect("recipe");
    let (lattice, placed, run) = simulated_recipe(&text);
    assert!(run.equilibrium.stats.lambda_min > 0.0, "{path}: not stable");
    (lattice, placed, run)
}

/// A recipe's lattice, its simulated shape and the simulation, with the
/// recipe's own strips and `[simulation]` settings.
fn simulated_recipe(text: &str) -> (Lattice, Lattice, sim::Simulation) {
    let d = karigami::parse(text, "t").expect("parses");
    let lattice = d.grow().expect("grows");
    let deploy = karigami::deploy::deployment(&lattice);
    let m = &d.fabrication.material;
    let run =
        sim::simulate(&lattice, &deploy, m.width, m.thickness, &d.simulation).expect("simulates");
    let placed = sim::placed_lattice(&lattice, &run.lm);
    (lattice, placed, run)
}

fn degrees(c: &[karigami::shape::VertexCurvature]) -> Vec<f64> {
    c.iter().map(|v| v.defect.to_degrees()).collect()
}

/// The eggbox's recipe with 1 mm strips instead of 0.5 mm, and `extra`
/// appended.
fn thick_eggbox(extra: &str) -> String {
    let text = std::fs::read_to_string("examples/eggbox.toml").expect("recipe");
    assert!(text.contains("\n[material]\nthickness = 0.5\n"));
    format!(
        "{}\n{extra}",
        text.replace(
            "\n[material]\nthickness = 0.5\n",
            "\n[material]\nthickness = 1.0\n"
        )
    )
}

/// Issue 11's measures of a shape, taken on the simulated equilibrium of
/// a gallery recipe (its own strip, material and `[simulation]`
/// settings): the shape the strips make, not the design's picture.
fn simulated_measures(path: &str) -> (Lattice, Lattice, sim::Simulation, karigami::Measures) {
    let (design, placed, run) = simulated_shape(path);
    let text = std::fs::read_to_string(path).expect("recipe");
    let d = karigami::parse(&text, "t").expect("parses");
    let m = karigami::measure_assembled(&d, &placed, &placed);
    (design, placed, run, m)
}

/// The eggbox is designed to make bumps and dips in a checkerboard, and
/// its simulated equilibrium (deployed as its recipe says: 0.5 mm strips,
/// the mean opening of all cells held at the design's) meets issue 11's
/// measures of an eggbox: at least 20 % of the interior vertices with an
/// angle defect of +3 deg or more, spread over at least 3 rows and 3
/// columns, and at least 20 % at -3 deg or less (over 3 rows too). The
/// relief is the designed one: no vertex curves beyond 3 deg against its
/// designed sign, at most one changes sign at all; the strips of the
/// simulated shape do not clash and stay within the allowable strain.
///
/// Measured (docs/physics.md, "The eggbox: strip thickness and relief"):
/// 47 % and 37 %, strain 1.16 %; the same design with 1 mm strips keeps
/// 45 % and 31 % but bends them to 3.0 %.
#[test]
fn eggbox_simulates_to_bumps_and_dips() {
    let (design, placed, run, m) = simulated_measures("examples/eggbox.toml");
    let designed = design.curvature();
    let got = placed.curvature();
    assert_eq!(
        designed.iter().map(|v| v.vertex).collect::<Vec<_>>(),
        got.iter().map(|v| v.vertex).collect::<Vec<_>>()
    );
    let (dd, gd) = (degrees(&designed), degrees(&got));
    let saddle_rows: std::collections::BTreeSet<u32> = got
        .iter()
        .filter(|v| v.defect.to_degrees() <= -3.0)
        .map(|v| placed.vertex(v.vertex).key.row)
        .collect();
    println!(
        "eggbox at {:.2} deg: simulated {:.0} % >= +3 deg over {} rows and {} columns, {:.0} % <= -3 deg over {} rows (range {:.2} to {:.2}); design range {:.2} to {:.2}; {} clashes; peak strain {:.3} % in {}",
        run.theta.to_degrees(),
        100.0 * m.bumps,
        m.bump_rows,
        m.bump_cols,
        100.0 * m.dimples,
        saddle_rows.len(),
        gd.iter().copied().fold(f64::INFINITY, f64::min),
        gd.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        dd.iter().copied().fold(f64::INFINITY, f64::min),
        dd.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        m.clashes.len(),
        100.0 * run.equilibrium.strain.eps,
        run.equilibrium.strain.rod
    );
    // Issue 11's eggbox, on the simulated shape.
    assert!(
        m.bumps >= 0.2 && m.dimples >= 0.2,
        "{} {}",
        m.bumps,
        m.dimples
    );
    assert!(
        m.bump_rows >= 3 && m.bump_cols >= 3,
        "{} {}",
        m.bump_rows,
        m.bump_cols
    );
    assert!(saddle_rows.len() >= 3, "{saddle_rows:?}");
    // The designed checkerboard, not another relief.
    let against: Vec<String> = dd
        .iter()
        .zip(&gd)
        .filter(|(d, g)| *d * *g < 0.0 && g.abs() >= 3.0)
        .map(|(d, g)| format!("{d:+.2} -> {g:+.2}"))
        .collect();
    assert!(against.is_empty(), "curved against the design: {against:?}");
    let changed = dd
        .iter()
        .zip(&gd)
        .filter(|(d, g)| *d * *g < 0.0 && g.abs() >= 0.5)
        .count();
    assert!(changed <= 1, "{changed} vertices changed sign");
    assert!(m.clashes.is_empty(), "{:?}", m.clashes);
    let allow = karigami::simulation::Material::ABS.eps_allow;
    assert!(
        run.equilibrium.strain.eps <= allow,
        "peak strain {} above {allow}",
        run.equilibrium.strain.eps
    );
}

/// The cranked ring (fixtures/designs/cranked-ring.toml, the gallery's
/// saddle ring before issue 32) is designed saddle-like everywhere with a
/// nearly constant Gaussian curvature, and its simulated equilibrium meets issue
/// 11's measures of it: at least 90 % of the interior vertices negatively
/// curved (-0.5 deg or less), mean angle defect -2 deg or less, and the
/// standard deviation of K at most half its mean; and it keeps at least
/// 75 % of the designed mean defect (measured: -3.62 of -3.84 deg under
/// the mean-opening hold with its two copies alike).
#[test]
fn cranked_ring_simulates_saddle_like() {
    let (design, placed, run, m) = simulated_measures("fixtures/designs/cranked-ring.toml");
    let designed = degrees(&design.curvature());
    let got = degrees(&placed.curvature());
    let c = m.curvature.expect("interior vertices");
    let negative = got.iter().filter(|&&x| x <= -0.5).count() as f64 / got.len() as f64;
    let mean = got.iter().sum::<f64>() / got.len() as f64;
    println!(
        "saddle ring: design mean {:.2} deg; simulated mean {mean:.2} deg, {:.0} % <= -0.5 deg (range {:.2} to {:.2}), std/|mean| of K {:.3}; {} clashes; {} iterations, E {:.1} N mm",
        designed.iter().sum::<f64>() / designed.len() as f64,
        100.0 * negative,
        got.iter().copied().fold(f64::INFINITY, f64::min),
        got.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        c.k_std / c.k_mean.abs(),
        m.clashes.len(),
        run.iterations,
        run.equilibrium.energy.total()
    );
    let designed_mean = designed.iter().sum::<f64>() / designed.len() as f64;
    assert!(designed_mean < 0.0);
    // Issue 11's saddle ring, on the simulated shape.
    assert!(negative >= 0.9, "{got:?}");
    assert!(mean <= -2.0, "{mean}");
    assert!(c.k_std / c.k_mean.abs() <= 0.5, "{c:?}");
    assert!(mean <= 0.75 * designed_mean, "{mean} of {designed_mean}");
    // Not asserted away: the simulated ring's bent strips of rows 0 and 2
    // come within the clash distance (60 pairs; the model has no contact),
    // and `build` says so (refused unless [clash] allows it: see
    // `bent_strips_that_meet_are_refused_though_their_chords_are_apart`).
    let source = std::fs::read_to_string("fixtures/designs/cranked-ring.toml").expect("recipe");
    let d = karigami::parse(&source, "t").expect("parses");
    let lattice = d.grow().expect("grows");
    let said = karigami::contact(&d, &lattice, &run.lm).expect("the bent strips clash");
    assert!(said.contains("(60 clashing pairs in all)"), "{said}");
}

/// The eggbox's overstrain at its corner strip (docs/physics.md): the same
/// recipe with the opening prescribed at cell 0, at the central cell, as
/// the mean of all cells (the default), or nowhere (only rigid motions
/// removed). Prints figures.
#[test]
#[ignore]
fn eggbox_actuation_study() {
    let text = std::fs::read_to_string("examples/eggbox.toml").expect("recipe");
    let d = karigami::parse(&text, "t").expect("parses");
    let lattice = d.grow().expect("grows");
    let m = &d.fabrication.material;
    let s = d.simulation;
    let centre = {
        let (lo, hi) = lattice.extent();
        let mid = (lo + hi) / 2.0;
        (0..lattice.cells.len())
            .min_by(|&a, &b| {
                let da = lattice.cells[a].pivot.distance(mid);
                let db = lattice.cells[b].pivot.distance(mid);
                da.total_cmp(&db)
            })
            .expect("cells")
    };
    for (what, cell, hold) in [
        ("cell 0 prescribed", 0, Some(false)),
        ("centre cell prescribed", centre, Some(false)),
        ("mean opening prescribed", 0, Some(true)),
        ("nothing prescribed", centre, None),
    ] {
        let mut lm = sim::LatticeModel::new(
            &lattice,
            karigami::simulation::section(&s.material, m.width, m.thickness),
            sim::Mesh {
                h_max: s.h_max,
                arm: m.width / 2.0,
                vertex_joint: s.vertex_joint,
            },
        );
        lm.anchor(cell);
        let design0 = lm.opening(0);
        match hold {
            Some(false) => {
                let phi = lm.opening(cell);
                lm.set_opening(cell, phi);
            }
            Some(true) => {
                let phi = lm.mean_opening();
                lm.set_mean_opening(phi);
            }
            None => {}
        }
        match sim::deploy(&mut lm, None, &Options::default()) {
            Ok((stats, it, _)) => {
                let eq = sim::equilibrium(&lm, stats, &s.material);
                let placed = sim::placed_lattice(&lattice, &lm);
                let c: Vec<f64> = placed
                    .curvature()
                    .iter()
                    .map(|v| v.defect.to_degrees())
                    .collect();
                println!(
                    "{what} ({}): {it} iterations, E {:.2} N mm, strain {:.3} % in {} at {:.1} mm ({}), lambda_min {:.2e}, cell 0 opening {:.2} deg (design {:.2}), defects {:.0} % >= 3, {:.0} % <= -3",
                    lattice.cell_name(&lattice.cells[cell]),
                    eq.energy.total(),
                    100.0 * eq.strain.eps,
                    eq.strain.rod,
                    eq.strain.s,
                    eq.strain.term,
                    eq.stats.lambda_min,
                    lm.opening(0).to_degrees(),
                    design0.to_degrees(),
                    100.0 * c.iter().filter(|&&x| x >= 3.0).count() as f64 / c.len() as f64,
                    100.0 * c.iter().filter(|&&x| x <= -3.0).count() as f64 / c.len() as f64,
                );
            }
            Err(e) => println!("{what}: {e}"),
        }
    }
}

/// Pictures to look at: the designed (rigid-fit) and the simulated
/// preview of the eggbox and the saddle ring, side by side in
/// target/tmp/sim-previews/ (the build's preview.png shows the simulated
/// one). Run by scripts/sim-long.
#[test]
#[ignore]
fn previews_of_the_simulated_beside_the_designed() {
    use karigami::testing::picture::preview_captioned;
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("sim-previews");
    std::fs::create_dir_all(&dir).expect("folder");
    for name in ["eggbox", "saddle-ring"] {
        let (design, placed, _) = simulated_shape(&format!("examples/{name}.toml"));
        let pages = [
            (
                "design",
                preview_captioned(
                    &design.placed(),
                    10.0,
                    name,
                    Some("shown: the design, rows placed by a rigid fit"),
                ),
            ),
            (
                "simulated",
                preview_captioned(
                    &placed,
                    10.0,
                    name,
                    Some("shown: the simulated deployed shape"),
                ),
            ),
        ];
        for (what, page) in pages {
            let path = dir.join(format!("{name}-{what}.png"));
            std::fs::write(&path, karigami::formats::png::write(&page, 8.0, 1.0)).expect("writes");
            println!("{}", path.display());
        }
    }
}

/// `[simulation] actuation` picks what deployment holds; the mean is the
/// default and an unknown word is refused with the choices named.
#[test]
fn simulation_actuation_is_read_from_the_recipe() {
    let text = std::fs::read_to_string("examples/eggbox.toml").expect("recipe");
    let with = |line: &str| format!("{text}\n[simulation]\n{line}\n");
    let read = |t: &str| karigami::parse(t, "t").map(|d| d.simulation.actuation);
    assert_eq!(read(&text).expect("parses"), Actuation::Mean);
    assert_eq!(
        read(&with("actuation = \"first-cell\"")).expect("parses"),
        Actuation::FirstCell
    );
    let e = read(&with("actuation = \"corner\"")).expect_err("refused");
    assert!(
        e.message.contains("actuation")
            && e.span.is_some()
            && e.hint.as_deref().is_some_and(|h| h.contains("first-cell")),
        "{e:?}"
    );
}

/// Going back from the mean hold to one cell's opening leaves no tie
/// behind: the chain then follows the ideal linkage at that cell's angle.
#[test]
fn mean_hold_switches_back_to_one_cell() {
    let chain = load("examples/mirror-arm.toml");
    let mut lm = sim::prepare(&chain, 10.0, 1.0, &Settings::default());
    assert_eq!(lm.hold, sim::Hold::Mean);
    let theta = lm.opening(0) - 5f64.to_radians();
    lm.set_opening(0, theta);
    assert!(lm.model.ties.is_empty());
    let (stats, _, _) = sim::deploy(&mut lm, None, &Options::default()).expect("deploys");
    assert!((lm.opening(0) - theta).abs() < 1e-12);
    let d = kabsch_distance(&lm.points(), &ideal_linkage(&chain, theta));
    assert!(d < 1e-6 && stats.lambda_min > 0.0, "{d} mm, {stats:?}");
}

/// The cranked ring's soft mode under the mean hold: openings of every
/// cell at h 10 and 5 mm, by row and column, and their difference.
#[test]
#[ignore]
fn cranked_ring_soft_mode_study() {
    let ring = load("fixtures/designs/cranked-ring.toml");
    let deploy = karigami::deploy::deployment(&ring);
    let design: Vec<f64> = {
        let lm = sim::prepare(&ring, 10.0, 1.0, &Settings::default());
        (0..ring.cells.len()).map(|c| lm.opening(c)).collect()
    };
    let act = match std::env::var("HOLD").as_deref() {
        Ok("first") => Actuation::FirstCell,
        _ => Actuation::Mean,
    };
    let symmetry = std::env::var("SYMMETRY").map_or(1, |s| s.parse().expect("a number"));
    let run = |h: f64| {
        let settings = Settings {
            h_max: h,
            actuation: act,
            symmetry,
            ..Settings::default()
        };
        sim::simulate(&ring, &deploy, 10.0, 1.0, &settings).expect("simulates")
    };
    let (a, b) = (run(10.0), run(5.0));
    let d = kabsch_distance(&a.equilibrium.points, &b.equilibrium.points);
    println!(
        "distance {d:.3} mm, E {:.3} {:.3}, iterations {} {}",
        a.equilibrium.energy.total(),
        b.equilibrium.energy.total(),
        a.iterations,
        b.iterations
    );
    let rows = ring.cells.iter().map(|c| c.row).max().unwrap() + 1;
    for r in 0..rows {
        let mut line = format!("row {r}:");
        let mut diff = format!("diff {r}:");
        for (c, cell) in ring.cells.iter().enumerate() {
            if cell.row == r {
                let oa = (a.equilibrium.openings[c] - design[c]).to_degrees();
                let ob = (b.equilibrium.openings[c] - design[c]).to_degrees();
                line += &format!(" {oa:+.2}");
                diff += &format!(" {:+.2}", ob - oa);
            }
        }
        println!("{line}\n{diff}");
    }
}

/// `[simulation] symmetry`: the cranked ring's 2 is read, 0 is refused at
/// its place, and a symmetry the lattice does not have is refused by the
/// simulation naming why (3 cells a row do not split into 2 copies).
#[test]
fn simulation_symmetry_is_read_and_checked() {
    let text = std::fs::read_to_string("fixtures/designs/cranked-ring.toml").expect("recipe");
    let read = |t: &str| karigami::parse(t, "t").map(|d| d.simulation.symmetry);
    assert_eq!(read(&text).expect("parses"), 2);
    let e = read(&text.replace("symmetry = 2", "symmetry = 0")).expect_err("refused");
    assert!(e.message.contains("symmetry") && e.span.is_some(), "{e:?}");
    let grid = uniform_grid();
    let deploy = karigami::deploy::deployment(&grid);
    let settings = Settings {
        symmetry: 2,
        ..Settings::default()
    };
    let e = sim::simulate(&grid, &deploy, 10.0, 1.0, &settings).expect_err("refused");
    assert!(
        matches!(e, sim::SimError::Symmetry { copies: 2, .. })
            && e.to_string().contains("not a multiple of 2"),
        "{e}"
    );
}

/// The eggbox's design with 1 mm strips instead of its 0.5 mm bends them
/// beyond the allowable (3.0 %); a recipe that accepts that still builds,
/// the build still warns about it, and report.txt states the simulated
/// shape's strain.
#[test]
fn an_accepted_overstrain_is_warned_and_reported() {
    // Not accepted: refused, naming the strip and what to change.
    let refused = karigami::parse(&thick_eggbox(""), "eggbox").expect("parses");
    let Err(e) = karigami::build(refused) else {
        panic!("built with 3 % strain");
    };
    assert_eq!(e.kind.name(), "Overstrain", "{e:?}");
    assert!(
        e.message.contains("strip R") && e.message.contains("allowable is 1.50 %"),
        "{}",
        e.message
    );
    let text = thick_eggbox("[simulation]\naccept_overstrain = true\n");
    let d = karigami::parse(&text, "eggbox").expect("parses");
    let b = karigami::build(d).expect("builds");
    let text = karigami::build_text(&b);
    let warned = text
        .lines()
        .find(|l| {
            l.starts_with("warning: strip ")
                && l.contains("the allowable is 1.50 %; the recipe accepts it")
        })
        .expect("an overstrain warning");
    assert!(warned.contains("accept_overstrain"), "{warned}");
    let line = text
        .lines()
        .find(|l| l.starts_with("simulated deployed shape (deployed.obj)"))
        .expect("the simulation line");
    assert!(
        line.contains("ABOVE it, accepted by the recipe")
            && line.contains("(flatwise bending, strip "),
        "{line}"
    );
}

/// `[optimise.target] shape = "simulated"` makes the curvature objective
/// measure the simulated deployed shape: the same recipe costs more or less
/// than with `shape = "design"` by exactly the difference of the curvature
/// error computed here from the two shapes (the mean squared distance of
/// each interior vertex's defect from the checkerboard target, over the
/// target), plus, where the simulated strips exceed the allowable strain,
/// that excess as a hard constraint's shortfall. An unknown shape, or one
/// with no curvature objective to measure, is refused.
#[test]
fn tune_can_aim_at_the_simulated_relief() {
    let base = std::fs::read_to_string("examples/eggbox.toml").expect("recipe");
    // Two variables (the leg angles), a budget of one: a few designs.
    let recipe = |shape: &str| {
        base.replace("vary = [\"angle\", \"front\"]", "vary = [\"angle\"]")
            .replace("budget = 1500", "budget = 1")
            .replace(
                "pattern = \"checkerboard\"\n",
                &format!("pattern = \"checkerboard\"\nshape = \"{shape}\"\n"),
            )
    };
    let cost = |text: &str| {
        let d = karigami::parse(text, "eggbox").expect("parses");
        karigami::optimise(&d, text, 2, &mut |_| {})
            .expect("optimises")
            .cost_before
    };
    let (designed, simulated) = (cost(&recipe("design")), cost(&recipe("simulated")));
    let (lattice, placed, _) = simulated_recipe(&base);
    let error = |l: &Lattice| {
        let c = l.curvature();
        c.iter()
            .map(|v| {
                let k = l.vertex(v.vertex).key;
                let want = if (k.row + k.col).is_multiple_of(2) {
                    6.5
                } else {
                    -6.5
                };
                ((v.defect.to_degrees() - want) / 6.5).powi(2)
            })
            .sum::<f64>()
            / c.len() as f64
    };
    let (e_design, e_sim) = (error(&lattice), error(&placed));
    println!(
        "cost {designed:.6} (design) vs {simulated:.6} (simulated); curvature error {e_design:.6} vs {e_sim:.6}"
    );
    assert!((e_sim - e_design).abs() > 1e-3, "the shapes differ");
    assert!(
        ((simulated - designed) - (e_sim - e_design)).abs() < 1e-9,
        "{simulated} - {designed} against {e_sim} - {e_design}"
    );
    // With 1 mm strips the simulated strain (3.0 %) is beyond the
    // allowable, and the build would refuse the design: the cost adds it
    // as a hard constraint's shortfall (100 times its share of the
    // allowable), so the search keeps to buildable designs.
    let thick = |shape: &str| {
        recipe(shape).replace(
            "\n[material]\nthickness = 0.5\n",
            "\n[material]\nthickness = 1.0\n",
        )
    };
    let (thick_designed, thick_simulated) = (cost(&thick("design")), cost(&thick("simulated")));
    let (_, heavy_placed, heavy) = simulated_recipe(&thick_eggbox(""));
    let eps = heavy.equilibrium.strain.eps;
    let allow = karigami::parse(&base, "eggbox")
        .expect("parses")
        .simulation
        .material
        .eps_allow;
    assert!(eps > allow, "{eps}");
    let e_thick = error(&heavy_placed);
    assert!(
        (thick_designed - designed).abs() < 1e-12,
        "the design's cost ignores the strips"
    );
    assert!(
        ((thick_simulated - thick_designed) - (e_thick - e_design + 100.0 * (eps - allow) / allow))
            .abs()
            < 1e-9,
        "{thick_simulated} - {thick_designed} against {e_thick} - {e_design} and strain {eps}"
    );
    // Nothing to measure: refused where written.
    let unused = recipe("simulated").replace("curvature = 1.0\n", "curvature = 0.0\n");
    let e = karigami::parse(&unused, "eggbox").expect_err("refused");
    assert_eq!(e.kind.name(), "TargetShapeUnused", "{e:?}");
    // Refused, located, with the choices.
    let bad = recipe("simulate");
    let e = karigami::parse(&bad, "eggbox").expect_err("refused");
    assert_eq!(e.kind.name(), "UnknownTargetShape");
    let at = bad.find("\"simulate\"").unwrap();
    let line = bad[..at].lines().count();
    assert_eq!(e.line_col(&bad).map(|(l, _)| l), Some(line), "{e:?}");
    assert!(
        e.hint.as_deref().unwrap_or("").contains("\"simulated\""),
        "{e:?}"
    );
}

/// A `[simulation] symmetry` the lattice does not have is the recipe's
/// mistake: `build` refuses it where it is written (no files), instead of
/// warning that the shape could not be simulated.
#[test]
fn a_symmetry_the_lattice_lacks_is_refused_where_written() {
    let text = format!(
        "{}\n[simulation]\nsymmetry = 3\n",
        std::fs::read_to_string("examples/eggbox.toml").expect("recipe")
    );
    let d = karigami::parse(&text, "eggbox").expect("parses");
    let Err(e) = karigami::build(d) else {
        panic!("built with a symmetry of 3 on rows of 8 cells");
    };
    assert_eq!(e.kind.name(), "SimulationOutOfRange", "{e:?}");
    assert!(e.message.contains("not a multiple of 3"), "{}", e.message);
    let line = text.lines().position(|l| l == "symmetry = 3").unwrap() + 1;
    assert_eq!(e.line_col(&text), Some((line, 12)), "{e:?}");
}

/// `--explore` solves its starts in parallel and groups them in seed
/// order: the equilibria found, the seeds that reach each and the starts
/// left out are the same, to the bit, for any number of jobs.
#[test]
fn explore_finds_the_same_equilibria_with_any_number_of_jobs() {
    let (_, _, run) = simulated_shape("examples/eggbox.toml");
    let material = Material::ABS;
    let finish = |lm: &sim::LatticeModel, stats| sim::equilibrium(lm, stats, &material);
    let explore = |jobs| {
        let solved = std::sync::atomic::AtomicUsize::new(0);
        let found = sim::explore::explore(&run.lm, 7, 2024, jobs, &finish, &solved);
        assert_eq!(solved.into_inner(), 7, "every start counted, jobs {jobs}");
        found
    };
    let (one, left_one) = explore(1);
    assert!(one.len() >= 2, "the eggbox is multistable: {}", one.len());
    for jobs in [2, 3] {
        let (many, left_many) = explore(jobs);
        assert_eq!(left_many, left_one, "jobs {jobs}");
        assert_eq!(many.len(), one.len(), "jobs {jobs}");
        for (a, b) in one.iter().zip(&many) {
            assert_eq!(a.hits, b.hits, "jobs {jobs}");
            assert!(a.hits.is_sorted(), "seed order: {:?}", a.hits);
            let bits = |f: &sim::explore::Found| -> Vec<u64> {
                let e = &f.equilibrium;
                let points = e.points.iter().flat_map(|p| p.to_array());
                points.chain([e.energy.total()]).map(f64::to_bits).collect()
            };
            assert_eq!(bits(a), bits(b), "jobs {jobs}");
        }
    }
}

/// Issue 33, item 1: the clash rule runs on the simulated strips as they
/// bend. The cranked ring's design has no clash; its simulated shape, with
/// every strip straightened to its chord, has some; bent as the simulation
/// bends them, more pairs come closer than a strip width plus the
/// clearance (pairs whose chords stay apart; src/parts/clash/bent.rs tests
/// a bow reaching a neighbour whose chord is clear). Without `[clash]
/// allow` the build is refused, naming the closest pair with both
/// distances. `[clash]` is not an input of the simulation, so the shared
/// build's state is restored rather than solved again (bit for bit the
/// same shape; docs/commands.md, "Rebuilds reuse the simulation").
#[test]
fn bent_strips_that_meet_are_refused_though_their_chords_are_apart() {
    let text = std::fs::read_to_string("fixtures/designs/cranked-ring.toml").expect("recipe");
    let strict = text.replace("[clash]\nallow = true\n", "");
    assert_ne!(
        strict, text,
        "the example accepts its clash in a [clash] table"
    );
    let d = karigami::parse(&strict, "cranked-ring").expect("parses");
    let reach = d.fabrication.material.width + d.clash.clearance;
    let checked = karigami::check(d.clone(), &mut |_| {}).expect("grows");
    assert!(checked.measures().clashes.is_empty(), "the design clashes");
    let built = crate::util::cli_build("fixtures/designs/cranked-ring.toml", &[]);
    let state = std::fs::read(built.join(karigami::STATE_FILE)).expect("the build's state");
    assert!(
        checked.restores(&state),
        "the state is not the strict recipe's"
    );
    let Err(e) = checked.assemble_for_check(Some(&state)) else {
        panic!("the bent strips' clash was not refused")
    };
    assert_eq!(e.kind, karigami::ErrorKind::StripClash, "{}", e.message);
    assert!(e.message.contains("bent centre lines"), "{}", e.message);
    let number_before = |tail: &str| -> f64 {
        let head = &e.message[..e.message.find(tail).expect(tail)];
        let word = head.rsplit(' ').next().unwrap();
        word.trim_start_matches('(').parse().unwrap()
    };
    let bent = number_before(" mm apart at");
    let chord = number_before(" mm as straight chords");
    assert!(bent < reach && bent < chord, "bent {bent}, chords {chord}");
    let bent_pairs = number_before(" clashing pairs in all");
    // The same simulated shape measured on straight chords finds fewer.
    let (lattice, placed, _) = simulated_recipe(&strict);
    let chords = karigami::measure(&d, &placed).clashes.len();
    assert!(
        (bent_pairs as usize) > chords,
        "{bent_pairs} bent against {chords} as chords ({} cells)",
        lattice.cells.len()
    );
}

/// Issue 33, item 3: a true planar mechanism folds and deploys with its
/// strips straight: zero energy (to 1e-6 N mm) at every step of the path
/// both ways, no snap-through, flat again at the collapsed end, and back
/// at the design's equilibrium.
#[test]
fn a_planar_mechanism_deploys_along_a_zero_energy_path() {
    let text = std::fs::read_to_string("examples/mirror-arm.toml").expect("recipe");
    let (_, _, run) = simulated_recipe(&text);
    let free = run.lm.model.fixed.iter().filter(|f| !**f).count();
    let steps = sim::path::Path::step_count(free, run.theta);
    let material = Material::ABS;
    let path = sim::path::path(&run.lm, &run.equilibrium.stats, steps, &material);
    assert_eq!(path.failed, None);
    assert_eq!(path.collapse.len(), steps + 1);
    assert_eq!(path.deploy.len(), steps + 1);
    for p in path.points() {
        assert!(
            p.energy.abs() <= 1e-6,
            "{} N mm at {} deg",
            p.energy,
            p.theta.to_degrees()
        );
        assert!(p.lambda_min > 0.0);
    }
    assert!(path.snaps().is_empty(), "{:?}", path.snaps());
    assert!(path.folds_flat());
    assert!(path.end_distance.unwrap() < 1e-6);
    // Both ways pass the same states.
    assert!(path.hysteresis < 1e-6, "{}", path.hysteresis);
    let low = path.collapse.last().unwrap().theta;
    assert!((low - sim::path::COLLAPSED * run.theta).abs() < 1e-12);
}

/// The path of a bent lattice is the same run after run (the report and
/// path.png depend on nothing else), and its steps bounded.
#[test]
fn the_deployment_path_repeats_and_is_bounded() {
    let text = std::fs::read_to_string("examples/curved-sheet.toml").expect("recipe");
    let (_, _, run) = simulated_recipe(&text);
    let free = run.lm.model.fixed.iter().filter(|f| !**f).count();
    let steps = sim::path::Path::step_count(free, run.theta);
    assert!((sim::path::MIN_STEPS..=sim::path::MAX_STEPS).contains(&steps));
    let a = sim::path::path(&run.lm, &run.equilibrium.stats, steps, &Material::ABS);
    let b = sim::path::path(&run.lm, &run.equilibrium.stats, steps, &Material::ABS);
    assert_eq!(a, b);
    assert_eq!(a.collapse[0].energy, run.equilibrium.energy.total());
}

/// The flat sheet and the disk are rigid as linkages: their path bends the
/// strips out of the plane from the flat design, where a whole step's
/// solve found no equilibrium (issue 33); split steps follow it the whole
/// way, back to the design's state.
#[test]
fn flat_designs_follow_the_whole_path() {
    for name in ["flat-sheet", "disk"] {
        let text = std::fs::read_to_string(format!("examples/{name}.toml")).expect("recipe");
        let (_, _, run) = simulated_recipe(&text);
        let (run, path) = sim::path::chosen(run, &Material::ABS);
        let path = path.expect("a path");
        assert_eq!(path.failed, None, "{name}");
        assert!(path.folds_flat(), "{name}");
        assert!(path.end_distance.unwrap() < 1e-3, "{name}");
        // Back in the design's state: that solve is the one reported.
        assert_eq!(run.equilibrium.energy.total(), path.collapse[0].energy);
    }
}

/// templates/bumps.toml on a coarse mesh, opened to `theta` (radians;
/// None: its design opening), held at its first and last rows as a
/// vault's two feet, or free. It is a mechanism: free, it opens to any
/// theta at no energy; held where the design has its rows, it cannot.
fn bumps_held(supports: bool, theta: Option<f64>) -> (Lattice, sim::Simulation) {
    let text = std::fs::read_to_string("templates/bumps.toml").expect("recipe");
    let d = karigami::parse(&format!("{text}\n[simulation]\nedge_length = 40.0\n"), "t")
        .expect("parses");
    let lattice = d.grow().expect("grows");
    let row = |r: u32| lattice.vertices.iter().filter(move |v| v.key.row == r);
    let last = lattice.vertices.iter().map(|v| v.key.row).max().unwrap();
    let mut settings = d.simulation.clone();
    settings.theta = theta;
    if supports {
        settings.supports = row(0)
            .chain(row(last))
            .map(|v| [v.key.row, v.key.col])
            .collect();
    }
    let deploy = karigami::deploy::deployment(&lattice);
    let m = &d.fabrication.material;
    let run = sim::simulate(&lattice, &deploy, m.width, m.thickness, &settings).expect("simulates");
    (lattice, run)
}

/// Pinned vertices stay exactly where the design has them, the pins take
/// force when the opening asked differs from the design's, and with no
/// load on the lattice the reactions balance: their sum and their moment
/// vanish to the solver's tolerance against the largest of them.
#[test]
fn supports_hold_their_vertices_and_their_reactions_balance() {
    let (lattice, design) = bumps_held(false, None);
    let theta = Some(0.9 * design.theta);
    let (_, held) = bumps_held(true, theta);
    let (_, free) = bumps_held(false, theta);
    let placed = lattice.placed();
    let eq = &held.equilibrium;
    assert!(eq.supports.len() >= 6, "{}", eq.supports.len());
    assert!(free.equilibrium.supports.is_empty());
    for r in &eq.supports {
        let v = r.vertex as usize;
        assert_eq!(eq.points[v], placed.vertices[v].pos, "vertex {v} moved");
        assert_eq!(r.at, placed.vertices[v].pos);
    }
    let largest = eq
        .supports
        .iter()
        .map(|r| r.force.length())
        .fold(0.0, f64::max);
    assert!(largest > 1e-3, "the pins hold nothing: {largest} N");
    let sum: DVec3 = eq.supports.iter().map(|r| r.force).sum();
    let c = eq.supports[0].at;
    let moment: DVec3 = eq.supports.iter().map(|r| (r.at - c).cross(r.force)).sum();
    let arm = eq
        .supports
        .iter()
        .map(|r| r.at.distance(c))
        .fold(0.0, f64::max);
    assert!(
        sum.length() <= 1e-6 * largest,
        "sum {sum} against {largest} N"
    );
    assert!(moment.length() <= 1e-6 * largest * arm, "moment {moment}");
    // Free, it opens at no energy (measured 2e-23 N mm); held, the
    // strips bend (1839 N mm, the largest reaction 172 N).
    assert!(free.equilibrium.energy.total() < 1e-9);
    assert!(eq.energy.total() > 100.0, "{}", eq.energy.total());
}

/// fixtures/designs/vault.toml (`karigami design` on a small cylindrical
/// vault, fixtures/designs/vault-target.toml): held at its 12 feet its
/// simulated shape keeps to its design; free, the sheet relaxes flat,
/// as a surface that unrolls without stretching does (docs/physics.md,
/// "Supports"). Measured (from the design, after the best rigid fit):
/// held rms 1.79 mm, largest 2.86 mm, strain 0.41 %; free rms 21.1 mm,
/// largest 32.8 mm.
#[test]
fn a_vault_held_at_its_feet_keeps_its_shape_and_free_it_flattens() {
    let text = std::fs::read_to_string("fixtures/designs/vault.toml").expect("recipe");
    let d = karigami::parse(&text, "vault").expect("parses");
    assert_eq!(d.simulation.supports.len(), 12);
    let lattice = d.grow().expect("grows");
    let deploy = karigami::deploy::deployment(&lattice);
    let m = &d.fabrication.material;
    let run = |settings: &Settings| {
        sim::simulate(&lattice, &deploy, m.width, m.thickness, settings).expect("simulates")
    };
    let held = run(&d.simulation);
    let free = run(&Settings {
        supports: Vec::new(),
        ..d.simulation.clone()
    });
    let (h, f) = (&held.equilibrium, &free.equilibrium);
    assert!(h.fit.rms < 3.0 && h.fit.max < 5.0, "held: {:?}", h.fit);
    assert!(f.fit.rms > 15.0 && f.fit.max > 25.0, "free: {:?}", f.fit);
    assert!(h.strain.eps < d.simulation.material.eps_allow);
}

/// Supports on a planar true mechanism, which is not simulated, are said
/// to be unused in the build's warnings, not dropped in silence.
#[test]
fn supports_on_a_lattice_that_is_not_simulated_are_said_unused() {
    let text = std::fs::read_to_string("templates/sheet.toml").expect("recipe")
        + "\n[simulation]\nsupports = [[5, 6], [0, 0], [2, 3]]\n";
    let built = karigami::build(karigami::parse(&text, "sheet").expect("parses")).expect("builds");
    let report = karigami::build_text(&built);
    assert!(
        report.contains(
            "[simulation] supports are not used: this lattice is a planar true mechanism"
        ),
        "{report}"
    );
}

/// The vault's build says which vertices are pinned and what they hold:
/// report.txt's supports line, deployed.json's `supports` and
/// `support_span`, and the guide's "Pin it to the base".
#[test]
fn a_vault_build_names_its_supports_in_the_report_the_json_and_the_guide() {
    let text = std::fs::read_to_string("fixtures/designs/vault.toml").expect("recipe");
    let built = karigami::build(karigami::parse(&text, "vault").expect("parses")).expect("builds");
    let report = karigami::build_text(&built);
    let line = report
        .lines()
        .find(|l| l.starts_with("supports: "))
        .unwrap_or_else(|| panic!("no supports line:\n{report}"));
    assert!(line.starts_with("supports: 12 vertices pinned"), "{line}");
    assert!(
        line.contains("[0, 0] ") && line.contains("[5, 4] "),
        "{line}"
    );
    // The state reported is the held one; the path is walked free.
    assert!(
        report.contains("equilibrium reported (docs/physics.md, \"Supports\"): the state solved from the design with its 12 supports held"),
        "{report}"
    );
    assert!(report.contains("deployment path (docs/physics.md) of the lattice standing free"));
    let files = karigami::files(&built);
    let json = &files
        .iter()
        .find(|(n, _)| n == "deployed.json")
        .expect("deployed.json")
        .1;
    let doc: serde_json::Value = serde_json::from_slice(json).expect("json");
    let supports = doc["supports"].as_array().expect("supports");
    assert_eq!(supports.len(), 12);
    assert_eq!(supports[0]["name"], "[0, 0]");
    let v3 = |x: &serde_json::Value| {
        let a: Vec<f64> = x
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        DVec3::new(a[0], a[1], a[2])
    };
    let at: Vec<DVec3> = supports.iter().map(|s| v3(&s["pos"])).collect();
    let span = at
        .iter()
        .flat_map(|a| at.iter().map(move |b| a.distance(*b)))
        .fold(0.0, f64::max);
    assert!((doc["support_span"].as_f64().unwrap() - span).abs() < 1e-9);
    assert!(
        line.contains(&format!("{span:.1} mm between the farthest two")),
        "{line}"
    );
    // No load: the reactions balance (tests above), here as written.
    let forces: Vec<DVec3> = supports.iter().map(|s| v3(&s["reaction"])).collect();
    let largest = forces.iter().map(|f| f.length()).fold(0.0, f64::max);
    assert!(largest > 0.1, "{largest} N");
    assert!(forces.iter().sum::<DVec3>().length() < 1e-6 * largest);
    let guide = karigami::guide(&built);
    let words: Vec<String> = guide
        .pages
        .iter()
        .flat_map(|p| &p.groups)
        .flat_map(|g| &g.items)
        .filter_map(|i| match &i.shape {
            karigami::Shape::Text { text, .. } => Some(text.clone()),
            _ => None,
        })
        .collect();
    assert!(
        words.iter().any(|w| w == "Pin it to the base"),
        "no heading"
    );
    let all = words.join(" ");
    assert!(all.contains("pin these 12 vertices"), "{all}");
}
