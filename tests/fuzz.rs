//! Robustness: random and mutated recipes thrown at parsing and the whole
//! pipeline. Never a panic, never NaN or infinity in a file.
//!
//! CI runs `FUZZ_CASES` cases; the long run is `scripts/fuzz 100000`
//! (`KARIGAMI_FUZZ_CASES=N`, optional `KARIGAMI_FUZZ_SEED=S`).

use crate::cli::{recipes, repo};
use crate::util::Rng;
use karigami::build::build;
use karigami::design;
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
            6 if !strings.is_empty() => splice(&s, *rng.pick(&strings), rng.pick::<&str>(STRINGS)),
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
fn run_case(text: &str) -> Result<&'static str, String> {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let design = match design::parse(text, "fuzz") {
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
        for (name, bytes) in built.files() {
            if name.ends_with(".png") || name.ends_with(".pdf") {
                continue;
            }
            let t = String::from_utf8_lossy(&bytes);
            if let Some(bad) = ["NaN", "nan", "inf", "Infinity"]
                .into_iter()
                .find(|bad| words_contain(&t, bad))
            {
                return Err(format!("{name} contains {bad}"));
            }
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
                    let result = run_case(&text);
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
                    if cases >= 10_000 && i % 10_000 == 0 {
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
