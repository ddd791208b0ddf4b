//! Sensitivities of an equilibrium (docs/physics.md, "Sensitivities"). At
//! q*(p), where the free gradient g(q*, p) is 0, dq*/dp = -H^-1 dg/dp with
//! H the free Hessian there, factored once without a shift (a stable
//! equilibrium's H is positive definite). The model's parameters: each
//! edge's rest length (its stretch term), each bend's rest length lbar,
//! and each fixed or tied variable's prescribed value (a tied variable's
//! offset). The other fixed variables do not move: derivatives are in the
//! gauge the anchor sets. dg/dp is exact: a stretch's by
//! `stretch_rest_gradient`, a bend's from E being proportional to 1/lbar,
//! a prescribed value's the Hessian's column (dual numbers).

use crate::model::{Model, Stencil, stretch_rest_gradient};
use crate::solver::{Factor, System};

/// A change of the parameters: (edge, d rest), (bend stencil, d lbar),
/// (fixed or tied variable, d value or d offset).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Direction {
    pub rest: Vec<(usize, f64)>,
    pub lbar: Vec<(usize, f64)>,
    pub fixed: Vec<(usize, f64)>,
}

impl Direction {
    /// Move the model's parameters by `h` times this direction (a finite
    /// step, e.g. for a design loop or a finite-difference check): rest
    /// lengths, bends' lbar, prescribed values and tied variables' offsets.
    pub fn apply(&self, model: &mut Model, h: f64) {
        for &(e, d) in &self.rest {
            model.edges[e].rest += h * d;
        }
        for &(s, d) in &self.lbar {
            if let Stencil::Bend { lbar, .. } = &mut model.stencils[s] {
                *lbar += h * d;
            }
        }
        for &(v, d) in &self.fixed {
            match model.ties.iter_mut().find(|t| t.var == v) {
                Some(t) => t.offset += h * d,
                None if model.fixed[v] => model.q[v] += h * d,
                None => {}
            }
        }
        model.apply_ties();
    }
}

/// The gradient of a scalar objective J(q*(p)) over the parameters: by
/// edge, by stencil (0 but for bends) and by variable (0 but for fixed and
/// tied ones).
#[derive(Clone, Debug, PartialEq)]
pub struct Gradient {
    pub rest: Vec<f64>,
    pub lbar: Vec<f64>,
    pub fixed: Vec<f64>,
}

/// Why a state has no sensitivities.
#[derive(Clone, Debug, PartialEq)]
pub enum AdjointError {
    /// Its Hessian is not positive definite: not a stable equilibrium (or
    /// one with a free mode), where q*(p) has no derivative.
    Indefinite,
}

impl std::fmt::Display for AdjointError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AdjointError::Indefinite => write!(
                f,
                "the Hessian at the equilibrium is not positive definite: no sensitivities"
            ),
        }
    }
}

/// An equilibrium's Hessian factored once, for any number of tangents
/// (one solve per parameter direction) and adjoints (one solve per
/// objective, for every parameter at once).
pub struct Linearisation<'a> {
    sys: &'a System,
    factor: Factor,
    /// The model whose factor the system kept (`System::keep_factor`), to
    /// keep it again on release.
    kept: Option<Model>,
}

impl<'a> Linearisation<'a> {
    /// Factor the Hessian of `model` as it is (an equilibrium), or take
    /// the factor the solver's last `finish` (or the last linearisation)
    /// left of that same state.
    pub fn new(sys: &'a System, model: &Model) -> Result<Self, AdjointError> {
        if let Some((factor, kept)) = sys.take_factor(model) {
            let kept = Some(kept);
            return Ok(Linearisation { sys, factor, kept });
        }
        let (_, g, h) = sys.assemble(model);
        let factor = sys.factor(&h, 0.0);
        sys.recycle(g, h);
        let factor = factor.ok_or(AdjointError::Indefinite)?;
        // Kept on release, as `finish` keeps its own: the next
        // linearisation of this state (an adjoint, then a warm re-solve's
        // tangent from it) takes it instead of factoring again.
        let kept = Some(model.clone());
        Ok(Linearisation { sys, factor, kept })
    }

    /// dq*/dt along `dir` over every variable: free ones by the solve,
    /// fixed ones as `dir` moves them, tied ones by their ties.
    pub fn tangent(&self, model: &Model, dir: &Direction) -> Vec<f64> {
        let sys = self.sys;
        let b = mixed(sys, model, dir);
        let x = sys.solve(&self.factor, &sys.free_gradient(&b));
        let mut dq = vec![0.0; model.q.len()];
        for &(v, d) in &dir.fixed {
            if model.fixed[v] {
                dq[v] += d;
            }
        }
        for (k, &v) in sys.free_vars.iter().enumerate() {
            dq[v] = -x[k];
        }
        for (v, terms) in sys.tied() {
            dq[*v] += terms
                .iter()
                .map(|&(f, c)| c * dq[sys.free_vars[f]])
                .sum::<f64>();
        }
        dq
    }

    /// dJ/dp for an objective J(q) with gradient `dj` over every variable:
    /// one solve for the multiplier lambda = H^-1 dJ/dq, then dJ/dp =
    /// dJ/dp (direct, a prescribed variable's own) - lambda . dg/dp.
    pub fn gradient(&self, model: &Model, dj: &[f64]) -> Gradient {
        let sys = self.sys;
        let lam = self.multiplier(model, dj);
        let mut out = Gradient {
            rest: vec![0.0; model.edges.len()],
            lbar: vec![0.0; model.stencils.len()],
            fixed: (0..model.q.len())
                .map(|v| if model.fixed[v] { dj[v] } else { 0.0 })
                .collect(),
        };
        let (mut g, mut h) = (Vec::new(), Vec::new());
        for (s, st) in model.stencils.iter().enumerate() {
            let vars = sys.vars_of(s);
            let dot = |g: &[f64]| vars.iter().zip(g).map(|(&v, x)| lam[v] * x).sum::<f64>();
            match *st {
                Stencil::Stretch { edge, .. } => {
                    stretch_rest_gradient(model, edge, vars, &mut g, &mut h);
                    out.rest[edge] -= dot(&g);
                }
                Stencil::Bend { lbar, .. } => {
                    let (_, gs, _) = model.stencil_derivatives(st, vars);
                    out.lbar[s] += dot(&gs) / lbar;
                }
                _ => {}
            }
            if vars.iter().any(|&v| model.fixed[v]) {
                let (_, _, hs) = model.stencil_derivatives(st, vars);
                let k = vars.len();
                for (b, &v) in vars.iter().enumerate() {
                    if model.fixed[v] {
                        out.fixed[v] -= (0..k).map(|a| lam[vars[a]] * hs[a * k + b]).sum::<f64>();
                    }
                }
            }
        }
        out
    }

    /// H^-1 dJ/dq over every variable: free ones solved, tied ones by
    /// their ties, fixed ones 0.
    fn multiplier(&self, model: &Model, dj: &[f64]) -> Vec<f64> {
        let sys = self.sys;
        let lf = sys.solve(&self.factor, &sys.free_gradient(dj));
        let mut lam = vec![0.0; model.q.len()];
        for (k, &v) in sys.free_vars.iter().enumerate() {
            lam[v] = lf[k];
        }
        for (v, terms) in sys.tied() {
            lam[*v] = terms.iter().map(|&(f, c)| c * lf[f]).sum();
        }
        lam
    }

    /// Hand the factor's buffer back to the system.
    pub fn release(self) {
        match self.kept {
            Some(model) => self.sys.keep_factor(self.factor, model),
            None => self.sys.release(self.factor),
        }
    }
}

/// dg/dt along `dir`, over every variable (before ties move it onto the
/// free ones).
fn mixed(sys: &System, model: &Model, dir: &Direction) -> Vec<f64> {
    let mut rest = vec![0.0; model.edges.len()];
    for &(e, d) in &dir.rest {
        rest[e] += d;
    }
    let mut lbar = vec![0.0; model.stencils.len()];
    for &(s, d) in &dir.lbar {
        lbar[s] += d;
    }
    let mut moved = vec![0.0; model.q.len()];
    for &(v, d) in &dir.fixed {
        if model.fixed[v] {
            moved[v] += d;
        }
    }
    let mut b = vec![0.0; model.q.len()];
    let (mut g, mut h) = (Vec::new(), Vec::new());
    for (s, st) in model.stencils.iter().enumerate() {
        let vars = sys.vars_of(s);
        let mut add = |g: &[f64], scale: f64| {
            for (&v, x) in vars.iter().zip(g) {
                b[v] += scale * x;
            }
        };
        match *st {
            Stencil::Stretch { edge, .. } if rest[edge] != 0.0 => {
                stretch_rest_gradient(model, edge, vars, &mut g, &mut h);
                add(&g, rest[edge]);
            }
            Stencil::Bend { lbar: l, .. } if lbar[s] != 0.0 => {
                let (_, gs, _) = model.stencil_derivatives(st, vars);
                add(&gs, -lbar[s] / l);
            }
            _ => {}
        }
        if vars.iter().any(|&v| moved[v] != 0.0) {
            let (_, _, hs) = model.stencil_derivatives(st, vars);
            let k = vars.len();
            for (c, &v) in vars.iter().enumerate() {
                if moved[v] != 0.0 {
                    for a in 0..k {
                        b[vars[a]] += hs[a * k + c] * moved[v];
                    }
                }
            }
        }
    }
    b
}
