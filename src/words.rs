//! English for messages and pages, written once.

/// "1 cell", "3 cells": a count with its noun (regular plurals only).
pub fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn one_is_singular_and_every_other_count_plural() {
        assert_eq!(super::plural(1, "strip"), "1 strip");
        assert_eq!(super::plural(0, "file"), "0 files");
        assert_eq!(super::plural(12, "recipe"), "12 recipes");
    }
}
