//! The assembly guide and the pictures: steps follow growth order, the PDF
//! has the documented structure (checked with poppler), previews and the
//! OBJ model hold what they should.

use crate::cli::{karigami, repo, scratch};
use crate::thirdparty::run;
use karigami::{Build, guide};
use std::collections::HashSet;

/// The example's build, shared with the other tests (tests/util.rs).
fn example(name: &str) -> &'static Build {
    crate::util::example(name)
}

#[test]
fn each_step_is_one_row_and_the_eyelets_add_up() {
    for name in ["flat-sheet", "curved-sheet", "mirror-arm"] {
        let b = example(name);
        let steps = &b.steps;
        assert_eq!(steps.len(), b.lattice.rows(), "{name}: one step per row");
        let mut joints = HashSet::new();
        for (k, step) in steps.iter().enumerate() {
            assert_eq!(step.number, k + 1);
            // Exactly the strips of this row's cells, both rods of each.
            let expected: Vec<usize> = (0..b.lattice.cells.len())
                .filter(|&c| b.lattice.cells[c].row as usize == k)
                .flat_map(|c| [2 * c, 2 * c + 1])
                .collect();
            assert_eq!(step.strips, expected, "{name} step {}", k + 1);
            for &s in &step.strips {
                assert_eq!(b.parts.strips[s].row as usize, k);
            }
            for j in &step.joints {
                assert!(joints.insert(j.vertex), "a joint closes once");
                // It closes when its last strip arrives, never before.
                let last = j
                    .ends
                    .iter()
                    .map(|e| b.lattice.cells[e.rod / 2].row)
                    .max()
                    .unwrap();
                assert_eq!(last as usize, k);
                let layers: Vec<u32> = j.ends.iter().map(|e| e.layer).collect();
                assert!(
                    layers.windows(2).all(|w| w[0] < w[1]),
                    "stacked bottom to top in layer order"
                );
            }
            assert_eq!(step.eyelets, step.cells.len() + step.joints.len());
        }
        let needing = karigami::joints(&b.lattice)
            .iter()
            .filter(|j| j.needs_eyelet())
            .count();
        assert_eq!(
            joints.len(),
            needing,
            "{name}: every joint with an eyelet is closed in some step"
        );
        assert_eq!(steps.last().unwrap().total, needing + b.lattice.cells.len());
        assert_eq!(steps.last().unwrap().total, b.parts.eyelets());
    }
}

fn pdf_pages(path: &std::path::Path) -> Option<(usize, String)> {
    let info = run("pdfinfo", &[path.to_str().unwrap()])?;
    let info = String::from_utf8_lossy(&info.stdout).into_owned();
    let pages = info.lines().find(|l| l.starts_with("Pages:")).unwrap()[6..]
        .trim()
        .parse()
        .unwrap();
    let size = info
        .lines()
        .find(|l| l.starts_with("Page size:"))
        .unwrap()
        .to_string();
    Some((pages, size))
}

#[test]
fn the_guide_pdf_has_every_page_and_every_strip_id() {
    let b = example("flat-sheet");
    let pages = guide(b).pages;
    let steps = b.steps.len();
    // Cover, bill of materials, the steps (several a page), the gauge, the checklist.
    assert!(pages.len() >= 4, "{} pages", pages.len());
    let dir = scratch("guide-pdf");
    let recipe = repo().join("examples/flat-sheet.toml");
    for (out, paper, size) in [
        ("a4", "a4", "595.276 x 841.89"),
        ("letter", "letter", "612 x 792"),
    ] {
        let o = karigami(
            &[
                "build",
                recipe.to_str().unwrap(),
                "--out",
                out,
                "--paper",
                paper,
            ],
            &dir,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let pdf = dir.join(out).join("assembly.pdf");
        let Some((count, line)) = pdf_pages(&pdf) else {
            return;
        };
        assert!(line.contains(size), "{paper}: {line}");
        if paper == "a4" {
            assert_eq!(
                count,
                pages.len(),
                "pdfinfo counts the pages the guide built"
            );
        }
        let Some(text) = run("pdftotext", &["-layout", pdf.to_str().unwrap(), "-"]) else {
            return;
        };
        let text = String::from_utf8_lossy(&text.stdout);
        for s in &b.parts.strips {
            assert!(
                text.contains(&s.id),
                "{paper}: strip {} is not in the guide",
                s.id
            );
        }
        for k in 1..=steps {
            assert!(text.contains(&format!("Step {k} of {steps}")), "step {k}");
        }
        assert!(
            text.contains("Bill of materials")
                && text.contains("Inspection gauge")
                && text.contains("Checklist")
        );
        let prefix = dir.join(out).join("page");
        let Some(r) = run(
            "pdftoppm",
            &[
                "-r",
                "15",
                "-png",
                pdf.to_str().unwrap(),
                prefix.to_str().unwrap(),
            ],
        ) else {
            return;
        };
        assert!(r.status.success());
        let rendered = std::fs::read_dir(dir.join(out))
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .starts_with("page")
            })
            .count();
        assert_eq!(rendered, count, "pdftoppm renders every page");
    }
}

/// Width, height and the share of pixels that are not white.
fn picture(bytes: &[u8]) -> (u32, u32, f64) {
    let p = tiny_skia::Pixmap::decode_png(bytes).expect("a PNG");
    let inked = p
        .pixels()
        .iter()
        .filter(|c| c.red() < 200 || c.green() < 200 || c.blue() < 200)
        .count();
    (
        p.width(),
        p.height(),
        inked as f64 / p.pixels().len() as f64,
    )
}

#[test]
fn previews_are_pictures_of_the_right_size() {
    for name in ["flat-sheet", "curved-sheet"] {
        let b = example(name);
        let files = karigami::files(b);
        let get = |f: &str| {
            &files
                .iter()
                .find(|x| x.0 == f)
                .unwrap_or_else(|| panic!("{f}"))
                .1
        };
        let (w, h, ink) = picture(get("preview.png"));
        assert_eq!((w, h), (1280, 960));
        assert!(ink > 0.02, "{name}: the preview shows the lattice ({ink})");
        let sheet = &b.design.fabrication.sheet;
        for i in 1..=b.layout.sheets.len() {
            let (w, h, ink) = picture(get(&format!("sheets/sheet-{i:02}.png")));
            assert_eq!(
                (w, h),
                (
                    (sheet.width * 2.0).round() as u32,
                    (sheet.height * 2.0).round() as u32
                )
            );
            assert!(ink > 0.005, "{name} sheet {i} shows its strips ({ink})");
        }
    }
}

#[test]
fn lattice_obj_has_one_box_per_strip() {
    let b = example("curved-sheet");
    let files = karigami::files(b);
    let obj = String::from_utf8(
        files
            .iter()
            .find(|f| f.0 == "lattice.obj")
            .unwrap()
            .1
            .clone(),
    )
    .unwrap();
    let n = b.parts.strips.len();
    let lines = |p: &str| obj.lines().filter(|l| l.starts_with(p)).count();
    assert_eq!((lines("o "), lines("v "), lines("f ")), (n, 8 * n, 6 * n));
    assert!(obj.lines().nth(1).unwrap().contains("units mm, to 0.001"));
    let names: Vec<&str> = obj.lines().filter_map(|l| l.strip_prefix("o ")).collect();
    assert_eq!(
        names,
        b.parts
            .strips
            .iter()
            .map(|s| s.id.as_str())
            .collect::<Vec<_>>()
    );
    let v: Vec<[f64; 3]> = obj
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            // Coordinates to 0.001 mm, as the header says.
            for t in l.split(' ') {
                assert!(t.split_once('.').is_none_or(|(_, d)| d.len() <= 3), "{l}");
            }
            let x: Vec<f64> = l.split(' ').map(|t| t.parse().unwrap()).collect();
            [x[0], x[1], x[2]]
        })
        .collect();
    // Faces name their own box's vertices, relative to the last one written
    // (-1), as Blender and trimesh read them.
    let mut written = 0;
    for l in obj.lines() {
        if l.starts_with("v ") {
            written += 1;
        }
        let Some(f) = l.strip_prefix("f ") else {
            continue;
        };
        for i in f.split(' ') {
            let i: i64 = i.parse().unwrap();
            assert!((-8..=-1).contains(&i), "{l}");
            assert!(written + i >= 0 && written % 8 == 0, "{l}: outside its box");
        }
    }
    // Each box is as long, wide and thick as its strip, to what 0.001 mm
    // corners allow (each coordinate off by up to 0.0005: a distance by up
    // to sqrt(3) * 0.001).
    let fab = &b.design.fabrication;
    let d = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    for (k, s) in b.parts.strips.iter().enumerate() {
        let c = &v[8 * k..8 * k + 8];
        let tol = 3f64.sqrt() * 1e-3;
        assert!((d(c[0], c[1]) - s.length).abs() <= tol, "{}", s.id);
        assert!((d(c[0], c[2]) - fab.material.width).abs() <= tol);
        assert!((d(c[0], c[4]) - fab.material.thickness).abs() <= tol);
    }
}

/// The 30 x 30-cell sheet's guide, built by the CLI; (folder, assembly.pdf).
fn sheet_30x30_guide(tag: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = scratch(tag);
    let recipe = repo().join("tests/golden/sheet-30x30.toml");
    let o = karigami(
        &[
            "build",
            recipe.to_str().unwrap(),
            "--out",
            "out",
            "--jobs",
            "1",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let pdf = dir.join("out/assembly.pdf");
    (dir, pdf)
}

/// The guide's pages and text are pinned: a change to how the guide is
/// drawn or serialised must not change what it says. The golden file holds
/// the page count and `pdftotext` output; `KARIGAMI_BLESS=1 cargo test
/// --test tests guide_golden` rewrites it after a deliberate change.
#[test]
fn guide_golden_30x30_pages_and_text() {
    let (_dir, pdf) = sheet_30x30_guide("guide-golden");
    let Some((pages, _)) = pdf_pages(&pdf) else {
        return;
    };
    let Some(text) = run("pdftotext", &[pdf.to_str().unwrap(), "-"]) else {
        return;
    };
    assert!(text.status.success());
    let actual = format!(
        "pages: {pages}\n{}",
        String::from_utf8(text.stdout).expect("pdftotext writes UTF-8")
    );
    if let Err(e) = crate::goldens::compare("tests/golden/guide-30x30.txt", actual.as_bytes()) {
        panic!("the 30 x 30 guide: {e}");
    }
}

/// Bytes of the guide per cell at most: each row's drawing is written once
/// and placed by reference on later step pages, so the guide grows with the
/// cells. Drawing every row again on every step page took 1,943 bytes a cell
/// at 30 x 30, and rows times that per cell in general. Since the step
/// pictures are labelled (issue 13), a row too fine to label in the whole
/// picture also gets zoomed pictures of itself and the row above, with a
/// label per strip, joint and column: about 980 bytes a cell at 30 x 30,
/// still the same for every row.
const GUIDE_BYTES_PER_CELL: u64 = 1100;

/// Every page of the 30 x 30 guide renders with poppler without a word on
/// stderr (a broken content stream or a missing resource is reported
/// there), and the guide's size is at most a fixed multiple of its cells.
#[test]
fn guide_30x30_renders_every_page_and_grows_with_the_cells() {
    let (dir, pdf) = sheet_30x30_guide("guide-render");
    let size = std::fs::metadata(&pdf).unwrap().len();
    let cells = 30 * 30;
    assert!(
        size <= GUIDE_BYTES_PER_CELL * cells,
        "assembly.pdf is {size} bytes, {} a cell: more than {GUIDE_BYTES_PER_CELL}",
        size / cells
    );
    let Some((pages, _)) = pdf_pages(&pdf) else {
        return;
    };
    let prefix = dir.join("page");
    let Some(r) = run(
        "pdftoppm",
        &[
            "-r",
            "20",
            "-png",
            pdf.to_str().unwrap(),
            prefix.to_str().unwrap(),
        ],
    ) else {
        return;
    };
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(
        r.stderr.is_empty(),
        "pdftoppm: {}",
        String::from_utf8_lossy(&r.stderr)
    );
    let rendered = std::fs::read_dir(&dir)
        .unwrap()
        .filter(|e| {
            let name = e.as_ref().unwrap().file_name();
            let name = name.to_string_lossy();
            name.starts_with("page") && name.ends_with(".png")
        })
        .count();
    assert_eq!(rendered, pages, "pdftoppm renders every page");
}

/// The texts of a group's items (font size, text), with its symbols' items.
fn texts<'a>(items: impl Iterator<Item = &'a karigami::Item>) -> Vec<(f64, String)> {
    items
        .filter_map(|i| match &i.shape {
            karigami::Shape::Text { size, text, .. } => Some((*size, text.clone())),
            _ => None,
        })
        .collect()
}

/// What a step's words name: joint keys `[r,c]` or `[k]`, part types
/// ("type X" gives X) and strip IDs (R..-C..-A/B).
fn named(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let words: Vec<&str> = text
        .split(char::is_whitespace)
        .filter(|w| !w.is_empty())
        .collect();
    for (i, w) in words.iter().enumerate() {
        let w = w.trim_end_matches(['.', ':', ';', ',', ')']);
        let w = w.trim_start_matches('(');
        if w.starts_with('[')
            && w.ends_with(']')
            && w[1..w.len() - 1]
                .chars()
                .all(|c| c.is_ascii_digit() || c == ',')
        {
            out.push(w.to_string());
        }
        if i > 0 && words[i - 1] == "type" {
            out.push(w.to_string());
        }
        let b = w.as_bytes();
        if b.len() >= 9
            && b[0] == b'R'
            && w.contains("-C")
            && (w.ends_with("-A") || w.ends_with("-B"))
        {
            out.push(w.to_string());
        }
    }
    out
}

/// Tokens a picture label shows: "R01-C02-A (E)" shows R01-C02-A and E.
fn shown(labels: &[(f64, String)]) -> HashSet<String> {
    labels
        .iter()
        .flat_map(|(_, t)| {
            t.split(|c: char| c.is_whitespace() || c == '(' || c == ')')
                .filter(|w| !w.is_empty())
                .map(str::to_string)
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The helix bowl (the gallery's bowl before its redesign) stands for a
/// long helix, one cell a step.
const HELIX: &str = "fixtures/designs/helix-bowl.toml";
const GUIDE_EXAMPLES: [&str; 5] = ["flat-sheet", "torus", HELIX, "eggbox", "curved-sheet"];

/// For every step of every example guide, each joint key, part type and
/// strip ID the step's words name is drawn as a label in its picture; the
/// types asked for ("2 x type E") are what the step's strips are.
#[test]
fn step_pictures_label_everything_their_text_names() {
    for name in GUIDE_EXAMPLES {
        let b = example(name);
        let g = guide(b);
        for step in &b.steps {
            let of = |suffix: &str| -> Vec<(f64, String)> {
                let id = format!("step-{}-{suffix}", step.number);
                texts(
                    g.pages
                        .iter()
                        .flat_map(|p| &p.groups)
                        .filter(|gr| gr.id == id)
                        .flat_map(|gr| &gr.items),
                )
            };
            let (words, labels) = (of("text"), of("labels"));
            assert!(!words.is_empty(), "{name} step {}: no words", step.number);
            let words: String = words
                .iter()
                .map(|w| w.1.as_str())
                .collect::<Vec<_>>()
                .join(" ");
            let names = named(&words);
            let shown = shown(&labels);
            for n in &names {
                assert!(
                    shown.contains(n),
                    "{name} step {}: the text names {n} but the picture does not show it (it shows {shown:?})",
                    step.number
                );
            }
            // Every joint the step closes is named and labelled.
            for j in &step.joints {
                let v = b.lattice.vertex(j.vertex).key;
                let key = if b.lattice.kind == karigami::Kind::Helix {
                    format!("[{}]", v.col)
                } else {
                    format!("[{},{}]", v.row, v.col)
                };
                assert!(
                    names.contains(&key) && shown.contains(&key),
                    "{name} step {}: {key}",
                    step.number
                );
            }
            // "Take from sheet 1, lanes 1-2: R00-C00-A (A), ..., n x type X,
            // engraved X": the step's strips, by ID or counted by type.
            let take = words
                .split("Take from ")
                .nth(1)
                .unwrap()
                .split(". ")
                .next()
                .unwrap();
            let mut asked: std::collections::BTreeMap<String, usize> = Default::default();
            for on_sheet in take.split("; from ") {
                let items = on_sheet.split_once(": ").unwrap().1.trim_end_matches('.');
                for part in items.split(", ").filter(|p| !p.starts_with("engraved ")) {
                    let (n, code) = match part.split_once(" x type ") {
                        Some((n, code)) => (n.parse().unwrap(), code.to_string()),
                        None => {
                            let (id, code) = part.split_once(" (").unwrap();
                            let s = b.parts.strips.iter().position(|s| s.id == id).unwrap();
                            assert!(
                                step.strips.contains(&s),
                                "{name} step {}: {id}",
                                step.number
                            );
                            (1, code.trim_end_matches(')').to_string())
                        }
                    };
                    *asked.entry(code).or_default() += n;
                }
            }
            let mut have: std::collections::BTreeMap<String, usize> = Default::default();
            for &s in &step.strips {
                *have
                    .entry(b.parts.types[b.parts.strips[s].part_type].code.clone())
                    .or_default() += 1;
            }
            assert_eq!(asked, have, "{name} step {}", step.number);
            // The stacking side is said in every step, with the grips.
            assert!(
                words.contains("Stacking side"),
                "{name} step {}",
                step.number
            );
            if !step.joints.is_empty() {
                assert!(words.contains("grip"), "{name} step {}", step.number);
            }
        }
    }
}

/// Item 7: the helix bowl's guide fits in 13 pages, and nothing in any guide,
/// preview or cut sheet is printed or engraved smaller than 2.5 mm.
#[test]
fn guides_are_compact_and_nothing_is_printed_under_2_5_mm() {
    const SMALLEST: f64 = 2.5;
    for name in GUIDE_EXAMPLES {
        let b = example(name);
        let g = guide(b);
        // 12 pages before issue 34 added the sheet map and kept each step
        // on one page.
        if name == HELIX {
            assert!(
                g.pages.len() <= 13,
                "the helix bowl guide has {} pages",
                g.pages.len()
            );
        }
        let all = texts(
            g.pages
                .iter()
                .flat_map(|p| &p.groups)
                .flat_map(|gr| &gr.items)
                .chain(g.symbols.iter().flat_map(|s| &s.items)),
        );
        assert!(all.len() > 50);
        for (size, text) in &all {
            assert!(
                *size >= SMALLEST - 1e-9,
                "{name} guide: {text:?} at {size} mm"
            );
        }
        let preview = karigami::testing::picture::preview(&b.assembled, 6.0, name);
        for (size, text) in texts(preview.groups.iter().flat_map(|gr| &gr.items)) {
            assert!(
                size >= SMALLEST - 1e-9,
                "{name} preview: {text:?} at {size} mm"
            );
        }
        // Engraved strip labels: text no smaller either (a strip whose text
        // does not fit falls back to its type code, then to dots).
        for s in &b.parts.strips {
            if matches!(
                s.marking,
                karigami::Marking::Id | karigami::Marking::Compact | karigami::Marking::Type
            ) {
                assert!(
                    s.label_height >= SMALLEST - 1e-9,
                    "{name}: strip {} engraved at {} mm",
                    s.id,
                    s.label_height
                );
            }
        }
        // Cut sheets print only their caption (stroke text on the reference
        // layer, after the scale bar's three lines): its height.
        for page in &b.pages {
            let caption = page.groups.iter().find(|gr| gr.id == "reference").unwrap();
            let ys: Vec<f64> = caption.items[3..]
                .iter()
                .flat_map(|i| match &i.shape {
                    karigami::Shape::Path {
                        start, segments, ..
                    } => {
                        let mut v = vec![start.y];
                        v.extend(segments.iter().map(|s| match s {
                            karigami::Segment::Line(p) => p.y,
                            karigami::Segment::Arc { to, .. } => to.y,
                        }));
                        v
                    }
                    _ => Vec::new(),
                })
                .collect();
            let h = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max)
                - ys.iter().copied().fold(f64::INFINITY, f64::min);
            assert!(h >= SMALLEST - 1e-6, "{name}: sheet caption {h} mm high");
        }
    }
}

/// Item 4: the inspection gauge is one line at 1:1, in tiles side by side
/// (as many as a page's width holds); the tiles' lengths less their
/// overlaps add up to the collapsed length, consecutive tiles carry the same
/// two registration marks one overlap apart, tiles on a page do not overlap
/// and no two of a page's gauge labels overlap.
#[test]
fn gauge_tiles_make_one_line_of_the_collapsed_length() {
    use karigami::{Shape, testing::text};
    let overlap_mm = karigami::testing::GAUGE_OVERLAP;
    for name in ["flat-sheet", "torus", HELIX] {
        let b = example(name);
        let g = guide(b);
        let l = &b.lattice;
        let zs = l
            .vertices
            .iter()
            .map(|v| v.z)
            .chain(l.cells.iter().map(|c| c.z_pivot));
        let (lo, hi) = zs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| {
            (a.min(z), b.max(z))
        });
        let mut tiles = Vec::new();
        for (p, page) in g.pages.iter().enumerate() {
            for gr in page
                .groups
                .iter()
                .filter(|gr| gr.id.starts_with("gauge-tile-"))
            {
                tiles.push((p, gr));
            }
        }
        assert!(!tiles.is_empty(), "{name}: a gauge");
        for (i, (_, gr)) in tiles.iter().enumerate() {
            assert_eq!(
                gr.id,
                format!("gauge-tile-{}", i + 1),
                "{name}: tiles in order"
            );
        }
        let drawn: f64 = tiles.iter().map(|t| t.1.items[0].shape.length()).sum();
        let overlap = overlap_mm * (tiles.len() - 1) as f64;
        assert!(
            ((drawn - overlap) - (hi - lo)).abs() < 0.1,
            "{name}: {} tiles draw {drawn:.2} mm less {overlap} mm of overlap, the collapsed length is {:.2} mm",
            tiles.len(),
            hi - lo
        );
        if name == "torus" {
            assert!(tiles.len() >= 4, "the torus gauge is over a metre long");
        }
        // Every text of a tile with its box: (text, x0, y0, x1, y1).
        let boxes = |gr: &karigami::Group| -> Vec<(String, f64, f64, f64, f64)> {
            gr.items
                .iter()
                .filter_map(|i| match &i.shape {
                    Shape::Text {
                        at,
                        size,
                        text: t,
                        font,
                        align,
                    } => {
                        let s = text::start(*at, t, *font, *size, *align);
                        let w = text::width(t, *font, *size);
                        Some((t.clone(), s.x, s.y - 0.75 * size, s.x + w, s.y + 0.2 * size))
                    }
                    _ => None,
                })
                .collect()
        };
        // Consecutive tiles: the same marks, one overlap apart on each.
        for k in 1..tiles.len() {
            for gr in [tiles[k - 1].1, tiles[k].1] {
                let b = boxes(gr);
                let y = |m: &str| {
                    b.iter()
                        .find(|t| t.0 == m)
                        .unwrap_or_else(|| panic!("{name}: {} has no {m}", gr.id))
                        .2
                };
                let apart = y(&format!("mark {k}b")) - y(&format!("mark {k}a"));
                assert!(
                    (apart - overlap_mm).abs() < 1e-6,
                    "{name}: {}'s marks {k}a and {k}b are {apart} mm apart",
                    gr.id
                );
            }
        }
        let pages: std::collections::BTreeSet<usize> = tiles.iter().map(|t| t.0).collect();
        for p in pages {
            let on_page: Vec<_> = tiles.iter().filter(|t| t.0 == p).map(|t| t.1).collect();
            // Side by side: each tile's drawing clear of the others'.
            let extent = |gr: &karigami::Group| {
                let xs: Vec<f64> = gr
                    .items
                    .iter()
                    .filter_map(|i| match &i.shape {
                        Shape::Path {
                            start, segments, ..
                        } => Some(
                            std::iter::once(start.x)
                                .chain(segments.iter().map(|s| match s {
                                    karigami::Segment::Line(p) => p.x,
                                    karigami::Segment::Arc { to, .. } => to.x,
                                }))
                                .collect::<Vec<_>>(),
                        ),
                        _ => None,
                    })
                    .flatten()
                    .chain(boxes(gr).iter().flat_map(|b| [b.1, b.3]))
                    .collect();
                (
                    xs.iter().copied().fold(f64::INFINITY, f64::min),
                    xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                )
            };
            for (i, a) in on_page.iter().enumerate() {
                let ea = extent(a);
                assert!(
                    ea.0 >= 0.0 && ea.1 <= g.pages[p].width,
                    "{name}: {} leaves the page: {ea:?}",
                    a.id
                );
                for c in &on_page[i + 1..] {
                    let ec = extent(c);
                    assert!(
                        ea.1 <= ec.0 || ec.1 <= ea.0,
                        "{name}: {} {ea:?} and {} {ec:?} overlap",
                        a.id,
                        c.id
                    );
                }
            }
            let texts: Vec<_> = on_page.iter().flat_map(|gr| boxes(gr)).collect();
            for (i, a) in texts.iter().enumerate() {
                for c in &texts[i + 1..] {
                    let apart = a.3 <= c.1 || c.3 <= a.1 || a.4 <= c.2 || c.4 <= a.2;
                    assert!(apart, "{name}: gauge labels collide: {a:?} {c:?}");
                }
            }
        }
        if name == HELIX {
            // Its 840 mm gauge takes few pages: tiles side by side.
            let pages: HashSet<usize> = tiles.iter().map(|t| t.0).collect();
            assert!(
                pages.len() < tiles.len(),
                "helix bowl: {} tiles on {} pages",
                tiles.len(),
                pages.len()
            );
        }
    }
}

/// The guide's bill of materials lists part types and groups the eyelets by
/// grip; the first step is the test piece, or says it is left out.
/// Every text of the guide, in drawing order, joined by spaces.
fn words(b: &Build) -> String {
    texts(
        guide(b)
            .pages
            .iter()
            .flat_map(|p| &p.groups)
            .flat_map(|gr| &gr.items),
    )
    .into_iter()
    .map(|t| t.1)
    .collect::<Vec<_>>()
    .join(" ")
}

#[test]
fn the_bill_of_materials_lists_types_and_grips_and_the_test_piece_comes_first() {
    // This test changes the build: its own.
    let mut b = crate::util::build_example("flat-sheet", &Default::default());
    let t = b.design.fabrication.material.thickness;
    let text = words(&b);
    for ty in &b.parts.types {
        assert!(text.contains(&ty.code), "type {}", ty.code);
    }
    let grips = karigami::testing::eyelets_by_grip(&b);
    assert_eq!(
        grips.iter().map(|g| g.1 + g.2).sum::<usize>(),
        b.parts.eyelets()
    );
    for (k, _, _) in &grips {
        assert!(text.contains(&format!("{:.1} mm ({k} strips)", *k as f64 * t)));
    }
    assert!(text.contains("loose enough"));
    let piece = text
        .find("Before step 1: cut and test the test piece")
        .expect("the test piece");
    assert!(piece < text.find("Step 1 of").unwrap());
    assert!(text.contains("100 mm"));
    b.design.fabrication.test_piece = false;
    assert!(words(&b).contains("The test piece is left out"));
}

/// The tiles cover the line from 0 to its end, each within its room, and
/// each overlaps the one before by exactly `GAUGE_OVERLAP`.
#[test]
fn gauge_tiles_cover_the_line_within_their_rooms() {
    use karigami::testing::{GAUGE_OVERLAP, gauge_tiles};
    for total in [0.0, 50.0, 116.0, 355.0, 839.9, 1636.9, 5000.0] {
        for (first, rest) in [(116.0, 243.0), (203.0, 243.0), (60.0, 100.0)] {
            let room = |i: usize| if i < 3 { first } else { rest };
            let tiles = gauge_tiles(total, room);
            assert_eq!(tiles[0].0, 0.0);
            assert_eq!(tiles.last().unwrap().1, total, "{total}: the line's end");
            for (i, t) in tiles.iter().enumerate() {
                assert!(t.1 - t.0 <= room(i) + 1e-9, "{total}: tile {i} {t:?}");
                if i > 0 {
                    let overlap = tiles[i - 1].1 - t.0;
                    assert!((overlap - GAUGE_OVERLAP).abs() < 1e-9, "{total}: {overlap}");
                    assert!(t.1 > tiles[i - 1].1, "{total}: tile {i} goes on");
                }
            }
        }
    }
}

/// A loop stacked by columns (the half ellipsoid) stacks its joints in two
/// orders: each step says both, with their joint keys, and no step asks for
/// a strip by an ID the strip does not carry.
#[test]
fn column_stacking_says_each_order_and_names_only_engraved_ids() {
    let b = example("half-ellipsoid");
    let text = words(b);
    // The steps (the parts list before them maps types to strip IDs).
    let text = &text[text.find("Step 1 of").expect("step 1")..];
    let orders = text.matches("2 stacking orders").count();
    assert!(
        orders + 1 >= b.steps.len(),
        "every step after the first says its two orders ({orders} of {})",
        b.steps.len()
    );
    for s in &b.parts.strips {
        if text.contains(&s.id) {
            assert_eq!(
                s.marking,
                karigami::Marking::Id,
                "{} is named but not engraved",
                s.id
            );
        }
    }
}

/// The cover's relief is counted on the shape it shows: for the eggbox the
/// simulated one, where the strips' stiffness flattens some of the design's
/// curved vertices. The counts are taken here again from a fresh
/// simulation of the recipe and from the design, and both must be in the
/// cover's text (read back with poppler) and differ from each other.
#[test]
fn cover_counts_the_relief_of_the_shape_it_shows() {
    use karigami::simulation::{placed_lattice, simulate};
    let dir = scratch("cover-relief");
    let out = dir.join("o");
    let built = karigami(
        &[
            "-q",
            "build",
            "examples/eggbox.toml",
            "--out",
            out.to_str().unwrap(),
        ],
        &repo(),
    );
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let pdf = out.join("assembly.pdf");
    let Some(text) = run(
        "pdftotext",
        &["-f", "1", "-l", "2", pdf.to_str().unwrap(), "-"],
    ) else {
        return;
    };
    let text: String = String::from_utf8_lossy(&text.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    let source = std::fs::read_to_string(repo().join("examples/eggbox.toml")).unwrap();
    let d = karigami::parse(&source, "eggbox").unwrap();
    let lattice = d.grow().unwrap();
    let deployment = karigami::deploy::deployment(&lattice);
    let m = &d.fabrication.material;
    let run = simulate(&lattice, &deployment, m.width, m.thickness, &d.simulation).unwrap();
    // The build's state: the one deploying reaches (docs/physics.md).
    let run = karigami::simulation::path::chosen(run, &d.simulation.material).0;
    let count = |l: &karigami::Lattice| {
        let c = l.curvature();
        let dome = c.iter().filter(|v| v.defect.to_degrees() >= 3.0).count();
        let saddle = c.iter().filter(|v| v.defect.to_degrees() <= -3.0).count();
        (dome, saddle, c.len())
    };
    let designed = count(&lattice);
    let simulated = count(&placed_lattice(&lattice, &run.lm));
    assert_ne!(designed, simulated, "the strips change the eggbox's relief");
    let said_design = format!(
        "the design makes {} of its {} inner vertices dome-like",
        designed.0, designed.2
    );
    let said_simulated = format!(
        "{} are dome-like and {} saddle-like",
        simulated.0, simulated.1
    );
    for said in [
        said_design,
        said_simulated,
        format!("and {} saddle-like", designed.1),
    ] {
        assert!(text.contains(&said), "{said:?} not on the cover:\n{text}");
    }
}

/// A bent-facet lattice above the cells `build` simulates is built without
/// its simulated shape, and the build says so (a warning in report.txt and
/// on the terminal), instead of passing the design off as what the strips
/// make.
#[test]
fn a_lattice_too_large_to_simulate_is_built_with_a_warning() {
    let text = std::fs::read_to_string(repo().join("templates/bumps.toml"))
        .unwrap()
        .replace("to = [240.0, 0.0, 0.0]", "to = [2400.0, 0.0, 0.0]")
        .replace("cells = 6", "cells = 60")
        .replace("rows = 5", "rows = 40");
    let b = karigami::build(karigami::parse(&text, "big-bumps").unwrap()).unwrap();
    assert!(
        b.lattice.cells.len() > 2000,
        "{} cells",
        b.lattice.cells.len()
    );
    assert_eq!(b.simulation_reused(), None, "not simulated");
    let report = karigami::build_text(&b);
    assert!(
        report.contains(
            "the deployed shape is not simulated: build simulates lattices of up to 2000 cells"
        ),
        "{report}"
    );
}

/// The guide shows a name's Latin letters as written (WinAnsi, the
/// built-in Helvetica's encoding: "Käfer-Brücke" was "K?fer-Br?cke"), `?`
/// only for what the font lacks, and a 199-character name stays inside the
/// text width on the cover and in the footer (it ran 50 pt past the
/// right margin and off the page).
#[test]
fn guide_names_keep_their_letters_and_stay_on_the_page() {
    let dir = scratch("guide-names");
    let chain = std::fs::read_to_string(repo().join("templates/chain.toml")).unwrap();
    let long = format!("{} {}", "Lang".repeat(12), "x".repeat(150));
    for (tag, name) in [("umlaut", "Käfer-Brücke – €5 円"), ("long", long.as_str())] {
        let recipe = dir.join(format!("{tag}.toml"));
        let mut text = chain.replace("name = \"chain\"", &format!("name = \"{name}\""));
        if tag == "long" {
            // The material's name is on the cover too.
            text.push_str(&format!("\n[material]\nname = \"{}\"\n", "m".repeat(180)));
        }
        assert_ne!(text, chain);
        std::fs::write(&recipe, text).unwrap();
        let out = dir.join(tag);
        let o = karigami(
            &[
                "-q",
                "build",
                recipe.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            &dir,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let pdf = out.join("assembly.pdf");
        let Some(words) = run("pdftotext", &["-bbox", pdf.to_str().unwrap(), "-"]) else {
            return;
        };
        let words = String::from_utf8(words.stdout).expect("pdftotext writes UTF-8");
        if tag == "umlaut" {
            assert!(words.contains(">Käfer-Brücke<"), "{words}");
            assert!(words.contains(">€5<") && words.contains(">?<"), "{words}");
            continue;
        }
        // A4: 595.3 pt wide, 15 mm (42.5 pt) margins.
        let right = 595.3 - 42.5 + 0.5;
        let mut lines = 0;
        for w in words.lines().filter(|l| l.contains("<word ")) {
            let x_max: f64 = w
                .split("xMax=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap()
                .parse()
                .unwrap();
            assert!(x_max <= right, "past the right margin: {w}");
            lines += usize::from(w.contains(">xxxxx"));
        }
        assert!(lines >= 1, "{words}");
        assert!(
            words.contains("...</word>"),
            "the long name is cut with ..."
        );
    }
}

/// No step runs over a page boundary unless it alone is longer than a page,
/// and then it says so on the page it starts: each of the torus's 19 rows
/// is longer than a page, the flat sheet's rows all fit.
#[test]
fn a_step_longer_than_a_page_says_so_where_it_starts() {
    const NOTE: &str = "This step is longer than a page: it continues on the next page.";
    for (name, steps, long) in [("torus", 19, 19), ("flat-sheet", 6, 0)] {
        let pdf = crate::util::cli_build(name, &[]).join("assembly.pdf");
        let Some(out) = run("pdftotext", &[pdf.to_str().unwrap(), "-"]) else {
            return;
        };
        let text = String::from_utf8(out.stdout).expect("pdftotext writes UTF-8");
        let mut titles = 0;
        let mut notes = 0;
        // pdftotext ends each page with a form feed.
        for page in text.split('\u{c}') {
            let flat = page.split_whitespace().collect::<Vec<_>>().join(" ");
            let here = (1..=steps)
                .filter(|k| flat.contains(&format!("Step {k} of {steps} - row")))
                .count();
            let said = flat.matches(NOTE).count();
            // A long step's note is on the page with its title.
            if long == steps {
                assert_eq!(said, here, "{name}: {flat}");
            }
            titles += here;
            notes += said;
        }
        assert_eq!(titles, steps, "{name}: every step has its title");
        assert_eq!(notes, long, "{name}");
    }
}
