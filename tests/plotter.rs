//! Machine presets (issue 34): a cutting plotter cuts on its mat, with the
//! labels on a pen layer that Design Space and Silhouette Studio can tell
//! from the cuts, refuses holes its blade would tear, and the guide's first
//! page carries the safety note for the stock on that machine.

use crate::cli::{karigami, repo, scratch};
use crate::thirdparty::{python_check, run};
use crate::util::cli_build;
use karigami::{ErrorKind, Layer, Overrides, STOCK_PRESETS, Shape, parse_with};

fn recipe(extra: &str) -> String {
    let chain = std::fs::read_to_string(repo().join("templates/chain.toml")).unwrap();
    format!("{chain}\n{extra}")
}

fn machine(m: &str) -> Overrides {
    Overrides {
        machine: Some(m.into()),
        ..Default::default()
    }
}

/// The first page of a guide as text, its words joined by single spaces.
fn first_page(pdf: &std::path::Path) -> Option<String> {
    let out = run("pdftotext", &["-f", "1", "-l", "1", pdf.to_str()?, "-"])?;
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    Some(text.split_whitespace().collect::<Vec<_>>().join(" "))
}

#[test]
fn a_plotter_cuts_on_its_mat_and_the_mat_is_checked() {
    let cases = [
        ("cricut", None, (292.1, 292.1)),
        ("silhouette", Some("12x24in"), (596.9, 292.1)),
        ("cricut", Some("12x12in"), (292.1, 292.1)),
    ];
    for (m, sheet, (w, h)) in cases {
        let o = Overrides {
            sheet: sheet.map(Into::into),
            ..machine(m)
        };
        // A recipe written for a laser sheet: --machine sets it aside.
        let d = parse_with(&recipe("[sheet]\npreset = \"a3\"\n"), "chain", &o).unwrap();
        let f = &d.fabrication;
        assert!(
            (f.sheet.width - w).abs() < 1e-9 && (f.sheet.height - h).abs() < 1e-9,
            "{m} {sheet:?}: {:?}",
            f.sheet
        );
        let p = f.plotter.as_ref().unwrap();
        assert_eq!(p.mat, sheet.unwrap_or("12x12in"));
        assert_eq!(p.min_hole, karigami::PLOTTER_MIN_HOLE);
        // A blade removes nothing: no kerf unless one is given.
        assert_eq!(karigami::testing::kerf(f), 0.0);
    }
    // In the recipe, the mat is the sheet preset; anything else is refused.
    let d = parse_with(
        &recipe("[machine]\npreset = \"cricut\"\n[sheet]\npreset = \"12x24in\"\nmargin = 3.0\n"),
        "chain",
        &Overrides::default(),
    )
    .unwrap();
    assert_eq!(d.fabrication.sheet.width, 596.9);
    assert_eq!(d.fabrication.sheet.margin, 3.0);
    let source = recipe("[machine]\npreset = \"cricut\"\n[sheet]\nwidth = 300.0\n");
    let e = parse_with(&source, "chain", &Overrides::default()).unwrap_err();
    assert_eq!(e.kind, ErrorKind::SheetNotAMat);
    assert_eq!(&source[e.span.clone().unwrap()], "300.0");
    let o = Overrides {
        sheet: Some("a4".into()),
        ..machine("silhouette")
    };
    let e = parse_with(&recipe(""), "chain", &o).unwrap_err();
    assert_eq!(e.kind, ErrorKind::SheetNotAMatFlag);
    assert_eq!(e.kind.exit_code(), 2);
    assert!(e.hint.unwrap().contains("12x12in, 12x24in"));
    let e = parse_with(&recipe(""), "chain", &machine("plotter")).unwrap_err();
    assert_eq!(e.kind, ErrorKind::UnknownMachinePresetFlag);
    assert!(
        e.hint
            .unwrap()
            .contains("laser-co2, laser-diode, cricut, silhouette")
    );
    // The laser presets are `[laser] machine`'s.
    let d = parse_with(&recipe(""), "chain", &machine("laser-diode")).unwrap();
    assert_eq!(d.fabrication.machine, karigami::Machine::Diode);
    assert!(d.fabrication.plotter.is_none());
}

/// A hole smaller than the blade cuts cleanly stops the build before any
/// file is written, naming the hole, its size, the minimum and the way out;
/// `min_hole` lowers the minimum, and the test piece drops its steps below it.
#[test]
fn holes_the_blade_would_tear_are_refused_before_anything_is_written() {
    let small = "[machine]\npreset = \"silhouette\"\n[eyelet]\nhole = 2.8\nflange = 6.0\n";
    let dir = scratch("plotter-small-holes");
    std::fs::write(dir.join("small.toml"), recipe(small)).unwrap();
    let o = karigami(&["build", "small.toml", "--out", "out"], &dir);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    for says in [
        "error[HoleTooSmallForBlade]",
        "eyelet holes (the custom eyelet's) are 2.8 mm across",
        "smaller than the 3 mm a Silhouette Cameo cutting plotter cuts cleanly",
        "small.toml:",
        "hole = 2.8",
        "use larger eyelets",
        "machine.preset = \"laser-co2\"",
        "machine.min_hole",
    ] {
        assert!(stderr.contains(says), "{says}: {stderr}");
    }
    assert!(!dir.join("out").exists(), "nothing is written");
    // Kerf compensation counts: 3.2 mm cut 0.3 mm narrower is 2.9 mm.
    let e = parse_with(
        &recipe("[machine]\npreset = \"cricut\"\n[laser]\nkerf = 0.3\ncompensate = true\n"),
        "chain",
        &Overrides::default(),
    )
    .unwrap_err();
    assert_eq!(e.kind, ErrorKind::HoleTooSmallForBlade);
    assert!(
        e.message.contains("2.9 mm across (cut 0.3 mm narrower"),
        "{}",
        e.message
    );
    // A blade that cuts 2.7 mm holes: the maker says so.
    let lower = small.replace("[eyelet]", "min_hole = 2.7\n[eyelet]");
    let d = parse_with(&recipe(&lower), "chain", &Overrides::default()).unwrap();
    let piece = karigami::testing::test_piece(&d.fabrication).unwrap();
    let steps: Vec<f64> = piece.holes.iter().map(|h| h.1).collect();
    assert_eq!(steps.len(), 4, "{steps:?}");
    assert!(steps.iter().all(|&s| s >= 2.7 - 1e-9), "{steps:?}");
    // The default 1/8 in eyelet keeps its 3.0 mm step at the 3 mm minimum.
    let d = parse_with(&recipe(""), "chain", &machine("cricut")).unwrap();
    let piece = karigami::testing::test_piece(&d.fabrication).unwrap();
    assert_eq!(piece.holes.len(), 5);
}

/// Every stock on every machine gets its own note: ABS is refused on a
/// laser and safe on a plotter; no plotter note talks of power or fumes to
/// extract; every laser note is today's.
#[test]
fn the_safety_note_follows_the_material_and_the_machine() {
    for stock in STOCK_PRESETS {
        for m in ["laser-co2", "laser-diode", "cricut", "silhouette"] {
            let extra = format!("[material]\npreset = \"{}\"\n", stock.key);
            let d = parse_with(&recipe(&extra), "chain", &machine(m)).unwrap();
            let note = d.fabrication.safety_note(stock.name);
            assert!(note.starts_with("Safety: "), "{note}");
            if m.starts_with("laser") {
                assert!(note.contains(stock.safety), "{m} {}: {note}", stock.key);
                assert!(!note.contains("cutting plotter:"), "{note}");
            } else {
                assert!(note.contains(stock.plotter_safety), "{note}");
                assert!(note.contains("safe to cut on a cutting plotter"), "{note}");
                assert!(note.contains("mat"), "{note}");
                assert!(note.contains("Holes under 3 mm are refused"), "{note}");
                assert!(
                    !note.contains("power") && !note.contains("extract"),
                    "{note}"
                );
                let name = if m == "cricut" {
                    "Cricut"
                } else {
                    "Silhouette"
                };
                assert!(note.contains(name), "{note}");
            }
        }
    }
    let abs = |m: &str| {
        let d = parse_with(&recipe(""), "chain", &machine(m)).unwrap();
        d.fabrication.safety_note("ABS")
    };
    assert!(abs("laser-co2").contains("ABS must not be cut on a laser"));
    assert!(
        abs("cricut").contains("ABS is safe to cut on a cutting plotter: a blade makes no fumes")
    );
    assert!(abs("cricut").contains("strong-grip mat"));
    // Stock without a preset: the blade, not the laser.
    let d = parse_with(
        &recipe("[material]\nname = \"styrene\"\n"),
        "chain",
        &machine("silhouette"),
    )
    .unwrap();
    let note = d.fabrication.safety_note("styrene");
    assert!(
        note.contains("styrene has no stock preset: a blade makes no fumes"),
        "{note}"
    );
}

/// A plotter's SVG read back by svgelements: two groups, `cut` (holes and
/// outlines, blue and red, every hole of the sheet) and `draw` (labels,
/// black only), no reference layer, on the mat's cutting area; librsvg
/// renders it; the guide's first page carries the plotter's safety note.
#[test]
fn a_plotter_sheet_has_a_cut_group_and_a_draw_group() {
    let out = cli_build("flat-sheet", &["--machine", "cricut", "--sheet", "12x24in"]);
    let svg = out.join("sheets/sheet-01.svg");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.contains("width=\"596.9mm\"") && text.contains("height=\"292.1mm\""),
        "{}",
        &text[..400]
    );
    assert!(text.contains("machine: a Cricut Maker or Explore cutting plotter on the 12x24in mat"));
    assert!(!text.contains("<use") && !text.contains("id=\"reference\""));
    // What the build drew: every hole and label of the sheet.
    let d = karigami::parse_with(
        &std::fs::read_to_string(repo().join("examples/flat-sheet.toml")).unwrap(),
        "flat-sheet",
        &Overrides {
            sheet: Some("12x24in".into()),
            ..machine("cricut")
        },
    )
    .unwrap();
    let b = karigami::build(d).unwrap();
    let page = &b.pages[0];
    let items = || page.groups.iter().flat_map(|g| &g.items);
    let holes = items()
        .filter(|i| matches!(i.shape, Shape::Circle { .. }))
        .count();
    let labels = items().filter(|i| i.layer == Layer::Labels).count();
    assert!(holes > 0 && labels > 0);
    let Some(read) = python_check("check_plotter_svg.py", &svg) else {
        return;
    };
    assert_eq!(read["order"], serde_json::json!(["cut", "draw"]), "{read}");
    let (cut, draw) = (&read["top"]["cut"], &read["top"]["draw"]);
    assert_eq!(cut["circles"].as_u64(), Some(holes as u64), "{read}");
    assert_eq!(
        cut["strokes"],
        serde_json::json!(["#0000ff", "#ff0000"]),
        "{read}"
    );
    assert_eq!(draw["circles"].as_u64(), Some(0), "{read}");
    assert_eq!(draw["paths"].as_u64(), Some(labels as u64), "{read}");
    assert_eq!(draw["strokes"], serde_json::json!(["#000000"]), "{read}");
    assert!(
        (read["width_mm"].as_f64().unwrap() - 596.9).abs() < 0.01,
        "{read}"
    );
    // Every strip's cut group is named by its ID; the test piece too.
    let groups: Vec<&str> = cut["groups"]
        .as_array()
        .unwrap()
        .iter()
        .map(|g| g.as_str().unwrap())
        .collect();
    assert!(
        groups.contains(&"test-piece") && groups.iter().any(|g| g.starts_with("R")),
        "{groups:?}"
    );
    // librsvg renders it at its size (3.78 px a mm at 96 dpi).
    let png = scratch("plotter-render").join("sheet-01.png");
    if let Some(o) = run(
        "rsvg-convert",
        &["-o", png.to_str().unwrap(), svg.to_str().unwrap()],
    ) {
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let bytes = std::fs::read(&png).unwrap();
        let (w, h) = (
            u32::from_be_bytes(bytes[16..20].try_into().unwrap()),
            u32::from_be_bytes(bytes[20..24].try_into().unwrap()),
        );
        assert!(
            (w as f64 - 596.9 * 96.0 / 25.4).abs() < 2.0
                && (h as f64 - 292.1 * 96.0 / 25.4).abs() < 2.0,
            "{w} x {h}"
        );
    }
    // The guide: the plotter's note and tools on the first page.
    let Some(page1) = first_page(&out.join("assembly.pdf")) else {
        return;
    };
    for says in [
        "ABS is safe to cut on a cutting plotter: a blade makes no fumes",
        "the 12x24in mat (596.9 x 292.1 mm cutting area)",
        "set its Operation to Pen (Draw)",
        "Attach",
    ] {
        assert!(page1.contains(says), "{says}: {page1}");
    }
    assert!(!page1.contains("must not be cut on a laser"), "{page1}");
    // The same recipe for the laser keeps the laser's warning.
    let Some(laser) = first_page(&cli_build("flat-sheet", &[]).join("assembly.pdf")) else {
        return;
    };
    assert!(laser.contains("ABS must not be cut on a laser"), "{laser}");
    assert!(laser.contains("A laser cutter"), "{laser}");
    // The cover prints the mat's size as the docs give it.
    assert!(page1.contains("1 sheet of 596.9 x 292.1 mm"), "{page1}");
}
