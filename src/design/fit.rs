//! Target fitting (MATH.md 6.4): rows found by a search, so that the lattice
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

use super::Design;
use super::raw::RawFit;
use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::geometry::{Direction, Leg};
use crate::lattice::{Grower, GrowthError, Kind, Lattice, RowParams};
use glam::{DVec2, DVec3};
use toml::Spanned;

#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    Disk {
        radius: f64,
    },
    Ellipsoid {
        axes: DVec3,
    },
    /// Profile points `(r, z)` in growth order.
    Revolution {
        profile: Vec<DVec2>,
    },
    /// A torus about the z axis (centre-circle radius `major`, tube radius
    /// `minor`): a revolution whose profile walks round the tube from the
    /// top (`psi = 0`) outwards by `step` degrees a row.
    Torus {
        major: f64,
        minor: f64,
        profile: Vec<DVec2>,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    pub surface: Surface,
    pub rows: usize,
    /// Directions tried per row (per axis, for the ellipsoid).
    pub samples: usize,
    /// Open fits: each row's leg angle, given instead of searched for.
    pub angles: Option<Vec<f64>>,
    /// Ellipsoid loops: each ring's step down the meridian (mm).
    pub steps: Option<Vec<f64>>,
    /// Where the table and those lists were written (for rewriting them).
    pub spans: FitSpans,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct FitSpans {
    pub table: std::ops::Range<usize>,
    pub angles: Option<std::ops::Range<usize>>,
    pub steps: Option<std::ops::Range<usize>>,
}

pub fn parse(f: &Spanned<RawFit>, kind: Kind, dim: usize) -> Result<Fit, Diagnostic> {
    let raw = f.get_ref();
    let need = |what: &str, hint: &str| {
        Diagnostic::new(
            ErrorKind::FitNeeds,
            format!("fit surface \"{}\" needs {what}", raw.surface.get_ref()),
        )
        .at(f.span())
        .hint(hint.to_string())
    };
    let positive = |n: &super::raw::Num, what: &str| -> Result<f64, Diagnostic> {
        let v = super::finite(n, what)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(Diagnostic::new(
                ErrorKind::FitNotPositive,
                format!("{what} must be positive"),
            )
            .at(n.span()))
        }
    };
    let (surface, want) = match raw.surface.get_ref().as_str() {
        "disk" => {
            let r = raw
                .radius
                .as_ref()
                .ok_or_else(|| need("`radius`", "give the disk's radius in mm"))?;
            (
                Surface::Disk {
                    radius: positive(r, "fit.radius")?,
                },
                (Kind::Sheet, 2),
            )
        }
        "ellipsoid" => {
            let a = raw
                .axes
                .as_ref()
                .ok_or_else(|| need("`axes`", "give the semi-axes [a, b, c] in mm"))?;
            let (v, d) = super::coords(a, "fit.axes")?;
            if d != 3 || v.min_element() <= 0.0 {
                return Err(Diagnostic::new(
                    ErrorKind::FitAxes,
                    "fit.axes must be 3 positive semi-axes [a, b, c]",
                )
                .at(a.span()));
            }
            (Surface::Ellipsoid { axes: v }, (Kind::Sheet, 3))
        }
        "revolution" => {
            let p = raw.profile.as_ref().ok_or_else(|| {
                need(
                    "`profile`",
                    "give the profile as [[r, z], ...] points, one per row after the seed's",
                )
            })?;
            let pts = p
                .get_ref()
                .iter()
                .map(|c| {
                    let (v, d) = super::coords(c, "a profile point")?;
                    if d != 2 || v.x <= 0.0 {
                        return Err(Diagnostic::new(
                            ErrorKind::FitProfilePoint,
                            "a profile point is [r, z] with r > 0",
                        )
                        .at(c.span()));
                    }
                    Ok(DVec2::new(v.x, v.y))
                })
                .collect::<Result<Vec<_>, _>>()?;
            (Surface::Revolution { profile: pts }, (Kind::Loop, 3))
        }
        "torus" => {
            let r = raw.radius.as_ref().ok_or_else(|| {
                need(
                    "`radius`",
                    "give the radius of the tube's centre circle in mm",
                )
            })?;
            let t = raw
                .tube
                .as_ref()
                .ok_or_else(|| need("`tube`", "give the tube's radius in mm"))?;
            let (major, minor) = (positive(r, "fit.radius")?, positive(t, "fit.tube")?);
            if minor >= major {
                return Err(Diagnostic::new(
                    ErrorKind::FitTubeTooLarge,
                    "fit.tube must be smaller than fit.radius",
                )
                .at(t.span())
                .hint("a torus's tube is narrower than its centre circle"));
            }
            let step = match &raw.step {
                Some(s) => super::finite(s, "fit.step")?,
                None => 18.0,
            };
            if !(step > 0.0 && step < 90.0) {
                let span = raw.step.as_ref().map_or(f.span(), |s| s.span());
                return Err(Diagnostic::new(
                    ErrorKind::FitStepOutOfRange,
                    format!("fit.step is {step}, but must be between 0 and 90 degrees"),
                )
                .at(span)
                .hint("the tube angle each row adds, in degrees"));
            }
            let rows = super::count(&raw.rows, "fit.rows", 1, 10_000)?;
            let profile = (1..=rows)
                .map(|i| {
                    let psi = (i as f64 * step).to_radians();
                    DVec2::new(major + minor * psi.sin(), minor * psi.cos())
                })
                .collect();
            (
                Surface::Torus {
                    major,
                    minor,
                    profile,
                },
                (Kind::Loop, 3),
            )
        }
        other => {
            return Err(Diagnostic::new(
                ErrorKind::UnknownFitSurface,
                format!("unknown fit surface \"{other}\""),
            )
            .at(raw.surface.span())
            .hint("surface must be \"disk\", \"ellipsoid\", \"torus\" or \"revolution\""));
        }
    };
    // A loop seed round the rim of a spheroid climbs it ring by ring.
    let spheroid_loop = matches!(surface, Surface::Ellipsoid { axes } if (axes.x - axes.y).abs() <= 1e-9 * axes.x)
        && (kind, dim) == (Kind::Loop, 3);
    if (kind, dim) != want && !spheroid_loop {
        return Err(Diagnostic::new(
            ErrorKind::FitDimension,
            format!(
                "fit surface \"{}\" grows a {}-D {}, but the seed is a {dim}-D {}",
                raw.surface.get_ref(),
                want.1,
                want.0.name(),
                kind.name()
            ),
        )
        .at(raw.surface.span())
        .hint(format!(
            "use seed = \"{}\" with {}-coordinate points",
            want.0.name(),
            want.1
        )));
    }
    let rows = super::count(&raw.rows, "fit.rows", 1, 10_000)?;
    if let Surface::Revolution { profile } = &surface
        && profile.len() != rows
    {
        return Err(Diagnostic::new(
            ErrorKind::FitProfileRows,
            format!(
                "the profile has {} points but fit.rows is {rows}",
                profile.len()
            ),
        )
        .at(raw.rows.span())
        .hint("give one profile point per grown row: where that row's vertices go"));
    }
    let samples = match &raw.samples {
        Some(n) => super::count(n, "fit.samples", 3, 2000)?,
        None => 61,
    };
    let list = |l: &Option<Spanned<Vec<super::raw::Num>>>,
                what: &str,
                open: bool|
     -> Result<Option<Vec<f64>>, Diagnostic> {
        let Some(l) = l else { return Ok(None) };
        if !open {
            return Err(Diagnostic::new(ErrorKind::FitUnused, format!("fit.{what} is not used by this target"))
                .at(l.span())
                .hint("fit.angles is for disk and ellipsoid sheets, fit.steps for an ellipsoid grown from a loop"));
        }
        if l.get_ref().len() != rows {
            return Err(Diagnostic::new(
                ErrorKind::FitValuesPerRow,
                format!(
                    "fit.{what} has {} values but fit.rows is {rows}",
                    l.get_ref().len()
                ),
            )
            .at(l.span())
            .hint("give one value per grown row"));
        }
        l.get_ref()
            .iter()
            .map(|n| super::finite(n, &format!("a value of fit.{what}")))
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    };
    let open = matches!(surface, Surface::Disk { .. })
        || (matches!(surface, Surface::Ellipsoid { .. }) && kind == Kind::Sheet);
    let angles = list(&raw.angles, "angles", open)?;
    let steps = list(&raw.steps, "steps", spheroid_loop)?;
    if let (Some(st), Some(l)) = (&steps, &raw.steps)
        && st.iter().any(|x| *x <= 0.0)
    {
        return Err(Diagnostic::new(
            ErrorKind::FitStepsNotPositive,
            "fit.steps must be positive lengths",
        )
        .at(l.span())
        .hint("each ring's step down the meridian, in mm"));
    }
    Ok(Fit {
        surface,
        rows,
        samples,
        angles,
        steps,
        spans: FitSpans {
            table: f.span(),
            angles: raw.angles.as_ref().map(|a| a.span()),
            steps: raw.steps.as_ref().map(|a| a.span()),
        },
    })
}

impl Surface {
    /// Distance from a point to the target surface (for the fit error).
    pub fn distance(&self, p: DVec3) -> f64 {
        match self {
            Surface::Disk { radius } => (p.truncate().length() - radius).max(0.0),
            Surface::Ellipsoid { axes } => ellipsoid_distance(*axes, p),
            Surface::Torus { major, minor, .. } => {
                (DVec2::new(p.truncate().length() - major, p.z).length() - minor).abs()
            }
            Surface::Revolution { profile } => {
                let q = DVec2::new(p.truncate().length(), p.z);
                profile
                    .windows(2)
                    .map(|w| segment_distance(q, w[0], w[1]))
                    .fold(
                        profile.first().map_or(f64::INFINITY, |a| a.distance(q)),
                        f64::min,
                    )
            }
        }
    }

    /// A length for relative errors.
    pub fn size(&self) -> f64 {
        match self {
            Surface::Disk { radius } => 2.0 * radius,
            Surface::Ellipsoid { axes } => 2.0 * axes.max_element(),
            Surface::Revolution { profile } => {
                2.0 * profile.iter().map(|p| p.x).fold(0.0, f64::max)
            }
            Surface::Torus { major, minor, .. } => 2.0 * (major + minor),
        }
    }

    /// Distance along the ray `p + t v` (t > 0) to the surface's boundary:
    /// the circle, or the ellipsoid.
    fn ray_exit(&self, p: DVec3, v: DVec3) -> Option<f64> {
        let (p, v) = match self {
            Surface::Disk { radius } => (p / *radius, v / *radius),
            Surface::Ellipsoid { axes } => (p / *axes, v / *axes),
            Surface::Revolution { .. } | Surface::Torus { .. } => return None,
        };
        // |p + t v|^2 = 1 in scaled coordinates.
        let (a, b, c) = (v.length_squared(), p.dot(v), p.length_squared() - 1.0);
        let disc = b * b - a * c;
        if c >= 0.0 || disc < 0.0 {
            return None;
        }
        Some((-b + disc.sqrt()) / a)
    }
}

fn segment_distance(q: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let t = ((q - a).dot(ab) / ab.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    q.distance(a + t * ab)
}

/// Distance to the half ellipsoid (z <= 0) by Newton on the foot point
/// parameter (Eberly's method, enough for a fit error).
fn ellipsoid_distance(e: DVec3, p: DVec3) -> f64 {
    let y = p.abs();
    // Solve sum (e_i y_i / (t + e_i^2))^2 = 1 for the largest root t.
    let f = |t: f64| -> f64 {
        (0..3)
            .map(|i| (e[i] * y[i] / (t + e[i] * e[i])).powi(2))
            .sum::<f64>()
            - 1.0
    };
    let lo = -e.min_element().powi(2);
    let (mut a, mut b) = (lo + 1e-12, y.length() * e.max_element() + 1.0);
    if f(a) < 0.0 {
        a = lo;
    }
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if f(m) > 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
    let t = 0.5 * (a + b);
    let foot = DVec3::new(
        e.x * e.x * y.x / (t + e.x * e.x),
        e.y * e.y * y.y / (t + e.y * e.y),
        e.z * e.z * y.z / (t + e.z * e.z),
    );
    let d = foot.distance(y);
    if d.is_finite() { d } else { 0.0 }
}

/// The fit error of a lattice: the largest vertex distance to the target,
/// absolute (mm) and relative to the target's size.
pub fn error(fit: &Fit, lattice: &Lattice) -> (f64, f64) {
    // A profile runs from the seed's circle through every row's point.
    let surface = match &fit.surface {
        Surface::Revolution { profile } => {
            let seed = lattice.vertices[0].pos;
            let mut curve = vec![DVec2::new(seed.truncate().length(), seed.z)];
            curve.extend(profile);
            Surface::Revolution { profile: curve }
        }
        other => other.clone(),
    };
    let worst = lattice
        .vertices
        .iter()
        .map(|v| surface.distance(v.pos))
        .fold(0.0, f64::max);
    (worst, worst / surface.size())
}

/// Grow the fitted lattice; `progress` hears about each row.
pub fn grow(
    design: &Design,
    fit: &Fit,
    progress: &mut dyn FnMut(&str),
) -> Result<Lattice, GrowthError> {
    grow_recorded(design, fit, progress).map(|(l, _)| l)
}

/// The row angles an open fit's search chose (None for other fits): where
/// the optimiser starts when the recipe gives no `fit.angles`.
pub fn searched_angles(design: &Design, fit: &Fit) -> Option<Vec<f64>> {
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
        || matches!(fit.surface, Surface::Ellipsoid { .. }) && design.kind == Kind::Sheet;
    if open {
        // Legs shorter than the eyelet flange (plus a wall) cannot be built.
        let min_leg = design.fabrication.eyelet.flange + 2.0 * super::MIN_WALL;
        if let Some(angles) = &fit.angles {
            for (i, &a) in angles.iter().enumerate() {
                let params = row_on_boundary(
                    &mut grower,
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
        };
        return if search.rows(&mut grower, 0) {
            Ok((grower.into_lattice(), Some(search.chosen)))
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
}

impl Search<'_> {
    /// Grow rows `i..` onto `grower`; false (with the rows taken back) if
    /// they cannot all be grown within the budget.
    fn rows(&mut self, grower: &mut Grower, i: usize) -> bool {
        if i == self.fit.rows {
            return true;
        }
        let (candidates, why) = ranked_rows(
            grower,
            &self.fit.surface,
            self.fit.samples,
            self.dim,
            self.min_leg,
            self.strip,
        );
        if i > self.deepest.0 || candidates.is_empty() && i == self.deepest.0 {
            self.deepest = (i, why.filter(|_| candidates.is_empty()));
        }
        for params in candidates.into_iter().take(BRANCHES) {
            if self.budget == 0 {
                return false;
            }
            self.budget -= 1;
            if grower.grow_row(&params).is_err() {
                continue;
            }
            if let Some(Direction::Angles { angle_deg, .. }) = params.direction {
                self.chosen.push(angle_deg);
            }
            (self.progress)(&row_note(self.fit, grower.lattice(), i));
            if self.rows(grower, i + 1) {
                return true;
            }
            grower.undo_row();
            self.chosen.pop();
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
fn no_row(i: usize) -> GrowthError {
    GrowthError::new(
        crate::lattice::GrowthErrorKind::InadmissibleDirection,
        crate::lattice::Param::Direction,
        Some(i),
        None,
        format!(
            "no leg direction found for this row (the deepest the fit reached in {SEARCH_BUDGET} tries) that keeps its end vertices on the target boundary with legs long enough for the eyelets"
        ),
        "fit fewer rows, or start from another seed arc",
    )
}

/// Scan the start direction of an open row; for each, put the end vertices
/// on the boundary (circle or ellipsoid) and score the row. The candidates
/// best first, and the last growth error met (for a row with none).
fn ranked_rows(
    grower: &mut Grower,
    surface: &Surface,
    samples: usize,
    dim: usize,
    min_leg: f64,
    strip: (f64, f64, f64),
) -> (Vec<RowParams>, Option<GrowthError>) {
    let tilts: Vec<f64> = if dim == 3 {
        (0..samples.div_ceil(4).max(3))
            .map(|k| -60.0 + 120.0 * k as f64 / (samples.div_ceil(4).max(3) - 1) as f64)
            .collect()
    } else {
        vec![0.0]
    };
    let mut scored: Vec<(f64, RowParams)> = Vec::new();
    let mut last_error = None;
    for &tilt in &tilts {
        for k in 1..samples {
            let angle = -89.0 + 178.0 * k as f64 / samples as f64;
            let direction = Some(Direction::Angles {
                angle_deg: angle,
                tilt_deg: tilt,
            });
            let params = match row_on_boundary(grower, surface, direction) {
                Ok(p) => p,
                Err(e) => {
                    last_error = e.or(last_error);
                    continue;
                }
            };
            if let Err(e) = grower.grow_row(&params) {
                last_error = Some(e);
                continue;
            }
            let score = row_score(grower.lattice(), surface, min_leg);
            // A disk's rows whose strips overlap others of their layer come
            // last (on a curved patch the distance to the surface decides).
            let lattice = grower.lattice();
            let first_new = 2 * (lattice.cells.len() - lattice.width);
            let clashes = if score.is_finite() && matches!(surface, Surface::Disk { .. }) {
                crate::parts::clash::clashes(lattice, strip.0, strip.1, strip.2)
                    .iter()
                    .filter(|c| c.rods[1] >= first_new)
                    .count()
            } else {
                0
            };
            grower.undo_row();
            let score = score + clashes as f64;
            if score.is_finite() {
                scored.push((score, params));
            }
        }
    }
    // A stable sort keeps scan order among equal scores: deterministic.
    scored.sort_by(|a, b| a.0.total_cmp(&b.0));
    (scored.into_iter().map(|s| s.1).collect(), last_error)
}

/// The row with leg direction `direction` whose two end vertices lie on the
/// surface's boundary (circle or ellipsoid); the growth error met, if any.
fn row_on_boundary(
    grower: &mut Grower,
    surface: &Surface,
    direction: Option<Direction>,
) -> Result<RowParams, Option<GrowthError>> {
    // Pivots do not depend on the end legs: grow once to find them.
    let probe = RowParams {
        direction,
        left_leg: Leg::Length(1.0),
        right_leg: Leg::Length(1.0),
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
    let (Some(l2), Some(l3)) = legs else {
        return Err(None);
    };
    Ok(RowParams {
        direction,
        left_leg: Leg::Length(l2),
        right_leg: Leg::Length(l3),
        ..RowParams::default()
    })
}

/// Lower is better: distance of the new vertices to the surface (3-D), then
/// the worst cell's shape: uneven legs (min/max leg ratio) or a cell near
/// flat-open or collapsed (sine of phi), so rows stay open and buildable.
fn row_score(lattice: &Lattice, surface: &Surface, min_leg: f64) -> f64 {
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
    // A disk's vertices stay inside (or on) its circle.
    if let Surface::Disk { radius } = surface
        && new
            .iter()
            .any(|v| v.pos.truncate().length() > radius * (1.0 + 1e-9))
    {
        return f64::INFINITY;
    }
    match surface {
        Surface::Ellipsoid { .. } => {
            let d = new
                .iter()
                .map(|v| surface.distance(v.pos))
                .fold(0.0, f64::max);
            d / surface.size() * 20.0 + balance
        }
        _ => balance,
    }
}

/// How much of the target the cells cover, measured from the cells' own
/// corners.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coverage {
    /// Covered share, 0 to 1.
    pub share: f64,
    /// What is covered: "the disk's area", "the half's area in plan",
    /// "the tube's circumference".
    pub of: &'static str,
    /// For a torus: the tube angle covered (degrees).
    pub degrees: Option<f64>,
}

/// Samples per axis of the area coverage grid (a 1/300 of the target's width).
const COVERAGE_SAMPLES: usize = 300;

/// The share of the target the lattice covers: the disk's area, the
/// ellipsoid's half in plan (projected onto z = 0), or the torus's tube
/// circumference. None for a free revolution profile.
pub fn coverage(fit: &Fit, lattice: &Lattice) -> Option<Coverage> {
    match &fit.surface {
        Surface::Disk { radius } => Some(Coverage {
            share: plan_coverage(lattice, *radius, *radius),
            of: "the disk's area",
            degrees: None,
        }),
        Surface::Ellipsoid { axes } => Some(Coverage {
            share: plan_coverage(lattice, axes.x, axes.y),
            of: "the half's area in plan",
            degrees: None,
        }),
        Surface::Torus { major, .. } => {
            let deg = tube_coverage(lattice, *major);
            Some(Coverage {
                share: deg / 360.0,
                of: "the tube's circumference",
                degrees: Some(deg),
            })
        }
        Surface::Revolution { .. } => None,
    }
}

/// The share of the ellipse x^2/a^2 + y^2/b^2 <= 1 under the cells,
/// projected onto the xy-plane: the centres of a square grid of samples,
/// each tested against the cells that a bin grid says are near it.
fn plan_coverage(lattice: &Lattice, a: f64, b: f64) -> f64 {
    let n = COVERAGE_SAMPLES;
    let h = 2.0 * a.max(b) / n as f64;
    let quads: Vec<[DVec2; 4]> = lattice
        .cells
        .iter()
        .map(|c| {
            let [ul, ur, ll, lr] = lattice.corners(c);
            // In order round the quad.
            [ul, ur, lr, ll].map(|p| p.truncate())
        })
        .collect();
    // Bins of 8 x 8 samples hold the cells whose boxes reach them.
    let bin = 8;
    let bins = n.div_ceil(bin);
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); bins * bins];
    let origin = DVec2::new(-a.max(b), -a.max(b));
    let index = |x: f64| ((x / (h * bin as f64)).floor().max(0.0) as usize).min(bins - 1);
    for (q, quad) in quads.iter().enumerate() {
        let lo = quad
            .iter()
            .fold(DVec2::splat(f64::INFINITY), |m, p| m.min(*p))
            - origin;
        let hi = quad
            .iter()
            .fold(DVec2::splat(f64::NEG_INFINITY), |m, p| m.max(*p))
            - origin;
        if !(lo.is_finite() && hi.is_finite()) {
            continue;
        }
        for y in index(lo.y)..=index(hi.y) {
            for x in index(lo.x)..=index(hi.x) {
                grid[y * bins + x].push(q as u32);
            }
        }
    }
    let (mut inside, mut covered) = (0usize, 0usize);
    for iy in 0..n {
        for ix in 0..n {
            let p = origin + h * DVec2::new(ix as f64 + 0.5, iy as f64 + 0.5);
            if (p.x / a).powi(2) + (p.y / b).powi(2) > 1.0 {
                continue;
            }
            inside += 1;
            let cell = &grid[(iy / bin) * bins + ix / bin];
            if cell.iter().any(|&q| in_quad(&quads[q as usize], p)) {
                covered += 1;
            }
        }
    }
    covered as f64 / inside.max(1) as f64
}

/// Inside (or on) a convex quad given in order round it, either orientation.
fn in_quad(q: &[DVec2; 4], p: DVec2) -> bool {
    let mut sign = 0.0f64;
    for k in 0..4 {
        let (a, b) = (q[k], q[(k + 1) % 4]);
        let c = (b - a).perp_dot(p - a);
        if c != 0.0 {
            if sign * c < 0.0 {
                return false;
            }
            sign = c;
        }
    }
    true
}

/// Degrees of the tube's circumference under the cells: each cell spans
/// the tube angles of its corners (psi = atan2(rho - R, z), 0 at the top);
/// the union of those arcs.
fn tube_coverage(lattice: &Lattice, major: f64) -> f64 {
    let psi = |p: DVec3| (p.truncate().length() - major).atan2(p.z).to_degrees();
    let mut arcs: Vec<(f64, f64)> = Vec::new();
    for c in &lattice.cells {
        let angles = lattice.corners(c).map(psi);
        // The shortest arc holding all four: unwrap about the first.
        let a0 = angles[0];
        let rel: Vec<f64> = angles
            .iter()
            .map(|a| (a - a0 + 540.0).rem_euclid(360.0) - 180.0)
            .collect();
        let lo = (rel.iter().copied().fold(f64::INFINITY, f64::min) + a0).rem_euclid(360.0);
        let span = rel.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - rel.iter().copied().fold(f64::INFINITY, f64::min);
        if lo + span > 360.0 {
            arcs.push((lo, 360.0));
            arcs.push((0.0, lo + span - 360.0));
        } else {
            arcs.push((lo, lo + span));
        }
    }
    arcs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut total, mut end) = (0.0, f64::NEG_INFINITY);
    for (a, b) in arcs {
        if b <= end {
            continue;
        }
        total += b - a.max(end);
        end = b;
    }
    total
}

/// The largest distance of a boundary vertex (the seed's and each row's
/// two ends) from the target's boundary curve (the disk's circle), or None
/// for targets without one.
pub fn boundary_error(fit: &Fit, lattice: &Lattice) -> Option<f64> {
    let Surface::Disk { radius } = fit.surface else {
        return None;
    };
    let m = lattice.width as u32;
    Some(
        lattice
            .vertices
            .iter()
            .filter(|v| v.key.row == 0 || v.key.col == 0 || v.key.col == m)
            .map(|v| (v.pos.truncate().length() - radius).abs())
            .fold(0.0, f64::max),
    )
}
