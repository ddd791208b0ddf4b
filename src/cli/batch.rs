//! Batch builds: several recipes built in parallel, each into its own
//! subfolder of one output folder, which replaces the old one as a whole.
//! The files written do not depend on the number of jobs or their order.

use super::args::Verbosity;
use super::build::{Report, inputs, kept_line, open_out};
use super::error::{Error, ErrorJson, json_text, print_json};
use super::files::{OutDir, Staged, safe_component};
use super::progress::Progress;
use super::recipe::{Recipe, run_recipe, stem};
use karigami::{ErrorKind, Overrides, util::plural};
use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

/// What became of one recipe.
struct Outcome {
    file: String,
    folder: String,
    seconds: f64,
    result: Result<Report, Error>,
    /// Its files were kept from the earlier build (`files::Staged::keep`).
    kept: bool,
    /// Writing its files failed: the batch must not commit.
    write_failed: Option<String>,
}

/// One recipe in batch.json and in `build --json`'s report of a batch.
#[derive(Serialize)]
struct Record<'a> {
    file: &'a str,
    folder: &'a str,
    /// "ok" or "error".
    status: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    check: Option<&'a Value>,
    #[serde(skip_serializing_if = "Option::is_none")]
    build: Option<&'a Value>,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<&'a ErrorJson>,
    /// Only in `--json`'s report: batch.json is the same on every run.
    #[serde(skip_serializing_if = "Option::is_none")]
    seconds: Option<f64>,
    /// Only in `--json`'s report: "solved" or "reused" (`recipe::simulation`).
    #[serde(skip_serializing_if = "Option::is_none")]
    simulation: Option<&'static str>,
}

pub(super) fn build(
    paths: &[PathBuf],
    out: &Path,
    force: bool,
    jobs: usize,
    json: bool,
    overrides: &Overrides,
    v: Verbosity,
) -> Result<(), Error> {
    let folders = folders(paths)?;
    let out = &open_out(out, paths, force, v)?;
    let shown = out.path().display();
    let staged = Staged::new(out, "batch")
        .map_err(|e| Error::io(format!("cannot write {shown}: {e}; {}", out.kept())))?;
    let outcomes: Vec<Mutex<Option<Outcome>>> = paths.iter().map(|_| Mutex::new(None)).collect();
    let order = dearest_first(paths, overrides, jobs);
    let next = AtomicUsize::new(0);
    // A write that failed (a full disk) stops the batch: it cannot commit.
    let stop = AtomicBool::new(false);
    let bar = Mutex::new(Progress::new(paths.len(), v.quiet || json));
    let what = format!("building {}", plural(paths.len(), "recipe"));
    // On a terminal the bar shows progress; off one, finished recipes are
    // lines and a long one still gets a line now and then.
    let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
    super::progress::heartbeat(&what, v.quiet || json || tty, || {
        std::thread::scope(|s| {
            for _ in 0..jobs.min(paths.len()) {
                s.spawn(|| {
                    loop {
                        if stop.load(Ordering::SeqCst) {
                            break;
                        }
                        let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) else {
                            break;
                        };
                        let path = &paths[i];
                        let outcome = build_one(path, &folders[i], out, &staged, overrides, jobs);
                        if outcome.write_failed.is_some() {
                            stop.store(true, Ordering::SeqCst);
                        }
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
    });
    bar.into_inner().unwrap_or_else(|e| e.into_inner()).clear();
    let outcomes: Vec<Outcome> = outcomes
        .into_iter()
        .filter_map(|m| m.into_inner().unwrap_or_else(|e| e.into_inner()))
        .collect();
    if let Some(why) = outcomes.iter().find_map(|o| o.write_failed.as_ref()) {
        drop(staged);
        return Err(Error::io(format!(
            "cannot write {shown}/{why}; the batch was not committed and {}",
            out.kept()
        )));
    }
    // batch.json records every recipe's status; no times, so that it is
    // the same on every run.
    let record: Vec<Record> = outcomes.iter().map(|o| o.record(false)).collect();
    let written = staged
        .write(
            "",
            &[(
                "batch.json".to_string(),
                (json_text(&record) + "\n").into_bytes(),
            )],
        )
        .and_then(|()| staged.commit());
    if let Err(e) = written {
        return Err(Error::io(format!(
            "cannot write {shown}: {e}; {}",
            out.kept()
        )));
    }
    if json {
        let timed: Vec<Record> = outcomes.iter().map(|o| o.record(true)).collect();
        print_json(&timed);
    } else if !v.quiet {
        out!("{}", table(&outcomes));
        if let Some(line) = reused_line(&outcomes) {
            outln!("{line}");
        }
        let kept = outcomes.iter().filter(|o| o.kept).count();
        if kept > 0 {
            let what = format!(
                "the files of {kept} of {}",
                plural(outcomes.len(), "recipe")
            );
            outln!("{}", kept_line(&what));
        }
        let built = outcomes.iter().filter(|o| o.result.is_ok()).count();
        outln!("wrote {} to {shown}", plural(built, "build"));
    }
    let failed: Vec<&Outcome> = outcomes.iter().filter(|o| o.result.is_err()).collect();
    if failed.is_empty() {
        return Ok(());
    }
    let names: Vec<&str> = failed.iter().map(|o| o.file.as_str()).collect();
    let io = failed
        .iter()
        .any(|o| o.result.as_ref().is_err_and(|e| e.kind == ErrorKind::Io));
    // Each failure was shown as it happened, and the JSON report has them.
    let kind = if io {
        ErrorKind::Io
    } else {
        ErrorKind::BatchFailed
    };
    Err(Error::new(
        kind,
        format!(
            "{} of {} failed: {}",
            failed.len(),
            plural(outcomes.len(), "recipe"),
            names.join(", ")
        ),
    )
    .text_only())
}

/// Each recipe's subfolder: its file name without `.toml`, made a safe
/// single path component (see `safe_component`); recipes of the same name
/// from different folders get the folder's name in front (`examples-disk`,
/// `templates-disk`). Names that differ only in case are refused too, as
/// they would share a folder on macOS and Windows.
fn folders(paths: &[PathBuf]) -> Result<Vec<String>, Error> {
    let mut count: BTreeMap<String, usize> = BTreeMap::new();
    for p in paths {
        *count
            .entry(safe_component(&stem(p)).to_lowercase())
            .or_default() += 1;
    }
    let names: Vec<String> = paths
        .iter()
        .map(|p| {
            let name = safe_component(&stem(p));
            let parent = p
                .parent()
                .and_then(|d| d.canonicalize().ok())
                .and_then(|d| d.file_name().map(|n| n.to_string_lossy().into_owned()));
            let name = match parent {
                Some(dir) if count[&name.to_lowercase()] > 1 => {
                    safe_component(&format!("{dir}-{name}"))
                }
                _ => name,
            };
            // The batch's own file keeps its name.
            if name.eq_ignore_ascii_case("batch.json") {
                format!("{name}_")
            } else {
                name
            }
        })
        .collect();
    let mut seen: BTreeMap<String, &Path> = BTreeMap::new();
    for (name, p) in names.iter().zip(paths) {
        if let Some(first) = seen.insert(name.to_lowercase(), p) {
            return Err(Error::new(
                ErrorKind::SameSubfolder,
                format!(
                    "{} and {} would both build into the subfolder {name}/; give one another file name",
                    first.display(),
                    p.display()
                ),
            ));
        }
    }
    Ok(names)
}

/// The recipes' indices in the order to start them: with several jobs the
/// dearest first, so that the jobs end together instead of one finishing
/// a long simulation alone (the examples' saddle ring and torus are last by
/// name). The cost is `karigami::build_cost`, read off the parsed recipe
/// without growing it (growth waits for the build, and a kept recipe never
/// grows); a recipe that does not parse costs nothing. Ties keep the name
/// order.
fn dearest_first(paths: &[PathBuf], overrides: &Overrides, jobs: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..paths.len()).collect();
    if jobs < 2 || paths.len() < 2 {
        return order;
    }
    let costs: Vec<usize> = paths
        .iter()
        .map(|path| {
            Recipe::read(path)
                .and_then(|r| r.parse(overrides))
                .map_or(0, |d| karigami::build_cost(&d))
        })
        .collect();
    order.sort_by_key(|&i| std::cmp::Reverse(costs[i]));
    order
}

/// Build one recipe of the batch into its subfolder, or keep the earlier
/// build's files there where nothing they are made from changed; with
/// `jobs > 1` its sheet pictures are drawn on a second thread
/// (`karigami::files_on`).
fn build_one(
    path: &Path,
    folder: &str,
    out: &OutDir,
    staged: &Staged,
    overrides: &Overrides,
    jobs: usize,
) -> Outcome {
    let started = Instant::now();
    let write_failed = std::cell::RefCell::new(None);
    let failed = |e: std::io::Error| {
        *write_failed.borrow_mut() = Some(format!("{folder}/: {e}"));
        Error::io(format!("cannot write {folder}/: {e}"))
    };
    let mut kept = false;
    let result = Recipe::read(path).and_then(|recipe| {
        let key = inputs(&recipe, overrides, folder);
        if let Some(report) = staged.keep(out, folder, key).map_err(failed)? {
            kept = true;
            return Ok(report);
        }
        let built = run_recipe(&recipe, overrides, &mut |_| {}, (out, folder))?;
        let report = Report::of(&built);
        staged
            .write_build(folder, &karigami::files_on(&built, jobs > 1), key, &report)
            .map_err(failed)?;
        Ok(report)
    });
    Outcome {
        file: path.display().to_string(),
        folder: folder.to_string(),
        seconds: started.elapsed().as_secs_f64(),
        result,
        kept,
        write_failed: write_failed.into_inner(),
    }
}

impl Outcome {
    fn record(&self, timed: bool) -> Record<'_> {
        let (status, summary, error) = match &self.result {
            Ok(s) => ("ok", Some(s), None),
            Err(e) => ("error", None, e.json.as_deref()),
        };
        Record {
            file: &self.file,
            folder: &self.folder,
            status,
            check: summary.map(|s| &s.check),
            build: summary.map(|s| &s.build),
            error,
            seconds: timed.then_some(self.seconds),
            simulation: summary
                .and_then(|s| s.simulation(self.kept))
                .filter(|_| timed),
        }
    }
}

/// How many of the simulated recipes reused the earlier batch's
/// simulation, in one line; None when none simulated.
fn reused_line(outcomes: &[Outcome]) -> Option<String> {
    let how: Vec<&str> = outcomes
        .iter()
        .filter_map(|o| o.result.as_ref().ok()?.simulation(o.kept))
        .collect();
    let reused = how.iter().filter(|h| **h == "reused").count();
    (!how.is_empty()).then(|| {
        format!(
            "simulations: {reused} of {} reused from the earlier build (nothing they depend on changed), {} solved",
            how.len(),
            how.len() - reused
        )
    })
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
                let class = e.kind.name();
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
