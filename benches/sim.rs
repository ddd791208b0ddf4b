//! Simulation benchmark: `cargo bench --bench sim [-- NAME...]`.
//! For each gallery example (default: all), the equilibrium of its strips
//! from the start placement (the design, or the rigid-fit placement of a
//! bent-facet lattice) at the design opening, on one core: wall time,
//! Newton iterations, Hessian assemblies and factorisations (those that
//! found the shifted Hessian indefinite in brackets), variables, energy,
//! largest strain and distance from the start. Also a 10 x 10-cell flat
//! sheet (100 cells). `--first-cell` holds the first cell's opening
//! instead of the mean of all cells.
//!
//! For design loops (issue 33, item 5), a second table: per example, a
//! warm re-solve (`simulation::resolve`) after the middle seed point moves
//! 0.1 mm along x (none where the seed then no longer closes: the saddle
//! ring's loop), and one after the held opening moves 0.1 deg (`warm_start` on
//! the equilibrium's model and the solve, timed), each on the cold run's
//! system kept untimed (`keep_system`), as a design loop's steps reuse it, and the adjoint gradient of the squared
//! distances of the joints to targets 1 mm above them over every leg length
//! and the opening (`sensitivity::objective_gradient`, on that system, taken
//! first, right after the cold solve, as a design loop does), each the
//! mean of 5 repetitions (`--repeat N`; the thread's CPU clock ticks
//! coarsely). Then the eggbox's 60-start explore on one job
//! (`--no-explore` to skip it).

use karigami::simulation::sensitivity::{Param, objective_gradient};
use karigami::simulation::warm::warm_start;
use karigami::{
    deploy::deployment,
    simulation::{self as sim, Actuation, Settings},
};
use karigami_rods::solver::{Options, counts, solve};
use std::time::Instant;

const SHEET_100: &str = r#"
name = "sheet-10x10"
[lattice]
seed = "sheet"
points = [[0.0, 0.0], [40.0, 0.0], [80.0, 0.0], [120.0, 0.0], [160.0, 0.0], [200.0, 0.0], [240.0, 0.0], [280.0, 0.0], [320.0, 0.0], [360.0, 0.0], [400.0, 0.0]]
kappa = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
[lattice.grow]
rows = 10
angle = 60.0
left_leg = 40.0
right_leg = "match"
"#;

/// What the design-loop table needs of an example's cold run.
struct Cold {
    design: karigami::Design,
    settings: Settings,
    run: sim::Simulation,
}

fn run(name: &str, text: &str, actuation: Actuation) -> Option<Cold> {
    let d = match karigami::parse(text, name) {
        Ok(d) => d,
        Err(e) => {
            println!("{name}: does not parse: {}", e.message);
            return None;
        }
    };
    let lattice = match d.grow() {
        Ok(l) => l,
        Err(e) => {
            println!("{name}: does not grow: {}", e.message);
            return None;
        }
    };
    let dep = deployment(&lattice);
    let settings = Settings {
        theta: None,
        actuation,
        ..d.simulation.clone()
    };
    let m = &d.fabrication.material;
    let clock = Instant::now();
    let cpu0 = cpu_seconds();
    let work0 = counts();
    let result = sim::simulate(&lattice, &dep, m.width, m.thickness, &settings);
    let cpu = cpu_seconds() - cpu0;
    let work = counts().since(work0);
    let work = format!(
        "{}, {} ({} failed)",
        work.assemblies, work.factorisations, work.failed
    );
    let secs = clock.elapsed().as_secs_f64();
    match result {
        Ok(run) => {
            let eq = &run.equilibrium;
            println!(
                "| {name} | {} | {} | {} | {cpu:.2} | {:.2} | {} | {work} | {:.3e} | {:.3} % ({}) | {:.3} |",
                lattice.cells.len(),
                run.lm.model.fixed.iter().filter(|f| !**f).count(),
                if lattice.extrinsic() && dep.is_mechanism() {
                    "mechanism"
                } else if !lattice.extrinsic() {
                    "bent facets"
                } else {
                    "rigid linkage"
                },
                secs,
                run.iterations,
                eq.energy.total(),
                100.0 * eq.strain.eps,
                eq.strain.rod,
                eq.distance
            );
            Some(Cold {
                settings,
                design: d.clone(),
                run,
            })
        }
        Err(e) => {
            println!(
                "| {name} | {} | | | {cpu:.2} | {secs:.2} | failed: {e} | {work} | | | |",
                lattice.cells.len()
            );
            None
        }
    }
}

/// The design-loop figures of one example (module documentation), each
/// the mean over `reps` repetitions from the same kept system.
fn design_loop(name: &str, cold: &Cold, reps: usize) {
    let mut times = [Mean::default(), Mean::default(), Mean::default()];
    let mut said = [String::new(), String::new(), String::new()];
    for _ in 0..reps.max(1) {
        let figures = design_step(cold);
        for ((t, s), (secs, what)) in times.iter_mut().zip(&mut said).zip(figures) {
            t.add(secs);
            *s = what;
        }
    }
    let [a, b, c] = [0, 1, 2].map(|i| {
        let t = &times[i];
        format!("{}{}", t.shown(), said[i])
    });
    println!("| {name} | {b} | {c} | {a} |");
}

/// One repetition of `design_loop`: ((CPU s, wall s), what it did) of the
/// adjoint, the seed-point re-solve and the opening re-solve.
fn design_step(cold: &Cold) -> [((f64, f64), String); 3] {
    // The loop's first step keeps the cold run's system (untimed; a
    // design loop makes it once) for the steps after it.
    let mut kept = cold.run.lm.clone();
    kept.keep_system();
    // The adjoint first, as a design loop takes it right after a solve.
    let lm = &kept;
    let t0 = (Instant::now(), thread_cpu());
    let sys = lm.system();
    let g = objective_gradient(lm, &sys, &targets(lm));
    let adjoint = (
        took(t0),
        match g {
            Ok(g) => format!(" ({} legs)", g.legs.len()),
            Err(e) => format!(" {e}"),
        },
    );
    let mut changed = cold.design.clone();
    let k = changed.points.len() / 2;
    if let Some(p) = changed.points.get_mut(k) {
        p.x += 0.1;
    }
    let seed = match changed.grow() {
        Ok(lattice) => {
            let dep = deployment(&lattice);
            let m = &changed.fabrication.material;
            let t0 = (Instant::now(), thread_cpu());
            let r = sim::resolve(
                &kept,
                &lattice,
                &dep,
                (m.width, m.thickness),
                &cold.settings,
            );
            let secs = took(t0);
            match r {
                Ok((run, warm)) => (
                    secs,
                    format!(
                        ", {} it{}",
                        run.iterations,
                        if warm { "" } else { " (cold)" }
                    ),
                ),
                Err(e) => ((f64::NAN, f64::NAN), format!(" failed: {e}")),
            }
        }
        Err(e) => (
            (f64::NAN, f64::NAN),
            format!("does not grow: {}", e.message),
        ),
    };
    let mut lm = kept.clone();
    lm.direction(Param::Opening)
        .apply(&mut lm.model, 0.1f64.to_radians());
    let t0 = (Instant::now(), thread_cpu());
    // The cold run's system, which the changed opening still fits.
    let sys = kept.system();
    warm_start(&mut lm, &kept, &sys);
    let r = solve(&mut lm.model, &sys, &Options::default());
    let secs = took(t0);
    let opening = match r {
        Ok(s) => (secs, format!(", {} it", s.iterations)),
        Err(e) => ((f64::NAN, f64::NAN), format!(" failed: {e}")),
    };
    [adjoint, seed, opening]
}

/// One Newton iteration's parts at the cold run's equilibrium, each the
/// mean of `reps` (`--floor`): an energy (what each line-search trial
/// costs), an assembly of the gradient and Hessian, a numeric
/// factorisation of the unshifted Hessian and one solve with it, on the
/// cold run's system; with the nodes, free variables and the entries of
/// the Hessian's lower triangle and of its factor.
fn floor(name: &str, cold: &Cold, reps: usize) {
    let lm = &cold.run.lm;
    let sys = lm.system();
    let model = &lm.model;
    let mut times = [
        Mean::default(),
        Mean::default(),
        Mean::default(),
        Mean::default(),
    ];
    // Each part `reps` times in a row: the thread's CPU clock is read
    // from the scheduler's accounts, which lag by up to a tick.
    let reps = reps.max(1);
    let t0 = (Instant::now(), thread_cpu());
    for _ in 0..reps {
        std::hint::black_box(model.energy());
    }
    times[0].add_many(took(t0), reps);
    let t0 = (Instant::now(), thread_cpu());
    for _ in 0..reps {
        let (_, g, h) = sys.assemble(model);
        sys.recycle(g, h);
    }
    times[1].add_many(took(t0), reps);
    let (_, g, h) = sys.assemble(model);
    let t0 = (Instant::now(), thread_cpu());
    for _ in 0..reps {
        if let Some(f) = sys.factor(&h, 0.0) {
            sys.release(f);
        }
    }
    times[2].add_many(took(t0), reps);
    let Some(f) = sys.factor(&h, 0.0) else {
        return println!("| {name} | the Hessian at its equilibrium does not factor |");
    };
    let gf = sys.free_gradient(&g);
    let t0 = (Instant::now(), thread_cpu());
    for _ in 0..reps {
        std::hint::black_box(sys.solve(&f, &gf));
    }
    times[3].add_many(took(t0), reps);
    sys.release(f);
    sys.recycle(g, h);
    let (h_entries, l_entries) = sys.entries();
    let [e, a, f, s] = times.map(|t| t.shown());
    println!(
        "| {name} | {} | {} | {h_entries} | {l_entries} | {e} | {a} | {f} | {s} |",
        model.nodes.len(),
        sys.n()
    );
}

/// A mean of (CPU, wall) seconds.
#[derive(Default)]
struct Mean {
    cpu: f64,
    wall: f64,
    n: usize,
}

impl Mean {
    fn add(&mut self, (cpu, wall): (f64, f64)) {
        self.add_many((cpu, wall), 1);
    }

    /// The seconds of `n` repetitions timed together.
    fn add_many(&mut self, (cpu, wall): (f64, f64), n: usize) {
        self.cpu += cpu;
        self.wall += wall;
        self.n += n;
    }

    /// "C ms CPU (W wall)", or nothing when not measured.
    fn shown(&self) -> String {
        let n = self.n.max(1) as f64;
        if !self.cpu.is_finite() {
            return String::new();
        }
        format!(
            "{:.2} ms CPU ({:.0} wall)",
            1e3 * self.cpu / n,
            1e3 * self.wall / n
        )
    }
}

/// Targets for the adjoint's objective: every point 1 mm higher.
fn targets(lm: &sim::LatticeModel) -> Vec<glam::DVec3> {
    lm.points().iter().map(|p| *p + glam::DVec3::Z).collect()
}

/// This thread's CPU time so far in seconds, to the nanosecond (Linux
/// /proc/thread-self/schedstat, its first field); NaN elsewhere. The
/// design-loop figures are tens of milliseconds, below `cpu_seconds`'
/// 10 ms ticks.
fn thread_cpu() -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |ns| ns * 1e-9)
}

/// (CPU s, wall s) since `(clock, cpu0)`.
fn took((clock, cpu0): (Instant, f64)) -> (f64, f64) {
    (thread_cpu() - cpu0, clock.elapsed().as_secs_f64())
}

/// User + system CPU time of this process (Linux /proc; the machine may be
/// shared, so wall time overstates the single-core cost). NaN elsewhere.
fn cpu_seconds() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else {
        return f64::NAN;
    };
    // Fields after the command name (which is in parentheses).
    let rest = stat.rsplit_once(')').map_or("", |r| r.1);
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| {
        f.get(i)
            .and_then(|x| x.parse::<f64>().ok())
            .unwrap_or(f64::NAN)
    };
    // utime and stime are fields 14 and 15 of stat, f[11] and f[12]; the
    // kernel counts them in USER_HZ = 100 ticks a second on Linux.
    (ticks(11) + ticks(12)) / 100.0
}

fn main() {
    let wanted: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-') && a.parse::<usize>().is_err())
        .collect();
    let actuation = if std::env::args().any(|a| a == "--first-cell") {
        Actuation::FirstCell
    } else {
        Actuation::Mean
    };
    println!(
        "| example | cells | variables | linkage | CPU s | wall s | Newton iterations | Hessians, factorisations | energy (N mm) | largest strain | distance from start (mm) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    let mut names: Vec<_> = std::fs::read_dir("examples")
        .expect("examples/")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    names.sort();
    let mut colds = Vec::new();
    for path in names {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if !wanted.is_empty() && !wanted.contains(&name) {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("readable");
        if let Some(c) = run(&name, &text, actuation) {
            colds.push((name, c));
        }
    }
    if (wanted.is_empty() || wanted.iter().any(|w| w == "sheet-10x10"))
        && let Some(c) = run("sheet-10x10", SHEET_100, actuation)
    {
        colds.push(("sheet-10x10".into(), c));
    }
    println!();
    println!(
        "| example | warm re-solve, seed point +0.1 mm | warm re-solve, opening +0.1 deg | adjoint gradient |"
    );
    println!("|---|---|---|---|");
    let reps = std::env::args()
        .skip_while(|a| a != "--repeat")
        .nth(1)
        .and_then(|n| n.parse().ok())
        .unwrap_or(5);
    for (name, c) in &colds {
        design_loop(name, c, reps);
    }
    if std::env::args().any(|a| a == "--floor") {
        println!();
        println!(
            "| example | nodes | free variables | H entries (lower) | factor entries | energy | assembly | factorisation | solve |"
        );
        println!("|---|---|---|---|---|---|---|---|---|");
        for (name, c) in &colds {
            floor(name, c, reps);
        }
    }
    if !std::env::args().any(|a| a == "--no-explore") {
        explore_eggbox();
    }
}

/// The eggbox's 60-start explore on one job, as `karigami simulate
/// examples/eggbox.toml --explore 60 --jobs 1` runs it (its seed, 2024).
fn explore_eggbox() {
    let text = std::fs::read_to_string("examples/eggbox.toml").expect("eggbox");
    let Ok(d) = karigami::parse(&text, "eggbox") else {
        return;
    };
    let Ok(lattice) = d.grow() else { return };
    let dep = deployment(&lattice);
    let m = &d.fabrication.material;
    let Ok(run) = sim::simulate(&lattice, &dep, m.width, m.thickness, &d.simulation) else {
        return println!("eggbox: does not simulate");
    };
    let material = d.simulation.material;
    let finish = |lm: &sim::LatticeModel, stats| sim::equilibrium(lm, stats, &material);
    let solved = std::sync::atomic::AtomicUsize::new(0);
    let (clock, cpu0) = (Instant::now(), cpu_seconds());
    let (found, rejected) = sim::explore::explore(&run.lm, 60, 2024, 1, &finish, &solved);
    println!();
    println!(
        "eggbox --explore 60 --jobs 1: {:.2} s CPU, {:.2} s wall, {} equilibria, {} starts left out",
        cpu_seconds() - cpu0,
        clock.elapsed().as_secs_f64(),
        found.len(),
        rejected.len()
    );
}
