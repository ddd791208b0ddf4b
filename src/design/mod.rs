//! A design: the validated recipe. `parse` turns TOML text into a `Design`
//! whose every problem is reported as a `Diagnostic` pointing at the text;
//! `Design::grow` grows it and points lattice errors back at the recipe.

mod fabrication;
mod raw;
pub mod seed;

pub use fabrication::{FabricationSpans, MIN_WALL, Overrides};

use crate::diagnostic::Diagnostic;
use crate::fabrication::Fabrication;
use crate::geometry::{Direction, Leg};
use crate::lattice::{GrowthError, Kind, Lattice, MAX_CELLS, Param, RowParams, grow_sheet};
use glam::DVec3;
use raw::{Coords, Num, RawDesign, RawKappa, RawLattice, RawLeg, RawRow};
use std::ops::Range;
use toml::Spanned;

#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    pub name: String,
    pub kind: Kind,
    pub dim: usize,
    /// The seed front.
    pub points: Vec<DVec3>,
    /// One collapsibility parameter per seed edge (mm).
    pub kappa: Vec<f64>,
    /// One parameter set per grown row, in growth order.
    pub rows: Vec<RowParams>,
    pub fabrication: Fabrication,
    /// FNV-1a hash of the recipe text, written into the files' metadata.
    pub recipe_hash: u64,
    spans: Spans,
}

/// Where each part of the design was written, for pointing errors.
#[derive(Clone, Debug, Default, PartialEq)]
struct Spans {
    lattice: Range<usize>,
    points: Range<usize>,
    kappa: Range<usize>,
    /// Per seed edge, when kappa is written as an array.
    kappa_edges: Vec<Range<usize>>,
    fabrication: FabricationSpans,
    grow: Option<FieldSpans>,
    /// One per `[[lattice.rows]]` entry.
    entries: Vec<FieldSpans>,
    /// For each row, its entry (or `NO_ENTRY` for the `[lattice.grow]` default).
    row_entry: Vec<u32>,
}

const NO_ENTRY: u32 = u32::MAX;

#[derive(Clone, Debug, Default, PartialEq)]
struct FieldSpans {
    table: Range<usize>,
    start: Option<Range<usize>>,
    direction: Option<Range<usize>>,
    left_leg: Option<Range<usize>>,
    right_leg: Option<Range<usize>>,
}

impl FieldSpans {
    fn of(&self, param: Param) -> Option<Range<usize>> {
        match param {
            Param::Start => self.start.clone(),
            Param::Direction => self.direction.clone(),
            Param::LeftLeg => self.left_leg.clone(),
            Param::RightLeg => self.right_leg.clone(),
            Param::SeedPoints | Param::SeedKappa(_) | Param::Front => None,
        }
    }
}

/// Parse and validate a recipe. `default_name` names the design when the
/// recipe has no `name` (the CLI passes the file stem).
pub fn parse(source: &str, default_name: &str) -> Result<Design, Diagnostic> {
    parse_with(source, default_name, &Overrides::default())
}

/// `parse`, with fabrication settings from the command line replacing the recipe's.
pub fn parse_with(
    source: &str,
    default_name: &str,
    overrides: &Overrides,
) -> Result<Design, Diagnostic> {
    let raw: RawDesign = toml::from_str(source).map_err(|e| {
        Diagnostic::new("toml", e.message().trim_end().to_string())
            .at_opt(e.span())
            .hint("see the recipe format in README.md")
    })?;
    let name = match &raw.name {
        Some(n) if n.get_ref().trim().is_empty() => {
            return Err(Diagnostic::new("design", "the name is empty")
                .at(n.span())
                .hint("give the design a name, or leave `name` out to use the file name"));
        }
        Some(n) => n.get_ref().clone(),
        None => default_name.to_string(),
    };
    let (fabrication, fabrication_spans) = fabrication::fabrication(&raw, overrides)?;
    let lattice_span = raw.lattice.span();
    let lat = raw.lattice.into_inner();
    let kind = match lat.seed.get_ref().as_str() {
        "sheet" => Kind::Sheet,
        "loop" | "helix" => {
            return Err(Diagnostic::new(
                "design",
                format!("seed = \"{}\" is not supported yet", lat.seed.get_ref()),
            )
            .at(lat.seed.span())
            .hint("use seed = \"sheet\""));
        }
        other => {
            return Err(
                Diagnostic::new("design", format!("unknown seed \"{other}\""))
                    .at(lat.seed.span())
                    .hint("seed must be \"sheet\""),
            );
        }
    };
    let (points, points_span) = seed_points(&lat, lattice_span.clone())?;
    let dim = dimension(&points)?;
    let points: Vec<DVec3> = points.into_iter().map(|(p, _)| p).collect();
    let mut spans = Spans {
        lattice: lattice_span.clone(),
        points: points_span,
        fabrication: fabrication_spans,
        ..Spans::default()
    };
    let kappa = seed_kappa(&lat, points.len(), &mut spans)?;
    let rows = rows(&lat, dim, points.len().saturating_sub(1), &mut spans)?;
    Ok(Design {
        name,
        kind,
        dim,
        points,
        kappa,
        rows,
        fabrication,
        recipe_hash: fnv1a(source.as_bytes()),
        spans,
    })
}

/// 64-bit FNV-1a: a stable fingerprint of the recipe for file metadata.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

impl Design {
    /// Grow the lattice; errors point at the recipe text that caused them.
    pub fn grow(&self) -> Result<Lattice, Diagnostic> {
        grow_sheet(self.dim, &self.points, &self.kappa, &self.rows).map_err(|e| self.locate(e))
    }

    /// Where the fabrication settings were written.
    pub fn fabrication_spans(&self) -> &FabricationSpans {
        &self.spans.fabrication
    }

    /// The text that sets row `i`'s leg direction, for errors about a row's strips.
    pub fn row_direction_span(&self, i: usize) -> Range<usize> {
        self.row_span(i, Param::Direction)
    }

    fn locate(&self, e: GrowthError) -> Diagnostic {
        let span = match e.param {
            Param::SeedPoints => Some(self.spans.points.clone()),
            Param::SeedKappa(j) => Some(
                self.spans
                    .kappa_edges
                    .get(j)
                    .unwrap_or(&self.spans.kappa)
                    .clone(),
            ),
            Param::Front => Some(match e.row {
                Some(i) if i > 0 => self.row_span(i - 1, Param::Direction),
                _ => self.spans.points.clone(),
            }),
            param => e.row.map(|i| self.row_span(i, param)),
        };
        let site = e.site();
        Diagnostic::new(e.kind.name(), e.message)
            .at_opt(span)
            .site(site)
            .hint(e.hint)
    }

    /// The text that sets `param` for row `i`: the row's own entry if it
    /// gives it, else `[lattice.grow]`, else the entry (or lattice) table.
    fn row_span(&self, i: usize, param: Param) -> Range<usize> {
        let entry = self
            .spans
            .row_entry
            .get(i)
            .filter(|&&e| e != NO_ENTRY)
            .map(|&e| &self.spans.entries[e as usize]);
        entry
            .and_then(|f| f.of(param))
            .or_else(|| self.spans.grow.as_ref().and_then(|g| g.of(param)))
            .or_else(|| entry.map(|f| f.table.clone()))
            .or_else(|| self.spans.grow.as_ref().map(|g| g.table.clone()))
            .unwrap_or_else(|| self.spans.lattice.clone())
    }
}

fn finite(n: &Num, what: &str) -> Result<f64, Diagnostic> {
    let v = *n.get_ref();
    if v.is_finite() {
        Ok(v)
    } else {
        Err(
            Diagnostic::new("design", format!("{what} is {v}, not a finite number"))
                .at(n.span())
                .hint("use an ordinary number"),
        )
    }
}

fn count(n: &Spanned<i64>, what: &str, min: i64, max: i64) -> Result<usize, Diagnostic> {
    let v = *n.get_ref();
    if (min..=max).contains(&v) {
        Ok(v as usize)
    } else {
        Err(Diagnostic::new(
            "design",
            format!("{what} is {v}, but must be between {min} and {max}"),
        )
        .at(n.span())
        .hint(format!("give {what} a whole number from {min} to {max}")))
    }
}

/// A point or vector of 2 or 3 finite coordinates.
fn coords(c: &Coords, what: &str) -> Result<(DVec3, usize), Diagnostic> {
    let v = c.get_ref();
    if !(2..=3).contains(&v.len()) {
        return Err(
            Diagnostic::new("design", format!("{what} has {} coordinates", v.len()))
                .at(c.span())
                .hint("give 2 coordinates (a planar lattice) or 3 (a lattice in space)"),
        );
    }
    let mut out = DVec3::ZERO;
    for (k, n) in v.iter().enumerate() {
        out[k] = finite(n, &format!("a coordinate of {what}"))?;
    }
    Ok((out, v.len()))
}

type SeedPoint = (DVec3, (usize, Range<usize>));

/// The seed front from exactly one of `points`, `[lattice.line]`,
/// `[lattice.arc]`, `[lattice.polyline]`; each point with its dimension and span.
fn seed_points(
    lat: &RawLattice,
    lattice_span: Range<usize>,
) -> Result<(Vec<SeedPoint>, Range<usize>), Diagnostic> {
    let given = [
        lat.points.as_ref().map(|p| p.span()),
        lat.line.as_ref().map(|p| p.span()),
        lat.arc.as_ref().map(|p| p.span()),
        lat.polyline.as_ref().map(|p| p.span()),
    ];
    let mut spans = given.iter().flatten();
    let Some(first) = spans.next() else {
        return Err(Diagnostic::new("design", "the lattice has no seed points")
            .at(lattice_span)
            .hint("give `points = [[x, y], ...]` or a [lattice.line], [lattice.arc] or [lattice.polyline] table"));
    };
    if let Some(second) = spans.next() {
        return Err(Diagnostic::new("design", "the seed points are given twice")
            .at(second.clone())
            .hint("keep only one of `points`, [lattice.line], [lattice.arc], [lattice.polyline]"));
    }
    let all = |pts: Vec<DVec3>, dim: usize, span: Range<usize>| {
        pts.into_iter().map(|p| (p, (dim, span.clone()))).collect()
    };
    let points = if let Some(p) = &lat.points {
        p.get_ref()
            .iter()
            .enumerate()
            .map(|(k, c)| coords(c, &format!("seed point {k}")).map(|(v, d)| (v, (d, c.span()))))
            .collect::<Result<Vec<_>, _>>()?
    } else if let Some(l) = &lat.line {
        let l = l.get_ref();
        let (from, d1) = coords(&l.from, "line.from")?;
        let (to, d2) = coords(&l.to, "line.to")?;
        if d1 != d2 {
            return Err(Diagnostic::new(
                "design",
                "line.from and line.to have different numbers of coordinates",
            )
            .at(l.to.span()));
        }
        let cells = count(&l.cells, "line.cells", 1, MAX_CELLS as i64)?;
        all(seed::line(from, to, cells), d1, first.clone())
    } else if let Some(a) = &lat.arc {
        let a = a.get_ref();
        let (center, dim) = coords(&a.center, "arc.center")?;
        let radius = finite(&a.radius, "arc.radius")?;
        if radius <= 0.0 {
            return Err(
                Diagnostic::new("design", "arc.radius must be positive").at(a.radius.span())
            );
        }
        let plane = match &a.plane {
            None => seed::Plane::Xy,
            Some(p) if dim == 2 && p.get_ref() != "xy" => {
                return Err(
                    Diagnostic::new("design", "a planar arc lies in the xy plane")
                        .at(p.span())
                        .hint("give arc.center 3 coordinates to use another plane"),
                );
            }
            Some(p) => seed::Plane::parse(p.get_ref()).ok_or_else(|| {
                Diagnostic::new("design", format!("unknown plane \"{}\"", p.get_ref()))
                    .at(p.span())
                    .hint("plane must be \"xy\", \"xz\" or \"yz\"")
            })?,
        };
        let cells = count(&a.cells, "arc.cells", 1, MAX_CELLS as i64)?;
        let (from, to) = (finite(&a.from, "arc.from")?, finite(&a.to, "arc.to")?);
        all(
            seed::arc(center, radius, from, to, cells, plane),
            dim,
            first.clone(),
        )
    } else {
        let p = lat
            .polyline
            .as_ref()
            .expect("one generator is given")
            .get_ref();
        let corners = p
            .points
            .get_ref()
            .iter()
            .enumerate()
            .map(|(k, c)| coords(c, &format!("polyline point {k}")))
            .collect::<Result<Vec<_>, _>>()?;
        if corners.len() < 2 {
            return Err(
                Diagnostic::new("SeedTooShort", "a polyline needs at least 2 points")
                    .at(p.points.span()),
            );
        }
        if corners.iter().any(|c| c.1 != corners[0].1) {
            return Err(Diagnostic::new(
                "design",
                "polyline points have different numbers of coordinates",
            )
            .at(p.points.span()));
        }
        let per = match &p.cells_per_segment {
            Some(n) => count(n, "polyline.cells_per_segment", 1, MAX_CELLS as i64)?,
            None => 1,
        };
        if per.saturating_mul(corners.len() - 1) > MAX_CELLS {
            return Err(
                Diagnostic::new("TooLarge", "the polyline makes too many seed edges")
                    .at(p.points.span()),
            );
        }
        let pts: Vec<DVec3> = corners.iter().map(|c| c.0).collect();
        all(seed::polyline(&pts, per), corners[0].1, first.clone())
    };
    if points.len() < 2 {
        return Err(Diagnostic::new(
            "SeedTooShort",
            format!(
                "a sheet seed needs at least 2 points, this one has {}",
                points.len()
            ),
        )
        .at(first.clone())
        .hint("add seed points: a sheet of m cells has m + 1"));
    }
    Ok((points, first.clone()))
}

/// All seed points must have the same number of coordinates.
fn dimension(points: &[SeedPoint]) -> Result<usize, Diagnostic> {
    let dim = points[0].1.0;
    if let Some((_, (d, span))) = points.iter().find(|p| p.1.0 != dim) {
        return Err(Diagnostic::new(
            "design",
            format!("this seed point has {d} coordinates but the first has {dim}"),
        )
        .at(span.clone())
        .hint("give every seed point the same number of coordinates"));
    }
    Ok(dim)
}

fn seed_kappa(lat: &RawLattice, npoints: usize, spans: &mut Spans) -> Result<Vec<f64>, Diagnostic> {
    let edges = npoints - 1;
    let Some(k) = &lat.kappa else {
        return Err(Diagnostic::new("design", "the seed has no kappa")
            .at(spans.lattice.clone())
            .hint(format!("give `kappa = 0.0` (every edge) or an array of {edges} numbers in mm, one per seed edge")));
    };
    spans.kappa = k.span();
    match k.get_ref() {
        RawKappa::Uniform(v) => {
            let n = Spanned::new(k.span(), *v);
            let v = finite(&n, "kappa")?;
            Ok(vec![v; edges])
        }
        RawKappa::PerEdge(list) => {
            if list.len() != edges {
                return Err(Diagnostic::new(
                    "design",
                    format!(
                        "kappa has {} values but the seed has {edges} edges",
                        list.len()
                    ),
                )
                .at(k.span())
                .hint(format!(
                    "give one kappa per seed edge ({edges}), or one number for all"
                )));
            }
            spans.kappa_edges = list.iter().map(|n| n.span()).collect();
            list.iter()
                .enumerate()
                .map(|(j, n)| finite(n, &format!("kappa of seed edge {j}")))
                .collect()
        }
    }
}

/// One `RowParams` per row: `[lattice.grow]` defaults overridden by the
/// `[[lattice.rows]]` entries.
fn rows(
    lat: &RawLattice,
    dim: usize,
    width: usize,
    spans: &mut Spans,
) -> Result<Vec<RowParams>, Diagnostic> {
    let defaults = lat.grow.as_ref().map(|g| g.get_ref());
    if let Some(g) = &lat.grow {
        for (field, name) in [(&g.get_ref().row, "row"), (&g.get_ref().repeat, "repeat")] {
            if let Some(f) = field {
                return Err(Diagnostic::new(
                    "design",
                    format!("`{name}` belongs in a [[lattice.rows]] entry, not in [lattice.grow]"),
                )
                .at(f.span())
                .hint("[lattice.grow] takes `rows` (how many) and the default row fields"));
            }
        }
        spans.grow = Some(field_spans(g));
    }
    let max_rows = MAX_CELLS / width.max(1);
    let total = match defaults.and_then(|g| g.rows.as_ref()) {
        Some(n) => Some(count(n, "grow.rows", 1, max_rows as i64)?),
        None => None,
    };
    // Which entry describes each row.
    let entries = lat.rows.as_deref().unwrap_or(&[]);
    let mut row_entry: Vec<u32> = Vec::new();
    for (e, entry) in entries.iter().enumerate() {
        let r = entry.get_ref();
        if let Some(n) = &r.rows {
            return Err(
                Diagnostic::new("design", "`rows` belongs in [lattice.grow]")
                    .at(n.span())
                    .hint(
                        "in a [[lattice.rows]] entry use `row` (which row) or `repeat` (how many)",
                    ),
            );
        }
        let index = match &r.row {
            Some(n) => count(n, "row", 0, max_rows as i64 - 1)?,
            None => row_entry.len(),
        };
        if index < row_entry.len() {
            let span = r.row.as_ref().map_or(entry.span(), |n| n.span());
            return Err(Diagnostic::new(
                "design",
                format!("row {index} is already described by an earlier [[lattice.rows]] entry"),
            )
            .at(span)
            .hint("list [[lattice.rows]] entries in increasing row order"));
        }
        let repeat = match &r.repeat {
            Some(n) => count(n, "repeat", 1, max_rows as i64)?,
            None => 1,
        };
        if index + repeat > total.unwrap_or(max_rows) {
            let limit = total.unwrap_or(max_rows);
            return Err(Diagnostic::new(
                "design",
                format!(
                    "this entry reaches row {}, but the lattice has {limit} rows",
                    index + repeat - 1
                ),
            )
            .at(entry.span())
            .hint("raise grow.rows, or lower `row` / `repeat`"));
        }
        row_entry.resize(index, NO_ENTRY);
        row_entry.resize(index + repeat, e as u32);
        spans.entries.push(field_spans(entry));
    }
    let total = total.unwrap_or(row_entry.len());
    if total == 0 {
        return Err(Diagnostic::new("design", "the design grows no rows")
            .at(spans.lattice.clone())
            .hint("add [[lattice.rows]] entries, or [lattice.grow] with `rows = N` and a default direction"));
    }
    row_entry.resize(total, NO_ENTRY);

    // Resolve each distinct (entry or default) once, then copy per row.
    let default_row = defaults.map(|g| resolve(None, g, dim)).transpose()?;
    let resolved: Vec<Option<RowParams>> = entries
        .iter()
        .map(|e| resolve(defaults, e.get_ref(), dim))
        .collect::<Result<_, _>>()?;
    let rows = row_entry
        .iter()
        .enumerate()
        .map(|(i, &e)| {
            let params = if e == NO_ENTRY { default_row.flatten() } else { resolved[e as usize] };
            params.ok_or_else(|| {
                let span = if e == NO_ENTRY {
                    spans.grow.as_ref().map_or(spans.lattice.clone(), |g| g.table.clone())
                } else {
                    spans.entries[e as usize].table.clone()
                };
                Diagnostic::new("design", format!("row {i} has no leg direction"))
                    .at(span)
                    .site(format!("row {i}"))
                    .hint("give `angle` (degrees) or `direction` in its [[lattice.rows]] entry or in [lattice.grow]")
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    spans.row_entry = row_entry;
    Ok(rows)
}

fn field_spans(table: &Spanned<RawRow>) -> FieldSpans {
    let r = table.get_ref();
    FieldSpans {
        table: table.span(),
        start: r.start.as_ref().map(|s| s.span()),
        direction: r
            .direction
            .as_ref()
            .map(|s| s.span())
            .or_else(|| r.angle.as_ref().map(|s| s.span())),
        left_leg: r.left_leg.as_ref().map(|s| s.span()),
        right_leg: r.right_leg.as_ref().map(|s| s.span()),
    }
}

/// A row's parameters from its own fields, falling back on `defaults`.
/// `None` when neither gives a direction (reported per row by the caller).
fn resolve(
    defaults: Option<&RawRow>,
    row: &RawRow,
    dim: usize,
) -> Result<Option<RowParams>, Diagnostic> {
    if let (Some(_), Some(a)) = (&row.direction, &row.angle) {
        return Err(
            Diagnostic::new("design", "both `direction` and `angle` are given")
                .at(a.span())
                .hint(
                    "give the leg direction one way: `angle` in degrees or `direction` as a vector",
                ),
        );
    }
    let pick = |own: bool| if own { Some(row) } else { defaults };
    let dir_source = pick(row.direction.is_some() || row.angle.is_some());
    let direction = match dir_source {
        Some(r) if r.direction.is_some() => {
            let c = r.direction.as_ref().expect("checked");
            let (v, d) = coords(c, "direction")?;
            if d != dim {
                return Err(Diagnostic::new(
                    "design",
                    format!("direction has {d} coordinates but the lattice is {dim}-D"),
                )
                .at(c.span())
                .hint(format!("give {dim} coordinates")));
            }
            Some(Direction::Vector(v))
        }
        Some(r) if r.angle.is_some() => {
            let a = r.angle.as_ref().expect("checked");
            let raw = *a.get_ref();
            let tilt = raw.tilt.unwrap_or(0.0);
            if !(raw.angle.is_finite() && tilt.is_finite()) {
                return Err(
                    Diagnostic::new("design", "the angle is not a finite number").at(a.span()),
                );
            }
            if dim == 2 && raw.tilt.is_some() {
                return Err(
                    Diagnostic::new("design", "a tilt angle needs a 3-D lattice")
                        .at(a.span())
                        .hint("in 2-D give `angle` as one number of degrees"),
                );
            }
            Some(Direction::Angles {
                angle_deg: raw.angle,
                tilt_deg: tilt,
            })
        }
        _ => None,
    };
    let start = match row
        .start
        .as_ref()
        .or(defaults.and_then(|d| d.start.as_ref()))
    {
        Some(s) => count(s, "start", 0, MAX_CELLS as i64)?,
        None => 0,
    };
    let leg = |own: &Option<Spanned<RawLeg>>,
               default: Option<&Spanned<RawLeg>>,
               name: &str|
     -> Result<Leg, Diagnostic> {
        match own.as_ref().or(default) {
            None => Ok(Leg::Match),
            Some(l) => match *l.get_ref() {
                RawLeg::Match => Ok(Leg::Match),
                RawLeg::Length(v) if v.is_finite() && v > 0.0 => Ok(Leg::Length(v)),
                RawLeg::Length(v) => Err(Diagnostic::new(
                    "NonPositiveLeg",
                    format!("{name} is {v}, but must be a positive length"),
                )
                .at(l.span())
                .hint(format!("give {name} a positive length in mm, or \"match\""))),
            },
        }
    };
    let left_leg = leg(
        &row.left_leg,
        defaults.and_then(|d| d.left_leg.as_ref()),
        "left_leg",
    )?;
    let right_leg = leg(
        &row.right_leg,
        defaults.and_then(|d| d.right_leg.as_ref()),
        "right_leg",
    )?;
    Ok(direction.map(|direction| RowParams {
        start,
        direction,
        left_leg,
        right_leg,
    }))
}
