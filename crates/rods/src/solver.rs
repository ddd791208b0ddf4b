//! Modified Newton (docs/physics.md, "Solver"): sparse Hessian with a pattern fixed per
//! model (one symbolic Cholesky), inertia correction by a multiple of a
//! diagonal metric, a negative-curvature step to leave saddles, and a
//! one-step watchdog line search. The factorisation is a simplicial sparse
//! LLT: its ordering and pattern from `sparse`, its numeric part an
//! up-looking factorisation here (`Numeric`), whose refusal of an
//! indefinite matrix is the inertia test.

use crate::model::{Memo, Model, VarKind};
use crate::sparse::{Pattern, amd_order, factor_pattern};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

const NONE: u32 = u32::MAX;

/// The solver's work since the process started, over every model and
/// thread: Hessian assemblies and factorisations, and how many of those
/// found the shifted Hessian indefinite. For benchmarks (`counts`).
static ASSEMBLIES: AtomicUsize = AtomicUsize::new(0);
static FACTORISATIONS: AtomicUsize = AtomicUsize::new(0);
static FAILED: AtomicUsize = AtomicUsize::new(0);

/// The solver's work so far in this process (`ASSEMBLIES`).
#[derive(Clone, Copy, Debug)]
pub struct Counts {
    pub assemblies: usize,
    pub factorisations: usize,
    /// Factorisations that stopped at a pivot that was not positive.
    pub failed: usize,
}

impl Counts {
    /// The work done since `earlier`.
    pub fn since(self, earlier: Counts) -> Counts {
        Counts {
            assemblies: self.assemblies - earlier.assemblies,
            factorisations: self.factorisations - earlier.factorisations,
            failed: self.failed - earlier.failed,
        }
    }
}

/// The solver's work so far in this process, counted on every thread.
pub fn counts() -> Counts {
    Counts {
        assemblies: ASSEMBLIES.load(Relaxed),
        factorisations: FACTORISATIONS.load(Relaxed),
        failed: FAILED.load(Relaxed),
    }
}

/// The free variables and the Hessian's lower-triangle pattern.
pub struct System {
    /// Free index of each variable, or usize::MAX when fixed.
    pub free_index: Vec<usize>,
    pub free_vars: Vec<usize>,
    /// Tied variables (`Model::ties`): (variable, [(free index, coef)]).
    tied: Vec<(usize, Vec<(usize, f64)>)>,
    stencil_vars: Vec<Vec<usize>>,
    /// For each stencil, its local variables expanded over free ones:
    /// (local index, coefficient); a tied variable gives one entry per
    /// free term, a fixed one none.
    stencil_entries: Vec<Vec<(u32, f64)>>,
    /// For each stencil, the value slot of each entry pair (p, q) whose
    /// free row >= free column, else NONE.
    stencil_pos: Vec<Vec<u32>>,
    /// Whether a stencil's entries are its local variables in order, each
    /// with coefficient 1 and their free indices increasing (a fixed
    /// variable has no entry; one tied to another with coefficient 1 keeps
    /// it plain only if its free index keeps the order): then its slots
    /// are those of its local Hessian's lower triangle, the only part of it
    /// computed.
    stencil_plain: Vec<bool>,
    pattern: Pattern,
    /// The Cholesky factor's structure, analysed once (`factor_structure`):
    /// the fill-reducing order, perm[new] = old free index, and the
    /// simplicial symbolic factor of the Hessian's upper triangle in that
    /// order (kept in `numeric`, which reads the Hessian's slots straight
    /// into it).
    perm: Vec<usize>,
    numeric: Numeric,
    /// A factor's buffer kept for the next factorisation, and the model
    /// whose unshifted Hessian it is the factor of, if it is one
    /// (`keep_factor`).
    spare: std::sync::Mutex<Spare>,
    /// A gradient's and a Hessian's buffers handed back (`recycle`) for
    /// the next assembly: the Hessian's values are megabytes, and fresh
    /// ones each time cost page faults.
    buffers: std::sync::Mutex<(Vec<f64>, Vec<f64>)>,
    diag_pos: Vec<usize>,
    /// Diagonal metric: 1 for lengths, (w/2)^2 for angles.
    pub dm: Vec<f64>,
}

impl System {
    pub fn new(model: &Model) -> System {
        let mut free_index = vec![usize::MAX; model.q.len()];
        let mut free_vars = Vec::new();
        for (i, &f) in model.fixed.iter().enumerate() {
            if !f {
                free_index[i] = free_vars.len();
                free_vars.push(i);
            }
        }
        let n = free_vars.len();
        // Every variable over the free ones: (free index, coefficient).
        let mut expand: Vec<Vec<(usize, f64)>> = free_index
            .iter()
            .map(|&f| {
                if f == usize::MAX {
                    vec![]
                } else {
                    vec![(f, 1.0)]
                }
            })
            .collect();
        let mut tied = Vec::new();
        for t in &model.ties {
            let terms: Vec<(usize, f64)> = t
                .terms
                .iter()
                .filter(|&&(u, _)| free_index[u] != usize::MAX)
                .map(|&(u, c)| (free_index[u], c))
                .collect();
            expand[t.var] = terms.clone();
            tied.push((t.var, terms));
        }
        let stencil_vars: Vec<Vec<usize>> = model
            .stencils
            .iter()
            .map(|s| model.stencil_vars(s))
            .collect();
        // (local index, free index, coefficient) of each stencil.
        let entries: Vec<Vec<(usize, usize, f64)>> = stencil_vars
            .iter()
            .map(|vars| {
                vars.iter()
                    .enumerate()
                    .flat_map(|(a, &v)| expand[v].iter().map(move |&(f, c)| (a, f, c)))
                    .collect()
            })
            .collect();
        let mut cols: Vec<Vec<usize>> = (0..n).map(|c| vec![c]).collect();
        for list in &entries {
            for &(_, fa, _) in list {
                for &(_, fb, _) in list {
                    if fa > fb {
                        cols[fb].push(fa);
                    }
                }
            }
        }
        let mut col_ptr = vec![0usize];
        let mut row_idx = Vec::new();
        for c in cols.iter_mut() {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(c);
            col_ptr.push(row_idx.len());
        }
        let slot = |row: usize, col: usize| -> usize {
            let range = col_ptr[col]..col_ptr[col + 1];
            col_ptr[col] + row_idx[range].binary_search(&row).expect("in the pattern")
        };
        let stencil_pos = entries
            .iter()
            .map(|list| {
                let k = list.len();
                let mut pos = vec![NONE; k * k];
                for (p, &(_, fa, _)) in list.iter().enumerate() {
                    for (q, &(_, fb, _)) in list.iter().enumerate() {
                        if fa >= fb {
                            pos[p * k + q] = slot(fa, fb) as u32;
                        }
                    }
                }
                pos
            })
            .collect();
        let stencil_entries: Vec<Vec<(u32, f64)>> = entries
            .iter()
            .map(|list| list.iter().map(|&(a, _, c)| (a as u32, c)).collect())
            .collect();
        // A variable tied to one other with coefficient 1 is one entry
        // too: plain only if its free index keeps the order.
        let stencil_plain = entries
            .iter()
            .zip(&stencil_vars)
            .map(|(list, vars)| {
                list.len() == vars.len()
                    && list
                        .iter()
                        .enumerate()
                        .all(|(p, &(a, _, c))| a == p && c == 1.0)
                    && list.windows(2).all(|w| w[0].1 < w[1].1)
            })
            .collect();
        let diag_pos = (0..n).map(|c| slot(c, c)).collect();
        let dm: Vec<f64> = free_vars.iter().map(|&v| metric(model, v)).collect();
        let pattern = Pattern { col_ptr, row_idx };
        let (upper, upper_pos, perm, chol) = factor_structure(&pattern);
        let numeric = Numeric::new(&upper, &upper_pos, &perm, &dm, &chol);
        System {
            free_index,
            free_vars,
            tied,
            stencil_vars,
            stencil_entries,
            stencil_pos,
            stencil_plain,
            pattern,
            perm,
            numeric,
            spare: std::sync::Mutex::new((None, None)),
            buffers: std::sync::Mutex::new((Vec::new(), Vec::new())),
            diag_pos,
            dm,
        }
    }

    pub fn n(&self) -> usize {
        self.free_vars.len()
    }

    /// The entries of the Hessian's lower triangle and of its Cholesky
    /// factor (the fill the ordering leaves): for benchmarks.
    pub fn entries(&self) -> (usize, usize) {
        (self.pattern.row_idx.len(), self.numeric.len_val())
    }

    /// Whether `System::new(model)` would be this system: the same free
    /// and fixed variables, ties (their free terms and coefficients),
    /// stencils' variables and metric. A changed design of the same
    /// topology keeps its system (warm re-solves, docs/physics.md,
    /// "Sensitivities"), saving the ordering and symbolic analysis.
    pub fn fits(&self, model: &Model) -> bool {
        let free = |v: usize| self.free_index[v];
        model.q.len() == self.free_index.len()
            && (model.fixed.iter().enumerate()).all(|(v, &f)| f == (free(v) == usize::MAX))
            && model.ties.len() == self.tied.len()
            && model.ties.iter().zip(&self.tied).all(|(t, (var, terms))| {
                let mut mine = terms.iter();
                let same = (t.terms.iter().filter(|&&(u, _)| free(u) != usize::MAX))
                    .all(|&(u, c)| mine.next() == Some(&(free(u), c)));
                t.var == *var && same && mine.next().is_none()
            })
            && model.stencils.len() == self.stencil_vars.len()
            && (model.stencils.iter().zip(&self.stencil_vars))
                .all(|(st, vars)| model.stencil_vars(st) == *vars)
            && (self.free_vars.iter().zip(&self.dm)).all(|(&v, &d)| d == metric(model, v))
    }

    /// Tied variables over the free ones: (variable, [(free index, coef)]).
    pub(crate) fn tied(&self) -> &[(usize, Vec<(usize, f64)>)] {
        &self.tied
    }

    /// The variables of stencil `s` (`Model::stencil_vars`).
    pub(crate) fn vars_of(&self, s: usize) -> &[usize] {
        &self.stencil_vars[s]
    }

    /// Energy, gradient over every variable, and the free Hessian's lower values.
    pub fn assemble(&self, model: &Model) -> (f64, Vec<f64>, Vec<f64>) {
        ASSEMBLIES.fetch_add(1, Relaxed);
        let (mut g, mut h) = self
            .buffers
            .lock()
            .map(|mut b| std::mem::take(&mut *b))
            .unwrap_or_default();
        g.clear();
        g.resize(model.q.len(), 0.0);
        h.clear();
        h.resize(self.pattern.row_idx.len(), 0.0);
        let mut e = 0.0;
        let (mut gs, mut hs) = (Vec::with_capacity(32), Vec::with_capacity(32 * 32));
        let mut memo = Memo::new();
        for (s, st) in model.stencils.iter().enumerate() {
            let vars = &self.stencil_vars[s];
            let plain = self.stencil_plain[s];
            e += model.stencil_derivatives_memo(st, vars, &mut gs, &mut hs, &mut memo, plain);
            let k = vars.len();
            for a in 0..k {
                g[vars[a]] += gs[a];
            }
            let entries = &self.stencil_entries[s];
            let ne = entries.len();
            let pos = &self.stencil_pos[s];
            if plain {
                // One entry per local variable, coefficient 1: the
                // products below are the values themselves, and the
                // slots those of the lower triangle.
                for (p, row) in hs.chunks_exact(k).enumerate() {
                    for (&slot, &v) in pos[p * k..=p * k + p].iter().zip(row) {
                        h[slot as usize] += v;
                    }
                }
                continue;
            }
            for (p, &(a, ca)) in entries.iter().enumerate() {
                let row = &hs[a as usize * k..(a as usize + 1) * k];
                for (q, &(b, cb)) in entries.iter().enumerate() {
                    let slot = pos[p * ne + q];
                    if slot != NONE {
                        h[slot as usize] += ca * cb * row[b as usize];
                    }
                }
            }
        }
        (e, g, h)
    }

    /// Hand an assembly's gradient and Hessian back for the next one.
    pub fn recycle(&self, g: Vec<f64>, h: Vec<f64>) {
        if let Ok(mut b) = self.buffers.lock() {
            *b = (g, h);
        }
    }

    /// The gradient over the free variables (tied variables' parts moved
    /// onto their terms).
    pub fn free_gradient(&self, g: &[f64]) -> Vec<f64> {
        let mut gf: Vec<f64> = self.free_vars.iter().map(|&v| g[v]).collect();
        for (v, terms) in &self.tied {
            for &(f, c) in terms {
                gf[f] += c * g[*v];
            }
        }
        gf
    }

    /// The largest diagonal entry of `h` over the variables' scales: the
    /// size of the shifts that make an indefinite Hessian factorable.
    pub fn diagonal_scale(&self, h: &[f64]) -> f64 {
        self.diag_pos
            .iter()
            .zip(&self.dm)
            .map(|(&p, d)| h[p] / d)
            .fold(0.0f64, f64::max)
            .max(1e-300)
    }

    /// Cholesky of H + tau Dm, or None if it is not positive definite.
    pub fn factor(&self, h: &[f64], tau: f64) -> Option<Factor> {
        let mut f = self
            .spare
            .lock()
            .ok()
            .and_then(|mut s| std::mem::take(&mut *s).0)
            .unwrap_or(Factor {
                l: Vec::new(),
                inv: Vec::new(),
            });
        f.l.resize(self.numeric.len_val(), 0.0);
        f.inv.resize(self.n(), 0.0);
        FACTORISATIONS.fetch_add(1, Relaxed);
        match self.numeric.factor(h, tau, &mut f.l, &mut f.inv) {
            Ok(()) => Some(f),
            Err(_) => {
                FAILED.fetch_add(1, Relaxed);
                self.release(f);
                None
            }
        }
    }

    /// Hand a factor's buffer back for the next factorisation (a Hessian's
    /// factor is megabytes: a fresh one each time costs page faults).
    pub fn release(&self, f: Factor) {
        if let Ok(mut s) = self.spare.lock() {
            *s = (Some(f), None);
        }
    }

    /// Hand back `f`, the factor of `model`'s Hessian unshifted, so that a
    /// linearisation at that same state (`take_factor`: a warm re-solve's
    /// tangent, an adjoint after a solve) needs no assembly and
    /// factorisation of its own until the buffer is used again.
    pub(crate) fn keep_factor(&self, f: Factor, model: Model) {
        if let Ok(mut s) = self.spare.lock() {
            *s = (Some(f), Some(model));
        }
    }

    /// The factor of `model`'s unshifted Hessian if the spare buffer holds
    /// it (`keep_factor` with an equal model: every variable, frame, rest
    /// length and term the same, so the same Hessian), with that model.
    pub(crate) fn take_factor(&self, model: &Model) -> Option<(Factor, Model)> {
        let mut s = self.spare.lock().ok()?;
        if !matches!(&*s, (Some(_), Some(kept)) if kept == model) {
            return None;
        }
        let (f, kept) = std::mem::take(&mut *s);
        Some((f?, kept?))
    }

    /// Solve (H + tau Dm) x = rhs with a factor of it.
    pub fn solve(&self, f: &Factor, rhs: &[f64]) -> Vec<f64> {
        let mut y = self.numeric.work();
        for (yi, &old) in y.iter_mut().zip(&self.perm) {
            *yi = rhs[old];
        }
        self.numeric.solve_in_place(f, &mut y);
        let mut x = vec![0.0; rhs.len()];
        for (&yi, &old) in y.iter().zip(&self.perm) {
            x[old] = yi;
        }
        x
    }

    /// y = H v from the lower triangle.
    pub fn mul(&self, h: &[f64], v: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; v.len()];
        self.mul_into(h, v, &mut y);
        y
    }

    /// `mul` into `y` (of v's length), overwritten.
    fn mul_into(&self, h: &[f64], v: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        let (cp, ri) = (&self.pattern.col_ptr, &self.pattern.row_idx);
        for c in 0..v.len() {
            // Each column's rows are sorted, the diagonal first (`new`).
            let d = cp[c];
            y[c] += h[d] * v[c];
            for p in d + 1..cp[c + 1] {
                let r = ri[p];
                y[r] += h[p] * v[c];
                y[c] += h[p] * v[r];
            }
        }
    }

    /// The lowest generalised eigenpair of (H, Dm) by inverse iteration with
    /// a factor of H + tau Dm (positive definite): (lambda, v).
    pub fn lowest_mode(&self, h: &[f64], llt: &Factor, seed: u64) -> (f64, Vec<f64>) {
        let n = self.n();
        let mut rng = crate::rng::Rng::new(seed);
        let mut v: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
        let mut lambda = 0.0;
        // The buffers of `solve` and `mul`, reused by every step: the same
        // operations as solve(Dm v) and mul(v), without their allocations.
        let (mut work, mut y, mut hv) = (self.numeric.work(), vec![0.0; n], vec![0.0; n]);
        for it in 0..60 {
            self.solve_dm_into(llt, &v, &mut work, &mut y);
            let norm = self.dm_norm(&y);
            if !(norm > 0.0) {
                break;
            }
            for (vi, &yi) in v.iter_mut().zip(&y) {
                *vi = yi / norm;
            }
            self.mul_into(h, &v, &mut hv);
            let l = v.iter().zip(&hv).map(|(a, b)| a * b).sum::<f64>();
            if it > 5 && (l - lambda).abs() <= 1e-10 * l.abs().max(1e-300) {
                lambda = l;
                break;
            }
            lambda = l;
        }
        (lambda, v)
    }

    /// out = (H + tau Dm)^-1 Dm v with a factor `llt` of H + tau Dm:
    /// `solve(Dm v)` in the caller's buffers (`work` is the factor's
    /// order), so an iteration allocates nothing.
    fn solve_dm_into(&self, llt: &Factor, v: &[f64], work: &mut [f64], out: &mut [f64]) {
        for (w, &old) in work.iter_mut().zip(&self.perm) {
            *w = v[old] * self.dm[old];
        }
        self.numeric.solve_in_place(llt, work);
        for (&w, &old) in work.iter().zip(&self.perm) {
            out[old] = w;
        }
    }

    /// The length of `x` in the Dm inner product.
    fn dm_norm(&self, x: &[f64]) -> f64 {
        x.iter()
            .zip(&self.dm)
            .map(|(a, b)| a * a * b)
            .sum::<f64>()
            .sqrt()
    }
}

impl System {
    /// The lowest generalised eigenvalue of (H, Dm) by Lanczos on
    /// (H + tau Dm)^-1 Dm with a factor of H + tau Dm (positive definite),
    /// in the Dm inner product (docs/physics.md, "Solver"): its largest
    /// Ritz value theta is 1 / (lambda + tau). The three-term recurrence
    /// only (no reorthogonalisation: a lost orthogonality repeats a
    /// converged Ritz value, it does not change the largest), until theta
    /// changes by at most 1e-12 of itself, at most 60 steps.
    pub fn lowest_eigenvalue(&self, llt: &Factor, tau: f64, seed: u64) -> f64 {
        let n = self.n();
        let mut rng = crate::rng::Rng::new(seed);
        let mut q: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
        let norm = self.dm_norm(&q);
        if !(norm > 0.0) {
            return f64::NAN;
        }
        q.iter_mut().for_each(|x| *x /= norm);
        let mut q_prev = vec![0.0; n];
        let mut w = vec![0.0; n];
        let mut work = self.numeric.work();
        let (mut alpha, mut beta) = (Vec::new(), Vec::new());
        let mut theta = 0.0;
        for step in 0..60 {
            self.solve_dm_into(llt, &q, &mut work, &mut w);
            let a: f64 = (w.iter().zip(&q).zip(&self.dm))
                .map(|((x, y), d)| x * y * d)
                .sum();
            let b_prev = beta.last().copied().unwrap_or(0.0);
            for ((x, &y), &z) in w.iter_mut().zip(&q).zip(&q_prev) {
                *x -= a * y + b_prev * z;
            }
            alpha.push(a);
            let next = largest_ritz_value(&alpha, &beta);
            let settled = step > 2 && (next - theta).abs() <= 1e-12 * next.abs();
            theta = next;
            let b = self.dm_norm(&w);
            // An invariant subspace (b = 0): theta is exact.
            if settled || !(b > 1e-300 * theta.abs()) {
                break;
            }
            beta.push(b);
            std::mem::swap(&mut q_prev, &mut q);
            for (y, &x) in q.iter_mut().zip(&w) {
                *y = x / b;
            }
        }
        1.0 / theta - tau
    }
}

/// The largest eigenvalue of the symmetric tridiagonal matrix with
/// diagonal `a` and off-diagonal `b` (one shorter), by bisection on the
/// Sturm sequence's count of eigenvalues below a point, to the last bits.
fn largest_ritz_value(a: &[f64], b: &[f64]) -> f64 {
    let k = a.len();
    // Gershgorin's bounds.
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..k {
        let r = b.get(i).map_or(0.0, |x| x.abs()) + i.checked_sub(1).map_or(0.0, |j| b[j].abs());
        lo = lo.min(a[i] - r);
        hi = hi.max(a[i] + r);
    }
    // How many eigenvalues are below x (the LDL^T pivots' signs).
    let below = |x: f64| {
        let (mut count, mut d) = (0, 1.0);
        for i in 0..k {
            let off = if i > 0 { b[i - 1] * b[i - 1] / d } else { 0.0 };
            d = a[i] - x - off;
            if d == 0.0 {
                d = -1e-300;
            }
            if d < 0.0 {
                count += 1;
            }
        }
        count
    };
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if !(mid > lo && mid < hi) {
            break;
        }
        if below(mid) < k {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// A factor's buffer and the model it is the unshifted factor of, if any.
type Spare = (Option<Factor>, Option<Model>);

/// Variable v's diagonal metric: 1 for lengths, (w/2)^2 for angles.
fn metric(model: &Model, v: usize) -> f64 {
    match model.kinds[v] {
        VarKind::Length => 1.0,
        VarKind::Angle => (model.section.width / 2.0).powi(2),
    }
}

/// The numeric Cholesky of the shifted Hessian, with everything that does
/// not depend on the values worked out once per model: an up-looking
/// simplicial LLT (row k of the factor from the rows its elimination
/// reach names), with each row's reach (a walk up the elimination tree)
/// worked out once and kept as a list,
/// the Hessian's values read straight from their slots, each pivot's
/// reciprocal taken once, and no bounds check per entry of the work
/// vector (`work`). The rows of the factor are visited in order and a
/// non-positive pivot stops it there.
struct Numeric {
    /// The upper triangle in the factor's order: column pointers, row of
    /// each entry, and the Hessian slot it holds.
    a_ptr: Vec<usize>,
    a_row: Vec<u32>,
    a_src: Vec<u32>,
    /// The metric of each column in the factor's order.
    dm: Vec<f64>,
    /// The factor's columns (`sparse::factor_pattern`).
    l_ptr: Vec<usize>,
    l_row: Vec<u32>,
    /// Row k's reach: the columns j < k with L[k][j] != 0, in the order
    /// the walk below finds them.
    reach_ptr: Vec<usize>,
    reach: Vec<u32>,
}

impl Numeric {
    /// The factor's number of entries.
    fn len_val(&self) -> usize {
        self.l_ptr[self.l_ptr.len() - 1]
    }

    fn new(
        upper: &Pattern,
        upper_pos: &[usize],
        perm: &[usize],
        dm: &[f64],
        chol: &Pattern,
    ) -> Numeric {
        let n = upper.n();
        let a_ptr = upper.col_ptr.clone();
        let a_row: Vec<u32> = upper.row_idx.iter().map(|&r| r as u32).collect();
        let mut a_src = vec![0u32; upper_pos.len()];
        for (slot, &p) in upper_pos.iter().enumerate() {
            a_src[p] = slot as u32;
        }
        let l_ptr = chol.col_ptr.clone();
        let l_row: Vec<u32> = chol.row_idx.iter().map(|&r| r as u32).collect();
        // Column j's entries are its rows in increasing order, the
        // diagonal first: its parent in the elimination tree is the next.
        let parent: Vec<usize> = (0..n)
            .map(|j| {
                if l_ptr[j + 1] - l_ptr[j] > 1 {
                    l_row[l_ptr[j] + 1] as usize
                } else {
                    usize::MAX
                }
            })
            .collect();
        // The reach: from each entry of A's column k above the
        // diagonal, up the tree to a node already met; each such path is
        // put before the paths found earlier.
        let mut reach_ptr = vec![0usize];
        let mut reach = Vec::with_capacity(l_row.len() - n);
        let mut visited = vec![usize::MAX; n];
        // The paths of one row one after another, and where each starts:
        // emitted last found first, each in its own order.
        let mut paths: Vec<u32> = Vec::new();
        let mut starts: Vec<usize> = Vec::new();
        for k in 0..n {
            visited[k] = k;
            paths.clear();
            starts.clear();
            for &i in &a_row[a_ptr[k]..a_ptr[k + 1]] {
                let mut i = i as usize;
                if i >= k {
                    continue;
                }
                starts.push(paths.len());
                while visited[i] != k {
                    paths.push(i as u32);
                    visited[i] = k;
                    i = parent[i];
                }
            }
            let mut end = paths.len();
            for &start in starts.iter().rev() {
                reach.extend_from_slice(&paths[start..end]);
                end = start;
            }
            reach_ptr.push(reach.len());
        }
        Numeric {
            a_ptr,
            a_row,
            a_src,
            dm: perm.iter().map(|&old| dm[old]).collect(),
            l_ptr,
            l_row,
            reach_ptr,
            reach,
        }
    }

    /// A zeroed vector of the factor's size, padded to a power of two: its
    /// entries are indexed `i & mask`, which the compiler knows to be in
    /// bounds (no check per entry of the factor's inner loops).
    fn work(&self) -> Vec<f64> {
        vec![0.0; self.dm.len().next_power_of_two()]
    }

    /// The factor of H + tau Dm into `l` (and the reciprocals of its
    /// diagonal into `inv`), or the row where a pivot is not positive or a
    /// value not finite.
    fn factor(&self, h: &[f64], tau: f64, l: &mut [f64], inv: &mut [f64]) -> Result<(), usize> {
        let n = self.dm.len();
        let mut work = self.work();
        let mask = work.len() - 1;
        let x = &mut work[..=mask];
        let mut next: Vec<usize> = self.l_ptr[..n].to_vec();
        for k in 0..n {
            let (lo, hi) = (self.a_ptr[k], self.a_ptr[k + 1]);
            let mut finite = true;
            for (&i, &src) in self.a_row[lo..hi].iter().zip(&self.a_src[lo..hi]) {
                let i = i as usize;
                let mut v = h[src as usize];
                if i == k && tau != 0.0 {
                    v += tau * self.dm[k];
                }
                finite &= v.is_finite();
                x[i & mask] += v;
            }
            if !finite {
                return Err(k);
            }
            let mut d = x[k & mask];
            x[k & mask] = 0.0;
            for &j in &self.reach[self.reach_ptr[k]..self.reach_ptr[k + 1]] {
                let j = j as usize;
                let start = self.l_ptr[j];
                next[j] += 1;
                let slot = next[j];
                let xj = x[j & mask];
                x[j & mask] = 0.0;
                let lkj = xj * inv[j];
                let done = start + 1..slot;
                for (&i, &lij) in self.l_row[done.clone()].iter().zip(&l[done]) {
                    x[i as usize & mask] -= lij * lkj;
                }
                d -= lkj * lkj;
                l[slot] = lkj;
            }
            if !(d > 0.0) {
                return Err(k);
            }
            let ljj = d.sqrt();
            l[self.l_ptr[k]] = ljj;
            inv[k] = 1.0 / ljj;
        }
        Ok(())
    }

    /// Solve L L^T y = b in place (`y` from `work`, b in its first n
    /// entries), as a simplicial solve does it, operation for
    /// operation: forward by columns, then backward by dot products.
    fn solve_in_place(&self, f: &Factor, y: &mut [f64]) {
        let (l, inv) = (&f.l, &f.inv);
        let n = self.dm.len();
        let mask = y.len() - 1;
        let y = &mut y[..=mask];
        for j in 0..n {
            let (lo, hi) = (self.l_ptr[j], self.l_ptr[j + 1]);
            let yj = y[j & mask] * inv[j];
            y[j & mask] = yj;
            for (&i, &lij) in self.l_row[lo + 1..hi].iter().zip(&l[lo + 1..hi]) {
                y[i as usize & mask] -= lij * yj;
            }
        }
        for j in (0..n).rev() {
            let (lo, hi) = (self.l_ptr[j], self.l_ptr[j + 1]);
            let mut acc = 0.0;
            for (&i, &lij) in self.l_row[lo + 1..hi].iter().zip(&l[lo + 1..hi]).rev() {
                acc += lij * y[i as usize & mask];
            }
            y[j & mask] = (y[j & mask] - acc) * inv[j];
        }
    }
}

/// The numeric Cholesky factor of one shifted Hessian, in the order of
/// `System::perm`, on the structure of `Numeric`.
pub struct Factor {
    l: Vec<f64>,
    /// The reciprocals of the factor's diagonal, each computed once (1 /
    /// L[j][j] is what every row that column j updates needs).
    inv: Vec<f64>,
}

/// The fill-reducing order (`sparse::amd_order`), the lower-triangle
/// `pattern` moved into it as an upper triangle, each of its slots' place
/// there, and the factor's pattern: (upper, upper_pos, perm, factor).
fn factor_structure(pattern: &Pattern) -> (Pattern, Vec<usize>, Vec<usize>, Pattern) {
    let n = pattern.n();
    let (perm, inv) = amd_order(pattern);
    // Entry (r, c), r >= c, lands at (min, max) of (inv r, inv c).
    let mut at = Vec::with_capacity(pattern.row_idx.len());
    let mut count = vec![0usize; n + 1];
    for c in 0..n {
        for &r in pattern.column(c) {
            let (a, b) = (inv[r], inv[c]);
            let (row, col) = (a.min(b), a.max(b));
            at.push((row, col));
            count[col + 1] += 1;
        }
    }
    for c in 0..n {
        count[c + 1] += count[c];
    }
    let col_ptr = count;
    // Within a column in the order met (a counting sort by column, which
    // is stable): the numeric factor sums a column's entries in this
    // order, which fixes its rounding, and with it the solver's path.
    let mut next = col_ptr[..n].to_vec();
    let mut row_idx = vec![0usize; at.len()];
    let mut upper_pos = vec![0usize; at.len()];
    for (k, &(row, col)) in at.iter().enumerate() {
        let slot = next[col];
        next[col] += 1;
        row_idx[slot] = row;
        upper_pos[k] = slot;
    }
    let upper = Pattern { col_ptr, row_idx };
    let factor = factor_pattern(&upper);
    (upper, upper_pos, perm, factor)
}

#[derive(Clone, Debug, PartialEq)]
pub struct Stats {
    pub iterations: usize,
    pub converged: bool,
    /// Largest free force component (N) and moment component (N mm) left.
    pub force: f64,
    pub moment: f64,
    /// Lowest eigenvalue of Dm^-1/2 H Dm^-1/2 at the end (stability).
    pub lambda_min: f64,
    pub energy: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub enum SolveError {
    /// The line search halved the step 30 times without a decrease.
    LineSearch { iteration: usize },
    /// A non-finite energy or gradient.
    NotFinite { iteration: usize },
    /// `Options::deadline` passed before this iteration.
    TimeLimit { iteration: usize },
}

impl std::fmt::Display for SolveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SolveError::LineSearch { iteration } => write!(
                f,
                "Newton stalled at iteration {iteration}: no decrease after 30 halvings of the step"
            ),
            SolveError::NotFinite { iteration } => {
                write!(f, "the energy became non-finite at iteration {iteration}")
            }
            SolveError::TimeLimit { iteration } => {
                write!(f, "stopped at the time limit before iteration {iteration}")
            }
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub struct Options {
    pub max_iterations: usize,
    /// Stop with `SolveError::TimeLimit` once this passes (checked once an
    /// iteration).
    pub deadline: Option<std::time::Instant>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            max_iterations: 300,
            deadline: None,
        }
    }
}

/// A Newton step at the current state: (step over free variables,
/// decrement, tau, gradient, Hessian values).
struct Step {
    d: Vec<f64>,
    dec: f64,
    tau: f64,
}

fn newton_step(sys: &System, model: &Model, tau_prev: &mut f64, curvature: bool) -> Option<Step> {
    let (_, g, h) = sys.assemble(model);
    if g.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let gf = sys.free_gradient(&g);
    let h_s = sys.diagonal_scale(&h);
    let mut tau = 0.0;
    let llt = loop {
        if let Some(f) = sys.factor(&h, tau) {
            break f;
        }
        tau = if tau == 0.0 {
            (*tau_prev / 4.0).max(1e-8 * h_s)
        } else {
            tau * 10.0
        };
        if tau > 1e30 * h_s {
            return None;
        }
    };
    *tau_prev = tau;
    let mut d: Vec<f64> = sys.solve(&llt, &gf).into_iter().map(|v| -v).collect();
    let mut dec = -gf.iter().zip(&d).map(|(a, b)| a * b).sum::<f64>();
    if curvature && tau > 0.0 && dec < 1e-6 * model.e_scale {
        let (_, mut v) = sys.lowest_mode(&h, &llt, 1);
        let gv: f64 = gf.iter().zip(&v).map(|(a, b)| a * b).sum();
        if gv > 0.0 {
            v.iter_mut().for_each(|x| *x = -*x);
        }
        let inf = v.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(1e-300);
        for (di, vi) in d.iter_mut().zip(&v) {
            *di += 0.5 * vi / inf;
        }
        dec = -gf.iter().zip(&d).map(|(a, b)| a * b).sum::<f64>();
        // Along negative curvature the decrease is real even where the
        // linear term is small; keep the Armijo test meaningful.
        dec = dec.max(1e-6 * model.e_scale);
    }
    sys.release(llt);
    sys.recycle(g, h);
    Some(Step { d, dec, tau })
}

fn apply(sys: &System, model: &mut Model, d: &[f64], scale: f64) {
    for (k, &v) in sys.free_vars.iter().enumerate() {
        model.q[v] += scale * d[k];
    }
    model.apply_ties();
}

/// Largest step component: lengths (mm) and angles (rad).
fn step_size(sys: &System, model: &Model, d: &[f64]) -> f64 {
    sys.free_vars
        .iter()
        .zip(d)
        .map(|(&v, x)| match model.kinds[v] {
            VarKind::Length | VarKind::Angle => x.abs(),
        })
        .fold(0.0, f64::max)
}

/// Minimise the model's energy over its free variables.
pub fn solve(model: &mut Model, sys: &System, opts: &Options) -> Result<Stats, SolveError> {
    let mut e = model.energy();
    let mut tau_prev = 0.0;
    let mut converged = false;
    let mut iterations = 0;
    for it in 0..opts.max_iterations {
        iterations = it + 1;
        if !e.is_finite() {
            return Err(SolveError::NotFinite { iteration: it });
        }
        if opts
            .deadline
            .is_some_and(|d| std::time::Instant::now() >= d)
        {
            return Err(SolveError::TimeLimit { iteration: it });
        }
        let Some(step) = newton_step(sys, model, &mut tau_prev, true) else {
            return Err(SolveError::NotFinite { iteration: it });
        };
        let small = step_size(sys, model, &step.d) < 1e-8;
        if step.tau == 0.0 && step.dec < 1e-12 * model.e_scale {
            apply(sys, model, &step.d, 1.0);
            model.update_frames();
            e = model.energy();
            if small {
                converged = true;
                break;
            }
            continue;
        }
        let saved_q = model.q.clone();
        let saved_frames = model.frames();
        // (i) the full step.
        apply(sys, model, &step.d, 1.0);
        let e1 = model.energy();
        if e1 <= e - 1e-4 * step.dec {
            model.update_frames();
            e = e1;
            continue;
        }
        // (ii) the watchdog: one more step from there.
        model.update_frames();
        let mut tau2 = tau_prev;
        if let Some(step2) = newton_step(sys, model, &mut tau2, false) {
            apply(sys, model, &step2.d, 1.0);
            let e2 = model.energy();
            if e2 <= e - 1e-4 * step.dec {
                model.update_frames();
                e = e2;
                continue;
            }
        }
        // (iii) back to q, halving.
        model.q = saved_q.clone();
        model.set_frames(&saved_frames);
        let mut alpha = 0.5;
        let mut accepted = false;
        for _ in 0..30 {
            model.q.clone_from(&saved_q);
            apply(sys, model, &step.d, alpha);
            let ea = model.energy();
            if ea <= e - 1e-4 * alpha * step.dec {
                e = ea;
                accepted = true;
                break;
            }
            alpha /= 2.0;
        }
        if !accepted {
            model.q = saved_q;
            // A decrement at round-off: nothing left to gain.
            if step.dec < 1e-10 * model.e_scale.max(e.abs()) && step.tau == 0.0 {
                converged = true;
                break;
            }
            return Err(SolveError::LineSearch { iteration: it });
        }
        model.update_frames();
    }
    Ok(finish(model, sys, iterations, converged))
}

/// Residual forces and moments, and the lowest eigenvalue.
pub fn finish(model: &Model, sys: &System, iterations: usize, converged: bool) -> Stats {
    let (e, g, h) = sys.assemble(model);
    let (mut force, mut moment) = (0.0f64, 0.0f64);
    for (&v, gv) in sys.free_vars.iter().zip(sys.free_gradient(&g)) {
        match model.kinds[v] {
            VarKind::Length => force = force.max(gv.abs()),
            VarKind::Angle => moment = moment.max(gv.abs()),
        }
    }
    let lambda_min = match sys.factor(&h, 0.0) {
        Some(llt) if sys.n() > 0 => {
            let lambda = sys.lowest_eigenvalue(&llt, 0.0, 7);
            sys.keep_factor(llt, model.clone());
            lambda
        }
        Some(_) => f64::INFINITY,
        None => {
            // Indefinite: estimate the negative eigenvalue with a shift.
            let mut tau = 1e-8 * sys.diagonal_scale(&h);
            loop {
                if let Some(llt) = sys.factor(&h, tau) {
                    let lambda = sys.lowest_eigenvalue(&llt, tau, 7);
                    sys.release(llt);
                    break lambda;
                }
                tau *= 10.0;
                if !tau.is_finite() {
                    break f64::NEG_INFINITY;
                }
            }
        }
    };
    sys.recycle(g, h);
    Stats {
        iterations,
        converged,
        force,
        moment,
        lambda_min,
        energy: e,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Section;
    use crate::rng::Rng;
    use crate::sparse::tests_support::random_lower;
    use glam::DVec3;

    /// The dense Cholesky of the symmetric matrix in the factor's order,
    /// column by column: L, or the row of the first pivot that is not
    /// positive.
    fn dense_cholesky(a: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, usize> {
        let n = a.len();
        let mut l = vec![vec![0.0; n]; n];
        for k in 0..n {
            let mut d = a[k][k];
            for j in 0..k {
                let mut s = a[k][j];
                for p in 0..j {
                    s -= l[k][p] * l[j][p];
                }
                l[k][j] = s / l[j][j];
                d -= l[k][j] * l[k][j];
            }
            if !(d > 0.0) {
                return Err(k);
            }
            l[k][k] = d.sqrt();
        }
        Ok(l)
    }

    /// A bent strip of 8 nodes, its first node fixed.
    fn bent_strip() -> Model {
        let section = Section {
            b_flat: 50.0,
            b_edge: 5000.0,
            ea: 2000.0,
            gj: 40.0,
            width: 8.0,
            thickness: 1.0,
        };
        let points: Vec<DVec3> = (0..8)
            .map(|i| DVec3::new(10.0 * i as f64, 0.0, 0.3 * (i * i) as f64))
            .collect();
        let mut m = Model::strip(section, &points, DVec3::Y);
        for v in 0..3 {
            m.fixed[v] = true;
        }
        m
    }

    /// A system fits the model it was made for and models that differ in
    /// values only, not one with another variable fixed or another width;
    /// a factor `finish` keeps is handed out for an equal model only, and
    /// is the factor a fresh assembly gives.
    #[test]
    fn a_system_is_kept_for_models_it_fits_and_its_factor_for_equal_ones() {
        let m = bent_strip();
        let sys = System::new(&m);
        let mut moved = m.clone();
        moved.q[5] += 0.25;
        assert!(sys.fits(&m) && sys.fits(&moved));
        let mut refixed = m.clone();
        refixed.fixed[4] = true;
        let mut wider = m.clone();
        wider.section.width += 1.0;
        assert!(!sys.fits(&refixed) && !sys.fits(&wider));

        let (_, _, h) = sys.assemble(&m);
        // Shifted: the strip turns freely about its fixed node. The
        // buffer is handed out as kept, whatever it holds.
        let fresh = sys.factor(&h, sys.diagonal_scale(&h)).expect("shifted");
        let want = (fresh.l.clone(), fresh.inv.clone());
        sys.keep_factor(fresh, m.clone());
        assert!(sys.take_factor(&moved).is_none());
        let (kept, of) = sys.take_factor(&m).expect("the kept factor");
        assert_eq!((kept.l, kept.inv), want);
        assert!(of == m && sys.take_factor(&m).is_none());
    }

    /// The eigenvalues of a dense symmetric matrix, by cyclic Jacobi.
    fn dense_eigenvalues(mut a: Vec<Vec<f64>>) -> Vec<f64> {
        let n = a.len();
        for _ in 0..100 {
            let off: f64 = (0..n)
                .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
                .map(|(i, j)| a[i][j] * a[i][j])
                .sum();
            if off < 1e-30 {
                break;
            }
            for p in 0..n {
                for q in p + 1..n {
                    if a[p][q].abs() < 1e-300 {
                        continue;
                    }
                    let th = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                    let t = th.signum() / (th.abs() + (th * th + 1.0).sqrt());
                    let t = if th == 0.0 { 1.0 } else { t };
                    let (c, s) = (1.0 / (t * t + 1.0).sqrt(), t / (t * t + 1.0).sqrt());
                    for k in 0..n {
                        let (akp, akq) = (a[k][p], a[k][q]);
                        a[k][p] = c * akp - s * akq;
                        a[k][q] = s * akp + c * akq;
                    }
                    for k in 0..n {
                        let (apk, aqk) = (a[p][k], a[q][k]);
                        a[p][k] = c * apk - s * aqk;
                        a[q][k] = s * apk + c * aqk;
                    }
                }
            }
        }
        (0..n).map(|i| a[i][i]).collect()
    }

    /// The Lanczos estimate of the lowest eigenvalue of (H, Dm) agrees
    /// with a dense one, from factors of H + tau Dm with several shifts,
    /// on a bent strip's Hessian (away from equilibrium, so indefinite)
    /// and on it moved by multiples of Dm.
    #[test]
    fn lowest_eigenvalue_agrees_with_a_dense_one() {
        let m = bent_strip();
        let sys = System::new(&m);
        let (_, _, h) = sys.assemble(&m);
        let n = sys.n();
        let scale = sys.diagonal_scale(&h);
        let dense = |add: f64| {
            let (cp, ri) = (&sys.pattern.col_ptr, &sys.pattern.row_idx);
            let mut a = vec![vec![0.0; n]; n];
            for c in 0..n {
                for p in cp[c]..cp[c + 1] {
                    let v = h[p] / (sys.dm[ri[p]] * sys.dm[c]).sqrt();
                    a[ri[p]][c] = v;
                    a[c][ri[p]] = v;
                }
                a[c][c] += add;
            }
            dense_eigenvalues(a)
                .into_iter()
                .fold(f64::INFINITY, f64::min)
        };
        let low = dense(0.0);
        assert!(low < 0.0, "the strip's Hessian is indefinite: {low}");
        let mut cases = 0;
        for add in [0.0, -low + 1e-3 * scale, -low + 0.3 * scale] {
            let mut hh = h.clone();
            for (k, &p) in sys.diag_pos.iter().enumerate() {
                hh[p] += add * sys.dm[k];
            }
            let want = dense(add);
            for tau in [1e-6, 1e-3, 0.1, 1.0].map(|t| t * scale - want.min(0.0)) {
                let llt = sys.factor(&hh, tau).expect("positive definite");
                let got = sys.lowest_eigenvalue(&llt, tau, 7);
                assert!(
                    (got - want).abs() <= 1e-9 * scale,
                    "add {add}, tau {tau}: {got} against {want}"
                );
                cases += 1;
            }
        }
        assert_eq!(cases, 12);
    }

    /// `Numeric` factors H + tau Dm exactly when it is positive definite,
    /// stops at the same row as a dense Cholesky in the same order when it
    /// is not, and its factor and solve agree with the dense ones to
    /// rounding.
    #[test]
    fn numeric_factor_and_solve_agree_with_dense_cholesky() {
        let mut rng = Rng::new(5);
        let mut failed = 0;
        for case in 0..60 {
            let n = 5 + case * 3;
            let pattern = random_lower(n, &mut rng);
            let (upper, upper_pos, perm, chol) = factor_structure(&pattern);
            let dm: Vec<f64> = (0..n).map(|_| 0.5 + rng.uniform()).collect();
            let numeric = Numeric::new(&upper, &upper_pos, &perm, &dm, &chol);
            // Off-diagonal values in [-1, 1); the diagonal from below to
            // above the row sums, so some matrices are indefinite.
            let (cp, ri) = (&pattern.col_ptr, &pattern.row_idx);
            let mut h: Vec<f64> = ri.iter().map(|_| rng.signed()).collect();
            let mut sums = vec![0.0; n];
            for c in 0..n {
                for p in cp[c]..cp[c + 1] {
                    if ri[p] != c {
                        sums[c] += h[p].abs();
                        sums[ri[p]] += h[p].abs();
                    }
                }
            }
            let scale = 0.1 + rng.uniform();
            for c in 0..n {
                h[cp[c]] = scale * sums[c] + 0.1;
            }
            let tau = if case % 3 == 0 {
                0.0
            } else {
                0.05 * case as f64
            };
            // The shifted matrix, dense, in the factor's order.
            let mut inv = vec![0; n];
            for (new, &old) in perm.iter().enumerate() {
                inv[old] = new;
            }
            let mut a = vec![vec![0.0; n]; n];
            for c in 0..n {
                for p in cp[c]..cp[c + 1] {
                    let (i, j) = (inv[ri[p]], inv[c]);
                    a[i][j] = h[p];
                    a[j][i] = h[p];
                }
                a[inv[c]][inv[c]] += tau * dm[c];
            }
            let mut ours = Factor {
                l: vec![0.0; chol.row_idx.len()],
                inv: vec![0.0; n],
            };
            let got = numeric.factor(&h, tau, &mut ours.l, &mut ours.inv);
            match (got, dense_cholesky(&a)) {
                (Ok(()), Ok(dense)) => {
                    for j in 0..n {
                        for (p, &i) in chol.column(j).iter().enumerate() {
                            let v = ours.l[chol.col_ptr[j] + p];
                            assert!(
                                (v - dense[i][j]).abs() < 1e-12 * (1.0 + dense[i][j].abs()),
                                "case {case}: L[{i}][{j}]"
                            );
                        }
                    }
                    let rhs: Vec<f64> = (0..n).map(|_| rng.normal()).collect();
                    let mut y = numeric.work();
                    y[..n].copy_from_slice(&rhs);
                    numeric.solve_in_place(&ours, &mut y);
                    for i in 0..n {
                        let ay: f64 = (0..n).map(|j| a[i][j] * y[j]).sum();
                        assert!((ay - rhs[i]).abs() < 1e-9, "case {case}: residual at {i}");
                    }
                }
                (Err(k), Err(want)) => {
                    failed += 1;
                    assert_eq!(k, want, "case {case}: stops at another row");
                }
                (got, want) => panic!("case {case}: ours {got:?}, dense {:?}", want.map(|_| ())),
            }
        }
        assert!(
            failed > 5 && failed < 55,
            "indefinite cases: {failed} of 60"
        );
    }
}
