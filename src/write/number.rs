//! Fixed-precision number text for the writers: the same value always
//! prints the same way, with no float noise (0.30000000000000004).

/// `x` to 4 decimals (0.1 micrometre in mm), trailing zeros trimmed.
pub fn num(x: f64) -> String {
    let mut s = format!("{:.4}", x);
    if s.contains('.') {
        s = s.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    if s == "-0" { "0".to_string() } else { s }
}

#[cfg(test)]
mod tests {
    use super::num;

    #[test]
    fn trims_and_rounds() {
        assert_eq!(num(0.1 + 0.2), "0.3");
        assert_eq!(num(600.0), "600");
        assert_eq!(num(-0.00001), "0");
        assert_eq!(num(1.23456), "1.2346");
    }
}
