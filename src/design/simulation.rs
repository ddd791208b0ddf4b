//! `[simulation]`: the strip material's moduli and allowable strain, the
//! deployment angle, the joint model and the mesh of the elastic
//! simulation (docs/physics.md). Every field is optional; defaults are ABS.

use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::sim::{Actuation, Settings, VertexJoint};
use serde::Deserialize;
use toml::Spanned;

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSimulation {
    /// Young's modulus (MPa).
    pub(crate) youngs_modulus: Option<Spanned<f64>>,
    pub(crate) poisson_ratio: Option<Spanned<f64>>,
    /// Allowable corner-fibre strain, in percent.
    pub(crate) allowable_strain: Option<Spanned<f64>>,
    /// Build even when a strip is strained beyond the allowable.
    pub(crate) accept_overstrain: Option<Spanned<bool>>,
    /// Opening of the reference cell (degrees).
    pub(crate) theta: Option<Spanned<f64>>,
    /// "eyelet" or "ball".
    pub(crate) vertex_joint: Option<Spanned<String>>,
    /// "mean" (mean opening of all cells) or "first-cell".
    pub(crate) actuation: Option<Spanned<String>>,
    /// Longest rod edge (mm).
    pub(crate) edge_length: Option<Spanned<f64>>,
    /// Identical copies of a loop lattice's cells around the loop.
    pub(crate) symmetry: Option<Spanned<i64>>,
}

fn number(
    v: &Option<Spanned<f64>>,
    what: &str,
    ok: impl Fn(f64) -> bool,
    bound: &str,
) -> Result<Option<f64>, Diagnostic> {
    match v {
        Some(x) if !ok(*x.get_ref()) => Err(Diagnostic::new(
            ErrorKind::SimulationOutOfRange,
            format!(
                "[simulation] {what} is {}, but must be {bound}",
                x.get_ref()
            ),
        )
        .at(x.span())
        .hint("see the [simulation] table in README.md")),
        Some(x) => Ok(Some(*x.get_ref())),
        None => Ok(None),
    }
}

/// The settings of a recipe's `[simulation]` table (defaults without one).
pub(crate) fn parse(raw: Option<&Spanned<RawSimulation>>) -> Result<Settings, Diagnostic> {
    let mut s = Settings::default();
    let Some(raw) = raw else { return Ok(s) };
    let r = raw.get_ref();
    if let Some(e) = number(
        &r.youngs_modulus,
        "youngs_modulus",
        |x| x > 0.0 && x < 1e6,
        "between 0 and 1e6 MPa",
    )? {
        s.material.youngs = e;
    }
    if let Some(nu) = number(
        &r.poisson_ratio,
        "poisson_ratio",
        |x| (0.0..0.5).contains(&x),
        "at least 0 and below 0.5",
    )? {
        s.material.poisson = nu;
    }
    if let Some(eps) = number(
        &r.allowable_strain,
        "allowable_strain",
        |x| x > 0.0 && x <= 100.0,
        "above 0 and at most 100 (percent)",
    )? {
        s.material.eps_allow = eps / 100.0;
    }
    if let Some(t) = number(
        &r.theta,
        "theta",
        |x| x > 0.0 && x < 180.0,
        "between 0 and 180 (degrees)",
    )? {
        s.theta = Some(t.to_radians());
    }
    if let Some(h) = number(
        &r.edge_length,
        "edge_length",
        |x| (0.5..=1000.0).contains(&x),
        "between 0.5 and 1000 mm",
    )? {
        s.h_max = h;
    }
    if let Some(n) = &r.symmetry {
        let v = *n.get_ref();
        if !(1..=1000).contains(&v) {
            return Err(Diagnostic::new(
                ErrorKind::SimulationOutOfRange,
                format!("[simulation] symmetry is {v}, but must be a whole number from 1 to 1000"),
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
