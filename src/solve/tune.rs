//! The helix seed tuner (docs/math.md 6.3): untuned helix seeds degenerate after
//! about two turns, so a seeded hill climb moves the seed points (in
//! cylindrical coordinates about the seed's axis) and redistributes kappa
//! until the helix grows the cells the recipe asks for. Deterministic: the
//! same seed always tunes to the same numbers. Its work is reckoned from
//! the tries and cells asked before it starts (`tune_estimate`), and
//! refused beyond the time limit (docs/commands.md, "Time limits").

use crate::budget::{Estimate, count, duration};
use crate::design::Design;
use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::lattice::{Lattice, angle_between, grow_helix_partial};
use crate::rng::Rng;
use glam::DVec3;

/// The result of tuning, and how it differs from the start.
#[derive(Clone, Debug, PartialEq)]
pub struct Tuned {
    /// The tuned seed points (mm).
    pub points: Vec<DVec3>,
    /// The tuned kappa, one per seed edge (mm).
    pub kappa: Vec<f64>,
    /// Admissible cells before and after (capped at the target).
    pub cells_before: usize,
    /// Admissible cells the tuned seed grows (capped at the target).
    pub cells_after: usize,
    /// Random tries made.
    pub iterations: usize,
    /// Largest point move (mm) and largest kappa change (mm).
    pub max_move: f64,
    /// Largest kappa change (mm).
    pub max_kappa_change: f64,
}

/// Seed parameters: cylindrical coordinates of every point about the axis,
/// kappa_0, and the share of each kappa_1..kappa_(N-1) in their sum (which
/// the seed condition fixes).
#[derive(Clone, Debug)]
pub(crate) struct Params {
    pub(crate) rho: Vec<f64>,
    pub(crate) theta: Vec<f64>,
    pub(crate) height: Vec<f64>,
    pub(crate) kappa0: f64,
    pub(crate) share: Vec<f64>,
}

pub(crate) struct Frame {
    pub(crate) centre: DVec3,
    pub(crate) dim: usize,
}

impl Frame {
    pub(crate) fn params(&self, points: &[DVec3], kappa: &[f64]) -> Params {
        let n = points.len() - 1;
        let rel: Vec<DVec3> = points.iter().map(|p| *p - self.centre).collect();
        let rod_dz: f64 = -kappa[1..n].iter().sum::<f64>();
        Params {
            rho: rel.iter().map(|p| p.x.hypot(p.y)).collect(),
            theta: rel.iter().map(|p| p.y.atan2(p.x)).collect(),
            height: rel.iter().map(|p| p.z).collect(),
            kappa0: kappa[0],
            share: kappa[1..n].iter().map(|k| -k / rod_dz).collect(),
        }
    }

    /// Points and kappa, with kappa_1..kappa_(N-1) scaled to meet the seed
    /// condition exactly.
    pub(crate) fn seed(&self, p: &Params) -> (Vec<DVec3>, Vec<f64>) {
        let points: Vec<DVec3> = (0..p.rho.len())
            .map(|k| {
                let h = if self.dim == 3 { p.height[k] } else { 0.0 };
                self.centre
                    + DVec3::new(p.rho[k] * p.theta[k].cos(), p.rho[k] * p.theta[k].sin(), h)
            })
            .collect();
        let n = points.len() - 1;
        let rod = points[n].distance(points[1]);
        let total: f64 = p.share.iter().sum();
        let mut kappa = vec![p.kappa0];
        kappa.extend(p.share.iter().map(|s| -rod * s / total));
        (points, kappa)
    }
}

/// How the start seed winds: its axis, and per turn the factor its radius
/// shrinks by and the height it drops. The tuner keeps the grown helix
/// winding the same way, turn after turn, so that a bowl stays a bowl.
#[derive(Clone, Debug)]
struct Winding {
    centre: DVec3,
    /// The start seed's radii.
    radii: Vec<f64>,
    shrink: f64,
    drop: f64,
    edge: f64,
}

impl Winding {
    fn of(points: &[DVec3], centre: DVec3, edge: f64) -> Self {
        let n = points.len() - 1;
        let r = |p: DVec3| (p - centre).truncate().length();
        Self {
            centre,
            radii: points.iter().map(|p| r(*p)).collect(),
            shrink: r(points[n]) / r(points[0]).max(1e-9),
            drop: points[0].z - points[n].z,
            edge,
        }
    }

    /// Mean departure (in edge lengths) of every vertex after the first
    /// from one turn earlier scaled by `shrink` and lowered by `drop` (the
    /// seed's own turn against the spiral it started as, so that tuning
    /// keeps the seed regular too).
    fn departure(&self, lattice: &Lattice) -> f64 {
        let n = lattice.width;
        let pos: Vec<DVec3> = lattice
            .vertices
            .iter()
            .map(|v| v.pos - self.centre)
            .collect();
        let grown = pos.len().saturating_sub(n + 1);
        if grown == 0 {
            return 0.0;
        }
        let seed: f64 = (1..=n)
            .map(|k| {
                let (r0, r) = (self.radii[k], pos[k].truncate().length());
                let z = pos[k].z - (pos[0].z - self.drop * k as f64 / n as f64);
                (r - r0).hypot(z)
            })
            .sum();
        let total: f64 = seed
            + (n + 1..pos.len())
                .map(|k| {
                    let (now, before) = (pos[k], pos[k - n]);
                    let r = now.truncate().length() - self.shrink * before.truncate().length();
                    let z = now.z - (before.z - self.drop);
                    r.hypot(z)
                })
                .sum::<f64>();
        total / (grown + n) as f64 / self.edge
    }
}

/// Admissible cells (up to `target`, and only while every leg is at least
/// `min_leg`, so the eyelets fit) plus a quality below 1: the worst cell's
/// opening (sine of phi) and leg balance, so ties prefer robust cells. Once
/// the target is reached, the helix's departure from the start seed's
/// winding counts against the quality (first reach, then shape).
fn score(
    dim: usize,
    points: &[DVec3],
    kappa: &[f64],
    target: usize,
    min_leg: f64,
    winding: &Winding,
) -> (usize, f64) {
    match grow_helix_partial(dim, points, kappa, target) {
        Ok((mut lattice, _)) => {
            let usable = lattice
                .cells
                .iter()
                .position(|c| lattice.legs(c).iter().any(|&l| l < min_leg))
                .unwrap_or(lattice.cells.len());
            lattice.cells.truncate(usable);
            let grown = lattice.width + 1 + usable;
            lattice.vertices.truncate(grown.min(lattice.vertices.len()));
            let shape = if usable >= target {
                winding.departure(&lattice)
            } else {
                0.0
            };
            (usable, quality(&lattice) - shape)
        }
        Err(_) => (0, 0.0),
    }
}

fn quality(lattice: &Lattice) -> f64 {
    lattice
        .cells
        .iter()
        .map(|c| {
            let legs = lattice.legs(c);
            let lo = legs.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = legs.iter().copied().fold(0.0, f64::max);
            let [ul, ur, _, _] = lattice.corners(c);
            let phi = angle_between((c.pivot - ul).normalize(), (c.pivot - ur).normalize());
            phi.sin().min(lo / hi)
        })
        .fold(1.0, f64::min)
        * 0.999
}

/// Seconds a try of the tuner is reckoned at, whatever it grows (its seed
/// moved and remade), and for each cell it grows (grown, its legs checked,
/// its quality and winding read): release build on the 2-core machine of
/// BENCHMARKS.md, "Bounded work", 3,000 tries of templates/helix.toml's 12
/// cells in 15.5 ms and of fixtures/designs/helix-bowl.toml's 32 cells in 34.5 ms of CPU.
const SECONDS_PER_TRY: f64 = 1.5e-6;
const SECONDS_PER_TRY_CELL: f64 = 3.2e-7;

/// The tuner's work reckoned before it starts: `tries` tries of a seed
/// that grows `grown` of the `cells` asked. A try costs what it grows, and
/// tries start from the start seed, which untuned grows a few turns (the
/// bowl's 38 cells of 200 asked: 50,000 tries at 16.6 us a try); reckoned
/// low so that only what is surely too long is refused, the deadline stops
/// a search whose seeds grow on.
pub fn tune_estimate(grown: usize, cells: usize, tries: usize) -> Estimate {
    let per_try = SECONDS_PER_TRY + SECONDS_PER_TRY_CELL * grown.min(cells) as f64;
    Estimate {
        seconds: crate::budget::reckoned_low(per_try * tries as f64),
        what: format!(
            "helix tuner: up to {} tries of ~{} cells (the start seed grows {} of {}), ~{} a try",
            count(tries as f64),
            count(grown.min(cells).max(1) as f64),
            count(grown.min(cells) as f64),
            count(cells as f64),
            duration(per_try)
        ),
    }
}

/// Refuse a tune of the design's seed reckoned longer than its deadline
/// allows (`tune_estimate`, from the cells the start seed grows;
/// docs/commands.md, "Time limits"), at the recipe's `cells` unless
/// `--cells` asked for them (`flag`), saying the most tries that fit; else
/// its estimate, for a long one to be said first.
pub fn tune_within_time(
    design: &Design,
    (cells, tries): (usize, usize),
    flag: bool,
) -> Result<Estimate, Diagnostic> {
    let grown = grow_helix_partial(design.dim, &design.points, &design.kappa, cells)
        .map_or(0, |(lattice, _)| lattice.cells.len());
    let estimate = tune_estimate(grown, cells, tries);
    let deadline = &design.deadline;
    if deadline.allows(estimate.seconds) {
        return Ok(estimate);
    }
    let per_try = estimate.seconds / tries.max(1) as f64;
    let fits = (deadline.ceiling() / per_try).floor().max(1.0);
    let asked = if flag {
        "--cells"
    } else {
        "the recipe's `cells`"
    };
    Err(Diagnostic::new(
        ErrorKind::WorkTooLong,
        format!(
            "the helix tuner may make up to {} tries of a seed that grows {} of {} cells ({asked}) at about {} each, about {} in all, longer than the {} allowed",
            count(tries as f64),
            count(grown.min(cells) as f64),
            count(cells as f64),
            duration(per_try),
            duration(estimate.seconds),
            duration(deadline.ceiling())
        ),
    )
    .at_opt((!flag).then(|| design.size_span()))
    .hint(format!(
        "use --iterations {} or fewer (now {tries}), fewer cells, or allow more time with --time-limit SECONDS (docs/commands.md, Time limits)",
        fits as usize
    )))
}

/// Tune a helix seed until it grows `target` cells with legs of at least
/// `min_leg` (or `max_iterations` pass).
pub fn tune_helix(
    dim: usize,
    points: &[DVec3],
    kappa: &[f64],
    target: usize,
    min_leg: f64,
    max_iterations: usize,
) -> Tuned {
    let none = crate::budget::Deadline::none();
    let tries = (target, min_leg, max_iterations);
    tune_helix_until(dim, points, kappa, tries, &none).unwrap_or_else(|t| *t)
}

/// `tune_helix`, stopped at `deadline` (checked once a try): the best seed
/// so far as the error, its `iterations` the tries made (docs/commands.md,
/// "Time limits").
pub fn tune_helix_until(
    dim: usize,
    points: &[DVec3],
    kappa: &[f64],
    (target, min_leg, max_iterations): (usize, f64, usize),
    deadline: &crate::budget::Deadline,
) -> Result<Tuned, Box<Tuned>> {
    let n = points.len() - 1;
    let centre = points[..n].iter().sum::<DVec3>() / n as f64;
    let frame = Frame { centre, dim };
    let start = frame.params(points, kappa);
    let (s_points, s_kappa) = frame.seed(&start);
    let edge = (0..n)
        .map(|k| points[k].distance(points[k + 1]))
        .sum::<f64>()
        / n as f64;
    let winding = Winding::of(points, centre, edge);
    let before = score(dim, &s_points, &s_kappa, target, min_leg, &winding);
    let mut best = (start.clone(), before);
    let mut rng = Rng::new(0x6b61_7269_6761_6d69);
    let mut step = 0.02;
    let mut iterations = 0;
    let mut polish = 0;
    let mut stopped = false;
    while iterations < max_iterations {
        if deadline.expired() {
            stopped = true;
            break;
        }
        if best.1.0 >= target {
            // Reached: more tries to open up the worst cell and follow the
            // start seed's winding.
            polish += 1;
            if polish > 3000 {
                break;
            }
        }
        iterations += 1;
        let mut p = best.0.clone();
        for k in 0..=n {
            p.rho[k] = (p.rho[k] + step * edge * rng.signed()).max(1e-3 * edge);
            p.theta[k] += step * edge / p.rho[k].max(edge) * rng.signed();
            p.height[k] += step * edge * rng.signed();
        }
        p.kappa0 += step * edge * 0.2 * rng.signed();
        for s in &mut p.share {
            *s = (*s + step * rng.signed() / n as f64).max(0.0);
        }
        if p.share.iter().sum::<f64>() <= 1e-9 {
            continue;
        }
        let (tp, tk) = frame.seed(&p);
        let s = score(dim, &tp, &tk, target, min_leg, &winding);
        if (s.0, s.1) > (best.1.0, best.1.1) {
            best = (p, s);
            step = (step * 1.3).min(0.2);
        } else if step < 1.5e-4 {
            // Stuck at the smallest step: kick the search wider again.
            step = 0.1;
        } else {
            step = (step * 0.985).max(1e-4);
        }
    }
    let (t_points, t_kappa) = frame.seed(&best.0);
    let max_move = t_points
        .iter()
        .zip(points)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f64::max);
    let max_kappa_change = t_kappa
        .iter()
        .zip(kappa)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let tuned = Tuned {
        points: t_points,
        kappa: t_kappa,
        cells_before: before.0,
        cells_after: best.1.0,
        iterations,
        max_move,
        max_kappa_change,
    };
    if stopped {
        Err(Box::new(tuned))
    } else {
        Ok(tuned)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::{grow_helix, seed_defect, verify};

    #[test]
    fn tuning_grows_more_cells_and_keeps_the_seed_condition() {
        let n = 9;
        let points: Vec<DVec3> = (0..=n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                // fixtures/designs/helix-bowl.toml's start seed.
                let r = 150.0 * 0.9f64.powf(k as f64 / n as f64);
                DVec3::new(r * a.cos(), r * a.sin(), -80.0 * k as f64 / n as f64)
            })
            .collect();
        let rod = points[n].distance(points[1]);
        let mut kappa = vec![0.0];
        kappa.extend(std::iter::repeat_n(-rod / (n - 1) as f64, n - 1));
        let tuned = tune_helix(3, &points, &kappa, 32, 8.5, 20_000);
        assert!(tuned.cells_before < 32);
        assert_eq!(tuned.cells_after, 32, "{tuned:?}");
        assert!(seed_defect(&tuned.points, &tuned.kappa).abs() < 1e-12);
        let lattice = grow_helix(3, &tuned.points, &tuned.kappa, 32).unwrap();
        assert!(verify(&lattice).passed());
        // Deterministic.
        assert_eq!(tune_helix(3, &points, &kappa, 32, 8.5, 20_000), tuned);
        assert!(
            lattice
                .cells
                .iter()
                .all(|c| lattice.legs(c).iter().all(|&l| l >= 8.5))
        );
    }
}
