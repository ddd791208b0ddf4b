//! Bounded work (issue 36; docs/commands.md, "Time limits"): heavy work
//! estimated from the input and refused beyond the limit with the
//! estimate, and `--time-limit` stopping `simulate`, `build`, `check` and
//! `tune` cleanly, with exit status 4, saying how far they got and writing
//! nothing half-done; long work allowed says its estimate first. Then the
//! corpus swept against the time and memory ceilings.

use crate::cli::{karigami, recipes, repo, scratch};
use crate::safety::tree;
use std::path::Path;
use std::process::Output;
use std::time::Instant;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `o` exited with `code` and its stderr holds every one of `words`.
fn says(o: &Output, code: i32, words: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(code), "{e}");
    for w in words {
        assert!(e.contains(w), "{w:?} not in: {e}");
    }
}

/// `karigami ARGS` in `cwd` with the simulation's estimate reckoned a
/// hundred times low (`KARIGAMI_FAULT_RECKON`, a hook of the
/// `fault-injection` feature): a simulation the limit would refuse up
/// front starts, and its stop at the limit is seen in a fraction of a
/// second. None when the binary has no hooks.
fn reckoned_low(args: &[&str], cwd: &Path) -> Option<Output> {
    crate::safety::faults().then(|| {
        std::process::Command::new(env!("CARGO_BIN_EXE_karigami"))
            .args(args)
            .current_dir(cwd)
            .env("KARIGAMI_FAULT_RECKON", "0.01")
            .output()
            .expect("runs karigami")
    })
}

/// Finding 6: tune with `shape = "simulated"` and `budget = 100000` (about
/// 19 h) is refused before its search, at `[optimise]`, with the estimate,
/// the limit and the budget that fits.
#[test]
fn a_tune_of_hours_is_refused_with_its_estimate() {
    let clock = Instant::now();
    let o = karigami(
        &["tune", "fixtures/designs/limits/tune-simulated.toml"],
        &repo(),
    );
    says(
        &o,
        1,
        &[
            "error[WorkTooLong]: the optimiser may cost up to 200017 designs at about",
            "longer than the 1.0 h allowed",
            "tune-simulated.toml:",
            "[optimise] budget = ",
            "--time-limit",
        ],
    );
    // Refused after one design, not hours.
    assert!(clock.elapsed().as_secs() < 120, "{:?}", clock.elapsed());
}

/// Finding 6: `--explore` of more starts than the limit holds is refused
/// with the estimate and the most starts that fit.
#[test]
fn an_exploration_beyond_the_limit_is_refused() {
    let o = karigami(
        &[
            "simulate",
            "examples/eggbox.toml",
            "--explore",
            "10000",
            "--time-limit",
            "60",
            "-j",
            "1",
        ],
        &repo(),
    );
    says(
        &o,
        1,
        &[
            "error[WorkTooLong]: --explore 10000 would take about",
            "longer than the 60.0 s allowed",
            "use --explore ",
        ],
    );
}

/// A simulation estimated within the limit that outruns it stops in its
/// Newton solve: exit 4, how far it got, no report.
#[test]
fn simulate_stops_at_its_time_limit() {
    let args = ["simulate", "examples/eggbox.toml", "--time-limit", "0.3"];
    // Reckoned at about 5 s, the eggbox is refused up front...
    says(&karigami(&args, &repo()), 1, &["error[WorkTooLong]: "]);
    // ...and reckoned low, it starts and stops at the limit.
    let Some(o) = reckoned_low(&args, &repo()) else {
        return;
    };
    // The eggbox's solve takes about 0.3 s: it stops in the solve, or in
    // the deployment path after it, by the machine's speed.
    says(&o, 4, &["error[TimeLimit]: ", "the time limit of 0.3 s"]);
    let e = stderr(&o);
    assert!(
        e.contains("the simulation stopped at ") && e.contains("Newton iterations after 0.")
            || e.contains("stopped on the deployment path"),
        "{e}"
    );
    assert!(
        o.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
}

/// The deployment path (about 10 s on the half ellipsoid, reckoned low
/// here) stops at the time limit too, rather than running on after a
/// solve that fitted.
#[test]
fn the_deployment_path_stops_at_the_time_limit() {
    let clock = Instant::now();
    let Some(o) = reckoned_low(
        &[
            "simulate",
            "examples/half-ellipsoid.toml",
            "--time-limit",
            "2",
        ],
        &repo(),
    ) else {
        return;
    };
    let seconds = clock.elapsed().as_secs_f64();
    says(&o, 4, &["error[TimeLimit]: ", "the time limit of 2 s"]);
    assert!(seconds < 7.0, "stopped after {seconds:.1} s");
    assert!(
        o.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
}

/// The fit's row search (seconds with 2,000 samples a row) looks at the
/// time limit once a tilt of its scan, not only once a row.
#[test]
fn the_fit_search_stops_at_the_time_limit() {
    let args = [
        "check",
        "fixtures/designs/limits/ellipsoid-2000.toml",
        "--time-limit",
        "0.5",
    ];
    let (o, seconds) = cpu_seconds(&args, &repo());
    says(
        &o,
        4,
        &["error[TimeLimit]: ", "row search stopped at", "of 0.5 s"],
    );
    // CPU, not wall: a loaded machine (the suite's own threads) stretches
    // the wall time of a run that stops on time.
    assert!(seconds < 3.0, "stopped after {seconds:.1} s of CPU");
}

/// A run of the binary in `cwd`, as /usr/bin/time measures it.
struct Timed {
    output: Output,
    /// Wall seconds.
    wall: f64,
    /// User + system seconds, and the peak resident KiB, where
    /// /usr/bin/time is there to say them.
    cpu: Option<f64>,
    peak: Option<u64>,
}

fn timed(args: &[&str], cwd: &Path) -> Timed {
    let clock = Instant::now();
    let time = Path::new("/usr/bin/time");
    let output = if time.exists() {
        std::process::Command::new(time)
            .args(["-f", "timed %U %S %M"])
            .arg(env!("CARGO_BIN_EXE_karigami"))
            .args(args)
            .current_dir(cwd)
            .output()
            .unwrap()
    } else {
        karigami(args, cwd)
    };
    let wall = clock.elapsed().as_secs_f64();
    let line: Option<Vec<String>> = stderr(&output).lines().rev().find_map(|l| {
        Some(
            l.strip_prefix("timed ")?
                .split(' ')
                .map(str::to_string)
                .collect(),
        )
    });
    let field = |k: usize| line.as_ref().and_then(|f| f.get(k)?.parse::<f64>().ok());
    Timed {
        cpu: field(0).zip(field(1)).map(|(u, s)| u + s),
        peak: field(2).map(|kb| kb as u64),
        output,
        wall,
    }
}

/// A run of the binary in `cwd` and its CPU seconds (its wall seconds
/// where /usr/bin/time is missing).
fn cpu_seconds(args: &[&str], cwd: &Path) -> (Output, f64) {
    let t = timed(args, cwd);
    let seconds = t.cpu.unwrap_or(t.wall);
    (t.output, seconds)
}

/// `explore_until` stops at its deadline with the starts solved so far;
/// without one it is `explore`.
#[test]
fn explore_stops_at_its_deadline() {
    use karigami::simulation as sim;
    use std::sync::atomic::AtomicUsize;
    let text = std::fs::read_to_string(repo().join("examples/mirror-arm.toml")).unwrap();
    let design = karigami::parse(&text, "mirror-arm").unwrap();
    let checked = karigami::check(design, &mut |_| {}).unwrap();
    let (d, l) = (&checked.design, &checked.lattice);
    let m = &d.fabrication.material;
    let run = sim::simulate(l, &checked.deployment, m.width, m.thickness, &d.simulation).unwrap();
    let finish = |lm: &sim::LatticeModel, s| sim::equilibrium(lm, s, &d.simulation.material);
    let solved = AtomicUsize::new(0);
    let now = karigami::Deadline::after(0.0);
    let stopped = sim::explore::explore_until(&run.lm, (40, 2024), 1, &finish, &solved, &now)
        .expect_err("stops");
    assert_eq!((stopped.done, stopped.of), (0, 40), "{stopped}");
    assert!(
        stopped
            .to_string()
            .starts_with("stopped at 0 of 40 starts after 0.0 s")
    );
    let never = karigami::Deadline::none();
    let (found, rejected) =
        sim::explore::explore_until(&run.lm, (7, 2024), 2, &finish, &solved, &never).unwrap();
    let (found0, rejected0) = sim::explore::explore(&run.lm, 7, 2024, 1, &finish, &solved);
    assert_eq!(found.len(), found0.len());
    assert_eq!(rejected, rejected0);
}

/// A build stopped at its limit leaves the earlier build as it was and
/// nothing beside it; `check` stops the same way.
#[test]
fn a_stopped_build_leaves_the_old_build_and_no_staging() {
    let dir = scratch("limits-build");
    let eggbox = repo().join("examples/eggbox.toml");
    std::fs::copy(&eggbox, dir.join("eggbox.toml")).unwrap();
    let chain = std::fs::read_to_string(repo().join("templates/chain.toml")).unwrap();
    std::fs::write(dir.join("chain.toml"), chain).unwrap();
    let first = karigami(&["-q", "build", "chain.toml", "--out", "out"], &dir);
    assert_eq!(first.status.code(), Some(0), "{}", stderr(&first));
    let before = tree(&dir.join("out"));
    let Some(o) = reckoned_low(
        &[
            "build",
            "eggbox.toml",
            "--out",
            "out",
            "--time-limit",
            "0.3",
        ],
        &dir,
    ) else {
        return;
    };
    says(&o, 4, &["error[TimeLimit]: ", "the time limit of 0.3 s"]);
    assert_eq!(tree(&dir.join("out")), before, "--out changed");
    let beside: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(beside.is_empty(), "left beside --out: {beside:?}");
    let o = reckoned_low(&["check", "eggbox.toml", "--time-limit", "0.3"], &dir);
    says(&o.expect("hooks"), 4, &["error[TimeLimit]: "]);
}

/// The helix tuner's work is reckoned before it starts (tries times the
/// cells its start seed grows) and refused beyond the limit, with the
/// estimate, the limit and the tries that fit; at the recipe's `cells`
/// when they are the recipe's. Nothing is written.
#[test]
fn a_helix_tune_beyond_the_limit_is_refused_up_front() {
    let dir = scratch("limits-tune-refused");
    let helix = std::fs::read_to_string(repo().join("templates/helix.toml")).unwrap();
    std::fs::write(dir.join("h.toml"), &helix).unwrap();
    let args = [
        "tune",
        "h.toml",
        "--iterations",
        "5000000",
        "--out",
        "h.toml",
    ];
    let flagged = [&args[..], &["--cells", "100000", "--time-limit", "0.5"]].concat();
    let clock = Instant::now();
    let o = karigami(&flagged, &dir);
    says(
        &o,
        1,
        &[
            "error[WorkTooLong]: the helix tuner may make up to 5,000,000 tries of a seed that grows ",
            "of 100,000 cells (--cells) at about ",
            "longer than the 500 ms allowed",
            "use --iterations ",
            "or fewer (now 5000000)",
        ],
    );
    assert!(clock.elapsed().as_secs() < 10, "{:?}", clock.elapsed());
    assert_eq!(std::fs::read_to_string(dir.join("h.toml")).unwrap(), helix);
    // The recipe's own `cells`, located where it is written.
    let big = helix.replace("\ncells = 12\n", "\ncells = 100000\n");
    assert_ne!(big, helix);
    std::fs::write(dir.join("big.toml"), &big).unwrap();
    let o = karigami(
        &[
            "tune",
            "big.toml",
            "--iterations",
            "5000000",
            "--time-limit",
            "0.5",
        ],
        &dir,
    );
    says(
        &o,
        1,
        &[
            "error[WorkTooLong]: ",
            "(the recipe's `cells`)",
            "big.toml:12:9",
        ],
    );
}

/// A tune reckoned within its limit that outruns it (its seeds growing on
/// as they are tuned, or a slower build than the estimate's) stops at the
/// limit, says how far it got and writes no recipe.
#[test]
fn tune_stops_at_its_time_limit_and_writes_nothing() {
    let dir = scratch("limits-tune");
    let helix = std::fs::read_to_string(repo().join("templates/helix.toml")).unwrap();
    std::fs::write(dir.join("h.toml"), &helix).unwrap();
    // 4,000,000 tries of the 18 cells the start seed grows are reckoned at
    // about 29 s, a hundred times low here (`reckoned_low`): allowed, and
    // far past the limit on any machine.
    let Some(o) = reckoned_low(
        &[
            "tune",
            "h.toml",
            "--cells",
            "100000",
            "--iterations",
            "4000000",
            "--out",
            "h.toml",
            "--time-limit",
            "0.4",
        ],
        &dir,
    ) else {
        return;
    };
    says(
        &o,
        4,
        &[
            "the tuner stopped at ",
            "of 4000000 tries",
            "nothing was written",
        ],
    );
    assert_eq!(std::fs::read_to_string(dir.join("h.toml")).unwrap(), helix);
}

/// The tuner stopped by its deadline returns the seed so far with the
/// tries made: none, at a deadline already passed.
#[test]
fn the_helix_tuner_stops_at_its_deadline() {
    let text = std::fs::read_to_string(repo().join("templates/helix.toml")).unwrap();
    let d = karigami::parse(&text, "helix").unwrap();
    let tries = (12, 8.5, 1000);
    let now = karigami::Deadline::after(0.0);
    let stopped =
        karigami::tune_helix_until(d.dim, &d.points, &d.kappa, tries, &now).expect_err("stops");
    assert_eq!(stopped.iterations, 0);
    let never = karigami::Deadline::none();
    let done = karigami::tune_helix_until(d.dim, &d.points, &d.kappa, tries, &never).unwrap();
    assert_eq!(done.iterations, 1000);
}

/// The first line of `karigami ARGS`'s stderr that holds `word`, the run
/// killed as soon as it is read (the work it announces is not done), and
/// the seconds it took to come; None when the run ends without one.
fn said_first(args: &[&str], cwd: &Path, word: &str) -> (Option<String>, f64) {
    use std::io::BufRead;
    let clock = Instant::now();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_karigami"))
        .args(args)
        .current_dir(cwd)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let err = std::io::BufReader::new(child.stderr.take().unwrap());
    let line = err.lines().map_while(Result::ok).find(|l| l.contains(word));
    let _ = child.kill();
    child.wait().unwrap();
    (line, clock.elapsed().as_secs_f64())
}

/// The torus example: a simulation reckoned at about 34 s (5,664 rod
/// nodes, its deployment path of 24 steps each way most of it; measured
/// 51 to 86 s), where check and build reach it in a second or two.
fn long_simulation(dir: &Path) {
    std::fs::copy(repo().join("examples/torus.toml"), dir.join("torus.toml")).unwrap();
}

/// Work reckoned at 5 s or more says so on stderr before it starts, with
/// what was counted and the limit; `check`, `build`, `simulate` and the
/// helix tuner alike (each run killed once it has said it). `-q` says
/// nothing.
#[test]
fn long_work_says_its_estimate_first() {
    let dir = scratch("limits-said");
    long_simulation(&dir);
    let limit = ["--time-limit", "60"];
    let mut slowest: f64 = 0.0;
    for command in [
        &["check", "torus.toml"][..],
        &["simulate", "torus.toml"],
        &["build", "torus.toml", "--out", "out"],
    ] {
        let args = [command, &limit].concat();
        let (line, seconds) = said_first(&args, &dir, "estimated");
        let line = line.unwrap_or_else(|| panic!("{command:?}: no estimate said"));
        for w in [
            "torus.toml: estimated ",
            " s (simulation: 5,664 rod nodes x ~",
            " Newton iterations, the deployment path's 24 steps each way included); it stops at the --time-limit of 60.0 s",
        ] {
            assert!(line.contains(w), "{command:?}: {w:?} not in {line}");
        }
        slowest = slowest.max(seconds);
    }
    assert!(!dir.join("out").exists(), "a build killed wrote --out");
    // Without a limit it says how to give one.
    let (line, _) = said_first(&["simulate", "torus.toml"], &dir, "estimated");
    assert!(
        line.is_some_and(|l| l.ends_with("; give --time-limit SECONDS to bound it")),
        "no estimate said without a limit"
    );
    // The helix tuner: 500,000 tries of the helix bowl's 38 cells, about 7 s.
    let bowl = std::fs::read_to_string(repo().join("fixtures/designs/helix-bowl.toml")).unwrap();
    let helix = &bowl[..bowl.find("\n[optimise]").unwrap()];
    std::fs::write(dir.join("bowl.toml"), helix).unwrap();
    let tune = [
        "tune",
        "bowl.toml",
        "--cells",
        "200",
        "--iterations",
        "500000",
    ];
    let (line, _) = said_first(&tune, &dir, "estimated");
    let line = line.expect("the tuner says its estimate");
    assert!(
        line.starts_with("bowl.toml: estimated ")
            && line.contains(
                "(helix tuner: up to 500,000 tries of ~38 cells (the start seed grows 38 of 200), ~"
            ),
        "{line}"
    );
    // -q: nothing on stderr by the time the line came, and well after.
    let mut quiet = std::process::Command::new(env!("CARGO_BIN_EXE_karigami"))
        .args(["-q", "check", "torus.toml", "--time-limit", "60"])
        .current_dir(&dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_secs_f64(2.0 * slowest + 0.5));
    let _ = quiet.kill();
    let o = quiet.wait_with_output().unwrap();
    assert!(o.stderr.is_empty(), "-q said: {}", stderr(&o));
}

/// `design` reckons its row search and candidate builds from the target's
/// area in cells before it starts: refused beyond the limit, at the
/// target, with the edge that fits, writing nothing; said first when long.
#[test]
fn a_design_beyond_the_limit_is_refused_and_a_long_one_said() {
    let dir = scratch("limits-design");
    let target = repo().join("fixtures/targets/sphere-cap.toml");
    let target = target.to_string_lossy();
    let ask = ["design", &target, "--out", "cap.toml", "--time-limit"];
    let o = karigami(&[&ask[..], &["10"]].concat(), &dir);
    says(
        &o,
        1,
        &[
            "error[WorkTooLong]: designing for this target at a cell edge of 60.0 mm may take about ",
            "(row search of up to 8 seeds, ~",
            "candidate builds of ~189 cells",
            "longer than the 10.0 s allowed",
            "sphere-cap.toml",
            "give a larger --edge, 119.6 mm or more",
        ],
    );
    assert!(!dir.join("cap.toml").exists());
    let (line, _) = said_first(&[&ask[..], &["300"]].concat(), &dir, "estimated");
    let line = line.expect("design says its estimate");
    assert!(
        line.starts_with("design: estimated ")
            && line.ends_with("; it stops at the --time-limit of 5 min"),
        "{line}"
    );
    assert!(!dir.join("cap.toml").exists());
}

/// A design reckoned within its limit that outruns it (here reckoned a
/// hundred times low, `reckoned_low`) stops: its search at its share of
/// the limit, keeping the rest for the builds, and a design none of whose
/// candidates could be built in time is a time-limit stop (exit 4) that
/// says how far it got and writes nothing, not a design that builds none.
#[test]
fn a_design_that_outruns_its_limit_stops_and_writes_nothing() {
    let dir = scratch("limits-design-stop");
    let target = repo().join("fixtures/targets/sphere-cap.toml");
    let target = target.to_string_lossy();
    let args = ["design", &target, "--out", "cap.toml", "--time-limit", "1"];
    let Some(o) = reckoned_low(&args, &dir) else {
        return;
    };
    says(
        &o,
        4,
        &[
            "sphere-cap.toml: stopped after ",
            " seed search",
            " found",
            "nothing was written",
        ],
    );
    assert!(!dir.join("cap.toml").exists());
}

/// Short work says no estimate.
#[test]
fn short_work_says_no_estimate() {
    for command in ["check", "simulate"] {
        let o = karigami(&[command, "templates/chain.toml"], &repo());
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        assert!(!stderr(&o).contains("estimated"), "{}", stderr(&o));
    }
}

/// A batch says a long recipe's estimate as that recipe's simulation
/// starts, in the words a single build uses, and `-q` silences it; the
/// optimiser (`tune` with `[optimise]`) says its estimate in the same one
/// line.
#[test]
fn a_batch_and_the_optimiser_say_their_estimates_first() {
    let dir = scratch("limits-said-batch");
    long_simulation(&dir);
    let chain = std::fs::read_to_string(repo().join("templates/chain.toml")).unwrap();
    std::fs::write(dir.join("chain.toml"), chain).unwrap();
    let batch = ["build", "chain.toml", "torus.toml", "--out", "out"];
    let (line, seconds) = said_first(&batch, &dir, "estimated");
    let line = line.expect("the batch says the torus's estimate");
    assert!(
        line.starts_with("torus.toml: estimated ")
            && line.contains("(simulation: 5,664 rod nodes x ~")
            && line.ends_with("; give --time-limit SECONDS to bound it"),
        "{line}"
    );
    let mut quiet = std::process::Command::new(env!("CARGO_BIN_EXE_karigami"))
        .args(["-q"].iter().chain(&batch))
        .current_dir(&dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_secs_f64(2.0 * seconds + 0.5));
    let _ = quiet.kill();
    let o = quiet.wait_with_output().unwrap();
    assert!(o.stderr.is_empty(), "-q said: {}", stderr(&o));
    // The optimiser of hours, allowed a year: said after its first design.
    let tune = [
        "tune",
        "fixtures/designs/limits/tune-simulated.toml",
        "--time-limit",
        "32000000",
    ];
    let (line, _) = said_first(&tune, &repo(), "estimated");
    let line = line.expect("the optimiser says its estimate");
    assert!(
        line.starts_with("fixtures/designs/limits/tune-simulated.toml: estimated ")
            && line.contains(" (optimiser: up to 200,017 designs of ~")
            && line.contains("; it stops at the --time-limit of "),
        "{line}"
    );
}

/// Seconds and KiB of peak memory of one run of the binary in `cwd`.
fn measured(args: &[&str], cwd: &Path) -> (Output, f64, Option<u64>) {
    let t = timed(args, cwd);
    (t.output, t.wall, t.peak)
}

/// The sweep: every recipe of the corpus (examples, templates, the bad
/// fixtures, the limits' fixtures) through `check` and `simulate` within
/// the time and memory ceilings; huge inputs are refused, not run. CI runs
/// the corpus once with an 8 s `--time-limit`, so a long fit or simulation
/// (the 2,000-cell ellipsoid's) shows that it stops there; `scripts/fuzz`
/// sets `KARIGAMI_SWEEP_CEILING` to 60 s on a release build, where every
/// input of the corpus finishes.
#[test]
fn no_input_of_the_corpus_exceeds_the_time_and_memory_ceilings() {
    let ceiling: f64 = std::env::var("KARIGAMI_SWEEP_CEILING")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(8.0);
    // The default memory ceiling (2 GiB) and the run's own overhead.
    let memory_kb: u64 = 2 * 1024 * 1024 + 256 * 1024;
    let mut slow = Vec::new();
    // The suite's size leaves out the examples (about 190 s of debug
    // builds' solves, which the gallery's tests build anyway);
    // `scripts/fuzz` sets KARIGAMI_SWEEP_FULL and sweeps them too.
    let full = std::env::var_os("KARIGAMI_SWEEP_FULL").is_some();
    let corpus = [
        "examples",
        "templates",
        "fixtures/designs/bad",
        "fixtures/designs/limits",
    ];
    for folder in corpus.into_iter().filter(|f| full || *f != "examples") {
        for path in recipes(folder) {
            let file = path.to_string_lossy().into_owned();
            for command in ["check", "simulate"] {
                let limit = ceiling.to_string();
                let args = ["-q", command, &file, "--time-limit", &limit];
                let (o, seconds, peak) = measured(&args, &repo());
                let code = o.status.code();
                assert!(
                    matches!(code, Some(0..=4)),
                    "{command} {file}: {code:?}: {}",
                    stderr(&o)
                );
                if seconds > ceiling + 5.0 || peak.is_some_and(|p| p > memory_kb) {
                    slow.push(format!("{command} {file}: {seconds:.1} s, {peak:?} KB"));
                }
            }
        }
    }
    assert!(slow.is_empty(), "beyond the ceilings: {slow:#?}");
}

/// Finding 1: a simulation whose mesh would pass the memory ceiling is
/// refused before it is made, with the edge length that fits, never a
/// panic or an abort: the 20,000-cell sheet at the default 2 GiB and at
/// `--memory 64`, and the sheet template stretched to a kilometre
/// (`to = [240.0, 1e6]`, once an out-of-memory panic).
#[test]
fn finding_1_a_mesh_beyond_the_memory_ceiling_is_refused_before_it_is_made() {
    let huge = ["simulate", "fixtures/designs/limits/huge-sheet.toml"];
    let words = [
        "error[SimulationTooLarge]: ",
        "huge-sheet.toml",
        "edge_length = ",
    ];
    says(&karigami(&huge, &repo()), 1, &words);
    let small = [&huge[..], &["--memory", "64"]].concat();
    says(
        &karigami(&small, &repo()),
        1,
        &[&words[..], &["64 MiB"]].concat(),
    );
    let dir = crate::cli::scratch("limits-memory");
    let sheet = std::fs::read_to_string(repo().join("templates/sheet.toml")).unwrap();
    assert!(sheet.contains("to = [240.0, 0.0]"));
    std::fs::write(
        dir.join("km.toml"),
        sheet.replace("to = [240.0, 0.0]", "to = [240.0, 1e6]"),
    )
    .unwrap();
    let o = karigami(&["simulate", "km.toml"], &dir);
    let e = stderr(&o);
    assert!(!e.contains("panicked") && o.status.code() == Some(1), "{e}");
    assert!(e.contains("km.toml"), "{e}");
}
