//! Whole-pipeline benchmark: `cargo bench --bench pipeline [-- CASE...]`.
//!
//! Cases: every recipe in examples/, flat sheets of C x R cells (default
//! 10x10, 30x30, 100x100 and 200x100, the largest `build` accepts, on a
//! 3000 x 2000 mm sheet so that long strips fit) built end to end, and
//! `check` of a 1000 x 1000 sheet (grow, verify, deployment, measures
//! and the text report: what `karigami check` computes). A case given on the command line is `CxR`
//! (a build) or `check:CxR`.
//!
//! Each case runs in a child process of its own, so that its peak resident
//! memory is its own; it prints wall time, CPU time (the process's, from
//! /proc: robust when other work shares the cores), peak memory, bytes
//! written, cells per second, and bytes and memory per cell.

use karigami::{Overrides, build, verify};
mod common;

use common::cpu_seconds as thread_cpu_seconds;
use common::{peak_rss, sheet_recipe, size};
use std::process::Command;
use std::time::Instant;

/// CPU seconds (user + system) of the whole process, every thread
/// included, ended ones too (`/proc/self/stat`, in clock ticks of 10 ms):
/// `check` and `files` work on two threads, and `common::cpu_seconds`
/// reads the calling thread's alone.
fn cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/self/stat")
        .ok()
        .and_then(|s| {
            // Fields after the command's closing parenthesis; utime and
            // stime are the 14th and 15th of the line.
            let rest = &s[s.rfind(')')? + 2..];
            let f: Vec<&str> = rest.split_whitespace().collect();
            Some(f.get(11)?.parse::<u64>().ok()? + f.get(12)?.parse::<u64>().ok()?)
        })
        .map_or(f64::NAN, |ticks| ticks as f64 / 100.0)
}

/// The child: build one recipe and print its figures on one line:
/// cells strips sheets files bytes grow+verify-s wall-s cpu-s peak-bytes.
fn one(name: &str, text: &str) {
    let (t0, c0) = (Instant::now(), cpu_seconds());
    let d =
        karigami::parse_with(text, name, &Overrides::default()).expect("benchmark recipe parses");
    let lattice = d.grow().expect("grows");
    let report = verify(&lattice);
    let grow_verify = t0.elapsed().as_secs_f64();
    assert!(report.passed());
    let cells = lattice.cells.len();
    drop(lattice);
    let built = build(d).expect("builds");
    let files = karigami::files(&built);
    let (wall, cpu) = (t0.elapsed().as_secs_f64(), cpu_seconds() - c0);
    let bytes: usize = files.iter().map(|(_, b)| b.len()).sum();
    println!(
        "{cells} {} {} {} {bytes} {grow_verify} {wall} {cpu} {}",
        built.parts.strips.len(),
        built.layout.sheets.len(),
        files.len(),
        peak_rss().unwrap_or(0)
    );
}

/// The child for `check`: what `karigami check` computes for its text
/// report (grow, then verify and the deployment beside the measures on a
/// second core where there is one, then the report), no files; "output"
/// is the report's bytes. Growth and verification are then timed alone
/// for the g+v column, in CPU seconds of this thread (the one they run
/// on), after the peak: the lattice is dropped first.
fn check(text: &str) {
    let (t0, c0) = (Instant::now(), cpu_seconds());
    let d = karigami::parse_with(text, "check", &Overrides::default()).expect("parses");
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs = karigami::Jobs::new(cores);
    let checked = karigami::check_on(d.clone(), &mut |_| {}, true, jobs).expect("grows");
    let report = karigami::check_text(&checked.verified());
    let (wall, cpu) = (t0.elapsed().as_secs_f64(), cpu_seconds() - c0);
    assert!(checked.report.passed());
    let cells = checked.lattice.cells.len();
    drop(checked);
    let c1 = thread_cpu_seconds();
    let lattice = d.grow().expect("grows");
    std::hint::black_box(verify(&lattice));
    let grow_verify = thread_cpu_seconds() - c1;
    println!(
        "{cells} 0 0 1 {} {grow_verify} {wall} {cpu} {}",
        report.len(),
        peak_rss().unwrap_or(0)
    );
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [flag, what] = &args[..] {
        match flag.as_str() {
            "--one-file" => {
                let text = std::fs::read_to_string(what).expect("recipe");
                let stem = std::path::Path::new(what)
                    .file_stem()
                    .unwrap()
                    .to_string_lossy()
                    .into_owned();
                return one(&stem, &text);
            }
            "--one-sheet" => {
                let (c, r) = size(what).expect("CxR");
                return one("sheet", &sheet_recipe(c, r));
            }
            "--one-check" => {
                let (c, r) = size(what).expect("CxR");
                return check(&sheet_recipe(c, r));
            }
            _ => {}
        }
    }
    let asked: Vec<&String> = args.iter().filter(|a| !a.starts_with('-')).collect();
    let mut cases: Vec<(String, Vec<String>)> = Vec::new();
    if asked.is_empty() {
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
    }
    let defaults = ["10x10", "30x30", "100x100", "200x100", "check:1000x1000"];
    let wanted: Vec<String> = if asked.is_empty() {
        defaults.iter().map(|s| s.to_string()).collect()
    } else {
        asked.iter().map(|s| s.to_string()).collect()
    };
    for w in wanted {
        match w.strip_prefix("check:") {
            Some(s) if size(s).is_some() => {
                cases.push((format!("check {s}"), vec!["--one-check".into(), s.into()]));
            }
            None if size(&w).is_some() => {
                cases.push((format!("sheet {w}"), vec!["--one-sheet".into(), w.clone()]));
            }
            _ => panic!("a case is CxR or check:CxR, not {w:?}"),
        }
    }
    println!(
        "{:<16} {:>9} {:>7} {:>6} {:>5} {:>9} {:>9} {:>9} {:>9} {:>10} {:>11} {:>10} {:>9}",
        "case",
        "cells",
        "strips",
        "sheets",
        "files",
        "g+v s",
        "wall s",
        "cpu s",
        "peak MiB",
        "output KiB",
        "cells/s cpu",
        "B out/cell",
        "KiB/cell"
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
        let [cells, strips, sheets, files, bytes, gv, wall, cpu, peak] = f[..] else {
            println!("{name:<16} unreadable: {line}");
            continue;
        };
        println!(
            "{:<16} {:>9} {:>7} {:>6} {:>5} {:>9.3} {:>9.3} {:>9.3} {:>9.1} {:>10.0} {:>11.0} {:>10.0} {:>9.2}",
            name,
            cells,
            strips,
            sheets,
            files,
            gv,
            wall,
            cpu,
            peak / 1048576.0,
            bytes / 1024.0,
            cells / cpu,
            bytes / cells,
            peak / 1024.0 / cells
        );
    }
}
