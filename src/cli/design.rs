//! `karigami design TARGET --out RECIPE.toml` (docs/design.md, "Design your
//! own object"): the search of `karigami::designing` on the target, each
//! candidate then built by the whole pipeline, so that a design `build`
//! refuses is never written; of those that build, the one whose simulated
//! shape fits the target best.

use super::args::Verbosity;
use super::check::TargetFile;
use super::error::Error;
use super::files::OutFile;
use karigami::designing::{self, DesignAsk, Found};
use karigami::{ErrorKind, Overrides};
use std::path::Path;
use std::time::Instant;

/// What the command was asked.
pub(super) struct Ask<'a> {
    pub target: &'a Path,
    pub out: &'a Path,
    pub force: bool,
    pub edge: Option<f64>,
    /// `--thickness`: written into the recipe's `[material]` table.
    pub thickness: Option<f64>,
    /// `--keep-miss`: write a design that misses the goal, saying so.
    pub keep_miss: bool,
    pub overrides: Overrides,
    /// The fabrication flags as given, for the recipe's record.
    pub flags: Vec<String>,
    pub jobs: usize,
}

/// Candidates built (each a full build with its simulation) at most.
const BUILT: usize = 6;

/// The design chosen of those built: how far it is from the goal, the
/// design, the fit of its lattice as assembled (`Build::assembled`, what
/// `check` reports) and the fit of its simulated shape.
struct Chosen {
    miss: f64,
    /// Candidates tried with a build, this one among them.
    built: usize,
    found: Found,
    design: karigami::targets::Fit,
    sim: karigami::targets::Fit,
    /// On a bump: the share of its top the simulated cells cover...
    top: Option<f64>,
    /// ...and the design's, as `check` says them.
    design_top: Option<f64>,
}

impl Chosen {
    /// Each measure of the simulated shape that misses the goal, with its
    /// value and limit.
    fn misses(&self) -> String {
        let mut misses = designing::goal::misses(&self.sim);
        if let Some(top) = self.top.filter(|&t| t < designing::goal::TOP_COVERED) {
            misses.push(format!(
                "the bump's top {:.1} % covered, under {} %",
                100.0 * top,
                100.0 * designing::goal::TOP_COVERED
            ));
        }
        misses.join("; ")
    }

    /// The simulated shape's fit in one line, with the bump's top.
    fn sim_summary(&self) -> String {
        super::check::fit_line(&self.sim, self.top, "joints")
    }

    /// The design's fit in one line, with the bump's top.
    fn design_summary(&self) -> String {
        super::check::fit_line(&self.design, self.design_top, "vertices")
    }
}

pub(super) fn design(ask: &Ask<'_>, v: Verbosity) -> Result<(), Error> {
    let started = Instant::now();
    // A refusal before the work, not after minutes of designing.
    let out = OutFile::check_design(ask.out, ask.target, ask.force)?;
    for (flag, x) in [("--edge", ask.edge), ("--thickness", ask.thickness)] {
        if x.is_some_and(|e| !(e.is_finite() && e > 0.0)) {
            return Err(Error::usage(format!(
                "{flag} must be a positive length in mm"
            )));
        }
    }
    let file = TargetFile::read(ask.target)?;
    // The flags are checked as flags (their own messages), then written
    // as the recipe's tables, so that the recipe builds as designed with
    // no flags; the candidates are built from those tables.
    let stub = format!(
        "{}{}",
        designing::STUB,
        Overrides::default().as_tables(ask.thickness)
    );
    karigami::parse_with(&stub, "design", &ask.overrides)
        .map_err(|d| Error::at("the fabrication flags", "", &d))?;
    let tables = ask.overrides.as_tables(ask.thickness);
    let limits = Overrides {
        memory: ask.overrides.memory,
        deadline: ask.overrides.deadline,
        ..Overrides::default()
    };
    let base = karigami::parse_with(&format!("{}{tables}", designing::STUB), "design", &limits)
        .map_err(|d| Error::at("the fabrication flags", "", &d))?;
    let edge = ask.edge.unwrap_or_else(|| designing::default_edge(&base));
    let target = std::sync::Arc::new(file.target.canonical());
    let note = |s: &str| {
        if !v.quiet {
            errln!("design: {s}");
        }
    };
    note(&format!(
        "{}: {}, D {:.1} mm, cell edge {edge:.1} mm",
        file.file,
        file.target.topology.describe(),
        target.extent
    ));
    // A target refused for its shape is refused before its work is said.
    designing::admissible(&target, &base, edge).map_err(|d| Error::at(&file.file, "", &d))?;
    let build = within_time((&file, &target), edge, &ask.overrides.deadline, &note)?;
    // The search leaves one candidate's reckoned build (at most half the
    // limit) for the builds: a search cut short still has its best built.
    let limit = ask.overrides.deadline.ceiling();
    let mut searching = base.clone();
    searching.deadline = ask.overrides.deadline.less(build.min(0.5 * limit));
    let search = DesignAsk {
        target: target.clone(),
        base: &searching,
        edge,
        deadline: searching.deadline.at(),
        jobs: karigami::Jobs::new(ask.jobs),
        polish: designing::POLISH_WORK,
    };
    let searched =
        designing::search(&search, &mut |s| note(s)).map_err(|d| Error::at(&file.file, "", &d))?;
    let name = ask
        .out
        .file_stem()
        .map_or("design".into(), |s| s.to_string_lossy().into_owned());
    // Fitted to the target as read, as `check` fits the recipe: the same
    // numbers (the fit's starts depend on the frame to a few hundredths
    // of a mm).
    // A search cut short by its share of the limit that found none is out
    // of time, as is a run the limit stops before a candidate is built.
    let stopped = || out_of_time(&file, &searched, &ask.overrides.deadline);
    if searched.found.is_empty() && searching.deadline.expired() {
        return Err(stopped());
    }
    let chosen = match choose(
        ask,
        &searched,
        (&name, &tables, &limits),
        (&file.target, edge),
        &note,
    ) {
        Ok(chosen) => chosen,
        Err(Unbuilt::Refused(why)) => return Err(no_design(&file, &searched, &why)),
        Err(Unbuilt::OutOfTime) => return Err(stopped()),
    };
    // Loops round a bump: the edge or the sheet's shape that would reach
    // the goal's coverage; round a long oval rim, a rounder or shallower
    // cap.
    let remedy = (chosen.miss > 1.0).then(|| {
        searched
            .bump
            .as_ref()
            .and_then(|b| {
                // The top's and the oval's hints speak of a loop's rings;
                // a sheet's miss is left to the coverage's and the goal's.
                let top = chosen.top.filter(|_| chosen.found.is_loop()).unwrap_or(1.0);
                b.remedy(&chosen.sim, top, (edge, designing::least_edge(&base)))
            })
            .or_else(|| {
                searched
                    .oval
                    .filter(|_| chosen.found.is_loop())
                    .and_then(|o| o.remedy())
            })
            .unwrap_or_else(|| {
                designing::goal::remedy(
                    &chosen.design,
                    &chosen.sim,
                    (edge, designing::goal::boundary_band(&file.target, edge)),
                    &base,
                )
            })
    });
    if let (Some(remedy), false) = (&remedy, ask.keep_miss) {
        return Err(missed(&file, &chosen, remedy));
    }
    let seconds = started.elapsed().as_secs_f64();
    let made = Made {
        ask,
        file: &file,
        searched: &searched,
        edge,
    };
    let notes = made.notes(&chosen, remedy.as_deref());
    let record = karigami::targets::recorded_path(ask.target, ask.out);
    let text = designing::recipe(
        &chosen.found,
        &name,
        &notes,
        Some((&record, file.hash)),
        &tables,
    );
    out.write(text.as_bytes())?;
    note(&format!(
        "wrote {} in {seconds:.1} s: {} cells; simulated {}{}",
        ask.out.display(),
        chosen.found.cells,
        chosen.sim_summary(),
        if remedy.is_some() {
            "; it MISSES the goal (--keep-miss)"
        } else {
            ""
        }
    ));
    Ok(())
}

/// Build the best candidates with the whole pipeline, in the search's
/// order (the fabrication settings in `tables`, only the run's `limits`
/// from the command line), and choose: the first whose simulated shape meets the goal,
/// else the one nearest it; `Err` with why each was refused when none
/// builds. A candidate that misses because its simulated shape flattens
/// is built again held at its feet (`designing::with_feet`), and kept so
/// when that comes nearer. Deterministic: the candidates come in a fixed
/// order.
fn choose(
    ask: &Ask<'_>,
    searched: &designing::Searched,
    (name, tables, limits): (&str, &str, &Overrides),
    (target, edge): (&karigami::targets::Target, f64),
    note: &dyn Fn(&str),
) -> Result<Chosen, Unbuilt> {
    let deadline = ask.overrides.deadline;
    let mut refusals = Vec::new();
    let mut best: Option<Chosen> = None;
    let mut built = 0;
    for found in searched.found.iter().take(BUILT) {
        if deadline.expired() {
            match best {
                Some(_) => break,
                None => return Err(Unbuilt::OutOfTime),
            }
        }
        let text = designing::recipe(found, name, &[], None, tables);
        built += 1;
        match built_fit(&text, name, limits, target) {
            Ok(free) => {
                let build = |text: &str| built_fit(text, name, limits, target);
                let (found, got) = match on_feet(found, &free, edge, (name, tables), &build, note) {
                    Some(pinned) => pinned,
                    None => (found.clone(), free),
                };
                let facets = got.lattice.facets();
                let (miss, top) = searched.judge(target, &got.fit, (&got.simulated, &facets));
                let design_top = searched.bump.as_ref().map(|b| {
                    let points: Vec<glam::DVec3> =
                        got.assembled.vertices.iter().map(|v| v.pos).collect();
                    b.top_covered(target, &got.design, (&points, &got.assembled.facets()))
                });
                let (found, design, sim) = (&found, got.design, got.fit);
                let chosen = Chosen {
                    miss,
                    built: 0,
                    found: found.clone(),
                    design,
                    sim,
                    top,
                    design_top,
                };
                note(&format!(
                    "built {} cells: simulated {}",
                    found.cells,
                    chosen.sim_summary()
                ));
                if best.as_ref().is_none_or(|b| miss < b.miss) {
                    best = Some(chosen);
                }
                if miss <= 1.0 {
                    break;
                }
            }
            // A build stopped by the limit is not a refusal of the design.
            Err(_) if deadline.expired() && best.is_none() => return Err(Unbuilt::OutOfTime),
            Err(why) => {
                note(&format!("{} cells: build refuses it: {why}", found.cells));
                refusals.push(why);
            }
        }
    }
    best.map(|b| Chosen { built, ..b })
        .ok_or(Unbuilt::Refused(refusals))
}

/// Why no design was chosen: every candidate built was refused (why each
/// was), or the time limit passed before one built.
enum Unbuilt {
    Refused(Vec<String>),
    OutOfTime,
}

/// The time limit passed before a candidate was built, or the search's
/// share of it before it found one: how far the search got, as a
/// `TimeLimit` stop (exit 4) that writes nothing.
fn out_of_time(
    file: &TargetFile,
    searched: &designing::Searched,
    whole: &karigami::Deadline,
) -> Error {
    let limit = whole.limit().unwrap_or(0.0);
    let passed = if whole.expired() {
        format!("the time limit of {limit} s has passed")
    } else {
        format!(
            "the search's share of the time limit of {limit} s has passed (the rest was kept for building candidates)"
        )
    };
    let built = if searched.found.is_empty() {
        ""
    } else {
        ", before one was built"
    };
    Error::new(
        ErrorKind::TimeLimit,
        format!(
            "{}: stopped after {} and {} found{built}, {:.1} s in: {passed}; nothing was written (allow more time with --time-limit SECONDS, or give a larger --edge; docs/commands.md, Time limits)",
            file.file,
            karigami::util::plural(searched.tried, "seed search"),
            karigami::util::plural(searched.found.len(), "design"),
            whole.elapsed(),
        ),
    )
}

/// A candidate whose free simulated shape misses the goal because it
/// flattens (`designing::flattens`), built again held at its feet: that
/// design and its build when it comes nearer the goal.
fn on_feet(
    found: &Found,
    free: &Built,
    edge: f64,
    (name, tables): (&str, &str),
    build: &dyn Fn(&str) -> Result<Built, String>,
    note: &dyn Fn(&str),
) -> Option<(Found, Built)> {
    let designed: Vec<glam::DVec3> = free.lattice.vertices.iter().map(|v| v.pos).collect();
    if designing::miss(&free.fit) <= 1.0 || !designing::flattens(&designed, &free.simulated) {
        return None;
    }
    let pinned = designing::with_feet(found, &free.lattice, edge)?;
    note(&format!(
        "{} cells: the free sheet flattens (simulated {}); built again held at its feet",
        found.cells,
        free.fit.summary("joints")
    ));
    match build(&designing::recipe(&pinned, name, &[], None, tables)) {
        Ok(p) if designing::miss(&p.fit) < designing::miss(&free.fit) => Some((pinned, p)),
        Ok(p) => {
            note(&format!(
                "held at its feet it comes no nearer: simulated {}",
                p.fit.summary("joints")
            ));
            None
        }
        Err(why) => {
            note(&format!("held at its feet, build refuses it: {why}"));
            None
        }
    }
}

/// No candidate builds: why each was refused.
fn no_design(file: &TargetFile, searched: &designing::Searched, refusals: &[String]) -> Error {
    Error::new(
        ErrorKind::TargetTopology,
        format!(
            "{}: no design found that builds ({} seeds grown{}{})",
            file.file,
            searched.tried,
            if refusals.is_empty() {
                ""
            } else {
                "; build refused: "
            },
            refusals.join("; ")
        ),
    )
}

/// The refusal of a best design that misses the goal: each measure missed
/// with its value and limit, what to try, and `--keep-miss`.
fn missed(file: &TargetFile, chosen: &Chosen, remedy: &str) -> Error {
    let d = karigami::Diagnostic {
        kind: ErrorKind::GoalMissed,
        message: format!(
            "the best design found, {} cells, misses the goal in its simulated shape (docs/design.md, \"The goal\"): {}",
            chosen.found.cells,
            chosen.misses()
        ),
        span: None,
        site: None,
        hint: Some(format!(
            "{remedy}; or give --keep-miss to write it anyway, the miss stated at the top of the recipe"
        )),
    };
    Error::at(&file.file, "", &d)
}

/// How a recipe was made, for its opening comment (docs/design.md,
/// "Design your own object").
struct Made<'a> {
    ask: &'a Ask<'a>,
    file: &'a TargetFile,
    searched: &'a designing::Searched,
    edge: f64,
}

impl Made<'_> {
    /// The options that shaped the result, as a command line gives them.
    fn options(&self) -> Vec<String> {
        let mut options = Vec::new();
        if let Some(e) = self.ask.edge {
            options.push(format!("--edge {e}"));
        }
        if let Some(t) = self.ask.thickness {
            options.push(format!("--thickness {t}"));
        }
        options.extend(self.ask.flags.iter().cloned());
        options
    }

    fn notes(&self, chosen: &Chosen, remedy: Option<&str>) -> Vec<String> {
        let (t, file) = (&self.file.target, &self.file.file);
        let options = self.options();
        let mut notes = Vec::new();
        if let Some(remedy) = remedy {
            notes.push(format!(
                "MISSES THE GOAL (docs/design.md, \"The goal\": {}): {}. Written only because --keep-miss was given; {remedy}.",
                designing::goal::WORDS,
                chosen.misses()
            ));
        }
        notes.extend([
            format!(
                "Designed by `karigami design {file}{}{}` (docs/design.md, \"Design your own object\").",
                if options.is_empty() { "" } else { " " },
                options.join(" ")
            ),
            format!(
                "Target: {file} (recorded in [target] below with its content hash): {}, {}; D {:.1} mm.",
                t.what,
                t.topology.describe(),
                t.extent
            ),
            self.settings(),
            format!("Topology: {}.", self.searched.topology),
            format!(
                "Found by: {} seeds grown on the target; of the best, {} built and simulated, this one kept.",
                self.searched.tried,
                chosen.built
            ),
            format!("Seed: {}.", chosen.found.seed),
            format!("Fit of the design: {}.", chosen.design_summary()),
            format!("Fit of the simulated shape: {}.", chosen.sim_summary()),
        ]);
        if remedy.is_none() {
            let top = if chosen.top.is_some() {
                format!(
                    "; on a bump, >= {} % of its top covered",
                    100.0 * designing::goal::TOP_COVERED
                )
            } else {
                String::new()
            };
            notes.push(format!(
                "The simulated shape meets the goal (docs/design.md, \"The goal\": {}{top}).",
                designing::goal::WORDS
            ));
        }
        notes
    }

    /// The cell edge and what it came from; the fabrication flags, which
    /// the recipe's tables carry (`Overrides::as_tables`).
    fn settings(&self) -> String {
        let edge = match self.ask.edge {
            Some(_) => "--edge".to_string(),
            None => {
                "the default: six strip widths, at least four of the eyelets' shortest leg".into()
            }
        };
        // The run's limits are not the recipe's: they are not carried.
        let (limits, carried): (Vec<&String>, Vec<&String>) = self
            .ask
            .flags
            .iter()
            .partition(|f| f.starts_with("--memory ") || f.starts_with("--time-limit "));
        let mut flags = String::new();
        if !carried.is_empty() {
            let carried: Vec<&str> = carried.iter().map(|f| f.as_str()).collect();
            flags.push_str(&format!(
                "; designed with {}, which the tables below carry",
                carried.join(" ")
            ));
        }
        if !limits.is_empty() {
            let limits: Vec<&str> = limits.iter().map(|f| f.as_str()).collect();
            flags.push_str(&format!(
                "; run with {} (a run's limits, not the recipe's)",
                limits.join(" ")
            ));
        }
        format!("Cell edge: {:.1} mm ({edge}){flags}.", self.edge)
    }
}

/// Seconds the search is reckoned at for each cell a design may have, a
/// seed (`karigami::designing`'s eight seeds of a sheet, the loop's ring
/// steps fewer and cheaper), and a candidate's build for each cell (its
/// simulation and deployment path most of it): release build on the
/// 2-core machine of BENCHMARKS.md, "Bounded work", from the targets of
/// fixtures/targets/ (the saddle's eight seeds in 17.8 s of CPU, the
/// sphere cap's two builds of 216 and 168 cells in 35.2 s).
const SEARCH_SECONDS_PER_CELL: f64 = 0.015;
const BUILD_SECONDS_PER_CELL: f64 = 0.09;

/// Seeds a search grows at most, and candidates reckoned built (of
/// `BUILT`: the search stops at the first that meets the goal).
const SEEDS: f64 = 8.0;
const BUILDS: f64 = 1.0;

/// The design's work reckoned from the target before it starts
/// (docs/commands.md, "Time limits"): the cells a design of `edge` may
/// have (the target's area in squares of `edge`, times the cells a square
/// its topology grows, `designing::cells_per_square`), times the seeds'
/// row search and the candidate builds, and a waved band's polish
/// (`designing::POLISH_SECONDS_PER_CELL`); refused when the search and
/// builds alone pass the limit (a polish is left out then), with the edge
/// that fits; else said to `note` when long (`Estimate::said`), and a
/// candidate's build reckoned (seconds).
fn within_time(
    (file, target): (&TargetFile, &std::sync::Arc<karigami::targets::Target>),
    edge: f64,
    deadline: &karigami::Deadline,
    note: &dyn Fn(&str),
) -> Result<f64, Error> {
    let per_square = designing::cells_per_square(target);
    let cells = (per_square * file.target.area / (edge * edge))
        .ceil()
        .max(1.0);
    let search = karigami::util::reckoned_low(SEEDS * SEARCH_SECONDS_PER_CELL * cells);
    let builds = karigami::util::reckoned_low(BUILDS * BUILD_SECONDS_PER_CELL * cells);
    let polish = if designing::polishes(target) {
        designing::POLISH_SECONDS_PER_CELL * designing::POLISH_WORK as f64
    } else {
        0.0
    };
    let seconds = search + polish + builds;
    let polishing = if polish > 0.0 {
        format!(
            ", a polish of the rings, ~{} (none when the limit leaves less)",
            karigami::duration(polish)
        )
    } else {
        String::new()
    };
    let estimate = karigami::Estimate {
        seconds,
        what: format!(
            "row search of up to {SEEDS} seeds, ~{}{polishing}, then {BUILDS} to {BUILT} candidate builds of ~{} cells, ~{} each",
            karigami::duration(search),
            karigami::count(cells),
            karigami::duration(builds / BUILDS)
        ),
    };
    // A polish is left out when the limit leaves it too little time:
    // only the rest must fit it.
    if deadline.allows(search + builds) {
        if let Some(line) = estimate.said(deadline) {
            note(&line);
        }
        return Ok(builds / BUILDS);
    }
    // The work goes as the cells, as 1 / edge^2; the search grows three
    // cells across the target at least.
    let fits = edge * ((search + builds) / deadline.ceiling()).sqrt();
    let larger = if fits <= file.target.extent / 3.0 {
        format!(
            "give a larger --edge, {:.1} mm or more (fewer, larger cells), or ",
            (fits * 10.0).ceil() / 10.0
        )
    } else {
        String::new()
    };
    let d = karigami::Diagnostic {
        kind: ErrorKind::WorkTooLong,
        message: format!(
            "designing for this target at a cell edge of {edge:.1} mm may take about {} ({}), longer than the {} allowed",
            karigami::duration(seconds),
            estimate.what,
            karigami::duration(deadline.ceiling())
        ),
        span: None,
        site: None,
        hint: Some(format!(
            "{larger}allow more time with --time-limit SECONDS (docs/commands.md, Time limits)"
        )),
    };
    Err(Error::at(&file.file, "", &d))
}

/// A candidate built: the fit to the target of its lattice as assembled
/// and of its simulated joints, its lattice as grown, and its vertices as
/// simulated.
struct Built {
    design: karigami::targets::Fit,
    fit: karigami::targets::Fit,
    lattice: karigami::Lattice,
    /// The lattice as assembled, which `design` fits.
    assembled: karigami::Lattice,
    simulated: Vec<glam::DVec3>,
}

/// Build a candidate recipe with the whole pipeline and fit to the target
/// its lattice as assembled (rows grown on rebuilt fronts placed onto the
/// rows they hang from) and its simulated joints; why the build refuses
/// it otherwise. The search's own fit is of the lattice as grown, which
/// that placing moves (a 70-cell vault: rms 1.02 % of D grown, 0.70 %
/// assembled), so the recipe says the assembled one, as `check` does.
fn built_fit(
    text: &str,
    name: &str,
    overrides: &Overrides,
    target: &karigami::targets::Target,
) -> Result<Built, String> {
    let design = karigami::parse_with(text, name, overrides).map_err(|d| d.message.clone())?;
    let built = karigami::build(design).map_err(|d| d.message.clone())?;
    let scene = karigami::viewer_scene(&built);
    let n = built.lattice.vertices.len();
    let points = scene
        .simulated
        .as_ref()
        .map(|p| p[..n.min(p.len())].to_vec())
        .ok_or("the build has no simulated shape")?;
    let mut simulated = built.lattice.clone();
    for (v, p) in simulated.vertices.iter_mut().zip(&points) {
        v.pos = *p;
    }
    Ok(Built {
        design: designing::fit_of(target, &built.assembled),
        fit: designing::fit_of(target, &simulated),
        lattice: built.lattice,
        assembled: built.assembled,
        simulated: points,
    })
}
