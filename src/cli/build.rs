//! `karigami build` of one recipe (several go to `batch`): grow, verify,
//! draw and write the files into --out, replacing it as a whole.

use super::args::Verbosity;
use super::check::{Recorded, TargetFile};
use super::error::{Error, print_json};
use super::files;
use super::progress::{self, Progress, fit_note};
use super::recipe::{self, Recipe, simulation};
use karigami::Overrides;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `build --json`'s report of one recipe.
#[derive(Serialize)]
struct Built<'a> {
    /// The recipe; null for the built-in sheet.
    file: Option<String>,
    status: &'static str,
    out: String,
    files: Vec<&'a str>,
    seconds: f64,
    check: serde_json::Value,
    build: serde_json::Value,
    /// "solved" or "reused" (from the earlier build in `out`); absent when
    /// the build does not simulate.
    #[serde(skip_serializing_if = "Option::is_none")]
    simulation: Option<&'static str>,
}

/// How one recipe is built: threads, the report's form, the target whose
/// fit report.txt gives.
#[derive(Clone, Copy)]
pub(super) struct Run<'a> {
    pub jobs: usize,
    pub json: bool,
    pub target: Option<&'a Path>,
}

pub(super) fn build(
    paths: &[PathBuf],
    out: &Path,
    force: bool,
    run: Run,
    overrides: &Overrides,
    v: Verbosity,
) -> Result<(), Error> {
    let Run { jobs, json, .. } = run;
    // A bad target is refused before anything is grown or written.
    let target = run.target.map(TargetFile::read).transpose()?;
    let dir = open_out(out, paths, force, v)?;
    let recipe = match paths.first() {
        Some(p) => Recipe::read(p)?,
        None => Recipe::built_in(),
    };
    let started = Instant::now();
    let fail = |e: std::io::Error| {
        Error::io(format!(
            "cannot write {}: {e}; {}",
            out.display(),
            dir.kept()
        ))
    };
    let staged = files::Staged::new(&dir, "single").map_err(fail)?;
    // No --target: the one the recipe records (`karigami design`), found
    // or said missing; a recipe that does not parse fails in the build.
    let recorded = match (&target, paths.first()) {
        (None, Some(p)) => recorded_of(&recipe, p, overrides),
        _ => Recorded::None,
    };
    let key = inputs_with(
        &recipe,
        overrides,
        "",
        &target_key(target.as_ref(), &recorded),
    );
    let target = target.as_ref().or(recorded.target());
    // The earlier build's files where nothing they are made from changed.
    let (report, kept) = match staged.keep::<Report>(&dir, "", key).map_err(fail)? {
        Some(report) => (report, true),
        None => {
            let mut bar = Progress::new(1, v.quiet || json);
            let what = format!(
                "building {}",
                paths
                    .first()
                    .map_or("the built-in sheet".into(), |p| p.display().to_string())
            );
            let built = progress::heartbeat(&what, v.quiet || json, || {
                run_recipe(&recipe, overrides, (&dir, v, json), &mut bar)
            });
            bar.clear();
            let built = built?;
            let mut outputs = progress::heartbeat("drawing the files", v.quiet || json, || {
                karigami::files_on(&built, karigami::Jobs::new(jobs))
            });
            let mut report = Report::of(&built);
            add_fit(&built, target, &recorded, &mut outputs, &mut report);
            staged
                .write_build("", &outputs, key, &report)
                .map_err(fail)?;
            (report, false)
        }
    };
    let names = staged.written();
    staged.commit()?;
    let how = report.simulation(kept);
    if json {
        print_json(&Built {
            file: paths.first().map(|p| p.display().to_string()),
            status: "ok",
            out: out.display().to_string(),
            files: names.iter().map(String::as_str).collect(),
            seconds: started.elapsed().as_secs_f64(),
            check: report.check,
            build: report.build,
            simulation: how,
        });
    } else if !v.quiet {
        if v.verbose {
            out!("{}", report.check_text);
        }
        out!("{}", report.summary);
        if let Some(fit) = &report.target_fit {
            out!("{fit}");
        }
        if let Some(how) = how {
            outln!("simulation: {}", simulation_line(how, out));
        }
        outln!("wrote {} files to {}", names.len(), out.display());
        if kept {
            outln!("{}", kept_line("every file"));
        }
    }
    Ok(())
}

/// The fit to `target` (or the line saying why the recorded one is not
/// fitted) added to report.txt and to the run's report: one build and a
/// batch's recipe alike.
pub(super) fn add_fit(
    built: &karigami::Build,
    target: Option<&TargetFile>,
    recorded: &Recorded,
    outputs: &mut [(String, Vec<u8>)],
    report: &mut Report,
) {
    let fit = target.map(|t| t.fit_build(built).text);
    if let Some(fit) = fit.or(recorded.note().map(str::to_string)) {
        if let Some((_, bytes)) = outputs.iter_mut().find(|(name, _)| name == "report.txt") {
            bytes.extend(format!("\n{fit}").bytes());
        }
        report.target_fit = Some(fit);
    }
}

/// The target a recipe records (`karigami design`), found or said
/// missing, when no --target is given; none for a recipe that does not
/// parse (it fails in the build).
pub(super) fn recorded_of(recipe: &Recipe, path: &Path, overrides: &Overrides) -> Recorded {
    recipe
        .parse(overrides)
        .map_or(Recorded::None, |d| Recorded::of(path, d.target.as_ref()))
}

/// What of the target report.txt reads, for the build's fingerprint: a
/// `--target` file's hash; the recorded target's path and hash, or the
/// line saying why it is not fitted; nothing without either.
pub(super) fn target_key(given: Option<&TargetFile>, recorded: &Recorded) -> Vec<u8> {
    match (given, recorded) {
        (Some(t), _) => t.hash.to_le_bytes().to_vec(),
        (None, Recorded::Target(t)) => format!("recorded {} {:016x}", t.file, t.hash).into_bytes(),
        (None, Recorded::Note(line)) => line.clone().into_bytes(),
        (None, Recorded::None) => Vec::new(),
    }
}

/// The fingerprint of what a recipe's files are made from (besides the
/// program, which `files::inputs` adds): the recipe's text and name, the
/// command line's options, the subfolder and the target's (`target_key`;
/// empty without one). The number of jobs is left out: the files are the
/// same with any.
pub(super) fn inputs_with(
    recipe: &Recipe,
    overrides: &Overrides,
    folder: &str,
    target: &[u8],
) -> Option<u64> {
    let options = format!("{overrides:?}");
    let mut parts: Vec<&[u8]> = vec![
        b"karigami build 1",
        recipe.file.as_bytes(),
        recipe.stem.as_bytes(),
        recipe.source.as_bytes(),
        options.as_bytes(),
        folder.as_bytes(),
    ];
    // Left out when there is none, so builds without a target keep the
    // fingerprint they had.
    if !target.is_empty() {
        parts.push(b"target");
        parts.push(target);
    }
    files::inputs(&parts)
}

/// The line saying what was kept from the earlier build (`what`: "every
/// file", "the files of 3 of 8 recipes").
pub(super) fn kept_line(what: &str) -> String {
    format!(
        "kept {what} from the earlier build (the same program, recipe and options, and every file as it was written)"
    )
}

/// What a build reports, recorded with its files so that a rebuild that
/// keeps them reports the same without building (`files::Staged::keep`).
#[derive(Serialize, serde::Deserialize)]
pub(super) struct Report {
    pub cells: usize,
    pub strips: usize,
    pub sheets: usize,
    /// Whether the build simulated the deployed shape.
    pub simulated: bool,
    pub check: serde_json::Value,
    pub build: serde_json::Value,
    /// `karigami::summary`, for the terminal.
    pub summary: String,
    /// `karigami::check_text`, for `--verbose`.
    pub check_text: String,
    /// The fit to `--target`, as report.txt gives it.
    #[serde(default)]
    pub target_fit: Option<String>,
    /// Whether this run restored the simulation (not recorded: a rebuild
    /// says "reused" where a fresh build says "solved").
    #[serde(skip)]
    pub reused: bool,
}

impl Report {
    pub(super) fn of(b: &karigami::Build) -> Self {
        let how = simulation(b);
        Self {
            cells: b.lattice.cells.len(),
            strips: b.parts.strips.len(),
            sheets: b.layout.sheets.len(),
            simulated: how.is_some(),
            check: karigami::build_check_json(b),
            build: karigami::build_json(b),
            summary: karigami::summary(b),
            check_text: karigami::check_text(&b.verified()),
            target_fit: None,
            reused: how == Some("reused"),
        }
    }

    /// Where the deployed shape came from (`recipe::simulation`): a build
    /// that was kept reused it.
    pub(super) fn simulation(&self, kept: bool) -> Option<&'static str> {
        self.simulated.then_some(if kept || self.reused {
            "reused"
        } else {
            "solved"
        })
    }
}

/// The terminal's line on where the deployed shape came from.
fn simulation_line(how: &str, out: &Path) -> String {
    match how {
        "reused" => format!(
            "reused from the earlier build in {} (nothing it depends on changed)",
            out.display()
        ),
        _ => "solved (a rebuild into the same folder reuses it)".to_string(),
    }
}

/// Check and lock the output folder before any work; say what interrupted
/// runs left and was repaired, and what `--force` deletes. The program's
/// hash for keeping files (`files::inputs`) starts meanwhile.
pub(super) fn open_out(
    out: &Path,
    inputs: &[PathBuf],
    force: bool,
    v: Verbosity,
) -> Result<files::OutDir, Error> {
    files::start_program_hash();
    let dir = files::OutDir::open(out, inputs, force)?;
    if !v.quiet {
        for note in &dir.notes {
            errln!("note: {note}");
        }
    }
    if let Some(warning) = dir.force_warning() {
        errln!("{warning}");
    }
    Ok(dir)
}

/// Parse, grow, verify, assemble and simulate one recipe, reusing the
/// simulation of the earlier build in `dir` when nothing it depends on
/// changed; a simulation reckoned long is said before it starts
/// (docs/commands.md, "Time limits"), unless quiet or `json`.
fn run_recipe(
    recipe: &Recipe,
    overrides: &Overrides,
    (dir, v, json): (&files::OutDir, Verbosity, bool),
    bar: &mut Progress,
) -> Result<karigami::Build, Error> {
    let unsimulated = recipe::unsimulated(recipe, overrides, &mut |n| fit_note(n, v, bar))?;
    let said = unsimulated
        .estimate()
        .and_then(|e| e.said(&overrides.deadline));
    if let Some(line) = said.filter(|_| !(v.quiet || json)) {
        bar.print(&format!("{}: {line}\n", recipe.file));
    }
    recipe::simulate(recipe, unsimulated, (dir, ""))
}
