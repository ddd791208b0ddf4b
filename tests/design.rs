//! `karigami design` (docs/design.md, "Design your own object"): the
//! simulated shape of what it writes fits the target, and whatever it
//! writes, `build` takes.

use crate::cli::{karigami, repo, scratch};
use crate::goldens::compare;
use karigami::designing::{self, DesignAsk, Found, Searched};
use karigami::targets::Target;
use std::sync::Arc;

fn target(text: &str) -> Target {
    karigami::targets::read("t.toml", text.as_bytes(), None).unwrap()
}

/// The design `karigami design` keeps: of the search's best that `build`
/// takes, the first whose simulated joints meet the goal as the search
/// judges them (`Searched::judge`: on a bump its top too), else the
/// nearest; with the fit of its simulated joints and how far it is from
/// the goal; None when none builds.
/// The search on `t` in its own frame (as the CLI turns it) at `edge`,
/// with `(jobs, polish)`: that frame's target and what it found.
fn search(t: &Target, edge: f64, (jobs, polish): (usize, usize)) -> (Arc<Target>, Searched) {
    let base = karigami::parse(designing::STUB, "t").unwrap();
    let canonical = Arc::new(t.canonical());
    let ask = DesignAsk {
        target: canonical.clone(),
        base: &base,
        edge,
        deadline: None,
        jobs: karigami::Jobs::new(jobs),
        polish,
    };
    let searched = designing::search(&ask, &mut |_| {}).unwrap();
    (canonical, searched)
}

fn design(t: &Target, edge: f64) -> Option<(String, usize, karigami::targets::Fit, f64)> {
    // Rings unpolished: a polish costs a minute and more in this build
    // (`a_saddle_rings_polish_lowers_its_largest_defect` runs one).
    let (canonical, searched) = search(t, edge, (2, 0));
    let mut best: Option<(String, usize, karigami::targets::Fit, f64)> = None;
    for found in searched.found.iter().take(6) {
        // The seed's comment line, as the CLI writes it.
        let seed = [format!("Seed: {}.", found.seed)];
        let text = designing::recipe(found, "t", &seed, None, "");
        let Ok(built) = karigami::build(karigami::parse(&text, "t").unwrap()) else {
            continue;
        };
        let scene = karigami::viewer_scene(&built);
        let mut lattice = built.lattice.clone();
        let sim = scene.simulated.expect("simulated");
        for (v, p) in lattice.vertices.iter_mut().zip(sim) {
            v.pos = p;
        }
        let fit = designing::fit_of(&canonical, &lattice);
        let points: Vec<_> = lattice.vertices.iter().map(|v| v.pos).collect();
        let (miss, _) = searched.judge(&canonical, &fit, (&points, &lattice.facets()));
        if best.as_ref().is_none_or(|b| miss < b.3) {
            best = Some((text, found.cells, fit, miss));
        }
        if miss <= 1.0 {
            break;
        }
    }
    best
}

/// A sphere cap 300 mm across: a loop round its rim, whose simulated
/// joints meet issue 32's goal (golden: 12 points round the rim).
#[test]
fn a_sphere_cap_is_designed_within_the_goal() {
    let t = target("[target]\nfamily = \"sphere-cap\"\nradius = 200.0\nheight = 60.0\n");
    let (text, cells, fit, _) = design(&t, 60.0).expect("a design that builds");
    assert!(text.contains("seed = \"loop\""), "{text}");
    assert!(designing::miss(&fit) <= 1.0, "{fit:?}");
    assert!(fit.rms <= 0.005 * fit.extent, "{fit:?}");
    assert_eq!(text.matches("\n    [").count(), 12, "{text}");
    assert_eq!(cells % 12, 0, "{text}");
}

/// Random smooth height fields (paraboloids of random curvatures, bowls,
/// saddles and troughs, 300 mm square): every candidate the search ranks
/// among its best builds, as the search's hard constraints promise (the
/// CLI builds up to six), and the one kept, written with its comment lines
/// as the CLI writes it, builds again to the same cells. None panics.
#[test]
fn designs_for_random_height_fields_build() {
    // Two fields here; eight more (seed 7) passed too, in 43 s.
    let mut rng = crate::util::Rng::new(32);
    for _ in 0..2 {
        let (a, b) = (rng.range(-40.0, 40.0), rng.range(-40.0, 40.0));
        let heights: Vec<String> = (0..5)
            .map(|i| {
                let row: Vec<String> = (0..5)
                    .map(|j| {
                        let (x, y) = (i as f64 / 4.0 - 0.5, j as f64 / 4.0 - 0.5);
                        format!("{:.3}", a * x * x + b * y * y)
                    })
                    .collect();
                format!("[{}]", row.join(", "))
            })
            .collect();
        let text = format!(
            "[target]\nfamily = \"height-field\"\nwidth = 300.0\nlength = 300.0\nheights = [{}]\n",
            heights.join(", ")
        );
        let (_, searched) = search(&target(&text), 75.0, (2, 0));
        assert!(!searched.found.is_empty(), "{text}: no design");
        for found in searched.found.iter().take(6) {
            let notes = [format!("Seed: {}.", found.seed)];
            let recipe = designing::recipe(found, "t", &notes, None, "");
            let built = karigami::build(karigami::parse(&recipe, "t").unwrap())
                .unwrap_or_else(|e| panic!("{text}: build refuses {}: {}", found.seed, e.message));
            assert_eq!(built.lattice.cells.len(), found.cells, "{recipe}");
        }
    }
}

/// A target that bends tighter than the strips reach at their allowable
/// strain (fixtures/targets/too-curved.toml, a half pipe of radius 25 mm
/// against 33.3 mm for 1 mm ABS at 1.5 %) is refused before the search,
/// with both radii and what would reach it (golden), writing nothing.
#[test]
fn a_target_tighter_than_the_strips_bend_is_refused_before_the_search() {
    let dir = scratch("design-too-curved");
    let out = dir.join("vault.toml");
    let target = "fixtures/targets/too-curved.toml";
    let o = karigami(
        &["-q", "design", target, "--out", out.to_str().unwrap()],
        &repo(),
    );
    let mut actual = o.stderr.clone();
    actual.extend(format!("exit status: {}\n", o.status.code().unwrap_or(-1)).bytes());
    compare("tests/golden/design/too-curved.stderr", &actual).unwrap();
    assert!(!out.exists());
}

/// A closed torus is refused with why (no rim, no pole; the paper's
/// wound loop misses the goal) and the band that would work (golden).
#[test]
fn a_torus_is_refused_with_the_band_that_would_work() {
    let dir = scratch("design-torus");
    let out = dir.join("torus.toml");
    let o = karigami(
        &[
            "-q",
            "design",
            "fixtures/targets/torus.toml",
            "--out",
            out.to_str().unwrap(),
        ],
        &repo(),
    );
    let mut actual = o.stderr.clone();
    actual.extend(format!("exit status: {}\n", o.status.code().unwrap_or(-1)).bytes());
    compare("tests/golden/design/torus.stderr", &actual).unwrap();
    assert!(!out.exists());
}

/// A closed ellipsoid of three unequal axes is round about none of them:
/// refused with how far from round and what would work (golden).
#[test]
fn a_closed_surface_not_of_revolution_is_refused() {
    let dir = scratch("design-triaxial");
    std::fs::write(
        dir.join("triaxial.toml"),
        "[target]\nfamily = \"spheroid-cap\"\naxes = [200.0, 150.0, 120.0]\nheight = 240.0\n",
    )
    .unwrap();
    let o = karigami(&["-q", "design", "triaxial.toml", "--out", "t.toml"], &dir);
    let mut actual = o.stderr.clone();
    actual.extend(format!("exit status: {}\n", o.status.code().unwrap_or(-1)).bytes());
    compare("tests/golden/design/triaxial.stderr", &actual).unwrap();
    assert!(!dir.join("t.toml").exists());
}

/// A whole sphere 200 mm across (a cap as high as twice its radius), at a
/// 50 mm edge: the search's best design is a loop from pole to pole that
/// meets the goal on the whole closed sphere, its open polar caps counted
/// uncovered. (Its simulated shape, too slow to build here, is measured
/// in docs/design.md, "What it reaches": the second candidate built meets
/// the goal.)
#[test]
fn a_closed_sphere_is_designed_pole_to_pole() {
    let t = target("[target]\nfamily = \"sphere-cap\"\nradius = 100.0\nheight = 200.0\n");
    let (_, searched) = search(&t, 50.0, (1, 0));
    assert!(
        searched
            .topology
            .starts_with("loop: the target is a closed surface of revolution")
    );
    let best = &searched.found[0];
    assert!(best.lattice.contains("seed = \"loop\""), "{}", best.lattice);
    assert!(best.seed.contains("near the top pole"), "{}", best.seed);
    let covered = best.fit.coverage.unwrap();
    assert!(designing::miss(&best.fit) <= 1.0, "{:?}", best.fit);
    assert!((0.85..1.0).contains(&covered), "{:?}", best.fit);
}

/// A recipe that records a target (as `karigami design` writes it): `check`
/// and `build` fit it without --target while its bytes hash as recorded,
/// and say in one line, exit 0, when it is missing or changed; --target
/// still overrides it; a rebuild with the target changed writes again.
#[test]
fn the_recorded_target_is_fitted_without_target_or_said_missing() {
    let dir = scratch("design-recorded");
    let chain = std::fs::read_to_string(repo().join("templates/chain.toml")).unwrap();
    let disk = std::fs::read(repo().join("fixtures/targets/disk.toml")).unwrap();
    std::fs::write(dir.join("disk.toml"), &disk).unwrap();
    let hash = format!("{:016x}", karigami::util::fnv1a(&disk));
    let recipe = |file: &str, hash: &str| {
        let text = chain.replace(
            "name = \"chain\"\n",
            &format!("name = \"chain\"\n\n[target]\nfile = \"{file}\"\nhash = \"{hash}\"\n"),
        );
        std::fs::write(dir.join("chain.toml"), text).unwrap();
    };
    let check = |extra: &[&str]| {
        let o = karigami(&[&["check", "chain.toml"], extra].concat(), &dir);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        String::from_utf8(o.stdout).unwrap()
    };
    recipe("disk.toml", &hash);
    let fitted = check(&[]);
    assert!(
        fitted.contains("target disk.toml: disk, an open patch")
            && fitted.contains("fit of the design, "),
        "{fitted}"
    );
    let o = karigami(&["-q", "build", "chain.toml", "--out", "out"], &dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let report = || std::fs::read_to_string(dir.join("out/report.txt")).unwrap();
    assert!(report().contains("target disk.toml: disk"), "{}", report());
    // The same recipe, its target edited: built again, the fit not given.
    std::fs::write(dir.join("disk.toml"), [&disk[..], b"# edited\n"].concat()).unwrap();
    let o = karigami(&["-q", "build", "chain.toml", "--out", "out"], &dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        report().contains("target disk.toml (recorded by the recipe): changed since"),
        "{}",
        report()
    );
    std::fs::write(dir.join("disk.toml"), &disk).unwrap();
    recipe("disk.toml", "0123456789abcdef");
    let changed = check(&[]);
    assert!(
        changed.contains(
            "target disk.toml (recorded by the recipe): changed since the design was made"
        ) && !changed.contains("fit of the design"),
        "{changed}"
    );
    let other = check(&["--target", "../../../fixtures/targets/sphere-cap.toml"]);
    assert!(other.contains("sphere-cap, an open patch"), "{other}");
    recipe("gone.toml", &hash);
    assert!(check(&[]).contains("target gone.toml (recorded by the recipe): not found"));
    let o = karigami(&["-q", "build", "chain.toml", "--out", "out"], &dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        report().contains("target gone.toml (recorded by the recipe): not found"),
        "{}",
        report()
    );
}

/// Each smooth family of issue 32 that the search reaches, at a small
/// size (about 300 mm across, 60-75 mm cells, so the suite stays fast):
/// the simulated joints meet the goal (docs/design.md, "The goal").
fn meets_the_goal(text: &str, edge: f64) -> (String, usize) {
    let (recipe, cells, fit, miss) = design(&target(text), edge).expect("a design that builds");
    assert!(miss <= 1.0, "{text}: {fit:?}, {miss}");
    (recipe, cells)
}

/// A flatter spheroid cap than the suite's, the other way up, its rim
/// round (an oval rim: `an_oval_cap_is_designed_within_the_goal`).
#[test]
fn a_spheroid_cap_is_designed_within_the_goal() {
    let (recipe, _) = meets_the_goal(
        "[target]\nfamily = \"spheroid-cap\"\naxes = [150.0, 150.0, 60.0]\nturn = [180.0, 0.0, 0.0]\n",
        60.0,
    );
    assert!(recipe.contains("seed = \"loop\""), "{recipe}");
}

/// A cap whose rim is an oval (semi-axes 150 and 115 mm, 70 mm deep): a
/// loop at equal chords round its rim closes every ring as a circle's
/// does (docs/design.md, "Level rims"). Sheets on such caps covered 21 to
/// 39 %.
#[test]
fn an_oval_cap_is_designed_within_the_goal() {
    let (recipe, _) = meets_the_goal(
        "[target]\nfamily = \"spheroid-cap\"\naxes = [150.0, 115.0, 70.0]\n",
        60.0,
    );
    assert!(recipe.contains("seed = \"loop\""), "{recipe}");
    assert!(
        recipe.contains("at equal chords round the level rim"),
        "{recipe}"
    );
}

#[test]
fn a_paraboloid_is_designed_within_the_goal() {
    meets_the_goal(
        "[target]\nfamily = \"paraboloid\"\nradius = 150.0\ndepth = 70.0\n",
        60.0,
    );
}

#[test]
fn a_flat_plate_is_designed_within_the_goal() {
    let zeros = ["[0.0, 0.0, 0.0]"; 3].join(", ");
    let (recipe, _) = meets_the_goal(
        &format!(
            "[target]\nfamily = \"height-field\"\nwidth = 240.0\nlength = 200.0\nheights = [{zeros}]\n"
        ),
        70.0,
    );
    assert!(recipe.contains("seed = \"sheet\""), "{recipe}");
}

/// A height field of a Gaussian `height` high (`sigma` wide) about the
/// middle of a `width` x `length` sheet, on a grid of `columns` x `rows`.
fn gaussian(
    width: f64,
    length: f64,
    height: f64,
    sigma: f64,
    [columns, rows]: [usize; 2],
) -> String {
    let rows: Vec<String> = (0..rows)
        .map(|j| {
            let y = -length / 2.0 + length * j as f64 / (rows - 1) as f64;
            let row: Vec<String> = (0..columns)
                .map(|i| {
                    let x = -width / 2.0 + width * i as f64 / (columns - 1) as f64;
                    format!(
                        "{:.3}",
                        height * (-(x * x + y * y) / (2.0 * sigma * sigma)).exp()
                    )
                })
                .collect();
            format!("[{}]", row.join(", "))
        })
        .collect();
    format!(
        "[target]\nfamily = \"height-field\"\nwidth = {width:.1}\nlength = {length:.1}\nheights = [{}]\n",
        rows.join(", ")
    )
}

/// A smooth bump on a flat sheet (mixed curvature: a cap on top, a
/// saddle-like flank, a flat rim), 260 x 260 mm with a Gaussian 45 mm
/// high (sigma 55 mm): sheets from a side do not climb it, so a loop
/// seeded round a level circle about its axis, or round a rounded box
/// inscribed in the sheet, grows up it to the top (docs/design.md, "Round
/// bumps"; the CLI's design of this 9 x 9 grid, round a rounded box,
/// simulates to rms 0.46 %, largest 0.85 % of D, 90.1 % covered; round
/// a circle, before the boxes, 0.82 %, 2.22 %, 89.2 %).
#[test]
fn a_bump_on_a_sheet_is_designed_within_the_goal() {
    let (recipe, _) = meets_the_goal(&gaussian(260.0, 260.0, 45.0, 55.0, [9, 9]), 60.0);
    assert!(recipe.contains("seed = \"loop\""), "{recipe}");
    assert!(
        recipe.contains("# Seed: a loop of ")
            && (recipe.contains("about the bump's axis")
                || recipe.contains("round the rounded box")),
        "{recipe}"
    );
}

/// A bump on a sheet 1.33 times as long as wide (300 x 225 mm, 45 mm
/// high, sigma 55 mm): a circle about its axis covers only the disk
/// between the long sides, and a loop round the rounded box inscribed in
/// the sheet reaches its ends (docs/design.md, "Rounded boxes"; the CLI's
/// design of this 11 x 8 grid simulates to rms 0.44 %, largest 1.00 % of
/// D, 91.2 % covered, and `scripts/bump-regions` finds the bump's top 89 %
/// covered; at 300 x 200 mm the pooled goal passed with the top 43 %
/// covered before the top was judged apart).
#[test]
fn a_bump_on_a_long_sheet_is_designed_within_the_goal() {
    let (recipe, _) = meets_the_goal(&gaussian(300.0, 225.0, 45.0, 55.0, [11, 8]), 60.0);
    assert!(recipe.contains("seed = \"loop\""), "{recipe}");
    assert!(
        recipe.contains("round the rounded box (a superellipse of exponent"),
        "{recipe}"
    );
}

/// A saddle (negative curvature) 300 x 300 mm, rising 40 mm at the middles
/// of two sides and falling 40 mm at the others: a sheet seeded on its
/// boundary (docs/design.md,
/// "What it reaches": the CLI's design simulates to rms 0.34 %, largest
/// 0.85 % of D, 95.5 % covered).
#[test]
fn a_saddle_is_designed_within_the_goal() {
    let (recipe, _) = meets_the_goal(
        "[target]\nfamily = \"saddle\"\nwidth = 300.0\nlength = 300.0\nheight = 40.0\n",
        60.0,
    );
    assert!(recipe.contains("seed = \"sheet\""), "{recipe}");
}

/// A ring cut from a saddle (a pringle band, z = 30 (r / 160)^2 cos 2t
/// between r = 60 and 160 mm; docs/design.md, "Saddle rings"): a loop
/// seeded on its outer rim whose every front is laid on the saddle fitted
/// to the target. It meets the goal (the CLI's design: rms 0.56 %, largest
/// 1.24 % of D, all covered), and its rebuilt fronts carry the band's
/// negative curvature: grown again on fronts as they grow (none laid),
/// the same rows average an angle defect of 0 to 0.01 deg.
#[test]
fn a_saddle_ring_is_designed_within_the_goal() {
    let (recipe, _) = meets_the_goal(
        "[target]\nfamily = \"saddle-ring\"\nradius = 160.0\nhole = 60.0\nheight = 30.0\n",
        60.0,
    );
    assert!(recipe.contains("seed = \"loop\""), "{recipe}");
    let d = karigami::parse(&recipe, "t").unwrap();
    assert!(
        d.rows
            .iter()
            .all(|r| r.front.as_ref().is_some_and(|f| f.saddle.is_some())),
        "every front laid on a saddle: {recipe}"
    );
    let mean = |l: &karigami::Lattice| {
        let c = l.curvature();
        c.iter().map(|v| v.defect.to_degrees()).sum::<f64>() / c.len() as f64
    };
    let laid = mean(&d.grow().unwrap());
    let mut plain = d.clone();
    for row in &mut plain.rows {
        row.front = None;
    }
    let plain = mean(&plain.grow().unwrap());
    assert!(
        laid < -0.1 && plain.abs() < 0.01,
        "laid {laid}, plain {plain} deg"
    );
}

/// The largest interior angle defect (degrees) of a recipe's design and of
/// its simulated equilibrium, the larger of the two.
fn largest_defect(recipe: &str) -> f64 {
    let d = karigami::parse(recipe, "t").unwrap();
    let designed = d.grow().unwrap();
    let deploy = karigami::deploy::deployment(&designed);
    let m = &d.fabrication.material;
    let run =
        karigami::simulation::simulate(&designed, &deploy, m.width, m.thickness, &d.simulation)
            .expect("simulates");
    let simulated = karigami::simulation::placed_lattice(&designed, &run.lm);
    [designed, simulated]
        .iter()
        .flat_map(|l| l.curvature())
        .map(|v| v.defect.to_degrees())
        .fold(f64::NEG_INFINITY, f64::max)
}

/// A ring cut from a saddle (fixtures/targets/saddle-ring.toml at a 90 mm
/// edge, as examples/saddle-ring.toml) grown nearest the target has
/// vertices of positive defect; its rings polished (docs/design.md,
/// "Polished rings"), here on a small budget of 150 designs, lower the
/// largest defect of the design and the simulated shape, and still meet
/// the goal once built. Not yet every vertex negative, the polished ring
/// is ranked by its fit with the rest, not built first.
#[test]
fn a_saddle_rings_polish_lowers_its_largest_defect() {
    let bytes = std::fs::read(repo().join("fixtures/targets/saddle-ring.toml")).unwrap();
    let t = karigami::targets::read("saddle-ring.toml", &bytes, None).unwrap();
    let (canonical, searched) = search(&t, 90.0, (2, 36 * 150));
    let is_polished = |f: &&Found| f.seed.contains("polished over 150 designs");
    let polished = searched.found.iter().find(is_polished).expect("polished");
    // The best grown, the one the polish starts from.
    let grown = searched
        .found
        .iter()
        .find(|f| !is_polished(f))
        .expect("grown");
    let text = |f: &Found| designing::recipe(f, "t", &[], None, "");
    let (before, after) = (
        largest_defect(&text(grown)),
        largest_defect(&text(polished)),
    );
    println!(
        "largest defect, design or simulated: {before:+.3} deg grown, {after:+.3} deg polished"
    );
    assert!(before > 0.0 && after < before, "{before} -> {after}");
    let built = karigami::build(karigami::parse(&text(polished), "t").unwrap()).expect("builds");
    let mut lattice = built.lattice.clone();
    let sim = karigami::viewer_scene(&built).simulated.expect("simulated");
    for (v, p) in lattice.vertices.iter_mut().zip(sim) {
        v.pos = p;
    }
    let fit = designing::fit_of(&canonical, &lattice);
    assert!(designing::miss(&fit) <= 1.0, "{fit:?}");
}

/// A paraboloid 300 mm across as a modeller exports it: an OBJ of uneven
/// rings and triangles, turned off level by 30 degrees and moved far from
/// the origin. `karigami design` takes it into its own frame and meets the
/// goal, and the fits its recipe records are the ones `check` reports for
/// that recipe, to the last digit (both fit the target as read, the
/// lattice as assembled).
#[test]
fn an_exported_mesh_turned_and_moved_is_designed_within_the_goal() {
    let mut rng = crate::util::Rng::new(7);
    let (rings, around) = (7, 28);
    let turn = glam::DQuat::from_axis_angle(glam::DVec3::new(1.0, 2.0, 0.5).normalize(), 0.52);
    let at = glam::DVec3::new(640.0, -310.0, 95.0);
    let mut obj = String::from("# uneven paraboloid r 150 depth 70, turned and moved\n");
    let mut vertex = |p: glam::DVec3| {
        let q = turn * p + at;
        obj.push_str(&format!("v {:.6} {:.6} {:.6}\n", q.x, q.y, q.z));
    };
    vertex(glam::DVec3::ZERO);
    for k in 1..=rings {
        let f = k as f64 / rings as f64;
        let r = 150.0
            * if k == rings {
                1.0
            } else {
                f + rng.range(-0.03, 0.03)
            };
        let offset = rng.range(0.0, 1.0);
        for j in 0..around {
            let a = std::f64::consts::TAU * (j as f64 + offset) / around as f64;
            vertex(glam::DVec3::new(
                r * a.cos(),
                r * a.sin(),
                70.0 * (r / 150.0).powi(2),
            ));
        }
    }
    let id = |k: usize, j: usize| 2 + (k - 1) * around + j % around;
    for j in 0..around {
        obj.push_str(&format!("f 1 {} {}\n", id(1, j), id(1, j + 1)));
    }
    for k in 1..rings {
        for j in 0..around {
            let (a, b, c, d) = (id(k, j), id(k, j + 1), id(k + 1, j), id(k + 1, j + 1));
            obj.push_str(&format!("f {a} {c} {d}\nf {a} {d} {b}\n"));
        }
    }
    let dir = scratch("design-export");
    std::fs::write(dir.join("export.obj"), &obj).unwrap();
    let o = karigami(
        &[
            "-q",
            "design",
            "export.obj",
            "--edge",
            "60",
            "--out",
            "r.toml",
        ],
        &dir,
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let recipe = std::fs::read_to_string(dir.join("r.toml")).unwrap();
    assert!(
        recipe.contains("# The simulated shape meets the goal"),
        "{recipe}"
    );
    let o = karigami(&["check", "r.toml"], &dir);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let checked = String::from_utf8(o.stdout).unwrap();
    let recorded = |what: &str| {
        let line = recipe.lines().find_map(|l| l.strip_prefix(what));
        line.and_then(|l| l.strip_suffix('.'))
            .expect(what)
            .to_string()
    };
    for (recorded, said) in [
        (recorded("# Fit of the design: "), "fit of the design, "),
        (
            recorded("# Fit of the simulated shape: "),
            "fit of the simulated shape, ",
        ),
    ] {
        assert!(
            checked.contains(&format!("{said}{recorded}\n")),
            "{recorded}\n{checked}"
        );
    }
    let extent = checked
        .split("largest extent D ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|d| d.parse::<f64>().ok())
        .expect("D");
    assert!((extent - 300.0).abs() < 3.0, "{checked}");
}

/// The simulated joints of a recipe's build, fitted to `target`, with the
/// build's design vertices and lattice.
fn simulated_fit(
    text: &str,
    target: &Target,
) -> (
    karigami::targets::Fit,
    Vec<glam::DVec3>,
    Vec<glam::DVec3>,
    karigami::Lattice,
) {
    let built = karigami::build(karigami::parse(text, "vault").unwrap()).expect("builds");
    let n = built.lattice.vertices.len();
    let sim = karigami::viewer_scene(&built).simulated.expect("simulated");
    let design: Vec<glam::DVec3> = built.lattice.vertices.iter().map(|v| v.pos).collect();
    let mut lattice = built.lattice.clone();
    for (v, p) in lattice.vertices.iter_mut().zip(&sim) {
        v.pos = *p;
    }
    let fit = designing::fit_of(target, &lattice);
    (fit, design, sim[..n].to_vec(), built.lattice.clone())
}

/// The choice `karigami design` makes for a vault (src/cli/design.rs,
/// docs/design.md "Supports"), on fixtures/designs/vault.toml's sheet as
/// the search found it: free, its simulated sheet flattens and misses the
/// goal; held at the feet `with_feet` gives it, it meets the goal.
#[test]
fn a_vault_that_flattens_free_meets_the_goal_held_at_its_feet() {
    let recipe = std::fs::read_to_string("fixtures/designs/vault.toml").unwrap();
    let start = recipe.find("[lattice]").unwrap();
    let end = recipe.find("\n# Supports:").unwrap();
    let file = std::fs::read_to_string("fixtures/designs/vault-target.toml").unwrap();
    let t = target(&file).canonical();
    let lattice = karigami::parse(&recipe, "vault").unwrap().grow().unwrap();
    let found = Found {
        lattice: recipe[start..=end].to_string(),
        cells: lattice.cells.len(),
        fit: designing::fit_of(&t, &lattice),
        seed: "the vault's seed".into(),
    };
    let free = designing::recipe(&found, "vault", &[], None, "");
    assert!(!free.contains("supports"), "{free}");
    let (fit, design, simulated, built) = simulated_fit(&free, &t);
    assert!(designing::miss(&fit) > 1.0, "free: {fit:?}");
    assert!(designing::flattens(&design, &simulated));
    let held = designing::with_feet(&found, &built, 60.0).expect("feet");
    assert!(
        held.lattice
            .contains("\n[simulation]\nsupports = [[0, 0], [0, 4], [1, 0]"),
        "{}",
        held.lattice
    );
    let (fit, design, simulated, _) =
        simulated_fit(&designing::recipe(&held, "vault", &[], None, ""), &t);
    assert!(designing::miss(&fit) <= 1.0, "held: {fit:?}");
    assert!(!designing::flattens(&design, &simulated));
}
