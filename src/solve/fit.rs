//! Target fitting (docs/math.md 6.4): rows found by a search, so that the lattice
//! approximates a target surface. The seed comes from the recipe; each row's
//! free parameters are chosen here, one row at a time, deterministically.
//!
//! * disk (2-D sheet): the two boundary legs put the row's end vertices on
//!   the circle; the leg direction is scanned for the most even legs.
//! * ellipsoid (3-D sheet, the half with z <= 0): the boundary legs put the
//!   end vertices on the ellipsoid; the direction (angle and tilt) is
//!   scanned for the new vertices nearest the surface. With a loop seed
//!   round the rim of a spheroid (a = b), each ring's vertex x[i+1][1] goes
//!   on the meridian of x[i][1], one edge length further down, so that the
//!   cells stay near square as the rings shrink.
//! * revolution (loop): each row's vertex x[i+1][1] is placed on the next
//!   profile point, in the meridian plane of x[i][1] (the paper's torus).

use crate::budget::Deadline;
use crate::design::fit::{Fit, Surface, error};
use crate::design::{Design, MIN_WALL};
use crate::lattice::{FrontMoves, Grower, GrowthError, Kind, Lattice, RowParams};
use crate::legs::{Direction, Leg};
use glam::DVec3;

mod refront;
mod steer;

/// Grow the fitted lattice; `progress` hears about each row.
pub(crate) fn grow(
    design: &Design,
    fit: &Fit,
    progress: &mut dyn FnMut(&str),
) -> Result<Lattice, GrowthError> {
    grow_recorded(design, fit, progress).map(|(l, _)| l)
}

/// The rows of the deepest sheet an open fit's search reached on `fit`
/// within `budget` rows tried (all `fit.rows` of them when it could), each
/// row's scan of `fit.samples` angles: the rows `karigami design` writes.
/// With `refront`, each row after the first grows on its front laid back
/// onto the target (`refront`, docs/math.md 7).
pub(crate) fn deepest_rows(
    design: &Design,
    fit: &Fit,
    budget: usize,
    refront: bool,
) -> Result<Vec<RowParams>, GrowthError> {
    let mut grower = Grower::new(design.kind, design.dim, &design.points, &design.kappa)?;
    let fab = &design.fabrication;
    let mut quiet = |_: &str| {};
    let mut search = Search {
        fit,
        dim: design.dim,
        min_leg: fab.eyelet.flange + 2.0 * MIN_WALL,
        strip: (fab.material.width, fab.end_margin, design.clash.clearance),
        budget,
        deepest: (0, None),
        progress: &mut quiet,
        chosen: Vec::new(),
        path: Vec::new(),
        best: Vec::new(),
        deadline: &design.deadline,
        stopped: false,
        refront,
    };
    search.rows(&mut grower, 0);
    if search.stopped {
        return Err(stopped(&design.deadline, search.best.len(), fit.rows));
    }
    if search.best.is_empty() {
        return Err(search.deepest.1.unwrap_or_else(|| no_row(0)));
    }
    Ok(search.best)
}

/// The row angles an open fit's search chose (None for other fits): where
/// the optimiser starts when the recipe gives no `fit.angles`.
pub(crate) fn searched_angles(design: &Design, fit: &Fit) -> Option<Vec<f64>> {
    // A 3-D search also chooses a tilt, which fit.angles does not hold.
    if design.dim != 2 {
        return None;
    }
    grow_recorded(design, fit, &mut |_| {}).ok()?.1
}

fn grow_recorded(
    design: &Design,
    fit: &Fit,
    progress: &mut dyn FnMut(&str),
) -> Result<(Lattice, Option<Vec<f64>>), GrowthError> {
    let mut grower = Grower::new(design.kind, design.dim, &design.points, &design.kappa)?;
    let open = matches!(fit.surface, Surface::Disk { .. })
        || matches!(fit.surface, Surface::Ellipsoid { .. } | Surface::Target(_))
            && design.kind == Kind::Sheet;
    if open {
        // Legs shorter than the eyelet flange (plus a wall) cannot be built.
        let min_leg = design.fabrication.eyelet.flange + 2.0 * MIN_WALL;
        if let Some(angles) = &fit.angles {
            for (i, &a) in angles.iter().enumerate() {
                let params = row_on_boundary(
                    &mut grower,
                    None,
                    &fit.surface,
                    Some(Direction::Angles {
                        angle_deg: a,
                        tilt_deg: 0.0,
                    }),
                )
                .map_err(|e| e.unwrap_or_else(|| no_row(i)))?;
                grower.grow_row(&params)?;
                progress(&row_note(fit, grower.lattice(), i));
            }
            return Ok((grower.into_lattice(), Some(angles.clone())));
        }
        let fab = &design.fabrication;
        let mut search = Search {
            fit,
            dim: design.dim,
            min_leg,
            strip: (fab.material.width, fab.end_margin, design.clash.clearance),
            budget: SEARCH_BUDGET,
            deepest: (0, None),
            progress,
            chosen: Vec::new(),
            path: Vec::new(),
            best: Vec::new(),
            deadline: &design.deadline,
            stopped: false,
            refront: false,
        };
        return if search.rows(&mut grower, 0) {
            Ok((grower.into_lattice(), Some(search.chosen)))
        } else if search.stopped {
            Err(stopped(&design.deadline, search.best.len(), fit.rows))
        } else {
            Err(search.deepest.1.unwrap_or_else(|| no_row(search.deepest.0)))
        };
    }
    for i in 0..fit.rows {
        let params = match &fit.surface {
            Surface::Ellipsoid { axes } if design.kind == Kind::Loop => {
                let front = grower.front();
                let step = match &fit.steps {
                    Some(s) => s[i],
                    None => front[0].pos.distance(front[1].pos),
                };
                let next = meridian_step(*axes, front[1].pos, step);
                RowParams {
                    target: Some(next),
                    ..RowParams::default()
                }
            }
            Surface::Revolution { profile } | Surface::Torus { profile, .. } => {
                let front = grower.front();
                let theta = front[1].pos.y.atan2(front[1].pos.x);
                let q = profile[i];
                RowParams {
                    target: Some(DVec3::new(q.x * theta.cos(), q.x * theta.sin(), q.y)),
                    ..RowParams::default()
                }
            }
            _ => unreachable!("open surfaces are searched above"),
        };
        grower.grow_row(&params)?;
        progress(&row_note(fit, grower.lattice(), i));
    }
    Ok((grower.into_lattice(), None))
}

/// The point one front edge (|x1 - x0|) further down the spheroid's meridian
/// through `x1`, towards z < 0: where the next ring's vertex goes.
fn meridian_step(axes: DVec3, x1: DVec3, edge: f64) -> DVec3 {
    let (a, c) = (axes.x, axes.z);
    let theta = x1.y.atan2(x1.x);
    // Meridian (a cos t, c sin t), t from 0 at the rim to -pi/2 at the pole.
    let r = x1.truncate().length();
    let mut t = -(r / a).clamp(-1.0, 1.0).acos() * if x1.z > 0.0 { -1.0 } else { 1.0 };
    // Walk down the meridian in small steps until one edge length is covered.
    let mut walked = 0.0;
    let dt = 1e-4;
    while walked < edge && t > -std::f64::consts::FRAC_PI_2 {
        let speed = (a * a * t.sin().powi(2) + c * c * t.cos().powi(2)).sqrt();
        walked += speed * dt;
        t -= dt;
    }
    let r = a * t.cos();
    DVec3::new(r * theta.cos(), r * theta.sin(), c * t.sin())
}

/// How far (a share of D) a new vertex may stray from a target.
const TARGET_STRAY: f64 = 0.01;

/// The same on a laid front: the row's error does not add up, as each
/// front is laid back on the target, and what a row strays the strips
/// take up by bending where the rows join (docs/design.md, "Rows").
const LAID_STRAY: f64 = 0.02;

/// Rows tried in all, over every backtrack of a fit.
const SEARCH_BUDGET: usize = 5_000;
/// The best rows of each scan that are tried in turn when a later row has
/// no admissible direction.
const BRANCHES: usize = 6;

/// A depth-first search over the rows of an open fit: at each row the
/// scan's best candidates in order, backing up when a later row finds none
/// (a greedy choice can leave a front no row grows on).
struct Search<'a> {
    fit: &'a Fit,
    dim: usize,
    min_leg: f64,
    /// Strip width, end margin and clearance: rows whose strips clash come last.
    strip: (f64, f64, f64),
    /// Rows left to try.
    budget: usize,
    /// The deepest row reached, and why it found no candidate (when it did not).
    deepest: (usize, Option<GrowthError>),
    progress: &'a mut dyn FnMut(&str),
    /// The leg angle of each row grown so far.
    chosen: Vec<f64>,
    /// The rows grown so far, and the longest such list met.
    path: Vec<RowParams>,
    best: Vec<RowParams>,
    /// The run's `--time-limit` (src/budget.rs), checked before each row
    /// tried; `stopped` once it has passed.
    deadline: &'a Deadline,
    stopped: bool,
    /// Lay each front back onto a target before its row (`refront`).
    refront: bool,
}

impl Search<'_> {
    /// Grow rows `i..` onto `grower`; false (with the rows taken back) if
    /// they cannot all be grown within the budget.
    fn rows(&mut self, grower: &mut Grower, i: usize) -> bool {
        if i == self.fit.rows {
            return true;
        }
        let front = match &self.fit.surface {
            Surface::Target(t) if self.refront && i > 0 => {
                let old = grower.front();
                let pos: Vec<DVec3> = old.iter().map(|p| p.pos).collect();
                let laid = refront::laid(&t.0, &pos);
                refront::moves(&pos, &laid).map(|moves| Rebuild {
                    target: &t.0,
                    old,
                    pos,
                    laid,
                    moves,
                })
            }
            _ => None,
        };
        let (candidates, why) = ranked_rows(
            grower,
            front.as_ref(),
            &self.fit.surface,
            (self.fit.samples, self.dim),
            self.min_leg,
            self.strip,
            self.deadline,
        );
        if self.deadline.expired() {
            self.stopped = true;
            return false;
        }
        if i > self.deepest.0 || candidates.is_empty() && i == self.deepest.0 {
            self.deepest = (i, why.filter(|_| candidates.is_empty()));
        }
        for params in candidates.into_iter().take(BRANCHES) {
            if self.budget == 0 {
                return false;
            }
            if self.deadline.expired() {
                self.stopped = true;
                return false;
            }
            self.budget -= 1;
            if grower.grow_row(&params).is_err() {
                continue;
            }
            if let Some(Direction::Angles { angle_deg, .. }) = params.direction {
                self.chosen.push(angle_deg);
            }
            self.path.push(params.clone());
            if self.path.len() > self.best.len() {
                self.best.clone_from(&self.path);
            }
            (self.progress)(&row_note(self.fit, grower.lattice(), i));
            if self.rows(grower, i + 1) {
                return true;
            }
            grower.undo_row();
            self.chosen.pop();
            self.path.pop();
        }
        false
    }
}

/// The progress note for fitted row `i`.
fn row_note(fit: &Fit, lattice: &Lattice, i: usize) -> String {
    let (abs, _) = error(fit, lattice);
    format!(
        "fit row {}/{}: largest vertex distance so far {abs:.3e} mm",
        i + 1,
        fit.rows
    )
}

/// No row `i` was found: none admissible there, or the search ran out of
/// tries on the way.
/// The fit's search stopped at the time limit, `rows` of `of` grown.
fn stopped(deadline: &Deadline, rows: usize, of: usize) -> GrowthError {
    GrowthError::new(
        crate::diagnostic::ErrorKind::TimeLimit,
        crate::lattice::Param::Direction,
        Some(rows),
        None,
        format!(
            "the fit's row search stopped at {rows} of {of} rows after {:.1} s: the time limit of {} s has passed",
            deadline.elapsed(),
            deadline.limit().unwrap_or(0.0)
        ),
        "nothing was written; allow more time with --time-limit SECONDS, or fit with fewer samples (docs/commands.md, Time limits)",
    )
}

fn no_row(i: usize) -> GrowthError {
    GrowthError::new(
        crate::diagnostic::ErrorKind::InadmissibleDirection,
        crate::lattice::Param::Direction,
        Some(i),
        None,
        format!(
            "no leg direction found for this row (the deepest the fit reached in {SEARCH_BUDGET} tries) that keeps its end vertices on the target boundary with legs long enough for the eyelets"
        ),
        "fit fewer rows, or start from another seed arc",
    )
}

/// The most tilts a 3-D row's scan takes: with a tilt for every four
/// angles the scan grew as `samples` squared (2,000 samples took 131 s and
/// 610 MB a fit); capped, it grows linearly. The default 61 samples take
/// 16 tilts either way.
const MAX_TILTS: usize = 16;

/// The tilts of a 3-D row's scan for `samples` leg angles.
fn tilt_count(samples: usize) -> usize {
    samples.div_ceil(4).clamp(3, MAX_TILTS)
}

/// The tilts a 3-D row's scan tries: `tilt_count(samples)` spread evenly
/// over -60..60 degrees, and 0 among them in order when an even count
/// steps over it, so that a flat patch's rows can grow flat.
fn scan_tilts(samples: usize) -> Vec<f64> {
    let n = tilt_count(samples);
    let mut tilts: Vec<f64> = (0..n)
        .map(|k| -60.0 + 120.0 * k as f64 / (n - 1) as f64)
        .collect();
    if !tilts.contains(&0.0) {
        let at = tilts.partition_point(|&t| t < 0.0);
        tilts.insert(at, 0.0);
    }
    tilts
}

/// A row's front laid back onto the target (`refront`): the old front,
/// its positions, the laid ones and the moves that rebuild it so.
struct Rebuild<'a> {
    target: &'a crate::target::Target,
    old: Vec<crate::lattice::Point>,
    pos: Vec<DVec3>,
    laid: Vec<DVec3>,
    moves: FrontMoves,
}

impl Rebuild<'_> {
    /// The moves for a row grown in `direction`: the laid front steered
    /// so that the row's new vertices land on the target (`steer`), or as
    /// laid when it cannot be.
    fn moves(&self, direction: Direction) -> FrontMoves {
        steer::steered(self.target, &self.old, &self.laid, direction)
            .and_then(|(x, _)| refront::moves(&self.pos, &x))
            .unwrap_or_else(|| self.moves.clone())
    }
}

/// Scan the start direction of an open row; for each, put the end vertices
/// on the boundary (circle or ellipsoid) and score the row. The candidates
/// best first, and the last growth error met (for a row with none).
/// `scan` is the angles scanned and the dimension.
fn ranked_rows(
    grower: &mut Grower,
    rebuild: Option<&Rebuild<'_>>,
    surface: &Surface,
    (samples, dim): (usize, usize),
    min_leg: f64,
    strip: (f64, f64, f64),
    deadline: &Deadline,
) -> (Vec<RowParams>, Option<GrowthError>) {
    let tilts: Vec<f64> = if dim == 3 {
        scan_tilts(samples)
    } else {
        vec![0.0]
    };
    let mut scored: Vec<(f64, RowParams)> = Vec::new();
    let mut last_error = None;
    for &tilt in &tilts {
        // A 2,000-sample scan takes seconds: the time limit is looked at
        // once a tilt.
        if deadline.expired() {
            break;
        }
        for k in 1..samples {
            let angle = -89.0 + 178.0 * k as f64 / samples as f64;
            let towards = Direction::Angles {
                angle_deg: angle,
                tilt_deg: tilt,
            };
            let moves = rebuild.map(|r| r.moves(towards));
            match scored_row(grower, moves.as_ref(), surface, towards, min_leg, strip) {
                Ok(Some(row)) => scored.push(row),
                Ok(None) => {}
                Err(e) => last_error = e.or(last_error),
            }
        }
    }
    // A stable sort keeps scan order among equal scores: deterministic.
    scored.sort_by(|a, b| a.0.total_cmp(&b.0));
    (scored.into_iter().map(|s| s.1).collect(), last_error)
}

/// The row grown in `direction` on `front` (rebuilt, or as it is) with
/// its end vertices where `row_on_boundary` puts them, and its score;
/// None when the score refuses it, the growth error when it does not grow.
fn scored_row(
    grower: &mut Grower,
    front: Option<&FrontMoves>,
    surface: &Surface,
    towards: Direction,
    min_leg: f64,
    strip: (f64, f64, f64),
) -> Result<Option<(f64, RowParams)>, Option<GrowthError>> {
    let params = row_on_boundary(grower, front, surface, Some(towards))?;
    grower.grow_row(&params).map_err(Some)?;
    let stray = if front.is_some() {
        LAID_STRAY
    } else {
        TARGET_STRAY
    };
    let score = row_score(grower.lattice(), surface, min_leg, stray);
    // A disk's rows whose strips overlap others of their layer come
    // last (on a curved patch the distance to the surface decides).
    let lattice = grower.lattice();
    let first_new = 2 * (lattice.cells.len() - lattice.width);
    let clashes = if score.is_finite() && matches!(surface, Surface::Disk { .. }) {
        crate::parts::clash::count_clashes(lattice, strip.0, strip.1, strip.2, |c| {
            c.rods[1] >= first_new
        })
    } else {
        0
    };
    grower.undo_row();
    let score = score + clashes as f64;
    Ok(score.is_finite().then_some((score, params)))
}

/// The row with leg direction `direction` whose two end vertices lie on the
/// surface's boundary (circle or ellipsoid); the growth error met, if any.
fn row_on_boundary(
    grower: &mut Grower,
    front: Option<&FrontMoves>,
    surface: &Surface,
    direction: Option<Direction>,
) -> Result<RowParams, Option<GrowthError>> {
    // Pivots do not depend on the end legs: grow once to find them.
    let probe = RowParams {
        direction,
        left_leg: Leg::Length(1.0),
        right_leg: Leg::Length(1.0),
        front: front.cloned(),
        ..RowParams::default()
    };
    grower.grow_row(&probe).map_err(Some)?;
    let lattice = grower.lattice();
    let w = lattice.width;
    let cells = &lattice.cells[lattice.cells.len() - w..];
    let (first, last) = (&cells[0], &cells[w - 1]);
    let [_, ur0, _, _] = lattice.corners(first);
    let [ul1, _, _, _] = lattice.corners(last);
    let v2 = (first.pivot - ur0).normalize();
    let v1 = (last.pivot - ul1).normalize();
    let legs = (
        surface.ray_exit(first.pivot, v2),
        surface.ray_exit(last.pivot, v1),
    );
    grower.undo_row();
    // A ray that never comes near a curved target (it leaves along the
    // surface, curving away) ends where the other lower leg does: the
    // next row's end kappa 0, the end vertex wherever the cell puts it,
    // for the stray rule to judge.
    let leg = |l: Option<f64>| match (l, surface) {
        (Some(l), _) => Some(Leg::Length(l)),
        (None, Surface::Target(_)) => Some(Leg::Match),
        (None, _) => None,
    };
    let (Some(left_leg), Some(right_leg)) = (leg(legs.0), leg(legs.1)) else {
        return Err(None);
    };
    Ok(RowParams {
        direction,
        left_leg,
        right_leg,
        front: front.cloned(),
        ..RowParams::default()
    })
}

/// Lower is better: distance of the new vertices to the surface (3-D), then
/// the worst cell's shape: uneven legs (min/max leg ratio) or a cell near
/// flat-open or collapsed (sine of phi), so rows stay open and buildable.
fn row_score(lattice: &Lattice, surface: &Surface, min_leg: f64, stray: f64) -> f64 {
    let w = lattice.width;
    let cells = &lattice.cells[lattice.cells.len() - w..];
    let n = w + 1;
    let new = &lattice.vertices[lattice.vertices.len() - n..];
    let worst = cells
        .iter()
        .map(|c| {
            let legs = lattice.legs(c);
            let lo = legs.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = legs.iter().copied().fold(0.0, f64::max);
            if lo < min_leg {
                return f64::NEG_INFINITY;
            }
            (lo / hi).min(lattice.phi(c).sin())
        })
        .fold(1.0, f64::min);
    if worst == f64::NEG_INFINITY {
        return f64::INFINITY;
    }
    let balance = 1.0 - worst;
    // A target's rows march on across it (docs/design.md, "Rows").
    if matches!(surface, Surface::Target(_)) && !marches(lattice) {
        return f64::INFINITY;
    }
    // A disk's vertices stay inside (or on) its circle.
    if let Surface::Disk { radius } = surface
        && new
            .iter()
            .any(|v| v.pos.truncate().length() > radius * (1.0 + 1e-9))
    {
        return f64::INFINITY;
    }
    // A target's new vertices stay on it: not past a flat patch's edge.
    if let Surface::Target(t) = surface
        && new
            .iter()
            .any(|v| surface.distance(v.pos) > stray * t.0.extent)
    {
        return f64::INFINITY;
    }
    match surface {
        Surface::Ellipsoid { .. } | Surface::Target(_) => {
            let d = new
                .iter()
                .map(|v| surface.distance(v.pos))
                .fold(0.0, f64::max);
            d / surface.size() * 20.0 + balance
        }
        _ => balance,
    }
}

/// The least cosine between a column's new step and its step before: a
/// target's sheet that turns back by more than this folds over the rows
/// it has grown (their strips clash), though each new vertex lies on the
/// target.
const MARCH: f64 = 0.5;

/// The shortest step a target's row may take, a share of its front's mean
/// edge: shorter steps keep the new vertices nearer a curved target, and
/// a search left to them piles thin rows on one another (measured on the
/// saddle: steps shrinking to a few mm by the fifth row, strips clashing).
const STEP: f64 = 0.5;

/// Whether every column of the last row steps on at least `STEP` of an
/// edge from the front it grew on, and within `MARCH` of the way it
/// stepped in the row before.
fn marches(lattice: &Lattice) -> bool {
    let n = lattice.width + 1;
    let rows = lattice.rows();
    let v = &lattice.vertices;
    let grown = |i: usize| v[i * n..(i + 1) * n].iter().map(|p| p.pos);
    // The front row i grew on: rebuilt, or the vertices of front i.
    let top = |i: usize| -> Vec<DVec3> {
        match lattice.fronts.get(i) {
            Some(f) if !f.is_empty() => f.clone(),
            _ => grown(i).collect(),
        }
    };
    let (new, mid) = (grown(rows).collect::<Vec<_>>(), top(rows - 1));
    let edge = mid.windows(2).map(|w| w[0].distance(w[1])).sum::<f64>() / (n - 1) as f64;
    let long = new
        .iter()
        .zip(&mid)
        .all(|(a, b)| a.distance(*b) >= STEP * edge);
    if !long || rows < 2 {
        return long;
    }
    let before: Vec<DVec3> = grown(rows - 1).collect();
    new.iter()
        .zip(&mid)
        .zip(before.iter().zip(&top(rows - 2)))
        .all(|((new, mid), (was, old))| {
            let (a, b) = (*new - *mid, *was - *old);
            a.dot(b) >= MARCH * a.length() * b.length()
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tilt scan: a tilt for every four angles up to the cap, so the
    /// default's 16 are kept and 2,000 samples cost 16 tilts, not 500.
    #[test]
    fn the_tilt_scan_is_capped() {
        assert_eq!(tilt_count(3), 3);
        assert_eq!(tilt_count(61), 16);
        assert_eq!(tilt_count(64), 16);
        assert_eq!(tilt_count(2000), MAX_TILTS);
    }

    /// Every count's scan holds tilt 0 (an even count's spread steps over
    /// it) and each of its spread tilts, in increasing order.
    #[test]
    fn every_tilt_scan_tries_tilt_zero() {
        for samples in [3, 9, 13, 31, 61, 2000] {
            let n = tilt_count(samples);
            let tilts = scan_tilts(samples);
            assert!(tilts.contains(&0.0), "{samples}: {tilts:?}");
            assert_eq!(tilts.len(), if n.is_multiple_of(2) { n + 1 } else { n });
            assert!(tilts.windows(2).all(|w| w[0] < w[1]), "{tilts:?}");
            assert_eq!((tilts[0], tilts[tilts.len() - 1]), (-60.0, 60.0));
        }
    }
}
