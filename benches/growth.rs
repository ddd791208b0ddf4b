//! Growth + verification benchmark: `cargo bench --bench growth [-- N...]`.
//! Grows an N x N-cell sheet (default 250, 500 and 1000), verifies it, and
//! prints cells per second and the peak resident memory of the process.

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
        "{:>6} {:>10} {:>10} {:>10} {:>14} {:>14} {:>12} {:>10}",
        "N",
        "cells",
        "grow s",
        "verify s",
        "grown cells/s",
        "grown+verified/s",
        "peak MiB",
        "worst"
    );
    for n in sizes {
        let (points, kappa, rows) = design(n);
        let t0 = Instant::now();
        let lattice = grow_sheet(2, &points, &kappa, &rows).expect("benchmark sheet grows");
        let grow_s = t0.elapsed().as_secs_f64();
        let t1 = Instant::now();
        let report = verify(&lattice);
        let verify_s = t1.elapsed().as_secs_f64();
        let cells = lattice.cells.len() as f64;
        let peak = peak_rss().map_or("n/a".to_string(), |b| {
            format!("{:.1}", b as f64 / 1048576.0)
        });
        println!(
            "{:>6} {:>10} {:>10.3} {:>10.3} {:>14.0} {:>14.0} {:>12} {:>10.1e}",
            n,
            lattice.cells.len(),
            grow_s,
            verify_s,
            cells / grow_s,
            cells / (grow_s + verify_s),
            peak,
            report.worst()
        );
        assert!(report.passed(), "benchmark lattice must verify");
        drop(lattice);
    }
}
