//! The `[target]` table (docs/design.md, "Analytic targets"): a family
//! and its parameters in mm, where it stands (`at`) and how it is turned
//! (`turn`), and optionally the topology expected of it. Every error points
//! at the line and column to change.

use super::Expect;
use super::surfaces::{Family, MAX_LINES};
use crate::diagnostic::{Diagnostic, ErrorKind, shown};
use glam::{DVec2, DVec3};
use serde::Deserialize;
use std::ops::Range;
use toml::Spanned;

/// A number written as a float or an integer.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(untagged)]
enum Number {
    Float(f64),
    Integer(i64),
}

type Num = Spanned<Number>;
type List = Spanned<Vec<Num>>;
type Rows = Spanned<Vec<List>>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    target: Spanned<RawTarget>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTarget {
    family: Spanned<String>,
    expect: Option<Spanned<String>>,
    at: Option<List>,
    turn: Option<List>,
    radius: Option<Num>,
    height: Option<Num>,
    axes: Option<List>,
    depth: Option<Num>,
    width: Option<Num>,
    length: Option<Num>,
    angle: Option<Num>,
    tube: Option<Num>,
    profile: Option<Rows>,
    heights: Option<Rows>,
    hole: Option<Num>,
}

/// The families and the parameters each takes (docs/design.md).
const FAMILIES: &[(&str, &[&str])] = &[
    ("disk", &["radius"]),
    ("sphere-cap", &["radius", "height"]),
    ("spheroid-cap", &["axes", "height"]),
    ("paraboloid", &["radius", "depth"]),
    ("saddle", &["width", "length", "height"]),
    ("saddle-ring", &["radius", "hole", "height"]),
    ("cylinder", &["radius", "length", "angle"]),
    ("torus", &["radius", "tube"]),
    ("revolution", &["profile"]),
    ("height-field", &["width", "length", "heights"]),
];

/// Parameters a family may leave out.
const OPTIONAL: &[(&str, &str)] = &[("spheroid-cap", "height"), ("cylinder", "angle")];

/// A parsed `[target]` table: the family placed, and what it must be.
pub(crate) struct Parsed {
    pub(crate) family: Family,
    pub(crate) turn: DVec3,
    pub(crate) at: DVec3,
    pub(crate) expect: Option<Expect>,
    /// Where the family was named, for errors of the whole surface.
    pub(crate) span: Range<usize>,
    /// Where `expect` was written, if it was.
    pub(crate) expect_span: Option<Range<usize>>,
}

pub(crate) fn parse(source: &str) -> Result<Parsed, Diagnostic> {
    let raw: RawFile = toml::from_str(source).map_err(|e| {
        Diagnostic::new(ErrorKind::Toml, e.message().trim_end().to_string())
            .at_opt(e.span())
            .hint("a target file is a [target] table with a family and its parameters (docs/design.md)")
    })?;
    let table_span = raw.target.span();
    let t = raw.target.into_inner();
    let name = t.family.get_ref().as_str();
    let Some(&(_, wanted)) = FAMILIES.iter().find(|(n, _)| *n == name) else {
        let names: Vec<&str> = FAMILIES.iter().map(|(n, _)| *n).collect();
        return Err(Diagnostic::new(
            ErrorKind::UnknownTargetFamily,
            format!("unknown target family \"{name}\""),
        )
        .at(t.family.span())
        .hint(format!("family is one of {}", names.join(", "))));
    };
    let given = given(&t);
    for (key, span) in &given {
        if !wanted.contains(key) {
            return Err(Diagnostic::new(
                ErrorKind::TargetUnused,
                format!("the {name} family does not use `{key}`"),
            )
            .at(span.clone())
            .hint(format!("a {name} takes {}", wanted.join(", "))));
        }
    }
    for key in wanted {
        if !given.iter().any(|(k, _)| k == key) && !OPTIONAL.contains(&(name, key)) {
            return Err(Diagnostic::new(
                ErrorKind::TargetNeeds,
                format!("the {name} family needs `{key}`"),
            )
            .at(table_span.clone())
            .hint(format!(
                "a {name} takes {} (docs/design.md)",
                wanted.join(", ")
            )));
        }
    }
    let family = family(name, &t)?;
    let expect = t
        .expect
        .as_ref()
        .map(|e| match e.get_ref().as_str() {
            "patch" => Ok(Expect::Patch),
            "annulus" => Ok(Expect::Annulus),
            "closed" => Ok(Expect::Closed),
            other => Err(Diagnostic::new(
                ErrorKind::TargetParameter,
                format!("unknown topology \"{other}\""),
            )
            .at(e.span())
            .hint("expect is \"patch\", \"annulus\" or \"closed\"")),
        })
        .transpose()?;
    Ok(Parsed {
        family,
        turn: point(t.turn.as_ref(), "turn")?,
        at: point(t.at.as_ref(), "at")?,
        expect,
        span: t.family.span(),
        expect_span: t.expect.as_ref().map(Spanned::span),
    })
}

/// The parameters written, with where.
fn given(t: &RawTarget) -> Vec<(&'static str, Range<usize>)> {
    let n = |x: &Option<Num>| x.as_ref().map(Spanned::span);
    let l = |x: &Option<List>| x.as_ref().map(Spanned::span);
    let r = |x: &Option<Rows>| x.as_ref().map(Spanned::span);
    [
        ("radius", n(&t.radius)),
        ("height", n(&t.height)),
        ("axes", l(&t.axes)),
        ("depth", n(&t.depth)),
        ("width", n(&t.width)),
        ("length", n(&t.length)),
        ("angle", n(&t.angle)),
        ("tube", n(&t.tube)),
        ("profile", r(&t.profile)),
        ("heights", r(&t.heights)),
        ("hole", n(&t.hole)),
    ]
    .into_iter()
    .filter_map(|(k, s)| s.map(|s| (k, s)))
    .collect()
}

fn finite(n: &Num, what: &str) -> Result<f64, Diagnostic> {
    let v = match *n.get_ref() {
        Number::Float(x) => x,
        Number::Integer(i) => i as f64,
    };
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Diagnostic::new(
            ErrorKind::NotFinite,
            format!("{what} is {v}, not a finite number"),
        )
        .at(n.span())
        .hint("use an ordinary number"))
    }
}

/// A number in `lo < x < hi` (or `<= hi` when `closed`), else an error at it.
fn within(
    n: &Num,
    what: &str,
    lo: f64,
    hi: f64,
    closed: bool,
    why: &str,
) -> Result<f64, Diagnostic> {
    let v = finite(n, what)?;
    if v > lo && (v < hi || (closed && v == hi)) {
        return Ok(v);
    }
    let bound = if hi.is_finite() {
        format!(
            "more than {} and {} {}",
            shown(lo),
            if closed { "at most" } else { "less than" },
            shown(hi)
        )
    } else {
        format!("more than {}", shown(lo))
    };
    Err(Diagnostic::new(
        ErrorKind::TargetParameter,
        format!("{what} is {}, but must be {bound}", shown(v)),
    )
    .at(n.span())
    .hint(why.to_string()))
}

fn positive(n: &Option<Num>, what: &str) -> Result<f64, Diagnostic> {
    let n = n.as_ref().expect("checked as given");
    within(
        n,
        what,
        0.0,
        f64::INFINITY,
        false,
        "a length in mm, more than 0",
    )
}

fn point(l: Option<&List>, what: &str) -> Result<DVec3, Diagnostic> {
    let Some(l) = l else { return Ok(DVec3::ZERO) };
    if l.get_ref().len() != 3 {
        return Err(Diagnostic::new(
            ErrorKind::TargetParameter,
            format!("`{what}` has {} numbers, not 3", l.get_ref().len()),
        )
        .at(l.span())
        .hint(format!("give `{what}` as [x, y, z]")));
    }
    let mut p = DVec3::ZERO;
    for (k, n) in l.get_ref().iter().enumerate() {
        p[k] = finite(n, &format!("a number of `{what}`"))?;
    }
    Ok(p)
}

fn family(name: &str, t: &RawTarget) -> Result<Family, Diagnostic> {
    Ok(match name {
        "disk" => Family::Disk {
            radius: positive(&t.radius, "radius")?,
        },
        "sphere-cap" => {
            let radius = positive(&t.radius, "radius")?;
            let height = within(
                t.height.as_ref().expect("given"),
                "height",
                0.0,
                2.0 * radius,
                true,
                "the cap's height in mm; twice the radius is the whole sphere, a closed surface",
            )?;
            Family::SphereCap { radius, height }
        }
        "spheroid-cap" => spheroid(t)?,
        "paraboloid" => Family::Paraboloid {
            radius: positive(&t.radius, "radius")?,
            depth: positive(&t.depth, "depth")?,
        },
        "saddle" => Family::Saddle {
            width: positive(&t.width, "width")?,
            length: positive(&t.length, "length")?,
            height: positive(&t.height, "height")?,
        },
        "saddle-ring" => {
            let radius = positive(&t.radius, "radius")?;
            let hole = within(
                t.hole.as_ref().expect("given"),
                "hole",
                0.0,
                radius,
                false,
                "the inner rim's radius in plan, in mm, more than 0 and less than the radius",
            )?;
            // Height may be negative: the band's high points then lie on y.
            let height = finite(t.height.as_ref().expect("given"), "height")?;
            Family::SaddleRing {
                radius,
                hole,
                height,
            }
        }
        "cylinder" => Family::Cylinder {
            radius: positive(&t.radius, "radius")?,
            length: positive(&t.length, "length")?,
            angle: match &t.angle {
                Some(a) => within(
                    a,
                    "angle",
                    0.0,
                    360.0,
                    true,
                    "the arc's angle in degrees; 360 is a whole tube",
                )?,
                None => 180.0,
            },
        },
        "torus" => {
            let radius = positive(&t.radius, "radius")?;
            let tube = within(
                t.tube.as_ref().expect("given"),
                "tube",
                0.0,
                radius,
                false,
                "the tube's radius, less than the radius of its centre circle",
            )?;
            Family::Torus { radius, tube }
        }
        "revolution" => revolution(t.profile.as_ref().expect("given"))?,
        _ => height_field(t)?,
    })
}

fn spheroid(t: &RawTarget) -> Result<Family, Diagnostic> {
    let a = t.axes.as_ref().expect("given");
    let mut axes = DVec3::ZERO;
    if a.get_ref().len() != 3 {
        return Err(Diagnostic::new(
            ErrorKind::TargetParameter,
            "`axes` must be 3 semi-axes [a, b, c]",
        )
        .at(a.span())
        .hint("the semi-axes along x, y and z in mm"));
    }
    for (k, n) in a.get_ref().iter().enumerate() {
        axes[k] = within(
            n,
            "a semi-axis",
            0.0,
            f64::INFINITY,
            false,
            "a semi-axis in mm, more than 0",
        )?;
    }
    let height = match &t.height {
        Some(h) => within(
            h,
            "height",
            0.0,
            2.0 * axes.z,
            true,
            "the cap's height along z in mm; twice the z semi-axis is the whole spheroid, a closed surface",
        )?,
        None => axes.z,
    };
    Ok(Family::SpheroidCap { axes, height })
}

fn revolution(p: &Rows) -> Result<Family, Diagnostic> {
    let rows = p.get_ref();
    if rows.len() < 2 {
        return Err(Diagnostic::new(
            ErrorKind::TargetParameter,
            "`profile` needs at least 2 points",
        )
        .at(p.span())
        .hint("give the profile as [[r, z], ...] in mm, from one edge to the other"));
    }
    let mut profile = Vec::new();
    for (k, row) in rows.iter().enumerate() {
        let pair = row.get_ref();
        let bad = |why: &str| {
            Diagnostic::new(ErrorKind::TargetParameter, format!("profile point {} {why}", k + 1))
                .at(row.span())
                .hint("a profile point is [r, z] in mm, r > 0 (r = 0 only at either end, where the surface closes over the axis)")
        };
        if pair.len() != 2 {
            return Err(bad("is not [r, z]"));
        }
        let q = DVec2::new(finite(&pair[0], "r")?, finite(&pair[1], "z")?);
        let end = k == 0 || k + 1 == rows.len();
        if q.x < 0.0 || (q.x == 0.0 && !end) {
            return Err(bad("has r at or below 0"));
        }
        if profile.last().is_some_and(|l: &DVec2| l.distance(q) == 0.0) {
            return Err(bad("repeats the point before it"));
        }
        profile.push(q);
    }
    if profile[0].x == 0.0 && profile[profile.len() - 1].x == 0.0 && profile.len() == 2 {
        return Err(
            Diagnostic::new(ErrorKind::TargetParameter, "the profile lies on the axis")
                .at(p.span())
                .hint("give points with r > 0 between the ends"),
        );
    }
    Ok(Family::Revolution { profile })
}

fn height_field(t: &RawTarget) -> Result<Family, Diagnostic> {
    let width = positive(&t.width, "width")?;
    let length = positive(&t.length, "length")?;
    let h = t.heights.as_ref().expect("given");
    let rows = h.get_ref();
    let cols = rows.first().map_or(0, |r| r.get_ref().len());
    let limit = MAX_LINES + 1;
    if rows.len() < 2 || cols < 2 || rows.len() > limit || cols > limit {
        return Err(Diagnostic::new(
            ErrorKind::TargetParameter,
            format!("`heights` is {} rows of {cols}: it must be 2 to {limit} rows of 2 to {limit} heights", rows.len()),
        )
        .at(h.span())
        .hint("one row of heights (mm) per grid line along y, each of the same count along x"));
    }
    let mut heights = Vec::with_capacity(rows.len());
    for (j, row) in rows.iter().enumerate() {
        if row.get_ref().len() != cols {
            return Err(Diagnostic::new(
                ErrorKind::TargetParameter,
                format!(
                    "row {} of `heights` has {} heights, row 1 has {cols}",
                    j + 1,
                    row.get_ref().len()
                ),
            )
            .at(row.span())
            .hint("every row holds the same number of heights"));
        }
        heights.push(
            row.get_ref()
                .iter()
                .map(|n| finite(n, "a height"))
                .collect::<Result<Vec<_>, _>>()?,
        );
    }
    Ok(Family::HeightField {
        width,
        length,
        heights,
    })
}
