//! The two traversals held together: the rows' pass gives the report of
//! the pass over the cells bit for bit, on good and damaged lattices; the
//! recording shortcuts give the full formulas' largest residuals.

use super::cells::verify_with;
use super::incidence::Incidence;
use super::report::{Check, Invariant, Report};
use super::residuals::{Ratio, bend};
use super::rows::verify_rows;
use super::verify;
use crate::lattice::{Kind, Lattice, fixtures};
use glam::DVec3;

fn sheet() -> Lattice {
    fixtures::sheet(&fixtures::line(3), &[0.0; 3], 1, 45.0, 3)
}

/// `record` keeps the largest residual (a NaN sticks) and its first
/// site; the shortcuts of `record_ratio` and `record_bend` keep the largest
/// residual, its site and the count of `record` of the full formula,
/// over residuals of every magnitude, with zeros, NaNs and infinities.
#[test]
fn shortcut_records_match_the_full_formula() {
    let mut rng = crate::rng::Rng::new(14);
    let value = |rng: &mut crate::rng::Rng| match rng.next_u64() % 40 {
        0 => 0.0,
        1 => f64::NAN,
        2 => f64::INFINITY,
        3 => f64::MIN_POSITIVE * rng.signed(),
        _ => rng.signed() * 10f64.powf(60.0 * rng.signed()),
    };
    for round in 0..200 {
        let (mut full, mut ratio) = (
            Check::new(Invariant::HorizontalPores),
            Check::new(Invariant::HorizontalPores),
        );
        let (mut full_bend, mut bend_check) = (
            Check::new(Invariant::RodStraightness),
            Check::new(Invariant::RodStraightness),
        );
        let mut reference: (f64, Option<String>) = (0.0, None);
        for k in 0..500 {
            // Mostly near-equal residuals, as in a good lattice.
            let scale = if round % 2 == 0 { 1e-12 } else { 1.0 };
            let num = if k % 7 == 0 {
                value(&mut rng)
            } else {
                scale * rng.signed()
            };
            let den = if k % 11 == 0 {
                value(&mut rng)
            } else {
                1.0 + rng.uniform()
            };
            let site = || format!("{k}");
            // `record`'s rule spelled out: a NaN sticks once seen, a
            // larger residual (or the first NaN) replaces the largest.
            let r = num / den;
            if !reference.0.is_nan() && (r.is_nan() || r.abs() > reference.0) {
                reference = (r.abs(), Some(site()));
            }
            full.record(r, site);
            ratio.record_ratio(Ratio { num, den }, site);
            let a = DVec3::new(rng.signed(), scale * rng.signed(), num.min(1e3));
            let b = DVec3::new(rng.signed(), rng.signed(), rng.signed());
            let (la, lb) = (1.0 + rng.uniform(), den);
            full_bend.record(bend([(a, la), (b, lb)]), site);
            bend_check.record_bend([(a, la), (b, lb)], site);
        }
        assert_eq!(full.count, 500);
        assert_eq!(full.max.to_bits(), reference.0.to_bits(), "round {round}");
        assert_eq!(full.site, reference.1, "round {round}");
        for (x, y) in [(&full, &ratio), (&full_bend, &bend_check)] {
            assert_eq!(x.count, y.count);
            assert_eq!(x.max.to_bits(), y.max.to_bits(), "round {round}");
            assert_eq!(x.site, y.site, "round {round}");
        }
    }
}

/// A tube of `n` points round a circle, `rows` rows tilted up.
fn tube(n: usize, rows: usize) -> Lattice {
    let step = glam::DQuat::from_rotation_z(std::f64::consts::TAU / n as f64);
    let ring: Vec<DVec3> = std::iter::successors(Some(30.0 * DVec3::X), |p| Some(step * *p))
        .take(n)
        .collect();
    let row = crate::lattice::RowParams {
        direction: Some(crate::legs::Direction::Angles {
            angle_deg: 45.0,
            tilt_deg: 90.0,
        }),
        ..Default::default()
    };
    crate::lattice::grow(Kind::Loop, 3, &ring, &vec![0.0; n], &vec![row; rows])
        .expect("the tube grows")
}

/// A grown sheet or loop is a grid whose formula names the cells the
/// table read from the corner indices holds, for every vertex, and
/// verification gives the same report with either; a cell with other
/// corners, or a vertex more, makes it a table again.
#[test]
fn a_grid_names_the_cells_of_the_table() {
    // The tube of templates/tube.toml: ten points round a circle.
    let tube = tube(10, 3);
    for lattice in [sheet(), tube] {
        let grid = Incidence::grid(&lattice).expect("a grown sheet or loop is a grid");
        let Incidence::Table(table) = Incidence::table(&lattice) else {
            unreachable!("a table")
        };
        assert_eq!(table.len(), lattice.vertices.len());
        for (v, entry) in table.iter().enumerate() {
            let rc = (v / grid.front, v % grid.front);
            assert_eq!(grid.at_vertex(rc.0, rc.1), *entry, "vertex {v}");
        }
        // Both give the same report, bit for bit.
        assert_eq!(
            verify_with(&lattice, &Incidence::table(&lattice)),
            verify(&lattice)
        );
        let mut odd = lattice.clone();
        odd.cells[1].ur = odd.cells[1].ul;
        assert!(Incidence::grid(&odd).is_none());
        let mut extra = lattice.clone();
        extra.vertices.push(extra.vertices[0]);
        assert!(Incidence::grid(&extra).is_none());
    }
}

/// Two reports the same bits (NaN included, which `==` would not
/// allow): every check's largest, site and count, and the tolerance.
fn same_bits(x: &Report, y: &Report) -> bool {
    let key = |r: &Report| {
        let checks: Vec<_> = r
            .checks
            .iter()
            .map(|c| (c.invariant, c.count, c.max.to_bits(), c.site.clone()))
            .collect();
        (checks, r.tolerance.to_bits(), r.interior_vertices)
    };
    key(x) == key(y)
}

/// Verification by rows gives the report of the pass over the cells,
/// bit for bit, on sheets and loops both good and damaged: positions,
/// pivots and z moved by amounts from rounding to gross, NaN and
/// infinite coordinates, a cell's column renamed, a corner index moved off the grid.
#[test]
fn rows_give_the_report_of_the_pass_over_the_cells() {
    let tube = tube(7, 4);
    let wide = fixtures::sheet(&fixtures::line(6), &[0.0; 6], 2, 40.0, 5);
    // Rows enough that most fronts and rows are left out of the
    // comparison with the construction, unless damaged (`Block`).
    let tall = fixtures::sheet(&fixtures::line(12), &[0.0; 12], 5, 45.0, 12);
    let mut rng = crate::rng::Rng::new(5);
    for lattice in [sheet(), wide, tube, tall] {
        let grid = Incidence::grid(&lattice).expect("a grid");
        assert!(lattice.extrinsic());
        let table = Incidence::table(&lattice);
        assert!(same_bits(
            &verify_rows(&lattice, &grid).expect("a regular grid"),
            &verify_with(&lattice, &table)
        ));
        for round in 0..300 {
            let mut bad = lattice.clone();
            for _ in 0..1 + round % 3 {
                let size = match rng.next_u64() % 6 {
                    0 => f64::NAN,
                    1 => f64::INFINITY,
                    k => 10f64.powi(-(3 * k as i32)) * rng.signed(),
                };
                let v = (rng.next_u64() % bad.vertices.len() as u64) as usize;
                let c = (rng.next_u64() % bad.cells.len() as u64) as usize;
                let axis = (rng.next_u64() % 3) as usize;
                match rng.next_u64() % 6 {
                    0 => bad.vertices[v].pos[axis] += size,
                    1 => bad.vertices[v].z += size,
                    2 => bad.cells[c].pivot[axis] += size,
                    3 => bad.cells[c].z_pivot += size,
                    4 => bad.cells[c].col ^= 1,
                    // A corner index off the grid: the rows' pass
                    // gives up at that row, the pass over the cells
                    // reports.
                    _ => bad.cells[c].lr = bad.cells[c].ll,
                }
            }
            let rows = verify(&bad);
            let cells = verify_with(&bad, &Incidence::table(&bad));
            assert!(
                same_bits(&rows, &cells),
                "round {round}: {rows:?} {cells:?}"
            );
        }
    }
}

/// A cell reached through no corner fails the collapsed state, and the
/// rod lengths are then measured after the sweep with the final z:
/// those of the cells that were reached stay exact.
#[test]
fn a_disconnected_cell_fails_and_the_rods_are_measured_after_the_sweep() {
    let good = verify(&sheet());
    assert!(good.passed());
    let mut lattice = sheet();
    // Give the last cell four corners of its own: no cell before it
    // reaches them.
    let last = lattice.cells.len() - 1;
    let cell = lattice.cells[last];
    for corner in cell.corner_ids() {
        let copy = lattice.vertices[corner as usize];
        lattice.vertices.push(copy);
    }
    let n = lattice.vertices.len() as u32;
    let c = &mut lattice.cells[last];
    (c.ul, c.ur, c.ll, c.lr) = (n - 4, n - 3, n - 2, n - 1);
    let report = verify(&lattice);
    let single = report.check(Invariant::CollapsedSingleValued);
    assert!(single.max.is_nan(), "{single:?}");
    assert!(
        single
            .site
            .as_deref()
            .is_some_and(|s| s.contains("not connected"))
    );
    // The last cell's corners have no z (NaN): its rods fail.
    assert!(report.check(Invariant::CollapsedRodLength).max.is_nan());
    assert!(!report.passed());
}
