//! Every file in fixtures/designs/bad/ must be refused with the error its
//! first line announces: `# expect: CLASS LINE:COL "part of the message"`.
//! To add a case, drop a recipe there with such a line.

use karigami::build;
use std::fs;
use std::path::PathBuf;

pub(crate) struct Expectation {
    pub class: String,
    pub line_col: (usize, usize),
    pub message: String,
}

pub(crate) fn expectation(source: &str, file: &str) -> Expectation {
    let line = source
        .trim_start_matches('\u{FEFF}')
        .lines()
        .next()
        .unwrap_or_default();
    let rest = line
        .strip_prefix("# expect: ")
        .unwrap_or_else(|| panic!("{file}: first line must be `# expect: ...`"));
    let (class, rest) = rest.split_once(' ').expect("class");
    let (pos, message) = rest.split_once(' ').expect("position");
    let (l, c) = pos.split_once(':').expect("LINE:COL");
    Expectation {
        class: class.to_string(),
        line_col: (l.parse().unwrap(), c.parse().unwrap()),
        message: message
            .strip_prefix('"')
            .and_then(|m| m.strip_suffix('"'))
            .expect("message in quotes")
            .replace("\\\"", "\""),
    }
}

pub(crate) fn bad_fixtures() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = fs::read_dir("fixtures/designs/bad")
        .expect("fixtures/designs/bad exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_bad_fixture_is_refused_where_and_why_it_says() {
    let files = bad_fixtures();
    assert!(
        files.len() >= 15,
        "expected the error fixtures, found {}",
        files.len()
    );
    let mut failures = Vec::new();
    for path in &files {
        let file = path.display().to_string();
        let source = fs::read_to_string(path).unwrap();
        let want = expectation(&source, &file);
        let got = karigami::parse(&source, "bad").and_then(|d| build(d).map(|_| ()));
        let Err(diag) = got else {
            failures.push(format!("{file}: was accepted"));
            continue;
        };
        let line_col = diag.line_col(&source);
        if diag.kind.name() != want.class
            || line_col != Some(want.line_col)
            || !diag.message.contains(&want.message)
        {
            failures.push(format!(
                "{file}: expected {} {:?} {:?}\n  got {} {:?} {:?}",
                want.class,
                want.line_col,
                want.message,
                diag.kind.name(),
                line_col,
                diag.message
            ));
        }
        let rendered = diag.render(&file, &source);
        if !rendered.contains(&format!("{file}:{}:{}", want.line_col.0, want.line_col.1)) {
            failures.push(format!("{file}: rendered without its location\n{rendered}"));
        }
        if !(rendered.contains("= help: ") || diag.kind == karigami::ErrorKind::Toml) {
            failures.push(format!("{file}: no hint\n{rendered}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// `--kerf` with `--compensate-kerf` is refused as a flag error (no place in
/// the recipe) when it would close the eyelet holes or a test piece step;
/// without compensation, or with the test piece left out, the same kerf
/// builds (chain --kerf 3.3 used to write r="-0.05" holes, --kerf 3 a test
/// hole of r="0").
#[test]
fn a_kerf_flag_that_closes_a_compensated_hole_is_refused() {
    let source = std::fs::read_to_string("templates/chain.toml").unwrap();
    let with = |kerf: f64, compensate: bool, test_piece: bool| {
        let o = karigami::Overrides {
            kerf: Some(kerf),
            compensate_kerf: Some(compensate),
            test_piece: Some(test_piece),
            ..Default::default()
        };
        karigami::parse_with(&source, "chain", &o)
    };
    let e = with(3.3, true, true).unwrap_err();
    assert_eq!(e.kind, karigami::ErrorKind::KerfClosesHoleFlag);
    assert!(e.span.is_none(), "{e:?}");
    assert!(
        e.message
            .contains("--kerf 3.3: kerf compensation closes the eyelet holes"),
        "{}",
        e.message
    );
    assert_eq!(e.kind.exit_code(), 2);
    // 3 mm closes the test piece's 3.0 mm step, not the 3.2 mm eyelet holes.
    let e = with(3.0, true, true).unwrap_err();
    assert!(
        e.message.contains("the test piece's smallest hole"),
        "{}",
        e.message
    );
    assert!(with(3.0, true, false).is_ok());
    assert!(with(3.3, false, true).is_ok());
    assert!(with(2.999, true, true).is_ok());
}
