//! Deployment (docs/math.md 8.4): C(theta) over random lattices and the gallery,
//! and the mobility counts docs/math.md reports.

use crate::property::random_lattice;
use crate::util::Rng;
use karigami::{
    Lattice, TOLERANCE,
    deploy::{configuration, deployment, mobility, planar_misfit},
};
use std::fs;

fn example(name: &str) -> Lattice {
    let text = fs::read_to_string(format!("{}/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap();
    karigami::parse(&text, "x").unwrap().grow().unwrap()
}

#[track_caller]
fn assert_configuration_valid(lattice: &Lattice, what: &str) {
    let c = configuration(lattice);
    assert_eq!(c.unreached, 0, "{what}: every cell is reached");
    assert!(
        c.path_residual < TOLERANCE,
        "{what}: path residual {:e}",
        c.path_residual
    );
    assert!(
        c.design_residual < TOLERANCE,
        "{what}: design residual {:e}",
        c.design_residual
    );
    assert!(
        c.collapse_residual < TOLERANCE,
        "{what}: collapse residual {:e}",
        c.collapse_residual
    );
    assert!(
        c.theta_max >= c.theta_design - 1e-12,
        "{what}: the design is in range"
    );
    // theta = 0 folds every cell shut; the design angle gives the design.
    let shut = c.angles(0.0).unwrap();
    assert!(shut.iter().all(|&phi| phi < 1e-6), "{what}: {shut:?}");
    assert!(c.angles(c.theta_max + 1e-6).is_none());
    // Every cell opens monotonically with the reference cell.
    let (a, b) = (
        c.angles(0.3 * c.theta_max).unwrap(),
        c.angles(0.6 * c.theta_max).unwrap(),
    );
    assert!(
        a.iter().zip(&b).all(|(x, y)| x <= y),
        "{what}: cells open together"
    );
}

#[test]
fn random_lattices_have_a_path_independent_configuration() {
    let mut rng = Rng::new(31);
    let mut checked = 0;
    for case in 0..120 {
        if let Ok((lattice, _)) = random_lattice(&mut rng, 2 + case % 2) {
            assert_configuration_valid(&lattice, &format!("case {case}"));
            checked += 1;
        }
    }
    assert!(checked > 60, "{checked}");
}

#[test]
fn random_sheets_of_four_or_more_rows_are_rigid_linkages_except_3d_ribbons() {
    // docs/math.md 8.4: generic 2-D and 3-D sheets with 4+ rows have no internal
    // degree of freedom; they deploy through strip bending.
    let mut rng = Rng::new(5);
    let mut counted = [0, 0];
    for case in 0..400 {
        let dim = 2 + case % 2;
        let Ok((lattice, _)) = random_lattice(&mut rng, dim) else {
            continue;
        };
        if lattice.rows() < 4 || lattice.width < 2 {
            continue;
        }
        // In space, two-cell-wide ribbons keep two bending modes (measured:
        // every random 4- and 5-row ribbon); from three cells wide they are rigid.
        let expected = if dim == 3 && lattice.width == 2 { 2 } else { 0 };
        assert_eq!(
            mobility(&lattice),
            Some(expected),
            "case {case}: {dim}-D, {} x {}",
            lattice.rows(),
            lattice.width
        );
        counted[dim - 2] += 1;
    }
    assert!(counted.iter().all(|&n| n >= 5), "{counted:?}");
}

#[test]
fn chains_are_mechanisms_that_place_exactly_at_every_angle() {
    let mut rng = Rng::new(9);
    let mut chains = 0;
    for _ in 0..2000 {
        let Ok((lattice, _)) = random_lattice(&mut rng, 2) else {
            continue;
        };
        if lattice.width != 1 || lattice.rows() < 2 {
            continue;
        }
        chains += 1;
        assert_eq!(mobility(&lattice), Some(1));
        let c = configuration(&lattice);
        for f in [0.1, 0.5, 0.9, 0.999] {
            let m = planar_misfit(&lattice, &c, f * c.theta_max).unwrap();
            assert!(m < 1e-9, "chain misfit {m:e} at {f} theta_max");
        }
        if chains == 20 {
            break;
        }
    }
    assert_eq!(chains, 20);
}

#[test]
fn the_gallery_mobility_verdicts_match_math_md() {
    // (recipe, internal degrees of freedom, a true mechanism)
    for (name, dof, mechanism) in [
        ("examples/mirror-arm.toml", 1, true),
        ("examples/flat-sheet.toml", 0, false),
        ("examples/torus.toml", 1, true),
        ("examples/disk.toml", 0, false),
        ("fixtures/designs/helix-bowl.toml", 0, false),
        // Axisymmetric like the torus: a mechanism too.
        ("examples/half-ellipsoid.toml", 1, true),
        ("examples/bowl.toml", 1, true),
    ] {
        let lattice = example(name);
        assert_configuration_valid(&lattice, name);
        let d = deployment(&lattice);
        assert_eq!(d.mobility, Some(dof), "{name}");
        assert_eq!(d.is_mechanism(), mechanism, "{name}");
    }
    // Bent facets: no rigid deployed state, so no linkage count.
    for name in ["examples/eggbox.toml", "examples/saddle-ring.toml"] {
        let lattice = example(name);
        assert_configuration_valid(&lattice, name);
        let d = deployment(&lattice);
        assert_eq!(d.mobility, None, "{name}");
        assert!(!d.is_mechanism());
        assert!(d.verdict(&lattice).contains("strip bending"));
    }
    // A uniform square grid moves as one (1 DOF) and places without misfit.
    let grid = "[lattice]\nseed = \"sheet\"\nkappa = 0.0\n[lattice.line]\nfrom = [0.0, 0.0]\nto = [100.0, 0.0]\ncells = 5\n[lattice.grow]\nrows = 5\nangle = 45.0\n";
    let lattice = karigami::parse(grid, "grid").unwrap().grow().unwrap();
    let d = deployment(&lattice);
    assert_eq!(d.mobility, Some(1));
    assert!(d.misfits.iter().all(|&(_, m)| m < 1e-9), "{:?}", d.misfits);
    // A generic planar sheet misses when placed away from its design angle.
    let d = deployment(&example("examples/flat-sheet.toml"));
    assert!(d.misfits.iter().all(|&(_, m)| m > 1e-4), "{:?}", d.misfits);
}
