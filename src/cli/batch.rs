//! Batch builds: several recipes built in parallel, each into its own
//! subfolder of one output folder, which replaces the old one as a whole.
//! The files written do not depend on the number of jobs or their order.

use super::args::Verbosity;
use super::build::{Report, add_fit, inputs_with, kept_line, open_out, recorded_of, target_key};
use super::check::Recorded;
use super::error::{Error, ErrorJson, json_text, print_json};
use super::files::{OutDir, Staged, safe_component};
use super::progress::Progress;
use super::recipe::{Recipe, simulate, stem, unsimulated};
use super::stages::{Stages, StopOnPanic, Task};
use karigami::{Build, ErrorKind, Jobs, Overrides, Unsimulated, util::plural};
use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

/// What became of one recipe.
struct Outcome {
    file: String,
    folder: String,
    /// Seconds spent on it, over its stages.
    seconds: f64,
    ended: Ended,
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
    let batch = Batch {
        paths,
        folders: &folders,
        out,
        staged: &staged,
        overrides,
        jobs,
        outcomes: paths.iter().map(|_| Mutex::new(None)).collect(),
        stages: Stages::new(dearest_first(paths, overrides, jobs)),
        bar: Mutex::new(Progress::new(paths.len(), v.quiet || json)),
        quiet: v.quiet || json,
    };
    let outcomes = batch.run(v.quiet || json);
    if let Some(why) = outcomes.iter().find_map(|o| o.ended.write_failed.as_ref()) {
        drop(staged);
        return Err(Error::io(format!(
            "cannot write {shown}/{why}; the batch was not committed and {}",
            out.kept()
        )));
    }
    // A recipe stopped at --time-limit stops the batch: nothing half-done
    // is committed (docs/commands.md, "Time limits").
    let timed_out = |o: &&Outcome| {
        o.ended
            .result
            .as_ref()
            .is_err_and(|e| e.kind == ErrorKind::TimeLimit)
    };
    if outcomes.iter().any(|o| timed_out(&o)) {
        drop(staged);
        let built = outcomes.iter().filter(|o| o.ended.result.is_ok()).count();
        return Err(Error::new(
            ErrorKind::TimeLimit,
            format!(
                "the batch stopped at its time limit with {built} of {} built; it was not committed and {}",
                plural(outcomes.len(), "recipe"),
                out.kept()
            ),
        ));
    }
    // batch.json records every recipe's status; no times, so that it is
    // the same on every run.
    let record: Vec<Record> = outcomes.iter().map(|o| o.record(false)).collect();
    // Recorded like a build's files (from no inputs, so never kept), so
    // that a rebuild can tell an edit to it.
    let written = staged.write_build(
        "",
        &[(
            "batch.json".to_string(),
            (json_text(&record) + "\n").into_bytes(),
        )],
        None,
        &(),
    );
    if let Err(e) = written {
        return Err(Error::io(format!(
            "cannot write {shown}: {e}; {}",
            out.kept()
        )));
    }
    staged.commit()?;
    if json {
        let timed: Vec<Record> = outcomes.iter().map(|o| o.record(true)).collect();
        print_json(&timed);
    } else if !v.quiet {
        summary(&outcomes, &shown);
    }
    failures(&outcomes)
}

/// A running batch: what its jobs share.
struct Batch<'a> {
    paths: &'a [PathBuf],
    folders: &'a [String],
    out: &'a OutDir,
    staged: &'a Staged<'a>,
    overrides: &'a Overrides,
    jobs: usize,
    /// Each recipe's outcome, once it has ended.
    outcomes: Vec<Mutex<Option<Outcome>>>,
    stages: Stages<Work<Unsimulated>, Work<Build>>,
    bar: Mutex<Progress>,
    /// Nothing said on stderr but errors (`-q`, `--json`).
    quiet: bool,
}

impl Batch<'_> {
    /// Runs every recipe's stages on the jobs (`quiet`: no progress), and
    /// gives the outcomes of those that ended, in the recipes' order.
    fn run(self, quiet: bool) -> Vec<Outcome> {
        let what = format!("building {}", plural(self.paths.len(), "recipe"));
        // On a terminal the bar shows progress; off one, finished recipes are
        // lines and a long one still gets a line now and then.
        let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
        super::progress::heartbeat(&what, quiet || tty, || {
            std::thread::scope(|s| {
                for _ in 0..self.jobs.min(self.paths.len()) {
                    s.spawn(|| self.job());
                }
            });
        });
        self.bar
            .into_inner()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
        self.outcomes
            .into_iter()
            .filter_map(|m| m.into_inner().unwrap_or_else(|e| e.into_inner()))
            .collect()
    }

    /// One job: takes stages of any recipe until none are left.
    fn job(&self) {
        let _stop = StopOnPanic(&self.stages);
        while let Some(task) = self.stages.take() {
            match task {
                Task::Start(i) => self.start(i),
                Task::Simulate(i, work) => self.simulate(i, work),
                Task::Draw {
                    recipe: i,
                    work,
                    alone,
                } => self.draw(i, &work, alone),
            }
        }
    }

    /// Recipe `i`'s first stage (`start`): ended there, or queued to
    /// simulate or to draw.
    fn start(&self, i: usize) {
        let clock = Instant::now();
        match start(
            &self.paths[i],
            &self.folders[i],
            self.out,
            self.staged,
            self.overrides,
        ) {
            Started::Ended(ended) => {
                self.end(i, clock.elapsed().as_secs_f64(), ended);
            }
            Started::Simulate(mut work) => {
                work.seconds += clock.elapsed().as_secs_f64();
                self.stages.simulate(i, work.build.cells(), work);
            }
            Started::Draw(mut work) => {
                work.seconds += clock.elapsed().as_secs_f64();
                self.stages.draw(i, work.build.lattice.cells.len(), work);
            }
        }
    }

    /// Recipe `i`'s simulation, then queued to draw; said first when
    /// reckoned long, as a single build says it (`Estimate::said`).
    fn simulate(&self, i: usize, work: Work<Unsimulated>) {
        let clock = Instant::now();
        let Work {
            recipe,
            key,
            recorded,
            seconds,
            build,
        } = work;
        let said = build
            .estimate()
            .and_then(|e| e.said(&self.overrides.deadline));
        if let Some(line) = said.filter(|_| !self.quiet) {
            let mut bar = self.bar.lock().unwrap_or_else(|e| e.into_inner());
            bar.print(&format!("{}: {line}\n", recipe.file));
        }
        let simulated = simulate(&recipe, build, (self.out, &self.folders[i]));
        let seconds = seconds + clock.elapsed().as_secs_f64();
        match simulated {
            Ok(build) => {
                let cells = build.lattice.cells.len();
                let work = Work {
                    recipe,
                    key,
                    recorded,
                    seconds,
                    build,
                };
                self.stages.draw(i, cells, work);
            }
            Err(e) => self.end(i, seconds, Ended::failed(e)),
        }
    }

    /// Recipe `i`'s last stage (`draw`).
    fn draw(&self, i: usize, work: &Work<Build>, alone: bool) {
        let clock = Instant::now();
        // A second thread for the pictures only where no other stage would
        // use the core.
        let jobs = if alone {
            Jobs::new(self.jobs)
        } else {
            Jobs::ONE
        };
        let ended = draw(work, &self.folders[i], self.staged, jobs);
        self.end(i, work.seconds + clock.elapsed().as_secs_f64(), ended);
    }

    /// A recipe has ended: its outcome recorded and shown. A write that
    /// failed (a full disk) stops the batch: it cannot commit.
    fn end(&self, i: usize, seconds: f64, ended: Ended) {
        let outcome = Outcome {
            file: self.paths[i].display().to_string(),
            folder: self.folders[i].clone(),
            seconds,
            ended,
        };
        if outcome.ended.write_failed.is_some() {
            self.stages.stop();
        }
        let mut bar = self.bar.lock().unwrap_or_else(|e| e.into_inner());
        match &outcome.ended.result {
            Ok(_) => bar.finished(&outcome.folder, "ok", outcome.seconds),
            Err(e) => {
                bar.print(&e.text);
                bar.finished(&outcome.folder, "FAILED", outcome.seconds);
            }
        }
        drop(bar);
        *self.outcomes[i].lock().unwrap_or_else(|e| e.into_inner()) = Some(outcome);
        self.stages.finish(i);
    }
}

/// The committed batch in words: the table, what was reused and kept,
/// and where it went.
fn summary(outcomes: &[Outcome], shown: &std::path::Display<'_>) {
    out!("{}", table(outcomes));
    if let Some(line) = reused_line(outcomes) {
        outln!("{line}");
    }
    let kept = outcomes.iter().filter(|o| o.ended.kept).count();
    if kept > 0 {
        let what = format!(
            "the files of {kept} of {}",
            plural(outcomes.len(), "recipe")
        );
        outln!("{}", kept_line(&what));
    }
    let built = outcomes.iter().filter(|o| o.ended.result.is_ok()).count();
    outln!("wrote {} to {shown}", plural(built, "build"));
}

/// The batch's error when any recipe failed: an I/O error if one of the
/// failures was.
fn failures(outcomes: &[Outcome]) -> Result<(), Error> {
    let failed: Vec<&Outcome> = outcomes
        .iter()
        .filter(|o| o.ended.result.is_err())
        .collect();
    if failed.is_empty() {
        return Ok(());
    }
    let names: Vec<&str> = failed.iter().map(|o| o.file.as_str()).collect();
    let io = failed.iter().any(|o| {
        o.ended
            .result
            .as_ref()
            .is_err_and(|e| e.kind == ErrorKind::Io)
    });
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

/// A folder name as file systems that fold names compare it: in Unicode
/// normal form C (`café` whether its `é` is one character or `e` and a
/// combining accent) and in lower case.
fn folded(name: &str) -> String {
    use unicode_normalization::UnicodeNormalization;
    name.nfc().collect::<String>().to_lowercase()
}

/// Each recipe's subfolder: its file name without `.toml`, made a safe
/// single path component (see `safe_component`); recipes of the same name
/// from different folders get the folder's name in front (`examples-disk`,
/// `templates-disk`). Names that differ only in case or in Unicode
/// normalisation are refused too (`folded`), as they would share a folder
/// on macOS and Windows, and look alike everywhere.
fn folders(paths: &[PathBuf]) -> Result<Vec<String>, Error> {
    let mut count: BTreeMap<String, usize> = BTreeMap::new();
    for p in paths {
        *count.entry(folded(&safe_component(&stem(p)))).or_default() += 1;
    }
    let names: Vec<String> = paths
        .iter()
        .map(|p| {
            let name = safe_component(&stem(p));
            // A bare file name's folder is the current one.
            let parent = super::files::dir_of(p)
                .canonicalize()
                .ok()
                .and_then(|d| d.file_name().map(|n| n.to_string_lossy().into_owned()));
            let name = match parent {
                Some(dir) if count[&folded(&name)] > 1 => safe_component(&format!("{dir}-{name}")),
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
        if let Some(first) = seen.insert(folded(name), p) {
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

/// The recipes' indices in the order to start them, each with the cells
/// its build will hold (`karigami::build_cells`, for `stages::HELD_CELLS`):
/// with several jobs the dearest first, so that the longest simulations
/// are known and started early (the examples' saddle ring and torus are
/// last by name). The cost is `karigami::build_cost`, read off the parsed
/// recipe without growing it (growth waits for the build, and a kept
/// recipe never grows); a recipe that does not parse costs nothing. Ties
/// keep the name order.
fn dearest_first(paths: &[PathBuf], overrides: &Overrides, jobs: usize) -> Vec<(usize, usize)> {
    let parsed: Vec<(usize, usize)> = paths
        .iter()
        .map(|path| {
            Recipe::read(path)
                .and_then(|r| r.parse(overrides))
                .map_or((0, 0), |d| {
                    (karigami::build_cost(&d), karigami::build_cells(&d))
                })
        })
        .collect();
    let mut order: Vec<usize> = (0..paths.len()).collect();
    if jobs > 1 {
        order.sort_by_key(|&i| std::cmp::Reverse(parsed[i].0));
    }
    order.into_iter().map(|i| (i, parsed[i].1)).collect()
}

/// A started recipe's work, carried from stage to stage.
struct Work<T> {
    recipe: Recipe,
    /// The fingerprint of its inputs (`build::inputs_with`).
    key: Option<u64>,
    /// The target the recipe records, if any.
    recorded: Recorded,
    /// Seconds spent on it so far, over its stages.
    seconds: f64,
    build: T,
}

/// What starting a recipe led to.
enum Started {
    /// Its files kept from the earlier build, or a failure.
    Ended(Ended),
    Simulate(Work<Unsimulated>),
    Draw(Work<Build>),
}

/// How a recipe's stages ended.
struct Ended {
    result: Result<Report, Error>,
    /// Its files were kept from the earlier build (`files::Staged::keep`).
    kept: bool,
    /// Writing its files failed: the batch must not commit.
    write_failed: Option<String>,
}

impl Ended {
    fn failed(e: Error) -> Self {
        Self {
            result: Err(e),
            kept: false,
            write_failed: None,
        }
    }

    /// Built (or kept from the earlier build, `kept`) and written.
    fn ok(report: Report, kept: bool) -> Self {
        Self {
            result: Ok(report),
            kept,
            write_failed: None,
        }
    }

    fn write_failed(folder: &str, e: &std::io::Error) -> Self {
        Self {
            result: Err(Error::io(format!("cannot write {folder}/: {e}"))),
            kept: false,
            write_failed: Some(format!("{folder}/: {e}")),
        }
    }
}

/// The first stage of one recipe of the batch: keep the earlier build's
/// files in its subfolder where nothing they are made from changed, else
/// build it up to its simulation; one that does not simulate is built
/// whole here.
fn start(
    path: &Path,
    folder: &str,
    out: &OutDir,
    staged: &Staged,
    overrides: &Overrides,
) -> Started {
    let recipe = match Recipe::read(path) {
        Ok(recipe) => recipe,
        Err(e) => return Started::Ended(Ended::failed(e)),
    };
    // The target the recipe records, fitted in its report.txt as a single
    // build fits it (docs/design.md, "The recipe's record").
    let recorded = recorded_of(&recipe, path, overrides);
    let key = inputs_with(&recipe, overrides, folder, &target_key(None, &recorded));
    match staged.keep(out, folder, key) {
        Err(e) => return Started::Ended(Ended::write_failed(folder, &e)),
        Ok(Some(report)) => {
            return Started::Ended(Ended::ok(report, true));
        }
        Ok(None) => {}
    }
    let unsimulated = unsimulated(&recipe, overrides, &mut |_| {});
    let build = match unsimulated {
        Ok(b) if b.simulates() => {
            return Started::Simulate(Work {
                recipe,
                key,
                recorded,
                seconds: 0.0,
                build: b,
            });
        }
        Ok(b) => simulate(&recipe, b, (out, folder)),
        Err(e) => Err(e),
    };
    match build {
        Ok(build) => Started::Draw(Work {
            recipe,
            key,
            recorded,
            seconds: 0.0,
            build,
        }),
        Err(e) => Started::Ended(Ended::failed(e)),
    }
}

/// The last stage of one recipe: its files made (on `jobs` threads,
/// `karigami::files_on`) and written.
fn draw(work: &Work<Build>, folder: &str, staged: &Staged, jobs: Jobs) -> Ended {
    let mut report = Report::of(&work.build);
    let mut files = karigami::files_on(&work.build, jobs);
    let target = work.recorded.target();
    add_fit(&work.build, target, &work.recorded, &mut files, &mut report);
    match staged.write_build(folder, &files, work.key, &report) {
        Ok(()) => Ended::ok(report, false),
        Err(e) => Ended::write_failed(folder, &e),
    }
}

impl Outcome {
    fn record(&self, timed: bool) -> Record<'_> {
        let (status, summary, error) = match &self.ended.result {
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
                .and_then(|s| s.simulation(self.ended.kept))
                .filter(|_| timed),
        }
    }
}

/// How many of the simulated recipes reused the earlier batch's
/// simulation, in one line; None when none simulated.
fn reused_line(outcomes: &[Outcome]) -> Option<String> {
    let how: Vec<&str> = outcomes
        .iter()
        .filter_map(|o| o.ended.result.as_ref().ok()?.simulation(o.ended.kept))
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
        match &o.ended.result {
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
