//! docs/math.md 5's worked examples, to 1e-9.

use crate::util::{close, close_vec, v2};
use glam::DVec3;
use karigami::{Direction, Leg, RowParams, grow_sheet, verify};

fn worked_example(scale: f64, start: usize, direction: DVec3) -> karigami::Lattice {
    let points = [v2(0.0, 0.0), v2(2.0, 0.0), v2(4.0, 0.3)].map(|p| p * scale);
    let kappa = [0.2 * scale, -0.1 * scale];
    let row = RowParams {
        start,
        direction: Some(Direction::Vector(direction)),
        left_leg: Leg::Length(1.0 * scale),
        right_leg: Leg::Length(1.3 * scale),
        ..RowParams::default()
    };
    grow_sheet(2, &points, &kappa, &[row]).expect("the worked example grows")
}

fn check_worked_example(scale: f64) {
    let d = 30f64.to_radians();
    let lat = worked_example(scale, 0, v2(-d.cos(), -d.sin()));
    let tol = 1e-9 * scale;
    let pivots = [
        v2(0.880761466250, -0.646192668748),
        v2(3.155892279165, -0.487752711272),
    ];
    let legs = [
        [
            1.092385337495,
            1.000000000000,
            1.461916132324,
            1.292385337495,
        ],
        [
            1.254587449477,
            1.499714020343,
            1.300000000000,
            1.154587449477,
        ],
    ];
    let z_pivot = [1.092385337495, 1.054587449477];
    let phi = [1.985022897110, 1.991412945673];
    for (j, cell) in lat.cells.iter().enumerate() {
        close_vec(cell.pivot, pivots[j] * scale, tol, &format!("pivot {j}"));
        for (k, (&got, want)) in lat.legs(cell).iter().zip(legs[j]).enumerate() {
            close(got, want * scale, tol, &format!("cell {j} leg l{}", k + 1));
        }
        close(cell.z_pivot, z_pivot[j] * scale, tol, &format!("z(p) {j}"));
        close(lat.phi(cell), phi[j], 1e-9, &format!("phi {j}"));
    }
    let front = [
        (v2(0.014736062466, -1.146192668748), 2.092385337495),
        (v2(2.059465859330, -1.510978614335), 2.554301469820),
        (v2(4.353624620215, -0.993160704088), 2.354587449477),
    ];
    for (j, (pos, z)) in front.iter().enumerate() {
        let v = &lat.vertices[3 + j];
        assert_eq!((v.key.row, v.key.col), (1, j as u32));
        close_vec(v.pos, *pos * scale, tol, &format!("x[1][{j}]"));
        close(v.z, z * scale, tol, &format!("z(x[1][{j}])"));
    }
    // Next-row kappa = z(x[1][j]) - z(x[1][j+1]).
    let next_kappa = [-0.461916132324, 0.199714020343];
    for (j, want) in next_kappa.iter().enumerate() {
        let k = lat.vertices[3 + j].z - lat.vertices[4 + j].z;
        close(k, want * scale, tol, &format!("next kappa {j}"));
    }
    let report = verify(&lat);
    assert!(report.passed(), "{report:#?}");
}

#[test]
fn worked_example_2d_unitless() {
    check_worked_example(1.0);
}

#[test]
fn worked_example_2d_in_mm() {
    // The same design written in mm (x10) scales every length by 10.
    check_worked_example(10.0);
}

#[test]
fn worked_example_from_the_other_start_site() {
    let d = 30f64.to_radians();
    let first = worked_example(1.0, 0, v2(-d.cos(), -d.sin()));
    let c1 = &first.cells[1];
    let v2_at_1 = (c1.pivot - first.vertices[2].pos).normalize();
    let second = worked_example(1.0, 1, v2_at_1);
    for (a, b) in first.vertices.iter().zip(&second.vertices) {
        close_vec(a.pos, b.pos, 1e-12, "vertex");
        close(a.z, b.z, 1e-12, "z");
    }
}

#[test]
fn single_cell_3d() {
    // docs/math.md 5: UL = 0, UR = (2,0,0), kappa = 0.5, v2 = unit(-1,-1,-0.5).
    let row = RowParams {
        start: 0,
        direction: Some(Direction::Vector(DVec3::new(-1.0, -1.0, -0.5))),
        left_leg: Leg::Match,
        right_leg: Leg::Length(1.0),
        ..RowParams::default()
    };
    let lat = grow_sheet(3, &[DVec3::ZERO, DVec3::new(2.0, 0.0, 0.0)], &[0.5], &[row]).unwrap();
    let cell = &lat.cells[0];
    let [l1, _, _, l4] = lat.legs(cell);
    close(l4, 2.25, 1e-12, "l4");
    close(l1, 1.75, 1e-12, "l1");
    close_vec(cell.pivot, DVec3::new(0.5, -1.5, -0.75), 1e-12, "pivot");
    assert!(verify(&lat).passed());
}
