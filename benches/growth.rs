//! Growth + verification benchmark: `cargo bench --bench growth [-- CASE...]`.
//! A case `N` grows an N x N-cell sheet (default 250, 500 and 1000),
//! verifies it, and prints cells per second and the peak resident memory of
//! the process. A case `check:CxR` (default check:1000x1000 and
//! check:2000x2000) runs what `karigami -q check` computes for a flat sheet
//! of C x R cells (parse, grow, verify, deployment, shape and clash
//! measures, the JSON report) in a child process of its own, so that its
//! peak memory is its own. Times are CPU time (/proc schedstat), robust
//! when other work shares the cores; the wall time is printed beside them.

use glam::DVec3;
use karigami::{Direction, Leg, Overrides, RowParams, deploy::deployment, grow_sheet, verify};
mod common;

use common::{cpu_seconds, peak_rss, sheet_recipe, size};
use std::process::Command;
use std::time::Instant;

/// A sheet of alternating 10 and 12 mm seed edges with kappa = 0, rows at
/// 45 deg with matched ends: cells of two sizes, admissible for 1000+ rows
/// (wide rows with non-zero kappa drift out of the cone: docs/math.md 4.6).
fn design(n: usize) -> (Vec<DVec3>, Vec<f64>, Vec<RowParams>) {
    let points: Vec<DVec3> = (0..=n)
        .map(|j| {
            DVec3::new(
                11.0 * j as f64 - if j % 2 == 1 { 1.0 } else { 0.0 },
                0.0,
                0.0,
            )
        })
        .collect();
    let kappa = vec![0.0; n];
    let row = RowParams {
        start: n / 2,
        direction: Some(Direction::Angles {
            angle_deg: 45.0,
            tilt_deg: 0.0,
        }),
        left_leg: Leg::Match,
        right_leg: Leg::Match,
        ..RowParams::default()
    };
    (points, kappa, vec![row; n])
}

/// The child of a `check:CxR` case: what `karigami -q check` computes, then
/// one line: cells, grow + verify CPU s, total CPU s, wall s, peak bytes.
fn check_child(cols: usize, rows: usize) {
    let (t0, c0) = (Instant::now(), cpu_seconds());
    let text = sheet_recipe(cols, rows);
    let d = karigami::parse_with(&text, "check", &Overrides::default()).expect("parses");
    let lattice = d.grow().expect("grows");
    let report = verify(&lattice);
    let grow_verify = cpu_seconds() - c0;
    let deploy = deployment(&lattice);
    let assembled = lattice.placed();
    let measures = karigami::measure_assembled(&d, &lattice, &assembled);
    let json = karigami::check_json(&karigami::Verified {
        design: &d,
        lattice: &lattice,
        assembled: &assembled,
        report: &report,
        deployment: &deploy,
        measures: &measures,
        parts: None,
    });
    let (wall, cpu) = (t0.elapsed().as_secs_f64(), cpu_seconds() - c0);
    assert!(report.passed(), "benchmark lattice must verify");
    std::hint::black_box(&json);
    println!(
        "{} {grow_verify} {cpu} {wall} {}",
        lattice.cells.len(),
        peak_rss().unwrap_or(0)
    );
}

/// Run the `check:CxR` cases, each in a child process.
fn check_cases(cases: &[(usize, usize)]) {
    println!(
        "\n{:>12} {:>10} {:>10} {:>10} {:>10} {:>12} {:>10} {:>9}",
        "check", "cells", "g+v CPU s", "CPU s", "wall s", "cells/s CPU", "peak MiB", "B/cell"
    );
    let me = std::env::current_exe().expect("own path");
    for &(c, r) in cases {
        let out = Command::new(&me)
            .args(["--check-child", &format!("{c}x{r}")])
            .output()
            .expect("child runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let line = String::from_utf8_lossy(&out.stdout);
        let f: Vec<f64> = line
            .split_whitespace()
            .map(|x| x.parse().expect("a number"))
            .collect();
        let [cells, gv, cpu, wall, peak] = f[..] else {
            panic!("child printed {line:?}")
        };
        println!(
            "{:>12} {:>10} {:>10.3} {:>10.3} {:>10.3} {:>12.0} {:>10.1} {:>9.0}",
            format!("{c}x{r}"),
            cells,
            gv,
            cpu,
            wall,
            cells / cpu,
            peak / 1048576.0,
            peak / cells
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [flag, what] = &args[..]
        && flag == "--check-child"
    {
        let (c, r) = size(what).expect("CxR");
        return check_child(c, r);
    }
    let mut sizes: Vec<usize> = args.iter().filter_map(|a| a.parse().ok()).collect();
    let mut checks: Vec<(usize, usize)> = args
        .iter()
        .filter_map(|a| size(a.strip_prefix("check:")?))
        .collect();
    if sizes.is_empty() && checks.is_empty() {
        sizes = vec![250, 500, 1000];
        checks = vec![(1000, 1000), (2000, 2000)];
    }
    println!(
        "{:>6} {:>10} {:>10} {:>10} {:>10} {:>14} {:>16} {:>10} {:>9} {:>10}",
        "N",
        "cells",
        "grow s",
        "verify s",
        "wall s",
        "grown cells/s",
        "grown+verified/s",
        "peak MiB",
        "B/cell",
        "worst"
    );
    for n in sizes {
        let (points, kappa, rows) = design(n);
        let (t0, c0) = (Instant::now(), cpu_seconds());
        let lattice = grow_sheet(2, &points, &kappa, &rows).expect("benchmark sheet grows");
        let c1 = cpu_seconds();
        let report = verify(&lattice);
        let (wall, c2) = (t0.elapsed().as_secs_f64(), cpu_seconds());
        let (grow_s, verify_s) = (c1 - c0, c2 - c1);
        let cells = lattice.cells.len() as f64;
        let peak = peak_rss().map_or(f64::NAN, |b| b as f64);
        println!(
            "{:>6} {:>10} {:>10.3} {:>10.3} {:>10.3} {:>14.0} {:>16.0} {:>10.1} {:>9.0} {:>10.1e}",
            n,
            lattice.cells.len(),
            grow_s,
            verify_s,
            wall,
            cells / grow_s,
            cells / (grow_s + verify_s),
            peak / 1048576.0,
            peak / cells,
            report.worst()
        );
        assert!(report.passed(), "benchmark lattice must verify");
        drop(lattice);
    }
    check_cases(&checks);
}
