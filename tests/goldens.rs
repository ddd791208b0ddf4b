//! Pinned outputs: what `karigami` writes for a few small recipes, and what
//! it says for every bad fixture, compared byte for byte with the files in
//! tests/golden/ and fixtures/designs/bad/. A refactoring must leave them
//! as they are; after a deliberate change, `KARIGAMI_BLESS=1 cargo test
//! --test tests golden` rewrites them (then read the diff before committing).

use crate::cli::{karigami, repo, scratch};
use crate::thirdparty::run;
use std::path::{Path, PathBuf};

/// True when the golden files are to be rewritten rather than compared.
pub(crate) fn blessing() -> bool {
    std::env::var_os("KARIGAMI_BLESS").is_some()
}

/// Compare `actual` with the golden file `path` (relative to the repository),
/// or write it when blessing. Err names the file and the first difference.
pub(crate) fn compare(path: &str, actual: &[u8]) -> Result<(), String> {
    let golden = repo().join(path);
    if blessing() {
        if let Some(dir) = golden.parent() {
            std::fs::create_dir_all(dir).unwrap();
        }
        std::fs::write(&golden, actual).unwrap();
        return Ok(());
    }
    let Ok(expected) = std::fs::read(&golden) else {
        return Err(format!("{path} is missing (KARIGAMI_BLESS=1 writes it)"));
    };
    if expected == actual {
        return Ok(());
    }
    let (e, a) = (
        String::from_utf8_lossy(&expected),
        String::from_utf8_lossy(actual),
    );
    let (e, a): (Vec<&str>, Vec<&str>) = (e.lines().collect(), a.lines().collect());
    let at = e
        .iter()
        .zip(&a)
        .position(|(x, y)| x != y)
        .unwrap_or(e.len().min(a.len()));
    Err(format!(
        "{path} differs at line {}: expected {:?}, got {:?} ({} vs {} lines, {} vs {} bytes)",
        at + 1,
        e.get(at),
        a.get(at),
        e.len(),
        a.len(),
        expected.len(),
        actual.len()
    ))
}

/// The pinned builds: (golden folder, recipe). Small and quick, one of each
/// kind of seed: an open sheet, a mechanism, a loop and a helix.
const CASES: [(&str, &str); 4] = [
    ("flat-sheet", "examples/flat-sheet.toml"),
    ("mirror-arm", "examples/mirror-arm.toml"),
    ("tube", "templates/tube.toml"),
    ("helix", "templates/helix.toml"),
];

/// The files of a build that are pinned as they are written.
const PINNED: [&str; 5] = [
    "lattice.json",
    "parts.csv",
    "report.txt",
    "sheets/sheet-01.svg",
    "sheets/sheet-01.dxf",
];

/// Build one case with the CLI and compare its files; the guide is pinned
/// as its page count and `pdftotext -layout` text.
fn golden_build(name: &str, recipe: &str) -> Vec<String> {
    // The build is shared with the other tests that read it (tests/util.rs).
    let out = crate::util::cli_build(recipe, &[]);
    let mut failures = Vec::new();
    for file in PINNED {
        let bytes = std::fs::read(out.join(file)).unwrap_or_default();
        if let Err(e) = compare(&format!("tests/golden/{name}/{file}"), &bytes) {
            failures.push(e);
        }
    }
    if let Some(text) = guide_text(&out.join("assembly.pdf"))
        && let Err(e) = compare(
            &format!("tests/golden/{name}/assembly.txt"),
            text.as_bytes(),
        )
    {
        failures.push(e);
    }
    failures
}

/// "pages: N" and the guide's `pdftotext -layout` text; None without poppler.
fn guide_text(pdf: &Path) -> Option<String> {
    let info = run("pdfinfo", &[pdf.to_str().unwrap()])?;
    let info = String::from_utf8_lossy(&info.stdout).into_owned();
    let pages = info
        .lines()
        .find_map(|l| l.strip_prefix("Pages:"))
        .map_or("?", str::trim)
        .to_string();
    let text = run("pdftotext", &["-layout", pdf.to_str().unwrap(), "-"])?;
    assert!(text.status.success(), "pdftotext {}", pdf.display());
    Some(format!(
        "pages: {pages}\n{}",
        String::from_utf8(text.stdout).expect("pdftotext writes UTF-8")
    ))
}

/// Every bad fixture with the command that refuses it: `tune` for the
/// optimiser's fixtures, `check` for the rest. Paths relative to the
/// repository, as the messages show them.
fn bad_fixtures() -> Vec<(PathBuf, &'static str)> {
    let mut all: Vec<(PathBuf, &str)> = Vec::new();
    for (folder, command) in [
        ("fixtures/designs/bad", "check"),
        ("fixtures/designs/bad/optimise", "tune"),
    ] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(repo().join(folder))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .map(|p| Path::new(folder).join(p.file_name().unwrap()))
            .collect();
        files.sort();
        all.extend(files.into_iter().map(|p| (p, command)));
    }
    all
}

/// The whole of what `karigami -q check` (or `tune`) prints on stderr for a
/// bad fixture, then its exit status, as `NAME.stderr` beside it.
fn golden_stderr(path: &Path, command: &str) -> Result<(), String> {
    let o = karigami(&["-q", command, path.to_str().unwrap()], &repo());
    let mut actual = o.stderr;
    actual.extend(format!("exit status: {}\n", o.status.code().unwrap_or(-1)).bytes());
    compare(
        &path.with_extension("stderr").display().to_string(),
        &actual,
    )
}

/// The pinned builds and the bad fixtures' messages, in one test so that
/// each case is built once; the builds run side by side.
#[test]
fn golden_outputs_and_error_messages_are_unchanged() {
    let fixtures = bad_fixtures();
    assert!(fixtures.len() >= 40, "{} bad fixtures", fixtures.len());
    let mut failures: Vec<String> = std::thread::scope(|s| {
        let builds: Vec<_> = CASES
            .iter()
            .map(|&(name, recipe)| s.spawn(move || golden_build(name, recipe)))
            .collect();
        let mut failures: Vec<String> = fixtures
            .iter()
            .filter_map(|(path, command)| golden_stderr(path, command).err())
            .collect();
        for b in builds {
            failures.extend(b.join().expect("a golden build"));
        }
        failures
    });
    failures.sort();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// What `--json` prints (stdout, then the exit status) for passing and
/// failing checks, each kind of refusal, and the batch record a build
/// writes: the JSON reports are pinned like the files.
#[test]
fn golden_json_reports_are_unchanged() {
    let dir = scratch("golden-json");
    std::fs::create_dir_all(dir.join("not-a-build")).unwrap();
    std::fs::write(dir.join("not-a-build/notes.txt"), "mine").unwrap();
    // Relative to the scratch folder, so that the paths in the reports do
    // not depend on where the repository is.
    let up = "../../../";
    let flat = format!("{up}examples/flat-sheet.toml");
    let bad = format!("{up}fixtures/designs/bad");
    let leg = format!("{up}fixtures/designs/bad/leg-shorter-than-flange.toml");
    let cases: [(&str, Vec<&str>); 7] = [
        (
            "check-pass",
            vec![
                "check",
                "--json",
                &flat,
                "../../../examples/mirror-arm.toml",
                "../../../templates/tube.toml",
                "../../../templates/helix.toml",
            ],
        ),
        ("check-bad-fixtures", vec!["check", "--json", &bad]),
        (
            "check-missing-file",
            vec!["check", "--json", "no-such.toml"],
        ),
        (
            "check-unknown-sheet-flag",
            vec!["check", "--json", "--sheet", "a9", &flat],
        ),
        ("usage-error", vec!["build", "--json", "--no-such-flag"]),
        (
            "out-not-a-build",
            vec!["build", "--json", &flat, "--out", "not-a-build"],
        ),
        (
            "batch",
            vec!["-q", "build", &flat, &leg, "--out", "batch", "--jobs", "1"],
        ),
    ];
    let mut failures = Vec::new();
    for (name, args) in &cases {
        let o = karigami(args, &dir);
        let mut actual = if *name == "batch" {
            std::fs::read(dir.join("batch/batch.json")).unwrap_or_default()
        } else {
            o.stdout
        };
        actual.extend(format!("exit status: {}\n", o.status.code().unwrap_or(-1)).bytes());
        if let Err(e) = compare(&format!("tests/golden/json/{name}.json"), &actual) {
            failures.push(e);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
