//! Fixed-precision number text for the writers: the same value always
//! prints the same way, with no float noise (0.30000000000000004).

/// `x` to 4 decimals (0.1 micrometre in mm), trailing zeros trimmed.
///
/// The text is `format!("{:.4}")`'s (the exact decimal value rounded), made
/// from the integer `round(x * 10^4)` when that product is far enough from
/// a rounding tie for its own rounding error not to matter, which is nearly
/// always: the writers print millions of numbers and the general formatter
/// was a sixth of a big build.
pub(crate) fn num(x: f64) -> Text {
    if let Some(units) = on_grid(x) {
        return fixed(units);
    }
    let mut s = format!("{x:.4}");
    if s.contains('.') {
        s = s.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    Text::General(if s == "-0" { "0".to_string() } else { s })
}

/// A number's text (`num`, `fixed`), shown with `Display`: on the grid
/// (nearly always) held in place, without the heap allocation a `String`
/// per number cost the writers (half a million numbers in the torus's
/// files).
#[derive(Clone)]
pub(crate) enum Text {
    /// ASCII text in `digits[start..]`.
    Grid { digits: [u8; 24], start: u8 },
    /// The general formatter's text.
    General(String),
}

impl Text {
    pub(crate) fn as_str(&self) -> &str {
        match self {
            Text::Grid { digits, start } => {
                std::str::from_utf8(&digits[*start as usize..]).expect("ASCII digits")
            }
            Text::General(s) => s,
        }
    }
}

impl std::fmt::Display for Text {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl std::fmt::Debug for Text {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        std::fmt::Debug::fmt(self.as_str(), f)
    }
}

impl PartialEq for Text {
    fn eq(&self, other: &Self) -> bool {
        self.as_str() == other.as_str()
    }
}

impl Eq for Text {}

impl std::hash::Hash for Text {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.as_str().hash(h);
    }
}

impl PartialEq<&str> for Text {
    fn eq(&self, other: &&str) -> bool {
        self.as_str() == *other
    }
}

impl PartialEq<String> for Text {
    fn eq(&self, other: &String) -> bool {
        self.as_str() == other
    }
}

/// `units(x)` when `num(x)` prints it as `fixed` of that (nearly always).
pub(crate) fn on_grid(x: f64) -> Option<i64> {
    let scaled = x * 1e4;
    // |scaled| < 2^31: its f64 error is below 2^-22, far inside the margin.
    (scaled.abs() < 2_147_483_648.0 && (scaled - scaled.floor() - 0.5).abs() > 1e-5)
        .then(|| scaled.round() as i64)
}

/// `x` in ten-thousandths, rounded: the grid `num` prints on. Writers that
/// print differences (relative path commands, shapes placed by an offset)
/// take them between grid points, so that the sums readers form land on
/// the grid exactly and no rounding error accumulates along a path.
pub(crate) fn units(x: f64) -> i64 {
    (x * 1e4).round() as i64
}

/// `units` ten-thousandths as decimal text, trailing zeros trimmed.
pub(crate) fn fixed(units: i64) -> Text {
    // Digits laid right to left in place: the writers print millions of
    // numbers, and `to_string` of the whole and fractional parts was three
    // allocations a number.
    let mut buf = [0u8; 24];
    let mut at = buf.len();
    let mut push = |b: u8| {
        at -= 1;
        buf[at] = b;
    };
    let (mut whole, mut frac) = (units.unsigned_abs() / 10_000, units.unsigned_abs() % 10_000);
    if frac > 0 {
        let mut digits = 4;
        while frac % 10 == 0 {
            frac /= 10;
            digits -= 1;
        }
        for _ in 0..digits {
            push(b'0' + (frac % 10) as u8);
            frac /= 10;
        }
        push(b'.');
    }
    loop {
        push(b'0' + (whole % 10) as u8);
        whole /= 10;
        if whole == 0 {
            break;
        }
    }
    if units < 0 {
        push(b'-');
    }
    Text::Grid {
        digits: buf,
        start: at as u8,
    }
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
        assert_eq!(num(-0.05), "-0.05");
        assert_eq!(num(-12.0007), "-12.0007");
        assert_eq!(
            num(1e300),
            format!("{:.4}", 1e300)
                .trim_end_matches('0')
                .trim_end_matches('.')
        );
    }

    /// The general formatter's text, as `num` printed before its fast path.
    fn general(x: f64) -> String {
        let mut s = format!("{x:.4}");
        if s.contains('.') {
            s = s.trim_end_matches('0').trim_end_matches('.').to_string();
        }
        if s == "-0" { "0".to_string() } else { s }
    }

    #[test]
    fn fixed_prints_ten_thousandths() {
        use super::fixed;
        assert_eq!(fixed(0), "0");
        assert_eq!(fixed(-5), "-0.0005");
        assert_eq!(fixed(120_000), "12");
        assert_eq!(fixed(-1_234_500), "-123.45");
        assert_eq!(fixed(i64::MIN), "-922337203685477.5808");
    }

    #[test]
    fn the_fast_path_prints_what_the_general_formatter_prints() {
        let mut rng = crate::rng::Rng::new(0x2545_f491_4f6c_dd1d);
        for i in 0..200_000 {
            let bits = rng.next_u64();
            let x = match i % 4 {
                // Random magnitudes, both signs.
                0 => f64::from_bits(bits) % 1e6,
                // Millimetres as drawings have them.
                1 => (bits >> 11) as f64 / (1u64 << 53) as f64 * 6000.0 - 3000.0,
                // Near rounding ties (x.xxxx5) and whole ten-thousandths.
                2 => ((bits % 20_000_000) as f64 - 1e7) / 1e4 + 0.00005,
                _ => ((bits % 20_000_000) as f64 - 1e7) / 1e4,
            };
            if x.is_finite() {
                assert_eq!(num(x), general(x), "{x:e}");
            }
        }
    }
}
