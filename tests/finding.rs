//! The maker's second pass (issue 34): every strip found from the printed
//! guide's text alone, LightBurn projects read back by two third-party
//! readers, and stock presets feeding the simulation.

use crate::cli::{recipes, repo, scratch};
use crate::thirdparty::run;
use crate::util::cli_build;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// parts.csv: each strip's (sheet, type) by ID.
fn strips_of(dir: &Path) -> BTreeMap<String, (usize, String)> {
    let csv = std::fs::read_to_string(dir.join("parts.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let (id, sheet, ty) = (col("id"), col("sheet"), col("part_type"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[id].to_string(),
                (f[sheet].parse().unwrap(), f[ty].to_string()),
            )
        })
        .collect()
}

/// The guide's text as one line: footers and continuation heads left out.
fn guide_text(dir: &Path) -> Option<String> {
    let pdf = dir.join("assembly.pdf");
    let out = run("pdftotext", &[pdf.to_str().unwrap(), "-"])?;
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    Some(
        text.lines()
            .filter(|l| !l.contains("assembly guide - page") && !l.contains("(continued)"))
            .collect::<Vec<_>>()
            .join(" "),
    )
}

#[test]
fn every_strip_is_found_by_its_engraving_and_sheet_from_the_guide_text() {
    for recipe in recipes("examples") {
        let name = recipe.file_stem().unwrap().to_string_lossy().into_owned();
        let dir = cli_build(&name, &[]);
        let Some(text) = guide_text(dir) else { return };
        let strips = strips_of(dir);
        // Every step's Take sentence: "Take from sheet 1, lanes 1-2: ...; from sheet 2, ...".
        let mut named: BTreeMap<String, usize> = BTreeMap::new();
        let mut counted: BTreeMap<(usize, String), usize> = BTreeMap::new();
        let mut takes = 0;
        for take in text.split("Take from ").skip(1) {
            takes += 1;
            let sentence = take.split(". ").next().unwrap();
            for part in sentence.split("; from ") {
                let rest = part.strip_prefix("sheet ").expect("a sheet named first");
                let (sheet, items) = rest.split_once(", lane").unwrap();
                let sheet: usize = sheet.parse().unwrap();
                let items = items.split_once(": ").unwrap().1.trim_end_matches('.');
                for item in items.split(", ").map(str::trim) {
                    if let Some((n, ty)) = item.split_once(" x type ") {
                        // "4 x type D" then ", engraved D" as the next item.
                        *counted.entry((sheet, ty.to_string())).or_default() +=
                            n.parse::<usize>().unwrap();
                    } else if let Some(engraved) = item.strip_prefix("engraved ") {
                        assert!(!engraved.is_empty(), "{name}: {item}");
                    } else {
                        let (id, ty) = item
                            .split_once(" (")
                            .unwrap_or_else(|| panic!("{name}: {item:?}"));
                        let ty = ty.trim_end_matches(')');
                        let (s, t) = strips
                            .get(id)
                            .unwrap_or_else(|| panic!("{name}: {id} is not a strip"));
                        assert_eq!((*s, t.as_str()), (sheet, ty), "{name}: {id}");
                        *named.entry(id.to_string()).or_default() += 1;
                    }
                }
            }
        }
        assert!(takes > 0, "{name}: no Take sentence");
        // Every strip once: by its ID, or counted with its type on its sheet.
        assert!(
            named.values().all(|&n| n == 1),
            "{name}: a strip named twice"
        );
        let mut rest: BTreeMap<(usize, String), usize> = BTreeMap::new();
        for (id, (s, t)) in &strips {
            if !named.contains_key(id) {
                *rest.entry((*s, t.clone())).or_default() += 1;
            }
        }
        assert_eq!(
            counted, rest,
            "{name}: the counted strips by sheet and type"
        );
        // The sheet maps: one per sheet.
        let sheets = strips.values().map(|v| v.0).max().unwrap();
        for k in 1..=sheets {
            assert!(
                text.contains(&format!("Sheet map: sheet {k} of {sheets}")),
                "{name}: map {k}"
            );
        }
    }
}

/// The lbrnts package's entry file: installed globally by scripts/test.
fn lbrnts() -> Option<std::path::PathBuf> {
    let root = run("npm", &["root", "-g"])?;
    let path = std::path::PathBuf::from(String::from_utf8(root.stdout).unwrap().trim())
        .join("lbrnts/dist/index.js");
    if path.exists() {
        return Some(path);
    }
    assert!(
        std::env::var_os("KARIGAMI_REQUIRE_TOOLS").is_none(),
        "lbrnts is required (npm install -g lbrnts svgson transformation-matrix)"
    );
    eprintln!("note: lbrnts not installed; skipped");
    None
}

/// The eggbox cut from polypropylene on a CO2 laser, built by the library.
fn pp_eggbox() -> karigami::Build {
    let text = std::fs::read_to_string(repo().join("examples/eggbox.toml"))
        .unwrap()
        .replace("[material]\n", "[material]\npreset = \"pp\"\n");
    karigami::build(karigami::parse(&text, "eggbox").unwrap()).unwrap()
}

#[test]
fn lightburn_holes_and_layer_settings_read_back_in_lbrnts_and_meerk40t() {
    let b = pp_eggbox();
    let preset = karigami::STOCK_PRESETS
        .iter()
        .find(|p| p.key == "pp")
        .unwrap();
    let co2 = preset.co2.unwrap();
    let dir = scratch("lbrn-readers");
    let files = karigami::files(&b);
    let (_, bytes) = files
        .iter()
        .find(|f| f.0 == "sheets/sheet-01.lbrn2")
        .unwrap();
    let file = dir.join("sheet-01.lbrn2");
    std::fs::write(&file, bytes).unwrap();
    // Every hole of the sheet, y flipped as LightBurn's y points up.
    let page = &b.pages[0];
    let mut holes: Vec<(f64, f64, f64)> = page
        .groups
        .iter()
        .flat_map(|g| &g.items)
        .filter_map(|i| match i.shape {
            karigami::Shape::Circle { center, radius } => {
                Some((center.x, page.height - center.y, radius))
            }
            _ => None,
        })
        .collect();
    // By position to the micrometre, so readers' last digits do not reorder.
    let sort = |v: &mut Vec<(f64, f64, f64)>| {
        v.sort_by_key(|h| ((h.0 * 1e3).round() as i64, (h.1 * 1e3).round() as i64));
    };
    sort(&mut holes);
    assert!(holes.len() > 300);
    let same = |read: Vec<(f64, f64, f64)>, who: &str| {
        let mut read = read;
        sort(&mut read);
        assert_eq!(read.len(), holes.len(), "{who}: every hole an ellipse");
        for (r, h) in read.iter().zip(&holes) {
            assert!(
                (r.0 - h.0).abs() < 1e-4 && (r.1 - h.1).abs() < 1e-4 && (r.2 - h.2).abs() < 1e-4,
                "{who}: {r:?} for {h:?}"
            );
        }
    };
    let expect = |name: &str| {
        if name.starts_with("labels") {
            co2.mark
        } else {
            co2.cut
        }
    };
    if let Some(lbrnts) = lbrnts() {
        let script = repo().join("tests/tools/lbrn_lbrnts.mjs");
        let out = run(
            "node",
            &[
                script.to_str().unwrap(),
                lbrnts.to_str().unwrap(),
                file.to_str().unwrap(),
            ],
        )
        .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: Value = serde_json::from_slice(&out.stdout).unwrap();
        let ellipses = v["ellipses"].as_array().unwrap();
        assert!(ellipses.iter().all(|e| e["rx"] == e["ry"]), "true circles");
        same(
            ellipses
                .iter()
                .map(|e| {
                    (
                        e["x"].as_f64().unwrap(),
                        e["y"].as_f64().unwrap(),
                        e["rx"].as_f64().unwrap(),
                    )
                })
                .collect(),
            "lbrnts",
        );
        let settings = v["settings"].as_array().unwrap();
        assert_eq!(settings.len(), 4);
        for s in settings
            .iter()
            .filter(|s| !s["name"].as_str().unwrap().starts_with("reference"))
        {
            let e = expect(s["name"].as_str().unwrap());
            assert_eq!(s["speed"].as_f64(), Some(e.speed), "{s}");
            assert_eq!(s["power"].as_f64(), Some(e.power), "{s}");
            assert_eq!(s["passes"].as_u64(), Some(e.passes as u64), "{s}");
        }
    }
    let script = repo().join("tests/tools/lbrn_meerk40t.py");
    let Some(out) = run(
        "python3",
        &[script.to_str().unwrap(), file.to_str().unwrap()],
    ) else {
        return;
    };
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            std::env::var_os("KARIGAMI_REQUIRE_TOOLS").is_none()
                && err.contains("ModuleNotFoundError"),
            "meerk40t: {err}"
        );
        eprintln!("note: meerk40t not installed: {err}");
        return;
    }
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    same(
        v["ellipses"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| {
                (
                    e["x"].as_f64().unwrap(),
                    e["y"].as_f64().unwrap(),
                    e["rx"].as_f64().unwrap(),
                )
            })
            .collect(),
        "meerk40t",
    );
    for op in v["ops"].as_array().unwrap() {
        let label = op["label"].as_str().unwrap();
        if label.starts_with("reference") {
            continue;
        }
        let e = expect(label);
        assert!(
            (op["speed"].as_f64().unwrap() - e.speed).abs() < 1e-9,
            "{op}"
        );
        assert!(
            (op["power"].as_f64().unwrap() - e.power).abs() < 1e-9,
            "{op}"
        );
    }
}

#[test]
fn a_stock_preset_sets_the_strain_the_report_judges_against() {
    let abs = std::fs::read_to_string(repo().join("examples/eggbox.toml")).unwrap();
    let design = |text: &str| karigami::parse(text, "eggbox").unwrap();
    assert_eq!(design(&abs).simulation.material.eps_allow, 0.015);
    let b = pp_eggbox();
    assert_eq!(b.design.simulation.material.eps_allow, 0.02);
    assert_eq!(b.design.simulation.material.youngs, 1300.0);
    let report = karigami::build_text(&b);
    assert!(report.contains("allowable 2.00 %"), "{report}");
    // [simulation] still has the last word.
    let own = abs.replace("[material]\n", "[material]\npreset = \"pp\"\n")
        + "\n[simulation]\nallowable_strain = 1.2\n";
    assert_eq!(design(&own).simulation.material.eps_allow, 0.012);
    // Unknown stock and a thickness outside the preset's range are errors.
    let bad = abs.replace("[material]\n", "[material]\npreset = \"pvc\"\n");
    let e = karigami::parse(&bad, "eggbox").unwrap_err();
    assert_eq!(e.kind, karigami::ErrorKind::UnknownMaterial);
    let thick = abs
        .replace("[material]\n", "[material]\npreset = \"pp\"\n")
        .replace("thickness = 0.5", "thickness = 2.0");
    let e = karigami::parse(&thick, "eggbox").unwrap_err();
    assert_eq!(e.kind, karigami::ErrorKind::ThicknessOutsidePreset);
    assert!(e.message.contains("0.5 to 1.5 mm"), "{}", e.message);
}

#[test]
fn the_guide_carries_the_safety_note_and_the_lightburn_file() {
    let dir = cli_build("eggbox", &[]);
    let Some(text) = guide_text(dir) else { return };
    let first = text.split("Bill of materials").next().unwrap();
    assert!(first.contains("ABS must not be cut on a laser"), "{first}");
    assert!(first.contains("hydrogen cyanide"));
    assert!(first.contains(".lbrn2"));
    assert!(!text.contains("parts-types.csv lists every strip"));
    // Torus: its open gap is named with its size; saddle ring: its clashes.
    let torus = guide_text(cli_build("torus", &[])).unwrap();
    assert!(torus.contains("18 deg gap"), "torus gap");
    assert!(!torus.contains("goes UNDER the work"));
    // A design whose strips clash says so in its guide, not only in report.txt.
    for name in ["saddle-ring", "eggbox", "torus"] {
        let dir = cli_build(name, &[]);
        let report = std::fs::read_to_string(dir.join("report.txt")).unwrap();
        let clashes = !report.contains("strip clashes: none");
        let guide = guide_text(dir).unwrap();
        assert_eq!(
            guide.contains("pairs of strips press on each other"),
            clashes,
            "{name}"
        );
    }
}

/// A word's box on a page of `pdftotext -bbox` (pt, y down) and its text.
struct Word {
    lo: (f64, f64),
    hi: (f64, f64),
    text: String,
}

fn attr(line: &str, name: &str) -> f64 {
    let key = format!("{name}=\"");
    line.split(&key)
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

/// Each page's height and words.
fn bbox_pages(pdf: &Path) -> Option<Vec<(f64, Vec<Word>)>> {
    let out = run("pdftotext", &["-bbox", pdf.to_str().unwrap(), "-"])?;
    let text = String::from_utf8(out.stdout).unwrap();
    let mut pages = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with("<page ") {
            pages.push((attr(line, "height"), Vec::new()));
        } else if line.starts_with("<word ") {
            let text = line
                .split('>')
                .nth(1)
                .unwrap()
                .split('<')
                .next()
                .unwrap()
                .to_string();
            let page = pages.last_mut().unwrap();
            page.1.push(Word {
                lo: (attr(line, "xMin"), attr(line, "yMin")),
                hi: (attr(line, "xMax"), attr(line, "yMax")),
                text,
            });
        }
    }
    Some(pages)
}

/// Issue 34's layout test over every example's guide: no two words (picture
/// labels included) overlap, no page but the last is under a fifth full,
/// and a step runs onto a second page only when it says it is longer than
/// a page.
#[test]
fn guide_pages_have_no_overlapping_labels_no_split_steps_and_no_near_empty_pages() {
    const MM: f64 = 72.0 / 25.4;
    for recipe in recipes("examples") {
        let name = recipe.file_stem().unwrap().to_string_lossy().into_owned();
        let dir = cli_build(&name, &[]);
        let Some(pages) = bbox_pages(&dir.join("assembly.pdf")) else {
            return;
        };
        let n = pages.len();
        for (k, (height, words)) in pages.iter().enumerate() {
            // Words 0.3 pt inside their boxes: neighbours on a line touch.
            let s = 0.3;
            for (i, a) in words.iter().enumerate() {
                for b in &words[i + 1..] {
                    let apart = a.hi.0 - s <= b.lo.0 + s
                        || b.hi.0 - s <= a.lo.0 + s
                        || a.hi.1 - s <= b.lo.1 + s
                        || b.hi.1 - s <= a.lo.1 + s;
                    assert!(
                        apart,
                        "{name} page {}: {:?} and {:?} overlap",
                        k + 1,
                        a.text,
                        b.text
                    );
                }
            }
            // The body: from the top margin to the footer (15 mm margins, a
            // 6 mm footer band).
            let footer = height - 21.0 * MM;
            let lowest = words
                .iter()
                .filter(|w| w.lo.1 < footer)
                .map(|w| w.hi.1)
                .fold(0.0, f64::max);
            let fill = (lowest - 15.0 * MM) / (footer - 15.0 * MM);
            assert!(
                k + 1 == n || fill >= 0.2,
                "{name} page {}: {:.0} % full",
                k + 1,
                100.0 * fill
            );
        }
        // "Step N (continued)" only after a step that said it is long.
        let text = guide_text(dir).unwrap();
        let all = {
            let out = run(
                "pdftotext",
                &[dir.join("assembly.pdf").to_str().unwrap(), "-"],
            )
            .unwrap();
            String::from_utf8(out.stdout).unwrap()
        };
        for (i, _) in all.match_indices(" (continued)") {
            let head = all[..i].rsplit('\n').next().unwrap();
            if let Some(step) = head.strip_prefix("Step ") {
                let title = format!("Step {step} of ");
                let block = text.split(&title).nth(1).unwrap();
                let block = block.split(" Step ").next().unwrap();
                assert!(
                    block.contains("longer than a page"),
                    "{name}: step {step} splits"
                );
            }
        }
    }
}

/// `--flat`: the SVG has no `<use>` and the DXF no blocks, and both still
/// hold every hole where the referencing files put it, as ezdxf and
/// svgelements read them.
#[test]
fn flat_files_draw_every_strip_without_references() {
    use crate::thirdparty::{alike_strips, holes_match, python_check};
    let b = alike_strips();
    let dir = scratch("flat-files");
    for (i, page) in b.pages.iter().enumerate() {
        let svg = karigami::formats::svg::write_flat(page);
        let text = String::from_utf8_lossy(&svg);
        assert!(
            !text.contains("<use") && !text.contains("<defs"),
            "sheet {i}"
        );
        let dxf = karigami::formats::dxf::write_flat(page);
        let dxf_text = String::from_utf8_lossy(&dxf);
        assert!(!dxf_text.contains("\nINSERT\n"), "sheet {i}: no INSERT");
        // The referencing files do use references here, so this is a change.
        let shared = karigami::formats::svg::write(page);
        assert!(String::from_utf8_lossy(&shared).contains("<use"));
        let path = dir.join(format!("sheet-{i}.svg"));
        std::fs::write(&path, &svg).unwrap();
        let Some(m) = python_check("check_svg.py", &path) else {
            return;
        };
        holes_match(page, &m["holes"], false, &format!("flat SVG sheet {i}"));
        let path = dir.join(format!("sheet-{i}.dxf"));
        std::fs::write(&path, &dxf).unwrap();
        let Some(m) = python_check("check_dxf.py", &path) else {
            return;
        };
        assert_eq!(m["errors"], 0, "{m}");
        assert_eq!(m["inserts"], 0, "{m}");
        holes_match(page, &m["holes"], true, &format!("flat DXF sheet {i}"));
    }
    // The recipe and the command line both ask for it.
    let text = std::fs::read_to_string(repo().join("examples/eggbox.toml")).unwrap()
        + "\n[laser]\nflat = true\n";
    let b = karigami::build(karigami::parse(&text, "eggbox").unwrap()).unwrap();
    let files = karigami::files(&b);
    let svg = &files
        .iter()
        .find(|f| f.0 == "sheets/sheet-01.svg")
        .unwrap()
        .1;
    assert!(!String::from_utf8_lossy(svg).contains("<use"));
}
