//! Rebuilds reuse the simulation (README "Build folders", docs/physics.md
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
