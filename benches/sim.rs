//! Simulation benchmark: `cargo bench --bench sim [-- NAME...]`.
//! For each gallery example (default: all), the equilibrium of its strips
//! from the start placement (the design, or the rigid-fit placement of a
//! bent-facet lattice) at the design opening, on one core: wall time,
//! Newton iterations, Hessian assemblies and factorisations (those that
//! found the shifted Hessian indefinite in brackets), variables, energy,
//! largest strain and distance from the start. Also a 10 x 10-cell flat
//! sheet (100 cells). `--first-cell` holds the first cell's opening
//! instead of the mean of all cells.

use karigami::{
    deploy::deployment,
    simulation::{self as sim, Actuation, Settings},
};
use karigami_rods::solver::counts;
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

fn run(name: &str, text: &str, actuation: Actuation) {
    let d = match karigami::parse(text, name) {
        Ok(d) => d,
        Err(e) => return println!("{name}: does not parse: {}", e.message),
    };
    let lattice = match d.grow() {
        Ok(l) => l,
        Err(e) => return println!("{name}: does not grow: {}", e.message),
    };
    let dep = deployment(&lattice);
    let settings = Settings {
        theta: None,
        actuation,
        ..d.simulation
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
        }
        Err(e) => println!(
            "| {name} | {} | | | {cpu:.2} | {secs:.2} | failed: {e} | {work} | | | |",
            lattice.cells.len()
        ),
    }
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
        .filter(|a| !a.starts_with('-'))
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
    for path in names {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if !wanted.is_empty() && !wanted.contains(&name) {
            continue;
        }
        run(
            &name,
            &std::fs::read_to_string(&path).expect("readable"),
            actuation,
        );
    }
    if wanted.is_empty() || wanted.iter().any(|w| w == "sheet-10x10") {
        run("sheet-10x10", SHEET_100, actuation);
    }
}
