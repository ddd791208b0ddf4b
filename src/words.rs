//! English for messages and pages, and the quoted strings of the recipes
//! karigami writes, written once.

/// "1 cell", "3 cells", "2 seed searches": a count with its noun
/// (regular plurals only: -es after s, x, ch and sh).
pub fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else if ["s", "x", "ch", "sh"].iter().any(|e| what.ends_with(e)) {
        format!("{n} {what}es")
    } else {
        format!("{n} {what}s")
    }
}

/// A TOML basic string (the recipes `new` and `design` write).
pub(crate) fn toml_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn one_is_singular_and_every_other_count_plural() {
        assert_eq!(super::plural(1, "strip"), "1 strip");
        assert_eq!(super::plural(0, "file"), "0 files");
        assert_eq!(super::plural(12, "recipe"), "12 recipes");
        assert_eq!(super::plural(2, "seed search"), "2 seed searches");
    }
}
