//! The design optimiser: moves the numbers a recipe's `[optimise]` table
//! frees (row leg angles, front-move angles, a helix's seed) to minimise
//! its weighted objectives under its hard constraints, with a
//! Nelder-Mead simplex (`simplex`; derivative-free: growth is piecewise smooth and refuses
//! whole regions, so gradients are unreliable). Restarts from the best
//! point while the budget lasts. Deterministic: the start simplex comes
//! from the recipe's `seed`, and Nelder-Mead draws nothing at random.
//!
//! Numbers that share a magnitude in one front (a zig-zag of +-60 deg,
//! sub-units cranked +-12 deg) are one variable with their signs kept,
//! so a pattern of identical sub-units stays one. A saddle front's
//! amplitudes c and d are two more (`slots::SADDLE_UNIT`).
//!
//! The other searches live beside it: `fit` (rows chosen to approximate a
//! target surface), `tune` (the helix seed's hill climb), and `grow`
//! (`Design::grow`, which calls the fit search).

mod cost;
pub(crate) mod design;
mod evolve;
pub(crate) mod fit;
mod grow;
mod rewrite;
mod simplex;
mod slots;
pub(crate) mod tune;

pub(crate) use cost::cost;
use evolve::evolve;
use rewrite::rewrite;
use slots::slots;

use crate::design::optimise::{Method, Optimise, Pattern, Vary};
use crate::design::{Design, MIN_WALL};
use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::lattice::{FrontMoves, Kind, Lattice, Saddle};
use crate::legs::Direction;
use crate::measure::{Measures, measure};
use crate::rng::Rng;
use glam::DVec3;
use std::cell::{Cell, RefCell};
use std::ops::Range;
use tune::{Frame, Params};

/// One group of recipe numbers that the optimiser moves together.
#[derive(Clone, Debug)]
enum Slot {
    /// A row table's `angle`: the rows it sets, the text to rewrite.
    Angle {
        rows: Vec<usize>,
        span: Range<usize>,
    },
    /// A row table's `front`: its distinct magnitudes are the variables,
    /// then its saddle's amplitudes c and d, when it has one.
    Front {
        rows: Vec<usize>,
        span: Range<usize>,
        magnitudes: Vec<f64>,
        saddle: bool,
    },
    /// A helix seed in cylindrical coordinates (see `solve::tune`).
    Seed,
    /// A fit's `angles` (true) or `steps` (false), one per row.
    Fit { angles: bool, rows: usize },
    /// A disk's sheet seed on its circle: each point's polar angle
    /// (degrees), then each edge's kappa (mm).
    Rim { radius: f64, points: usize },
}

/// The result of `optimise`.
#[derive(Clone, Debug)]
pub struct Optimised {
    /// The recipe text with the optimised numbers, comments kept.
    pub text: String,
    /// The optimised recipe, parsed back from `text`.
    pub design: Design,
    /// Cost (weighted objectives, lower is better) of the recipe as given.
    pub cost_before: f64,
    /// Cost of the optimised recipe, as written and read back.
    pub cost_after: f64,
    /// Optimiser iterations used, over all restarts.
    pub iterations: usize,
    /// Designs grown and scored.
    pub evaluations: usize,
    /// Number of variables searched (numbers sharing a magnitude count once).
    pub variables: usize,
    /// Every shape measure of the optimised design.
    pub measures: Measures,
}

struct Problem<'a> {
    space: Space<'a>,
    /// Designs costed at once (`evaluate_all`).
    jobs: usize,
    evaluations: Cell<usize>,
    /// Designs costed when the deadline passed (`Design::deadline`).
    stopped: Cell<Option<usize>>,
    best: RefCell<(f64, Vec<f64>)>,
    progress: RefCell<&'a mut dyn FnMut(&str)>,
}

/// Cost of a design that does not grow (plus the rows or cells it misses).
const UNGROWN: f64 = 1e9;
/// Weight of a hard constraint's shortfall in the cost.
const PENALTY: f64 = 100.0;

/// What the optimiser moves and how a point becomes a design: the part of
/// the problem that several threads may cost designs with at once.
struct Space<'a> {
    design: &'a Design,
    opt: &'a Optimise,
    slots: Vec<Slot>,
    /// Start values and the size of one unit of each variable.
    x0: Vec<f64>,
    unit: Vec<f64>,
    frame: Option<Frame>,
    seed0: Option<Params>,
}

impl Space<'_> {
    /// The design at scaled variables `x` (0 is the recipe's).
    fn design_at(&self, x: &[f64]) -> Design {
        let mut d = self.design.clone();
        let v: Vec<f64> = x
            .iter()
            .zip(&self.x0)
            .zip(&self.unit)
            .map(|((x, x0), u)| x0 + x * u)
            .collect();
        let mut k = 0;
        for slot in &self.slots {
            match slot {
                Slot::Angle { rows, .. } => {
                    let (angle, tilt) = (v[k], if d.dim == 3 { v[k + 1] } else { 0.0 });
                    for &r in rows {
                        d.rows[r].direction = Some(Direction::Angles {
                            angle_deg: angle,
                            tilt_deg: tilt,
                        });
                    }
                    k += if d.dim == 3 { 2 } else { 1 };
                }
                Slot::Front {
                    rows,
                    magnitudes,
                    saddle,
                    ..
                } => {
                    let new = &v[k..k + magnitudes.len()];
                    k += magnitudes.len();
                    let amplitudes = saddle.then(|| Saddle {
                        c: v[k],
                        d: v[k + 1],
                    });
                    for &r in rows {
                        if let Some(f) = d.rows[r].front.as_mut() {
                            map_front(f, |a| {
                                let i = magnitudes
                                    .iter()
                                    .position(|m| (m - a.abs()).abs() < 1e-9)
                                    .expect("a magnitude of this front");
                                a.signum() * new[i]
                            });
                            if amplitudes.is_some() {
                                f.saddle = amplitudes;
                            }
                        }
                    }
                    k += if *saddle { 2 } else { 0 };
                }
                Slot::Fit { angles, rows } => {
                    let values = v[k..k + rows].to_vec();
                    if let Some(f) = d.fit.as_mut() {
                        if *angles {
                            f.angles = Some(values);
                        } else {
                            f.steps = Some(values);
                        }
                    }
                    k += rows;
                }
                Slot::Rim { radius, points } => {
                    let (angles, kappa) = v[k..k + 2 * points - 1].split_at(*points);
                    d.points = angles
                        .iter()
                        .map(|a| {
                            let a = a.to_radians();
                            DVec3::new(radius * a.cos(), radius * a.sin(), 0.0)
                        })
                        .collect();
                    d.kappa = kappa.to_vec();
                    k += 2 * points - 1;
                }
                Slot::Seed => {
                    let (frame, p0) = (self.frame.as_ref().unwrap(), self.seed0.as_ref().unwrap());
                    let n = p0.rho.len();
                    let mut p = p0.clone();
                    p.rho.copy_from_slice(&v[k..k + n]);
                    p.theta.copy_from_slice(&v[k + n..k + 2 * n]);
                    p.height.copy_from_slice(&v[k + 2 * n..k + 3 * n]);
                    p.kappa0 = v[k + 3 * n];
                    let m = p.share.len();
                    p.share
                        .copy_from_slice(&v[k + 3 * n + 1..k + 3 * n + 1 + m]);
                    let (points, kappa) = frame.seed(&p);
                    d.points = points;
                    d.kappa = kappa;
                    k += 3 * n + 1 + m;
                }
            }
        }
        d
    }

    /// The cost of the design at `x`.
    fn cost_at(&self, x: &[f64]) -> f64 {
        let d = self.design_at(x);
        match grown(&d) {
            Ok(lattice) => cost(&d, &lattice, self.opt, &measure(&d, &lattice)).0,
            Err(missing) => UNGROWN * (1.0 + missing as f64),
        }
    }
}

impl Problem<'_> {
    /// The cost of the design at `x`, counted and kept if it is the best.
    fn evaluate(&self, x: &[f64]) -> f64 {
        if self.out_of_time() {
            return UNGROWN;
        }
        let cost = self.space.cost_at(x);
        self.record(x, cost);
        cost
    }

    /// The costs of the designs at `xs`, `jobs` at a time (a population:
    /// a bent lattice's simulated shape takes a second a design), recorded
    /// in their order, so the counts, the best design and the progress
    /// notes are those of one at a time.
    fn evaluate_all(&self, xs: &[Vec<f64>]) -> Vec<f64> {
        if self.out_of_time() {
            return vec![UNGROWN; xs.len()];
        }
        let mut costs = Vec::with_capacity(xs.len());
        let space = &self.space;
        crate::jobs::Jobs::new(self.jobs).in_order(
            xs.len(),
            |k| space.cost_at(&xs[k]),
            |k, cost| {
                self.record(&xs[k], cost);
                costs.push(cost);
            },
        );
        costs
    }

    /// Whether the deadline has passed (noting how many designs were
    /// costed by then): the search's remaining designs are then not
    /// costed, and `optimise` reports where it stopped.
    fn out_of_time(&self) -> bool {
        if self.stopped.get().is_none() && self.space.design.deadline.expired() {
            self.stopped.set(Some(self.evaluations.get()));
        }
        self.stopped.get().is_some()
    }

    /// Count a design costed; keep it if it is the best so far.
    fn record(&self, x: &[f64], cost: f64) {
        let n = self.evaluations.get() + 1;
        self.evaluations.set(n);
        let mut best = self.best.borrow_mut();
        if cost < best.0 {
            *best = (cost, x.to_vec());
        }
        if n.is_multiple_of(25) {
            (self.progress.borrow_mut())(&format!(
                "optimise: {n} designs tried, best cost {:.6}",
                best.0
            ));
        }
    }
}

/// Grow a design; the error says how many rows or cells it missed.
fn grown(d: &Design) -> Result<Lattice, usize> {
    if d.kind == Kind::Helix {
        let (lattice, _) =
            crate::lattice::grow_helix_partial(d.dim, &d.points, &d.kappa, d.helix_cells)
                .map_err(|_| d.helix_cells)?;
        let missing = d.helix_cells.saturating_sub(lattice.cells.len());
        return if missing == 0 {
            Ok(lattice)
        } else {
            Err(missing)
        };
    }
    d.grow().map_err(|_| 1)
}

/// Every angle of a front's moves, in a fixed order.
fn map_front(f: &mut FrontMoves, mut g: impl FnMut(f64) -> f64) {
    for list in [&mut f.turn, &mut f.bend, &mut f.twist]
        .into_iter()
        .flatten()
    {
        for a in list.iter_mut() {
            *a = g(*a);
        }
    }
    for p in &mut f.pivots {
        p.angle_deg = g(p.angle_deg);
    }
    for c in &mut f.cranks {
        c.angle_deg = g(c.angle_deg);
    }
}

/// Optimise a design as its `[optimise]` table says. `source` is the
/// recipe text (rewritten with the result); `progress` hears every 25
/// designs tried, and first the estimate when the search is long
/// (`Estimate::said`, told by `Estimate::is_said`). Refuses with a located error when the best design found
/// misses a hard constraint, naming it and its shortfall.
pub fn optimise(
    design: &Design,
    source: &str,
    jobs: usize,
    progress: &mut dyn FnMut(&str),
) -> Result<Optimised, Diagnostic> {
    let opt = design.optimise.as_ref().ok_or_else(|| {
        Diagnostic::new(
            ErrorKind::NoOptimiseTable,
            "the recipe has no [optimise] table",
        )
        .hint("add [optimise] with `vary` and objectives (see README)")
    })?;
    let (slots, mut x0, mut unit) = slots(design, source, opt);
    let (frame, seed0) = if slots.iter().any(|s| matches!(s, Slot::Seed)) {
        let (f, p) = seed_variables(design, &mut x0, &mut unit);
        (Some(f), Some(p))
    } else {
        (None, None)
    };
    check_variables(design, source, opt, &slots, &x0)?;
    let dims = x0.len();
    let problem = Problem {
        space: Space {
            design,
            opt,
            slots,
            x0,
            unit,
            frame,
            seed0,
        },
        jobs,
        evaluations: Cell::new(0),
        stopped: Cell::new(None),
        best: RefCell::new((f64::INFINITY, vec![0.0; dims])),
        progress: RefCell::new(progress),
    };
    let start = vec![0.0; dims];
    let clock = std::time::Instant::now();
    let cost_before = problem.evaluate(&start);
    within_time(&problem, opt, dims, clock.elapsed().as_secs_f64())?;
    let iterations = search(&problem, opt, dims);
    if let Some(done) = problem.stopped.get() {
        let stopped = design.deadline.stopped(done, designs(opt, dims), "designs");
        return Err(Diagnostic::new(
            ErrorKind::TimeLimit,
            format!("the optimiser {stopped} (the most the budget may try)"),
        )
        .hint("nothing was written; allow more time with --time-limit SECONDS, or lower [optimise] budget (docs/commands.md, Time limits)"));
    }
    let best = problem.best.borrow().1.clone();
    let optimised = problem.space.design_at(&best);
    let text = rewrite(&problem, &optimised, source, &best);
    let (design_out, cost_after, m) = judge(&text, &design.name, opt)?;
    let evaluations = problem.evaluations.get();
    Ok(Optimised {
        text,
        design: design_out,
        cost_before,
        cost_after,
        iterations,
        evaluations,
        variables: dims,
        measures: m,
    })
}

/// The most designs a search of `opt.budget` may cost: Nelder-Mead about
/// two an iteration and a simplex a restart, the evolution strategy its
/// population and mean a generation (`evolve`).
fn designs(opt: &Optimise, dims: usize) -> usize {
    let per = match opt.method {
        Method::NelderMead => 2,
        Method::Evolution => (4 + (3.0 * (dims as f64).ln()) as usize).max(8) + 5,
    };
    opt.budget.saturating_mul(per).saturating_add(dims + 1)
}

/// Refuse a search reckoned longer than the design's deadline allows:
/// its most designs at the first design's measured `seconds` each, the
/// evolution strategy's spread over its jobs (docs/commands.md, "Time
/// limits"). Long searches that are allowed say their estimate first.
fn within_time(
    problem: &Problem,
    opt: &Optimise,
    dims: usize,
    seconds: f64,
) -> Result<(), Diagnostic> {
    let deadline = &problem.space.design.deadline;
    let threads = match opt.method {
        Method::Evolution => problem.jobs.max(1) as f64,
        Method::NelderMead => 1.0,
    };
    let per = seconds / threads;
    let build = final_build_seconds(problem.space.design);
    let estimate = per * designs(opt, dims) as f64 + build;
    let say = crate::budget::duration;
    if deadline.allows(estimate) {
        let said = crate::budget::Estimate {
            seconds: estimate,
            what: format!(
                "optimiser: up to {} designs of ~{} each, then ~{} to build the best",
                crate::budget::count(designs(opt, dims) as f64),
                say(seconds),
                say(build)
            ),
        }
        .said(deadline);
        if let Some(line) = said {
            (problem.progress.borrow_mut())(&line);
        }
        return Ok(());
    }
    let per_iteration = (designs(opt, dims) - dims - 1) as f64 / opt.budget as f64;
    let fits = (((deadline.ceiling() - build) / per - (dims + 1) as f64) / per_iteration).floor();
    let budget = if fits >= 1.0 {
        format!(
            "[optimise] budget = {} or less (now {}), ",
            fits as usize, opt.budget
        )
    } else {
        String::new()
    };
    Err(Diagnostic::new(
        ErrorKind::WorkTooLong,
        format!(
            "the optimiser may cost up to {} designs at about {} each (the recipe's own took that) and about {} to build the best, about {} in all, longer than the {} allowed",
            designs(opt, dims),
            say(seconds),
            say(build),
            say(estimate),
            say(deadline.ceiling())
        ),
    )
    .at(opt.span.clone())
    .hint(format!(
        "use {budget}a cheaper objective (shape = \"design\" measures without simulating), or allow more time with --time-limit SECONDS (docs/commands.md, Time limits)"
    )))
}

/// The build `tune` makes of the best design, to be sure `build` takes
/// it: reckoned as the start design's simulation (`sim::reckoned`, the
/// deployment path included), which the best resembles; 0 when the start
/// does not grow or needs no simulation.
fn final_build_seconds(design: &Design) -> f64 {
    let Ok(lattice) = grown(design) else {
        return 0.0;
    };
    let deployment = crate::lattice::deploy::deployment(&lattice);
    if !crate::sim::wanted(&lattice, &deployment) {
        return 0.0;
    }
    crate::sim::reckoned(&lattice, &design.simulation).2
}

/// A helix seed's variables (`solve::tune`), appended to `x0` and `unit`:
/// each point's radius, angle and height, kappa at the start, and each
/// edge's share of the rest; with the frame they are measured in.
fn seed_variables(design: &Design, x0: &mut Vec<f64>, unit: &mut Vec<f64>) -> (Frame, Params) {
    let n = design.points.len() - 1;
    let centre = design.points[..n].iter().sum::<DVec3>() / n as f64;
    let f = Frame {
        centre,
        dim: design.dim,
    };
    let p = f.params(&design.points, &design.kappa);
    for r in &p.rho {
        x0.push(*r);
        unit.push(1.0);
    }
    for (t, r) in p.theta.iter().zip(&p.rho) {
        x0.push(*t);
        unit.push(1.0 / r.max(1.0));
    }
    for h in &p.height {
        x0.push(*h);
        unit.push(1.0);
    }
    x0.push(p.kappa0);
    unit.push(1.0);
    for s in &p.share {
        x0.push(*s);
        unit.push(0.01);
    }
    (f, p)
}

/// Refuses a search with no variables, or one that would rewrite a seed
/// the recipe does not write as points.
fn check_variables(
    design: &Design,
    source: &str,
    opt: &Optimise,
    slots: &[Slot],
    x0: &[f64],
) -> Result<(), Diagnostic> {
    if x0.is_empty() {
        return Err(Diagnostic::new(
            ErrorKind::NothingToVary,
            "the optimiser has nothing to vary in this recipe",
        )
        .at(opt.span.clone())
        .hint("vary \"angle\" needs rows with `angle = ...`, \"front\" rows with `front = { ... }`, \"seed\" a helix seed"));
    }
    // Only a seed written as `points = [...]` reads back as written (an
    // arc's table would be overwritten by a list).
    let reads_back = || {
        design
            .with_seed(source, &design.points, &design.kappa)
            .and_then(|t| crate::design::parse(&t, &design.name).ok())
            .is_some_and(|again| again.points == design.points && again.kappa == design.kappa)
    };
    if slots.iter().any(|s| matches!(s, Slot::Rim { .. })) && !reads_back() {
        return Err(Diagnostic::new(
            ErrorKind::NothingToVary,
            "vary \"seed\" rewrites the seed, which this recipe does not write as points",
        )
        .at(opt.span.clone())
        .hint("write the seed as `points = [[x, y], ...]` on the circle and `kappa = [...]`, one per edge"));
    }
    Ok(())
}

/// The search `opt.method` names, from the recipe's point (0) while the
/// budget lasts; gives the iterations used. The best point found is in
/// `problem.best`.
fn search(problem: &Problem, opt: &Optimise, dims: usize) -> usize {
    let mut rng = Rng::new(opt.seed ^ 0x6b61_7269_6761_6d69);
    let (mut iterations, mut round) = (0usize, 0usize);
    if opt.method == Method::Evolution {
        iterations = evolve(problem, opt, dims, &mut rng);
    }
    while opt.method == Method::NelderMead && iterations < opt.budget {
        let from = problem.best.borrow().1.clone();
        // Each restart a smaller simplex with fresh signs, about the best so far.
        let step = opt.step / (1.0 + round as f64);
        let mut simplex = vec![from.clone()];
        for i in 0..dims {
            let mut v = from.clone();
            let sign = if rng.next_u64() & 1 == 0 { 1.0 } else { -1.0 };
            v[i] += sign * step;
            simplex.push(v);
        }
        let left = opt.budget - iterations;
        let used = simplex::minimise(simplex, 1e-9, left, &mut |x| problem.evaluate(x));
        iterations += used.max(1);
        round += 1;
        if used < 2 && round > 3 {
            break;
        }
    }
    iterations
}

/// Judges what is written: the recipe `text` as it will be read back,
/// grown, measured and costed. Refused, located, when it misses a hard
/// constraint, naming it and its shortfall.
fn judge(text: &str, name: &str, opt: &Optimise) -> Result<(Design, f64, Measures), Diagnostic> {
    let design_out = crate::design::parse(text, name)?;
    let lattice = grown(&design_out).map_err(|_| {
        Diagnostic::new(
            ErrorKind::OptimiseFailed,
            "no design the optimiser tried grows every row",
        )
        .at(opt.span.clone())
        .hint("start from a recipe that grows, or loosen the hard constraints")
    })?;
    let m = measure(&design_out, &lattice);
    let (cost_after, checks) = cost(&design_out, &lattice, opt, &m);
    if let Some(why) = cost::refused(&design_out, &lattice, &m) {
        return Err(Diagnostic::new(
            ErrorKind::ConstraintNotMet,
            format!("the best design found is one that build refuses: {why}"),
        )
        .at(opt.span.clone())
        .hint(format!(
            "vary more of the recipe, raise optimise.budget (now {}), or change the sheet or strips",
            opt.budget
        )));
    }
    if let Some((name, value, bound, _)) = checks.iter().find(|c| c.3 > 0.0) {
        let span = opt
            .require
            .iter()
            .find(|r| r.name == *name)
            .map(|r| r.span.clone());
        return Err(Diagnostic::new(
            ErrorKind::ConstraintNotMet,
            format!(
                "no admissible design meets require.{name} = {bound}: the best found has {}, short by {}",
                shown(*value),
                shown((value - bound).abs())
            ),
        )
        .at_opt(span)
        .hint(format!(
            "loosen require.{name}, vary more of the recipe, or raise optimise.budget (now {})",
            opt.budget
        )));
    }
    Ok((design_out, cost_after, m))
}

/// A constraint's number as the user can read it: four decimals, or four
/// significant digits when four decimals would show zero.
fn shown(x: f64) -> String {
    if x != 0.0 && x.abs() < 1e-3 {
        format!("{x:.3e}")
    } else {
        format!("{x:.4}")
    }
}
