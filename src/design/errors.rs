//! Suggestions for recipe errors: the known field a misspelt one means.

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
            Some("did you mean `kappa`? (the recipe format is in README.md)")
        );
        // Far from every field: no guess.
        let e = parse("[lattice]\nseed = \"sheet\"\nwobble = 0.0\n", "x").unwrap_err();
        assert_eq!(
            e.hint.as_deref(),
            Some("see the recipe format in README.md")
        );
        assert_eq!(edit_distance("angel", "angle"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
    }
}
