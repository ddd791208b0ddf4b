//! Helpers shared by the integration tests.
#![allow(dead_code)]

use glam::DVec3;
use karigami::{Build, Overrides, Unsimulated, build_unsimulated, parse_with};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, Once, OnceLock};

pub(crate) fn v2(x: f64, y: f64) -> DVec3 {
    DVec3::new(x, y, 0.0)
}

/// Assert two numbers agree to `tol` (absolute), with a useful message.
#[track_caller]
pub(crate) fn close(actual: f64, expected: f64, tol: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= tol,
        "{what}: got {actual:.15}, expected {expected:.15} (tol {tol:e})"
    );
}

#[track_caller]
pub(crate) fn close_vec(actual: DVec3, expected: DVec3, tol: f64, what: &str) {
    assert!(
        actual.distance(expected) <= tol,
        "{what}: got {actual:?}, expected {expected:?} (tol {tol:e})"
    );
}

/// The library's deterministic generator (SplitMix64) with the draws the
/// property tests use, so the cases are the same on every run.
pub(crate) struct Rng(karigami_rods::rng::Rng);

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Self(karigami_rods::rng::Rng::new(seed))
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in [lo, hi).
    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }

    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// One item of a non-empty slice.
    pub(crate) fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

// Shared builds. Building the example recipes is most of the test time, and
// many tests only read a build: each recipe (with its overrides or CLI flags)
// is built once per test process and shared. A test that checks building
// itself (determinism, flags, faults) still builds its own.

type Slots<T> = OnceLock<Mutex<HashMap<String, &'static OnceLock<T>>>>;

/// The slot for `key`, made on first use. The map is locked only to find the
/// slot: different keys build in parallel, one key builds once (a second
/// test waits for the first).
fn slot<T: Send + Sync>(slots: &'static Slots<T>, key: String) -> &'static OnceLock<T> {
    let mut map = slots
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    map.entry(key).or_insert_with(|| Box::leak(Box::default()))
}

/// `examples/<name>.toml` (a path under the repository or a bare name).
fn example_path(name: &str) -> PathBuf {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    if name.ends_with(".toml") {
        repo.join(name)
    } else {
        repo.join("examples").join(format!("{name}.toml"))
    }
}

/// A fresh in-process build of an example recipe, for tests that compare two
/// builds or change one.
pub(crate) fn build_example(name: &str, o: &Overrides) -> Build {
    simulated(name, o, None)
}

/// `unsimulated(name, o)` simulated, restored from `state` when nothing
/// the simulation reads differs (as `build` does with no state).
fn simulated(name: &str, o: &Overrides, state: Option<&[u8]>) -> Build {
    unsimulated(name, o)
        .simulate(state)
        .unwrap_or_else(|e| panic!("{}: {e:?}", example_path(name).display()))
}

/// An example recipe built in-process with `o`, once per test process.
/// A gallery example's simulation is restored from its shared CLI build
/// (`cli_build`, which the cut-file and guide tests read for every
/// example anyway) when nothing the simulation reads differs, as a rebuild
/// restores it (docs/commands.md, "Rebuilds reuse the simulation"); else
/// it is solved here.
pub(crate) fn example_with(name: &str, o: &Overrides) -> &'static Build {
    static BUILDS: Slots<Build> = OnceLock::new();
    let path = example_path(name);
    slot(&BUILDS, format!("{} {o:?}", path.display())).get_or_init(|| {
        let gallery = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples");
        // None for a lattice that is not simulated (a planar mechanism).
        let state = (path.parent() == Some(gallery.as_path()))
            .then(|| std::fs::read(cli_build(name, &[]).join(karigami::STATE_FILE)).ok())
            .flatten();
        simulated(name, o, state.as_deref())
    })
}

/// A recipe grown, verified, cut and laid out with `o`, without its
/// simulation, once per test process: for tests that read only the
/// lattice, parts, layout and pages.
pub(crate) fn unsimulated_with(name: &str, o: &Overrides) -> &'static Build {
    static BUILDS: Slots<Unsimulated> = OnceLock::new();
    let path = example_path(name);
    slot(&BUILDS, format!("{} {o:?}", path.display()))
        .get_or_init(|| unsimulated(name, o))
        .build()
}

/// A fresh build of a recipe up to its simulation (`unsimulated_with`).
pub(crate) fn unsimulated(name: &str, o: &Overrides) -> Unsimulated {
    let path = example_path(name);
    let text = std::fs::read_to_string(&path).unwrap();
    let stem = path.file_stem().unwrap().to_string_lossy();
    build_unsimulated(parse_with(&text, &stem, o).unwrap(), &mut |_| {})
        .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()))
}

/// An example recipe built in-process with its own settings, once per test process.
pub(crate) fn example(name: &str) -> &'static Build {
    example_with(name, &Overrides::default())
}

/// `karigami build <recipe> <flags> --out out` (with `--jobs 2` unless the
/// flags give a number) run once per test process in
/// target/test-scratch/shared/; the output folder, for tests that only read it.
pub(crate) fn cli_build(name: &str, flags: &[&str]) -> &'static Path {
    prefetch_gallery();
    shared_build(name, flags)
}

/// The gallery's recipes, the dearest to build first (debug builds,
/// 2026-12-03: the torus 52 s of CPU, the half-ellipsoid 16 s, the bowl
/// 9 s; 2026-12-04: the saddle ring 7.3 s; the others 5 s or less).
pub(crate) const GALLERY: [&str; 9] = [
    "torus",
    "half-ellipsoid",
    "bowl",
    "saddle-ring",
    "eggbox",
    "flat-sheet",
    "disk",
    "curved-sheet",
    "mirror-arm",
];

/// Start the shared builds of the whole gallery on two threads of their
/// own, once, at the first `cli_build`: a test waiting for a build another
/// test is making holds its thread idle, and most readers of a build read
/// several, so building ahead, dearest first, keeps the cores busy. Each
/// build runs on one core, and the torus alone costs about what the other
/// eight do together (debug builds: 52 s of CPU against 51 s), so two
/// threads have the whole gallery in half the time one takes.
fn prefetch_gallery() {
    static STARTED: Once = Once::new();
    STARTED.call_once(|| {
        std::thread::spawn(|| {
            each_in_parallel(&GALLERY, 2, |name| {
                // A failed build panics here and again in the test that
                // reads it, which reports it.
                let _ = std::panic::catch_unwind(|| shared_build(name, &[]));
            });
        });
    });
}

/// `f` on each of `items`, on `workers` threads taking the items in order:
/// for a test that runs many independent commands (dearest first).
pub(crate) fn each_in_parallel<T: Sync>(items: &[T], workers: usize, f: impl Fn(&T) + Sync) {
    let next = std::sync::atomic::AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..workers.max(1) {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some(item) = items.get(i) else { break };
                    f(item);
                }
            });
        }
    });
}

/// `cli_build` without the prefetch.
fn shared_build(name: &str, flags: &[&str]) -> &'static Path {
    static OUTS: Slots<PathBuf> = OnceLock::new();
    let recipe = example_path(name);
    let key = format!("{} {}", recipe.display(), flags.join(" "));
    slot(&OUTS, key).get_or_init(|| {
        let tag: String = format!(
            "{} {}",
            recipe.file_stem().unwrap().to_string_lossy(),
            flags.join(" ")
        )
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
        let dir = crate::cli::scratch(&format!("shared/{tag}"));
        let mut args = vec!["build", recipe.to_str().unwrap()];
        args.extend_from_slice(flags);
        // Two jobs whatever the machine: the batch test compares these
        // folders with a one-job batch.
        if !flags.contains(&"--jobs") {
            args.extend(["--jobs", "2"]);
        }
        args.extend(["--out", "out"]);
        let o = crate::cli::karigami(&args, &dir);
        assert!(
            o.status.success(),
            "karigami {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&o.stderr)
        );
        dir.join("out")
    })
}

/// The flags that fit the torus example to its torus: the check of every
/// example and the fit's own test share that one check.
pub(crate) const TORUS_TARGET: [&str; 2] = ["--target", "fixtures/targets/torus.toml"];

/// `karigami check examples/<name>.toml`, once per test process, reusing
/// the simulation of the shared build (`cli_build`): each gallery shape is
/// solved once in the suite, and the build's own tests cover that solve
/// (a check that reuses nothing is `check_reuses_what_a_build_solved`'s).
/// The torus is fitted to its torus too (`TORUS_TARGET`).
pub(crate) fn gallery_check(name: &str) -> &'static std::process::Output {
    let built = cli_build(name, &[]).to_str().unwrap().to_string();
    let mut flags = vec!["--reuse", built.as_str()];
    if name == "torus" {
        flags.extend(TORUS_TARGET);
    }
    cli_check(&format!("examples/{name}.toml"), &flags)
}

/// `karigami check <recipe> <flags>`, the recipe a path under the
/// repository, run there once per test process; its output.
pub(crate) fn cli_check(recipe: &str, flags: &[&str]) -> &'static std::process::Output {
    static RUNS: Slots<std::process::Output> = OnceLock::new();
    let key = format!("{recipe} {}", flags.join(" "));
    slot(&RUNS, key).get_or_init(|| {
        let mut args = vec!["check", recipe];
        args.extend_from_slice(flags);
        crate::cli::karigami(&args, &crate::cli::repo())
    })
}

/// A JSON array of numbers as floats (panics on anything else: a test's
/// own files).
pub(crate) fn floats(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}
