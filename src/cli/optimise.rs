//! `karigami tune` on a recipe with an `[optimise]` table: run the design
//! optimiser and write the recipe back with the optimised numbers, its
//! comments and every other setting kept.

use super::args::Verbosity;
use super::error::Error;
use super::files;
use super::progress::Progress;
use super::recipe::Recipe;
use karigami::Design;
use std::time::Instant;

pub(super) fn run(
    recipe: &Recipe,
    design: &Design,
    out: Option<&files::OutFile>,
    jobs: usize,
    v: Verbosity,
) -> Result<(), Error> {
    let mut bar = Progress::new(1, v.quiet);
    let started = Instant::now();
    let result = karigami::optimise(design, &recipe.source, jobs, &mut |note| {
        // The one estimate line, as every long command says it.
        if karigami::Estimate::is_said(note) {
            if !v.quiet {
                bar.print(&format!("{}: {note}\n", recipe.file));
            }
        } else if v.verbose {
            errln!("{note}");
        } else {
            bar.note(note);
        }
    });
    bar.clear();
    let done = match result {
        Ok(d) => d,
        Err(e) => return Err(recipe.error(&e)),
    };
    // "Met" is build's word too: the whole pipeline, simulation included,
    // must take the result (docs/commands.md, `karigami tune`), or tune says why it
    // does not; within the run's --time-limit, as the search was.
    let mut best = done.design.clone();
    best.deadline = design.deadline;
    if let Err(d) = karigami::build(best) {
        if d.kind == karigami::ErrorKind::TimeLimit {
            return Err(recipe.error(&d));
        }
        return Err(Error::new(
            d.kind,
            format!(
                "{}: the optimised design meets [optimise.require], but build refuses it: {}",
                recipe.file, d.message
            ),
        ));
    }
    if !v.quiet {
        errln!(
            "optimised {} in {:.1} s: {} variables, {} iterations or generations, {} designs grown; cost {:.6} -> {:.6}; every hard constraint met",
            recipe.file,
            started.elapsed().as_secs_f64(),
            done.variables,
            done.iterations,
            done.evaluations,
            done.cost_before,
            done.cost_after
        );
    }
    match out {
        Some(o) => o.write(done.text.as_bytes())?,
        None => out!("{}", done.text),
    }
    Ok(())
}
