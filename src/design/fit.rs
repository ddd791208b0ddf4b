//! Target fitting (docs/math.md 6.4): the `[fit]` table of a recipe, the target
//! surfaces and how far a lattice is from them (error, coverage). The
//! search that grows the rows is `solve::fit`.

use super::raw::RawFit;
use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::lattice::{Kind, Lattice};
use glam::{DVec2, DVec3};
use toml::Spanned;

mod coverage;
pub use coverage::{Coverage, coverage};

#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Surface {
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
    /// Any target (docs/design.md): a mesh or a family, met by rays and
    /// closest points through its bounding-volume tree. Made by
    /// `karigami design`, never written in a recipe.
    Target(Shared),
}

/// A target shared by the fits of one search; equal when the same one.
#[derive(Clone, Debug)]
pub(crate) struct Shared(pub(crate) std::sync::Arc<crate::target::Target>);

impl PartialEq for Shared {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.0, &other.0)
    }
}

impl Fit {
    /// A fit that grows `rows` rows of a 3-D sheet onto `target`, each
    /// row's direction scanned over `samples` angles.
    pub(crate) fn on_target(
        target: std::sync::Arc<crate::target::Target>,
        rows: usize,
        samples: usize,
    ) -> Fit {
        Fit {
            surface: Surface::Target(Shared(target)),
            rows,
            samples,
            angles: None,
            steps: None,
            spans: FitSpans::default(),
        }
    }
}

/// A validated `[lattice.fit]` table: the target surface and how the search
/// grows rows towards it.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    pub(crate) surface: Surface,
    pub(crate) rows: usize,
    /// Directions tried per row (per axis, for the ellipsoid).
    pub(crate) samples: usize,
    /// Open fits: each row's leg angle, given instead of searched for.
    pub(crate) angles: Option<Vec<f64>>,
    /// Ellipsoid loops: each ring's step down the meridian (mm).
    pub(crate) steps: Option<Vec<f64>>,
    /// Where the table and those lists were written (for rewriting them).
    pub(crate) spans: FitSpans,
}

#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct FitSpans {
    pub(crate) table: std::ops::Range<usize>,
    pub(crate) angles: Option<std::ops::Range<usize>>,
    pub(crate) steps: Option<std::ops::Range<usize>>,
}

pub(crate) fn parse(f: &Spanned<RawFit>, kind: Kind, dim: usize) -> Result<Fit, Diagnostic> {
    let raw = f.get_ref();
    let (surface, want) = target_surface(f)?;
    let spheroid_loop = check_seed(raw, &surface, want, kind, dim)?;
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
    let open = matches!(surface, Surface::Disk { .. })
        || (matches!(surface, Surface::Ellipsoid { .. }) && kind == Kind::Sheet);
    let angles = per_row(&raw.angles, "angles", open, rows)?;
    let steps = per_row(&raw.steps, "steps", spheroid_loop, rows)?;
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

/// The seed's kind and dimension a target surface grows from.
type Want = (Kind, usize);

/// A key the surface needs but the table lacks.
fn need(f: &Spanned<RawFit>, what: &str, hint: &str) -> Diagnostic {
    Diagnostic::new(
        ErrorKind::FitNeeds,
        format!(
            "fit surface \"{}\" needs {what}",
            f.get_ref().surface.get_ref()
        ),
    )
    .at(f.span())
    .hint(hint.to_string())
}

fn positive(n: &super::raw::Num, what: &str) -> Result<f64, Diagnostic> {
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
}

/// The target surface the table names, with the seed it grows from.
fn target_surface(f: &Spanned<RawFit>) -> Result<(Surface, Want), Diagnostic> {
    let raw = f.get_ref();
    Ok(match raw.surface.get_ref().as_str() {
        "disk" => {
            let r = raw
                .radius
                .as_ref()
                .ok_or_else(|| need(f, "`radius`", "give the disk's radius in mm"))?;
            (
                Surface::Disk {
                    radius: positive(r, "fit.radius")?,
                },
                (Kind::Sheet, 2),
            )
        }
        "ellipsoid" => (ellipsoid(f)?, (Kind::Sheet, 3)),
        "revolution" => (revolution(f)?, (Kind::Loop, 3)),
        "torus" => (torus(f)?, (Kind::Loop, 3)),
        other => {
            return Err(Diagnostic::new(
                ErrorKind::UnknownFitSurface,
                format!("unknown fit surface \"{other}\""),
            )
            .at(raw.surface.span())
            .hint("surface must be \"disk\", \"ellipsoid\", \"torus\" or \"revolution\""));
        }
    })
}

fn ellipsoid(f: &Spanned<RawFit>) -> Result<Surface, Diagnostic> {
    let a = f
        .get_ref()
        .axes
        .as_ref()
        .ok_or_else(|| need(f, "`axes`", "give the semi-axes [a, b, c] in mm"))?;
    let (v, d) = super::coords(a, "fit.axes")?;
    if d != 3 || v.min_element() <= 0.0 {
        return Err(Diagnostic::new(
            ErrorKind::FitAxes,
            "fit.axes must be 3 positive semi-axes [a, b, c]",
        )
        .at(a.span()));
    }
    Ok(Surface::Ellipsoid { axes: v })
}

fn revolution(f: &Spanned<RawFit>) -> Result<Surface, Diagnostic> {
    let p = f.get_ref().profile.as_ref().ok_or_else(|| {
        need(
            f,
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
    Ok(Surface::Revolution { profile: pts })
}

/// A torus's profile is generated here, one tube point per row, so it
/// reads `fit.rows` before the checks common to every surface do.
fn torus(f: &Spanned<RawFit>) -> Result<Surface, Diagnostic> {
    let raw = f.get_ref();
    let r = raw.radius.as_ref().ok_or_else(|| {
        need(
            f,
            "`radius`",
            "give the radius of the tube's centre circle in mm",
        )
    })?;
    let t = raw
        .tube
        .as_ref()
        .ok_or_else(|| need(f, "`tube`", "give the tube's radius in mm"))?;
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
            format!(
                "fit.step is {}, but must be more than 0 and less than 90 degrees",
                crate::diagnostic::shown(step)
            ),
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
    Ok(Surface::Torus {
        major,
        minor,
        profile,
    })
}

/// Checks the seed is the one the surface grows from, and says whether it
/// is a spheroid loop: a loop seed round the rim of a spheroid climbs it
/// ring by ring, so it may fit an ellipsoid too.
fn check_seed(
    raw: &RawFit,
    surface: &Surface,
    want: Want,
    kind: Kind,
    dim: usize,
) -> Result<bool, Diagnostic> {
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
    Ok(spheroid_loop)
}

/// A list of one value per grown row (`fit.angles`, `fit.steps`), if
/// given; `used` says whether this target reads it.
fn per_row(
    l: &Option<Spanned<Vec<super::raw::Num>>>,
    what: &str,
    used: bool,
    rows: usize,
) -> Result<Option<Vec<f64>>, Diagnostic> {
    let Some(l) = l else { return Ok(None) };
    if !used {
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
}

impl Surface {
    /// Distance from a point to the target surface (for the fit error).
    pub(crate) fn distance(&self, p: DVec3) -> f64 {
        match self {
            Surface::Disk { radius } => (p.truncate().length() - radius).max(0.0),
            Surface::Ellipsoid { axes } => ellipsoid_distance(*axes, p),
            Surface::Torus { major, minor, .. } => {
                (DVec2::new(p.truncate().length() - major, p.z).length() - minor).abs()
            }
            Surface::Target(t) => t.0.closest(p).1,
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
    pub(crate) fn size(&self) -> f64 {
        match self {
            Surface::Disk { radius } => 2.0 * radius,
            Surface::Ellipsoid { axes } => 2.0 * axes.max_element(),
            Surface::Revolution { profile } => {
                2.0 * profile.iter().map(|p| p.x).fold(0.0, f64::max)
            }
            Surface::Torus { major, minor, .. } => 2.0 * (major + minor),
            Surface::Target(t) => t.0.extent,
        }
    }

    /// Distance along the ray `p + t v` (t > 0) to the surface's boundary:
    /// the circle, or the ellipsoid, or a target's first crossing.
    pub(crate) fn ray_exit(&self, p: DVec3, v: DVec3) -> Option<f64> {
        let (p, v) = match self {
            // Beyond a hair of the pivot: a leg of zero length is no leg.
            Surface::Target(t) => return target_exit(&t.0, p, v),
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

/// Where the ray `p + t v` (v a unit vector) leaves a target patch: on the
/// first stretch of the ray within `EXIT_BAND` of D of the surface, the
/// crossing when the ray meets the surface at an angle (a short stretch),
/// else the stretch's end, where a ray running along the surface passes
/// its edge (a flat or nearly flat patch). None when it never comes near.
fn target_exit(t: &crate::target::Target, p: DVec3, v: DVec3) -> Option<f64> {
    let (d, band) = (t.extent, EXIT_BAND * t.extent);
    let h = d / 200.0;
    // Marched in 400 steps: each asks only whether the target is within
    // the band, not where it is (96 % of an oval cap's design went to
    // unbounded closest-point searches here).
    let near = |s: f64| t.near(p + s * v, band);
    let start = (1..=400).map(|k| k as f64 * h).find(|&s| near(s))?;
    let mut end = start;
    while end < 2.0 * d && near(end + h) {
        end += h;
    }
    // The stretch's end to within a thousandth of a step.
    let (mut a, mut b) = (end, end + h);
    for _ in 0..10 {
        let m = 0.5 * (a + b);
        if near(m) { a = m } else { b = m }
    }
    let end = a;
    if end - start > 4.0 * band / (1.0 - 0.95f64.powi(2)).sqrt() {
        return Some(end);
    }
    // A crossing: the distance's least on the stretch (golden section).
    let (mut lo, mut hi) = ((start - h).max(0.0), end);
    let f = |s: f64| t.closest(p + s * v).1;
    for _ in 0..40 {
        let (m1, m2) = (lo + 0.382 * (hi - lo), lo + 0.618 * (hi - lo));
        if f(m1) <= f(m2) { hi = m2 } else { lo = m1 }
    }
    Some(0.5 * (lo + hi)).filter(|s| *s > 1e-6 * d)
}

/// How near a target (a share of D) a ray counts as on it.
const EXIT_BAND: f64 = 0.002;

/// The plan distance from `q` to the segment from `a` to `b`.
pub(crate) fn segment_distance(q: DVec2, a: DVec2, b: DVec2) -> f64 {
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

/// The largest distance of a boundary vertex (the seed's, each row's two
/// ends and the last row's) from the target's boundary curve (the disk's
/// circle), or None for targets without one.
pub(crate) fn boundary_error(fit: &Fit, lattice: &Lattice) -> Option<f64> {
    let Surface::Disk { radius } = fit.surface else {
        return None;
    };
    let m = lattice.width as u32;
    let last = lattice.vertices.iter().map(|v| v.key.row).max()?;
    Some(
        lattice
            .vertices
            .iter()
            .filter(|v| v.key.row == 0 || v.key.row == last || v.key.col == 0 || v.key.col == m)
            .map(|v| (v.pos.truncate().length() - radius).abs())
            .fold(0.0, f64::max),
    )
}
