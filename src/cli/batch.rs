//! Batch builds: several recipes built in parallel, each into its own
//! subfolder of one output folder, which replaces the old one as a whole.
//! The files written do not depend on the number of jobs or their order.

use super::files::Staged;
use super::progress::Progress;
use super::{
    EXIT_INVALID, EXIT_IO, EXIT_USAGE, Failed, Recipe, RecipeError, Verbosity, run_recipe, stem,
};
use karigami::design::Overrides;
use karigami::report;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// What became of one recipe.
struct Outcome {
    file: String,
    folder: String,
    seconds: f64,
    result: Result<Summary, RecipeError>,
}

struct Summary {
    cells: usize,
    strips: usize,
    sheets: usize,
    json: Value,
}

pub fn build(
    paths: &[PathBuf],
    out: &Path,
    force: bool,
    jobs: usize,
    json: bool,
    overrides: &Overrides,
    v: Verbosity,
) -> Result<(), Failed> {
    let folders = folders(paths)?;
    let staged = Staged::new(out, force).map_err(|e| {
        eprintln!("error: cannot write {}: {e}", out.display());
        Failed(EXIT_IO)
    })?;
    let outcomes: Vec<Mutex<Option<Outcome>>> = paths.iter().map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    let bar = Mutex::new(Progress::new(paths.len(), v.quiet || json));
    std::thread::scope(|s| {
        for _ in 0..jobs.min(paths.len()) {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(path) = paths.get(i) else { break };
                    let outcome = build_one(path, &folders[i], &staged, overrides);
                    let mut bar = bar.lock().unwrap_or_else(|e| e.into_inner());
                    match &outcome.result {
                        Ok(_) => bar.finished(&outcome.folder, "ok", outcome.seconds),
                        Err(e) => {
                            bar.print(&e.text);
                            bar.finished(&outcome.folder, "FAILED", outcome.seconds);
                        }
                    }
                    *outcomes[i].lock().unwrap_or_else(|e| e.into_inner()) = Some(outcome);
                }
            });
        }
    });
    bar.into_inner().unwrap_or_else(|e| e.into_inner()).clear();
    let outcomes: Vec<Outcome> = outcomes
        .into_iter()
        .map(|m| {
            m.into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .expect("every recipe was built")
        })
        .collect();
    // batch.json marks the folder as a karigami batch and records every
    // recipe's status; no times, so that it is the same on every run.
    let record: Vec<Value> = outcomes.iter().map(|o| o.record(false)).collect();
    let written = staged
        .write(
            "",
            &[(
                "batch.json".to_string(),
                (serde_json::to_string_pretty(&record).expect("JSON") + "\n").into_bytes(),
            )],
        )
        .and_then(|()| staged.commit());
    if let Err(e) = written {
        eprintln!("error: cannot write {}: {e}", out.display());
        return Err(Failed(EXIT_IO));
    }
    if json {
        let timed: Vec<Value> = outcomes.iter().map(|o| o.record(true)).collect();
        println!("{}", serde_json::to_string_pretty(&timed).expect("JSON"));
    } else if !v.quiet {
        print!("{}", table(&outcomes));
        println!(
            "wrote {} to {}",
            plural(outcomes.len(), "build"),
            out.display()
        );
    }
    let failed: Vec<&Outcome> = outcomes.iter().filter(|o| o.result.is_err()).collect();
    if failed.is_empty() {
        return Ok(());
    }
    let names: Vec<&str> = failed.iter().map(|o| o.file.as_str()).collect();
    eprintln!(
        "error: {} of {} failed: {}",
        failed.len(),
        plural(outcomes.len(), "recipe"),
        names.join(", ")
    );
    let io = failed
        .iter()
        .any(|o| o.result.as_ref().is_err_and(|e| e.code == EXIT_IO));
    Err(Failed(if io { EXIT_IO } else { EXIT_INVALID }))
}

/// Each recipe's subfolder: its file name without `.toml`; recipes of the
/// same name from different folders get the folder's name in front
/// (`examples-disk`, `templates-disk`).
fn folders(paths: &[PathBuf]) -> Result<Vec<String>, Failed> {
    let mut count: BTreeMap<String, usize> = BTreeMap::new();
    for p in paths {
        *count.entry(stem(p)).or_default() += 1;
    }
    let names: Vec<String> = paths
        .iter()
        .map(|p| {
            let name = stem(p);
            let parent = p.parent().and_then(Path::file_name);
            match parent {
                Some(dir) if count[&name] > 1 => format!("{}-{name}", dir.to_string_lossy()),
                _ => name,
            }
        })
        .collect();
    let mut seen: BTreeMap<&str, &Path> = BTreeMap::new();
    for (name, p) in names.iter().zip(paths) {
        if let Some(first) = seen.insert(name, p) {
            eprintln!(
                "error: {} and {} would both build into the subfolder {name}/; give one another file name",
                first.display(),
                p.display()
            );
            return Err(Failed(EXIT_USAGE));
        }
    }
    Ok(names)
}

fn build_one(path: &Path, folder: &str, staged: &Staged, overrides: &Overrides) -> Outcome {
    let started = Instant::now();
    let result = Recipe::read(path)
        .and_then(|recipe| run_recipe(&recipe, overrides, &mut |_| {}))
        .and_then(|built| {
            staged
                .write(folder, &built.files())
                .map_err(|e| RecipeError {
                    code: EXIT_IO,
                    text: format!("error: cannot write {folder}/: {e}\n"),
                    json: json!({ "class": "io", "message": format!("cannot write {folder}/: {e}") }),
                })?;
            Ok(Summary {
                cells: built.lattice.cells.len(),
                strips: built.parts.strips.len(),
                sheets: built.layout.sheets.len(),
                json: json!({
                    "check": report::check_json(
                        &built.design,
                        &built.lattice,
                        &built.report,
                        &built.deployment,
                    ),
                    "build": report::build_json(&built),
                }),
            })
        });
    Outcome {
        file: path.display().to_string(),
        folder: folder.to_string(),
        seconds: started.elapsed().as_secs_f64(),
        result,
    }
}

impl Outcome {
    fn record(&self, timed: bool) -> Value {
        let mut v = match &self.result {
            Ok(s) => {
                let mut v = json!({ "file": self.file, "folder": self.folder, "status": "ok" });
                v["check"] = s.json["check"].clone();
                v["build"] = s.json["build"].clone();
                v
            }
            Err(e) => {
                json!({ "file": self.file, "folder": self.folder, "status": "error", "error": e.json })
            }
        };
        if timed {
            v["seconds"] = json!(self.seconds);
        }
        v
    }
}

fn table(outcomes: &[Outcome]) -> String {
    let width = outcomes
        .iter()
        .map(|o| o.file.chars().count())
        .max()
        .unwrap_or(0)
        .max(6);
    let mut out = format!(
        "{:<width$}  {:<28} {:>7} {:>7} {:>6} {:>8}\n",
        "recipe", "status", "cells", "strips", "sheets", "time"
    );
    for o in outcomes {
        let time = format!("{:.2} s", o.seconds);
        match &o.result {
            Ok(s) => out.push_str(&format!(
                "{:<width$}  {:<28} {:>7} {:>7} {:>6} {:>8}\n",
                o.file, "ok", s.cells, s.strips, s.sheets, time
            )),
            Err(e) => {
                let class = e.json["class"].as_str().unwrap_or("error");
                out.push_str(&format!(
                    "{:<width$}  {:<28} {:>7} {:>7} {:>6} {:>8}\n",
                    o.file,
                    format!("FAILED ({class})"),
                    "-",
                    "-",
                    "-",
                    time
                ));
            }
        }
    }
    out
}

fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}
