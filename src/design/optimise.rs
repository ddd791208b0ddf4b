//! The recipe's `[clash]` and `[optimise]` tables: how close strips may
//! come, and what the design optimiser (`crate::solve`) varies, which
//! weighted objectives it minimises and which hard constraints a design
//! must meet.
//!
//! ```toml
//! [optimise]
//! vary = ["angle", "front"]   # row angles, front-move angles and saddle amplitudes, or "seed" (helix, disk)
//! method = "nelder-mead"      # or "evolution" (a seeded population search)
//! budget = 400                # Nelder-Mead iterations, or generations
//! seed = 1                    # how the start simplex is laid out
//! step = 3.0                  # start simplex size (degrees; 2 % of a length)
//! [optimise.objective]        # weights of the objectives
//! curvature = 1.0
//! [optimise.target]           # what `curvature` aims at
//! defect = -4.0               # degrees at every interior vertex, or
//! pattern = "checkerboard"    # +defect and -defect alternating
//! shape = "simulated"         # measured on the simulated deployed shape
//!                             # (docs/physics.md), not the design
//! [optimise.require]          # hard constraints
//! negative = 0.9
//! ```

use super::raw::{Num, RawClash, RawOptimise};
use crate::diagnostic::{Diagnostic, ErrorKind};
use std::ops::Range;
use toml::Spanned;

/// How close strips of one layer may come, and whether a clash is allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct ClashRule {
    /// The smallest gap (mm) between strips of one layer.
    pub clearance: f64,
    pub(crate) allow: bool,
    /// Which neighbours alternate their layers (`stacking`).
    pub(crate) stacking: crate::lattice::Stacking,
    /// `[clash]`, or the lattice table when there is none.
    pub(crate) span: Option<Range<usize>>,
}

impl Default for ClashRule {
    fn default() -> Self {
        Self {
            clearance: crate::fabrication::DEFAULT_CLEARANCE,
            allow: false,
            stacking: crate::lattice::Stacking::Rows,
            span: None,
        }
    }
}

/// Which recipe numbers the optimiser moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Vary {
    /// Every row table's leg `angle` (and tilt in 3-D).
    Angle,
    /// Every angle of the rows' front moves.
    Front,
    /// A helix's seed points and kappa (the seed condition kept).
    Seed,
    /// A fit's row angles (`fit.angles`) or ring steps (`fit.steps`).
    Fit,
}

/// How the optimiser searches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Method {
    /// The Nelder-Mead simplex (`solve::simplex`), restarted about the best point.
    NelderMead,
    /// A seeded (mu/mu_w, lambda) evolution strategy: a population about a
    /// moving mean, for rugged costs with many local minima (a helix seed).
    Evolution,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Pattern {
    /// The same defect at every interior vertex.
    Constant,
    /// +defect and -defect alternating along rows and columns.
    Checkerboard,
}

/// Objective weights (0: not an objective).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Weights {
    pub(crate) surface: f64,
    pub(crate) boundary: f64,
    pub(crate) coverage: f64,
    pub(crate) regularity: f64,
    pub(crate) legs: f64,
    pub(crate) clashes: f64,
    pub(crate) curvature: f64,
    /// Helix: a bowl. Turns round (within 12 %), each narrower and lower,
    /// vertices near one sphere, every interior defect clearly positive.
    pub(crate) rings: f64,
    /// Intrinsic rows: how far rebuilt fronts miss their rows.
    pub(crate) bending: f64,
}

/// A hard constraint: the measure it bounds, the bound, and where it was written.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Requirement {
    pub(crate) name: &'static str,
    pub(crate) bound: f64,
    pub(crate) span: Range<usize>,
}

/// A validated `[optimise]` table: what the optimiser varies, how it
/// searches, and what it aims for.
#[derive(Clone, Debug, PartialEq)]
pub struct Optimise {
    pub(crate) vary: Vec<Vary>,
    pub(crate) method: Method,
    pub(crate) budget: usize,
    pub(crate) seed: u64,
    pub(crate) step: f64,
    pub(crate) weights: Weights,
    pub(crate) defect_deg: f64,
    pub(crate) pattern: Pattern,
    /// Whether the curvature objective measures the simulated deployed
    /// shape (`target.shape = "simulated"`) instead of the design.
    pub(crate) simulated: bool,
    pub(crate) require: Vec<Requirement>,
    pub(crate) span: Range<usize>,
}

pub(crate) fn parse_clash(raw: Option<&Spanned<RawClash>>) -> Result<ClashRule, Diagnostic> {
    let Some(raw) = raw else {
        return Ok(ClashRule::default());
    };
    let r = raw.get_ref();
    let clearance = match &r.clearance {
        Some(c) => {
            let v = super::finite(c, "clash.clearance")?;
            if v < 0.0 {
                return Err(Diagnostic::new(
                    ErrorKind::NegativeClearance,
                    "clash.clearance must not be negative",
                )
                .at(c.span())
                .hint("the gap in mm wanted between neighbouring strips of one layer"));
            }
            v
        }
        None => crate::fabrication::DEFAULT_CLEARANCE,
    };
    let stacking = match r
        .stacking
        .as_ref()
        .map(|s| (s.get_ref().as_str(), s.span()))
    {
        None | Some(("rows", _)) => crate::lattice::Stacking::Rows,
        Some(("columns", _)) => crate::lattice::Stacking::Columns,
        Some((other, span)) => {
            return Err(Diagnostic::new(
                ErrorKind::UnknownStacking,
                format!("clash.stacking is \"{other}\""),
            )
            .at(span)
            .hint("stacking = \"rows\" (neighbouring rows alternate layers) or \"columns\" (neighbouring columns of an even loop)"));
        }
    };
    Ok(ClashRule {
        clearance,
        stacking,
        allow: r.allow.as_ref().is_some_and(|a| *a.get_ref()),
        span: Some(raw.span()),
    })
}

pub(crate) fn parse(raw: &Spanned<RawOptimise>) -> Result<Optimise, Diagnostic> {
    let r = raw.get_ref();
    let vary = vary(r)?;
    let method = method(r)?;
    let budget = match &r.budget {
        Some(b) => super::count(b, "optimise.budget", 1, 100_000)?,
        None => 300,
    };
    let seed = match &r.seed {
        Some(s) => super::count(s, "optimise.seed", 0, i64::MAX)? as u64,
        None => 1,
    };
    let step = match &r.step {
        Some(s) => {
            let v = super::finite(s, "optimise.step")?;
            if v <= 0.0 {
                return Err(Diagnostic::new(
                    ErrorKind::NonPositiveStep,
                    "optimise.step must be positive",
                )
                .at(s.span()));
            }
            v
        }
        None => 3.0,
    };
    let weights = weights(r)?;
    let (defect_deg, pattern, simulated) = target(r)?;
    let require = require(r)?;
    if simulated && weights.curvature == 0.0 {
        let span = r
            .target
            .as_ref()
            .and_then(|t| t.get_ref().shape.as_ref())
            .map(|s| s.span());
        return Err(Diagnostic::new(
            ErrorKind::TargetShapeUnused,
            "target.shape = \"simulated\" measures the curvature objective, but its weight is 0",
        )
        .at_opt(span)
        .hint("give [optimise.objective] a curvature weight, or drop shape"));
    }
    Ok(Optimise {
        vary,
        method,
        budget,
        seed,
        step,
        weights,
        defect_deg,
        pattern,
        simulated,
        require,
        span: raw.span(),
    })
}

/// `optimise.vary`: each word once, in the order first written.
fn vary(r: &RawOptimise) -> Result<Vec<Vary>, Diagnostic> {
    let mut vary = Vec::new();
    for v in r.vary.get_ref() {
        let which = match v.get_ref().as_str() {
            "angle" => Vary::Angle,
            "front" => Vary::Front,
            "seed" => Vary::Seed,
            "fit" => Vary::Fit,
            other => {
                return Err(Diagnostic::new(ErrorKind::UnknownVary, format!("optimise.vary has \"{other}\""))
                    .at(v.span())
                    .hint("vary \"angle\" (row leg angles), \"front\" (front-move angles and saddle amplitudes), \"seed\" (a helix's seed, or a disk's seed on its circle) or \"fit\" (a fit's row angles or ring steps)"));
            }
        };
        if !vary.contains(&which) {
            vary.push(which);
        }
    }
    if vary.is_empty() {
        return Err(
            Diagnostic::new(ErrorKind::EmptyVary, "optimise.vary is empty")
                .at(r.vary.span())
                .hint("say what the optimiser may change: [\"angle\"], [\"front\"] or [\"seed\"]"),
        );
    }
    Ok(vary)
}

fn method(r: &RawOptimise) -> Result<Method, Diagnostic> {
    Ok(match &r.method {
        None => Method::NelderMead,
        Some(m) => match m.get_ref().as_str() {
            "nelder-mead" => Method::NelderMead,
            "evolution" => Method::Evolution,
            other => {
                return Err(Diagnostic::new(
                    ErrorKind::UnknownOptimiseMethod,
                    format!("optimise.method is \"{other}\""),
                )
                .at(m.span())
                .hint("method is \"nelder-mead\" (default) or \"evolution\""));
            }
        },
    })
}

/// `[optimise.objective]`: a weight left out is 0, not an objective.
fn weights(r: &RawOptimise) -> Result<Weights, Diagnostic> {
    let weight = |n: Option<&Num>, what: &str| -> Result<f64, Diagnostic> {
        match n {
            None => Ok(0.0),
            Some(n) => {
                let v = super::finite(n, what)?;
                if v < 0.0 {
                    return Err(Diagnostic::new(
                        ErrorKind::OptimiseNegative,
                        format!("{what} must not be negative"),
                    )
                    .at(n.span())
                    .hint("a weight is 0 (ignored) or more"));
                }
                Ok(v)
            }
        }
    };
    Ok(match r.objective.as_ref().map(|o| o.get_ref()) {
        None => Weights::default(),
        Some(w) => Weights {
            surface: weight(w.surface.as_ref(), "objective.surface")?,
            boundary: weight(w.boundary.as_ref(), "objective.boundary")?,
            coverage: weight(w.coverage.as_ref(), "objective.coverage")?,
            regularity: weight(w.regularity.as_ref(), "objective.regularity")?,
            legs: weight(w.legs.as_ref(), "objective.legs")?,
            clashes: weight(w.clashes.as_ref(), "objective.clashes")?,
            curvature: weight(w.curvature.as_ref(), "objective.curvature")?,
            rings: weight(w.rings.as_ref(), "objective.rings")?,
            bending: weight(w.bending.as_ref(), "objective.bending")?,
        },
    })
}

/// `[optimise.target]`: the defect (degrees) the curvature objective aims
/// at, its pattern, and whether it measures the simulated shape.
fn target(r: &RawOptimise) -> Result<(f64, Pattern, bool), Diagnostic> {
    let (mut defect_deg, mut pattern, mut simulated) = (0.0, Pattern::Constant, false);
    if let Some(t) = &r.target {
        let t = t.get_ref();
        if let Some(s) = &t.shape {
            simulated = super::choice(
                s,
                "target shape",
                &[("design", false), ("simulated", true)],
                ErrorKind::UnknownTargetShape,
                "shape is \"design\" (the cells as cut) or \"simulated\" (the shape the strips take, docs/physics.md)",
            )?;
        }
        if let Some(d) = &t.defect {
            defect_deg = super::finite(d, "target.defect")?;
        }
        if let Some(p) = &t.pattern {
            pattern = super::choice(
                p,
                "curvature pattern",
                &[
                    ("constant", Pattern::Constant),
                    ("checkerboard", Pattern::Checkerboard),
                ],
                ErrorKind::UnknownCurvaturePattern,
                "pattern is \"constant\" or \"checkerboard\"",
            )?;
        }
    }
    Ok((defect_deg, pattern, simulated))
}

/// `[optimise.require]`: the hard constraints, in this fixed order.
fn require(r: &RawOptimise) -> Result<Vec<Requirement>, Diagnostic> {
    let mut require = Vec::new();
    if let Some(q) = &r.require {
        let q = q.get_ref();
        for (name, n) in [
            ("max_distance", &q.max_distance),
            ("max_boundary_distance", &q.max_boundary_distance),
            ("min_coverage", &q.min_coverage),
            ("max_area_ratio", &q.max_area_ratio),
            ("min_positive", &q.min_positive),
            ("min_negative", &q.min_negative),
            ("max_mean_defect", &q.max_mean_defect),
            ("min_mean_defect", &q.min_mean_defect),
            ("max_k_spread", &q.max_k_spread),
            ("max_front_gap", &q.max_front_gap),
            ("max_turn_spread", &q.max_turn_spread),
            ("max_clashes", &q.max_clashes),
            ("min_bumps", &q.min_bumps),
            ("min_leg", &q.min_leg),
            ("min_dimples", &q.min_dimples),
        ] {
            if let Some(n) = n {
                require.push(Requirement {
                    name,
                    bound: super::finite(n, &format!("require.{name}"))?,
                    span: n.span(),
                });
            }
        }
    }
    Ok(require)
}
