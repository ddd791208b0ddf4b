//! `karigami check`: grow and verify recipes, print the report, write nothing.

use super::args::Verbosity;
use super::error::{Error, ErrorJson, print_json};
use super::files;
use super::progress::{self, Progress, fit_note};
use super::recipe::Recipe;
use karigami::{ErrorKind, Overrides};
use serde::Serialize;
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
}

impl CheckJson {
    fn new(file: &str, status: &'static str) -> Self {
        Self {
            file: file.to_string(),
            status,
            error: None,
            check: None,
            build: None,
        }
    }
}

pub(super) fn check(
    paths: &[PathBuf],
    json: bool,
    overrides: &Overrides,
    v: Verbosity,
) -> Result<(), Error> {
    let paths = files::recipes(paths)?;
    let mut reports = Vec::new();
    let mut worst: Option<ErrorKind> = None;
    let mut bar = Progress::new(paths.len(), v.quiet || json);
    for path in &paths {
        let what = format!("checking {}", path.display());
        let (failed, report) = progress::heartbeat(&what, v.quiet || json, || {
            check_one(path, json, overrides, v, &mut bar)
        });
        if let Some(kind) = failed {
            if worst.is_none_or(|w| kind.exit_code() > w.exit_code()) {
                worst = Some(kind);
            }
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

/// Check one recipe: print its report (text unless `json`), return what
/// failed, if anything, and the JSON report.
fn check_one(
    path: &Path,
    json: bool,
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
    // A shown report reads the measures: taken at once, on a second core
    // beside verification where there is one (the report is the same).
    let shown = json || !v.quiet;
    let two = std::thread::available_parallelism().is_ok_and(|n| n.get() > 1);
    let checked = match karigami::check_on(design, &mut |note| fit_note(note, v, bar), shown, two) {
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
        std::thread::spawn(move || drop(checked));
        let mut checked = CheckJson::new(&file, "pass");
        checked.check = check;
        return (None, checked);
    }
    match checked.assemble_for_check() {
        Ok(built) => {
            if !json && !v.quiet {
                out!("{}", karigami::summary(&built));
                outln!("result: PASS (geometry verified, every strip can be cut)");
            }
            let mut checked = CheckJson::new(&file, "pass");
            checked.check = check;
            checked.build = json.then(|| karigami::build_json(&built));
            (None, checked)
        }
        Err(d) => {
            let (failed, mut checked) = fail(recipe.error(&d), bar);
            checked.check = check;
            (failed, checked)
        }
    }
}
