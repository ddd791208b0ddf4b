//! `karigami tune`: tune a helix seed until it grows the cells asked for
//! (or, with an [optimise] table, run the design optimiser).

use super::args::Verbosity;
use super::error::Error;
use super::recipe::Recipe;
use super::{files, optimise, progress};
use karigami::{ErrorKind, Overrides};
use std::path::Path;

/// `out`: the file to write the tuned recipe to, and whether `--force`
/// lets it replace an existing file.
pub(super) fn tune(
    path: &Path,
    cells: Option<usize>,
    out: Option<(&Path, bool)>,
    iterations: usize,
    (jobs, deadline): (usize, karigami::Deadline),
    v: Verbosity,
) -> Result<(), Error> {
    let recipe = Recipe::read(path)?;
    // A refusal before the work, not after minutes of tuning.
    let out = out
        .map(|(o, force)| files::OutFile::check(o, (path, &recipe.source), force))
        .transpose()?;
    let out = out.as_ref();
    let design = recipe.parse(&Overrides {
        deadline,
        ..Overrides::default()
    })?;
    if design.optimise.is_some() {
        return optimise::run(&recipe, &design, out, jobs, v);
    }
    if design.kind != karigami::Kind::Helix {
        return Err(Error::usage(format!(
            "{}: `karigami tune` tunes helix seeds; this recipe's seed is \"{}\"",
            recipe.file,
            design.kind.name()
        )));
    }
    let target = cells.unwrap_or(design.helix_cells);
    // Legs shorter than the eyelet flange (plus a wall) cannot be built.
    let min_leg = design.fabrication.eyelet.flange + 2.0 * karigami::MIN_WALL;
    // Refused up front beyond the limit, said up front when long
    // (docs/commands.md, "Time limits").
    let estimate = karigami::tune_within_time(&design, (target, iterations), cells.is_some())
        .map_err(|d| recipe.error(&d))?;
    if let Some(line) = estimate.said(&deadline).filter(|_| !v.quiet) {
        errln!("{}: {line}", recipe.file);
    }
    let what = format!("tuning {} (up to {iterations} tries)", recipe.file);
    let tuned = progress::heartbeat(&what, v.quiet, || {
        karigami::tune_helix_until(
            design.dim,
            &design.points,
            &design.kappa,
            (target, min_leg, iterations),
            &deadline,
        )
    })
    .map_err(|t| {
        let stopped = deadline.stopped(t.iterations, iterations, "tries");
        Error::new(
            ErrorKind::TimeLimit,
            format!(
                "{}: the tuner {stopped}, growing {} of {target} cells; nothing was written (allow more time with --time-limit SECONDS, docs/commands.md)",
                recipe.file, t.cells_after
            ),
        )
    })?;
    let Some(text) = design.with_seed(&recipe.source, &tuned.points, &tuned.kappa) else {
        return Err(Error::usage(format!(
            "{}: write the seed as `points = [...]` and `kappa = [...]` to tune it",
            recipe.file
        )));
    };
    if !v.quiet {
        errln!(
            "tuned {} in {} tries: grows {} of {target} cells with legs of at least {min_leg:.1} mm (was {}); points moved up to {:.3} mm, kappa changed up to {:.3} mm",
            recipe.file,
            tuned.iterations,
            tuned.cells_after,
            tuned.cells_before,
            tuned.max_move,
            tuned.max_kappa_change
        );
    }
    // Only a seed that reached the target is written: a failed tune leaves
    // the --out file (often the recipe itself) as it was.
    if tuned.cells_after < target {
        let kept = out.map_or(String::new(), |o| {
            format!("; {} was not written", o.path().display())
        });
        return Err(Error::new(
            ErrorKind::TuneNotReached,
            format!(
                "the tuner did not reach {target} cells: try fewer cells, more --iterations, or another start seed{kept}"
            ),
        ));
    }
    match out {
        Some(o) => o.write(text.as_bytes())?,
        None => out!("{text}"),
    }
    Ok(())
}
