//! `karigami build` of one recipe (several go to `batch`): grow, verify,
//! draw and write the files into --out, replacing it as a whole.

use super::args::Verbosity;
use super::error::{Error, print_json};
use super::files;
use super::progress::{self, Progress, fit_note};
use super::recipe::{Recipe, run_recipe, simulation};
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

pub(super) fn build(
    paths: &[PathBuf],
    out: &Path,
    force: bool,
    jobs: usize,
    json: bool,
    overrides: &Overrides,
    v: Verbosity,
) -> Result<(), Error> {
    let dir = open_out(out, paths, force, v)?;
    let recipe = match paths.first() {
        Some(p) => Recipe::read(p),
        None => Ok(Recipe::built_in()),
    };
    let started = Instant::now();
    let mut bar = Progress::new(1, v.quiet || json);
    let what = format!(
        "building {}",
        paths
            .first()
            .map_or("the built-in sheet".into(), |p| p.display().to_string())
    );
    let built = progress::heartbeat(&what, v.quiet || json, || {
        recipe
            .and_then(|r| run_recipe(&r, overrides, &mut |n| fit_note(n, v, &mut bar), (&dir, "")))
    });
    bar.clear();
    let built = built?;
    let outputs = progress::heartbeat("drawing the files", v.quiet || json, || {
        karigami::files_on(&built, jobs > 1)
    });
    let written = files::Staged::new(&dir, "single").and_then(|staged| {
        staged.write("", &outputs)?;
        staged.commit()
    });
    if let Err(e) = written {
        return Err(Error::io(format!(
            "cannot write {}: {e}; {}",
            out.display(),
            dir.kept()
        )));
    }
    if json {
        print_json(&Built {
            file: paths.first().map(|p| p.display().to_string()),
            status: "ok",
            out: out.display().to_string(),
            files: outputs.iter().map(|(n, _)| n.as_str()).collect(),
            seconds: started.elapsed().as_secs_f64(),
            check: karigami::build_check_json(&built),
            build: karigami::build_json(&built),
            simulation: simulation(&built),
        });
    } else if !v.quiet {
        if v.verbose {
            out!("{}", karigami::check_text(&built.verified()));
        }
        out!("{}", karigami::summary(&built));
        if let Some(how) = simulation(&built) {
            outln!("simulation: {}", simulation_line(how, out));
        }
        outln!("wrote {} files to {}", outputs.len(), out.display());
    }
    Ok(())
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
/// runs left and was repaired, and what `--force` deletes.
pub(super) fn open_out(
    out: &Path,
    inputs: &[PathBuf],
    force: bool,
    v: Verbosity,
) -> Result<files::OutDir, Error> {
    let dir = files::OutDir::open(out, inputs, force)?;
    if !v.quiet {
        for note in &dir.notes {
            eprintln!("note: {note}");
        }
    }
    if let Some(warning) = dir.force_warning() {
        eprintln!("{warning}");
    }
    Ok(dir)
}
