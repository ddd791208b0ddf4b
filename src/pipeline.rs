//! The whole pipeline for one design, pure: design -> lattice -> parts ->
//! layout -> pages. `output` turns the result into file bytes; the CLI
//! only writes what that returns.

use crate::assembly::{Step, steps};
use crate::budget::Estimate;
use crate::design::Design;
use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::drawing::{Meta, Page, sheet_page};
use crate::jobs::Jobs;
use crate::lattice::deploy::{Deployment, deployment};
use crate::lattice::{Joint, Kind, Lattice, Report, joints, verify};
use crate::layout::{Bounds, Job, Layout, SheetOption, pick, sheet_options};
use crate::measure::{
    Measures, measure_assembled, measure_with, simulated_clashes, strip_clashes, whole,
};
use crate::parts::{Outline, Parts, PartsError, parts};
use std::borrow::Cow;
use std::cell::OnceCell;

mod reuse;
pub(crate) use reuse::state as simulation_state;
pub use reuse::{SOURCES as SIMULATION_SOURCES, STATE_FILE};

/// Everything one design makes before any file bytes: the grown and verified
/// lattice, its strips, their layout on sheets and the cut-sheet pages.
pub struct Build {
    /// The validated recipe it was built from.
    pub design: Design,
    /// The lattice as grown.
    pub lattice: Lattice,
    /// The lattice as assembled, for pictures: rows grown on rebuilt fronts
    /// placed onto the rows they hang from (`Lattice::placed`).
    pub assembled: Lattice,
    /// Verification of the grown lattice (docs/math.md 8).
    pub report: Report,
    /// Its shape, fit and clash measures, measured once for the clash
    /// refusal and the reports.
    pub measures: Measures,
    /// The vertex joints (`lattice::joints`), computed once for the parts and lattice.json.
    pub(crate) joints: Vec<Joint>,
    /// The assembly steps in growth order (`assembly::steps`), computed once
    /// for the guide, the viewer and the report.
    pub steps: Vec<Step>,
    /// How it deploys (docs/math.md 8.4), for the reports.
    pub deployment: Deployment,
    /// The strips and eyelets.
    pub parts: Parts,
    /// The strips nested on sheets.
    pub layout: Layout,
    /// One page per sheet.
    pub pages: Vec<Page>,
    /// What was nested: outline lengths and width, test piece, steps.
    pub(crate) job: Job,
    /// The smallest sheet preset that holds the job (sheet advice); None
    /// when no preset does.
    pub(crate) advice: Option<SheetOption>,
    /// The simulated deployed shape (docs/physics.md), for lattices that
    /// are not planar true mechanisms (`sim::wanted`).
    pub(crate) simulation: Option<crate::sim::Simulation>,
    /// The fingerprint of everything the simulation read (`reuse`), and
    /// whether it was restored from an earlier build instead of solved.
    pub(crate) simulation_key: Option<(u64, bool)>,
    /// The deployment path of the simulated structure (`sim::path`): from
    /// its equilibrium down to nearly collapsed and back.
    pub(crate) path: Option<crate::sim::path::Path>,
}

/// Grow, verify, make the parts and nest them. A design that fails
/// verification or a fabrication check is refused with a located error.
pub fn build(design: Design) -> Result<Build, Diagnostic> {
    build_with(design, &mut |_| {})
}

/// `build`, telling `progress` about each fitted row (long fits).
pub fn build_with(design: Design, progress: &mut dyn FnMut(&str)) -> Result<Build, Diagnostic> {
    check(design, progress)?.assemble()
}

/// `build_with` up to the simulation (`Unsimulated::simulate`), which
/// takes most of a bent lattice's build: a batch runs its recipes'
/// simulations, the longest chains of its work, before drawing any files.
pub fn build_unsimulated(
    design: Design,
    progress: &mut dyn FnMut(&str),
) -> Result<Unsimulated, Diagnostic> {
    assemble(check(design, progress)?)
}

/// A build whose deployed shape is still to be simulated: every field of
/// its `Build` is made except the simulation's.
pub struct Unsimulated(Build);

impl Unsimulated {
    /// Whether `simulate` solves an equilibrium (or restores one).
    pub fn simulates(&self) -> bool {
        crate::sim::wanted(&self.0.lattice, &self.0.deployment)
    }

    /// The build so far: every field but the simulation's, which is None
    /// (as for a planar mechanism), for what reads only the lattice, the
    /// parts, the layout and the pages.
    pub fn build(&self) -> &Build {
        &self.0
    }

    /// The lattice's cells.
    pub fn cells(&self) -> usize {
        self.0.lattice.cells.len()
    }

    /// Its simulation as reckoned before it runs, when it simulates (and
    /// fits its memory: else it is refused, not run): to say long work up
    /// front (`simulation_estimate`).
    pub fn estimate(&self) -> Option<Estimate> {
        let settings = &self.0.design.simulation;
        let runs = self.simulates() && crate::sim::within_memory(&self.0.lattice, settings).is_ok();
        runs.then(|| simulation_estimate(&self.0.lattice, settings))
    }

    /// The build with its simulated deployed shape, restored from the
    /// `STATE_FILE` of an earlier build (`previous`) when nothing it
    /// depends on changed. Strips strained beyond the allowable are an
    /// error unless the recipe accepts them (`simulated`).
    pub fn simulate(self, previous: Option<&[u8]>) -> Result<Build, Diagnostic> {
        self.simulate_then(previous, true)
    }

    /// `simulate`, following the deployment path (`sim::path`) when
    /// `follow`. `check` follows it too: the state a build reports is the
    /// one deploying ends in (docs/physics.md, "The chosen equilibrium").
    fn simulate_then(self, previous: Option<&[u8]>, follow: bool) -> Result<Build, Diagnostic> {
        let mut b = self.0;
        let (simulation, path, simulation_key) = simulated(
            &b.design,
            &b.lattice,
            &crate::sim::Derived {
                placed: &b.assembled,
                joints: &b.joints,
            },
            &b.deployment,
            (previous, follow),
            &mut b.parts.warnings,
        )?;
        b.path = path;
        in_time(&b.design, "after the simulation")?;
        b.simulation = simulation;
        b.simulation_key = simulation_key;
        Ok(b)
    }
}

/// The simulation of `lattice` under `settings` as reckoned before it runs
/// (`sim::reckoned`, which refuses it beyond the limit): its seconds and
/// what they count, for the line long work says up front (docs/commands.md,
/// "Time limits").
pub fn simulation_estimate(lattice: &Lattice, settings: &crate::sim::Settings) -> Estimate {
    let (cost, work, seconds) = crate::sim::reckoned(lattice, settings);
    Estimate {
        seconds,
        what: format!(
            "simulation: {} rod nodes x ~{:.0} Newton iterations, the deployment path's {} steps each way included",
            crate::budget::count(cost.nodes),
            work.iterations,
            work.path_steps
        ),
    }
}

/// A `TimeLimit` error when the design's deadline has passed (checked
/// between the stages of a build: growth, the simulation, the deployment
/// path), saying where the run stopped.
pub(crate) fn in_time(design: &Design, at: &str) -> Result<(), Diagnostic> {
    if !design.deadline.expired() {
        return Ok(());
    }
    Err(Diagnostic::new(
        ErrorKind::TimeLimit,
        format!(
            "stopped {at}, {:.1} s in: the time limit of {} s has passed",
            design.deadline.elapsed(),
            design.deadline.limit().unwrap_or(0.0)
        ),
    )
    .hint("nothing was written; allow more time with --time-limit SECONDS (docs/commands.md, Time limits)"))
}

/// The first stage of every build, and all of `karigami check`: a design
/// grown, its lattice verified and its deployment worked out. `check`
/// reports on it whether or not it passed; `assemble` makes the parts,
/// layout and pages of one that did.
///
/// What the reports and `assemble` both need (the placement, the measures,
/// the joints and parts) is derived on first use, once, and carried into
/// the `Build`: `karigami check -q` of a 4 M-cell lattice measures nothing
/// it does not show.
pub struct Checked {
    /// The validated recipe it was grown from.
    pub design: Design,
    /// The lattice as grown.
    pub lattice: Lattice,
    /// Verification of the grown lattice (docs/math.md 8); it may have failed.
    pub report: Report,
    /// How it deploys (docs/math.md 8.4).
    pub deployment: Deployment,
    /// `Lattice::placed`, None when that is the grown lattice (extrinsic).
    placed: OnceCell<Option<Lattice>>,
    measures: OnceCell<Measures>,
    joints: OnceCell<Vec<Joint>>,
    parts: OnceCell<Result<Parts, PartsError>>,
}

/// What the check reports read, borrowed from a `Checked` or a `Build` with
/// everything derived already: the report writers receive the measures and
/// the parts, and never measure or make parts themselves.
pub struct Verified<'a> {
    /// The validated recipe.
    pub design: &'a Design,
    /// The lattice as grown.
    pub lattice: &'a Lattice,
    /// The lattice as assembled (`Lattice::placed`).
    pub assembled: &'a Lattice,
    /// Verification of the grown lattice.
    pub report: &'a Report,
    /// How it deploys.
    pub deployment: &'a Deployment,
    /// Shape, fit and clash measures (`measure`).
    pub measures: &'a Measures,
    /// The strips, when the lattice is small enough to make them and they
    /// could be made.
    pub parts: Option<&'a Parts>,
}

/// Grow `design` (telling `progress` about each fitted row), verify the
/// lattice and work out its deployment. Only growth can fail here; a
/// failed verification is in the report.
pub fn check(design: Design, progress: &mut dyn FnMut(&str)) -> Result<Checked, Diagnostic> {
    check_on(design, progress, false, Jobs::ONE)
}

/// Lattices with fewer cells are checked on one thread: their whole
/// check takes milliseconds, so a second thread has little to save.
const PARALLEL_FROM_CELLS: usize = 10_000;

/// `check`, measuring at once when `measure` (a report that shows the
/// measures: `karigami check` without `-q`), on `jobs` threads. After
/// growth, the work falls into two independent halves of about equal cost
/// on large lattices: the deployment (C(theta) with the misfits) with the
/// shape, and the placement, the clash search, verification and the
/// lattice's extent. They may run in parallel (`Jobs::join`); every result
/// is the same computation either way, so the reports are byte-identical
/// for any number of jobs.
pub fn check_on(
    design: Design,
    progress: &mut dyn FnMut(&str),
    measure: bool,
    jobs: Jobs,
) -> Result<Checked, Diagnostic> {
    let lattice = design.grow_with(progress)?;
    in_time(&design, "after growing the lattice")?;
    let jobs = if lattice.cells.len() >= PARALLEL_FROM_CELLS {
        jobs
    } else {
        Jobs::ONE
    };
    let (report, deployment, measured) = if measure {
        let ((deployment, shape), (placed, clashes, report, whole)) = jobs.join(
            |_| (deployment(&lattice), lattice.shape()),
            |_| {
                let placed = place(&lattice);
                let assembled = placed.as_ref().unwrap_or(&lattice);
                let clashes = strip_clashes(&design, assembled);
                let whole = whole(&lattice, assembled);
                (placed, clashes, verify(&lattice), whole)
            },
        );
        let measures = measure_with(&design, &lattice, shape, clashes, whole);
        (report, deployment, Some((placed, measures)))
    } else {
        let (report, deployment) = jobs.join(|_| verify(&lattice), |_| deployment(&lattice));
        (report, deployment, None)
    };
    let (placed, measures) = match measured {
        Some((placed, measures)) => (OnceCell::from(placed), OnceCell::from(measures)),
        None => (OnceCell::new(), OnceCell::new()),
    };
    Ok(Checked {
        design,
        lattice,
        report,
        deployment,
        placed,
        measures,
        joints: OnceCell::new(),
        parts: OnceCell::new(),
    })
}

/// `Lattice::placed`, None when that is the grown lattice (extrinsic).
fn place(lattice: &Lattice) -> Option<Lattice> {
    match lattice.placed() {
        Cow::Owned(placed) => Some(placed),
        Cow::Borrowed(_) => None,
    }
}

/// The measures of `lattice`, as assembled `assembled` (`place`): the one
/// place the pipeline measures, lazily or at once (`check_on`).
fn measured(design: &Design, lattice: &Lattice, assembled: &Lattice) -> Measures {
    measure_assembled(design, lattice, assembled)
}

impl Checked {
    /// Why karigami makes no cut files for this lattice, if it does not
    /// (`too_large_to_fabricate`).
    pub fn too_large_to_fabricate(&self) -> Option<Diagnostic> {
        too_large_to_fabricate(&self.design, &self.lattice)
    }

    /// The lattice as assembled: rows grown on rebuilt fronts placed onto
    /// the rows they hang from (`Lattice::placed`), placed once.
    pub fn assembled(&self) -> &Lattice {
        self.placed
            .get_or_init(|| place(&self.lattice))
            .as_ref()
            .unwrap_or(&self.lattice)
    }

    /// The shape, fit and clash measures, measured once.
    pub fn measures(&self) -> &Measures {
        self.measures
            .get_or_init(|| measured(&self.design, &self.lattice, self.assembled()))
    }

    /// The vertex joints, found once.
    fn joints(&self) -> &[Joint] {
        self.joints.get_or_init(|| joints(&self.lattice))
    }

    /// The strips and eyelets, made once (a lattice too large to fabricate
    /// has none: callers check `too_large_to_fabricate` first).
    fn parts(&self) -> &Result<Parts, PartsError> {
        self.parts
            .get_or_init(|| parts(&self.lattice, self.joints(), &self.design.fabrication))
    }

    /// The check reports' view, deriving what it needs on first use.
    pub fn verified(&self) -> Verified<'_> {
        let small = self.lattice.cells.len() <= MAX_FABRICATED_CELLS;
        Verified {
            design: &self.design,
            lattice: &self.lattice,
            assembled: self.assembled(),
            report: &self.report,
            deployment: &self.deployment,
            measures: self.measures(),
            parts: small.then(|| self.parts().as_ref().ok()).flatten(),
        }
    }

    /// The parts, layout and pages. A lattice too large to fabricate, or
    /// one that failed verification or a fabrication check, is refused
    /// with a located error.
    pub fn assemble(self) -> Result<Build, Diagnostic> {
        assemble(self)?.simulate(None)
    }

    /// The simulation `assemble_for_check` runs, as reckoned before it
    /// starts; None when it simulates nothing (`Unsimulated::estimate`).
    pub fn estimate(&self) -> Option<Estimate> {
        let settings = &self.design.simulation;
        let simulates = self.too_large_to_fabricate().is_none()
            && crate::sim::wanted(&self.lattice, &self.deployment)
            && crate::sim::within_memory(&self.lattice, settings).is_ok();
        simulates.then(|| simulation_estimate(&self.lattice, settings))
    }

    /// Whether `previous`, an earlier build's `STATE_FILE`, holds this
    /// lattice's simulation whole, so that `assemble_for_check` restores it
    /// rather than solving: long work is said only when it will run.
    pub fn restores(&self, previous: &[u8]) -> bool {
        let m = &self.design.fabrication.material;
        let derived = crate::sim::Derived {
            placed: self.assembled(),
            joints: self.joints(),
        };
        let key = reuse::fingerprint(
            &self.lattice,
            &derived,
            m.width,
            m.thickness,
            &self.design.simulation,
        );
        reuse::written_for(previous, key)
    }

    /// `assemble` for `karigami check`: everything its reports show, the
    /// simulated shape and its clash refusal included. The deployment path
    /// is followed as in a build, since its end is the state reported.
    /// The simulation is restored from an earlier build's `STATE_FILE`
    /// (`previous`) when nothing it depends on changed, as a rebuild
    /// restores it (`Unsimulated::simulate`).
    pub fn assemble_for_check(self, previous: Option<&[u8]>) -> Result<Build, Diagnostic> {
        assemble(self)?.simulate_then(previous, true)
    }
}

/// The most cells karigami makes parts for (two strips a cell). Growth and
/// verification go to `MAX_CELLS`. A build costs about 0.2 ms of CPU,
/// 13 KiB of memory and 2.4 KB of files a cell (BENCHMARKS.md, measured
/// 2026-11-30): 20,000 cells build in about 4.5 s of CPU and 260 MiB,
/// with a 200-step guide; more would pass 5 s and make a guide too long to
/// print.
pub const MAX_FABRICATED_CELLS: usize = 20_000;

/// The cells growing `design` makes, read off the recipe without growing
/// it (a batch bounds the cells of the builds it holds in memory at once).
pub fn build_cells(design: &Design) -> usize {
    let rows = design.fit.as_ref().map_or(design.rows.len(), |f| f.rows);
    match design.kind {
        Kind::Helix => design.helix_cells,
        Kind::Sheet => rows.saturating_mul(design.points.len().saturating_sub(1)),
        Kind::Loop => rows.saturating_mul(design.points.len()),
    }
}

/// A guess of what `build` of a design costs, read off the recipe without
/// growing it, for ordering a batch's work: its cells, times 50 where the
/// build solves an elastic equilibrium over Newton iterations (a lattice
/// that leaves the plane or grows on rebuilt fronts, up to
/// `sim::MAX_SIMULATED_CELLS`; a plane lattice's strips are solved in one).
pub fn build_cost(design: &Design) -> usize {
    let cells = build_cells(design);
    let bent = design.dim == 3 || design.rows.iter().any(|r| r.front.is_some());
    let simulated = bent && cells <= crate::sim::MAX_SIMULATED_CELLS;
    cells.saturating_mul(if simulated { 50 } else { 1 })
}

/// The assembly guide has a page or more for every growth step, and each
/// step page places about 2 sqrt(steps) shared row drawings: at most this
/// many steps (a 2 x 2,000 sheet's guide is 2,000+ pages).
pub(crate) const MAX_GUIDE_STEPS: usize = 2_000;

/// Why karigami makes no cut files for a lattice this size (None when it
/// does): more than `MAX_FABRICATED_CELLS` cells, or a guide of more than
/// `MAX_GUIDE_STEPS` steps. `karigami check` still verifies it.
fn too_large_to_fabricate(design: &Design, lattice: &Lattice) -> Option<Diagnostic> {
    let cells = lattice.cells.len();
    let (message, hint) = if cells > MAX_FABRICATED_CELLS {
        (
            format!(
                "the lattice has {cells} cells; karigami makes cut files for at most {MAX_FABRICATED_CELLS} cells"
            ),
            "grow fewer rows or a narrower seed; `karigami check` verifies the geometry of lattices up to 4,000,000 cells",
        )
    } else if lattice.steps() > MAX_GUIDE_STEPS {
        (
            format!(
                "the assembly guide would have {} steps, a page or more each; karigami makes guides of at most {MAX_GUIDE_STEPS} steps",
                lattice.steps()
            ),
            "grow fewer rows (a long, narrow lattice has a step for every row); `karigami check` still verifies it",
        )
    } else {
        return None;
    };
    Some(
        Diagnostic::new(ErrorKind::TooLarge, message)
            .at(design.size_span())
            .hint(hint),
    )
}

/// The parts, layout and pages of a grown and verified lattice
/// (`Checked::assemble`), from what the check derived already; the
/// simulation is left to `Unsimulated::simulate`.
fn assemble(checked: Checked) -> Result<Unsimulated, Diagnostic> {
    if let Some(e) = checked.too_large_to_fabricate() {
        return Err(e);
    }
    let report = &checked.report;
    if !report.passed() {
        let worst = report
            .checks
            .iter()
            .filter(|c| !c.passed())
            .max_by(|a, b| a.max.total_cmp(&b.max))
            .expect("a failed check");
        return Err(Diagnostic::new(
            ErrorKind::VerificationFailed,
            format!(
                "{} is {:.2e}, above the tolerance",
                worst.invariant.describe(),
                worst.max
            ),
        )
        .site(worst.site.clone().unwrap_or_default())
        .hint("run `karigami check` for the full report; the design is too close to degenerate"));
    }
    // Derived in the order the refusals come: parts errors before clashes.
    if checked.parts().is_ok() {
        checked.measures();
    }
    let Checked {
        mut design,
        lattice,
        report,
        deployment,
        placed,
        measures,
        joints,
        parts,
    } = checked;
    let parts = parts
        .into_inner()
        .expect("made above")
        .map_err(|e| locate(&design, e))?;
    let joints = joints.into_inner().expect("found with the parts");
    let measures = measures.into_inner().expect("measured above");
    let job = job(&design, &lattice, &parts);
    // Every strip fits the longest preset (checked by `parts`), so one holds the job.
    let auto = design
        .fabrication
        .sheet_auto
        .then(|| pick(&job, &design.fabrication.sheet, None).expect("a preset holds the job"));
    if let Some((best, _)) = &auto {
        design.fabrication.sheet = best.spec(&design.fabrication.sheet);
    }
    let fab = &design.fabrication;
    if let Some(e) = measures.clash_error(&lattice, &design) {
        return Err(e);
    }
    let (layout, advice) = match auto {
        Some((best, layout)) => (layout, Some(best)),
        None => {
            let layout = job.nest(&fab.sheet);
            let advice = pick(&job, &fab.sheet, Some(&layout)).map(|(best, _)| best);
            (layout, advice)
        }
    };
    let meta = Meta {
        design: design.name.clone(),
        recipe_hash: design.recipe_hash,
    };
    let pages = (0..layout.sheets.len())
        .map(|i| {
            let mut page = sheet_page(&parts.strips, &layout, i, fab, &meta);
            crate::drawing::colours::apply(&mut page, fab.colours);
            if fab.tabs > 0.0 {
                page.metadata.push((
                    "tabs".into(),
                    format!(
                        "{} mm gaps left uncut in each outline (holding tabs; the bridge is narrower by the kerf)",
                        fab.tabs
                    ),
                ));
            }
            page
        })
        .collect();
    // The placement the measures were taken on; an extrinsic lattice is
    // its own.
    let assembled = placed
        .into_inner()
        .flatten()
        .unwrap_or_else(|| lattice.clone());
    Ok(Unsimulated(Build {
        steps: steps(&lattice, &joints),
        joints,
        simulation: None,
        simulation_key: None,
        path: None,
        design,
        assembled,
        measures,
        deployment,
        lattice,
        report,
        parts,
        layout,
        pages,
        job,
        advice,
    }))
}

/// What there is to nest.
fn job(design: &Design, lattice: &Lattice, parts: &Parts) -> Job {
    let fab = &design.fabrication;
    Job {
        lengths: parts
            .strips
            .iter()
            .map(|s| Outline::of(s.length, fab).length)
            .collect(),
        width: Outline::of(0.0, fab).width,
        test_piece: fab
            .test_piece
            .then(|| Outline::of(crate::parts::test_piece::LENGTH, fab).length),
        // Strip index = rod id; a rod's cell is id / 2.
        steps_if_free: !fab.group_by_step,
        steps: (fab.group_by_step || fab.group_if_free).then(|| {
            parts
                .strips
                .iter()
                .map(|s| lattice.step_of(s.rod / 2))
                .collect()
        }),
    }
}

/// A build's simulation, its deployment path, and its fingerprint with
/// whether it was restored.
type Simulated = (
    Option<crate::sim::Simulation>,
    Option<crate::sim::path::Path>,
    Option<(u64, bool)>,
);

/// The simulated deployed shape when `sim::wanted`, restored from
/// `previous` when that holds it (`reuse`), with its fingerprint and
/// whether it was restored. With `follow`, the deployment path too, and
/// the state reported is the one it deploys into (`chosen`). Strips
/// strained beyond the allowable are an error unless the recipe accepts
/// them. A solver failure is a warning (the cut files do not depend on
/// it): no deployed files then.
fn simulated(
    design: &Design,
    lattice: &Lattice,
    derived: &crate::sim::Derived<'_>,
    deployment: &Deployment,
    (previous, follow): (Option<&[u8]>, bool),
    warnings: &mut Vec<crate::parts::Warning>,
) -> Result<Simulated, Diagnostic> {
    if !crate::sim::wanted(lattice, deployment) {
        if crate::sim::needed(lattice, deployment) {
            warnings.push(crate::parts::Warning {
                strip: None,
                message: format!(
                    "the deployed shape is not simulated: build simulates lattices of up to {} cells and this one has {}; \
                     preview.png and the guide show the shape as designed, not the one its strips will take (docs/physics.md)",
                    crate::sim::MAX_SIMULATED_CELLS,
                    lattice.cells.len()
                ),
            });
        } else if !design.simulation.supports.is_empty() {
            warnings.push(crate::parts::Warning {
                strip: None,
                message: "[simulation] supports are not used: this lattice is a planar true mechanism, which is not \
                     simulated (its design is its deployed shape, docs/physics.md); it needs no pins to keep it"
                    .into(),
            });
        }
        return Ok((None, None, None));
    }
    let settings = &design.simulation;
    let m = &design.fabrication.material;
    let (w, t) = (m.width, m.thickness);
    let key = reuse::fingerprint(lattice, derived, w, t, settings);
    let restored =
        previous.and_then(|bytes| reuse::restore(bytes, key, lattice, derived, w, t, settings));
    // A state restored without its path (written by a build that did not
    // follow it) serves only a caller that does not want one.
    let restored = restored.filter(|(_, path)| path.is_some() || !follow);
    let reused = restored.is_some();
    let solved = match restored {
        Some(run) => Ok(run),
        None => crate::sim::simulate_with(
            lattice,
            deployment,
            derived,
            w,
            t,
            settings,
            &design.deadline,
        )
        .map(|run| match follow {
            true => crate::sim::path::chosen_until(run, &settings.material, &design.deadline),
            false => (run, None),
        }),
    };
    let (run, path) = match solved {
        Ok(run) => run,
        Err(e) => {
            // A recipe's mistake, not the solver's: refused where it is written.
            if let Some(d) = recipe_error(design, lattice, &e) {
                return Err(d);
            }
            warnings.push(crate::parts::Warning {
                strip: None,
                message: format!(
                    "the deployed shape could not be simulated ({e}); no deployed.obj or deployed.json, and the preview shows the design (docs/physics.md)"
                ),
            });
            return Ok((None, None, None));
        }
    };
    if let Some(p) = &path {
        path_warnings(p, &settings.material, warnings);
    }
    let strain = &run.equilibrium.strain;
    let allow = settings.material.eps_allow;
    if strain.eps > allow {
        let what = format!(
            "strained {:.2} % ({}) at {:.1} mm from its first hole in the simulated deployed shape; the allowable is {:.2} %",
            100.0 * strain.eps,
            strain.term,
            strain.s,
            100.0 * allow
        );
        if !settings.accept_overstrain {
            return Err(
                Diagnostic::new(ErrorKind::Overstrain, format!("strip {} is {what}", strain.rod))
                    .site(format!("strip {}", strain.rod))
                    .hint("use thinner or narrower strips, change the design, or accept it with [simulation] accept_overstrain = true (docs/physics.md)"),
            );
        }
        // Accepted by the recipe, but the maker should still hear of it.
        warnings.push(crate::parts::Warning {
            strip: Some(strain.rod.clone()),
            message: format!("{what}; the recipe accepts it ([simulation] accept_overstrain)"),
        });
    }
    // The clash rule on the strips as the simulation bends them: refused
    // as a clash of the design's strips is, unless the recipe allows it.
    if let Some(message) = contact(design, lattice, &run.lm) {
        if !design.clash.allow {
            let clashes = simulated_clashes(design, lattice, &run.lm);
            let c = clashes.first().expect("a clash");
            let name = |r: usize| crate::parts::clash::rod_name(lattice, r);
            return Err(Diagnostic::new(ErrorKind::StripClash, message)
                .at_opt(design.clash.span.clone().or(Some(design.size_span())))
                .site(format!("strips {} and {}", name(c.rods[0]), name(c.rods[1])))
                .hint("open the cells there, use narrower, thicker or stiffer strips, or accept the overlap with [clash] allow = true (docs/physics.md, Limits)"));
        }
        warnings.push(crate::parts::Warning {
            strip: None,
            message: format!("{message} (allowed by [clash])"),
        });
    }
    Ok((Some(run), path, Some((key, reused))))
}

/// A strain above the allowable on the deployment path is a warning (the
/// build's equilibrium is judged by `simulated`).
fn path_warnings(
    walked: &crate::sim::path::Path,
    material: &crate::sim::Material,
    warnings: &mut Vec<crate::parts::Warning>,
) {
    let allow = material.eps_allow;
    if let Some(p) = walked.overstrained(allow) {
        warnings.push(crate::parts::Warning {
            strip: Some(p.rod.clone()),
            message: format!(
                "strained {:.2} % on the deployment path at a held opening of {:.1} deg; the allowable is {:.2} % (report.txt, deployment path)",
                100.0 * p.strain,
                p.theta.to_degrees(),
                100.0 * allow
            ),
        });
    }
}

/// A simulation error that is the recipe's to fix, located in it: a
/// `[simulation] symmetry` the lattice does not have, or a mesh too large
/// for the memory allowed. None for the solver's failures.
pub fn recipe_error(
    design: &Design,
    lattice: &Lattice,
    e: &crate::sim::SimError,
) -> Option<Diagnostic> {
    match e {
        crate::sim::SimError::Symmetry { .. } => Some(
            Diagnostic::new(ErrorKind::SimulationOutOfRange, e.to_string())
                .at_opt(design.symmetry_span())
                .hint("symmetry is for loop lattices: how many identical copies of its cells the loop has; use a divisor of the cells in a row whose copies are alike, or 1, which a sheet always has (docs/physics.md)"),
        ),
        crate::sim::SimError::TooLarge { .. } => Some(too_large_to_simulate(design, lattice, e)),
        crate::sim::SimError::TooLong { limit, .. } => {
            let coarser = match crate::sim::edge_within_time(lattice, *limit, &design.simulation) {
                Some(h) if h <= 1e6 => format!(
                    "a coarser mesh, [simulation] edge_length = {} mm or more (now {} mm), ",
                    crate::diagnostic::shown((h * 10.0).ceil() / 10.0),
                    crate::diagnostic::shown(design.simulation.h_max)
                ),
                _ => String::new(),
            };
            Some(
                Diagnostic::new(ErrorKind::WorkTooLong, e.to_string())
                    .at_opt(design.edge_length_span().or(Some(design.size_span())))
                    .hint(format!("use {coarser}fewer or shorter strips, or allow more time with --time-limit SECONDS (docs/commands.md, Time limits)")),
            )
        }
        crate::sim::SimError::TimeLimit(_) => Some(
            Diagnostic::new(ErrorKind::TimeLimit, e.to_string())
                .hint("nothing was written; allow more time with --time-limit SECONDS, or use a coarser [simulation] edge_length (docs/commands.md, Time limits)"),
        ),
        _ => None,
    }
}

/// A simulation refused for its memory (`sim::within_memory`), blamed on
/// `[simulation] edge_length` with the coarsest edge that would fit.
fn too_large_to_simulate(
    design: &Design,
    lattice: &Lattice,
    e: &crate::sim::SimError,
) -> Diagnostic {
    let settings = &design.simulation;
    let hint = match crate::sim::edge_within(lattice, settings.memory) {
        Some(h) if h <= 1e6 => format!(
            "use a coarser mesh, [simulation] edge_length = {} mm or more (now {} mm), fewer or shorter strips, or allow more memory with --memory (docs/physics.md, Limits)",
            crate::diagnostic::shown((h * 10.0).ceil() / 10.0),
            crate::diagnostic::shown(settings.h_max)
        ),
        _ => "the lattice's strips are too long to simulate in this memory at any mesh; use fewer or shorter strips, or allow more memory with --memory (docs/physics.md, Limits)".to_string(),
    };
    Diagnostic::new(ErrorKind::SimulationTooLarge, e.to_string())
        .at_opt(design.edge_length_span())
        .hint(hint)
}

/// The clash rule of `check` applied to the strips of a simulated deployed
/// shape (`lm` at its equilibrium), each strip's bent centre line measured
/// (`measure::simulated_clashes`): None when no two strips of one
/// layer come closer than the strip width plus the clearance, else the
/// closest pair, how far apart their bent centre lines and their chords
/// are, and how many pairs clash. The simulation has no contact between
/// strips: where its shape breaks the rule the real strips press on each
/// other instead.
pub fn contact(
    design: &Design,
    lattice: &Lattice,
    lm: &crate::sim::LatticeModel,
) -> Option<String> {
    let clashes = simulated_clashes(design, lattice, lm);
    let c = clashes.first()?;
    let name = |r: usize| crate::parts::clash::rod_name(lattice, r);
    // The same two strips as straight chords (first hole to last, with the
    // end margins), for comparison: the bending is what brings them closer.
    let lines = lm.centre_lines();
    let margin = design.fabrication.end_margin;
    let chord = |r: usize| {
        let (a, b) = (lines[r][0], *lines[r].last().expect("two points"));
        let dir = (b - a).normalize_or_zero();
        (a - margin * dir, b + margin * dir)
    };
    let ((a, b), (p, q)) = (chord(c.rods[0]), chord(c.rods[1]));
    let (x, y) = crate::parts::clash::closest_points(a, b, p, q);
    Some(format!(
        "in the simulated deployed shape, strips {} and {} lie in the same stacking layer and their bent centre lines come {:.2} mm apart at ({:.1}, {:.1}, {:.1}) ({:.2} mm as straight chords), closer than the strip width {} mm plus {} mm clearance: they overlap ({} in all); the simulation does not model contact, so there the strips press on each other and the piece may not take the shape shown (docs/physics.md, Limits)",
        name(c.rods[0]),
        name(c.rods[1]),
        c.distance,
        c.at.x,
        c.at.y,
        c.at.z,
        x.distance(y),
        design.fabrication.material.width,
        design.clash.clearance,
        crate::words::plural(clashes.len(), "clashing pair"),
    ))
}

fn locate(design: &Design, e: PartsError) -> Diagnostic {
    Diagnostic::new(e.kind, e.message)
        .at(design.row_direction_span(e.row as usize))
        .site(format!("row {}, strip {}", e.row, e.strip))
        .hint(e.hint)
}

impl Build {
    /// The check reports' view of the build.
    pub fn verified(&self) -> Verified<'_> {
        Verified {
            design: &self.design,
            lattice: &self.lattice,
            assembled: &self.assembled,
            report: &self.report,
            deployment: &self.deployment,
            measures: &self.measures,
            parts: Some(&self.parts),
        }
    }

    /// Whether the simulated deployed shape was restored from the earlier
    /// build given to `Unsimulated::simulate` (true) or solved (false); None when
    /// the build did not simulate.
    pub fn simulation_reused(&self) -> Option<bool> {
        self.simulation_key.map(|(_, reused)| reused)
    }

    /// Lower bounds on the sheet count for the layout's parts.
    pub fn bounds(&self) -> Bounds {
        self.layout.bounds()
    }

    pub(crate) fn cut_length(&self) -> f64 {
        self.pages.iter().map(Page::cut_length).sum()
    }

    /// The job nested on every sheet preset, in preset order (for `--json`:
    /// five more nestings, so only where asked for).
    pub(crate) fn sheet_options(&self) -> Vec<SheetOption> {
        sheet_options(
            &self.job,
            &self.design.fabrication.sheet,
            Some(&self.layout),
        )
    }
}
