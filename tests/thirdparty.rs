//! Our files checked by tools nobody here wrote: librsvg and svgelements for
//! SVG, poppler and qpdf for PDF, ezdxf for DXF. `scripts/test` installs them
//! and sets KARIGAMI_REQUIRE_TOOLS, so in CI a missing tool fails the test;
//! a plain `cargo test` without them skips with a note.

use crate::cli::{recipes, repo, scratch};
use crate::util::cli_build;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

const PT_PER_MM: f64 = 72.0 / 25.4;

/// Run a tool; None (after a note) when it is missing and not required.
pub(crate) fn run(tool: &str, args: &[&str]) -> Option<std::process::Output> {
    match Command::new(tool).args(args).output() {
        Ok(out) => Some(out),
        Err(e) => {
            assert!(
                std::env::var_os("KARIGAMI_REQUIRE_TOOLS").is_none(),
                "{tool} is required: {e}"
            );
            eprintln!("note: {tool} not available ({e}); skipped");
            None
        }
    }
}

pub(crate) fn python_check(script: &str, file: &Path) -> Option<Value> {
    let script = repo().join("tests/tools").join(script);
    let out = run(
        "python3",
        &[script.to_str().unwrap(), file.to_str().unwrap()],
    )?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            std::env::var_os("KARIGAMI_REQUIRE_TOOLS").is_none()
                && err.contains("ModuleNotFoundError"),
            "{}: {err}",
            script.display()
        );
        eprintln!("note: {} needs a Python module: {err}", script.display());
        return None;
    }
    Some(serde_json::from_slice(&out.stdout).unwrap())
}

/// Every example built once by the CLI (shared with the other tests that only
/// read the files): (output folder, sheet width, height, a scratch folder of
/// this test's own for what the tools render).
fn built_examples(tag: &str) -> Vec<(PathBuf, f64, f64, PathBuf)> {
    recipes("examples")
        .into_iter()
        .map(|recipe| {
            let name = recipe.file_stem().unwrap().to_string_lossy().into_owned();
            let out = cli_build(&name, &[]).to_path_buf();
            let text = std::fs::read_to_string(&recipe).unwrap();
            let sheet = karigami::parse(&text, "x").unwrap().fabrication.sheet;
            (
                out,
                sheet.width,
                sheet.height,
                scratch(&format!("{tag}-{name}")),
            )
        })
        .collect()
}

fn sheets(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("sheets"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    files.sort();
    assert!(!files.is_empty());
    files
}

fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn svg_renders_at_true_size_and_holes_measure_their_diameter() {
    for (dir, w, h, renders) in built_examples("svg") {
        for svg in sheets(&dir, "svg") {
            let png = renders.join(svg.with_extension("png").file_name().unwrap());
            let Some(out) = run(
                "rsvg-convert",
                &[
                    "-d",
                    "96",
                    "-p",
                    "96",
                    svg.to_str().unwrap(),
                    "-o",
                    png.to_str().unwrap(),
                ],
            ) else {
                return;
            };
            assert!(
                out.status.success(),
                "rsvg-convert: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let (pw, ph) = png_size(&png);
            let px = |mm: f64| mm * 96.0 / 25.4;
            assert!(
                (pw as f64 - px(w)).abs() <= 1.0 && (ph as f64 - px(h)).abs() <= 1.0,
                "{}: {pw} x {ph} px",
                svg.display()
            );
            let Some(m) = python_check("check_svg.py", &svg) else {
                return;
            };
            // svgelements converts with a rounded px-per-mm constant: allow 1 micrometre.
            assert!((m["width_mm"].as_f64().unwrap() - w).abs() < 1e-3, "{m}");
            assert!((m["height_mm"].as_f64().unwrap() - h).abs() < 1e-3, "{m}");
            let holes: Vec<f64> = m["hole_diameters_mm"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect();
            // One hole size, plus the test piece's stepped holes on sheet 1.
            let first = svg.ends_with("sheet-01.svg");
            assert!(
                holes.iter().any(|d| (d - 3.2).abs() < 0.001),
                "the 1/8 in eyelet hole: {m}"
            );
            for d in &holes {
                let step = ((d - 3.2) / 0.1).round();
                assert!(
                    (d - 3.2 - step * 0.1).abs() < 0.001
                        && step.abs() <= 2.0
                        && (first || step == 0.0),
                    "{}: hole of {d} mm",
                    svg.display()
                );
            }
        }
    }
}

#[test]
fn pdf_pages_are_the_sheet_size_and_qpdf_finds_no_errors() {
    for (dir, w, h, renders) in built_examples("pdf") {
        let pdf = dir.join("cut.pdf");
        let pdf_s = pdf.to_str().unwrap();
        let Some(info) = run("pdfinfo", &["-f", "1", "-l", "999", pdf_s]) else {
            return;
        };
        let info = String::from_utf8_lossy(&info.stdout).into_owned();
        let pages: usize = info.lines().find(|l| l.starts_with("Pages:")).unwrap()[6..]
            .trim()
            .parse()
            .unwrap();
        assert_eq!(pages, sheets(&dir, "svg").len(), "one page per sheet");
        for line in info
            .lines()
            .filter(|l| l.starts_with("Page") && l.contains("size:"))
        {
            let nums: Vec<f64> = line
                .split_whitespace()
                .filter_map(|t| t.parse().ok())
                .collect();
            let (pw, ph) = (nums[nums.len() - 2], nums[nums.len() - 1]);
            assert!(
                (pw - w * PT_PER_MM).abs() < 0.01 && (ph - h * PT_PER_MM).abs() < 0.01,
                "{line}: expected {w} x {h} mm"
            );
        }
        let Some(check) = run("qpdf", &["--check", pdf_s]) else {
            return;
        };
        let text = String::from_utf8_lossy(&check.stdout);
        assert!(
            check.status.success() && text.contains("No syntax or stream encoding errors"),
            "{text}"
        );
        let prefix = renders.join("page");
        let Some(render) = run(
            "pdftoppm",
            &["-r", "20", "-png", pdf_s, prefix.to_str().unwrap()],
        ) else {
            return;
        };
        assert!(render.status.success());
        let rendered = std::fs::read_dir(&renders)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .starts_with("page")
            })
            .count();
        assert_eq!(rendered, pages);
    }
}

#[test]
fn dxf_passes_ezdxf_audit_in_millimetres() {
    for (dir, w, h, _) in built_examples("dxf") {
        for dxf in sheets(&dir, "dxf") {
            let Some(m) = python_check("check_dxf.py", &dxf) else {
                return;
            };
            assert_eq!(m["errors"], 0, "{}: {m}", dxf.display());
            assert_eq!(m["version"], "AC1015");
            assert_eq!(m["units"], 4, "millimetres");
            // True circles of the hole radius (and the test piece's steps on sheet 1).
            let radii: Vec<f64> = m["radii"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect();
            let expected: &[f64] = if dxf.ends_with("sheet-01.dxf") {
                &[1.5, 1.55, 1.6, 1.65, 1.7]
            } else {
                &[1.6]
            };
            assert_eq!(radii.len(), expected.len(), "{m}");
            for (r, e) in radii.iter().zip(expected) {
                assert!((r - e).abs() < 1e-6, "{m}");
            }
            let layers: Vec<&str> = m["entity_layers"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_str().unwrap())
                .collect();
            assert!(
                layers.contains(&"CIRCLE:holes")
                    && layers.contains(&"LWPOLYLINE:outlines")
                    && layers.contains(&"LWPOLYLINE:labels"),
                "{layers:?}"
            );
            let (min, max) = (&m["extmin"], &m["extmax"]);
            assert!(
                min[0].as_f64().unwrap() >= 0.0 && min[1].as_f64().unwrap() >= 0.0,
                "{m}"
            );
            assert!(
                max[0].as_f64().unwrap() <= w && max[1].as_f64().unwrap() <= h,
                "{m}"
            );
        }
    }
}

/// Every hole a tool read back (`[x, y, r]` mm, any order) against the
/// page's circles (y flipped for DXF), to 0.001 mm.
pub(crate) fn holes_match(page: &karigami::Page, read: &Value, flip: bool, what: &str) {
    use karigami::Shape;
    // Both lists on the files' 0.1 um grid, so that they sort alike.
    let grid = |v: f64| (v * 1e4).round() / 1e4;
    let mut want: Vec<[f64; 3]> = page
        .groups
        .iter()
        .flat_map(|g| &g.items)
        .filter_map(|i| match i.shape {
            Shape::Circle { center, radius } => {
                let y = if flip {
                    page.height - center.y
                } else {
                    center.y
                };
                Some([center.x, y, radius].map(grid))
            }
            _ => None,
        })
        .collect();
    want.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let mut got: Vec<[f64; 3]> = read
        .as_array()
        .unwrap()
        .iter()
        .map(|h| [0, 1, 2].map(|k| grid(h[k].as_f64().unwrap())))
        .collect();
    got.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(got.len(), want.len(), "{what}");
    for (g, w) in got.iter().zip(&want) {
        assert!(
            (0..3).all(|k| (g[k] - w[k]).abs() < 0.001),
            "{what}: {g:?} read, {w:?} drawn"
        );
    }
}

/// The 30 x 30 golden sheet built in-process up to its simulation (its
/// sheets are what these tests read), once for all of them: strips
/// engraved with their type, not their ID, so 1800 of them are drawn alike.
pub(crate) fn alike_strips() -> &'static karigami::Build {
    crate::util::unsimulated_with("tests/golden/sheet-30x30.toml", &Default::default())
}

/// Repeated strips are blocks placed by INSERTs, and `<use>` of one
/// drawing in SVG; ezdxf and svgelements, expanding them, find every hole
/// of the drawing where the sheet puts it (to 0.001 mm) and nothing else.
#[test]
fn dxf_blocks_and_svg_uses_expand_to_every_hole_of_the_sheet() {
    let b = alike_strips();
    let dir = scratch("shared-drawings");
    for (i, page) in b.pages.iter().enumerate() {
        let strips = page.groups.len() - 1;
        let path = dir.join(format!("sheet-{i}.dxf"));
        std::fs::write(&path, karigami::formats::dxf::write(page)).unwrap();
        let Some(m) = python_check("check_dxf.py", &path) else {
            return;
        };
        assert_eq!(m["errors"], 0, "{m}");
        assert!(
            m["inserts"].as_u64().unwrap() as usize >= strips / 2,
            "most of the {strips} strips are repeats: {}",
            m["inserts"]
        );
        holes_match(page, &m["holes"], true, &format!("DXF sheet {i}"));
        let path = dir.join(format!("sheet-{i}.svg"));
        let svg = karigami::formats::svg::write(page);
        let uses = String::from_utf8_lossy(&svg).matches("<use ").count();
        assert!(uses >= strips / 2, "{uses} <use> for {strips} strips");
        std::fs::write(&path, svg).unwrap();
        let Some(m) = python_check("check_svg.py", &path) else {
            return;
        };
        holes_match(page, &m["holes"], false, &format!("SVG sheet {i}"));
    }
}
