//! `karigami check`: grow and verify recipes, print the report, write nothing.

use super::args::Verbosity;
use super::error::{Error, ErrorJson, print_json};
use super::files;
use super::progress::{self, Progress, fit_note};
use super::recipe::Recipe;
use glam::DVec3;
use karigami::targets::{Fit, Target};
use karigami::{ErrorKind, Lattice, Overrides};
use serde::Serialize;
use std::io::Read as _;
use std::path::{Path, PathBuf};

/// One recipe in `check --json`'s report.
#[derive(Serialize)]
struct CheckJson {
    file: String,
    /// "pass", "fail" (the lattice fails verification) or "error".
    status: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<ErrorJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    check: Option<serde_json::Value>,
    #[serde(skip_serializing_if = "Option::is_none")]
    build: Option<serde_json::Value>,
    /// The fit to `--target`, or to the target the recipe records.
    #[serde(skip_serializing_if = "Option::is_none")]
    target: Option<FitJson>,
    /// Why the recorded target's fit is not reported: missing, changed.
    #[serde(skip_serializing_if = "Option::is_none")]
    target_note: Option<String>,
    /// "solved" or "reused" (from `--reuse`'s build), as in `build --json`;
    /// absent when nothing was simulated.
    #[serde(skip_serializing_if = "Option::is_none")]
    simulation: Option<&'static str>,
}

impl CheckJson {
    fn new(file: &str, status: &'static str) -> Self {
        Self {
            file: file.to_string(),
            status,
            error: None,
            check: None,
            build: None,
            target: None,
            target_note: None,
            simulation: None,
        }
    }
}

/// What `check` was asked beside its recipes.
#[derive(Clone, Copy)]
pub(super) struct Asked<'a> {
    /// A JSON report on stdout instead of text.
    pub json: bool,
    /// `--target`: the shape to report the fit to.
    pub target: Option<&'a Path>,
    /// `--reuse`: a build folder whose simulation states are restored.
    pub reuse: Option<&'a Path>,
}

pub(super) fn check(
    paths: &[PathBuf],
    asked: Asked,
    overrides: &Overrides,
    v: Verbosity,
) -> Result<(), Error> {
    let json = asked.json;
    // A bad target or build folder is refused before any recipe is grown.
    let target = asked.target.map(TargetFile::read).transpose()?;
    let reuse = asked.reuse.map(files::EarlierBuild::open).transpose()?;
    let given = Given {
        target: target.as_ref(),
        reuse: reuse.as_ref(),
    };
    let paths = files::recipes(paths)?;
    let mut reports = Vec::new();
    let mut worst: Option<ErrorKind> = None;
    let mut bar = Progress::new(paths.len(), v.quiet || json);
    for path in &paths {
        let what = format!("checking {}", path.display());
        let (failed, report) = progress::heartbeat(&what, v.quiet || json, || {
            check_one(path, json, &given, overrides, v, &mut bar)
        });
        if let Some(kind) = failed
            && worst.is_none_or(|w| kind.exit_code() > w.exit_code())
        {
            worst = Some(kind);
        }
        reports.push(report);
    }
    bar.clear();
    if json {
        print_json(&reports);
    }
    match worst {
        None => Ok(()),
        Some(kind) => Err(Error::shown(kind)),
    }
}

/// The files `check` read for every recipe: `--target` and `--reuse`.
struct Given<'a> {
    target: Option<&'a TargetFile>,
    reuse: Option<&'a files::EarlierBuild>,
}

/// Check one recipe: print its report (text unless `json`), return what
/// failed, if anything, and the JSON report.
fn check_one(
    path: &Path,
    json: bool,
    given: &Given,
    overrides: &Overrides,
    v: Verbosity,
    bar: &mut Progress,
) -> (Option<ErrorKind>, CheckJson) {
    let file = path.display().to_string();
    let fail = |e: Error, bar: &mut Progress| {
        if !json {
            bar.print(&e.text);
        }
        let mut checked = CheckJson::new(&file, "error");
        checked.error = e.json.map(|j| *j);
        (Some(e.kind), checked)
    };
    let recipe = match Recipe::read(path) {
        Ok(r) => r,
        Err(e) => return fail(e, bar),
    };
    let design = match recipe.parse(overrides) {
        Ok(d) => d,
        Err(e) => return fail(e, bar),
    };
    // No --target: the one the recipe records, if any (`karigami design`).
    let target = given.target;
    let recorded = match target {
        Some(_) => Recorded::None,
        None => Recorded::of(path, design.target.as_ref()),
    };
    let target = target.or(recorded.target());
    let target_note = recorded.note().map(str::to_string);
    // A shown report reads the measures: taken at once, on a second core
    // beside verification where there is one (the report is the same).
    let shown = json || !v.quiet;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs = karigami::Jobs::new(cores);
    let checked = match karigami::check_on(design, &mut |note| fit_note(note, v, bar), shown, jobs)
    {
        Ok(c) => c,
        Err(d) => return fail(recipe.error(&d), bar),
    };
    bar.clear();
    // Each report is made only when it is shown, and `-q` shows neither:
    // the measures and parts they read are derived on first use, once, and
    // `assemble` takes them over.
    let check = json.then(|| karigami::check_json(&checked.verified()));
    if !json && !v.quiet {
        out!("{}", karigami::check_text(&checked.verified()));
    }
    if !checked.report.passed() {
        let mut checked = CheckJson::new(&file, "fail");
        checked.check = check;
        return (Some(ErrorKind::VerificationFailed), checked);
    }
    if let Some(why) = checked.too_large_to_fabricate() {
        if !json && !v.quiet {
            outln!(
                "fabrication: not checked ({})\nresult: PASS (geometry verified)",
                why.message
            );
        }
        // Freeing a large lattice's memory takes a tenth of a second on 4 M
        // cells: done beside the next recipe, or left to the exit.
        let fit = target.map(|t| t.fit(checked.assembled(), None));
        if !(json || v.quiet) {
            out!(
                "{}",
                fit.as_ref()
                    .map_or(target_note.as_deref().unwrap_or(""), |f| &f.text)
            );
        }
        std::thread::spawn(move || drop(checked));
        let mut checked = CheckJson::new(&file, "pass");
        checked.check = check;
        checked.target = fit.map(|f| f.json);
        checked.target_note = target_note.map(|n| n.trim_end().to_string());
        return (None, checked);
    }
    let state = given
        .reuse
        // The batch's subfolder is named as the recipe's stem made safe.
        .and_then(|r| r.state(&recipe.stem, super::recipe::STATE_LIMIT));
    if !state.as_deref().is_some_and(|s| checked.restores(s)) {
        say_estimate(&file, &checked, overrides, json || v.quiet, bar);
    }
    match checked.assemble_for_check(state.as_deref()) {
        Ok(built) => {
            let fit = target.map(|t| t.fit_build(&built));
            if !json && !v.quiet {
                out!("{}", karigami::summary(&built));
                if let Some(r) = given.reuse {
                    out!("{}", reuse_line(&built, r));
                }
                let said = fit.as_ref().map(|f| f.text.as_str());
                out!("{}", said.or(target_note.as_deref()).unwrap_or(""));
                outln!("result: PASS (geometry verified, every strip can be cut)");
            }
            let mut checked = CheckJson::new(&file, "pass");
            checked.check = check;
            checked.target = fit.map(|f| f.json);
            checked.target_note = target_note.map(|n| n.trim_end().to_string());
            checked.build = json.then(|| karigami::build_json(&built));
            checked.simulation = super::recipe::simulation(&built);
            (None, checked)
        }
        Err(d) => {
            let (failed, mut checked) = fail(recipe.error(&d), bar);
            checked.check = check;
            (failed, checked)
        }
    }
}

/// Where `--reuse` found the simulated shape, as a line of the report;
/// nothing for a build that simulates nothing.
fn reuse_line(built: &karigami::Build, reuse: &files::EarlierBuild) -> String {
    let dir = reuse.path().display();
    match built.simulation_reused() {
        Some(true) => {
            format!("simulation: reused from the build in {dir} (nothing it depends on changed)\n")
        }
        Some(false) => format!(
            "simulation: solved (the build in {dir} holds none of this recipe as it is now)\n"
        ),
        None => String::new(),
    }
}

/// Long work said up front (docs/commands.md, "Time limits"): the
/// simulation `assemble_for_check` runs, when reckoned long; nothing when
/// `quiet` (`-q`, or `--json`, which prints no progress).
fn say_estimate(
    file: &str,
    checked: &karigami::Checked,
    overrides: &Overrides,
    quiet: bool,
    bar: &mut Progress,
) {
    let said = checked.estimate().and_then(|e| e.said(&overrides.deadline));
    if let Some(line) = said.filter(|_| !quiet) {
        bar.print(&format!("{file}: {line}\n"));
    }
}

/// The target a recipe's `[target]` table records (`karigami design`,
/// docs/design.md "The recipe's record"), its path read relative to the
/// recipe's folder: the file when it is there and its bytes hash as
/// recorded, else one line saying why its fit is not reported.
pub(super) enum Recorded {
    None,
    Target(TargetFile),
    Note(String),
}

impl Recorded {
    pub(super) fn of(recipe: &Path, target: Option<&(String, Option<String>)>) -> Self {
        let Some((file, hash)) = target else {
            return Self::None;
        };
        let path = recipe.parent().unwrap_or(Path::new(".")).join(file);
        // Named as the recipe records it, so that the report reads the
        // same whatever folder the build was run from.
        let shown = file;
        let note = |why: String| {
            Self::Note(format!(
                "target {shown} (recorded by the recipe): {why}, so its fit is not reported; --target FILE fits any\n"
            ))
        };
        if !path.is_file() {
            return note("not found".into());
        }
        match TargetFile::read(&path) {
            Ok(t) => match hash {
                Some(h) if *h != format!("{:016x}", t.hash) => note(format!(
                    "changed since the design was made (hash {:016x}, the recipe records {h})",
                    t.hash
                )),
                _ => Self::Target(TargetFile {
                    file: file.clone(),
                    ..t
                }),
            },
            Err(e) => note(format!("cannot be read ({})", e.message())),
        }
    }

    pub(super) fn target(&self) -> Option<&TargetFile> {
        match self {
            Self::Target(t) => Some(t),
            _ => None,
        }
    }

    pub(super) fn note(&self) -> Option<&str> {
        match self {
            Self::Note(n) => Some(n),
            _ => None,
        }
    }
}

/// A `--target` file read and validated (docs/design.md), with a
/// fingerprint of its bytes for the build's record.
pub(super) struct TargetFile {
    pub file: String,
    pub target: Target,
    pub hash: u64,
}

/// The fit of a design and its simulated shape to a target, as text for
/// the terminal and report.txt and as `check --json`'s `target`.
pub(super) struct TargetFit {
    pub text: String,
    pub json: FitJson,
}

/// A fit's line (`Fit::summary`) with, on a bump, the share of its top
/// covered: `check`, the report and `design`'s recipe say it alike.
pub(super) fn fit_line(fit: &Fit, top: Option<f64>, what: &str) -> String {
    let mut line = fit.summary(what);
    if let Some(top) = top {
        line.push_str(&format!("; the bump's top {:.1} % covered", 100.0 * top));
    }
    line
}

/// `check --json`'s fit to the target: lengths in mm.
#[derive(Serialize)]
pub(super) struct FitJson {
    file: String,
    what: String,
    topology: String,
    triangles: usize,
    extent: f64,
    design: FitFigures,
    #[serde(skip_serializing_if = "Option::is_none")]
    simulated: Option<FitFigures>,
}

#[derive(Serialize)]
struct FitFigures {
    points: usize,
    rms: f64,
    largest: f64,
    coverage: Option<f64>,
    /// On a bump: the share of its top covered.
    #[serde(skip_serializing_if = "Option::is_none")]
    top: Option<f64>,
}

impl FitFigures {
    fn of(f: &Fit, top: Option<f64>) -> Self {
        Self {
            points: f.points,
            rms: f.rms,
            largest: f.largest,
            coverage: f.coverage,
            top,
        }
    }
}

impl TargetFile {
    /// Read a target: refused from its length and first bytes before the
    /// rest is read, so a huge file costs neither time nor memory.
    pub(super) fn read(path: &Path) -> Result<Self, Error> {
        let file = path.display().to_string();
        let unreadable = |e: std::io::Error| Error::unreadable(&file, &e);
        let mut f = std::fs::File::open(path).map_err(unreadable)?;
        let len = f.metadata().map_err(unreadable)?.len();
        if path.is_dir() {
            return Err(unreadable(std::io::Error::other(
                "it is a folder, not a target file",
            )));
        }
        let mut bytes = Vec::new();
        (&mut f)
            .take(84)
            .read_to_end(&mut bytes)
            .map_err(unreadable)?;
        karigami::targets::refuse_early(&file, len, &bytes)
            .map_err(|d| Error::at(&file, "", &d))?;
        // No more than the length checked, should the file grow meanwhile.
        f.take(len.saturating_sub(bytes.len() as u64))
            .read_to_end(&mut bytes)
            .map_err(unreadable)?;
        let target = karigami::targets::read(&file, &bytes, None)
            .map_err(|d| Error::at(&file, std::str::from_utf8(&bytes).unwrap_or(""), &d))?;
        Ok(Self {
            file,
            target,
            hash: karigami::util::fnv1a(&bytes),
        })
    }

    /// The fit of a build's lattice as assembled and, where it was
    /// simulated, of its simulated joints.
    pub(super) fn fit_build(&self, built: &karigami::Build) -> TargetFit {
        let scene = karigami::viewer_scene(built);
        let joints = scene
            .simulated
            .as_ref()
            .map(|points| &points[..built.lattice.vertices.len().min(points.len())]);
        self.fit(&built.assembled, joints)
    }

    /// The fit of a lattice's vertices and, when given, of the simulated
    /// positions of the same vertices; the cells are the facets.
    pub(super) fn fit(&self, lattice: &Lattice, simulated: Option<&[DVec3]>) -> TargetFit {
        let facets = lattice.facets();
        let points: Vec<DVec3> = lattice.vertices.iter().map(|v| v.pos).collect();
        let t = &self.target;
        let design = t.fit(&points, &facets);
        let simulated = simulated.map(|s| (t.fit(s, &facets), s));
        // A bump's top is judged apart (docs/design.md, "The goal").
        let top = karigami::designing::bump_top(t);
        let top_of = |fit: &Fit, points: &[DVec3]| {
            top.as_ref()
                .map(|top| t.covered_part(fit, (points, &facets), top))
        };
        let design_top = top_of(&design, &points);
        let simulated = simulated.map(|(fit, s)| {
            let top = top_of(&fit, s);
            (fit, top)
        });
        let mut text = format!(
            "target {}: {}, {}, {} triangles, largest extent D {:.1} mm\n",
            self.file,
            t.what,
            t.topology.describe(),
            t.mesh.triangles.len(),
            t.extent
        );
        text.push_str(&format!(
            "  fit of the design, {}\n",
            fit_line(&design, design_top, "vertices")
        ));
        if let Some((s, top)) = &simulated {
            text.push_str(&format!(
                "  fit of the simulated shape, {}\n",
                fit_line(s, *top, "joints")
            ));
        }
        TargetFit {
            text,
            json: FitJson {
                file: self.file.clone(),
                what: t.what.clone(),
                topology: t.topology.describe(),
                triangles: t.mesh.triangles.len(),
                extent: t.extent,
                design: FitFigures::of(&design, design_top),
                simulated: simulated.as_ref().map(|(s, top)| FitFigures::of(s, *top)),
            },
        }
    }
}
