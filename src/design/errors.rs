//! Recipe errors the TOML reader finds, in the recipe's words: what a key
//! wants ("rows must be a whole number", "[lattice] must be a table")
//! instead of the library's ("expected i64", "expected struct RawLattice"),
//! the key given twice, and the known field a misspelt one means.

use std::ops::Range;

/// The TOML reader's message in the recipe's words, or as it is when it
/// is of no form known here.
pub(super) fn plain(message: &str, source: &str, span: Option<Range<usize>>) -> String {
    let spanned = span
        .as_ref()
        .and_then(|s| source.get(s.clone()))
        .unwrap_or_default();
    if message == "duplicate key" {
        let before = span
            .as_ref()
            .and_then(|s| source.get(..s.start))
            .unwrap_or_default();
        // A header's line starts with `[`: name the whole header, dotted
        // (`[lattice.grow]`, whose span is `grow` alone).
        let line = &before[before.rfind('\n').map_or(0, |i| i + 1)..];
        // Only a table's own header: `[name.` up to the key, no `[[`
        // (an array of tables), no `{` or `=` (an array's line).
        let header = line
            .trim_start()
            .strip_prefix('[')
            .filter(|h| {
                h.chars()
                    .all(|c| c.is_alphanumeric() || " ._-\"'".contains(c))
            })
            .map(|h| format!("{h}{}", spanned.trim()));
        return match (spanned.trim(), header) {
            ("", _) => "a key is given twice".to_string(),
            (_, Some(table)) => {
                let table: String = table.chars().filter(|c| !c.is_whitespace()).collect();
                format!("the table [{table}] is given twice (or its keys were already set)")
            }
            (key, None) => format!("`{key}` is given twice in this table"),
        };
    }
    if let Some(field) = message
        .strip_prefix("missing field `")
        .and_then(|r| r.strip_suffix('`'))
    {
        let table = spanned.trim();
        // The top level's span starts the recipe (a table's starts at its
        // header, an inline table's at its brace).
        let top = span.as_ref().is_none_or(|s| s.start == 0);
        return if table.starts_with('[') && !table.contains('\n') {
            format!("{table} has no `{field}`, which it needs")
        } else if top && field == "lattice" {
            "the recipe has no [lattice] table, which it needs".to_string()
        } else if top {
            format!("the recipe has no `{field}`, which it needs")
        } else {
            format!("this table has no `{field}`, which it needs")
        };
    }
    let typed = message
        .strip_prefix("invalid type: ")
        .or_else(|| message.strip_prefix("invalid value: "));
    let (found, expected) = if let Some(rest) = typed {
        match rest.split_once(", expected ") {
            Some((found, expected)) => (found_words(found, spanned), expected),
            None => return message.to_string(),
        }
    } else if let Some(rest) = message.strip_prefix("invalid length ") {
        match rest.split_once(", expected ") {
            Some((n, expected)) => (format!("an array of {n} values"), expected),
            _ => return message.to_string(),
        }
    } else {
        return message.to_string();
    };
    let (key, direct) = key_of(source, span.map_or(0, |s| s.start));
    if let Some(table) = expected.strip_prefix("struct ") {
        let table = table.split(' ').next().unwrap_or_default();
        let name = table_name(table)
            .map(str::to_string)
            .or(key.map(|k| format!("[{k}]")))
            .unwrap_or_else(|| "this value".to_string());
        return format!("{name} must be a table, not {found}");
    }
    let subject = match key {
        Some(k) if direct => k.to_string(),
        Some(k) => format!("a value in {k}"),
        None => "this value".to_string(),
    };
    format!(
        "{subject} is {found}, but must be {}",
        expected_words(expected)
    )
}

/// What the reader found, from serde's words (`integer `5``, `map`).
fn found_words(found: &str, spanned: &str) -> String {
    let quoted = |prefix: &str| {
        found
            .strip_prefix(prefix)
            .map(|v| v.trim_matches('`').to_string())
    };
    if let Some(v) = quoted("integer ") {
        format!("the whole number {v}")
    } else if let Some(v) = quoted("floating point ") {
        format!("the number {v}")
    } else if let Some(v) = quoted("boolean ") {
        v
    } else if let Some(v) = found.strip_prefix("string ") {
        format!("the text {v}")
    } else if found == "sequence" {
        "an array".to_string()
    } else if found == "map" && looks_like_date(spanned) {
        format!("the date or time {}", spanned.trim())
    } else if found == "map" {
        "a table".to_string()
    } else {
        found.to_string()
    }
}

/// A TOML date or time (`1979-05-27`, `07:32:00`): serde sees a table.
fn looks_like_date(text: &str) -> bool {
    let b = text.trim().as_bytes();
    let digits = |r: Range<usize>| b.get(r).is_some_and(|d| d.iter().all(u8::is_ascii_digit));
    (digits(0..4) && b.get(4) == Some(&b'-')) || (digits(0..2) && b.get(2) == Some(&b':'))
}

/// What a key wants, from serde's words (`i64`, `a sequence`); the
/// recipe's own descriptions (`a leg length in mm or "match"`) as they are.
fn expected_words(expected: &str) -> &str {
    match expected {
        "i64" | "i32" | "u64" | "u32" | "usize" => "a whole number",
        "f64" | "f32" => "a number",
        "a boolean" => "true or false",
        "a string" => "text in quotes",
        "a sequence" => "an array",
        other => other,
    }
}

/// The recipe table a `Raw*` struct reads.
fn table_name(raw: &str) -> Option<&'static str> {
    Some(match raw {
        "RawLattice" => "[lattice]",
        "RawRow" => "[lattice.grow] or a [[lattice.rows]] entry",
        "RawMaterial" => "[material]",
        "RawEyelet" => "[eyelet]",
        "RawStrip" => "[strip]",
        "RawLaser" => "[laser]",
        "RawMachine" => "[machine]",
        "RawSheet" => "[sheet]",
        "RawGuide" => "[guide]",
        "RawClash" => "[clash]",
        "RawOptimise" => "[optimise]",
        "RawSimulation" => "[simulation]",
        "RawFit" => "[lattice.fit]",
        "RawLine" => "lattice.line",
        "RawArc" => "lattice.arc",
        "RawCircle" => "lattice.circle",
        "RawPolyline" => "lattice.polyline",
        "RawFront" => "a row's front",
        "RawPivot" => "a front's pivot",
        "RawCrank" => "a front's crank",
        "RawWeights" => "[optimise.objective]",
        "RawTarget" => "[optimise.target]",
        "RawRequire" => "[optimise.require]",
        _ => return None,
    })
}

/// The key whose value holds byte `at`: the last `key =` before it on its
/// line, and whether the value at `at` is that key's whole value (not an
/// element of an array or inline table).
fn key_of(source: &str, at: usize) -> (Option<&str>, bool) {
    let at = at.min(source.len());
    let Some(before) = source.get(..at) else {
        return (None, false);
    };
    let line = &before[before.rfind('\n').map_or(0, |i| i + 1)..];
    let Some(eq) = line.rfind('=') else {
        return (None, false);
    };
    let key = line[..eq]
        .rsplit(['{', ',', '['])
        .next()
        .unwrap_or_default()
        .trim()
        .trim_matches('"');
    let direct = line[eq + 1..].trim().is_empty();
    ((!key.is_empty()).then_some(key), direct)
}

/// For serde's "unknown field `x`, expected one of `a`, `b`": the expected
/// field nearest `x`, if it is a likely typo (at most 2 edits).
pub(super) fn did_you_mean(message: &str) -> Option<&str> {
    let rest = message.strip_prefix("unknown field `")?;
    let (field, rest) = rest.split_once('`')?;
    let expected = rest.split_once("expected")?.1;
    expected
        .split('`')
        .skip(1)
        .step_by(2)
        .map(|c| (edit_distance(field, c), c))
        .filter(|&(d, _)| d <= 2)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

/// Levenshtein distance (short field names only).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let here = (prev + usize::from(ca != cb))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            prev = row[j + 1];
            row[j + 1] = here;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::parse;

    #[test]
    fn unknown_fields_suggest_the_nearest_known_one() {
        let e = parse("[lattice]\nseed = \"sheet\"\nkapa = 0.0\n", "x").unwrap_err();
        assert_eq!(
            e.hint.as_deref(),
            Some("did you mean `kappa`? (the recipe format is in docs/recipe.md)")
        );
        // Far from every field: no guess.
        let e = parse("[lattice]\nseed = \"sheet\"\nwobble = 0.0\n", "x").unwrap_err();
        assert_eq!(
            e.hint.as_deref(),
            Some("see the recipe format in docs/recipe.md")
        );
        assert_eq!(edit_distance("angel", "angle"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
    }

    #[test]
    fn type_errors_say_what_the_key_wants() {
        let said = |src: &str| parse(src, "x").unwrap_err().message;
        assert_eq!(
            said("lattice = 5\n"),
            "[lattice] must be a table, not the whole number 5"
        );
        assert_eq!(
            said("lattice = []\n"),
            "[lattice] must be a table, not an array of 0 values"
        );
        assert_eq!(
            said("[lattice]\nseed = \"sheet\"\npoints = [[0.0, 1979-05-27]]\n"),
            "a value in points is the date or time 1979-05-27, but must be a number"
        );
        assert_eq!(
            said("[lattice]\nseed = \"sheet\"\n[lattice.grow]\nrows = 6.5\n"),
            "rows is the number 6.5, but must be a whole number"
        );
        assert_eq!(
            said("[lattice]\nseed = \"sheet\"\n[laser]\ncompensate = \"yes\"\n"),
            "compensate is the text \"yes\", but must be true or false"
        );
        assert_eq!(
            said("lattice = { seed = \"sheet\", seed = \"loop\" }\n"),
            "`seed` is given twice in this table"
        );
        assert_eq!(
            said("[lattice]\nseed = \"sheet\"\n[lattice]\n"),
            "the table [lattice] is given twice (or its keys were already set)"
        );
        assert_eq!(
            said("[lattice]\nseed = \"sheet\"\n[lattice.grow]\nrows = 1\n[ lattice. grow ]\n"),
            "the table [lattice.grow] is given twice (or its keys were already set)"
        );
        assert_eq!(
            said("[lattice]\nseed = \"sheet\"\n[lattice.grow]\nrows = [\n[{row = 1, row = 2}]]\n"),
            "`row` is given twice in this table"
        );
        assert_eq!(
            said("[lattice]\nseed = \"sheet\"\n[lattice.grow]\nleft_leg = \"matchx\"\n"),
            "left_leg is the text \"matchx\", but must be a leg length in mm or \"match\""
        );
        assert_eq!(
            said("[lattice]\nseed = \"sheet\"\n[lattice.grow]\nangle = [40.0, 30.0, 1.0]\n"),
            "angle is an array of 3 values, but must be an angle in degrees, or [angle, tilt] in degrees for 3-D"
        );
        assert_eq!(
            said("name = \"x\"\n"),
            "the recipe has no [lattice] table, which it needs"
        );
        // Syntax errors are the reader's own words.
        assert_eq!(
            said("name = \"x\"\n[lattice]\nkappa = 0.0\n"),
            "[lattice] has no `seed`, which it needs"
        );
        let m = "unclosed table, expected `]`";
        assert_eq!(plain(m, "[lattice\n", Some(0..1)), m);
    }
}
