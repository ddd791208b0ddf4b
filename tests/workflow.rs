//! The maker workflow: batch builds, templates, JSON reports, completions.

use crate::cli::{karigami, recipes, repo, scratch};
use serde_json::Value;
use std::collections::BTreeMap;
use std::fs;
use std::path::Path;

/// Every file under `dir` with its bytes, by relative path.
pub(crate) fn tree(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).unwrap().to_string_lossy().into_owned();
                out.insert(rel, fs::read(&p).unwrap());
            }
        }
    }
    out
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// The gallery's three dearest simulations (debug builds: the torus 52 s
/// of CPU, the half-ellipsoid 16 s, the bowl 9 s; `util::GALLERY`): the
/// batch test leaves them out, since nothing a batch does depends on a
/// recipe's size, and every other kind of lattice (sheet, disk, loop, bumps,
/// chain) is in it.
const DEAREST: [&str; 3] = ["half-ellipsoid", "bowl", "torus"];

/// A batch of the gallery with one job writes, for each recipe, the same
/// files as its own build with two jobs (the shared builds of
/// `util::cli_build`, which run with `--jobs 2`): one batch, not two, so
/// the examples are built twice in all, not three times. The recipes are
/// copied, with the targets they name (`../fixtures/targets/…`).
#[test]
fn a_batch_gives_the_same_files_with_one_job_or_two() {
    let dir = scratch("batch-jobs");
    let (examples, targets) = (dir.join("examples"), dir.join("fixtures/targets"));
    fs::create_dir_all(&examples).unwrap();
    fs::create_dir_all(&targets).unwrap();
    let chosen: Vec<_> = recipes("examples")
        .into_iter()
        .filter(|r| !DEAREST.contains(&r.file_stem().unwrap().to_str().unwrap()))
        .collect();
    for r in &chosen {
        fs::copy(r, examples.join(r.file_name().unwrap())).unwrap();
    }
    for t in fs::read_dir(repo().join("fixtures/targets")).unwrap() {
        let t = t.unwrap().path();
        if t.is_file() {
            fs::copy(&t, targets.join(t.file_name().unwrap())).unwrap();
        }
    }
    let o = karigami(&["build", "examples", "--out", "one", "--jobs", "1"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(
        stdout.contains("recipe") && stdout.contains("strips"),
        "{stdout}"
    );
    let n = chosen.len();
    assert!(n >= 5, "{n} recipes");
    let mut files = 0;
    for r in chosen {
        let stem = r.file_stem().unwrap().to_str().unwrap();
        let one = tree(&dir.join("one").join(stem));
        // The build folder's marker sits at the batch's root.
        let mut two = tree(crate::util::cli_build(stem, &[]));
        two.remove(".karigami-build");
        assert_eq!(
            one.keys().collect::<Vec<_>>(),
            two.keys().collect::<Vec<_>>(),
            "{stem}"
        );
        for (name, bytes) in &one {
            assert!(
                bytes == &two[name],
                "{stem}/{name} differs between --jobs 1 and --jobs 2"
            );
        }
        assert!(one.contains_key("lattice.json"), "{stem}");
        assert!(one.contains_key("cut.pdf"), "{stem}");
        files += one.len();
    }
    assert!(files > 8 * n, "{files} files for {n} recipes");
}

/// The batch starts the dearest recipes first by a guess read off each
/// recipe without growing it: the guess must count the cells growth then
/// makes, and weigh them as simulated exactly where the build solves an
/// equilibrium over Newton iterations (out of the plane or bent facets, up
/// to the simulation's cell limit).
#[test]
fn the_batch_order_guesses_cells_and_simulation_as_built() {
    let mut costs = Vec::new();
    for r in recipes("examples").into_iter().chain(recipes("templates")) {
        let text = fs::read_to_string(&r).unwrap();
        let stem = r.file_stem().unwrap().to_string_lossy();
        let design = karigami::parse(&text, &stem).unwrap();
        let lattice = design.grow().unwrap();
        let cells = lattice.cells.len();
        let iterated = lattice.dim == 3 || !lattice.extrinsic();
        let weight = if iterated && cells <= 2_000 { 50 } else { 1 };
        assert_eq!(
            karigami::build_cost(&design),
            cells * weight,
            "{}: {cells} cells, simulated over iterations: {iterated}",
            r.display()
        );
        costs.push((karigami::build_cost(&design), iterated));
    }
    // Every recipe whose build iterates towards an equilibrium starts before
    // every one whose strips are solved at once (the gallery's lattices are
    // all small enough that cells alone do not reorder them).
    let cheapest_iterated = costs.iter().filter(|c| c.1).map(|c| c.0).min();
    let dearest_direct = costs.iter().filter(|c| !c.1).map(|c| c.0).max();
    assert!(cheapest_iterated > dearest_direct, "{costs:?}");
}

#[test]
fn a_broken_recipe_fails_alone_and_is_named() {
    let dir = scratch("batch-broken");
    let recipes_dir = dir.join("recipes");
    fs::create_dir_all(&recipes_dir).unwrap();
    for name in ["flat-sheet.toml", "mirror-arm.toml"] {
        fs::copy(repo().join("examples").join(name), recipes_dir.join(name)).unwrap();
    }
    fs::write(
        recipes_dir.join("broken.toml"),
        "name = \"broken\"\n[lattice]\nseed = \"sheet\"\npoints = [[0.0, 0.0], [10.0, 0.0]]\nkappa = [25.0]\n[lattice.grow]\nrows = 2\nangle = 45.0\nleft_leg = 10.0\n",
    )
    .unwrap();
    let o = karigami(&["build", "recipes", "--out", "out", "--jobs", "2"], &dir);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    let stderr = text(&o.stderr);
    assert!(
        stderr.contains("broken.toml:5:"),
        "the error points at the line: {stderr}"
    );
    assert!(
        stderr.contains("1 of 3 recipes failed: recipes/broken.toml"),
        "{stderr}"
    );
    let stdout = text(&o.stdout);
    let row = stdout.lines().find(|l| l.contains("broken.toml")).unwrap();
    assert!(row.contains("FAILED"), "{stdout}");
    assert!(dir.join("out/flat-sheet/cut.pdf").is_file());
    assert!(dir.join("out/mirror-arm/lattice.json").is_file());
    assert!(!dir.join("out/broken").exists());
    let batch: Value =
        serde_json::from_slice(&fs::read(dir.join("out/batch.json")).unwrap()).unwrap();
    let statuses: Vec<(&str, &str)> = batch
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r["folder"].as_str().unwrap(), r["status"].as_str().unwrap()))
        .collect();
    assert_eq!(
        statuses,
        [
            ("broken", "error"),
            ("flat-sheet", "ok"),
            ("mirror-arm", "ok")
        ]
    );
    assert_eq!(batch[0]["error"]["line"], 5);
}

#[test]
fn a_batch_output_folder_is_replaced_whole_and_foreign_folders_refused() {
    let dir = scratch("batch-replace");
    let a = repo().join("examples/mirror-arm.toml");
    let b = repo().join("examples/flat-sheet.toml");
    let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
    assert!(
        karigami(&["build", a, b, "--out", "out"], &dir)
            .status
            .success()
    );
    let o = karigami(&["build", a, a, "--out", "out"], &dir);
    assert_eq!(
        o.status.code(),
        Some(2),
        "the same recipe twice is a usage error"
    );
    fs::create_dir_all(dir.join("mine")).unwrap();
    fs::write(dir.join("mine/notes.txt"), "keep").unwrap();
    let o = karigami(&["build", a, b, "--out", "mine"], &dir);
    assert_eq!(o.status.code(), Some(3), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("--force"));
    assert_eq!(
        fs::read_to_string(dir.join("mine/notes.txt")).unwrap(),
        "keep"
    );
    let o = karigami(
        &[
            "build",
            repo().join("templates/chain.toml").to_str().unwrap(),
            a,
            "--out",
            "out",
        ],
        &dir,
    );
    assert!(o.status.success());
    assert!(
        !dir.join("out/flat-sheet").exists(),
        "the old batch is replaced as a whole"
    );
    assert!(dir.join("out/chain/lattice.json").is_file());
    let leftovers: Vec<_> = fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(
        leftovers.is_empty(),
        "temporary folders left: {leftovers:?}"
    );
}

#[test]
fn recipes_of_the_same_name_get_their_folder_in_front() {
    let dir = scratch("batch-same-name");
    let o = karigami(
        &[
            "build",
            repo().join("examples/disk.toml").to_str().unwrap(),
            repo().join("templates/disk.toml").to_str().unwrap(),
            "--out",
            "out",
            "--quiet",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(o.stdout.is_empty(), "--quiet prints nothing on success");
    assert!(dir.join("out/examples-disk/lattice.json").is_file());
    assert!(dir.join("out/templates-disk/lattice.json").is_file());
}

/// A recipe named without a folder is in the current one, whose name it
/// gets in front like the other: `batch-here-chain` and `tpl-chain`.
#[test]
fn a_recipe_in_the_current_folder_gets_its_name_in_front_too() {
    let dir = scratch("batch-here");
    fs::create_dir_all(dir.join("tpl")).unwrap();
    let chain = fs::read(repo().join("templates/chain.toml")).unwrap();
    fs::write(dir.join("chain.toml"), &chain).unwrap();
    fs::write(dir.join("tpl/chain.toml"), &chain).unwrap();
    let o = karigami(
        &[
            "build",
            "chain.toml",
            "tpl/chain.toml",
            "--out",
            "out",
            "-q",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(dir.join("out/batch-here-chain/lattice.json").is_file());
    assert!(dir.join("out/tpl-chain/lattice.json").is_file());
}

#[test]
fn every_template_is_listed_and_new_writes_a_recipe_that_checks() {
    let dir = scratch("templates");
    let o = karigami(&["templates"], &dir);
    assert!(o.status.success());
    let listing = text(&o.stdout);
    let names: Vec<&str> = listing
        .lines()
        .map(|l| l.split_whitespace().next().unwrap())
        .collect();
    for t in ["sheet", "chain", "tube", "helix", "disk"] {
        assert!(names.contains(&t), "{t} missing from {listing}");
    }
    for name in &names {
        let file = format!("my-{name}");
        let o = karigami(&["new", &file, "--template", name], &dir);
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
        let recipe = format!("{file}.toml");
        let source = fs::read_to_string(dir.join(&recipe)).unwrap();
        assert!(source.contains(&format!("name = \"{file}\"")), "{source}");
        let o = karigami(&["check", &recipe], &dir);
        assert!(
            o.status.success(),
            "{name}: {}{}",
            text(&o.stdout),
            text(&o.stderr)
        );
    }
    let o = karigami(&["new", "my-sheet"], &dir);
    assert_eq!(
        o.status.code(),
        Some(2),
        "an existing file is not overwritten"
    );
    let o = karigami(&["new", "x", "--template", "nope"], &dir);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("sheet, chain"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn check_and_build_report_json() {
    let dir = scratch("json");
    let recipe = repo().join("examples/flat-sheet.toml");
    let o = karigami(&["check", recipe.to_str().unwrap(), "--json"], &dir);
    assert!(o.status.success());
    let v: Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    assert_eq!(v[0]["status"], "pass");
    assert_eq!(v[0]["check"]["cells"], 48);
    assert_eq!(v[0]["check"]["passed"], true);
    assert!(v[0]["check"]["largest_residual"].as_f64().unwrap() < 1e-9);
    assert_eq!(v[0]["build"]["strips"], 96);
    let o = karigami(
        &["build", recipe.to_str().unwrap(), "--out", "o", "--json"],
        &dir,
    );
    assert!(o.status.success());
    let v: Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    assert_eq!(v["status"], "ok");
    assert_eq!(v["build"]["sheets"], 1);
    assert!(
        v["files"]
            .as_array()
            .unwrap()
            .iter()
            .any(|f| f == "cut.pdf")
    );
    let bad = repo().join("fixtures/designs/bad/seed-edge-not-spacelike.toml");
    let o = karigami(&["check", bad.to_str().unwrap(), "--json"], &dir);
    assert_eq!(o.status.code(), Some(1));
    let v: Value = serde_json::from_slice(&o.stdout).expect("stdout is JSON");
    assert_eq!(v[0]["status"], "error");
    assert_eq!(v[0]["error"]["class"], "SeedEdgeNotSpacelike");
    assert!(v[0]["error"]["line"].as_u64().is_some());
}

#[test]
fn completions_are_printed_for_each_shell() {
    for shell in ["bash", "zsh", "fish"] {
        let o = karigami(&["completions", shell], &repo());
        assert!(o.status.success());
        let script = text(&o.stdout);
        assert!(
            script.contains("templates") && script.contains("jobs"),
            "{shell}"
        );
    }
}

#[test]
fn lattices_too_large_to_fabricate_are_verified_but_not_built() {
    // 2 cells wide and 10,000 rows: 20,000 cells, but a guide of 10,000
    // steps that would draw them all each time.
    let dir = scratch("too-large");
    fs::write(
        dir.join("long.toml"),
        "[lattice]\nseed = \"sheet\"\npoints = [[0.0, 0.0], [20.0, 0.0], [40.0, 0.0]]\nkappa = 0.0\n[lattice.grow]\nangle = 45.0\nrows = 10000\n",
    )
    .unwrap();
    let o = karigami(&["build", "long.toml", "--out", "out"], &dir);
    assert_eq!(o.status.code(), Some(1));
    let stderr = text(&o.stderr);
    assert!(
        stderr.contains("error[TooLarge]") && stderr.contains("long.toml:5:1"),
        "{stderr}"
    );
    assert!(!dir.join("out").exists(), "nothing is written");
    let o = karigami(&["check", "long.toml"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("fabrication: not checked"), "{stdout}");
    assert!(
        stdout.contains("result: PASS (geometry verified)"),
        "{stdout}"
    );
}
