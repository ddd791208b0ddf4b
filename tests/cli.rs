//! The real `karigami` binary, run as a user would.

use crate::errors::{bad_fixtures, expectation};
use serde_json::Value;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub(crate) fn karigami(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_karigami"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("runs karigami")
}

pub(crate) fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A fresh empty folder under the target dir, unique to the test.
pub(crate) fn scratch(name: &str) -> PathBuf {
    let dir = repo().join("target").join("test-scratch").join(name);
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

pub(crate) fn recipes(folder: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = fs::read_dir(repo().join(folder))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn check_passes_on_every_example_and_template() {
    // The gallery dearest first, then the templates: two at a time, so the
    // torus's long check does not come last.
    let files: Vec<String> = crate::util::GALLERY
        .iter()
        .map(|name| format!("examples/{name}.toml"))
        .chain(recipes("templates").iter().map(|f| {
            let rel = f.strip_prefix(repo()).unwrap();
            rel.to_str().unwrap().to_string()
        }))
        .collect();
    assert_eq!(recipes("examples").len(), crate::util::GALLERY.len());
    assert!(
        files.len() > crate::util::GALLERY.len(),
        "templates/ holds recipes"
    );
    crate::util::each_in_parallel(&files, 2, |rel| {
        // A gallery example reuses its shared build's simulation; the
        // torus's check is the fit test's too (targets.rs).
        let out = match rel.strip_prefix("examples/") {
            Some(name) => crate::util::gallery_check(name.trim_end_matches(".toml")),
            None => crate::util::cli_check(rel, &[]),
        };
        let stdout = text(&out.stdout);
        assert!(
            out.status.success(),
            "{rel}: {}{}",
            stdout,
            text(&out.stderr)
        );
        assert!(stdout.contains("result: PASS"), "{rel}: {stdout}");
        assert!(!stdout.contains("simulation: solved"), "{rel}: {stdout}");
    });
}

/// `check --reuse` restores the simulated shape a build solved, and its
/// report is the one a check that solves prints, but for the line that
/// says so; what the build did not solve is solved anew, and a folder that is
/// not a build is refused before anything is grown.
#[test]
fn check_reuses_what_a_build_solved() {
    let sheet = "examples/curved-sheet.toml";
    let built = crate::util::cli_build("curved-sheet", &[])
        .to_str()
        .unwrap();
    let solved = karigami(&["check", sheet], &repo());
    let reused = karigami(&["check", sheet, "--reuse", built], &repo());
    assert!(reused.status.success(), "{}", text(&reused.stderr));
    let line =
        format!("simulation: reused from the build in {built} (nothing it depends on changed)\n");
    let reused = text(&reused.stdout);
    assert!(reused.contains(&line), "{reused}");
    assert_eq!(reused.replacen(&line, "", 1), text(&solved.stdout));

    // Narrower strips bend otherwise: the state is not theirs.
    let args = ["check", sheet, "--strip-width", "9", "--reuse", built];
    let other = karigami(&args, &repo());
    let other = text(&other.stdout);
    assert!(
        other.contains(&format!(
            "simulation: solved (the build in {built} holds none of this recipe as it is now)"
        )),
        "{other}"
    );

    let out = karigami(&["check", sheet, "--reuse", "examples"], &repo());
    assert_eq!(out.status.code(), Some(3));
    assert_eq!(
        text(&out.stderr),
        "error: cannot reuse examples: it is not a karigami build folder (no .karigami-build in it); give the --out folder of `karigami build`\n"
    );
}

/// A batch names a recipe's subfolder by its file name made safe
/// (`curved:sheet.toml` in `curved_sheet/`): `check --reuse` finds its
/// state there, as a build of the same batch does.
#[test]
fn check_reuses_a_batch_member_whose_name_was_made_safe() {
    let dir = scratch("reuse-safe-name");
    fs::create_dir_all(dir.join("in")).unwrap();
    fs::copy(
        repo().join("examples/curved-sheet.toml"),
        dir.join("in/curved:sheet.toml"),
    )
    .unwrap();
    let built = karigami(&["-q", "build", "in", "--out", "out"], &dir);
    assert!(built.status.success(), "{}", text(&built.stderr));
    assert!(dir.join("out/curved_sheet").is_dir());
    let o = karigami(&["check", "in/curved:sheet.toml", "--reuse", "out"], &dir);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout)
            .contains("simulation: reused from the build in out (nothing it depends on changed)\n"),
        "{}",
        text(&o.stdout)
    );
}

#[test]
fn check_fails_on_bad_fixtures_with_exit_1_and_the_place() {
    for f in bad_fixtures() {
        let rel = f.display().to_string();
        let source = fs::read_to_string(&f).unwrap();
        let want = expectation(&source, &rel);
        let out = karigami(&["check", &rel], &repo());
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{rel}: {stderr}");
        let place = format!("{rel}:{}:{}", want.line_col.0, want.line_col.1);
        assert!(
            stderr.contains(&place),
            "{rel}: expected {place} in\n{stderr}"
        );
        assert!(
            stderr.contains(&format!("error[{}]", want.class)),
            "{stderr}"
        );
        assert!(!text(&out.stdout).contains("result: PASS"));
    }
}

#[test]
fn missing_recipe_is_an_io_error() {
    let out = karigami(&["check", "no/such/design.toml"], &repo());
    assert_eq!(out.status.code(), Some(3));
    assert!(text(&out.stderr).contains("cannot read no/such/design.toml"));
}

#[test]
fn bad_usage_exits_2() {
    let out = karigami(&["frobnicate"], &repo());
    assert_eq!(out.status.code(), Some(2));
}

/// Keys of the first object on the line that starts with `prefix`, in file order.
fn key_order(json: &str, prefix: &str) -> Vec<String> {
    let line = json
        .lines()
        .find(|l| l.trim_start().starts_with(prefix))
        .expect("record line");
    let record = line.trim().trim_end_matches(',');
    let value: Value = serde_json::from_str(record).unwrap();
    let mut keys: Vec<(usize, String)> = value
        .as_object()
        .unwrap()
        .keys()
        .map(|k| (record.find(&format!("\"{k}\":")).unwrap(), k.clone()))
        .collect();
    keys.sort();
    keys.into_iter().map(|(_, k)| k).collect()
}

#[test]
fn build_writes_lattice_json_in_the_documented_schema() {
    let out = crate::util::cli_build("flat-sheet", &[]);
    let raw = fs::read_to_string(out.join("lattice.json")).unwrap();
    let json: Value = serde_json::from_str(&raw).unwrap();

    let top: Vec<&str> = raw
        .lines()
        .next()
        .unwrap()
        .split('"')
        .skip(1)
        .step_by(2)
        .collect();
    assert_eq!(top, ["format", "kind", "sheet", "dim", "extrinsic"]);
    assert_eq!(json["format"], 2);
    assert_eq!(json["kind"], "sheet");
    assert_eq!(json["dim"], 2);
    assert_eq!(json["extrinsic"], true);
    assert_eq!(
        key_order(&raw, "{\"key\":[0,0],\"pos\""),
        ["key", "pos", "z"]
    );
    // An extrinsic lattice writes no frame and no rebuilt top corners.
    assert_eq!(
        key_order(&raw, "{\"key\":[0,0],\"vertices\""),
        ["key", "vertices", "pivot", "z_pivot", "layers"]
    );
    // What format 2 derives instead of writing.
    for gone in [
        "\"rods\"",
        "\"eyelets\"",
        "\"legs\"",
        "\"kappa\"",
        "\"corners\"",
    ] {
        assert!(!raw.contains(gone), "{gone} is derived, not written");
    }

    let vertices = json["vertices"].as_array().unwrap();
    let cells = json["cells"].as_array().unwrap();
    assert_eq!(vertices.len(), 7 * 9);
    assert_eq!(cells.len(), 6 * 8);
    assert_eq!(vertices[0]["z"], 0.0, "z = 0 at the first seed vertex");
    // Creation order: seed front, then row by row, left to right.
    for (n, v) in vertices.iter().enumerate() {
        assert_eq!(v["key"], serde_json::json!([n / 9, n % 9]));
        assert_eq!(v["pos"].as_array().unwrap().len(), 2);
    }
    let f = |v: &Value| v.as_f64().unwrap();
    let pos = |v: &Value| -> Vec<f64> { v.as_array().unwrap().iter().map(f).collect() };
    let corner = |cell: &Value, k: usize| &vertices[cell["vertices"][k].as_u64().unwrap() as usize];
    // The joints, derived as docs/lattice-json.md says: per vertex, the
    // layers of the rod ends meeting there.
    let mut joints: Vec<Vec<u64>> = vec![Vec::new(); vertices.len()];
    for (c, cell) in cells.iter().enumerate() {
        let (i, j) = (c / 8, c % 8);
        assert_eq!(cell["key"], serde_json::json!([i, j]));
        // UL, UR, LL, LR are the cell's grid corners.
        for (k, (di, dj)) in [(0, 0), (0, 1), (1, 0), (1, 1)].into_iter().enumerate() {
            assert_eq!(corner(cell, k)["key"], serde_json::json!([i + di, j + dj]));
        }
        // Scissor cells: the pivot lies on both rods, UL-LR and UR-LL.
        let pivot = pos(&cell["pivot"]);
        for (from, to) in [(0, 3), (1, 2)] {
            let (a, b) = (
                pos(&corner(cell, from)["pos"]),
                pos(&corner(cell, to)["pos"]),
            );
            let cross = (b[0] - a[0]) * (pivot[1] - a[1]) - (b[1] - a[1]) * (pivot[0] - a[0]);
            assert!(cross.abs() < 1e-9, "cell {c}: the pivot is off a rod");
        }
        let layers = pos(&cell["layers"]);
        for (k, slot) in [(0, 0), (1, 1), (2, 1), (3, 0)] {
            let v = cell["vertices"][k].as_u64().unwrap() as usize;
            joints[v].push(layers[slot] as u64);
        }
    }
    // An interior vertex joins 4 rod ends in 4 distinct layers, a corner 1.
    let interior = &joints[2 * 9 + 3];
    assert_eq!(interior.len(), 4);
    let mut layers = interior.clone();
    layers.sort();
    layers.dedup();
    assert_eq!(layers.len(), 4);
    assert_eq!(joints[0].len(), 1);
}

#[test]
fn an_intrinsic_lattice_json_gives_each_rows_frame_and_the_strips_legs() {
    // eggbox grows rows on rebuilt fronts: its cells carry `frame`, and
    // `top` where the row rebuilt (docs/lattice-json.md).
    let out = crate::util::cli_build("eggbox", &[]);
    let json: Value =
        serde_json::from_str(&fs::read_to_string(out.join("lattice.json")).unwrap()).unwrap();
    assert_eq!(json["extrinsic"], false);
    let cells = json["cells"].as_array().unwrap();
    let mut rebuilt = 0;
    for cell in cells {
        let row = cell["key"][0].as_u64().unwrap();
        let frame = cell["frame"]
            .as_u64()
            .expect("a frame in an intrinsic lattice");
        assert!(frame <= row);
        assert_eq!(!cell["top"].is_null(), frame == row && row > 0, "{cell}");
        rebuilt += usize::from(!cell["top"].is_null());
    }
    assert!(rebuilt > 0);
    // The legs derived from the cells are the strips' hole pitches.
    let legs = crate::cutfiles::rod_legs(&json);
    let csv = fs::read_to_string(out.join("parts.csv")).unwrap();
    let mut rows = 0;
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let rod: usize = f[1].parse().unwrap();
        for k in 0..2 {
            let pitch: f64 = f[9 + k].parse().unwrap();
            assert!(
                (legs[rod][k] - pitch).abs() < 1e-4,
                "{line}: leg {k} {}",
                legs[rod][k]
            );
        }
        rows += 1;
    }
    assert_eq!(rows, legs.len());
}

#[test]
fn build_is_deterministic() {
    // One build shared with the other tests, one of this test's own.
    let a = crate::util::cli_build("curved-sheet", &[]);
    let dir = scratch("build-determinism");
    let recipe = repo().join("examples/curved-sheet.toml");
    assert!(
        karigami(&["build", recipe.to_str().unwrap(), "--out", "b"], &dir)
            .status
            .success()
    );
    assert_eq!(
        fs::read(a.join("lattice.json")).unwrap(),
        fs::read(dir.join("b/lattice.json")).unwrap()
    );
}

#[test]
fn build_without_a_design_builds_the_default_into_karigami_out() {
    let dir = scratch("build-default");
    let out = karigami(&["build"], &dir);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let json: Value =
        serde_json::from_slice(&fs::read(dir.join("karigami-out/lattice.json")).unwrap()).unwrap();
    assert!(!json["cells"].as_array().unwrap().is_empty());
    // The whole build, and no temporary files or folders left behind.
    let list = |d: &Path| {
        let mut names: Vec<String> = fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    };
    assert_eq!(
        list(&dir.join("karigami-out")),
        [
            ".karigami-build",
            "assembly.pdf",
            "cut.pdf",
            "lattice.json",
            "lattice.obj",
            "parts-types.csv",
            "parts.csv",
            "preview.png",
            "report.txt",
            "sheets",
            "viewer.html"
        ]
    );
    assert_eq!(
        list(&dir.join("karigami-out/sheets")),
        [
            "sheet-01.dxf",
            "sheet-01.lbrn2",
            "sheet-01.png",
            "sheet-01.svg"
        ]
    );
    assert_eq!(list(&dir), ["karigami-out"]);
}

#[test]
fn full_precision_numbers_round_trip() {
    let raw = fs::read_to_string(crate::util::cli_build("curved-sheet", &[]).join("lattice.json"))
        .unwrap();
    let json: Value = serde_json::from_str(&raw).unwrap();
    // A 3-D position written with fewer than ~15 significant digits would
    // have been rounded; shortest round-trip output keeps them all.
    let x = json["cells"][0]["pivot"][0].as_f64().unwrap();
    assert!(raw.contains(&format!("{x:?}")));
    assert!(!raw.contains("NaN") && !raw.contains("null") && !raw.contains("inf"));
}

/// `karigami simulate --explore` on the eggbox, as a user runs it: the
/// report's figures are printed, several stable equilibria are found around
/// the reported one (3 of 12 starts with the 0.5 mm strips), and between
/// them bumps pop through
/// as the paper describes: a dome-like vertex turned inside out, standing
/// out to the other side of the sheet and still dome-like (measured on
/// each simulated shape).
#[test]
fn simulate_explore_finds_the_eggboxs_pop_through() {
    let out = karigami(
        &["simulate", "examples/eggbox.toml", "--explore", "12"],
        &repo(),
    );
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}{}", stdout, text(&out.stderr));
    for line in [
        "energy: ",
        "largest strain: ",
        "largest joint reaction: ",
        "distance from the design (after the best rigid fit): largest ",
        "curvature (simulated): ",
    ] {
        assert!(
            stdout.lines().any(|l| l.starts_with(line)),
            "no {line:?} in\n{stdout}"
        );
    }
    let found: usize = stdout
        .lines()
        .find_map(|l| l.strip_prefix("explore: 12 starts"))
        .and_then(|l| l.rsplit_once(": ")?.1.split(' ').next()?.parse().ok())
        .unwrap_or_else(|| panic!("no explore line in\n{stdout}"));
    assert!(
        found >= 2,
        "the eggbox is multistable, found {found}:\n{stdout}"
    );
    // The reported state (the one deploying reaches) is the lowest found,
    // 143.404 N mm; every other one is compared with it.
    assert!(
        stdout.contains("  1: energy 1.434041e2 N mm") && stdout.contains("(the reported one)"),
        "{stdout}"
    );
    let popped: Vec<usize> = stdout
        .lines()
        .filter(|l| l.contains(" against 1: energy ") && l.contains(" pop"))
        .map(|l| {
            let n = l.split("; ").nth(1).unwrap();
            n.split(' ').next().unwrap().parse().unwrap()
        })
        .collect();
    assert_eq!(popped.len(), found - 1, "{stdout}");
    assert!(
        popped.iter().any(|&n| n >= 1),
        "no bump pops through:\n{stdout}"
    );
    assert!(
        stdout.contains("  build reports 1: the state deploying reaches"),
        "{stdout}"
    );
}

/// A torus fitted over 1,000 rows winds round its tube 50 times: its
/// strips overlap those of every turn, 588,000 clashing pairs. The search
/// counts them all but keeps only the closest (it used to collect every
/// pair: 10,000 rows, 60 million pairs, aborted at a 3 GB allocation);
/// `check` refuses with the count and `--json` lists the first hundred.
#[test]
fn a_torus_of_a_thousand_rows_is_refused_with_all_its_clashes_counted() {
    let dir = scratch("clash-count");
    let torus = fs::read_to_string(repo().join("examples/torus.toml")).unwrap();
    assert!(torus.contains("\nrows = 19\n"));
    fs::write(
        dir.join("torus.toml"),
        torus.replace("\nrows = 19\n", "\nrows = 1000\n"),
    )
    .unwrap();
    let out = karigami(&["check", "torus.toml"], &dir);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("error[StripClash]: strips R000-C06-B and R020-C06-B ")
            && stderr.contains("(588000 clashing pairs in all)"),
        "{stderr}"
    );
    assert!(
        text(&out.stdout)
            .contains("  strip clashes: 588000 pairs; closest R000-C06-B and R020-C06-B,"),
        "{}",
        text(&out.stdout)
    );
    let out = karigami(&["check", "--json", "torus.toml"], &dir);
    let json: Value = serde_json::from_slice(&out.stdout).expect("a JSON report");
    assert_eq!(json[0]["error"]["class"], "StripClash", "{json}");
    let shape = &json[0]["check"]["shape"];
    assert_eq!(shape["clash_count"], 588000, "{shape}");
    let listed = shape["clashes"].as_array().expect("a list");
    assert_eq!(listed.len(), 100);
    assert_eq!(listed[0]["strips"][0], "R000-C06-B");
    let distances: Vec<f64> = listed
        .iter()
        .map(|c| c["distance_mm"].as_f64().unwrap())
        .collect();
    assert!(distances.is_sorted(), "closest first: {distances:?}");
    // What the measures hold: the count, and only the closest few.
    let d = karigami::parse(
        &fs::read_to_string(dir.join("torus.toml")).unwrap(),
        "torus",
    )
    .unwrap();
    let m = karigami::measure(&d, &d.grow().unwrap());
    let kept = karigami::testing::clash::KEPT;
    assert_eq!((m.clashes.len(), m.clashes.iter().len()), (588000, kept));
    assert_eq!(m.clashes.dropped().0, 588000 - kept);
}

/// `simulate --theta` outside [0.1, 180) deg (the recipe's bounds) is a usage
/// error naming the flag, with the number readable; `--explore` is
/// bounded; a long `--explore` says how far it has got on stderr (after
/// 50 ms here rather than 2 s: the fault module's clock), and `-q` not.
#[test]
fn simulates_flags_are_bounded_and_a_long_explore_says_how_far_it_is() {
    let arm = "examples/mirror-arm.toml";
    for (theta, shown) in [
        ("nan", "NaN"),
        ("inf", "inf"),
        ("1e300", "1e300"),
        ("0", "0"),
        ("0.09", "0.09"),
        ("1e-300", "1e-300"),
        ("180", "180"),
    ] {
        let out = karigami(&["simulate", arm, "--theta", theta], &repo());
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{theta}: {stderr}");
        assert_eq!(
            stderr,
            format!(
                "error: --theta is {shown}, but must be an opening in degrees of at least 0.1 and less than 180\n"
            )
        );
    }
    for n in ["0", "10001", "1000000"] {
        let out = karigami(&["simulate", arm, "--explore", n], &repo());
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{n}: {stderr}");
        assert_eq!(
            stderr,
            format!("error: --explore is {n}, but must be from 1 to 10000 starts\n")
        );
    }
    // The progress line needs the test clock (`firstnote`).
    if !crate::safety::faults() {
        return;
    }
    let explore = |quiet: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_karigami"))
            .args([&["simulate", arm, "--explore", "40", "-j", "1"], quiet].concat())
            .current_dir(repo())
            .env("KARIGAMI_FAULT", "firstnote@50")
            .output()
            .expect("runs karigami")
    };
    let out = explore(&[]);
    let stderr = text(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr
            .lines()
            .any(|l| l.starts_with("explore: ") && l.contains(" of 40 starts (")),
        "no progress line: {stderr}"
    );
    let quiet = explore(&["-q"]);
    assert!(
        quiet.status.success() && quiet.stderr.is_empty(),
        "{}",
        text(&quiet.stderr)
    );
}
