//! viewer.html: deterministic, self-contained and within its size budget,
//! and driven in a real browser (headless Chromium from the distribution,
//! over the DevTools protocol by tests/tools/viewer_driver.py) as a maker
//! would use it: steps, clicks, taps, search, deployment. Screenshots of
//! every tested view go to target/viewer-shots/.

use crate::cli::repo;
use crate::thirdparty::run;
use karigami::{
    Build, Layout, Outline, Placement, Sheet, build,
    deploy::deployment,
    formats::viewer::{Scene, write},
    parts,
};
use serde_json::{Value, json};
use std::collections::BTreeSet;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// The example's build, shared with the other tests (tests/util.rs).
fn built(name: &str) -> &'static Build {
    crate::util::example(name)
}

fn page(b: &Build) -> Vec<u8> {
    write(&karigami::viewer_scene(b))
}

/// The JSON data block of a page.
fn data(html: &str) -> Value {
    let start = html.find("id=\"karigami-data\">").unwrap() + "id=\"karigami-data\">".len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end]).unwrap()
}

#[test]
fn viewer_page_is_self_contained_deterministic_and_small() {
    let b = built("flat-sheet");
    let html = page(b);
    let again = crate::util::build_example("flat-sheet", &Default::default());
    assert_eq!(html, page(&again), "same recipe, same bytes");
    let file = karigami::files(b)
        .into_iter()
        .find(|f| f.0 == "viewer.html")
        .unwrap();
    assert_eq!(file.1, html, "the build writes this page");
    let text = String::from_utf8(html).unwrap();
    eprintln!("flat-sheet viewer.html: {} bytes", text.len());
    assert!(text.len() < 1_500_000, "{} bytes", text.len());
    // Nothing to fetch: no URL, no external script, style or image.
    for what in ["://", "src=", "@import", "url(", "href=\"http"] {
        assert!(!text.contains(what), "{what} in the page");
    }
    let d = data(&text);
    assert_eq!(strips_of(&d).len(), b.parts.strips.len());
    assert_eq!(d["steps"].as_array().unwrap().len(), b.lattice.steps());
    assert_eq!(
        d["cells"].as_array().unwrap().len(),
        7 * b.lattice.cells.len()
    );
    assert_eq!(
        d["points"].as_array().unwrap().len(),
        3 * (b.lattice.vertices.len() + b.lattice.cells.len())
    );
    // Strips carry their sheet and position from the layout.
    let strips = strips_of(&d);
    for (s, sheet) in b.layout.sheets.iter().enumerate() {
        for p in &sheet.placements {
            let row = &strips[p.part];
            assert_eq!(row.id, b.parts.strips[p.part].id);
            assert_eq!(row.sheet, s + 1);
            assert!((row.x - p.x).abs() < 1e-4);
            assert!((row.y - p.y).abs() < 1e-4);
            assert_eq!(row.rotated, p.rotated);
        }
    }
}

/// Positions as the page reads them: differences from the point before
/// (x, y, z), in mm to 0.001, summed in whole micrometres.
fn positions(d: &Value) -> Vec<f64> {
    let mut at = [0i64; 3];
    d.as_array()
        .unwrap()
        .iter()
        .enumerate()
        .map(|(k, v)| {
            at[k % 3] += (v.as_f64().unwrap() * 1e3).round() as i64;
            at[k % 3] as f64 / 1e3
        })
        .collect()
}

/// One strip as the page reads it from the data block.
struct PageStrip {
    id: String,
    length: f64,
    legs: [f64; 2],
    cut: f64,
    part: String,
    sheet: usize,
    x: f64,
    y: f64,
    rotated: bool,
}

/// The strips decoded as viewer.js decodes them: IDs from the runs of
/// cells (row, first column, count) and the rod (A then B per cell),
/// numbers from the shape table, places five numbers a strip.
fn strips_of(d: &Value) -> Vec<PageStrip> {
    let int = |v: &Value| v.as_u64().unwrap() as usize;
    let runs: Vec<usize> = d["strips"]["ids"]
        .as_array()
        .unwrap()
        .iter()
        .map(int)
        .collect();
    let (rd, cd) = (runs[0], runs[1]);
    let cells: Vec<String> = runs[2..]
        .chunks(3)
        .flat_map(|r| (0..r[2]).map(move |n| format!("R{:0rd$}-C{:0cd$}-", r[0], r[1] + n)))
        .collect();
    let shapes = d["strips"]["shapes"].as_array().unwrap();
    let place = d["strips"]["place"].as_array().unwrap();
    assert_eq!(place.len() % 5, 0);
    let mut at = (0i64, 0i64);
    place
        .chunks(5)
        .enumerate()
        .map(|(i, f)| {
            let sh = &shapes[int(&f[0])];
            let n = |v: &Value| v.as_f64().unwrap();
            // Places are differences from the strip before, in 0.0001 mm.
            at.0 += (n(&f[2]) * 1e4).round() as i64;
            at.1 += (n(&f[3]) * 1e4).round() as i64;
            PageStrip {
                id: format!("{}{}", cells[i / 2], ["A", "B"][i % 2]),
                length: n(&sh[0]),
                legs: [n(&sh[1]), n(&sh[2])],
                cut: n(&sh[3]),
                part: sh[4].as_str().unwrap().to_string(),
                sheet: int(&f[1]),
                x: at.0 as f64 / 1e4,
                y: at.1 as f64 / 1e4,
                rotated: int(&f[4]) == 1,
            }
        })
        .collect()
}

#[test]
fn viewer_strips_decode_to_every_strips_own_id_and_numbers() {
    // The compact strip table (IDs from cells, shared shapes) must give
    // every strip of every example its own ID, lengths, part and place.
    for entry in std::fs::read_dir(repo().join("examples")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        let b = built(&name);
        let d = data(&String::from_utf8(page(b)).unwrap());
        let strips = strips_of(&d);
        assert_eq!(strips.len(), b.parts.strips.len(), "{name}");
        let fab = &b.design.fabrication;
        let mut place = vec![None; strips.len()];
        for (s, sheet) in b.layout.sheets.iter().enumerate() {
            for p in &sheet.placements {
                place[p.part] = Some((s + 1, *p));
            }
        }
        for ((page, strip), place) in strips.iter().zip(&b.parts.strips).zip(place) {
            let (sheet, p) = place.unwrap();
            let near = |a: f64, b: f64| (a - b).abs() <= 5.0001e-5;
            assert_eq!(page.id, strip.id, "{name}");
            assert!(near(page.length, strip.length), "{name} {}", strip.id);
            assert!(near(page.legs[0], strip.legs[0]), "{name} {}", strip.id);
            assert!(near(page.legs[1], strip.legs[1]), "{name} {}", strip.id);
            assert!(near(page.cut, Outline::of(strip.length, fab).length));
            assert_eq!(page.part, b.parts.types[strip.part_type].code);
            assert_eq!((page.sheet, page.rotated), (sheet, p.rotated));
            assert!(
                near(page.x, p.x) && near(page.y, p.y),
                "{name} {}",
                strip.id
            );
        }
        // Joints: vertex and rods as differences, keys from runs of vertices.
        let int = |v: &Value| v.as_i64().unwrap();
        let runs: Vec<i64> = d["keys"].as_array().unwrap().iter().map(int).collect();
        let keys: Vec<(i64, i64)> = runs
            .chunks(3)
            .flat_map(|r| (0..r[2]).map(move |n| (r[0], r[1] + n)))
            .collect();
        assert_eq!(keys.len(), b.lattice.vertices.len(), "{name}");
        for (st, step) in d["steps"].as_array().unwrap().iter().zip(&b.steps) {
            let flat: Vec<i64> = st["joints"].as_array().unwrap().iter().map(int).collect();
            let (mut at, mut v) = (0, 0);
            for j in &step.joints {
                v += flat[at];
                assert_eq!(v, i64::from(j.vertex), "{name}");
                let key = b.lattice.vertex(j.vertex).key;
                assert_eq!(keys[v as usize], (key.row.into(), key.col.into()));
                assert_eq!(flat[at + 1], j.ends.len() as i64);
                let mut rod = 0;
                for (k, e) in j.ends.iter().enumerate() {
                    rod += flat[at + 2 + k];
                    assert_eq!(rod, e.rod as i64, "{name}");
                }
                at += 2 + j.ends.len();
            }
            assert_eq!(at, flat.len(), "{name}");
        }
    }
}

#[test]
fn a_name_cannot_break_out_of_the_page() {
    let source = std::fs::read_to_string(repo().join("examples/mirror-arm.toml"))
        .unwrap()
        .replace(
            "name = \"mirror-arm\"",
            "name = \"</script><script>alert(1)</script> & <b>\"",
        );
    let b = build(karigami::parse(&source, "x").unwrap()).unwrap();
    let text = String::from_utf8(page(&b)).unwrap();
    assert_eq!(text.matches("</script>").count(), 2, "only the page's own");
    assert!(text.contains("&lt;/script&gt;&lt;script&gt;alert(1)&lt;/script&gt; &amp; &lt;b&gt;"));
    assert_eq!(
        data(&text)["name"],
        json!("</script><script>alert(1)</script> & <b>")
    );
}

/// A 100 x 100 sheet from the starter template.
fn big_sheet() -> karigami::Design {
    let source = std::fs::read_to_string(repo().join("templates/sheet.toml")).unwrap();
    let source = source
        .replace("to = [240.0, 0.0]", "to = [4000.0, 0.0]")
        .replace("cells = 6", "cells = 100")
        .replace("rows = 5", "rows = 100");
    let cut = source.find("\n[[lattice.rows]]").unwrap();
    karigami::parse(&source[..cut], "big").unwrap()
}

#[test]
fn viewer_page_of_a_10000_cell_sheet_is_under_15_mb() {
    // The pipeline up to what the page needs, with a stand-in layout: the
    // real nesting of 20,000 strips takes over a minute in a debug build,
    // and a placement is written the same way wherever it lands.
    let design = big_sheet();
    let lattice = design.grow().unwrap();
    assert_eq!(lattice.cells.len(), 10_000);
    let fab = &design.fabrication;
    let parts = parts(&lattice, &karigami::joints(&lattice), fab).unwrap();
    let lengths: Vec<f64> = parts
        .strips
        .iter()
        .map(|s| Outline::of(s.length, fab).length)
        .collect();
    let per_sheet = 90;
    let layout = Layout {
        by_step: false,
        sheet: fab.sheet.clone(),
        part_width: Outline::of(0.0, fab).width,
        sheets: (0..lengths.len().div_ceil(per_sheet))
            .map(|s| Sheet {
                placements: (s * per_sheet..((s + 1) * per_sheet).min(lengths.len()))
                    .map(|part| Placement {
                        part,
                        x: 5.0 + (part % 3) as f64 * 196.123_456,
                        y: 5.0 + (part % per_sheet / 3) as f64 * 12.987_654,
                        rotated: part % 7 == 0,
                    })
                    .collect(),
                test_piece: None,
            })
            .collect(),
        lengths,
        test_piece: None,
    };
    let deployment = deployment(&lattice);
    let steps = karigami::steps(&lattice, &karigami::joints(&lattice));
    let html = write(&Scene::new(
        &design,
        &lattice,
        &lattice,
        &parts,
        &layout,
        &deployment,
        &steps,
    ));
    // Kept for a look in a browser (the page's speed is not a test).
    std::fs::write(shots().join("sheet-100x100.html"), &html).unwrap();
    eprintln!("10,000-cell sheet viewer.html: {} bytes", html.len());
    assert!(html.len() < 15_000_000, "{} bytes", html.len());
}

/// Where screenshots go: target/viewer-shots/ in the repository.
fn shots() -> PathBuf {
    let dir = repo().join("target").join("viewer-shots");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Run the driver on a plan; None when Chromium is missing and not required.
fn drive(plan: &Value) -> Option<Value> {
    let exe = ["chromium", "chromium-browser"].into_iter().find(|e| {
        run("sh", &["-c", &format!("command -v {e}")]).is_some_and(|o| o.status.success())
    });
    let Some(exe) = exe else {
        assert!(
            std::env::var_os("KARIGAMI_REQUIRE_TOOLS").is_none(),
            "chromium is required (scripts/test installs it)"
        );
        eprintln!("note: chromium not available; browser tests skipped");
        return None;
    };
    let script = repo().join("tests/tools/viewer_driver.py");
    let mut plan = plan.clone();
    plan["chromium"] = json!(exe);
    let mut child = Command::new("python3")
        .arg(&script)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("python3 runs");
    child
        .stdin
        .take()
        .unwrap()
        .write_all(plan.to_string().as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "driver failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(serde_json::from_slice(&out.stdout).unwrap())
}

/// Distinct colours in a screenshot, and the share of pixels that differ
/// from the most common one (the background).
fn colours(path: &Path) -> (usize, f64) {
    let pixmap = tiny_skia::Pixmap::load_png(path).unwrap();
    // Packed and sorted rather than hashed: quick in a debug build.
    let mut packed: Vec<u32> = pixmap
        .pixels()
        .iter()
        .map(|p| u32::from_be_bytes([0, p.red(), p.green(), p.blue()]))
        .collect();
    packed.sort_unstable();
    let (mut distinct, mut longest, mut run) = (0, 0, 0);
    for (i, c) in packed.iter().enumerate() {
        if i == 0 || packed[i - 1] != *c {
            distinct += 1;
            run = 0;
        }
        run += 1;
        longest = longest.max(run);
    }
    (distinct, 1.0 - longest as f64 / packed.len() as f64)
}

/// JavaScript that sets a range input as a person dragging it would.
fn slide(id: &str, value: usize) -> String {
    format!(
        "(s => {{ s.value = '{value}'; s.dispatchEvent(new Event('input', {{bubbles: true}})); return +s.value; }})(document.getElementById('{id}'))"
    )
}

fn search(text: &str) -> Vec<Value> {
    vec![
        json!({"eval": "(s => { s.value = ''; s.dispatchEvent(new Event('input')); s.focus(); return 1; })(document.getElementById('search'))"}),
        json!({"type": text}),
        json!({"eval": "karigami.highlighted()"}),
    ]
}

fn ids(v: &Value) -> BTreeSet<String> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_str().unwrap().to_string())
        .collect()
}

#[test]
fn viewer_works_in_headless_chromium() {
    // A sheet, two loops (a torus and the bowl), an intrinsic lattice, and a
    // planar true mechanism.
    let names = ["flat-sheet", "torus", "bowl", "eggbox", "mirror-arm"];
    let shots = shots();
    let mut plan_pages = Vec::new();
    let mut expect = Vec::new();
    let started = std::time::Instant::now();
    let builds: Vec<&Build> = std::thread::scope(|scope| {
        let handles: Vec<_> = names
            .iter()
            .map(|&name| scope.spawn(move || built(name)))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    eprintln!(
        "built {} examples in {:.1} s",
        names.len(),
        started.elapsed().as_secs_f64()
    );
    for (name, b) in names.into_iter().zip(builds) {
        let dir = shots.join(name);
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("viewer.html");
        std::fs::write(&file, page(b)).unwrap();
        let steps = &b.steps;
        let n = steps.len();
        let k = n.div_ceil(2);
        let upto = |k: usize| -> BTreeSet<String> {
            steps[..k]
                .iter()
                .flat_map(|s| s.strips.iter().map(|&i| b.parts.strips[i].id.clone()))
                .collect()
        };
        // A strip of step k, selected by a click on its first leg.
        let target = b.parts.strips[steps[k - 1].strips[0]].id.clone();
        let sheet = b
            .layout
            .sheets
            .iter()
            .position(|s| {
                s.placements
                    .iter()
                    .any(|p| p.part == steps[k - 1].strips[0])
            })
            .unwrap()
            + 1;
        let prefix = target[..target.find('-').unwrap()].to_string();
        let shot = |what: &str| json!({"shot": shots.join(format!("{name}-{what}.png"))});
        let mut actions = vec![
            json!({"eval": "karigami.webgl"}),
            json!({"eval": "karigami.steps()"}),
            json!({"eval": "karigami.visibleStrips()"}),
            shot("all"),
            json!({"eval": slide("step", k)}),
            json!({"eval": "karigami.visibleStrips()"}),
            shot(&format!("step-{k}")),
        ];
        // Keys and buttons move one step at a time.
        actions.push(json!({"eval": "document.activeElement.blur(), 1"}));
        actions.push(json!({"key": "ArrowLeft"}));
        actions.push(json!({"eval": "karigami.visibleStrips()"}));
        actions.push(json!({"key": "ArrowRight"}));
        actions.push(json!({"eval": "karigami.step()"}));
        actions.push(json!({"click": "(r => [r.left + r.width / 2, r.top + r.height / 2])(document.getElementById('next').getBoundingClientRect())"}));
        actions.push(json!({"eval": "karigami.step()"}));
        actions.push(json!({"eval": slide("step", k)}));
        // Select by a click on the strip as drawn.
        actions.push(json!({"click": format!("karigami.pickPoint('{target}')")}));
        actions.push(json!({"eval": "karigami.selected()"}));
        actions.push(json!({"eval": "document.getElementById('info').textContent"}));
        actions.push(json!({"eval": "karigami.sheet()"}));
        actions.push(shot("selected"));
        // Centre the view on it: its centre comes to the middle of the view.
        actions.push(json!({"click": "(r => [r.left + r.width / 2, r.top + r.height / 2])(document.querySelector('#info button').getBoundingClientRect())"}));
        actions.push(json!({"eval": format!("(c => {{ const r = document.getElementById('view').getBoundingClientRect(); return Math.hypot(c[0] - r.left - r.width / 2, c[1] - r.top - r.height / 2); }})(karigami.centre('{target}'))")}));
        actions.push(shot("centred"));
        // Search: the target's part type code, then an ID prefix.
        let part = b.parts.strips[steps[k - 1].strips[0]].part_type;
        let code = b.parts.types[part].code.clone();
        actions.extend(search(&code.to_lowercase()));
        actions.push(shot("search-type"));
        actions.push(json!({"eval": "document.getElementById('sheet').scrollIntoView(), karigami.sheetHighlighted()"}));
        actions.push(json!({"eval": "karigami.sheet()"}));
        actions.push(shot("sheet"));
        actions.extend(search(&prefix.to_lowercase()));
        actions.push(shot("search-prefix"));
        actions.push(json!({"eval": "!document.getElementById('deploy').hidden"}));
        let deploys = b.deployment.is_mechanism() && b.lattice.dim == 2;
        if deploys {
            // The whole piece, nothing found or selected, then opened wider.
            actions.push(json!({"eval": format!("{}, (s => {{ s.value = ''; s.dispatchEvent(new Event('input')); }})(document.getElementById('search')), document.getElementById('view').focus(), 1", slide("step", n))}));
            actions.push(json!({"key": "Escape"}));
            actions.push(json!({"eval": format!("karigami.shapeAt({})", b.deployment.config.theta_design.to_degrees())}));
            actions.push(json!({"eval": slide("theta", 400)}));
            actions.push(json!({"eval": "karigami.deployCheck()"}));
            actions.push(json!({"eval": "karigami.theta()"}));
            actions.push(shot("deployed"));
        }
        // Axis views and reset.
        let button = |sel: &str| json!({"click": format!("(r => [r.left + r.width / 2, r.top + r.height / 2])(document.querySelector('{sel}').getBoundingClientRect())")});
        actions.push(button("#views [data-axis=z]"));
        actions.push(json!({"eval": "karigami.viewDirection()"}));
        actions.push(shot("axis-z"));
        actions.push(button("#views [data-axis=x]"));
        actions.push(json!({"eval": "karigami.viewDirection()"}));
        actions.push(button("#view-reset"));
        actions.push(json!({"eval": "karigami.viewDirection()"}));
        // Orbit with a drag; the picture changes, nothing breaks.
        actions.push(json!({"drag": [500, 400, 620, 330]}));
        actions.push(json!({"eval": "karigami.viewDirection()"}));
        actions.push(shot("turned"));
        plan_pages.push(json!({
            "url": format!("file://{}", file.display()),
            "viewport": [1280, 800],
            "actions": actions,
        }));
        let (all, upto_k, before_k) = (upto(n), upto(k), upto(k - 1));
        expect.push((
            name, b, n, k, all, upto_k, before_k, target, sheet, prefix, deploys,
        ));
    }
    // The torus on a phone, tapped.
    let torus = &expect[1];
    let phone_target = torus.7.clone();
    plan_pages.push(json!({
        "url": format!("file://{}", shots.join("torus/viewer.html").display()),
        "viewport": [390, 844],
        "mobile": true,
        "actions": [
            {"tap": format!("karigami.pickPoint('{phone_target}')")},
            {"eval": "karigami.selected()"},
            {"shot": shots.join("torus-phone.png")},
            // Two fingers spread: closer. A wheel turn back: farther.
            {"eval": "karigami.viewDistance()"},
            {"pinch": [195, 250, 40, 120]},
            {"eval": "karigami.viewDistance()"},
            {"wheel": [195, 250, 300]},
            {"eval": "karigami.viewDistance()"},
            {"shot": shots.join("torus-phone-pinched.png")},
        ],
    }));
    let started = std::time::Instant::now();
    let Some(report) = drive(&json!({"pages": plan_pages})) else {
        return;
    };
    eprintln!(
        "browser: {}; {} pages in {:.1} s; screenshots in {}",
        report["browser"],
        plan_pages.len(),
        started.elapsed().as_secs_f64(),
        shots.display()
    );
    let pages = report["pages"].as_array().unwrap();
    for p in pages {
        let url = p["url"].as_str().unwrap();
        // Warnings are shown, not failed on: SwiftShader warns of a GPU
        // stall whenever a screenshot reads the canvas back.
        for w in p["warnings"].as_array().unwrap() {
            if !w.as_str().unwrap().contains("GPU stall due to ReadPixels") {
                eprintln!("{url}: warning: {w}");
            }
        }
        assert_eq!(p["console_errors"], json!([]), "{url}");
        assert_eq!(p["exceptions"], json!([]), "{url}");
        assert_eq!(p["failed_requests"], json!([]), "{url}");
        assert_eq!(p["requests"], json!([url]), "{url}: only the page itself");
    }
    for (page, (name, b, n, k, all, upto_k, before_k, target, sheet, prefix, deploys)) in
        pages.iter().zip(&expect)
    {
        let r = page["results"].as_array().unwrap();
        let mut at = 0;
        let mut next = || {
            at += 1;
            &r[at - 1]
        };
        assert_eq!(next(), &json!(true), "{name}: WebGL");
        assert_eq!(next(), &json!(n), "{name}: steps");
        assert_eq!(&ids(next()), all, "{name}: every strip at the last step");
        let all_shot = PathBuf::from(next().as_str().unwrap());
        let (count, drawn) = colours(&all_shot);
        eprintln!("{name}: {count} colours, {:.1} % drawn", 100.0 * drawn);
        assert!(
            count > 50 && drawn > 0.05,
            "{name}: a blank view? {count} colours, {drawn}"
        );
        assert_eq!(next(), &json!(k), "{name}: slider");
        assert_eq!(&ids(next()), upto_k, "{name}: strips of steps 1..{k}");
        next(); // shot
        next(); // blur
        next(); // ArrowLeft
        assert_eq!(
            &ids(next()),
            before_k,
            "{name}: ArrowLeft shows steps 1..{}",
            k - 1
        );
        next(); // ArrowRight
        assert_eq!(next(), &json!(k), "{name}: ArrowRight");
        next(); // click on next
        assert_eq!(next(), &json!((*k + 1).min(*n)), "{name}: the next button");
        next(); // slider back to k
        next(); // click
        assert_eq!(next(), &json!(target), "{name}: a click selects {target}");
        let info = next().as_str().unwrap();
        assert!(
            info.contains(target.as_str())
                && info.contains(&format!("{sheet} of {}", b.layout.sheets.len())),
            "{name}: {info}"
        );
        assert_eq!(
            next(),
            &json!(sheet),
            "{name}: the sheet view shows its sheet"
        );
        next(); // shot
        next(); // click "Centre the view on it"
        let off = next().as_f64().unwrap();
        assert!(off < 2.0, "{name}: centred {off} px off the middle");
        next(); // shot
        next(); // clear the search box
        next(); // type
        let by_type = ids(next());
        let part = b
            .parts
            .strips
            .iter()
            .find(|s| &s.id == target)
            .unwrap()
            .part_type;
        let expected: BTreeSet<String> = b.parts.types[part]
            .strips
            .iter()
            .map(|&i| b.parts.strips[i].id.clone())
            .collect();
        assert!(expected.contains(target));
        assert_eq!(
            by_type, expected,
            "{name}: search by part type {}",
            b.parts.types[part].code
        );
        next(); // shot
        let marked = ids(next());
        let shown_sheet = next().as_u64().unwrap() as usize;
        let on_sheet: BTreeSet<String> = b.layout.sheets[shown_sheet - 1]
            .placements
            .iter()
            .map(|p| b.parts.strips[p.part].id.clone())
            .filter(|id| expected.contains(id) || id == target)
            .collect();
        assert!(!on_sheet.is_empty(), "{name}: the sheet shown has a match");
        assert_eq!(
            marked, on_sheet,
            "{name}: the sheet view highlights the matches and the selection"
        );
        next(); // shot
        next();
        next();
        let by_prefix = ids(next());
        let expected: BTreeSet<String> = b
            .parts
            .strips
            .iter()
            .filter(|s| s.id.starts_with(prefix.as_str()))
            .map(|s| s.id.clone())
            .collect();
        assert!(!expected.is_empty());
        assert_eq!(by_prefix, expected, "{name}: search by {prefix}");
        next(); // shot
        assert_eq!(next(), &json!(deploys), "{name}: deployment slider shown");
        if *deploys {
            next(); // whole piece
            next(); // Escape
            let design = next();
            assert!(
                design["fromDesign"].as_f64().unwrap() < 2e-3
                    && design["misfit"].as_f64().unwrap() < 1e-6,
                "{name}: C(theta) at the design angle places the designed shape: {design}"
            );
            assert_eq!(next(), &json!(400));
            let check = next();
            let (pitch, misfit, moved) = (
                check["pitchError"].as_f64().unwrap(),
                check["misfit"].as_f64().unwrap(),
                check["fromDesign"].as_f64().unwrap(),
            );
            assert!(pitch < 1e-6 && misfit < 1e-6, "{name}: {check}");
            assert!(moved > 1.0, "{name}: the slider moved nothing: {check}");
            let theta = next().as_f64().unwrap();
            let expected = 0.4 * b.deployment.config.theta_max.to_degrees();
            assert!((theta - expected).abs() < 1e-9, "{theta} {expected}");
            next();
        }
        next(); // click Z
        let dir = crate::util::floats;
        let z = dir(next());
        assert!((z[2] + 1.0).abs() < 1e-9, "{name}: Z looks down z: {z:?}");
        next(); // shot
        next(); // click X
        let x = dir(next());
        assert!((x[0] + 1.0).abs() < 1e-9, "{name}: X looks along x: {x:?}");
        next(); // reset
        let reset = dir(next());
        let first = b.assembled.clone();
        let camera = karigami::testing::picture::Camera::for_lattice(&first);
        for (a, e) in reset.iter().zip(camera.forward.to_array()) {
            assert!(
                (a - e).abs() < 1e-4,
                "{name}: reset view {reset:?} vs {:?}",
                camera.forward
            );
        }
        next(); // drag
        let turned_dir = dir(next());
        let turn: f64 = turned_dir.iter().zip(&reset).map(|(a, b)| a * b).sum();
        assert!(turn < 0.99, "{name}: a drag turns the view ({turn})");
        let turned = PathBuf::from(next().as_str().unwrap());
        assert!(colours(&turned).0 > 50);
    }
    let phone = pages.last().unwrap()["results"].as_array().unwrap();
    assert_eq!(phone[1], json!(phone_target), "a tap on a phone selects");
    let d = |i: usize| phone[i].as_f64().unwrap();
    assert!(d(5) < 0.6 * d(3), "a pinch zooms in: {} -> {}", d(3), d(5));
    assert!(d(7) > d(5), "the wheel zooms out: {} -> {}", d(5), d(7));
}

#[test]
fn the_page_opens_cells_by_the_checks_c_theta() {
    let b = built("mirror-arm");
    let d = data(&String::from_utf8(page(b)).unwrap());
    let config = &b.deployment.config;
    let cells = d["deploy"]["cells"].as_array().unwrap();
    assert_eq!(cells.len(), 7 * b.lattice.cells.len());
    for k in 1..20 {
        let theta = config.theta_max * k as f64 / 20.0;
        let phis = config.angles(theta).unwrap();
        for (i, phi) in phis.iter().enumerate() {
            let (a, bb) = (
                cells[7 * i].as_f64().unwrap(),
                cells[7 * i + 1].as_f64().unwrap(),
            );
            let page_phi = (a + bb * theta.cos()).clamp(-1.0, 1.0).acos();
            assert!(
                (page_phi - phi).abs() < 1e-9,
                "cell {i} at {theta}: {page_phi} vs {phi}"
            );
        }
    }
    // Lattices that are not planar true mechanisms get no slider.
    for name in ["flat-sheet", "torus", "eggbox"] {
        let d = data(&String::from_utf8(page(built(name))).unwrap());
        assert_eq!(d["deploy"], Value::Null, "{name}");
    }
}

#[test]
fn a_simulated_shape_has_its_slot_beside_the_designed_one() {
    let b = built("flat-sheet");
    let mut scene = Scene::new(
        &b.design,
        &b.lattice,
        &b.assembled,
        &b.parts,
        &b.layout,
        &b.deployment,
        &b.steps,
    );
    let d = data(&String::from_utf8(write(&scene)).unwrap());
    assert_eq!(d["simulated"], Value::Null, "no simulation, no slot filled");
    let shape: Vec<glam::DVec3> = b
        .assembled
        .vertices
        .iter()
        .map(|v| v.pos)
        .chain(b.assembled.cells.iter().map(|c| c.pivot))
        .map(|p| p + glam::DVec3::new(0.0, 0.0, 1.5))
        .collect();
    scene.simulated = Some(shape);
    let d = data(&String::from_utf8(write(&scene)).unwrap());
    let (designed, simulated) = (positions(&d["points"]), positions(&d["simulated"]));
    assert_eq!(simulated.len(), designed.len());
    for (k, (a, s)) in designed.iter().zip(&simulated).enumerate() {
        let lift = if k % 3 == 2 { 1.5 } else { 0.0 };
        assert!((s - a - lift).abs() < 2e-3);
    }
    // The designed positions come back to 0.001 mm.
    for (k, p) in b
        .assembled
        .vertices
        .iter()
        .map(|v| v.pos)
        .chain(b.assembled.cells.iter().map(|c| c.pivot))
        .enumerate()
    {
        let q = &designed[3 * k..3 * k + 3];
        assert!((p - glam::DVec3::new(q[0], q[1], q[2])).abs().max_element() <= 5.0001e-4);
    }
}
