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
use crate::diagnostic::Diagnostic;
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
}

#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    pub surface: Surface,
    pub rows: usize,
    /// Directions tried per row (per axis, for the ellipsoid).
    pub samples: usize,
}

pub fn parse(f: &Spanned<RawFit>, kind: Kind, dim: usize) -> Result<Fit, Diagnostic> {
    let raw = f.get_ref();
    let need = |what: &str, hint: &str| {
        Diagnostic::new(
            "design",
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
            Err(Diagnostic::new("design", format!("{what} must be positive")).at(n.span()))
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
                    "design",
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
                            "design",
                            "a profile point is [r, z] with r > 0",
                        )
                        .at(c.span()));
                    }
                    Ok(DVec2::new(v.x, v.y))
                })
                .collect::<Result<Vec<_>, _>>()?;
            (Surface::Revolution { profile: pts }, (Kind::Loop, 3))
        }
        other => {
            return Err(
                Diagnostic::new("design", format!("unknown fit surface \"{other}\""))
                    .at(raw.surface.span())
                    .hint("surface must be \"disk\", \"ellipsoid\" or \"revolution\""),
            );
        }
    };
    // A loop seed round the rim of a spheroid climbs it ring by ring.
    let spheroid_loop = matches!(surface, Surface::Ellipsoid { axes } if (axes.x - axes.y).abs() <= 1e-9 * axes.x)
        && (kind, dim) == (Kind::Loop, 3);
    if (kind, dim) != want && !spheroid_loop {
        return Err(Diagnostic::new(
            "design",
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
            "design",
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
    Ok(Fit {
        surface,
        rows,
        samples,
    })
}

impl Surface {
    /// Distance from a point to the target surface (for the fit error).
    pub fn distance(&self, p: DVec3) -> f64 {
        match self {
            Surface::Disk { radius } => (p.truncate().length() - radius).max(0.0),
            Surface::Ellipsoid { axes } => ellipsoid_distance(*axes, p),
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
        }
    }

    /// Distance along the ray `p + t v` (t > 0) to the surface's boundary:
    /// the circle, or the ellipsoid.
    fn ray_exit(&self, p: DVec3, v: DVec3) -> Option<f64> {
        let (p, v) = match self {
            Surface::Disk { radius } => (p / *radius, v / *radius),
            Surface::Ellipsoid { axes } => (p / *axes, v / *axes),
            Surface::Revolution { .. } => return None,
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
    let mut grower = Grower::new(design.kind, design.dim, &design.points, &design.kappa)?;
    let open = matches!(fit.surface, Surface::Disk { .. })
        || matches!(fit.surface, Surface::Ellipsoid { .. }) && design.kind == Kind::Sheet;
    if open {
        // Legs shorter than the eyelet flange (plus a wall) cannot be built.
        let min_leg = design.fabrication.eyelet.flange + 2.0 * super::MIN_WALL;
        let mut search = Search {
            fit,
            dim: design.dim,
            min_leg,
            budget: SEARCH_BUDGET,
            deepest: (0, None),
            progress,
        };
        return if search.rows(&mut grower, 0) {
            Ok(grower.into_lattice())
        } else {
            Err(search.deepest.1.unwrap_or_else(|| no_row(search.deepest.0)))
        };
    }
    for i in 0..fit.rows {
        let params = match &fit.surface {
            Surface::Ellipsoid { axes } if design.kind == Kind::Loop => {
                let front = grower.front();
                let next = meridian_step(*axes, front[0].pos, front[1].pos);
                RowParams {
                    target: Some(next),
                    ..RowParams::default()
                }
            }
            Surface::Revolution { profile } => {
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
    Ok(grower.into_lattice())
}

/// The point one front edge (|x1 - x0|) further down the spheroid's meridian
/// through `x1`, towards z < 0: where the next ring's vertex goes.
fn meridian_step(axes: DVec3, x0: DVec3, x1: DVec3) -> DVec3 {
    let (a, c) = (axes.x, axes.z);
    let theta = x1.y.atan2(x1.x);
    // Meridian (a cos t, c sin t), t from 0 at the rim to -pi/2 at the pole.
    let r = x1.truncate().length();
    let mut t = -(r / a).clamp(-1.0, 1.0).acos() * if x1.z > 0.0 { -1.0 } else { 1.0 };
    let edge = x0.distance(x1);
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
    /// Rows left to try.
    budget: usize,
    /// The deepest row reached, and why it found no candidate (when it did not).
    deepest: (usize, Option<GrowthError>),
    progress: &'a mut dyn FnMut(&str),
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
            (self.progress)(&row_note(self.fit, grower.lattice(), i));
            if self.rows(grower, i + 1) {
                return true;
            }
            grower.undo_row();
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
            // Pivots do not depend on the end legs: grow once to find them.
            let probe = RowParams {
                direction,
                left_leg: Leg::Length(1.0),
                right_leg: Leg::Length(1.0),
                ..RowParams::default()
            };
            if let Err(e) = grower.grow_row(&probe) {
                last_error = Some(e);
                continue;
            }
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
            let (Some(l2), Some(l3)) = legs else { continue };
            let params = RowParams {
                direction,
                left_leg: Leg::Length(l2),
                right_leg: Leg::Length(l3),
                ..RowParams::default()
            };
            if let Err(e) = grower.grow_row(&params) {
                last_error = Some(e);
                continue;
            }
            let score = row_score(grower.lattice(), surface, min_leg);
            grower.undo_row();
            if score.is_finite() {
                scored.push((score, params));
            }
        }
    }
    // A stable sort keeps scan order among equal scores: deterministic.
    scored.sort_by(|a, b| a.0.total_cmp(&b.0));
    (scored.into_iter().map(|s| s.1).collect(), last_error)
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
