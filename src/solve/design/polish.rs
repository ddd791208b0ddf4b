//! A waved band's rings polished so that the shape carries the target's
//! negative curvature at every vertex, in the design and in the simulated
//! shape (docs/design.md, "Polished rings"). Growing each ring nearest the
//! target leaves its laid fronts with a pattern of angle defects round the
//! ring larger than a saddle's own small defect, so some vertices come out
//! positive. A Nelder-Mead search then moves each ring's aim (along the
//! high azimuth and up) and its front's saddle amplitudes, against a cost
//! of the distances to the target, defects above -0.1 deg, ring-mean K
//! uneven from ring to ring and narrow openings, for the design and for
//! its simulated equilibrium, and the design's defects away from the
//! grown ring's mean. Each equilibrium is solved warm from the best one so
//! far (`sim::resolve`).

use super::DesignAsk;
use super::waved::{Band, Ring, design};
use crate::design::Design;
use crate::lattice::{Lattice, Saddle};
use crate::sim::{LatticeModel, placed_lattice, resolve, simulate};
use glam::DVec3;
use std::time::{Duration, Instant};

/// The curvature measures of one shape: interior vertices' angle defects
/// (degrees), largest and mean, and ring-mean K's largest over smallest
/// (infinite when a ring's mean K is 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Defects {
    pub largest: f64,
    pub mean: f64,
    pub k_ratio: f64,
}

/// Rings polished, with the design's and the simulated shape's measures
/// and the designs costed.
#[derive(Clone, Debug)]
pub(super) struct Polished {
    pub rows: Vec<Ring>,
    pub design: Defects,
    pub simulated: Defects,
    pub evaluations: usize,
}

impl Polished {
    /// Every interior vertex negative, in the design and simulated.
    pub(super) fn negative(&self) -> bool {
        self.design.largest < 0.0 && self.simulated.largest < 0.0
    }
}

/// Cells costed at most by default (`DesignAsk::polish`): a ring of 36
/// cells is costed 1,200 times.
pub const POLISH_WORK: usize = 43_200;

/// Seconds reckoned for each cell costed: the example saddle ring's 1,155
/// designs of 36 cells in about 90 s with the release build (docs/design.md,
/// "Polished rings"); POLISH_WORK of them, about 95 s.
pub const POLISH_SECONDS_PER_CELL: f64 = 0.0022;

/// Moves of the search at most, and its first step in each variable's
/// unit (mm for the aim; `SADDLE_UNIT` and a tenth of it for c and d).
const MOVES: usize = 800;
const STEP: f64 = 6.0;
const SADDLE_UNIT: f64 = 1e-4;

/// How far below zero a defect must be (degrees) before it costs nothing,
/// and the cost's weights.
const MARGIN: f64 = 0.1;
const ABOVE: f64 = 50.0;
const EVEN: f64 = 10.0;
const K_RATIO: f64 = 1.4;
const K_WEIGHT: f64 = 5.0;
const OPENING: f64 = 25.0;

/// The simulated fit aimed at, inside the goal's (85 % covered, largest
/// 4 % of D) by a margin, and the weight of the shortfall in coverage.
const COVERED: f64 = 0.9;
const LARGEST: f64 = 0.03;
const COVER_WEIGHT: f64 = 20.0;

/// `rows` polished, when the rings' mean defect is negative (a saddle:
/// there is a sign to carry) and the polish lowers the larger of the
/// design's and the simulated shape's largest defect; None otherwise, and
/// when the time left before the ask's deadline is less than the polish
/// is reckoned at (so that a time limit gives the whole polish or none).
/// Bounded by `MOVES` and the ask's `polish` work; `progress` hears every
/// `SAY_EVERY` designs.
pub(super) fn polish(
    ask: &DesignAsk<'_>,
    (band, points, rows): (&Band, &[DVec3], &[Ring]),
    progress: &mut dyn FnMut(&str),
) -> Option<Polished> {
    if !allowed(ask, progress) {
        return None;
    }
    let start = Shaped::of(ask, points, rows, None)?;
    if !(start.design.mean < 0.0) {
        return None;
    }
    progress(&format!(
        "polishing the rings of the best loop ({} points, {} rings) so that every vertex carries the saddle's curvature",
        points.len(),
        rows.len()
    ));
    let want = start.design.mean;
    let mut search = Search {
        ask,
        band,
        points,
        rows,
        want,
        cells: start.cells,
        best: None,
        evaluations: 0,
        progress,
    };
    let dims = 4 * rows.len();
    let mut simplex = vec![vec![0.0; dims]];
    simplex.extend((0..dims).map(|k| {
        let mut x = vec![0.0; dims];
        x[k] = STEP;
        x
    }));
    crate::solve::simplex::minimise(simplex, 1e-6, MOVES, &mut |x| search.cost(x));
    let (x, _, _) = search.best.take()?;
    // Solved again from the start, as `build` will: a warm solve follows
    // its own chain of states, which may have left the design's.
    let rows = moved(band, rows, &x);
    let best = Shaped::of(ask, points, &rows, None)?;
    let worst = |s: &Shaped| s.design.largest.max(s.simulated.largest);
    (worst(&best) < worst(&start)).then_some(Polished {
        rows,
        design: best.design,
        simulated: best.simulated,
        evaluations: search.evaluations,
    })
}

/// Whether the ask allows a polish: some work, and as long as it is
/// reckoned at before the deadline (said to `progress` when not).
fn allowed(ask: &DesignAsk<'_>, progress: &mut dyn FnMut(&str)) -> bool {
    if ask.polish == 0 {
        return false;
    }
    let reckoned = Duration::from_secs_f64(POLISH_SECONDS_PER_CELL * ask.polish as f64);
    let short = ask
        .deadline
        .is_some_and(|d| d.saturating_duration_since(Instant::now()) < reckoned);
    if short {
        progress(&format!(
            "rings left unpolished: the time limit leaves less than the polish's ~{:.0} s",
            reckoned.as_secs_f64()
        ));
    }
    !short
}

/// The rings moved by `x`: per ring, its aim along the high azimuth and
/// up (mm), and its saddle's c and d (in `SADDLE_UNIT` and a tenth of it).
fn moved(band: &Band, rows: &[Ring], x: &[f64]) -> Vec<Ring> {
    let u = DVec3::new(band.phase.cos(), band.phase.sin(), 0.0);
    rows.iter()
        .zip(x.chunks(4))
        .map(|(r, v)| Ring {
            target: r.target + v[0] * u + v[1] * DVec3::Z,
            saddle: Saddle {
                c: r.saddle.c + v[2] * SADDLE_UNIT,
                d: r.saddle.d + v[3] * SADDLE_UNIT / 10.0,
            },
        })
        .collect()
}

/// The search's state: what it polishes, and the best design so far with
/// its equilibrium (each solve starts warm from it).
struct Search<'a> {
    ask: &'a DesignAsk<'a>,
    band: &'a Band,
    points: &'a [DVec3],
    rows: &'a [Ring],
    want: f64,
    cells: usize,
    best: Option<(Vec<f64>, f64, Shaped)>,
    evaluations: usize,
    progress: &'a mut dyn FnMut(&str),
}

/// The optimiser's cost of a design that does not grow (`solve`'s), here
/// also of one that does not simulate, and of any once the work is spent
/// or the deadline passed.
use crate::solve::UNGROWN;

/// Designs between two progress lines.
const SAY_EVERY: usize = 100;

impl Search<'_> {
    fn cost(&mut self, x: &[f64]) -> f64 {
        let spent = self.evaluations * self.cells >= self.ask.polish;
        if spent || self.ask.deadline.is_some_and(|d| Instant::now() > d) {
            return UNGROWN;
        }
        self.evaluations += 1;
        if self.evaluations.is_multiple_of(SAY_EVERY) {
            let best = self.best.as_ref().map_or(f64::NAN, |b| b.1);
            (self.progress)(&format!(
                "polishing: {} designs costed, the best at {best:.3}",
                self.evaluations
            ));
        }
        let rows = moved(self.band, self.rows, x);
        let warm = self.best.as_ref().map(|b| &b.2.model);
        let Some(shaped) = Shaped::of(self.ask, self.points, &rows, warm) else {
            return UNGROWN;
        };
        if shaped.cells != self.cells {
            return UNGROWN;
        }
        let c = shaped.cost(self.want);
        if !c.is_finite() {
            return UNGROWN;
        }
        if self.best.as_ref().is_none_or(|b| c < b.1) {
            self.best = Some((x.to_vec(), c, shaped));
        }
        c
    }
}

/// A design grown and simulated, with what the cost reads of both.
struct Shaped {
    /// The grown lattice's cells.
    cells: usize,
    design: Defects,
    simulated: Defects,
    /// Interior vertices' defects (degrees), design then simulated.
    defects: [Vec<f64>; 2],
    /// Smallest opening (degrees), of either shape.
    opening: f64,
    /// The design's vertices' rms distance to the target, and the
    /// simulated shape's fit, each relative to D.
    design_rms: f64,
    fit: crate::target::Fit,
    model: LatticeModel,
}

impl Shaped {
    fn of(
        ask: &DesignAsk<'_>,
        points: &[DVec3],
        rows: &[Ring],
        warm: Option<&LatticeModel>,
    ) -> Option<Shaped> {
        let d = design(ask.base, points, rows);
        let lattice = d.grow().ok()?;
        let model = equilibrium(&d, &lattice, warm)?;
        let simulated = placed_lattice(&lattice, &model);
        let t = &ask.target;
        let ms = lattice
            .vertices
            .iter()
            .map(|v| t.closest(v.pos).1.powi(2))
            .sum::<f64>()
            / lattice.vertices.len() as f64;
        let (design_defects, design_signs) = signs(&lattice);
        let (sim_defects, sim_signs) = signs(&simulated);
        Some(Shaped {
            opening: opening(&lattice).min(opening(&simulated)),
            design_rms: ms.sqrt() / t.extent,
            fit: super::fit_of(t, &simulated),
            design: design_signs,
            simulated: sim_signs,
            defects: [design_defects, sim_defects],
            cells: lattice.cells.len(),
            model,
        })
    }

    /// Distances in % of D; defects above -MARGIN, and away from `want`,
    /// in degrees squared; K's ratio beyond K_RATIO; openings under
    /// OPENING degrees; the simulated fit short of COVERED and LARGEST.
    fn cost(&self, want: f64) -> f64 {
        let mean = |v: &[f64], f: &dyn Fn(f64) -> f64| {
            v.iter().map(|d| f(*d)).sum::<f64>() / v.len() as f64
        };
        let mut c = 100.0 * (self.design_rms + self.fit.rms / self.fit.extent);
        for (defects, signs) in self.defects.iter().zip([self.design, self.simulated]) {
            c += ABOVE * mean(defects, &|d| (d + MARGIN).max(0.0).powi(2));
            c += K_WEIGHT * (signs.k_ratio - K_RATIO).max(0.0);
        }
        c += EVEN * mean(&self.defects[0], &|d| (d - want).powi(2));
        c += (OPENING - self.opening).max(0.0);
        let covered = self.fit.coverage.unwrap_or(0.0);
        c + COVER_WEIGHT * (COVERED - covered).max(0.0)
            + 100.0 * (self.fit.largest / self.fit.extent - LARGEST).max(0.0)
    }
}

/// The design's equilibrium: warm from `warm` when it has one, else
/// deployed from the start.
fn equilibrium(d: &Design, lattice: &Lattice, warm: Option<&LatticeModel>) -> Option<LatticeModel> {
    let deployment = crate::lattice::deploy::deployment(lattice);
    let m = &d.fabrication.material;
    let warmed = warm.and_then(|p| {
        resolve(
            p,
            lattice,
            &deployment,
            (m.width, m.thickness),
            &d.simulation,
        )
        .ok()
    });
    let run = match warmed {
        Some((run, _)) => run,
        None => simulate(lattice, &deployment, m.width, m.thickness, &d.simulation).ok()?,
    };
    Some(run.lm)
}

/// Interior vertices' defects (degrees) and their measures.
fn signs(l: &Lattice) -> (Vec<f64>, Defects) {
    let c = l.curvature();
    let defects: Vec<f64> = c.iter().map(|v| v.defect.to_degrees()).collect();
    let rows = c
        .iter()
        .map(|v| l.vertex(v.vertex).key.row as usize + 1)
        .max()
        .unwrap_or(0);
    let mut ring = vec![(0.0, 0usize); rows];
    for v in &c {
        let s = &mut ring[l.vertex(v.vertex).key.row as usize];
        s.0 += v.k;
        s.1 += 1;
    }
    let k: Vec<f64> = ring
        .iter()
        .filter(|s| s.1 > 0)
        .map(|s| (s.0 / s.1 as f64).abs())
        .collect();
    let least = k.iter().copied().fold(f64::INFINITY, f64::min);
    let signs = Defects {
        largest: defects.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        mean: defects.iter().sum::<f64>() / defects.len().max(1) as f64,
        k_ratio: if least > 0.0 {
            k.iter().copied().fold(0.0, f64::max) / least
        } else {
            f64::INFINITY
        },
    };
    (defects, signs)
}

/// The smallest angle between a cell's two rods (degrees).
fn opening(l: &Lattice) -> f64 {
    l.cells
        .iter()
        .map(|c| {
            let phi = l.phi(c).to_degrees();
            phi.min(180.0 - phi)
        })
        .fold(f64::INFINITY, f64::min)
}
