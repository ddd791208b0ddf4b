//! Whole-pipeline benchmark: `cargo bench --bench pipeline [-- N...]`.
//!
//! For every recipe in examples/ and for flat N x N-cell sheets (default N =
//! 10, 30 and 100, on a 3000 x 2000 mm sheet so that long strips fit):
//! growth + verification time, whole-pipeline wall time (grow, verify,
//! parts, nesting, every output file rendered in memory), peak memory and
//! output bytes. Each case runs in a child process of its own so that its
//! peak resident memory is its own.

use karigami::build::build;
use karigami::design::{self, Overrides};
use karigami::lattice::verify;
use std::process::Command;
use std::time::Instant;

/// Peak resident set size of this process in bytes (Linux VmHWM).
fn peak_rss() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// A flat sheet recipe of n x n square cells (20 mm seed edges).
fn sheet_recipe(n: usize) -> String {
    format!(
        "name = \"sheet-{n}x{n}\"\n[lattice]\nseed = \"sheet\"\nkappa = 0.0\n[lattice.line]\nfrom = [0.0, 0.0]\nto = [{}.0, 0.0]\ncells = {n}\n[lattice.grow]\nrows = {n}\nstart = {}\nangle = 45.0\n[sheet]\nwidth = 3000.0\nheight = 2000.0\n",
        20 * n,
        n / 2
    )
}

/// The child: build one recipe and print its figures on one line.
fn one(name: &str, text: &str) {
    let t0 = Instant::now();
    let d = design::parse_with(text, name, &Overrides::default()).expect("benchmark recipe parses");
    let lattice = d.grow().expect("grows");
    let report = verify(&lattice);
    let grow_verify = t0.elapsed().as_secs_f64();
    assert!(report.passed());
    let built = build(d).expect("builds");
    let files = built.files();
    let total = t0.elapsed().as_secs_f64();
    let bytes: usize = files.iter().map(|(_, b)| b.len()).sum();
    println!(
        "{} {} {} {grow_verify} {total} {bytes} {} {}",
        lattice.cells.len(),
        built.parts.strips.len(),
        built.layout.sheets.len(),
        files.len(),
        peak_rss().unwrap_or(0)
    );
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [flag, what] = &args[..] {
        if flag == "--one-file" {
            let text = std::fs::read_to_string(what).expect("recipe");
            let stem = std::path::Path::new(what)
                .file_stem()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            return one(&stem, &text);
        }
        if flag == "--one-sheet" {
            return one("sheet", &sheet_recipe(what.parse().expect("N")));
        }
    }
    let sizes: Vec<usize> = args.iter().filter_map(|a| a.parse().ok()).collect();
    let sizes = if sizes.is_empty() {
        vec![10, 30, 100]
    } else {
        sizes
    };
    let mut cases: Vec<(String, Vec<String>)> = Vec::new();
    let mut files: Vec<_> = std::fs::read_dir("examples")
        .expect("run from the repository root")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    for f in files {
        let name = f.file_stem().unwrap().to_string_lossy().into_owned();
        cases.push((name, vec!["--one-file".into(), f.display().to_string()]));
    }
    for n in sizes {
        cases.push((
            format!("sheet {n}x{n}"),
            vec!["--one-sheet".into(), n.to_string()],
        ));
    }
    println!(
        "{:<16} {:>7} {:>7} {:>6} {:>12} {:>14} {:>10} {:>9} {:>11}",
        "case",
        "cells",
        "strips",
        "sheets",
        "grow+verify s",
        "cells/s",
        "total s",
        "peak MiB",
        "output KiB"
    );
    let exe = std::env::current_exe().expect("own path");
    for (name, args) in cases {
        let out = Command::new(&exe)
            .args(&args)
            .output()
            .expect("runs the child");
        if !out.status.success() {
            println!(
                "{name:<16} failed: {}",
                String::from_utf8_lossy(&out.stderr)
                    .lines()
                    .last()
                    .unwrap_or("")
            );
            continue;
        }
        let line = String::from_utf8_lossy(&out.stdout);
        let f: Vec<f64> = line
            .split_whitespace()
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect();
        println!(
            "{:<16} {:>7} {:>7} {:>6} {:>12.3} {:>14.0} {:>10.3} {:>9.1} {:>11.0}",
            name,
            f[0],
            f[1],
            f[2],
            f[3],
            f[0] / f[3],
            f[4],
            f[7] / 1048576.0,
            f[5] / 1024.0
        );
    }
}
