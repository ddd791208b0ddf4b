//! Robustness: random and mutated recipes thrown at parsing and the whole
//! pipeline. Never a panic, never NaN or infinity in a file, and every file
//! parses: JSON, well-formed SVG (balanced tags, no control characters),
//! DXF group structure, CSV rows of one width, OBJ records of finite
//! numbers. Strings get control characters, numbers their extremes.
//!
//! CI runs `FUZZ_CASES` cases; the long run is `scripts/fuzz 100000`
//! (`KARIGAMI_FUZZ_CASES=N`, optional `KARIGAMI_FUZZ_SEED=S`). Hostile build
//! folders (planted markers, FIFOs) go through the binary the same way.

use crate::cli::{recipes, repo};
use crate::util::Rng;
use karigami::build;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

const FUZZ_CASES: usize = 400;

/// Numbers that break naive code: non-finite, huge, tiny, negative, counts.
const EXTREMES: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "+nan",
    "0",
    "-0.0",
    "1e308",
    "-1e308",
    "1e-308",
    "5e-324",
    "9007199254740993",
    "-1",
    "999999999",
    "2147483648",
    "100000",
    "4000001",
    "1e6",
    "1e-9",
    "0.5",
    "3",
    "7.0",
    "90.0",
    "-90.0",
    "180",
    "1e4",
    "1e300",
    "-1e300",
    "1e15",
    "1000001",
    "-1e6",
    "1e-300",
    "0.0001",
    "5000.0001",
    "500.0001",
    "-0.0001",
    "18446744073709551616",
];

const STRINGS: &[&str] = &[
    "sheet",
    "loop",
    "helix",
    "match",
    "xz",
    "yz",
    "disk",
    "ellipsoid",
    "revolution",
    "",
    "ßπ",
    "compact",
    "none",
    "id",
    "a4",
    "letter",
    "glowforge",
    "1/8in",
    "12x24in",
    "0x0",
    "1e9x1e9",
    "abs",
    "3/16in",
    // Control characters (as TOML escapes), markup, and long or wide text.
    "two\\nlines",
    "esc\\u001b[31m",
    "tab\\there",
    "nul\\u0000",
    "cr\\r\\nlf",
    "del\\u007f",
    "<title>&amp;</title>]]>--",
    "%%c\\\\P{\\\\}",
    "ボウル 🍜",
    "\\u202eevil",
    "\\ufeffbom",
];

/// Lines a recipe may have, for random recipes and insertions.
const LINES: &[&str] = &[
    "[lattice]",
    "seed = \"sheet\"",
    "seed = \"loop\"",
    "seed = \"helix\"",
    "kappa = 0.0",
    "kappa = [1.0, -1.0, 0.0]",
    "points = [[0.0, 0.0], [20.0, 0.0], [40.0, 0.0]]",
    "points = [[0.0, 0.0, 0.0], [20.0, 0.0, 5.0]]",
    "cells = 12",
    "[lattice.line]",
    "from = [0.0, 0.0]",
    "to = [100.0, 0.0]",
    "[lattice.arc]",
    "center = [0.0, 0.0]",
    "radius = 100.0",
    "from = 180.0",
    "to = 90.0",
    "[lattice.circle]",
    "points = 8",
    "[lattice.grow]",
    "rows = 3",
    "start = 1",
    "angle = 45.0",
    "angle = [45.0, 10.0]",
    "direction = [1.0, -1.0]",
    "left_leg = \"match\"",
    "right_leg = 30.0",
    "[[lattice.rows]]",
    "row = 1",
    "repeat = 2",
    "front = { zigzag = 20.0 }",
    "front = { turn = [10.0, -10.0] }",
    "front = { bend = 10.0, twist = 30.0 }",
    "front = { crank = [{ from = 0, to = 2, angle = 30.0 }] }",
    "candidate = 2",
    "target = [10.0, 10.0, 10.0]",
    "[lattice.fit]",
    "surface = \"disk\"",
    "surface = \"revolution\"",
    "profile = [[100.0, 0.0], [120.0, -20.0]]",
    "axes = [100.0, 100.0, 50.0]",
    "[material]",
    "width = 10.0",
    "thickness = 0.5",
    "[eyelet]",
    "preset = \"1/8in\"",
    "hole = 3.0",
    "flange = 6.0",
    "[strip]",
    "end_margin = 6.0",
    "label = \"compact\"",
    "[laser]",
    "kerf = 0.15",
    "compensate_kerf = true",
    "[sheet]",
    "preset = \"a4\"",
    "width = 300.0",
    "height = 200.0",
    "margin = 5.0",
    "gap = 2.0",
    "[guide]",
    "paper = \"letter\"",
    "name = \"x\"",
    "name = \"two\\nlines\"",
    "name = \"<&>\\\"'\"",
    "name = \"\\u001b[2J\"",
    "name = \"ボウル\"",
    "[material]\nname = \"ABS\\r\\n0 EOF\"",
    "[material]\nname = \"\\u0000\"",
    // The shapes of issue 36's heavy inputs: tall and huge sheets, tiny
    // simulation edges (each refused or bounded, never hours).
    "rows = 3000",
    "cells = 200",
    "rows = 100",
    "[simulation]\nedge_length = 0.01",
    "[simulation]\nedge_length = 0.5",
    "[simulation]\ntheta = 170.0",
];

/// A byte range `[start, end)` of a recipe.
type Span = (usize, usize);

/// Byte ranges of number tokens and of string contents in `s`.
fn tokens(s: &str) -> (Vec<Span>, Vec<Span>) {
    let b = s.as_bytes();
    let (mut numbers, mut strings) = (Vec::new(), Vec::new());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'#' {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i] == b'"' {
            let start = i + 1;
            i += 1;
            while i < b.len() && b[i] != b'"' && b[i] != b'\n' {
                i += 1;
            }
            strings.push((start, i));
            i += 1;
        } else if b[i].is_ascii_digit()
            || (b[i] == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let start = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_digit() || b"._eE+-".contains(&b[i])) {
                i += 1;
            }
            numbers.push((start, i));
        } else {
            i += 1;
        }
    }
    (numbers, strings)
}

fn splice(s: &str, (a, b): Span, with: &str) -> String {
    format!("{}{with}{}", &s[..a], &s[b..])
}

fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut s = text.to_string();
    for _ in 0..1 + rng.below(2) {
        let (numbers, strings) = tokens(&s);
        let lines: Vec<&str> = s.lines().collect();
        // Number changes are most likely to reach the geometry; junk and
        // truncation exercise the parser.
        s = match rng.below(12) {
            0..=3 if !numbers.is_empty() => {
                splice(&s, *rng.pick(&numbers), rng.pick::<&str>(EXTREMES))
            }
            4 | 5 if !numbers.is_empty() => {
                let span = *rng.pick(&numbers);
                let v: f64 = s[span.0..span.1].parse().unwrap_or(1.0);
                let factor = *rng.pick(&[-1.0, 10.0, 0.1, 1.001, 0.999, 2.0, 0.0]);
                splice(&s, span, &format!("{:?}", v * factor))
            }
            6 if !strings.is_empty() => {
                let with = if rng.below(8) == 0 {
                    "x".repeat(150 + rng.below(100))
                } else {
                    rng.pick::<&str>(STRINGS).to_string()
                };
                splice(&s, *rng.pick(&strings), &with)
            }
            7 if !lines.is_empty() => {
                let k = rng.below(lines.len());
                let mut l = lines.clone();
                l.remove(k);
                l.join("\n")
            }
            8 if !lines.is_empty() => {
                let mut l = lines.clone();
                let (a, b) = (rng.below(l.len()), rng.below(l.len()));
                l.swap(a, b);
                l.join("\n")
            }
            9 => {
                let mut l = lines.clone();
                let at = rng.below(l.len() + 1);
                l.insert(at, *rng.pick(LINES));
                l.join("\n")
            }
            10 => {
                let mut at = rng.below(s.len() + 1);
                while !s.is_char_boundary(at) {
                    at -= 1;
                }
                let junk = rng.pick(&[
                    "[", "]", "=", "\"", "{", "}", ",", "\n", "#", "é", "\u{0}", "0x", "1_000",
                    "'''", "\\",
                ]);
                format!("{}{junk}{}", &s[..at], &s[at..])
            }
            _ => {
                let mut at = rng.below(s.len() + 1);
                while !s.is_char_boundary(at) {
                    at -= 1;
                }
                s[..at].to_string()
            }
        };
    }
    s
}

fn random_recipe(rng: &mut Rng) -> String {
    (0..3 + rng.below(25))
        .map(|_| *rng.pick(LINES))
        .collect::<Vec<_>>()
        .join("\n")
}

/// One case through the whole pipeline: Err describes what went wrong.
fn run_case(text: &str, limit: f64) -> Result<&'static str, String> {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // The case's own time limit, as `--time-limit` gives one: a case
        // past it stops cleanly ("refused later").
        let overrides = karigami::Overrides {
            deadline: karigami::Deadline::after(limit),
            ..karigami::Overrides::default()
        };
        let design = match karigami::parse_with(text, "fuzz", &overrides) {
            Ok(d) => d,
            Err(d) => {
                let rendered = d.render("fuzz.toml", text);
                return if rendered.is_empty() {
                    Err("an empty error".to_string())
                } else {
                    Ok("refused")
                };
            }
        };
        let built = match build(design) {
            Ok(b) => b,
            Err(d) => {
                let _ = d.render("fuzz.toml", text);
                return Ok("refused later");
            }
        };
        for (name, bytes) in karigami::files(&built) {
            // Binary files: pictures, PDFs, and the solver's state, whose
            // reader refuses anything non-finite (tests/rebuild.rs).
            if name.ends_with(".png") || name.ends_with(".pdf") || name == karigami::STATE_FILE {
                continue;
            }
            let t = String::from_utf8_lossy(&bytes);
            if let Some(bad) = ["NaN", "nan", "inf", "Infinity"]
                .into_iter()
                .find(|bad| words_contain(&t, bad))
            {
                return Err(format!("{name} contains {bad}"));
            }
            parses(&name, &t).map_err(|e| format!("{name} does not parse: {e}"))?;
        }
        Ok("built")
    }));
    match outcome {
        Ok(r) => r,
        Err(p) => Err(format!(
            "panic: {}",
            p.downcast_ref::<String>()
                .map(String::as_str)
                .or(p.downcast_ref::<&str>().copied())
                .unwrap_or("?")
        )),
    }
}

/// The file parses in its format (readers of our own, kept strict and
/// fast enough for every fuzz case; the third-party readers check the
/// examples and hostile names in tests/thirdparty.rs and tests/safety.rs).
pub(crate) fn parses(name: &str, text: &str) -> Result<(), String> {
    let ext = name.rsplit('.').next().unwrap_or_default();
    let control = |t: &str| t.chars().find(|&c| c.is_control() && !"\n\r\t".contains(c));
    match ext {
        "json" => serde_json::from_str::<serde_json::Value>(text)
            .map(|_| ())
            .map_err(|e| e.to_string()),
        "svg" => {
            if let Some(c) = control(text) {
                return Err(format!("control character U+{:04X}", u32::from(c)));
            }
            let mut open: Vec<String> = Vec::new();
            for event in svg::read(text).map_err(|e| e.to_string())? {
                match event {
                    svg::parser::Event::Error(e) => return Err(e.to_string()),
                    svg::parser::Event::Tag(tag, kind, _) => match kind {
                        svg::node::element::tag::Type::Start => open.push(tag.to_string()),
                        svg::node::element::tag::Type::End => {
                            if open.pop().as_deref() != Some(tag) {
                                return Err(format!("</{tag}> closes nothing open"));
                            }
                        }
                        svg::node::element::tag::Type::Empty => {}
                    },
                    _ => {}
                }
            }
            if open.is_empty() {
                Ok(())
            } else {
                Err(format!("unclosed {open:?}"))
            }
        }
        "dxf" => {
            // Pairs of lines: an integer group code, then its value.
            let lines: Vec<&str> = text.lines().collect();
            if !lines.len().is_multiple_of(2) || lines.last() != Some(&"EOF") {
                return Err("not whole code/value pairs ending in EOF".to_string());
            }
            for pair in lines.chunks(2) {
                let code: i32 = pair[0]
                    .trim()
                    .parse()
                    .map_err(|_| format!("group code {:?}", pair[0]))?;
                if let Some(c) = control(pair[1]) {
                    return Err(format!(
                        "code {code}: control character U+{:04X}",
                        u32::from(c)
                    ));
                }
                if (10..60).contains(&code) && pair[1].trim().parse::<f64>().is_err() {
                    return Err(format!("code {code}: not a number: {:?}", pair[1]));
                }
            }
            Ok(())
        }
        "csv" => {
            let mut width = None;
            for line in text.lines() {
                let mut fields = 1;
                let mut quoted = false;
                for c in line.chars() {
                    match c {
                        '"' => quoted = !quoted,
                        ',' if !quoted => fields += 1,
                        _ => {}
                    }
                }
                if quoted {
                    return Err(format!("unclosed quote: {line}"));
                }
                if *width.get_or_insert(fields) != fields {
                    return Err(format!("{fields} fields: {line}"));
                }
            }
            Ok(())
        }
        "obj" => {
            for line in text.lines() {
                let mut words = line.split_whitespace();
                match words.next() {
                    None | Some("#" | "o" | "g" | "s" | "mtllib" | "usemtl") => {}
                    Some("v" | "vn") => {
                        for w in words {
                            if !w.parse::<f64>().is_ok_and(f64::is_finite) {
                                return Err(format!("bad record: {line}"));
                            }
                        }
                    }
                    Some("f" | "l") => {
                        for w in words {
                            let i = w.split('/').next().unwrap_or_default();
                            if i.parse::<i64>().is_err() {
                                return Err(format!("bad record: {line}"));
                            }
                        }
                    }
                    Some(w) if w.starts_with('#') => {}
                    Some(other) => return Err(format!("unknown record {other:?}")),
                }
            }
            Ok(())
        }
        _ => match control(text) {
            Some(c) => Err(format!("control character U+{:04X}", u32::from(c))),
            None => Ok(()),
        },
    }
}

/// `bad` as a number token, not inside a word such as "info".
fn words_contain(text: &str, bad: &str) -> bool {
    text.match_indices(bad).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + bad.len()..].chars().next();
        !before.is_some_and(char::is_alphanumeric) && !after.is_some_and(char::is_alphanumeric)
    })
}

#[test]
fn random_and_mutated_recipes_never_panic_nor_write_non_finite_numbers() {
    let cases: usize = std::env::var("KARIGAMI_FUZZ_CASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(FUZZ_CASES);
    let seed: u64 = std::env::var("KARIGAMI_FUZZ_SEED")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(1);
    let corpus: Vec<String> = recipes("examples")
        .into_iter()
        .chain(recipes("templates"))
        .chain(recipes("fixtures/designs/bad"))
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    // Panics are caught and reported per case; keep the default hook quiet.
    std::panic::set_hook(Box::new(|_| {}));
    // KARIGAMI_FUZZ_START skips to a case; KARIGAMI_FUZZ_LOG prints each
    // case number first (to find a case that kills the process).
    let start: usize = std::env::var("KARIGAMI_FUZZ_START")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(0);
    let log = std::env::var_os("KARIGAMI_FUZZ_LOG").is_some();
    // Each case runs under a time limit (KARIGAMI_FUZZ_LIMIT seconds: CI's
    // debug build 10, `scripts/fuzz` 25 on a release build), and no case
    // may take longer than KARIGAMI_FUZZ_CEILING (CI 60, `scripts/fuzz`
    // 30): the limit must stop it cleanly well within that.
    let limit: f64 = std::env::var("KARIGAMI_FUZZ_LIMIT")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(10.0);
    let ceiling: f64 = std::env::var("KARIGAMI_FUZZ_CEILING")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(60.0);
    let next = AtomicUsize::new(start);
    let tally = Mutex::new([0usize; 3]);
    let failures = Mutex::new(Vec::new());
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= cases {
                        break;
                    }
                    let mut rng = Rng::new(seed.wrapping_mul(1_000_003).wrapping_add(i as u64));
                    let text = if rng.below(10) == 0 {
                        random_recipe(&mut rng)
                    } else {
                        mutate(rng.pick(corpus.as_slice()).as_str(), &mut rng)
                    };
                    if log {
                        eprintln!("fuzz case {i}:\n{text}\n");
                    }
                    let clock = std::time::Instant::now();
                    let mut result = run_case(&text, limit);
                    let seconds = clock.elapsed().as_secs_f64();
                    if result.is_ok() && seconds > ceiling {
                        result = Err(format!(
                            "took {seconds:.1} s, beyond the {ceiling} s a case may take"
                        ));
                    }
                    if log {
                        eprintln!("fuzz case {i} done");
                    }
                    match result {
                        Ok(kind) => {
                            let k = ["refused", "refused later", "built"]
                                .iter()
                                .position(|&x| x == kind)
                                .unwrap();
                            tally.lock().unwrap()[k] += 1;
                        }
                        Err(why) => failures.lock().unwrap().push((i, why, text)),
                    }
                    if cases >= 10_000 && i.is_multiple_of(10_000) {
                        eprintln!("fuzz: case {i} of {cases}");
                    }
                }
            });
        }
    });
    let _ = std::panic::take_hook();
    let tally = tally.into_inner().unwrap();
    let mut failures = failures.into_inner().unwrap();
    failures.sort_by_key(|f| f.0);
    eprintln!(
        "fuzz: {cases} cases (seed {seed}): {} refused when read, {} refused when grown or laid out, {} built, {} failures",
        tally[0],
        tally[1],
        tally[2],
        failures.len()
    );
    if let Some((i, why, text)) = failures.first() {
        let dir = repo().join("target/fuzz-failures");
        let _ = std::fs::create_dir_all(&dir);
        for (i, why, text) in &failures {
            let _ = std::fs::write(
                dir.join(format!("case-{i}.toml")),
                format!("# {why}\n{text}"),
            );
        }
        panic!(
            "{} of {cases} cases failed (all in target/fuzz-failures/); the first, case {i}: {why}\n{text}",
            failures.len()
        );
    }
    // The corpus must reach every stage, or the test proves little.
    assert!(tally.iter().all(|&n| n > 0), "{tally:?}");
}

#[test]
fn the_format_checks_catch_broken_files() {
    let good = [
        ("a.json", "{\"a\": [1, 2]}"),
        (
            "a.svg",
            "<?xml version=\"1.0\"?>\n<svg><title>a &amp; b</title><g><path d=\"M0 0\"/></g></svg>",
        ),
        ("a.dxf", "999\nkarigami: two lines\n0\nEOF"),
        ("a.csv", "id,name\n1,\"a, b\"\n"),
        ("a.obj", "# x\no strip\nv 1 2 3\nf 1 2 3\n"),
    ];
    for (name, text) in good {
        assert_eq!(parses(name, text), Ok(()), "{name}");
    }
    let bad = [
        ("a.json", "{\"a\": [1, 2}"),
        ("a.svg", "<svg><title>a\u{1b}[31m</title></svg>"),
        ("a.svg", "<svg><g></svg>"),
        ("a.dxf", "999\nkarigami: two\nlines\n0\nEOF"),
        ("a.dxf", "10\nx\n0\nEOF"),
        ("a.csv", "id,name\n1,a,b\n"),
        ("a.obj", "v 1 inf 0\n"),
        ("report.txt", "name: esc\u{1b}\n"),
    ];
    for (name, text) in bad {
        assert!(parses(name, text).is_err(), "{name}: {text:?} passed");
    }
}

/// Hostile build folders (issue 36): markers planted in --out or in a
/// staging folder beside it, listing paths outside, a user's files with
/// made-up records, or being a FIFO, a link to /dev/zero or junk; FIFOs
/// among the files; a FIFO as the recipe. No run hangs or panics, and no
/// file of anyone's is lost: each victim is still somewhere under the
/// case's folder (kept aside, perhaps). CI runs `FOLDER_CASES`; the long
/// run `scripts/fuzz` sets `KARIGAMI_FUZZ_FOLDERS`.
#[cfg(unix)]
#[test]
fn planted_markers_and_fifos_never_hang_nor_cost_a_file() {
    let cases: u64 = std::env::var("KARIGAMI_FUZZ_FOLDERS")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(FOLDER_CASES);
    let root = crate::cli::scratch("fuzz-folders");
    let chain = std::fs::read_to_string(repo().join("templates/chain.toml")).unwrap();
    let recipe = chain.replace("rows = 6 ", "rows = 3 ");
    for i in 0..cases {
        let mut rng = Rng::new(0x5eed_f01d + i);
        let case = root.join(format!("case-{i}"));
        std::fs::create_dir_all(case.join("victim")).unwrap();
        std::fs::create_dir_all(case.join("far/empty")).unwrap();
        std::fs::write(case.join("victim/keep.txt"), "victim").unwrap();
        std::fs::write(case.join("a.toml"), &recipe).unwrap();
        let notes = format!("notes of case {i}");
        let (name, args) = planted(&case, &notes, &mut rng);
        let o = timed_run(&case, &args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        let code = o.status.code();
        assert!(
            matches!(code, Some(0 | 2 | 3)),
            "case {i} ({name}): {code:?}: {stderr}"
        );
        assert_eq!(
            std::fs::read(case.join("victim/keep.txt")).ok().as_deref(),
            Some(&b"victim"[..]),
            "case {i} ({name}): {stderr}"
        );
        assert!(case.join("far/empty").is_dir(), "case {i} ({name})");
        assert!(
            holds(&case, notes.as_bytes()),
            "case {i} ({name}): the user's notes are gone: {stderr}"
        );
    }
}

/// Hostile-folder cases in CI (each is one or two runs of the binary).
const FOLDER_CASES: u64 = 12;

/// Plant one hostile shape in `case` (a user's `notes.txt` holding
/// `notes` in the folder planted in); what it is and the run to try.
#[cfg(unix)]
fn planted(case: &std::path::Path, notes: &str, rng: &mut Rng) -> (String, Vec<String>) {
    use std::os::unix::fs::symlink;
    let build = |out: &str| ["build", "a.toml", "--out", out].map(String::from).to_vec();
    if rng.below(8) == 0 {
        mkfifo(&case.join("f.toml"));
        std::fs::write(case.join("notes.txt"), notes).unwrap();
        return (
            "a FIFO as the recipe".into(),
            vec!["check".into(), "f.toml".into()],
        );
    }
    let place = if rng.below(2) == 0 {
        "out"
    } else {
        ".out.karigami-new-4242"
    };
    let dir = case.join(place);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("notes.txt"), notes).unwrap();
    let marker = dir.join(".karigami-build");
    let far = case.join("far/empty/x").display().to_string();
    let victim = case.join("victim/keep.txt").display().to_string();
    let listed = [
        "../victim/keep.txt",
        "notes.txt",
        "../far/empty/x",
        "a/../../victim/keep.txt",
        "report.txt",
        "pipe",
        &far,
        &victim,
    ];
    let shape = rng.below(5);
    let name = match shape {
        0 => {
            mkfifo(&marker);
            "a FIFO marker"
        }
        1 => {
            symlink("/dev/zero", &marker).unwrap();
            "a marker linked to /dev/zero"
        }
        2 => {
            let junk: Vec<u8> = (0..rng.below(4096)).map(|_| rng.next_u64() as u8).collect();
            std::fs::write(
                &marker,
                [b"karigami build folder\n".as_slice(), &junk].concat(),
            )
            .unwrap();
            "a junk marker"
        }
        _ => {
            if shape == 4 {
                mkfifo(&dir.join("pipe"));
            }
            let files: Vec<&str> = (0..1 + rng.below(4)).map(|_| *rng.pick(&listed)).collect();
            let records: Vec<String> = files
                .iter()
                .map(|f| {
                    let len = if rng.below(2) == 0 { notes.len() } else { rng.below(99) };
                    format!(
                        r#"{{"folder":"","inputs":"","files":[["{f}",{len},"{:016x}"]],"report":null}}"#,
                        rng.next_u64()
                    )
                })
                .collect();
            std::fs::write(&marker, crate::safety::planted_marker(&files, &records)).unwrap();
            "a marker listing others' files"
        }
    };
    (format!("{name} in {place}"), build("out"))
}

#[cfg(unix)]
fn mkfifo(path: &std::path::Path) {
    let made = std::process::Command::new("mkfifo").arg(path).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo {}", path.display());
}

/// Run karigami in `dir`, failing the test if it takes over a minute.
fn timed_run(dir: &std::path::Path, args: &[String]) -> std::process::Output {
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_karigami"))
        .args(args)
        .current_dir(dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed().as_secs() > 60 {
            let _ = child.kill();
            panic!("karigami {args:?} hung");
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    child.wait_with_output().unwrap()
}

/// Whether a regular file under `dir` (links not followed) holds `bytes`.
fn holds(dir: &std::path::Path, bytes: &[u8]) -> bool {
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let kind = e.file_type().unwrap();
            if kind.is_dir() {
                stack.push(e.path());
            } else if kind.is_file() && std::fs::read(e.path()).is_ok_and(|b| b == bytes) {
                return true;
            }
        }
    }
    false
}
