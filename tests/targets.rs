//! Targets (docs/design.md): every family and mesh of fixtures/targets/
//! read with its extent and topology, the fit measures checked against
//! motions and coverage we know, every bad target refused with its golden
//! message, and `check --target` on the examples.

use crate::cli::{karigami, repo, scratch};
use crate::goldens::compare;
use crate::util::Rng;
use glam::{DQuat, DVec3};
use karigami::targets::{self, Expect, Rigid, Target, Topology};
use std::path::{Path, PathBuf};

fn read(path: &str) -> Target {
    let bytes = std::fs::read(repo().join(path)).unwrap();
    targets::read(path, &bytes, None).unwrap_or_else(|d| panic!("{path}: {}", d.message))
}

/// Each fixture's largest extent D (mm) from its shape, and its topology.
const SUITE: &[(&str, f64, Topology)] = &[
    ("disk.toml", 400.0, Topology::Patch),
    // Base radius sqrt(h (2r - h)) = 240 for r 300, h 120.
    ("sphere-cap.toml", 480.0, Topology::Patch),
    ("spheroid-cap.toml", 400.0, Topology::Patch),
    ("oval-cap.toml", 400.0, Topology::Patch),
    ("paraboloid.toml", 400.0, Topology::Patch),
    // Corner to corner of the 400 x 400 square, where the height is 0.
    ("saddle.toml", 565.685424949238, Topology::Patch),
    // Corner to corner: the length and the chord 2 r sin(50 deg).
    ("cylinder.toml", 553.8104569330253, Topology::Patch),
    ("torus.toml", 460.0, Topology::Closed { genus: 1 }),
    // From (230, 300) to (-220, 90) across the axis.
    ("revolution.toml", 496.5883607174055, Topology::Patch),
    // The diagonal of 420 x 360 (the corners stand 0.17 mm high).
    ("height-field.toml", 553.1726674375732, Topology::Patch),
    // The flat plate's diagonal: hypot(400, 300).
    ("plate.toml", 500.0, Topology::Patch),
    ("sphere-cap-export.obj", 480.0, Topology::Patch),
    ("saddle-export.stl", 565.685424949238, Topology::Patch),
    ("paraboloid-export.stl", 400.0, Topology::Patch),
    ("vault-export.obj", 553.8104569330253, Topology::Patch),
    ("plate-export.stl", 500.0, Topology::Patch),
    // The bump's sheet corner to corner, hypot(360, 360): the corners
    // stand alike, 0.44 mm high.
    ("bump-export.obj", 509.1168824543142, Topology::Patch),
    // The examples' own targets: the bowl's rim diameter (its rim to its
    // apex is only hypot(200, 240)); across the band from a rim point to
    // the other rim's opposite point, hypot(2 x 146.2552, 2 x 126.3165).
    ("bowl.toml", 400.0, Topology::Patch),
    ("saddle-band.toml", 386.5045495167683, Topology::Annulus),
    ("saddle-ring.toml", 480.0, Topology::Annulus),
    // Refused by `design` for its curvature: the length and the diameter.
    ("too-curved.toml", 304.138126514911, Topology::Patch),
    // Closed: pole to pole (the egg's width is under its length), and the
    // torus band across its outer equator, 2 (160 + 70).
    ("sphere.toml", 400.0, Topology::Closed { genus: 0 }),
    ("sphere-export.obj", 360.0, Topology::Closed { genus: 0 }),
    ("egg-export.stl", 400.0, Topology::Closed { genus: 0 }),
    ("torus-band.toml", 460.0, Topology::Annulus),
];

#[test]
fn every_target_of_the_suite_reads_with_its_extent_and_topology() {
    for &(name, extent, topology) in SUITE {
        let t = read(&format!("fixtures/targets/{name}"));
        assert_eq!(t.topology, topology, "{name}");
        // Meshes stand their corners on the surface, so D is at most the
        // surface's: the families' triangles are within 0.1 % of D, the
        // coarse exports within 0.5 %.
        let within = if name.contains("export") {
            0.005
        } else {
            0.001
        };
        assert!(
            t.extent <= extent * (1.0 + 1e-6) && t.extent >= extent * (1.0 - within),
            "{name}: D {} against {extent}",
            t.extent
        );
        assert!(t.area > 0.0 && t.mesh.triangles.len() > 50, "{name}");
    }
}

#[test]
fn the_suite_covers_every_family_once() {
    let families = [
        "disk",
        "sphere-cap",
        "spheroid-cap",
        "paraboloid",
        "saddle",
        "saddle-ring",
        "cylinder",
        "torus",
        "revolution",
        "height-field",
    ];
    for f in families {
        let t = read(&format!("fixtures/targets/{f}.toml"));
        assert_eq!(t.what, f);
    }
}

#[test]
fn a_caller_may_ask_for_a_patch_and_a_closed_mesh_is_refused() {
    let bytes = std::fs::read(repo().join("fixtures/targets/sphere-cap-export.obj")).unwrap();
    assert!(targets::read("cap.obj", &bytes, Some(Expect::Patch)).is_ok());
    let e = targets::read("cap.obj", &bytes, Some(Expect::Closed)).unwrap_err();
    assert_eq!(e.kind.name(), "TargetTopology");
    assert!(e.message.contains("an open patch"), "{}", e.message);
}

fn random_motion(rng: &mut Rng, angle: f64, shift: f64) -> Rigid {
    let axis = DVec3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    )
    .normalize();
    Rigid {
        rotation: DQuat::from_axis_angle(axis, rng.range(-angle, angle)),
        translation: DVec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ) * shift,
    }
}

#[test]
fn kabsch_recovers_a_random_rigid_motion_to_1e_9() {
    let mut rng = Rng::new(3);
    for _ in 0..100 {
        let m = random_motion(&mut rng, std::f64::consts::PI, 1000.0);
        let from: Vec<DVec3> = (0..3 + rng.below(40))
            .map(|_| {
                DVec3::new(
                    rng.range(-300.0, 300.0),
                    rng.range(-300.0, 300.0),
                    rng.range(-300.0, 300.0),
                )
            })
            .collect();
        let to: Vec<DVec3> = from.iter().map(|&p| m.apply(p)).collect();
        let got = targets::kabsch(&from, &to);
        for (p, q) in from.iter().zip(&to) {
            assert!(got.apply(*p).distance(*q) < 1e-9);
        }
    }
}

/// The target's corners, moved by a random rigid motion, fit back onto it
/// with no distance left. Targets without a motion that maps them onto
/// themselves: a surface of revolution could turn about its axis, held
/// only by its facets.
#[test]
fn a_moved_copy_of_the_target_fits_back_onto_it() {
    let mut rng = Rng::new(4);
    let spheroid =
        "[target]\nfamily = \"spheroid-cap\"\naxes = [200.0, 150.0, 120.0]\nheight = 90.0\n";
    let cases = [
        read("fixtures/targets/saddle-export.stl"),
        targets::read("uneven.toml", spheroid.as_bytes(), None).unwrap(),
    ];
    for t in &cases {
        let m = random_motion(&mut rng, 0.15, 30.0);
        // Every 20th corner: enough to hold the fit, few enough to be quick.
        let moved: Vec<DVec3> = t
            .mesh
            .positions
            .iter()
            .step_by(20)
            .map(|&p| m.apply(p))
            .collect();
        let fit = t.fit(&moved, &[]);
        // Closest-point steps close in linearly: a millionth of D is
        // 0.0004 mm here.
        assert!(
            fit.rms < 1e-6 * t.extent && fit.largest < 1e-5 * t.extent,
            "{}: {fit:?}",
            t.what
        );
        assert_eq!((fit.points, fit.coverage), (moved.len(), None));
    }
}

/// Part of a nearly square patch (the suite's vault: 400 mm long, 383 mm
/// across), turned any way at all, fits back: the middle 60 % of it along
/// one axis spreads more across than along, so the points' principal axes
/// come in the other order than the target's, and the fit tries both (the
/// design of a vault lying on it was fitted at 7.3 % of D).
#[test]
fn part_of_a_nearly_square_patch_turned_any_way_fits_back() {
    let mut rng = Rng::new(5);
    let t = read("fixtures/targets/cylinder.toml");
    let corners = &t.mesh.positions;
    let mean = corners.iter().sum::<DVec3>() / corners.len() as f64;
    for k in 0..3 {
        let range = corners
            .iter()
            .map(|p| (p[k] - mean[k]).abs())
            .fold(0.0, f64::max);
        let part: Vec<DVec3> = corners
            .iter()
            .filter(|p| (p[k] - mean[k]).abs() < 0.6 * range)
            .step_by(7)
            .copied()
            .collect();
        for _ in 0..3 {
            let m = random_motion(&mut rng, std::f64::consts::PI, 500.0);
            let moved: Vec<DVec3> = part.iter().map(|&p| m.apply(p)).collect();
            let fit = t.fit(&moved, &[]);
            assert!(fit.rms < 1e-4 * t.extent, "axis {k}: {fit:?}");
        }
    }
}

/// A lattice that is the target's own triangulation covers all of it.
#[test]
fn the_targets_own_triangles_cover_it() {
    for name in [
        "sphere-cap-export.obj",
        "saddle-export.stl",
        "paraboloid-export.stl",
    ] {
        let t = read(&format!("fixtures/targets/{name}"));
        let facets: Vec<[u32; 4]> = t
            .mesh
            .triangles
            .iter()
            .map(|&[a, b, c]| [a, b, c, c])
            .collect();
        let fit = t.fit(&t.mesh.positions, &facets);
        assert!(fit.rms < 1e-9 * t.extent, "{name}: {fit:?}");
        let coverage = fit.coverage.unwrap();
        assert!(coverage > 0.9999, "{name}: coverage {coverage}");
    }
}

#[test]
fn half_the_triangles_cover_about_half_the_disk() {
    let t = read("fixtures/targets/disk.toml");
    let facets: Vec<[u32; 4]> = t
        .mesh
        .triangles
        .iter()
        .filter(|tri| {
            tri.iter()
                .map(|&i| t.mesh.positions[i as usize].x)
                .sum::<f64>()
                < 0.0
        })
        .map(|&[a, b, c]| [a, b, c, c])
        .collect();
    let c = t.fit(&t.mesh.positions, &facets).coverage.unwrap();
    // Half the disk, and a band 3 % of D (12 mm) wide along its 400 mm
    // diameter: (pi 200^2 / 2 + 400 x 12) / (pi 200^2) = 0.538.
    assert!((c - 0.538).abs() < 0.01, "coverage {c}");
}

#[test]
fn closest_points_on_a_family_agree_with_brute_force() {
    let mut rng = Rng::new(5);
    for name in ["saddle.toml", "torus.toml", "paraboloid-export.stl"] {
        let t = read(&format!("fixtures/targets/{name}"));
        for _ in 0..25 {
            let p = DVec3::new(
                rng.range(-400.0, 400.0),
                rng.range(-400.0, 400.0),
                rng.range(-400.0, 400.0),
            );
            let (q, d) = t.closest(p);
            let brute = t
                .mesh
                .triangles
                .iter()
                .map(|tri| {
                    let [a, b, c] = tri.map(|i| t.mesh.positions[i as usize]);
                    // The plane's foot, clamped by sampling the triangle finely
                    // enough for a bound: the true minimum is never larger.
                    (0..=6)
                        .flat_map(|i| (0..=6 - i).map(move |j| (i, j)))
                        .map(|(i, j)| {
                            p.distance(a + (b - a) * (i as f64 / 6.0) + (c - a) * (j as f64 / 6.0))
                        })
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(f64::INFINITY, f64::min);
            assert!(d <= brute + 1e-9, "{name}: {d} > sampled {brute}");
            assert!((p.distance(q) - d).abs() < 1e-9);
            // ...and no further than the sampling's own error below it.
            assert!(
                d >= brute - 0.05 * t.extent,
                "{name}: {d} far below {brute}"
            );
        }
    }
}

fn bad_targets() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(repo().join("fixtures/targets/bad"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e != "stderr"))
        .collect();
    files.sort();
    files
}

/// The error each bad target is refused with.
const BAD: &[(&str, &str)] = &[
    ("bowtie.obj", "TargetNonManifold"),
    ("cap-too-high.toml", "TargetParameter"),
    ("closed-where-patch.toml", "TargetTopology"),
    ("degenerate.obj", "TargetDegenerate"),
    ("empty.obj", "TargetEmpty"),
    ("garbage.obj", "TargetFormat"),
    ("garbage.stl", "TargetFormat"),
    ("huge.stl", "TargetUnits"),
    ("infinite.stl", "TargetNotFinite"),
    ("missing-parameter.toml", "TargetNeeds"),
    ("nan-radius.toml", "NotFinite"),
    ("nan.obj", "TargetNotFinite"),
    ("non-manifold.obj", "TargetNonManifold"),
    ("ring-hole-too-wide.toml", "TargetParameter"),
    ("thin-torus.toml", "TargetTooLarge"),
    ("tiny.obj", "TargetUnits"),
    ("truncated.stl", "TargetFormat"),
    ("two-pieces.obj", "TargetPieces"),
    ("unknown-family.toml", "UnknownTargetFamily"),
    ("unknown-key.toml", "Toml"),
    ("unused-parameter.toml", "TargetUnused"),
    ("wrong-extension.ply", "TargetFormat"),
];

/// What `karigami -q check RECIPE --target BAD` prints on stderr, then its
/// exit status, as BAD.stderr beside it; the target is refused before the
/// recipe is grown.
#[test]
fn every_bad_target_is_refused_with_its_golden_message() {
    let files = bad_targets();
    let names: Vec<String> = files
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        BAD.iter().map(|(n, _)| n.to_string()).collect::<Vec<_>>()
    );
    let mut failures = Vec::new();
    for (name, kind) in BAD {
        let rel = Path::new("fixtures/targets/bad").join(name);
        let o = karigami(
            &[
                "-q",
                "check",
                "examples/flat-sheet.toml",
                "--target",
                rel.to_str().unwrap(),
            ],
            &repo(),
        );
        let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
        if !stderr.starts_with(&format!("error[{kind}]"))
            || !stderr.contains(&format!("--> {}", rel.display()))
        {
            failures.push(format!(
                "{name}: expected error[{kind}] naming the file, got\n{stderr}"
            ));
        }
        if stderr.contains("panicked") {
            failures.push(format!("{name}: panicked"));
        }
        let mut actual = o.stderr;
        actual.extend(format!("exit status: {}\n", o.status.code().unwrap_or(-1)).bytes());
        if let Err(e) = compare(&format!("fixtures/targets/bad/{name}.stderr"), &actual) {
            failures.push(e);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A binary STL of ten million triangles whose length matches its count (a
/// sparse file: 500 MB that take no disk) is refused from its header.
#[test]
fn ten_million_triangles_are_refused_from_the_header() {
    let dir = scratch("ten-million");
    let path = dir.join("big.stl");
    let mut head = vec![0u8; 80];
    head.extend(10_000_000u32.to_le_bytes());
    std::fs::write(&path, &head).unwrap();
    std::fs::OpenOptions::new()
        .write(true)
        .open(&path)
        .unwrap()
        .set_len(84 + 50 * 10_000_000)
        .unwrap();
    let o = karigami(
        &[
            "-q",
            "check",
            "../../../examples/flat-sheet.toml",
            "--target",
            "big.stl",
        ],
        &dir,
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.starts_with(
            "error[TargetTooLarge]: the binary STL's header counts 10000000 triangles"
        ),
        "{stderr}"
    );
    assert_eq!(o.status.code(), Some(1));
    let _ = std::fs::remove_file(&path);
}

/// `check --target` reports the fit of the design and of the simulated
/// shape; the torus example is grown onto its torus.
#[test]
fn check_reports_the_fit_of_the_torus_example_to_its_torus() {
    let o = crate::util::gallery_check("torus");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        out.contains("target fixtures/targets/torus.toml: torus, a closed surface"),
        "{out}"
    );
    let line = out
        .lines()
        .find(|l| l.contains("fit of the design"))
        .expect("a design fit line");
    let rms: f64 = line
        .split("rms ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    // The fit grows every vertex onto the torus: the triangulation's
    // 0.1 % of D is all that is left.
    assert!(rms < 0.001 * 460.0, "{line}");
}

/// `build --target` adds the fit to report.txt and the terminal; a rebuild
/// with another target does not keep the earlier files, one with the same
/// target keeps them.
#[test]
fn build_puts_the_fit_into_report_txt() {
    let dir = scratch("build-target");
    let recipe = "../../../examples/flat-sheet.toml";
    let disk = "../../../fixtures/targets/disk.toml";
    let o = karigami(&["build", recipe, "--target", disk, "--out", "out"], &dir);
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let report = std::fs::read_to_string(dir.join("out/report.txt")).unwrap();
    let fit = report
        .split(&format!("target {disk}: disk"))
        .nth(1)
        .expect("the fit in report.txt");
    assert!(
        fit.contains("fit of the design") && fit.contains("% of the target's area"),
        "{report}"
    );
    assert!(stdout.contains("fit of the design"), "{stdout}");
    // The same target: kept. Another: built again, with its own fit.
    let again = karigami(&["build", recipe, "--target", disk, "--out", "out"], &dir);
    assert!(String::from_utf8_lossy(&again.stdout).contains("kept every file"));
    let cap = "../../../fixtures/targets/sphere-cap.toml";
    let other = karigami(&["build", recipe, "--target", cap, "--out", "out"], &dir);
    assert!(!String::from_utf8_lossy(&other.stdout).contains("kept every file"));
    let report = std::fs::read_to_string(dir.join("out/report.txt")).unwrap();
    assert!(
        report.contains(&format!("target {cap}: sphere-cap")),
        "{report}"
    );
    // Several recipes and a target: refused, nothing built.
    let batch = karigami(
        &["build", recipe, recipe, "--target", disk, "--out", "batch"],
        &dir,
    );
    assert_eq!(batch.status.code(), Some(2));
    assert!(!dir.join("batch").exists());
}

/// Random bytes, and the suite's meshes with bytes changed, are read or
/// refused, never a panic.
#[test]
fn damaged_targets_are_refused_without_a_panic() {
    let mut rng = Rng::new(6);
    let meshes: Vec<(&str, Vec<u8>)> = [
        "sphere-cap-export.obj",
        "saddle-export.stl",
        "paraboloid-export.stl",
        "height-field.toml",
    ]
    .iter()
    .map(|n| {
        (
            *n,
            std::fs::read(repo().join("fixtures/targets").join(n)).unwrap(),
        )
    })
    .collect();
    for case in 0..300 {
        let (name, mut bytes) = meshes[case % meshes.len()].clone();
        if case % 3 == 0 {
            bytes = (0..rng.below(400)).map(|_| rng.below(256) as u8).collect();
        } else {
            for _ in 0..1 + rng.below(8) {
                let at = rng.below(bytes.len());
                // Digits, signs, separators and line breaks do the most harm.
                bytes[at] = *rng.pick(b"0123456789-.e \n/nai\x00\xff");
            }
        }
        let result = std::panic::catch_unwind(|| targets::read(name, &bytes, None).map(|_| ()));
        assert!(result.is_ok(), "case {case} ({name}) panicked");
    }
}
