//! Derived data is computed once in the staged pipeline (`pipeline::check` ->
//! `Checked` -> `assemble` -> `Build`) and carried: the reports, the output
//! files and the CLI receive the placement, the measures, the joints, the
//! parts and the steps (`pipeline::Verified`, `Build`'s fields) and never place,
//! measure, join or make parts themselves; the simulation takes the
//! placement and joints the build hands it (`sim::simulate_with`).

use karigami::{build, build_text, check, check_json, check_text, measure, parse};

/// The derivations a stage could repeat: free-function calls (and the
/// placement, a method), as they are written in src/.
const DERIVATIONS: [&str; 6] = [
    ".placed()",
    "measure(",
    "measure_assembled(",
    "joints(",
    "parts(",
    "steps(",
];

/// How many times `token` is called in `source`: not as a method (`.x(`)
/// or a longer name, not where it is defined, not in comments.
fn calls(source: &str, token: &str) -> usize {
    source
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .map(|line| {
            line.match_indices(token)
                .filter(|&(i, _)| {
                    let before = &line[..i];
                    token.starts_with('.')
                        || !(before.ends_with(|c: char| c.is_alphanumeric() || "_.".contains(c))
                            || before.ends_with("fn "))
                })
                .count()
        })
        .sum()
}

fn sources(path: &str, out: &mut Vec<(String, String)>) {
    let p = std::path::Path::new(path);
    if p.is_dir() {
        for entry in std::fs::read_dir(p).unwrap() {
            sources(entry.unwrap().path().to_str().unwrap(), out);
        }
    } else if p.extension().is_some_and(|e| e == "rs") {
        out.push((path.to_string(), std::fs::read_to_string(p).unwrap()));
    }
}

#[test]
fn only_the_pipeline_derives_and_only_once() {
    // Everything above the pipeline reads what it carries.
    let mut above = Vec::new();
    for dir in [
        "src/report",
        "src/output.rs",
        "src/guide",
        "src/write",
        "src/drawing",
        "src/cli",
    ] {
        sources(dir, &mut above);
    }
    assert!(above.len() > 20, "the scan found the sources");
    for (path, text) in &above {
        for token in DERIVATIONS {
            assert_eq!(
                calls(text, token),
                0,
                "{path} calls {token}...): take it from the Build or pipeline::Verified"
            );
        }
    }
    // The pipeline derives each once.
    let pipeline = std::fs::read_to_string("src/pipeline.rs").unwrap();
    for token in [
        ".placed()",
        "measure_assembled(",
        "joints(",
        "parts(",
        "steps(",
    ] {
        assert_eq!(calls(&pipeline, token), 1, "src/pipeline.rs calls {token}");
    }
    assert_eq!(calls(&pipeline, "measure("), 0);
    // The build hands its placement and joints to the simulation
    // (`sim::simulate_with`), never the entry point that derives them again.
    assert_eq!(calls(&pipeline, "simulate_with("), 1);
    assert_eq!(
        calls(&pipeline, "simulate("),
        0,
        "src/pipeline.rs calls sim::simulate(: pass the Derived to simulate_with"
    );
    // The output files place the simulated shape once, for the preview and
    // the viewer both.
    let output = std::fs::read_to_string("src/output.rs").unwrap();
    assert_eq!(
        calls(&output, "placed_lattice("),
        1,
        "src/output.rs places the simulated shape more than once"
    );
}

/// The functions of `source`: each from its `fn` line to the next one.
fn functions(source: &str) -> Vec<String> {
    let mut out = vec![String::new()];
    for line in source.lines() {
        let t = line.trim_start();
        let t = t
            .strip_prefix("pub(crate) ")
            .or(t.strip_prefix("pub "))
            .unwrap_or(t);
        if t.starts_with("fn ") {
            out.push(String::new());
        }
        let last = out.last_mut().unwrap();
        last.push_str(line);
        last.push('\n');
    }
    out
}

#[test]
fn the_simulation_derives_only_in_its_standalone_entry_points() {
    // The simulation takes the placement and joints it is given (`Derived`);
    // a function of src/sim that places or joins a lattice itself is a
    // standalone entry point that hands them on to a `_with` form.
    let mut sim = Vec::new();
    sources("src/sim", &mut sim);
    assert!(sim.len() >= 3, "the scan found src/sim");
    let mut derivers = 0;
    for (path, text) in &sim {
        for f in functions(text) {
            if calls(&f, ".placed()") + calls(&f, "joints(") == 0 {
                continue;
            }
            derivers += 1;
            let head = f.lines().next().unwrap_or_default().trim();
            assert!(
                f.contains("_with(") || f.contains("with_derived("),
                "{path}: `{head}` places or joins the lattice without handing it on"
            );
        }
    }
    assert!(derivers >= 1, "the scan saw the entry points");
}

fn recipe(name: &str) -> karigami::Design {
    let text = std::fs::read_to_string(format!("examples/{name}.toml")).unwrap();
    parse(&text, name).unwrap()
}

#[test]
fn a_check_derives_on_first_use_and_keeps_it() {
    // An intrinsic lattice: its placement is a new lattice, made once.
    let checked = check(recipe("eggbox"), &mut |_| {}).unwrap();
    assert!(!checked.lattice.extrinsic());
    let (a, b) = (checked.verified(), checked.verified());
    assert!(std::ptr::eq(a.assembled, b.assembled), "placed once");
    assert!(!std::ptr::eq(a.assembled, &checked.lattice));
    assert!(std::ptr::eq(a.measures, b.measures), "measured once");
    assert!(
        std::ptr::eq(a.parts.unwrap(), b.parts.unwrap()),
        "parts made once"
    );
    // What was derived is what a fresh measurement gives.
    assert_eq!(*a.measures, measure(&checked.design, &checked.lattice));
    // The reports read it: the text and JSON agree with a build's.
    let text = check_text(&a);
    assert!(text.contains("part types: "), "{text}");
    assert!(check_json(&a)["shape"]["clash_count"].is_u64());
}

#[test]
fn a_build_carries_what_its_check_derived() {
    let checked = check(recipe("mirror-arm"), &mut |_| {}).unwrap();
    let shown = check_text(&checked.verified());
    let measures = checked.measures().clone();
    let built = checked.assemble().unwrap();
    assert_eq!(
        built.measures, measures,
        "the build keeps the check's measures"
    );
    // A build whose check showed nothing derives the same, once, itself.
    let fresh = build(recipe("mirror-arm")).unwrap();
    assert_eq!(fresh.measures, measures);
    assert_eq!(build_text(&built), build_text(&fresh));
    assert!(build_text(&built).contains(&shown));
}

/// `karigami check` on several jobs (the deployment and the shape beside
/// the placement, clashes and verification, from 10,000 cells) reports
/// what one thread and the lazy derivation report, to the byte; so does `-q`'s split (verification beside the deployment). A
/// plane sheet (C(theta) placing its cells as it takes them), an intrinsic
/// 3-D sheet (measured as assembled) and a plane loop (no grid: the
/// misfits in a pass of their own).
#[test]
fn a_check_on_any_jobs_reports_what_one_thread_does() {
    let sheet = "name = \"sheet-100x100\"\n[lattice]\nseed = \"sheet\"\nkappa = 0.0\n\
        [lattice.line]\nfrom = [0.0, 0.0]\nto = [2000.0, 0.0]\ncells = 100\n\
        [lattice.grow]\nrows = 100\nstart = 50\nangle = 45.0\n\
        [sheet]\nwidth = 3000.0\nheight = 2000.0\n";
    let bumps = "name = \"bumps\"\n[lattice]\nseed = \"sheet\"\nkappa = 0.0\n\
        [lattice.line]\nfrom = [0.0, 0.0, 0.0]\nto = [4000.0, 0.0, 0.0]\ncells = 100\n\
        [lattice.grow]\nrows = 100\nstart = 50\nangle = [40.0, 0.0]\n\
        left_leg = \"match\"\nright_leg = \"match\"\n\
        [[lattice.rows]]\nrow = 2\nfront = { zigzag = 15.0 }\n\
        [[lattice.rows]]\nrow = 50\nfront = { zigzag = 10.0 }\n";
    let ring = "name = \"ring\"\n[lattice]\nseed = \"loop\"\nkappa = 0.0\n\
        [lattice.circle]\ncenter = [0.0, 0.0]\nradius = 2000.0\npoints = 200\n\
        [lattice.grow]\nrows = 50\nangle = 60.0\n";
    for (name, text) in [("sheet", sheet), ("bumps", bumps), ("ring", ring)] {
        let design = parse(text, name).unwrap();
        let lazy = check(design.clone(), &mut |_| {}).unwrap();
        assert!(
            lazy.lattice.cells.len() >= 10_000,
            "{name}: large enough for two threads"
        );
        let (text, json) = (check_text(&lazy.verified()), check_json(&lazy.verified()));
        for (measure, jobs) in [(true, 2), (true, 1), (false, 2), (true, 3)] {
            let jobs = karigami::Jobs::new(jobs);
            let c = karigami::check_on(design.clone(), &mut |_| {}, measure, jobs).unwrap();
            assert_eq!(c.report, lazy.report, "{name} {measure} {jobs:?}");
            assert_eq!(check_text(&c.verified()), text, "{name} {measure} {jobs:?}");
            assert_eq!(check_json(&c.verified()), json, "{name} {measure} {jobs:?}");
        }
    }
}
