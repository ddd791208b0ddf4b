//! Nesting benchmark: `cargo bench --bench nesting [-- --seconds S]`.
//!
//! For every example and a stress set of 2000 strips: sheets used against
//! the lower bounds, utilisation and wall time. Then, on the same strip sets
//! in the same run, strip packing (fixed height, minimise length) against
//! the sparrow reference (`scripts/spyrrow_compare.py`, needs
//! `pip install spyrrow`) given S seconds (default 30).

use karigami::{Fabrication, Outline, build, nest, testing::strip_length};
use std::path::Path;
use std::process::Command;
use std::time::Instant;

struct Set {
    name: String,
    lengths: Vec<f64>,
    width: f64,
    fab: Fabrication,
}

fn example_sets() -> Vec<Set> {
    let mut files: Vec<_> = std::fs::read_dir("examples")
        .expect("run from the repository root")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|path| {
            let text = std::fs::read_to_string(path).unwrap();
            let b = build(karigami::parse(&text, "example").unwrap()).unwrap();
            let fab = b.design.fabrication.clone();
            Set {
                name: path.file_stem().unwrap().to_string_lossy().into_owned(),
                lengths: b.layout.lengths.clone(),
                width: b.layout.part_width,
                fab,
            }
        })
        .collect()
}

/// 2000 strips from 40 to 250 mm, deterministic (the library's seeded
/// generator, so no second generator to keep).
fn stress_set() -> Set {
    let mut rng = karigami_rods::rng::Rng::new(0x2545_F491_4F6C_DD1D);
    let lengths = (0..2000).map(|_| 40.0 + 210.0 * rng.uniform()).collect();
    let fab = Fabrication::default();
    Set {
        name: "stress-2000".into(),
        lengths,
        width: Outline::of(0.0, &fab).width,
        fab,
    }
}

fn sparrow(set: &Set, height: f64, seconds: u32) -> Option<serde_json::Value> {
    let script = Path::new("scripts/spyrrow_compare.py");
    if !script.exists() {
        return None;
    }
    let instance = serde_json::json!({
        "strip_height": height,
        "width": set.width,
        "gap": set.fab.sheet.gap,
        "lengths": set.lengths,
    });
    let file = std::env::temp_dir().join(format!("karigami-nest-{}.json", set.name));
    std::fs::write(&file, instance.to_string()).ok()?;
    let out = Command::new("python3")
        .args([
            script.to_str()?,
            file.to_str()?,
            "--seconds",
            &seconds.to_string(),
        ])
        .output()
        .ok()?;
    if !out.status.success() {
        eprintln!(
            "sparrow failed on {}: {}",
            set.name,
            String::from_utf8_lossy(&out.stderr)
        );
        return None;
    }
    serde_json::from_slice(&out.stdout).ok()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let seconds: u32 = args
        .iter()
        .position(|a| a == "--seconds")
        .and_then(|i| args.get(i + 1))
        .and_then(|s| s.parse().ok())
        .unwrap_or(30);
    let mut sets = example_sets();
    sets.push(stress_set());

    println!("sheets (lane nesting)");
    println!(
        "{:<14} {:>6} {:>7} {:>11} {:>11} {:>12} {:>10}",
        "set", "strips", "sheets", "area bound", "lane bound", "utilisation", "wall ms"
    );
    for set in &sets {
        let t = Instant::now();
        let layout = nest(&set.lengths, set.width, &set.fab.sheet);
        let ms = t.elapsed().as_secs_f64() * 1000.0;
        let b = layout.bounds();
        println!(
            "{:<14} {:>6} {:>7} {:>11} {:>11} {:>11.1}% {:>10.2}",
            set.name,
            set.lengths.len(),
            layout.sheets.len(),
            b.area,
            b.lanes,
            100.0 * layout.utilisation(),
            ms
        );
    }

    println!("\nstrip packing at the sheet's usable height, against sparrow ({seconds} s)");
    println!(
        "{:<14} {:>8} {:>12} {:>10} {:>12} {:>12} {:>8} {:>10}",
        "set", "height", "ours mm", "ours ms", "sparrow mm", "area bound", "ratio", "sparrow s"
    );
    for set in &sets {
        let height = set.fab.sheet.usable().1;
        let t = Instant::now();
        let ours = strip_length(&set.lengths, set.width, set.fab.sheet.gap, height);
        let ms = t.elapsed().as_secs_f64() * 1000.0;
        match sparrow(set, height, seconds) {
            Some(s) => {
                let theirs = s["strip_length"].as_f64().unwrap_or(f64::NAN);
                println!(
                    "{:<14} {:>8.1} {:>12.1} {:>10.2} {:>12.1} {:>12.1} {:>8.4} {:>10.1}",
                    set.name,
                    height,
                    ours,
                    ms,
                    theirs,
                    s["area_bound"].as_f64().unwrap_or(f64::NAN),
                    ours / theirs,
                    s["wall_s"].as_f64().unwrap_or(f64::NAN)
                );
            }
            None => println!(
                "{:<14} {:>8.1} {:>12.1} {:>10.2}   sparrow not available (pip install spyrrow)",
                set.name, height, ours, ms
            ),
        }
    }
}
