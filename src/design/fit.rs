//! Target fitting (MATH.md 6.4): rows found by a search so that the lattice
//! approximates a target surface.

use super::Design;
use crate::lattice::{GrowthError, Kind, Lattice};

#[derive(Clone, Debug, PartialEq)]
pub struct Fit {}

pub fn parse(
    f: &toml::Spanned<super::raw::RawFit>,
    kind: Kind,
    dim: usize,
) -> Result<Fit, crate::diagnostic::Diagnostic> {
    let _ = (f, kind, dim);
    Ok(Fit {})
}

pub fn grow(
    design: &Design,
    fit: &Fit,
    progress: &mut dyn FnMut(&str),
) -> Result<(Lattice, f64), GrowthError> {
    let _ = (design, fit, progress);
    unimplemented!()
}
