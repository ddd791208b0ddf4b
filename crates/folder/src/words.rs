//! The two small helpers this crate shares with karigami's library
//! (karigami's src/words.rs and src/hash.rs), written again here so that
//! the crate does not depend on it: the same words, the same hash.

/// "1 file", "3 files": a count with its noun (regular plurals only).
pub(crate) fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

/// 64-bit FNV-1a, for the hidden names of names that are not UTF-8: the
/// names an earlier run chose, so the hash must not change.
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_hash_is_fnv1a_and_plurals_are_regular() {
        // FNV-1a's published values for "" and "a".
        assert_eq!(super::fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(super::fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(super::plural(1, "file"), "1 file");
        assert_eq!(super::plural(0, "file"), "0 files");
    }
}
