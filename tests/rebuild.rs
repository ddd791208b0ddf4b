//! Rebuilds reuse the simulation (docs/commands.md, "Build folders", docs/physics.md
//! "Rebuilds"): a rebuild into the same folder restores the earlier
//! equilibrium instead of solving, and writes every file byte for byte as a
//! fresh solve does; a changed input, or a state file that is not the one
//! karigami wrote, is solved again.

use crate::cli::{karigami, repo, scratch};
use crate::workflow::tree;
use std::collections::BTreeMap;
use std::fs;
use std::path::Path;

/// Build `recipe` into `out` (in `dir`) and return what it said about the
/// simulation: "solved", "reused" or "" when it did not simulate.
fn build(dir: &Path, recipe: &str, out: &str) -> String {
    let o = karigami(&["build", recipe, "--out", out], dir);
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let line = stdout
        .lines()
        .find(|l| l.starts_with("simulation"))
        .unwrap_or("");
    if line.contains("reused") {
        "reused".into()
    } else if line.contains("solved") {
        "solved".into()
    } else {
        String::new()
    }
}

fn same(a: &BTreeMap<String, Vec<u8>>, b: &BTreeMap<String, Vec<u8>>, what: &str) {
    assert_eq!(
        a.keys().collect::<Vec<_>>(),
        b.keys().collect::<Vec<_>>(),
        "{what}"
    );
    for (name, bytes) in a {
        assert!(bytes == &b[name], "{name} differs: {what}");
    }
}

/// The curved sheet, the quickest example that simulates, with `extra`
/// appended (a table or keys of the recipe).
fn recipe(dir: &Path, name: &str, extra: &str) -> String {
    let text = fs::read_to_string(repo().join("examples/curved-sheet.toml")).unwrap();
    let text = text.replace("name = \"curved-sheet\"", "name = \"sheet\"");
    fs::write(dir.join(name), format!("{text}\n{extra}")).unwrap();
    name.to_string()
}

#[test]
fn a_rebuild_reuses_the_simulation_and_writes_the_same_files() {
    let dir = scratch("rebuild-same");
    let r = recipe(&dir, "sheet.toml", "");
    assert_eq!(build(&dir, &r, "fresh"), "solved");
    let fresh = tree(&dir.join("fresh"));
    assert!(
        fresh.contains_key(karigami::STATE_FILE),
        "{:?}",
        fresh.keys()
    );
    assert!(
        String::from_utf8_lossy(&fresh["deployed.json"]).contains("\"fingerprint\""),
        "deployed.json records the fingerprint"
    );
    fs::rename(dir.join("fresh"), dir.join("again")).unwrap();
    assert_eq!(build(&dir, &r, "again"), "reused");
    same(&fresh, &tree(&dir.join("again")), "a reused simulation");
    // The maker's loop: another sheet size changes the cut files, not the
    // deployed shape, which is reused and the same to the byte.
    let bigger = recipe(&dir, "bigger.toml", "[sheet]\npreset = \"a3\"\n");
    assert_eq!(build(&dir, &bigger, "again"), "reused");
    let again = tree(&dir.join("again"));
    for f in ["deployed.json", "deployed.obj", karigami::STATE_FILE] {
        assert!(again[f] == fresh[f], "{f} changed with the sheet size");
    }
    // --json says so too.
    let o = karigami(&["build", &r, "--out", "again", "--json"], &dir);
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["simulation"], "reused", "{json}");
}

#[test]
fn a_changed_input_or_a_damaged_state_is_solved_again() {
    let dir = scratch("rebuild-changed");
    let r = recipe(&dir, "sheet.toml", "");
    assert_eq!(build(&dir, &r, "fresh"), "solved");
    let fresh = tree(&dir.join("fresh"));
    let state = dir.join("fresh").join(karigami::STATE_FILE);
    // Each damage: the build solves, and its files are a fresh solve's.
    type Damage = fn(&Path);
    let damages: [(&str, Damage); 6] = [
        ("a flipped byte", |p| {
            let mut b = fs::read(p).unwrap();
            let n = b.len();
            b[n - 100] ^= 1;
            fs::write(p, b).unwrap();
        }),
        ("cut short", |p| {
            let b = fs::read(p).unwrap();
            fs::write(p, &b[..b.len() - 8]).unwrap();
        }),
        ("empty", |p| fs::write(p, b"").unwrap()),
        ("another fingerprint", |p| {
            let b = fs::read(p).unwrap();
            let t = String::from_utf8_lossy(&b[..200]).into_owned();
            let at = t.find("fingerprint ").unwrap() + "fingerprint ".len();
            let mut b = b;
            b[at] = if b[at] == b'0' { b'1' } else { b'0' };
            fs::write(p, b).unwrap();
        }),
        ("a NaN energy under a recomputed hash", |p| {
            // A hand-made state whose header checks out: the NaN must not
            // slip through the energy comparison.
            let b = fs::read(p).unwrap();
            let split = b.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
            let mut payload = b[split..].to_vec();
            let n = payload.len();
            payload[n - 8..].copy_from_slice(&f64::NAN.to_bits().to_le_bytes());
            let hash = karigami::util::fnv1a(&payload);
            let head = String::from_utf8_lossy(&b[..split]).into_owned();
            let mut lines: Vec<String> = head.trim_end().lines().map(str::to_owned).collect();
            let at = lines
                .iter()
                .position(|l| l.starts_with("payload "))
                .unwrap();
            lines[at] = format!("payload {n} bytes, fnv1a {hash:016x}");
            let mut out = (lines.join("\n") + "\n\n").into_bytes();
            out.extend_from_slice(&payload);
            fs::write(p, out).unwrap();
        }),
        ("gone", |p| fs::remove_file(p).unwrap()),
    ];
    for (what, damage) in damages {
        damage(&state);
        assert_eq!(build(&dir, &r, "fresh"), "solved", "state {what}");
        same(&fresh, &tree(&dir.join("fresh")), what);
    }
    // A damaged deployed.json is an output like any other: rewritten, and
    // the state it sits beside still holds.
    fs::write(dir.join("fresh/deployed.json"), "{ not json").unwrap();
    assert_eq!(build(&dir, &r, "fresh"), "reused");
    same(&fresh, &tree(&dir.join("fresh")), "deployed.json damaged");
    // Inputs of the solve: the strip section, the mesh, the material.
    for (i, extra) in [
        "[material]\nthickness = 1.2\n",
        "[simulation]\nedge_length = 8.0\n",
        "[simulation]\nyoungs_modulus = 2000.0\n",
    ]
    .iter()
    .enumerate()
    {
        let changed = recipe(&dir, &format!("changed-{i}.toml"), extra);
        assert_eq!(build(&dir, &changed, "fresh"), "solved", "{extra}");
        assert_eq!(build(&dir, &r, "fresh"), "solved", "back from {extra}");
    }
    same(
        &fresh,
        &tree(&dir.join("fresh")),
        "after the changed inputs",
    );
}

#[test]
fn a_batch_rebuild_reuses_each_simulation() {
    let dir = scratch("rebuild-batch");
    fs::create_dir(dir.join("recipes")).unwrap();
    recipe(&dir, "recipes/sheet.toml", "");
    fs::copy(
        repo().join("examples/mirror-arm.toml"),
        dir.join("recipes/mirror-arm.toml"),
    )
    .unwrap();
    let run = |out: &str| {
        let o = karigami(&["build", "recipes", "--out", out, "--jobs", "2"], &dir);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let first = run("batch");
    assert!(first.contains("simulations: 0 of 1 reused"), "{first}");
    let fresh = tree(&dir.join("batch"));
    let second = run("batch");
    assert!(second.contains("mirror-arm"), "{second}");
    assert!(second.contains("simulations: 1 of 1 reused"), "{second}");
    same(&fresh, &tree(&dir.join("batch")), "a batch rebuild");
}

/// The fingerprint hashes the code the equilibrium comes from: every file
/// of the simulation and of the rods crate must be in its list.
#[test]
fn the_fingerprint_covers_every_file_of_the_simulation() {
    let listed: Vec<&str> = karigami::testing::SIMULATION_SOURCES
        .iter()
        .map(|(name, _)| *name)
        .collect();
    for folder in ["src/sim", "crates/rods/src"] {
        for e in fs::read_dir(repo().join(folder)).unwrap() {
            let p = e.unwrap().path();
            let rel = p
                .strip_prefix(repo())
                .unwrap()
                .to_string_lossy()
                .into_owned();
            assert!(
                p.is_file() && listed.contains(&rel.as_str()),
                "{rel} is not in pipeline::reuse::SOURCES (a folder or a new file)"
            );
        }
    }
}

/// A folder `recipes/` with two quick recipes that do not simulate: a
/// chain of three cells and the mirror arm.
fn two_recipes(name: &str) -> std::path::PathBuf {
    let dir = scratch(name);
    fs::create_dir(dir.join("recipes")).unwrap();
    let chain = fs::read_to_string(repo().join("templates/chain.toml")).unwrap();
    let three = chain.replace("rows = 6 ", "rows = 3 ");
    assert_ne!(three, chain, "the template sets rows = 6");
    fs::write(dir.join("recipes/chain.toml"), three).unwrap();
    fs::copy(
        repo().join("examples/mirror-arm.toml"),
        dir.join("recipes/mirror-arm.toml"),
    )
    .unwrap();
    dir
}

/// `karigami build recipes --out OUT --jobs 2 EXTRA...`: its stdout.
fn batch(dir: &Path, out: &str, extra: &[&str]) -> String {
    let mut args = vec!["build", "recipes", "--out", out, "--jobs", "2"];
    args.extend(extra);
    let o = karigami(&args, dir);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// How many recipes a batch's stdout says it kept (0 when it says nothing).
fn kept(stdout: &str) -> usize {
    stdout
        .lines()
        .find_map(|l| l.strip_prefix("kept the files of "))
        .map_or(0, |rest| rest.split(' ').next().unwrap().parse().unwrap())
}

/// A fresh batch of `recipes/` with `extra` into a folder of its own.
fn fresh_batch(dir: &Path, extra: &[&str]) -> BTreeMap<String, Vec<u8>> {
    let _ = fs::remove_dir_all(dir.join("reference"));
    assert_eq!(kept(&batch(dir, "reference", extra)), 0);
    let t = tree(&dir.join("reference"));
    fs::remove_dir_all(dir.join("reference")).unwrap();
    t
}

#[test]
fn a_rebuild_keeps_the_files_that_check_out_and_restores_the_others() {
    let dir = two_recipes("rebuild-keep");
    let fresh = fresh_batch(&dir, &[]);
    assert_eq!(kept(&batch(&dir, "out", &[])), 0, "a first build");
    same(&fresh, &tree(&dir.join("out")), "a first build");
    assert_eq!(kept(&batch(&dir, "out", &[])), 2, "nothing changed");
    same(
        &fresh,
        &tree(&dir.join("out")),
        "a rebuild that kept everything",
    );
    // Each damage to one file of one recipe: that recipe is built again,
    // the other kept, and the folder is a fresh build's.
    type Damage = fn(&Path);
    let damages: [(&str, &str, Damage); 6] = [
        ("deleted", "chain/cut.pdf", |p| fs::remove_file(p).unwrap()),
        ("cut short", "chain/sheets/sheet-01.png", |p| {
            let b = fs::read(p).unwrap();
            fs::write(p, &b[..b.len() / 2]).unwrap();
        }),
        ("a flipped byte", "mirror-arm/report.txt", |p| {
            let mut b = fs::read(p).unwrap();
            b[10] ^= 1;
            fs::write(p, b).unwrap();
        }),
        ("emptied", "mirror-arm/viewer.html", |p| {
            fs::write(p, "").unwrap();
        }),
        ("the same length, another byte", "chain/lattice.json", |p| {
            let mut b = fs::read(p).unwrap();
            let n = b.len();
            b[n - 2] = if b[n - 2] == b' ' { b'\t' } else { b' ' };
            fs::write(p, b).unwrap();
        }),
        ("replaced by a folder", "chain/parts.csv", |p| {
            fs::remove_file(p).unwrap();
            fs::create_dir(p).unwrap();
        }),
    ];
    for (what, file, damage) in damages {
        damage(&dir.join("out").join(file));
        // A folder that is not the build's is a file the build did not
        // write: it takes --force, as before.
        let force: &[&str] = if what.contains("folder") {
            &["--force"]
        } else {
            &[]
        };
        let said = batch(&dir, "out", force);
        assert_eq!(kept(&said), 1, "{file} {what}: {said}");
        same(&fresh, &tree(&dir.join("out")), &format!("{file} {what}"));
    }
    // The batch's own report is the same whether kept or built.
    let o = karigami(
        &["build", "recipes", "--out", "out", "--jobs", "2", "--json"],
        &dir,
    );
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json[0]["build"]["strips"], 6, "{json}");
    assert_eq!(
        json[1]["check"],
        serde_json::from_slice::<serde_json::Value>(&fresh["batch.json"]).unwrap()[1]["check"]
    );
}

#[test]
fn a_changed_recipe_or_option_rebuilds_what_it_changes() {
    let dir = two_recipes("rebuild-changed-recipe");
    batch(&dir, "out", &[]);
    // One recipe changed (a comment only): it is built again, the other
    // kept, and the folder is a fresh build's of the new recipes.
    let path = dir.join("recipes/chain.toml");
    let text = fs::read_to_string(&path).unwrap();
    fs::write(&path, format!("{text}\n# changed\n")).unwrap();
    let fresh = fresh_batch(&dir, &[]);
    assert_eq!(kept(&batch(&dir, "out", &[])), 1);
    same(&fresh, &tree(&dir.join("out")), "one recipe changed");
    // An option on the command line changes every recipe's files.
    let kerf = fresh_batch(&dir, &["--kerf", "0.2"]);
    assert_eq!(kept(&batch(&dir, "out", &["--kerf", "0.2"])), 0);
    same(&kerf, &tree(&dir.join("out")), "--kerf 0.2");
    assert_ne!(kerf["chain/cut.pdf"], fresh["chain/cut.pdf"]);
    // The number of jobs changes nothing.
    let o = karigami(
        &[
            "build", "recipes", "--out", "out", "--jobs", "1", "--kerf", "0.2",
        ],
        &dir,
    );
    assert_eq!(kept(&String::from_utf8_lossy(&o.stdout)), 2);
    same(&kerf, &tree(&dir.join("out")), "--jobs 1");
    // Back without the option: built again, as fresh.
    assert_eq!(kept(&batch(&dir, "out", &[])), 0);
    same(&fresh, &tree(&dir.join("out")), "back without --kerf");
}

#[test]
fn a_single_rebuild_keeps_its_files_and_reports_the_same() {
    let dir = two_recipes("rebuild-keep-single");
    let run = |extra: &[&str]| {
        let mut args = vec!["build", "recipes/mirror-arm.toml", "--out", "out"];
        args.extend(extra);
        let o = karigami(&args, &dir);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let first = run(&["-v"]);
    assert!(!first.contains("kept every file"), "{first}");
    let fresh = tree(&dir.join("out"));
    let second = run(&["-v"]);
    assert!(second.contains("kept every file"), "{second}");
    same(&fresh, &tree(&dir.join("out")), "a kept single build");
    // The terminal says the same but for the line on what was kept.
    let without = |s: &str| {
        s.lines()
            .filter(|l| !l.starts_with("kept "))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(without(&first), without(&second));
    let json: serde_json::Value = serde_json::from_str(&run(&["--json"])).unwrap();
    let files: Vec<&str> = json["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    assert!(
        files.contains(&"cut.pdf") && files.contains(&"sheets/sheet-01.svg"),
        "{files:?}"
    );
    assert_eq!(
        files.len(),
        fresh.len() - 1,
        "every file but the marker: {files:?}"
    );
    assert_eq!(json["build"]["strips"], 8, "{json}");
}

/// The files a rebuild keeps are links to the earlier build's: nothing a
/// later build writes may reach them through a link, and a file replaced
/// by a link is not followed.
#[test]
fn kept_files_are_never_written_through() {
    let dir = two_recipes("rebuild-keep-links");
    let fresh = fresh_batch(&dir, &[]);
    batch(&dir, "out", &[]);
    batch(&dir, "out", &[]);
    // A backup that shares the files (as `cp -al` makes).
    let status = std::process::Command::new("cp")
        .args(["-al", "out", "backup"])
        .current_dir(&dir)
        .status()
        .unwrap();
    assert!(status.success());
    let times = || -> Vec<std::time::SystemTime> {
        tree(&dir.join("backup"))
            .keys()
            .map(|f| {
                fs::metadata(dir.join("backup").join(f))
                    .unwrap()
                    .modified()
                    .unwrap()
            })
            .collect()
    };
    let before = times();
    // The last file of a recipe damaged: the keep links the others, finds
    // it, undoes and builds; what it writes must not reach the backup.
    let report = dir.join("out/chain/report.txt");
    let mut b = fs::read(&report).unwrap();
    b.push(b'\n');
    fs::remove_file(&report).unwrap();
    fs::write(&report, b).unwrap();
    assert_eq!(kept(&batch(&dir, "out", &[])), 1);
    same(&fresh, &tree(&dir.join("out")), "after the damage");
    same(&fresh, &tree(&dir.join("backup")), "the backup");
    // Not even written again with the same bytes.
    assert!(before == times(), "a file of the backup was written");
    // A file replaced by a link to a copy of itself outside the folder:
    // --force builds, and the file outside stays as it was.
    let outside = dir.join("outside.svg");
    fs::copy(dir.join("out/mirror-arm/sheets/sheet-01.svg"), &outside).unwrap();
    fs::remove_file(dir.join("out/mirror-arm/sheets/sheet-01.svg")).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(&outside, dir.join("out/mirror-arm/sheets/sheet-01.svg")).unwrap();
    let said = batch(&dir, "out", &["--force"]);
    assert_eq!(kept(&said), 1, "{said}");
    same(&fresh, &tree(&dir.join("out")), "a file replaced by a link");
    assert!(fs::read(&outside).unwrap() == fresh["mirror-arm/sheets/sheet-01.svg"]);
}

/// The GNU build ID note of an executable (the linker's hash of it, which
/// karigami takes as the program's fingerprint): where its 20 bytes start.
fn build_id_at(exe: &[u8]) -> Option<usize> {
    let head: &[u8] = &[4, 0, 0, 0, 20, 0, 0, 0, 3, 0, 0, 0, b'G', b'N', b'U', 0];
    exe.windows(head.len())
        .take(64 << 10)
        .position(|w| w == head)
        .map(|at| at + head.len())
}

/// Another program (here this one with a byte of its build ID changed, or
/// without one, a byte appended) never keeps the files of this one: it
/// builds. The same program with a byte appended (which runs the same) is
/// the same program where it has a build ID.
#[test]
fn another_program_builds_again() {
    let dir = two_recipes("rebuild-keep-program");
    batch(&dir, "out", &[]);
    let fresh = tree(&dir.join("out"));
    let exe = fs::read(env!("CARGO_BIN_EXE_karigami")).unwrap();
    let other = dir.join("karigami-other");
    let run = |bytes: &[u8]| {
        fs::write(&other, bytes).unwrap();
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            fs::set_permissions(&other, fs::Permissions::from_mode(0o755)).unwrap();
        }
        // A test thread that forks while the copy was open for writing
        // makes it busy for a moment (ETXTBSY): try again.
        let mut tries = 0;
        let o = loop {
            match std::process::Command::new(&other)
                .args(["build", "recipes", "--out", "out", "--jobs", "2"])
                .current_dir(&dir)
                .output()
            {
                Err(e) if e.raw_os_error() == Some(26) && tries < 50 => {
                    tries += 1;
                    std::thread::sleep(std::time::Duration::from_millis(100));
                }
                o => break o.unwrap(),
            }
        };
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        kept(&String::from_utf8_lossy(&o.stdout))
    };
    let mut appended = exe.clone();
    appended.push(0);
    let id = build_id_at(&exe);
    if cfg!(target_os = "linux") && id.is_some() {
        assert_eq!(run(&appended), 2, "the same build ID");
    }
    let mut changed = exe.clone();
    match id {
        Some(at) => changed[at] ^= 1,
        None => changed.push(0),
    }
    assert_eq!(run(&changed), 0, "another program");
    let again = tree(&dir.join("out"));
    assert_eq!(run(&changed), 2, "the other program's own files");
    fs::remove_file(&other).unwrap();
    // The same files but for the record of the program in the marker.
    for (name, bytes) in &fresh {
        if name != ".karigami-build" {
            assert!(again[name] == *bytes, "{name}");
        }
    }
    assert!(again[".karigami-build"] != fresh[".karigami-build"]);
    assert_eq!(kept(&batch(&dir, "out", &[])), 0, "back to this program");
}
