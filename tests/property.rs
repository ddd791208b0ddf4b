//! Property tests over random admissible designs (docs/math.md 8): every invariant
//! holds to 1e-9, and a row regrown from another start site is the same row.

use crate::util::Rng;
use glam::DVec3;
use karigami::{
    Direction, Lattice, Leg, RowParams, TOLERANCE, grow_sheet, testing::front_frame, verify,
};

pub(crate) struct RandomDesign {
    pub dim: usize,
    pub points: Vec<DVec3>,
    pub kappa: Vec<f64>,
    pub rows: Vec<RowParams>,
}

fn random_seed(rng: &mut Rng, dim: usize) -> (Vec<DVec3>, Vec<f64>) {
    let m = 1 + rng.below(7);
    let mut points = vec![DVec3::ZERO];
    let mut kappa = Vec::new();
    for _ in 0..m {
        let z = if dim == 3 { rng.range(-0.3, 0.3) } else { 0.0 };
        let step = DVec3::new(rng.range(0.7, 1.3), rng.range(-0.2, 0.2), z);
        points.push(*points.last().unwrap() + step);
        kappa.push(rng.range(-0.4, 0.4) * step.length());
    }
    (points, kappa)
}

/// A direction strictly inside the admissible cone of the start cell
/// (docs/math.md 4.2): within `acos(kappa/|t|)` of the axis, on the growth side.
fn direction_in_cone(rng: &mut Rng, dim: usize, ul: DVec3, ur: DVec3, kappa: f64) -> Direction {
    let half = (kappa / ul.distance(ur)).acos();
    let angle = rng.range(0.2, 0.8) * half;
    let frame = front_frame(ul, ur).unwrap();
    let tilt = if dim == 3 { rng.range(-0.6, 0.6) } else { 0.0 };
    let v =
        angle.cos() * frame.axis + angle.sin() * (tilt.cos() * frame.down + tilt.sin() * frame.out);
    Direction::Vector(v * rng.range(0.5, 3.0))
}

fn random_leg(rng: &mut Rng) -> Leg {
    if rng.below(3) == 0 {
        Leg::Match
    } else {
        Leg::Length(rng.range(0.4, 1.4))
    }
}

/// Grow a random design one row at a time, drawing each row's direction in
/// the cone of the front it grows on. Returns None if a row is refused.
pub(crate) fn random_lattice(rng: &mut Rng, dim: usize) -> Result<(Lattice, RandomDesign), String> {
    let (points, kappa) = random_seed(rng, dim);
    let m = kappa.len();
    let nrows = 1 + rng.below(5);
    let mut rows = Vec::new();
    let mut lattice = grow_sheet(dim, &points, &kappa, &[]).unwrap();
    for i in 0..nrows {
        let start = rng.below(m);
        let base = i * (m + 1);
        let (a, b) = (
            lattice.vertices[base + start],
            lattice.vertices[base + start + 1],
        );
        rows.push(RowParams {
            start,
            direction: Some(direction_in_cone(rng, dim, a.pos, b.pos, a.z - b.z)),
            left_leg: random_leg(rng),
            right_leg: random_leg(rng),
            ..RowParams::default()
        });
        lattice = grow_sheet(dim, &points, &kappa, &rows).map_err(|e| e.to_string())?;
    }
    Ok((
        lattice,
        RandomDesign {
            dim,
            points,
            kappa,
            rows,
        },
    ))
}

/// Regrow every row from a different start site with the direction the
/// first growth produced there; the rows must agree to 1e-9.
fn assert_start_site_independent(lattice: &Lattice, design: &RandomDesign, rng: &mut Rng) {
    let m = lattice.width;
    for (i, row) in design.rows.iter().enumerate() {
        let other = rng.below(m);
        let cell = &lattice.cells[i * m + other];
        let ur = lattice.vertex(cell.ur).pos;
        let mut rows = design.rows.clone();
        rows[i] = RowParams {
            start: other,
            direction: Some(Direction::Vector(cell.pivot - ur)),
            ..row.clone()
        };
        let again = grow_sheet(design.dim, &design.points, &design.kappa, &rows).expect("regrows");
        let scale = lattice.legs(cell).iter().sum::<f64>();
        for (a, b) in lattice.vertices.iter().zip(&again.vertices) {
            let d = a.pos.distance(b.pos).max((a.z - b.z).abs()) / scale;
            assert!(
                d < TOLERANCE,
                "row {i} regrown from column {other}: vertex differs by {d:e} relative"
            );
        }
    }
}

fn run(dim: usize, cases: usize, seed: u64) {
    let mut rng = Rng::new(seed);
    let mut grown = 0;
    let mut refused = 0;
    for case in 0..cases {
        match random_lattice(&mut rng, dim) {
            Ok((lattice, design)) => {
                grown += 1;
                let report = verify(&lattice);
                assert!(report.passed(), "case {case}: {:#?}", report.checks);
                assert!(report.worst() < TOLERANCE);
                assert_start_site_independent(&lattice, &design, &mut rng);
            }
            Err(message) => {
                refused += 1;
                assert!(!message.is_empty());
            }
        }
    }
    // Directions are drawn in the start cone, so most designs must grow;
    // a generator that only produced refusals would test nothing.
    assert!(
        grown * 2 > cases,
        "only {grown} of {cases} random {dim}-D designs grew ({refused} refused)"
    );
}

#[test]
fn random_2d_sheets_satisfy_every_invariant() {
    run(2, 400, 1);
}

#[test]
fn random_3d_sheets_satisfy_every_invariant() {
    run(3, 400, 2);
}

/// Verification must catch a broken lattice: each corruption below breaks
/// one invariant of docs/math.md 8 and the report must say which.
#[test]
fn corrupted_lattices_fail_verification() {
    use karigami::Invariant as I;
    let mut rng = Rng::new(7);
    let (lattice, _) = loop {
        if let Ok(found) = random_lattice(&mut rng, 3)
            && found.0.width >= 2
            && found.0.rows() >= 2
        {
            break found;
        }
    };
    // A pivot off its rods.
    let mut bent = lattice.clone();
    bent.cells[0].pivot += DVec3::new(1e-6, 0.0, 0.0);
    let report = verify(&bent);
    assert!(!report.passed());
    assert!(report.check(I::RodStraightness).max > 1e-8);

    // A vertex whose z disagrees with its legs.
    let mut shifted = lattice.clone();
    let v = shifted.cells[0].lr as usize;
    shifted.vertices[v].z += 1e-6;
    let report = verify(&shifted);
    assert!(report.check(I::LegsMatchZ).max > 1e-8);
    assert!(report.check(I::CollapsedMatchesConstruction).max > 1e-8);

    // An interior vertex moved in space: legs change, so collapsibility and
    // compatibility around it break.
    let mut moved = lattice.clone();
    let v = moved.cells[moved.width + 1].ul as usize;
    moved.vertices[v].pos += DVec3::new(0.0, 1e-6, 1e-6);
    let report = verify(&moved);
    assert!(!report.passed());
    assert!(report.check(I::CollapsedSingleValued).max > 1e-8);

    // A NaN anywhere fails.
    let mut broken = lattice.clone();
    broken.cells[1].pivot.x = f64::NAN;
    assert!(!verify(&broken).passed());
}
