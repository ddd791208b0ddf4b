//! `karigami simulate RECIPE [--theta DEG] [--explore N] [--path] [--jobs N]`: the deployed
//! shape of the strips as elastic rods joined by eyelets (docs/physics.md).

use super::args::Verbosity;
use super::error::Error;
use super::progress;
use super::recipe::Recipe;
use karigami::{
    Design, ErrorKind, Lattice, Overrides,
    shape::{self, VertexCurvature},
    simulation::{
        self as sim, Equilibrium, LatticeModel, Settings, Simulation,
        explore::explore_until,
        states::{self, Relief},
    },
    util::{plural, shown},
};
use std::fmt::Write as _;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Seed of `--explore`'s perturbations (reported with the results).
pub(super) const EXPLORE_SEED: u64 = 2024;

/// The most starts `--explore` takes. Each is a full Newton solve (about
/// 13 ms on mirror-arm: `--explore 100 --jobs 1` took 1.31 s; 180 ms on
/// the eggbox: 12 starts 2.16 s; one core), and the report lists
/// every start left out: 10,000 starts are minutes to half an hour on the
/// examples, where a million were hours to days with no end in sight. The
/// equilibria are found within the first dozens of starts (the eggbox's
/// three in 12); a basin that 10,000 starts miss is not one a maker meets.
const MAX_EXPLORE: usize = 10_000;

pub(super) fn simulate(
    path: &Path,
    theta: Option<f64>,
    explore_n: Option<usize>,
    follow_path: bool,
    (jobs, memory, deadline): (usize, Option<u64>, karigami::Deadline),
    v: Verbosity,
) -> Result<(), Error> {
    // The flags first: a usage error before the recipe is read or grown.
    if let Some(t) = theta.filter(|t| !(*t >= sim::MIN_THETA && *t < sim::MAX_THETA)) {
        return Err(Error::new(
            ErrorKind::FlagOutOfRange,
            format!(
                "--theta is {}, but must be an opening in degrees of at least {} and less than {}",
                shown(t),
                sim::MIN_THETA,
                sim::MAX_THETA
            ),
        ));
    }
    if let Some(n) = explore_n.filter(|n| !(1..=MAX_EXPLORE).contains(n)) {
        return Err(Error::new(
            ErrorKind::FlagOutOfRange,
            format!("--explore is {n}, but must be from 1 to {MAX_EXPLORE} starts"),
        ));
    }
    let recipe = Recipe::read(path)?;
    let design = recipe.parse(&Overrides {
        deadline,
        ..Overrides::default()
    })?;
    // The staged pipeline's first stage, as `karigami check` runs it.
    let checked = karigami::check(design, &mut |_| {}).map_err(|d| recipe.error(&d))?;
    if !checked.report.passed() {
        return Err(Error::new(
            ErrorKind::VerificationFailed,
            format!(
                "{} fails verification; run `karigami check {}`",
                recipe.file, recipe.file
            ),
        ));
    }
    let (design, lattice, deploy) = (&checked.design, &checked.lattice, &checked.deployment);
    let mut settings = design.simulation.clone();
    if let Some(mb) = memory {
        settings.memory = mb << 20;
    }
    if let Some(t) = theta {
        settings.theta = Some(t.to_radians());
    }
    let (w, t) = (
        design.fabrication.material.width,
        design.fabrication.material.thickness,
    );
    let failed = |e: sim::SimError| match karigami::recipe_error(design, lattice, &e) {
        Some(d) => recipe.error(&d),
        None => Error::new(
            ErrorKind::SimulationFailed,
            format!("{}: simulation failed: {e}", recipe.file),
        ),
    };
    // A mesh too large for the memory, or longer than allowed, is refused
    // first; long work is said up front (docs/commands.md, "Time limits").
    sim::within_memory(lattice, &settings).map_err(failed)?;
    sim::within_time(lattice, &settings, &deadline).map_err(failed)?;
    say_simulation(&recipe.file, lattice, &settings, &deadline, v);
    // A large lattice's solve runs for minutes (a 4,800-cell torus 3 min).
    let what = format!("simulating {}", recipe.file);
    let run = progress::heartbeat(&what, v.quiet, || {
        sim::simulate_until(lattice, deploy, w, t, &settings, &deadline)
    })
    .map_err(failed)?;
    // `--explore` refused by the solve's measured cost before the path,
    // which can take minutes on a large sheet.
    let explored = explore_n
        .map(|n| explore_estimate(&recipe, &run, (n, jobs), &deadline))
        .transpose()?;
    // The state reported is the one deploying ends in (docs/physics.md,
    // "The chosen equilibrium"): the path is followed on every run.
    let (run, walked) = progress::heartbeat("following the deployment path", v.quiet, || {
        sim::path::chosen_until(run, &settings.material, &deadline)
    });
    if deadline.expired() {
        return Err(recipe.error(&plain(
            ErrorKind::TimeLimit,
            format!(
                "stopped on the deployment path, {:.1} s in: the time limit of {} s has passed",
                deadline.elapsed(),
                deadline.limit().unwrap_or(0.0)
            ),
            "nothing was reported; allow more time with --time-limit SECONDS (docs/commands.md, Time limits)".into(),
        )));
    }
    if !v.quiet {
        out!(
            "{}",
            text(
                &recipe.file,
                design,
                lattice,
                &deploy.verdict(lattice),
                &run,
                &settings
            )
        );
        if let Some(walked) = &walked {
            let how = sim::path::Walked {
                held: settings.actuation,
                free: !run.equilibrium.supports.is_empty(),
            };
            print!(
                "{}",
                walked.text(settings.material.eps_allow, follow_path, how)
            );
            print!(
                "{}",
                states::known(lattice, &run.lm, &run.equilibrium, walked)
            );
        }
    }
    if let (Some(n), Some(estimate)) = (explore_n, explored) {
        say_estimate(&recipe.file, &estimate, &deadline, v);
        explore(&recipe, lattice, &run, &settings, (n, jobs), &deadline, v)?;
    }
    Ok(())
}

/// Newton iterations an `--explore` start is reckoned at, in the
/// unperturbed solve's measured time an iteration: the eggbox's starts take
/// 180 ms against its 17 ms an iteration, a 1,980-cell sheet's 5 to 7 s
/// against 1.8 s.
const START_ITERATIONS: f64 = 10.0;

/// `--explore N`'s work reckoned from the solve (`START_ITERATIONS` of its
/// measured Newton iterations a start, over the threads), refused beyond
/// the time limit with the most starts that fit (docs/commands.md, "Time
/// limits").
fn explore_estimate(
    recipe: &Recipe,
    run: &Simulation,
    (n, jobs): (usize, usize),
    deadline: &karigami::Deadline,
) -> Result<karigami::Estimate, Error> {
    let per_start = run.seconds / (run.iterations + 1) as f64 * START_ITERATIONS;
    let estimate = per_start * n as f64 / jobs.min(n).max(1) as f64;
    if !deadline.allows(estimate) {
        return Err(recipe.error(&plain(
            ErrorKind::WorkTooLong,
            format!(
                "--explore {n} would take about {} ({n} starts of about {} each on {}), longer than the {} allowed",
                karigami::duration(estimate),
                karigami::duration(per_start),
                plural(jobs, "thread"),
                karigami::duration(deadline.ceiling())
            ),
            format!(
                "use --explore {} or fewer, or allow more time with --time-limit SECONDS (docs/commands.md, Time limits)",
                ((deadline.ceiling() / per_start * jobs as f64).floor() as usize).max(1)
            ),
        )));
    }
    Ok(karigami::Estimate {
        seconds: estimate,
        what: format!(
            "--explore: {n} starts of ~{} on {}",
            karigami::duration(per_start),
            plural(jobs.min(n), "thread")
        ),
    })
}

/// `--explore N`: the other stable states, from N seeded perturbations of
/// the reported equilibrium (its estimate refused or said before).
fn explore(
    recipe: &Recipe,
    lattice: &Lattice,
    run: &Simulation,
    settings: &Settings,
    (n, jobs): (usize, usize),
    deadline: &karigami::Deadline,
    v: Verbosity,
) -> Result<(), Error> {
    let material = settings.material;
    let solved = AtomicUsize::new(0);
    let line = |seconds| {
        let k = solved.load(Ordering::Relaxed);
        format!("explore: {k} of {n} starts ({seconds} s)")
    };
    let (found, rejected) = progress::heartbeat_saying(line, v.quiet, || {
        explore_until(
            &run.lm,
            (n, EXPLORE_SEED),
            jobs,
            &|lm, stats| sim::equilibrium(lm, stats, &material),
            &solved,
            deadline,
        )
    })
    .map_err(|stopped| {
        recipe.error(&plain(
            ErrorKind::TimeLimit,
            format!("--explore {stopped}"),
            "nothing of the exploration was reported; allow more time with --time-limit SECONDS, or fewer starts (docs/commands.md, Time limits)".into(),
        ))
    })?;
    if !v.quiet {
        out!(
            "{}",
            explore_text(lattice, &run.lm, &found, &rejected, n, settings)
        );
    }
    Ok(())
}

/// An error of the command line's work, not at a place in the recipe.
fn plain(kind: ErrorKind, message: String, hint: String) -> karigami::Diagnostic {
    karigami::Diagnostic {
        kind,
        message,
        span: None,
        site: None,
        hint: Some(hint),
    }
}

/// Say a simulation reckoned long before it starts (`say_estimate`).
fn say_simulation(
    file: &str,
    lattice: &Lattice,
    settings: &Settings,
    deadline: &karigami::Deadline,
    v: Verbosity,
) {
    let estimate = karigami::simulation_estimate(lattice, settings);
    say_estimate(file, &estimate, deadline, v);
}

/// Say work reckoned at `karigami::SAY_ABOVE` seconds or more before it
/// starts, with the limit it runs under (`Estimate::said`).
fn say_estimate(
    file: &str,
    estimate: &karigami::Estimate,
    deadline: &karigami::Deadline,
    v: Verbosity,
) {
    if let Some(line) = estimate.said(deadline).filter(|_| !v.quiet) {
        errln!("{file}: {line}");
    }
}

fn pct(x: f64) -> String {
    format!("{:.3} %", 100.0 * x)
}

/// The report of one simulation (docs/physics.md, "Strain and what is
/// allowed"; README, `simulate`).
pub(super) fn text(
    file: &str,
    design: &Design,
    lattice: &Lattice,
    verdict: &str,
    run: &Simulation,
    s: &Settings,
) -> String {
    let mut o = String::new();
    model_lines(&mut o, file, lattice, verdict, run, s);
    strain_lines(&mut o, lattice, run, s);
    shape_lines(&mut o, design, lattice, run);
    opening_lines(&mut o, run);
    solver_line(&mut o, run);
    o
}

/// The model, its material, the held angle and the energy.
fn model_lines(
    o: &mut String,
    file: &str,
    lattice: &Lattice,
    verdict: &str,
    run: &Simulation,
    s: &Settings,
) {
    let eq = &run.equilibrium;
    let m = &run.lm.model;
    let sec = &m.section;
    let _ = writeln!(
        o,
        "{file}: {} cells, {} strips as elastic rods, {} joints ({} vertices)",
        lattice.cells.len(),
        m.rods.len(),
        m.joints.len(),
        s.vertex_joint.name()
    );
    let _ = writeln!(o, "deployment: {verdict}");
    let _ = writeln!(
        o,
        "material: E {} MPa, nu {}, strip {} x {} mm: flatwise EI {:.1} N mm^2, edgewise EI {:.0} N mm^2, GJ {:.1} N mm^2",
        s.material.youngs,
        s.material.poisson,
        sec.width,
        sec.thickness,
        sec.b_flat,
        sec.b_edge,
        sec.gj
    );
    let copies = if s.symmetry > 1 && s.actuation == sim::Actuation::Mean {
        format!(", the loop's {} copies opening alike", s.symmetry)
    } else {
        String::new()
    };
    let _ = writeln!(
        o,
        "theta ({} held{copies}): {:.3} deg",
        s.actuation.describe(),
        run.theta.to_degrees()
    );
    let e = &eq.energy;
    let _ = writeln!(
        o,
        "energy: {:.6e} N mm (stretch {:.3e}, bend {:.3e}, twist {:.3e}); energy scale {:.3} N mm",
        e.total(),
        e.stretch,
        e.bend,
        e.twist,
        m.e_scale
    );
}

/// The largest strains, the largest joint reaction and the distance from
/// the design.
fn strain_lines(o: &mut String, lattice: &Lattice, run: &Simulation, s: &Settings) {
    let eq = &run.equilibrium;
    let st = &eq.strain;
    let verdict = if st.eps > s.material.eps_allow {
        "ABOVE the allowable"
    } else {
        "within the allowable"
    };
    if st.rod.is_empty() {
        let _ = writeln!(o, "largest strain: 0");
    } else {
        let _ = writeln!(
            o,
            "largest strain: {} ({}) in strip {} at {:.1} mm from its first hole; allowable {}: {verdict}",
            pct(st.eps),
            st.term,
            st.rod,
            st.s,
            pct(s.material.eps_allow)
        );
    }
    let _ = writeln!(
        o,
        "largest twist shear strain: {}; largest equivalent (von Mises) strain: {}",
        pct(st.gamma),
        pct(st.eps_eq)
    );
    let (f, j, rod) = &eq.reaction;
    let _ = writeln!(
        o,
        "largest joint reaction: {:.4} N, at {} on strip {rod}",
        f,
        run.lm.joint_name(lattice, *j)
    );
    if let Some((a, b, span)) = karigami::simulation::supports::span(&eq.supports) {
        let name = |v: u32| run.lm.point_name(lattice, v as usize);
        let each: Vec<String> = eq
            .supports
            .iter()
            .map(|r| format!("{} {:.4} N", name(r.vertex), r.force.length()))
            .collect();
        let _ = writeln!(
            o,
            "supports ([simulation] supports): {} vertices held at their design positions, {span:.1} mm between the farthest two ({} and {}); reactions: {}",
            eq.supports.len(),
            name(a),
            name(b),
            each.join(", ")
        );
    }
    let _ = writeln!(
        o,
        "distance from the design (after the best rigid fit): largest {:.4} mm at {}, rms {:.4} mm",
        eq.fit.max,
        run.lm.point_name(lattice, eq.fit.at),
        eq.fit.rms
    );
}

/// Curvature and relief, design and simulated, and the clashes.
fn shape_lines(o: &mut String, design: &Design, lattice: &Lattice, run: &Simulation) {
    let sec = &run.lm.model.section;
    // One measure for both (lattice::shape): the design's defects from each
    // cell's own corners (what the cut strips fix), the simulated ones from
    // the joints where the strips put them.
    let simulated = sim::placed_lattice(lattice, &run.lm);
    for (what, c) in [
        ("design", lattice.curvature()),
        ("simulated", simulated.curvature()),
    ] {
        let _ = writeln!(o, "curvature ({what}): {}", curvature_summary(&c));
    }
    for (what, l) in [("design", lattice), ("simulated", &simulated)] {
        let _ = writeln!(o, "relief ({what}): {}", relief(l));
    }
    let _ = writeln!(
        o,
        "clashes: {}",
        karigami::contact(design, lattice, &run.lm).unwrap_or_else(|| format!(
            "none in the simulated deployed shape (same-layer strips at least {} mm + {} mm clearance apart)",
            sec.width, design.clash.clearance
        ))
    );
}

/// The cell openings: their range, any inverted, and each when few.
fn opening_lines(o: &mut String, run: &Simulation) {
    let eq = &run.equilibrium;
    let (lo, hi) = eq
        .openings
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(*x), b.max(*x))
        });
    let _ = writeln!(
        o,
        "cell openings: {:.2} to {:.2} deg",
        lo.to_degrees(),
        hi.to_degrees()
    );
    let inverted = eq.openings.iter().filter(|p| **p <= 0.0).count();
    if inverted > 0 {
        let _ = writeln!(
            o,
            "  warning: {} at or below 0 deg: inverted, their strips would pass through each other (hold a larger theta)",
            if inverted == 1 {
                "1 cell opens".to_string()
            } else {
                format!("{inverted} cells open")
            }
        );
    }
    if eq.openings.len() <= 12 {
        let list: Vec<String> = eq
            .openings
            .iter()
            .map(|p| format!("{:.2}", p.to_degrees()))
            .collect();
        let _ = writeln!(o, "  per cell: {}", list.join(", "));
    }
}

/// How the solver did.
fn solver_line(o: &mut String, run: &Simulation) {
    let eq = &run.equilibrium;
    let st = &eq.stats;
    let _ = writeln!(
        o,
        "solver: {} Newton iterations in {}, {:.3} s; residual force {:.1e} N, moment {:.1e} N mm; lowest eigenvalue {:.3e} ({})",
        run.iterations,
        plural(run.steps, "step"),
        run.seconds,
        st.force,
        st.moment,
        st.lambda_min,
        if st.lambda_min > 0.0 {
            "stable"
        } else {
            "NOT stable"
        }
    );
}

/// Signs of the angle defects at interior vertices (discrete Gaussian
/// curvature, lattice::shape's measure): how many dome-like (at least
/// +CURVED_DEG), saddle-like (at most -CURVED_DEG) and flat, and the range.
pub(super) fn curvature_summary(c: &[VertexCurvature]) -> String {
    let Some(sum) = shape::summary(c) else {
        return "no interior vertices".into();
    };
    let n = sum.interior;
    let pos = (sum.positive * n as f64).round() as usize;
    let neg = (sum.negative * n as f64).round() as usize;
    format!(
        "angle defects at {n} interior vertices: {pos} dome-like (>= +{c} deg), {neg} saddle-like (<= -{c} deg), {} flat; from {:.2} to {:.2} deg, mean {:.2} deg",
        n - pos - neg,
        sum.min_deg,
        sum.max_deg,
        sum.mean_deg,
        c = shape::CURVED_DEG,
    )
}

/// How many interior vertices of `l` are dome-like (angle defect of at
/// least +3 deg) and saddle-like (-3 or less), and over how many rows and
/// columns each spreads: the shape measures of `karigami check`.
fn relief(l: &Lattice) -> String {
    let c = l.curvature();
    let deg = karigami::BUMP_DEG;
    let (dome, saddle) = shape::relief(&c, deg);
    let over = |(rows, cols): (usize, usize)| format!("{rows} rows, {cols} columns");
    format!(
        "{dome} of {} interior vertices at +{deg} deg or more (over {}), {saddle} at -{deg} deg or less (over {})",
        c.len(),
        over(shape::spread(l, &c, |d| d >= deg)),
        over(shape::spread(l, &c, |d| d <= -deg))
    )
}

fn explore_text(
    lattice: &Lattice,
    lm: &LatticeModel,
    found: &[sim::explore::Found],
    rejected: &[(u64, String)],
    n: usize,
    s: &Settings,
) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "explore: {n} starts from the reported equilibrium (seed {EXPLORE_SEED}; start 0 unperturbed, others moved along the strips' face normals by 1, 3, 10 mm x N(0,1)): {} distinct stable equilibri{}",
        found.len(),
        if found.len() == 1 { "um" } else { "a" }
    );
    // Start 0 is the reported state itself, unperturbed.
    let reported = found.iter().position(|f| f.hits.contains(&0));
    let lowest: Option<&Equilibrium> = found.first().map(|f| &f.equilibrium);
    for (k, f) in found.iter().enumerate() {
        let eq = &f.equilibrium;
        let to_lowest = lowest.map_or(0.0, |l| sim::kabsch_distance(&eq.points, &l.points));
        let _ = writeln!(
            o,
            "  {}: energy {:.6e} N mm, {}, lowest eigenvalue {:.3e}, largest strain {} in {}{}, {:.3} mm from the design, {:.3} mm from the lowest{}",
            k + 1,
            eq.energy.total(),
            plural(f.hits.len(), "hit"),
            eq.stats.lambda_min,
            pct(eq.strain.eps),
            eq.strain.rod,
            if eq.strain.eps > s.material.eps_allow {
                " (ABOVE the allowable)"
            } else {
                ""
            },
            eq.distance,
            to_lowest,
            if Some(k) == reported {
                " (the reported one)"
            } else {
                ""
            }
        );
    }
    // Pop-through (the paper's: a bump turned inside out, still a bump),
    // and vertices that change from dome-like to saddle-like or back,
    // between the reported equilibrium and each other, measured on each
    // shape (docs/physics.md, "Multistability").
    if let Some(r) = reported {
        let base = Relief::at(lattice, lm, &found[r].equilibrium.points);
        for (k, f) in found.iter().enumerate().filter(|(k, _)| *k != r) {
            let other = Relief::at(lattice, lm, &f.equilibrium.points);
            let (popped, flipped) = (base.popped(&other, lattice), base.flipped(&other, lattice));
            let _ = writeln!(
                o,
                "  {} against {}: energy {:+.3} N mm; {} (dome-like vertices whose height over their neighbours, at least {} mm, changes side): {}",
                k + 1,
                r + 1,
                f.equilibrium.energy.total() - found[r].equilibrium.energy.total(),
                match popped.len() {
                    1 => "1 bump pops through".to_string(),
                    n => format!("{n} bumps pop through"),
                },
                states::BUMP_MM,
                states::listed(&popped, "mm")
            );
            let _ = writeln!(
                o,
                "  {} against {}: {} sign (defect from beyond +-{} deg to beyond it the other way): {}",
                k + 1,
                r + 1,
                match flipped.len() {
                    1 => "1 vertex changes its curvature's".to_string(),
                    n => format!("{n} vertices change their curvature's"),
                },
                shape::CURVED_DEG,
                states::listed(&flipped, "deg")
            );
        }
        let _ = writeln!(
            o,
            "  build reports {}: {} (start 0)",
            r + 1,
            if lm.supports().is_empty() {
                "the state deploying reaches"
            } else {
                "the state solved from the design with its supports held"
            }
        );
    }
    for (seed, why) in rejected {
        let _ = writeln!(o, "  start {seed}: {why}");
    }
    o
}
