//! The recipe's numbers and coordinates, checked: finite, in range, 2-D or 3-D.

use super::raw::{Coords, Num};
use crate::diagnostic::{Diagnostic, ErrorKind, shown};
use glam::DVec3;
use toml::Spanned;

pub(super) fn finite(n: &Num, what: &str) -> Result<f64, Diagnostic> {
    let v = *n.get_ref();
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Diagnostic::new(
            ErrorKind::NotFinite,
            format!("{what} is {v}, not a finite number"),
        )
        .at(n.span())
        .hint("use an ordinary number"))
    }
}

pub(super) fn count(n: &Spanned<i64>, what: &str, min: i64, max: i64) -> Result<usize, Diagnostic> {
    let v = *n.get_ref();
    if (min..=max).contains(&v) {
        Ok(v as usize)
    } else {
        Err(Diagnostic::new(
            ErrorKind::OutOfRange,
            format!("{what} is {v}, but must be at least {min} and at most {max}"),
        )
        .at(n.span())
        .hint(format!("give {what} a whole number from {min} to {max}")))
    }
}

/// A range in words that says which ends are allowed: "at least 0 and
/// less than 180", "more than 0 and at most 100".
pub(super) fn range(low: f64, low_allowed: bool, high: f64, high_allowed: bool) -> String {
    let low = if low_allowed {
        format!("at least {}", shown(low))
    } else {
        format!("more than {}", shown(low))
    };
    if !high.is_finite() {
        return low;
    }
    let high = if high_allowed {
        format!("at most {}", shown(high))
    } else {
        format!("less than {}", shown(high))
    };
    format!("{low} and {high}")
}

/// A point or vector of 2 or 3 finite coordinates.
pub(super) fn coords(c: &Coords, what: &str) -> Result<(DVec3, usize), Diagnostic> {
    let v = c.get_ref();
    if !(2..=3).contains(&v.len()) {
        return Err(Diagnostic::new(
            ErrorKind::WrongCoordinates,
            format!("{what} has {} coordinates", v.len()),
        )
        .at(c.span())
        .hint("give 2 coordinates (a planar lattice) or 3 (a lattice in space)"));
    }
    let mut out = DVec3::ZERO;
    for (k, n) in v.iter().enumerate() {
        out[k] = finite(n, &format!("a coordinate of {what}"))?;
    }
    Ok((out, v.len()))
}

/// One of a few words: its value, or an error at the word naming the
/// choices.
pub(super) fn choice<T: Copy>(
    word: &Spanned<String>,
    what: &str,
    options: &[(&str, T)],
    kind: ErrorKind,
    hint: &str,
) -> Result<T, Diagnostic> {
    let w = word.get_ref().as_str();
    options
        .iter()
        .find(|(name, _)| *name == w)
        .map(|&(_, v)| v)
        .ok_or_else(|| {
            Diagnostic::new(kind, format!("unknown {what} \"{w}\""))
                .at(word.span())
                .hint(hint)
        })
}
