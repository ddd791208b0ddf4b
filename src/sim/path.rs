//! The deployment path (docs/physics.md, "The deployment path"): the
//! structure followed by continuation in the held opening from its
//! equilibrium at the design opening down to nearly collapsed (does it
//! fold flat again?), then back up to the design (what deploying is like),
//! each step's solve started from the last step's equilibrium. Along the
//! way: the energy, the largest strain, the lowest eigenvalue, and the
//! jumps of the state between steps that mark a snap-through.

use super::solver::{Options, Stats, System};
use super::strips::LatticeModel;
use super::{Material, Simulation, results, shape_distance};
use crate::budget::Deadline;
use glam::DVec3;

/// The nearly collapsed end of the path: this share of the design's
/// opening.
pub const COLLAPSED: f64 = 0.1;

/// A step's state jump counts as a snap-through when it is at least this
/// many times the path's median jump, and at least `SNAP_MM`.
pub const SNAP_RATIO: f64 = 4.0;
/// The least jump (mm) of a snap-through: smaller ones are the smooth
/// motion of a small piece.
pub const SNAP_MM: f64 = 1.0;

/// Steps each way: at least this many, so the curve is a curve.
pub const MIN_STEPS: usize = 6;
/// At most this many steps each way.
pub const MAX_STEPS: usize = 24;
/// The opening a step covers, at most (radians): small enough that the
/// secant predictor lands near the next equilibrium and Newton takes a few
/// iterations (docs/physics.md, "The deployment path": fewer, longer steps
/// cost more iterations in all).
pub const PATH_STEP: f64 = 4.0 * std::f64::consts::PI / 180.0;

/// One step of the path: its equilibrium's figures.
#[derive(Clone, Debug, PartialEq)]
pub struct PathPoint {
    /// The held opening (radians).
    pub theta: f64,
    /// Elastic energy (N mm).
    pub energy: f64,
    /// Largest corner-fibre strain (fraction) and the strip.
    pub strain: f64,
    /// The strip of the largest strain.
    pub rod: String,
    /// Lowest eigenvalue of the scaled Hessian (positive: stable).
    pub lambda_min: f64,
    /// Largest joint move from the last step's equilibrium (mm).
    pub jump: f64,
    /// Newton iterations of the step, its splits and retries included.
    pub iterations: usize,
    /// The smallest and largest cell opening (radians).
    pub openings: (f64, f64),
    /// Whether the step leapt: no equilibrium near the last one even with
    /// the step halved (a fold of the path), so the whole step was solved
    /// from the last equilibrium with the build's own iteration cap and
    /// landed on another branch, a snap-through.
    pub leapt: bool,
    /// Every vertex, then every pivot.
    pub points: Vec<DVec3>,
}

/// The path both ways and what it says.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    /// The design opening the path starts and ends at (radians).
    pub design: f64,
    /// The nearly collapsed end (radians).
    pub low: f64,
    /// Steps each way, as planned.
    pub steps: usize,
    /// Newton iterations the path took, and its budget.
    pub iterations: usize,
    /// The most Newton iterations the path may take.
    pub budget: usize,
    /// From the design's equilibrium down to `low`, the start first.
    pub collapse: Vec<PathPoint>,
    /// From `low` back up to the design, its first point `low`'s.
    pub deploy: Vec<PathPoint>,
    /// Where a step found no equilibrium: the opening tried and why.
    pub failed: Option<(f64, String)>,
    /// The deployed end against the build's equilibrium: largest distance
    /// after the best rigid fit (mm); None when the path did not get there.
    pub end_distance: Option<f64>,
    /// Largest distance between the collapse and the deploy at the same
    /// opening (mm): a path that differs going back is bistable there.
    pub hysteresis: f64,
}

impl Path {
    /// Steps each way: one per `PATH_STEP` of the way, within `MIN_STEPS`
    /// to `MAX_STEPS`, whatever the model's size (`free`, its free
    /// variables: a large model's longer steps would cost more).
    pub fn step_count(_free: usize, design: f64) -> usize {
        let way = design * (1.0 - COLLAPSED);
        ((way / PATH_STEP).ceil() as usize).clamp(MIN_STEPS, MAX_STEPS)
    }

    /// Every point in the order walked: the collapse, then the deploy.
    pub fn points(&self) -> impl Iterator<Item = &PathPoint> {
        self.collapse.iter().chain(&self.deploy)
    }

    /// Steps (of either way) whose state jump marks a snap-through, or
    /// whose equilibrium is not stable, as (way, index): way 0 the
    /// collapse, 1 the deploy.
    pub fn snaps(&self) -> Vec<(usize, usize)> {
        let mut jumps: Vec<f64> = self
            .points()
            .filter(|p| p.jump > 0.0)
            .map(|p| p.jump)
            .collect();
        let median = if jumps.is_empty() {
            0.0
        } else {
            let mid = jumps.len() / 2;
            *jumps.select_nth_unstable_by(mid, f64::total_cmp).1
        };
        let limit = (SNAP_RATIO * median).max(SNAP_MM);
        let mut out = Vec::new();
        for (w, way) in [&self.collapse, &self.deploy].into_iter().enumerate() {
            for (i, p) in way.iter().enumerate() {
                if p.leapt || p.jump > limit || !(p.lambda_min > 0.0) {
                    out.push((w, i));
                }
            }
        }
        out
    }

    /// The first point strained beyond `allow`, if any.
    pub fn overstrained(&self, allow: f64) -> Option<&PathPoint> {
        self.points().find(|p| p.strain > allow)
    }

    /// The largest strain along the path.
    pub fn peak_strain(&self) -> Option<&PathPoint> {
        self.points()
            .fold(None, |best: Option<&PathPoint>, p| match best {
                Some(b) if !(p.strain > b.strain) => Some(b),
                _ => Some(p),
            })
    }

    /// Whether the collapse reached the nearly collapsed end with every
    /// cell closed (none inverted, none left open past twice that end).
    pub fn folds_flat(&self) -> bool {
        self.collapse.last().is_some_and(|p| {
            self.collapse.len() > 1
                && (p.theta - self.low).abs() < 1e-9
                && p.openings.0 > 0.0
                && p.openings.1 <= 2.0 * self.low
        })
    }
}

/// The path of `lm`, at its equilibrium at the design opening (as `simulate`
/// leaves it), `steps` steps each way (`Path::step_count`).
pub fn path(lm: &LatticeModel, stats: &Stats, steps: usize, material: &Material) -> Path {
    follow(lm, stats, steps, material).0
}

/// `path`, and the model at the deployed end with its solve's statistics
/// when the deploy reached the design opening: the state a build reports
/// (docs/physics.md, "The chosen equilibrium").
pub fn follow(
    lm: &LatticeModel,
    stats: &Stats,
    steps: usize,
    material: &Material,
) -> (Path, Option<(LatticeModel, Stats)>) {
    follow_until(lm, stats, steps, material, &Deadline::none())
}

/// `follow`, each solve stopped at `deadline` (src/budget.rs): the path then
/// ends short, and the caller reports the time limit.
fn follow_until(
    lm: &LatticeModel,
    stats: &Stats,
    steps: usize,
    material: &Material,
    deadline: &Deadline,
) -> (Path, Option<(LatticeModel, Stats)>) {
    let mut lm = lm.clone();
    let design = lm.held_opening();
    let low = COLLAPSED * design;
    let start = point(&lm, stats, material, None);
    let mut walker = Walker {
        sys: System::new(&lm.model),
        left: budget(steps),
        material,
        deadline: deadline.at(),
    };
    let budget = walker.left;
    let (collapse, mut failed, _) = walker.way(&mut lm, low, steps, start);
    let mut deploy = Vec::new();
    let mut end = None;
    if failed.is_none() {
        let mut first = collapse.last().expect("the start").clone();
        first.jump = 0.0;
        let (way, why, last) = walker.way(&mut lm, design, steps, first);
        deploy = way;
        failed = why;
        end = last.filter(|_| failed.is_none()).map(|s| (lm, s));
    }
    let end_distance = end
        .as_ref()
        .and(deploy.last())
        .map(|e| shape_distance(&e.points, &collapse[0].points).max);
    // The collapse's step k and the deploy's step n - k are at one opening
    // (both ways walked in full).
    let hysteresis = if end_distance.is_some() {
        collapse
            .iter()
            .zip(deploy.iter().rev())
            .map(|(a, b)| shape_distance(&a.points, &b.points).max)
            .fold(0.0, f64::max)
    } else {
        0.0
    };
    let path = Path {
        design,
        low,
        steps,
        iterations: budget - walker.left,
        budget,
        collapse,
        deploy,
        failed,
        end_distance,
        hysteresis,
    };
    (path, end)
}

/// The simulation at the state it reports (docs/physics.md, "The chosen
/// equilibrium"): the deployment path's deployed end when the path got
/// there, else the equilibrium solved from the design; with the path
/// (`Path::step_count` steps each way for the model's size).
pub fn chosen(run: Simulation, material: &Material) -> (Simulation, Option<Path>) {
    chosen_until(run, material, &Deadline::none())
}

/// `chosen`, the path's solves stopped at `deadline`: a caller that gave
/// one checks it afterwards and reports the time limit, not the short path.
pub fn chosen_until(
    run: Simulation,
    material: &Material,
    deadline: &Deadline,
) -> (Simulation, Option<Path>) {
    let clock = std::time::Instant::now();
    let free = run.lm.model.fixed.iter().filter(|f| !**f).count();
    let steps = Path::step_count(free, run.theta);
    if !run.lm.pins.is_empty() {
        return pinned(run, steps, material, deadline);
    }
    let (path, end) = follow_until(&run.lm, &run.equilibrium.stats, steps, material, deadline);
    // Back at the state solved from the design (within `SAME_MM`): that
    // solve's numbers, not the round trip's few ulp away from them.
    let home = path.end_distance.is_some_and(|d| d <= SAME_MM);
    let run = match end.filter(|_| !home) {
        Some((lm, stats)) => Simulation {
            equilibrium: super::equilibrium(&lm, stats, material),
            theta: lm.held_opening(),
            lm,
            iterations: run.iterations + path.iterations,
            steps: run.steps + path.collapse.len() + path.deploy.len() - 2,
            seconds: run.seconds + clock.elapsed().as_secs_f64(),
        },
        None => run,
    };
    (run, Some(path))
}

/// A lattice held at its supports: the path of the lattice standing free
/// (its pins released, `LatticeModel::released`), which a maker deploys
/// before pinning its feet, and the state solved from the design with the
/// pins held, whatever the path's end (docs/physics.md, "Supports"). No
/// path when the free lattice finds no equilibrium at the design opening.
fn pinned(
    run: Simulation,
    steps: usize,
    material: &Material,
    deadline: &Deadline,
) -> (Simulation, Option<Path>) {
    let mut free = run.lm.released();
    let opts = Options {
        deadline: deadline.at(),
        ..Options::default()
    };
    let path = super::deploy(&mut free, None, &opts)
        .ok()
        .map(|(stats, _, _)| follow_until(&free, &stats, steps, material, deadline).0);
    (run, path)
}

/// Two states closer than this (mm, largest joint distance after the best
/// rigid fit) are one.
pub const SAME_MM: f64 = 1e-3;

/// Newton iterations of one solve of the path: a step from a nearby
/// equilibrium takes a few; one that needs more is split instead
/// (docs/physics.md, "The deployment path").
pub const STEP_ITERATIONS: usize = 40;
/// A step that finds no equilibrium is halved, at most this many times
/// (to 1/16 of a step).
pub const SPLITS: u32 = 4;

/// The path's bound on Newton iterations: `STEP_ITERATIONS` for every
/// step both ways, twice over (room for splits on part of the way); a
/// deterministic bound, not the machine's speed.
fn budget(steps: usize) -> usize {
    2 * steps * 2 * STEP_ITERATIONS
}

/// Why a path stops when its bound is reached.
const BOUND: &str = "the path's bound on Newton iterations was reached";

/// What walks the path: the Newton system, the iterations left and the
/// material the strains are judged in.
struct Walker<'a> {
    sys: System,
    left: usize,
    material: &'a Material,
    /// When the run's `--time-limit` passes: every solve stops there.
    deadline: Option<std::time::Instant>,
}

/// A way walked: its points, why it stopped short (the opening tried and
/// why), and the last solve's statistics.
type Way = (Vec<PathPoint>, Option<(f64, String)>, Option<Stats>);

impl Walker<'_> {
    /// Walk to `target` in `n` steps, each step's point recorded after
    /// `first`; each solve starts from the last equilibrium moved along
    /// the last step's change (the secant predictor), and a step that
    /// finds no equilibrium is split in halves (`SPLITS`). The first step
    /// that finds none even so, or a spent budget, ends the way.
    fn way(&mut self, lm: &mut LatticeModel, target: f64, n: usize, first: PathPoint) -> Way {
        let from = lm.held_opening();
        let at = |k: usize| from + (target - from) * k as f64 / n as f64;
        let mut out = vec![first];
        let mut back: Option<(Vec<f64>, f64)> = None;
        let mut last = None;
        for k in 1..=n {
            let (here, phi) = (lm.model.q.clone(), lm.held_opening());
            let left = self.left;
            let (stats, leapt) = match self.step(lm, back.as_ref(), at(k), 0) {
                Ok(stats) => (stats, false),
                Err(why) => match self.leap(lm, at(k)) {
                    Some(stats) => (stats, true),
                    None => return (out, Some((at(k), why)), last),
                },
            };
            let mut p = point(lm, &stats, self.material, out.last().map(|p| &p.points));
            p.iterations = left - self.left;
            p.leapt = leapt;
            out.push(p);
            last = Some(stats);
            back = Some((here, phi));
            if self.left == 0 && k < n {
                return (out, Some((at(k + 1), BOUND.to_string())), last);
            }
        }
        (out, None, last)
    }

    /// Solve at the held opening `phi` from the current equilibrium,
    /// predicted from `back` (the equilibrium and opening one step back)
    /// when given; split in two when that fails, `depth` splits deep.
    fn step(
        &mut self,
        lm: &mut LatticeModel,
        back: Option<&(Vec<f64>, f64)>,
        phi: f64,
        depth: u32,
    ) -> Result<Stats, String> {
        let (here, from, frames) = (lm.model.q.clone(), lm.held_opening(), lm.model.frames());
        let restore = |lm: &mut LatticeModel| {
            lm.model.q.clone_from(&here);
            lm.model.set_frames(&frames);
            lm.set_held_opening(from);
        };
        if let Some((q, theta)) = back {
            predict(&mut lm.model, q, *theta, from, phi);
        }
        lm.set_held_opening(phi);
        let mut why = match self.solve(lm) {
            Ok(s) => return Ok(s),
            Err(e) => e,
        };
        restore(lm);
        if back.is_some() {
            // The prediction overshot (a fold of the path): from the last
            // equilibrium as it is.
            lm.set_held_opening(phi);
            match self.solve(lm) {
                Ok(s) => return Ok(s),
                Err(e) => why = e,
            }
            restore(lm);
        }
        if self.left == 0 {
            return Err(BOUND.to_string());
        }
        if depth >= SPLITS {
            return Err(format!(
                "{why}, the step halved {SPLITS} times (to {:.2} deg)",
                (phi - from).abs().to_degrees()
            ));
        }
        let mid = 0.5 * (from + phi);
        self.step(lm, None, mid, depth + 1)?;
        let half = (here, from);
        self.step(lm, Some(&half), phi, depth + 1)
    }

    /// Past a fold: the held opening set to `phi` and solved from the last
    /// equilibrium with the build's own cap (`Options::default`, within
    /// the budget); the equilibrium it lands on, if any.
    fn leap(&mut self, lm: &mut LatticeModel, phi: f64) -> Option<Stats> {
        lm.set_held_opening(phi);
        let cap = Options::default().max_iterations;
        self.solve_within(lm, cap).ok()
    }

    /// One Newton solve of at most `STEP_ITERATIONS` (and the budget
    /// left), its iterations taken from the budget; a stable equilibrium
    /// or why not.
    fn solve(&mut self, lm: &mut LatticeModel) -> Result<Stats, String> {
        self.solve_within(lm, STEP_ITERATIONS)
    }

    /// `solve` with at most `cap` iterations.
    fn solve_within(&mut self, lm: &mut LatticeModel, cap: usize) -> Result<Stats, String> {
        let opts = Options {
            max_iterations: cap.min(self.left.max(1)),
            deadline: self.deadline,
        };
        let s = super::solver::solve(&mut lm.model, &self.sys, &opts);
        let used = match &s {
            Ok(s) => s.iterations,
            Err(_) => opts.max_iterations,
        };
        self.left = self.left.saturating_sub(used);
        match s {
            Ok(s) if s.converged => Ok(s),
            Ok(s) => Err(format!(
                "Newton did not converge in {} iterations",
                s.iterations
            )),
            Err(e) => Err(e.to_string()),
        }
    }
}

/// Move the free variables of `m` from the equilibrium `q` at opening
/// `at` along the secant from `back` (at `before`), to the opening `to`.
fn predict(m: &mut super::model::Model, back: &[f64], before: f64, at: f64, to: f64) {
    let r = if (at - before).abs() > 0.0 {
        (to - at) / (at - before)
    } else {
        0.0
    };
    let here = m.q.clone();
    for (i, q) in m.q.iter_mut().enumerate() {
        if !m.fixed[i] {
            *q = here[i] + r * (here[i] - back[i]);
        }
    }
    m.apply_ties();
    m.update_frames();
}

/// The figures of `lm`'s equilibrium now; its jump from `last`.
fn point(
    lm: &LatticeModel,
    stats: &Stats,
    material: &Material,
    last: Option<&Vec<DVec3>>,
) -> PathPoint {
    let m = &lm.model;
    let strain = results::strain_peak(m, material.youngs, material.shear());
    let points = lm.points();
    let jump = last.map_or(0.0, |l| {
        l.iter()
            .zip(&points)
            .map(|(a, b)| a.distance(*b))
            .fold(0.0, f64::max)
    });
    let openings = (0..lm.delta.len())
        .map(|c| lm.opening(c))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    PathPoint {
        theta: lm.held_opening(),
        energy: m.energy(),
        strain: strain.eps,
        rod: strain.rod,
        lambda_min: stats.lambda_min,
        jump,
        iterations: stats.iterations,
        openings,
        leapt: false,
        points,
    }
}

/// How the path's report says what it walks.
#[derive(Clone, Copy, Debug)]
pub struct Walked {
    /// The opening held (the design's own is the path's top).
    pub held: crate::design::settings::Actuation,
    /// Whether the lattice is held at supports, which the path walks
    /// released (docs/physics.md, "Supports").
    pub free: bool,
}

impl Path {
    /// The path in words: a line per way (energy, the largest strain and
    /// where, snap-throughs), whether it folds flat again, where the
    /// deploy ends against the build's equilibrium, and, with `table`, a
    /// line per step. Strains are judged against `allow` (a fraction).
    pub fn text(&self, allow: f64, table: bool, walked: Walked) -> String {
        use std::fmt::Write as _;
        let mut o = String::new();
        let deg = f64::to_degrees;
        let (whose, start) = if walked.free {
            (
                " of the lattice standing free, its supports released (\"Supports\")",
                "its free equilibrium at the design opening",
            )
        } else {
            ("", "the build's equilibrium")
        };
        let _ = writeln!(
            o,
            "deployment path (docs/physics.md){whose}: from the design's {}, {:.1} deg, down to {:.1} deg and back, {} steps each way; {} of its {} Newton iterations",
            walked.held.describe(),
            deg(self.design),
            deg(self.low),
            self.steps,
            self.iterations,
            self.budget
        );
        let snaps = self.snaps();
        for (w, (name, way)) in [("collapsing", &self.collapse), ("deploying", &self.deploy)]
            .into_iter()
            .enumerate()
        {
            let (Some(first), Some(last)) = (way.first(), way.last()) else {
                continue;
            };
            let peak = way
                .iter()
                .fold(first, |b, p| if p.strain > b.strain { p } else { b });
            let here: Vec<String> = snaps
                .iter()
                .filter(|s| s.0 == w)
                .map(|&(_, i)| {
                    let p = &way[i];
                    format!(
                        "at {:.1} deg (joints jump {:.1} mm, energy {:.3} -> {:.3} N mm{}{})",
                        deg(p.theta),
                        p.jump,
                        way[i.saturating_sub(1)].energy,
                        p.energy,
                        if p.leapt {
                            ", past a fold of the path"
                        } else {
                            ""
                        },
                        if p.lambda_min > 0.0 {
                            ""
                        } else {
                            ", not stable"
                        }
                    )
                })
                .collect();
            let _ = writeln!(
                o,
                "  {name}: energy {:.3} to {:.3} N mm, largest strain {:.2} %{} at {:.1} deg ({}); snap-throughs: {}",
                first.energy,
                last.energy,
                100.0 * peak.strain,
                if peak.rod.is_empty() {
                    String::new()
                } else {
                    format!(" (strip {})", peak.rod)
                },
                deg(peak.theta),
                if peak.strain > allow {
                    "ABOVE the allowable"
                } else {
                    "within the allowable"
                },
                if here.is_empty() {
                    "none".to_string()
                } else {
                    here.join("; ")
                }
            );
        }
        if let Some((theta, why)) = &self.failed {
            let last = self.deploy.last().or(self.collapse.last());
            let _ = writeln!(
                o,
                "  no equilibrium found at {:.1} deg: {why}{}",
                deg(*theta),
                last.map_or(String::new(), |p| format!(
                    "; the path stops at {:.1} deg, strained {:.2} % there",
                    deg(p.theta),
                    100.0 * p.strain
                ))
            );
        }
        let _ = writeln!(
            o,
            "  folds flat again: {}",
            if self.folds_flat() {
                let p = self.collapse.last().expect("a point");
                format!(
                    "yes (every cell between {:.1} and {:.1} deg at {:.1} deg)",
                    deg(p.openings.0),
                    deg(p.openings.1),
                    deg(self.low)
                )
            } else if let Some(p) = self
                .collapse
                .last()
                .filter(|p| (p.theta - self.low).abs() < 1e-9)
            {
                format!(
                    "no (cells between {:.1} and {:.1} deg at {:.1} deg)",
                    deg(p.openings.0),
                    deg(p.openings.1),
                    deg(self.low)
                )
            } else {
                "not known (the collapse stopped on the way)".to_string()
            }
        );
        if let Some(d) = self.end_distance {
            let _ = writeln!(
                o,
                "  deployed again, the piece ends {d:.3} mm from {start} ({}); collapsing and deploying differ by up to {:.3} mm at one opening",
                if d <= 1e-3 {
                    "the same state"
                } else {
                    "another state"
                },
                self.hysteresis
            );
        }
        if table {
            let _ = writeln!(
                o,
                "  {:>9} {:>9} {:>14} {:>9} {:>11} {:>9} {:>7}",
                "way", "theta", "energy", "strain", "lambda_min", "jump", "newton"
            );
            for (name, way) in [("collapse", &self.collapse), ("deploy", &self.deploy)] {
                for p in way {
                    let _ = writeln!(
                        o,
                        "  {name:>9} {:>9.2} {:>14.6e} {:>8.3}% {:>11.3e} {:>9.3} {:>7}",
                        deg(p.theta),
                        p.energy,
                        100.0 * p.strain,
                        p.lambda_min,
                        p.jump,
                        p.iterations
                    );
                }
            }
        }
        o
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(theta: f64, jump: f64, lambda_min: f64) -> PathPoint {
        PathPoint {
            theta,
            energy: 0.0,
            strain: 0.0,
            rod: String::new(),
            lambda_min,
            jump,
            iterations: 1,
            openings: (theta, theta),
            leapt: false,
            points: Vec::new(),
        }
    }

    #[test]
    fn a_jump_far_above_the_paths_median_or_an_unstable_step_is_a_snap() {
        let way = |jumps: &[f64]| -> Vec<PathPoint> {
            jumps
                .iter()
                .enumerate()
                .map(|(k, &j)| at(k as f64, j, 1.0))
                .collect()
        };
        let mut path = Path {
            design: 1.0,
            low: 0.1,
            steps: 4,
            iterations: 0,
            budget: 1,
            collapse: way(&[0.0, 2.0, 2.1, 1.9, 2.0]),
            deploy: way(&[0.0, 2.0, 9.0, 2.0, 2.0]),
            failed: None,
            end_distance: Some(0.0),
            hysteresis: 0.0,
        };
        assert_eq!(path.snaps(), vec![(1, 2)]);
        // Below 4 times the median: smooth.
        path.deploy[2].jump = 7.9;
        assert!(path.snaps().is_empty());
        // A small piece's jumps under SNAP_MM never count.
        for p in path.collapse.iter_mut().chain(&mut path.deploy) {
            p.jump *= 0.01;
        }
        path.deploy[2].jump = 0.9;
        assert!(path.snaps().is_empty());
        path.collapse[3].lambda_min = -1e-3;
        assert_eq!(path.snaps(), vec![(0, 3)]);
    }

    #[test]
    fn steps_follow_the_opening_within_the_bounds() {
        let deg = f64::to_radians;
        // 2 degrees a step over 90 % of the way, within 6 to 12.
        // 4 degrees a step over 90 % of the way, within 6 to 24.
        assert_eq!(Path::step_count(100, deg(60.0)), 14);
        assert_eq!(Path::step_count(100, deg(10.0)), MIN_STEPS);
        assert_eq!(Path::step_count(100, deg(150.0)), 24);
        assert_eq!(Path::step_count(100_000, deg(60.0)), 14);
    }
}
