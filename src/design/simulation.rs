//! `[simulation]`: the strip material's moduli and allowable strain, the
//! deployment angle, the joint model and the mesh of the elastic
//! simulation (docs/physics.md). Every field is optional; defaults are the
//! `[material] preset`'s, ABS without one.

use super::raw::RawSimulation;
use super::settings::{Actuation, Settings, VertexJoint};
use crate::diagnostic::{Diagnostic, ErrorKind, shown};
use crate::fabrication::StockPreset;
use toml::Spanned;

/// The softest strip stock karigami simulates (MPa): soft rubbers are
/// about 1 MPa, plastics and wood 1,000 MPa and more. Below it a strip's
/// stiffness underflows next to the solver's tolerances and a stable
/// design reads as unstable (`youngs_modulus = 1e-300` gave energy 0 and
/// "lowest eigenvalue 0 (NOT stable)"); examples/eggbox.toml at 1 MPa and
/// the thinnest stock (`MIN_THICKNESS`) still solves, stable.
pub(crate) const MIN_YOUNGS: f64 = 1.0;
/// The smallest opening simulated (degrees): nearer the collapsed bundle
/// Newton stalls (`theta = 1e-300` on templates/chain.toml and
/// examples/eggbox.toml: "no decrease after 30 halvings"); both solve,
/// stable, at 0.1.
pub const MIN_THETA: f64 = 0.1;
/// The opening simulated is less than this (degrees): a cell opened flat.
pub const MAX_THETA: f64 = 180.0;
/// The stiffest: above diamond (about 1.05e6 MPa).
pub(crate) const MAX_YOUNGS: f64 = 1e6;

/// A `[simulation]` number within `low` to `high`, each end allowed or
/// not as `range` says it.
fn number(
    v: &Option<Spanned<f64>>,
    what: &str,
    (low, low_allowed): (f64, bool),
    (high, high_allowed): (f64, bool),
    unit: &str,
    hint: &str,
) -> Result<Option<f64>, Diagnostic> {
    let Some(x) = v else { return Ok(None) };
    let value = *x.get_ref();
    let above = if low_allowed {
        value >= low
    } else {
        value > low
    };
    let below = if high_allowed {
        value <= high
    } else {
        value < high
    };
    if above && below {
        return Ok(Some(value));
    }
    let bound = super::values::range(low, low_allowed, high, high_allowed);
    Err(Diagnostic::new(
        ErrorKind::SimulationOutOfRange,
        format!(
            "[simulation] {what} is {}, but must be {bound}{unit}",
            shown(value)
        ),
    )
    .at(x.span())
    .hint(format!(
        "{hint}see the [simulation] table in docs/recipe.md"
    )))
}

/// The settings of a recipe's `[simulation]` table (defaults without one):
/// the stock preset's modulus, Poisson's ratio and allowable strain, which
/// the table's own values replace (ABS without a preset).
pub(crate) fn parse(
    raw: Option<&Spanned<RawSimulation>>,
    stock: Option<&StockPreset>,
) -> Result<Settings, Diagnostic> {
    let mut s = Settings::default();
    if let Some(p) = stock {
        s.material.youngs = p.youngs;
        s.material.poisson = p.poisson;
        s.material.eps_allow = p.allowable_strain;
    }
    let Some(raw) = raw else { return Ok(s) };
    let r = raw.get_ref();
    if let Some(e) = number(
        &r.youngs_modulus,
        "youngs_modulus",
        (MIN_YOUNGS, true),
        (MAX_YOUNGS, false),
        " (MPa)",
        "1 MPa is soft rubber, ABS is about 2000, steel 210000; ",
    )? {
        s.material.youngs = e;
    }
    if let Some(nu) = number(
        &r.poisson_ratio,
        "poisson_ratio",
        (0.0, true),
        (0.5, false),
        "",
        "",
    )? {
        s.material.poisson = nu;
    }
    if let Some(eps) = number(
        &r.allowable_strain,
        "allowable_strain",
        (0.0, false),
        (100.0, true),
        " (percent)",
        "",
    )? {
        s.material.eps_allow = eps / 100.0;
    }
    if let Some(t) = number(
        &r.theta,
        "theta",
        (MIN_THETA, true),
        (MAX_THETA, false),
        " (degrees)",
        "",
    )? {
        s.theta = Some(t.to_radians());
    }
    if let Some(h) = number(
        &r.edge_length,
        "edge_length",
        (0.5, true),
        (1000.0, true),
        " (mm)",
        "",
    )? {
        s.h_max = h;
    }
    if let Some(n) = &r.symmetry {
        let v = *n.get_ref();
        if !(1..=1000).contains(&v) {
            return Err(Diagnostic::new(
                ErrorKind::SimulationOutOfRange,
                format!("[simulation] symmetry is {v}, but must be a whole number, at least 1 and at most 1000"),
            )
            .at(n.span())
            .hint("symmetry is how many identical copies of its cells a loop lattice has around the loop (1: none); see docs/physics.md"));
        }
        s.symmetry = v as u32;
    }
    if let Some(a) = &r.accept_overstrain {
        s.accept_overstrain = *a.get_ref();
    }
    if let Some(a) = &r.actuation {
        s.actuation = super::choice(
            a,
            "actuation",
            &[
                ("mean", Actuation::Mean),
                ("first-cell", Actuation::FirstCell),
            ],
            ErrorKind::SimulationOutOfRange,
            "actuation must be \"mean\" (the mean opening of all cells is held) or \"first-cell\" (the first cell's opening is held)",
        )?;
    }
    if let Some(j) = &r.vertex_joint {
        s.vertex_joint = super::choice(
            j,
            "vertex_joint",
            &[("eyelet", VertexJoint::Eyelet), ("ball", VertexJoint::Ball)],
            ErrorKind::UnknownVertexJoint,
            "vertex_joint must be \"eyelet\" (strips stacked on one eyelet) or \"ball\" (position only)",
        )?;
    }
    Ok(s)
}
