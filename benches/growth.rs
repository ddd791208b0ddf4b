//! Growth + verification benchmark: `cargo bench --bench growth [-- N...]`.
//! Grows an N x N-cell sheet (default 250, 500 and 1000), verifies it, and
//! prints cells per second and the peak resident memory of the process.
//! Times are the thread's CPU time (/proc/thread-self/schedstat), robust
//! when other work shares the cores; the wall time is printed beside them.

use glam::DVec3;
use karigami::geometry::{Direction, Leg};
use karigami::lattice::{RowParams, grow_sheet, verify};
use std::time::Instant;

/// A sheet of alternating 10 and 12 mm seed edges with kappa = 0, rows at
/// 45 deg with matched ends: cells of two sizes, admissible for 1000+ rows
/// (wide rows with non-zero kappa drift out of the cone: MATH.md 4.6).
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

/// Peak resident set size of this process in bytes (Linux VmHWM).
fn peak_rss() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// CPU time this thread has run, in seconds (Linux schedstat, ns).
fn cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .map_or(f64::NAN, |ns| ns as f64 * 1e-9)
}

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let sizes = if sizes.is_empty() {
        vec![250, 500, 1000]
    } else {
        sizes
    };
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
}
