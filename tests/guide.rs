//! The assembly guide and the pictures: steps follow growth order, the PDF
//! has the documented structure (checked with poppler), previews and the
//! OBJ model hold what they should.

use crate::cli::{karigami, repo, scratch};
use crate::thirdparty::run;
use karigami::build::{Build, build};
use karigami::design;
use karigami::guide::{guide, steps};
use std::collections::HashSet;

fn example(name: &str) -> Build {
    let text =
        std::fs::read_to_string(repo().join("examples").join(format!("{name}.toml"))).unwrap();
    build(design::parse(&text, name).unwrap()).unwrap()
}

#[test]
fn each_step_is_one_row_and_the_eyelets_add_up() {
    for name in ["flat-sheet", "curved-sheet", "mirror-arm"] {
        let b = example(name);
        let steps = steps(&b.lattice);
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
        let needing = karigami::lattice::joints(&b.lattice)
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
    let pages = guide(&b).pages;
    let steps = steps(&b.lattice).len();
    // Cover, bill of materials, one or more pages a step, the gauge, the checklist.
    assert!(pages.len() >= steps + 4, "{} pages", pages.len());
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
            assert!(text.contains(&format!("Step {k}")), "step {k}");
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
        let files = b.files();
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
    let files = b.files();
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
            let x: Vec<f64> = l.split(' ').map(|t| t.parse().unwrap()).collect();
            [x[0], x[1], x[2]]
        })
        .collect();
    for f in obj.lines().filter_map(|l| l.strip_prefix("f ")) {
        for i in f.split(' ') {
            let i: usize = i.parse().unwrap();
            assert!((1..=v.len()).contains(&i));
        }
    }
    // Each box is as long, wide and thick as its strip.
    let fab = &b.design.fabrication;
    let d = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    for (k, s) in b.parts.strips.iter().enumerate() {
        let c = &v[8 * k..8 * k + 8];
        assert!((d(c[0], c[1]) - s.length).abs() < 1e-3, "{}", s.id);
        assert!((d(c[0], c[2]) - fab.material.width).abs() < 1e-3);
        assert!((d(c[0], c[4]) - fab.material.thickness).abs() < 1e-3);
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
/// cells (about 510 bytes a cell for 30 x 30, text included). Drawing every
/// row again on every step page took 1,943 bytes a cell at 30 x 30, and
/// rows times that per cell in general.
const GUIDE_BYTES_PER_CELL: u64 = 600;

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
