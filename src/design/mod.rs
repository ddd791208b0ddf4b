//! A design: the validated recipe. `parse` turns TOML text into a `Design`
//! whose every problem is reported as a `Diagnostic` pointing at the text;
//! `Design::grow` grows it and points lattice errors back at the recipe.

mod fabrication;
pub mod fit;
pub mod measure;
pub mod optimise;
mod raw;
pub mod seed;
pub mod simulation;
pub mod tune;

pub use fabrication::{FabricationSpans, MIN_WALL, Overrides};

use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::fabrication::Fabrication;
use crate::geometry::{Direction, Leg};
use crate::lattice::{
    Crank, FrontMoves, GrowthError, Kind, Lattice, MAX_CELLS, Param, PivotMove, RowParams, grow,
    grow_helix,
};
use glam::DVec3;
use raw::{Coords, Num, RawDesign, RawFront, RawKappa, RawLattice, RawLeg, RawRow};
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
    /// One parameter set per grown row, in growth order (sheets, loops).
    pub rows: Vec<RowParams>,
    /// Helix seeds: the number of cells to grow.
    pub helix_cells: usize,
    /// Target fitting: rows are found by a search instead of written out.
    pub fit: Option<fit::Fit>,
    pub fabrication: Fabrication,
    /// How close strips of one layer may come (`[clash]`).
    pub clash: optimise::ClashRule,
    /// The design optimiser's settings (`[optimise]`), for `karigami tune`.
    pub optimise: Option<optimise::Optimise>,
    /// `[simulation]`: material moduli and deployment for `simulate`.
    pub simulation: crate::sim::Settings,
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
    /// Helix `cells`.
    cells: Range<usize>,
    /// `[lattice.fit]`.
    fit: Range<usize>,
}

const NO_ENTRY: u32 = u32::MAX;

#[derive(Clone, Debug, Default, PartialEq)]
struct FieldSpans {
    table: Range<usize>,
    start: Option<Range<usize>>,
    direction: Option<Range<usize>>,
    left_leg: Option<Range<usize>>,
    right_leg: Option<Range<usize>>,
    target: Option<Range<usize>>,
    candidate: Option<Range<usize>>,
    front: Option<Range<usize>>,
}

impl FieldSpans {
    fn of(&self, param: Param) -> Option<Range<usize>> {
        match param {
            Param::Start => self.start.clone(),
            Param::Direction => self.direction.clone(),
            Param::LeftLeg => self.left_leg.clone(),
            Param::RightLeg => self.right_leg.clone(),
            Param::Target => self.target.clone(),
            Param::Candidate => self.candidate.clone(),
            Param::FrontMoves => self.front.clone(),
            Param::SeedPoints | Param::SeedKappa(_) | Param::Front | Param::Cells => None,
        }
    }
}

/// Parse and validate a recipe. `default_name` names the design when the
/// recipe has no `name` (the CLI passes the file stem).
pub fn parse(source: &str, default_name: &str) -> Result<Design, Diagnostic> {
    parse_with(source, default_name, &Overrides::default())
}

/// For serde's "unknown field `x`, expected one of `a`, `b`": the expected
/// field nearest `x`, if it is a likely typo (at most 2 edits).
fn did_you_mean(message: &str) -> Option<&str> {
    let rest = message.strip_prefix("unknown field `")?;
    let (field, rest) = rest.split_once('`')?;
    let expected = rest.split_once("expected")?.1;
    expected
        .split('`')
        .skip(1)
        .step_by(2)
        .map(|c| (edit_distance(field, c), c))
        .filter(|&(d, _)| d <= 2)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

/// Levenshtein distance (short field names only).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let here = (prev + usize::from(ca != cb))
                .min(row[j] + 1)
                .min(row[j + 1] + 1);
            prev = row[j + 1];
            row[j + 1] = here;
        }
    }
    row[b.len()]
}

/// `parse`, with fabrication settings from the command line replacing the recipe's.
pub fn parse_with(
    source: &str,
    default_name: &str,
    overrides: &Overrides,
) -> Result<Design, Diagnostic> {
    raw::check_values(source)?;
    let raw: RawDesign = toml::from_str(source).map_err(|e| {
        let message = e.message().trim_end().to_string();
        let hint = did_you_mean(&message)
            .map_or("see the recipe format in README.md".to_string(), |f| {
                format!("did you mean `{f}`? (the recipe format is in README.md)")
            });
        Diagnostic::new(ErrorKind::Toml, message)
            .at_opt(e.span())
            .hint(hint)
    })?;
    let name = match &raw.name {
        Some(n) if n.get_ref().trim().is_empty() => {
            return Err(Diagnostic::new(ErrorKind::EmptyName, "the name is empty")
                .at(n.span())
                .hint("give the design a name, or leave `name` out to use the file name"));
        }
        Some(n) => n.get_ref().clone(),
        None => default_name.to_string(),
    };
    let (fabrication, fabrication_spans) = fabrication::fabrication(&raw, overrides)?;
    let clash = optimise::parse_clash(raw.clash.as_ref())?;
    let optimise = raw.optimise.as_ref().map(optimise::parse).transpose()?;
    let simulation = simulation::parse(raw.simulation.as_ref())?;
    let lattice_span = raw.lattice.span();
    let lat = raw.lattice.into_inner();
    let kind = match lat.seed.get_ref().as_str() {
        "sheet" => Kind::Sheet,
        "loop" => Kind::Loop,
        "helix" => Kind::Helix,
        other => {
            return Err(Diagnostic::new(
                ErrorKind::UnknownSeed,
                format!("unknown seed \"{other}\""),
            )
            .at(lat.seed.span())
            .hint("seed must be \"sheet\", \"loop\" or \"helix\""));
        }
    };
    let (points, points_span) = seed_points(&lat, kind, lattice_span.clone())?;
    let dim = dimension(&points)?;
    let points: Vec<DVec3> = points.into_iter().map(|(p, _)| p).collect();
    let mut spans = Spans {
        lattice: lattice_span.clone(),
        points: points_span,
        fabrication: fabrication_spans,
        ..Spans::default()
    };
    let edges = if kind == Kind::Loop {
        points.len()
    } else {
        points.len() - 1
    };
    let kappa = seed_kappa(&lat, edges, &mut spans)?;
    let (mut rows, mut helix_cells, mut fit) = (Vec::new(), 0, None);
    if kind == Kind::Helix {
        helix_cells = helix_cell_count(&lat, &spans)?;
        // Growth errors of a helix point at its cell count (grow fewer cells).
        spans.cells = lat
            .cells
            .as_ref()
            .map_or(spans.lattice.clone(), |c| c.span());
    } else if let Some(f) = &lat.fit {
        if lat.grow.is_some() || lat.rows.is_some() {
            return Err(Diagnostic::new(
                ErrorKind::FittedRowsGiven,
                "a fitted lattice finds its own rows",
            )
            .at(f.span())
            .hint("remove [lattice.grow] and [[lattice.rows]], or remove [lattice.fit]"));
        }
        fit = Some(fit::parse(f, kind, dim)?);
        spans.fit = f.span();
    } else {
        rows = self::rows(&lat, kind, dim, points.len(), &mut spans)?;
    }
    Ok(Design {
        name,
        kind,
        dim,
        points,
        kappa,
        rows,
        helix_cells,
        fit,
        fabrication,
        clash,
        optimise,
        simulation,
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
        self.grow_with(&mut |_| {})
    }

    /// `grow`, telling `progress` about each fitted row (long fits).
    pub fn grow_with(&self, progress: &mut dyn FnMut(&str)) -> Result<Lattice, Diagnostic> {
        let result = match (self.kind, &self.fit) {
            (Kind::Helix, _) => grow_helix(self.dim, &self.points, &self.kappa, self.helix_cells),
            (_, Some(f)) => fit::grow(self, f, progress),
            _ => grow(self.kind, self.dim, &self.points, &self.kappa, &self.rows),
        };
        result.map_err(|e| self.locate(e))
    }

    /// The recipe text with its seed `points` and `kappa` replaced, all else
    /// (comments included) kept. Only for seeds written as `points = [...]`.
    pub fn with_seed(&self, source: &str, points: &[DVec3], kappa: &[f64]) -> Option<String> {
        let (p, k) = (self.spans.points.clone(), self.spans.kappa.clone());
        if !source.get(p.clone())?.trim_start().starts_with('[')
            || p.start < k.end && k.start < p.end
        {
            return None;
        }
        let point = |v: &DVec3| {
            let c: Vec<String> = v.to_array()[..self.dim]
                .iter()
                .map(|x| format!("{x:?}"))
                .collect();
            format!("[{}]", c.join(", "))
        };
        let points_text = format!(
            "[\n{}\n]",
            points
                .iter()
                .map(|v| format!("    {},", point(v)))
                .collect::<Vec<_>>()
                .join("\n")
        );
        let kappa_text = format!(
            "[{}]",
            kappa
                .iter()
                .map(|k| format!("{k:?}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        let mut edits = [(p, points_text), (k, kappa_text)];
        edits.sort_by_key(|e| std::cmp::Reverse(e.0.start));
        let mut out = source.to_string();
        for (range, text) in edits {
            out.replace_range(range, &text);
        }
        Some(out)
    }

    /// Where the fabrication settings were written.
    pub fn fabrication_spans(&self) -> &FabricationSpans {
        &self.spans.fabrication
    }

    /// The text that sets the lattice's size, for errors about a lattice too
    /// large to build: a helix's `cells`, `[lattice.fit]`, or the table that
    /// gives the last row.
    pub fn size_span(&self) -> Range<usize> {
        match (self.kind, &self.fit) {
            (Kind::Helix, _) => self.spans.cells.clone(),
            (_, Some(_)) => self.spans.fit.clone(),
            _ => self.row_table(self.rows.len().saturating_sub(1)),
        }
    }

    /// The text that sets row `i`'s front moves (its table when it has none).
    pub fn row_front_span(&self, i: usize) -> Range<usize> {
        self.row_span(i, Param::FrontMoves)
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
                Some(i) if i > 0 && self.fit.is_none() => self.row_span(i - 1, Param::Direction),
                _ => self.spans.points.clone(),
            }),
            Param::Cells => Some(self.spans.cells.clone()),
            _ if self.fit.is_some() => Some(self.spans.fit.clone()),
            param => e.row.map(|i| self.row_span(i, param)),
        };
        let site = e.site();
        Diagnostic::new(e.kind, e.message)
            .at_opt(span)
            .site(site)
            .hint(e.hint)
    }

    /// The text that sets `param` for row `i`: the row's own entry if it
    /// gives it, else `[lattice.grow]`, else the entry (or lattice) table.
    fn row_span(&self, i: usize, param: Param) -> Range<usize> {
        self.row_entry(i)
            .and_then(|f| f.of(param))
            .or_else(|| self.spans.grow.as_ref().and_then(|g| g.of(param)))
            .unwrap_or_else(|| self.row_table(i))
    }

    /// Row `i`'s `[[lattice.rows]]` entry, if it has one.
    fn row_entry(&self, i: usize) -> Option<&FieldSpans> {
        self.spans
            .row_entry
            .get(i)
            .filter(|&&e| e != NO_ENTRY)
            .map(|&e| &self.spans.entries[e as usize])
    }

    /// The table that describes row `i`: its entry, `[lattice.grow]`, or `[lattice]`.
    fn row_table(&self, i: usize) -> Range<usize> {
        self.row_entry(i)
            .map(|f| f.table.clone())
            .or_else(|| self.spans.grow.as_ref().map(|g| g.table.clone()))
            .unwrap_or_else(|| self.spans.lattice.clone())
    }
}

fn finite(n: &Num, what: &str) -> Result<f64, Diagnostic> {
    let v = *n.get_ref();
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

fn count(n: &Spanned<i64>, what: &str, min: i64, max: i64) -> Result<usize, Diagnostic> {
    let v = *n.get_ref();
    if (min..=max).contains(&v) {
        Ok(v as usize)
    } else {
        Err(Diagnostic::new(
            ErrorKind::OutOfRange,
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
        return Err(Diagnostic::new(
            ErrorKind::WrongCoordinates,
            format!("{what} has {} coordinates", v.len()),
        )
        .at(c.span())
        .hint("give 2 coordinates (a planar lattice) or 3 (a lattice in space)"));
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
    kind: Kind,
    lattice_span: Range<usize>,
) -> Result<(Vec<SeedPoint>, Range<usize>), Diagnostic> {
    let given = [
        lat.points.as_ref().map(|p| p.span()),
        lat.line.as_ref().map(|p| p.span()),
        lat.arc.as_ref().map(|p| p.span()),
        lat.polyline.as_ref().map(|p| p.span()),
        lat.circle.as_ref().map(|p| p.span()),
    ];
    let mut spans = given.iter().flatten();
    let Some(first) = spans.next() else {
        return Err(Diagnostic::new(ErrorKind::NoSeedPoints, "the lattice has no seed points")
            .at(lattice_span)
            .hint("give `points = [[x, y], ...]` or a [lattice.line], [lattice.arc], [lattice.polyline] or [lattice.circle] table"));
    };
    if let Some(second) = spans.next() {
        return Err(Diagnostic::new(ErrorKind::SeedGivenTwice, "the seed points are given twice")
            .at(second.clone())
            .hint("keep only one of `points`, [lattice.line], [lattice.arc], [lattice.polyline], [lattice.circle]"));
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
                ErrorKind::LineDimensionsDiffer,
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
            return Err(Diagnostic::new(
                ErrorKind::NonPositiveRadius,
                "arc.radius must be positive",
            )
            .at(a.radius.span()));
        }
        let plane = plane(&a.plane, dim, "arc")?;
        let cells = count(&a.cells, "arc.cells", 1, MAX_CELLS as i64)?;
        let (from, to) = (finite(&a.from, "arc.from")?, finite(&a.to, "arc.to")?);
        all(
            seed::arc(center, radius, from, to, cells, plane),
            dim,
            first.clone(),
        )
    } else if let Some(c) = &lat.circle {
        let c = c.get_ref();
        let (center, dim) = coords(&c.center, "circle.center")?;
        let radius = finite(&c.radius, "circle.radius")?;
        if radius <= 0.0 {
            return Err(Diagnostic::new(
                ErrorKind::NonPositiveRadius,
                "circle.radius must be positive",
            )
            .at(c.radius.span()));
        }
        let plane = plane(&c.plane, dim, "circle")?;
        let n = count(&c.points, "circle.points", 3, MAX_CELLS as i64)?;
        let from = match &c.start {
            Some(a) => finite(a, "circle.start")?,
            None => 0.0,
        };
        let mut pts = seed::arc(center, radius, from, from + 360.0, n, plane);
        pts.pop();
        all(pts, dim, first.clone())
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
            return Err(Diagnostic::new(
                ErrorKind::SeedTooShort,
                "a polyline needs at least 2 points",
            )
            .at(p.points.span()));
        }
        if corners.iter().any(|c| c.1 != corners[0].1) {
            return Err(Diagnostic::new(
                ErrorKind::PolylineDimensionsDiffer,
                "polyline points have different numbers of coordinates",
            )
            .at(p.points.span()));
        }
        let per = match &p.cells_per_segment {
            Some(n) => count(n, "polyline.cells_per_segment", 1, MAX_CELLS as i64)?,
            None => 1,
        };
        if per.saturating_mul(corners.len() - 1) > MAX_CELLS {
            return Err(Diagnostic::new(
                ErrorKind::TooLarge,
                "the polyline makes too many seed edges",
            )
            .at(p.points.span()));
        }
        let pts: Vec<DVec3> = corners.iter().map(|c| c.0).collect();
        all(seed::polyline(&pts, per), corners[0].1, first.clone())
    };
    let (min, hint) = match kind {
        Kind::Sheet => (2, "a sheet of m cells has m + 1"),
        Kind::Loop => (3, "a loop of N cells a row has N points"),
        Kind::Helix => (3, "a helix of loop length N has N + 1 points y_0 .. y_N"),
    };
    if points.len() < min {
        return Err(Diagnostic::new(
            ErrorKind::SeedTooShort,
            format!(
                "a {} seed needs at least {min} points, this one has {}",
                kind.name(),
                points.len()
            ),
        )
        .at(first.clone())
        .hint(format!("add seed points: {hint}")));
    }
    Ok((points, first.clone()))
}

/// The coordinate plane of an arc or circle.
fn plane(p: &Option<Spanned<String>>, dim: usize, what: &str) -> Result<seed::Plane, Diagnostic> {
    match p {
        None => Ok(seed::Plane::Xy),
        Some(p) if dim == 2 && p.get_ref() != "xy" => Err(Diagnostic::new(
            ErrorKind::PlanarSeedOffPlane,
            format!("a planar {what} lies in the xy plane"),
        )
        .at(p.span())
        .hint(format!(
            "give {what}.center 3 coordinates to use another plane"
        ))),
        Some(p) => seed::Plane::parse(p.get_ref()).ok_or_else(|| {
            Diagnostic::new(
                ErrorKind::UnknownPlane,
                format!("unknown plane \"{}\"", p.get_ref()),
            )
            .at(p.span())
            .hint("plane must be \"xy\", \"xz\" or \"yz\"")
        }),
    }
}

/// A helix grows `cells` cells from its seed.
fn helix_cell_count(lat: &RawLattice, spans: &Spans) -> Result<usize, Diagnostic> {
    for (given, what) in [
        (lat.grow.as_ref().map(|g| g.span()), "[lattice.grow]"),
        (
            lat.rows.as_ref().and_then(|r| r.first()).map(|r| r.span()),
            "[[lattice.rows]]",
        ),
        (lat.fit.as_ref().map(|f| f.span()), "[lattice.fit]"),
    ] {
        if let Some(span) = given {
            return Err(Diagnostic::new(
                ErrorKind::HelixTakesNoRows,
                format!("a helix is fully determined by its seed, so it takes no {what}"),
            )
            .at(span)
            .hint("give `cells = K` in [lattice] instead"));
        }
    }
    match &lat.cells {
        Some(n) => count(n, "cells", 1, MAX_CELLS as i64),
        None => Err(Diagnostic::new(
            ErrorKind::HelixNeedsCells,
            "a helix needs the number of cells to grow",
        )
        .at(spans.lattice.clone())
        .hint("give `cells = K` in [lattice]")),
    }
}

/// All seed points must have the same number of coordinates.
fn dimension(points: &[SeedPoint]) -> Result<usize, Diagnostic> {
    let dim = points[0].1.0;
    if let Some((_, (d, span))) = points.iter().find(|p| p.1.0 != dim) {
        return Err(Diagnostic::new(
            ErrorKind::SeedDimensionsDiffer,
            format!("this seed point has {d} coordinates but the first has {dim}"),
        )
        .at(span.clone())
        .hint("give every seed point the same number of coordinates"));
    }
    Ok(dim)
}

fn seed_kappa(lat: &RawLattice, edges: usize, spans: &mut Spans) -> Result<Vec<f64>, Diagnostic> {
    let Some(k) = &lat.kappa else {
        return Err(Diagnostic::new(ErrorKind::NoKappa, "the seed has no kappa")
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
                    ErrorKind::KappaCount,
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
    kind: Kind,
    dim: usize,
    npoints: usize,
    spans: &mut Spans,
) -> Result<Vec<RowParams>, Diagnostic> {
    if let Some(c) = &lat.cells {
        return Err(
            Diagnostic::new(ErrorKind::CellsWithoutHelix, "`cells` is for helix seeds")
                .at(c.span())
                .hint("grow rows with [lattice.grow] or [[lattice.rows]]"),
        );
    }
    let width = if kind == Kind::Loop {
        npoints
    } else {
        npoints - 1
    };
    // The front's last vertex index (N, vertex 0 again, on a loop).
    let last = width;
    let defaults = lat.grow.as_ref().map(|g| g.get_ref());
    if let Some(g) = &lat.grow {
        for (field, name) in [(&g.get_ref().row, "row"), (&g.get_ref().repeat, "repeat")] {
            if let Some(f) = field {
                return Err(Diagnostic::new(
                    ErrorKind::RowSettingInGrow,
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
            return Err(Diagnostic::new(
                ErrorKind::RowsOutsideGrow,
                "`rows` belongs in [lattice.grow]",
            )
            .at(n.span())
            .hint("in a [[lattice.rows]] entry use `row` (which row) or `repeat` (how many)"));
        }
        let index = match &r.row {
            Some(n) => count(n, "row", 0, max_rows as i64 - 1)?,
            None => row_entry.len(),
        };
        if index < row_entry.len() {
            let span = r.row.as_ref().map_or(entry.span(), |n| n.span());
            return Err(Diagnostic::new(
                ErrorKind::RowGivenTwice,
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
                ErrorKind::RowBeyondLattice,
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
        return Err(Diagnostic::new(ErrorKind::NoRows, "the design grows no rows")
            .at(spans.lattice.clone())
            .hint("add [[lattice.rows]] entries, or [lattice.grow] with `rows = N` and a default direction"));
    }
    row_entry.resize(total, NO_ENTRY);

    // Resolve each distinct (entry or default) once, then copy per row.
    let default_row = defaults
        .map(|g| resolve(None, g, dim, last))
        .transpose()?
        .unwrap_or_default();
    let resolved: Vec<RowParams> = entries
        .iter()
        .map(|e| resolve(defaults, e.get_ref(), dim, last))
        .collect::<Result<_, _>>()?;
    let rows = row_entry
        .iter()
        .enumerate()
        .map(|(i, &e)| {
            let params = if e == NO_ENTRY { &default_row } else { &resolved[e as usize] };
            // Only an open front must be given a direction; a loop row's
            // comes from closure.
            let needed = kind == Kind::Sheet && params.direction.is_none();
            (!needed).then(|| params.clone()).ok_or_else(|| {
                let span = if e == NO_ENTRY {
                    spans.grow.as_ref().map_or(spans.lattice.clone(), |g| g.table.clone())
                } else {
                    spans.entries[e as usize].table.clone()
                };
                Diagnostic::new(ErrorKind::NoLegDirection, format!("row {i} has no leg direction"))
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
        target: r.target.as_ref().map(|s| s.span()),
        candidate: r.candidate.as_ref().map(|s| s.span()),
        front: r.front.as_ref().map(|s| s.span()),
    }
}

/// A row's parameters from its own fields, falling back on `defaults`.
/// A missing direction is reported per row by the caller.
fn resolve(
    defaults: Option<&RawRow>,
    row: &RawRow,
    dim: usize,
    last: usize,
) -> Result<RowParams, Diagnostic> {
    if let (Some(_), Some(a)) = (&row.direction, &row.angle) {
        return Err(Diagnostic::new(
            ErrorKind::DirectionAndAngle,
            "both `direction` and `angle` are given",
        )
        .at(a.span())
        .hint("give the leg direction one way: `angle` in degrees or `direction` as a vector"));
    }
    let pick = |own: bool| if own { Some(row) } else { defaults };
    let dir_source = pick(row.direction.is_some() || row.angle.is_some());
    let direction = match dir_source {
        Some(r) if r.direction.is_some() => {
            let c = r.direction.as_ref().expect("checked");
            let (v, d) = coords(c, "direction")?;
            if d != dim {
                return Err(Diagnostic::new(
                    ErrorKind::DirectionDimension,
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
                return Err(Diagnostic::new(
                    ErrorKind::AngleNotFinite,
                    "the angle is not a finite number",
                )
                .at(a.span()));
            }
            if dim == 2 && raw.tilt.is_some() {
                return Err(Diagnostic::new(
                    ErrorKind::TiltNeeds3d,
                    "a tilt angle needs a 3-D lattice",
                )
                .at(a.span())
                .hint("in 2-D give `angle` as one number of degrees"));
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
                    ErrorKind::NonPositiveLeg,
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
    let own = |f: fn(&RawRow) -> bool| {
        if f(row) {
            Some(row)
        } else {
            defaults.filter(|d| f(d))
        }
    };
    let target = match own(|r| r.target.is_some()).and_then(|r| r.target.as_ref()) {
        Some(c) => {
            let (v, d) = coords(c, "target")?;
            if d != dim {
                return Err(Diagnostic::new(
                    ErrorKind::TargetDimension,
                    format!("target has {d} coordinates but the lattice is {dim}-D"),
                )
                .at(c.span())
                .hint(format!("give {dim} coordinates")));
            }
            Some(v)
        }
        None => None,
    };
    let candidate = match own(|r| r.candidate.is_some()).and_then(|r| r.candidate.as_ref()) {
        Some(c) => Some(count(c, "candidate", 1, 2)?),
        None => None,
    };
    let front = match own(|r| r.front.is_some()).and_then(|r| r.front.as_ref()) {
        Some(f) => Some(front_moves(f, last)?),
        None => None,
    };
    Ok(RowParams {
        start,
        direction,
        left_leg,
        right_leg,
        target,
        candidate,
        front,
    })
}

/// The generators of a rebuilt front (MATH.md 7), from `front = { ... }`.
/// `last` is the index of the front's last vertex (N, i.e. vertex 0 again, on a loop).
fn front_moves(f: &Spanned<RawFront>, last: usize) -> Result<FrontMoves, Diagnostic> {
    let raw = f.get_ref();
    if raw.is_empty() {
        return Err(Diagnostic::new(
            ErrorKind::EmptyFront,
            "front = { } rebuilds the front with no move",
        )
        .at(f.span())
        .hint("give turn, bend, twist, pivot, crank or zigzag, or leave `front` out"));
    }
    let angles = |a: &Option<Spanned<raw::RawAngles>>,
                  what: &str|
     -> Result<Option<Vec<f64>>, Diagnostic> {
        match a {
            None => Ok(None),
            Some(a) if a.get_ref().0.iter().all(|v| v.is_finite()) && !a.get_ref().0.is_empty() => {
                Ok(Some(a.get_ref().0.clone()))
            }
            Some(a) => Err(Diagnostic::new(
                ErrorKind::FrontAnglesNotFinite,
                format!("front.{what} needs finite angles"),
            )
            .at(a.span())
            .hint("give an angle in degrees, or one per interior front vertex")),
        }
    };
    let index = |n: &Spanned<i64>, what: &str| count(n, what, 0, last as i64);
    let mut moves = FrontMoves {
        turn: angles(&raw.turn, "turn")?,
        bend: angles(&raw.bend, "bend")?,
        twist: angles(&raw.twist, "twist")?,
        ..FrontMoves::default()
    };
    for p in raw.pivot.iter().flatten() {
        let p = p.get_ref();
        moves.pivots.push(PivotMove {
            at: index(&p.at, "front.pivot.at")?,
            axis: p
                .axis
                .as_ref()
                .map(|a| coords(a, "front.pivot.axis").map(|c| c.0))
                .transpose()?,
            angle_deg: finite(&p.angle, "front.pivot.angle")?,
        });
    }
    for c in raw.crank.iter().flatten() {
        let c = c.get_ref();
        moves.cranks.push(Crank {
            from: index(&c.from, "front.crank.from")?,
            to: index(&c.to, "front.crank.to")?,
            angle_deg: finite(&c.angle, "front.crank.angle")?,
        });
    }
    if let Some(z) = &raw.zigzag {
        let a = finite(z, "front.zigzag")?;
        // Odd vertices alternately up and down: sub-units of 4 edges.
        for j in (1..last).step_by(2) {
            let sign = if j % 4 == 1 { 1.0 } else { -1.0 };
            moves.cranks.push(Crank {
                from: j - 1,
                to: j + 1,
                angle_deg: sign * a,
            });
        }
    }
    Ok(moves)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_fields_suggest_the_nearest_known_one() {
        let e = parse("[lattice]\nseed = \"sheet\"\nkapa = 0.0\n", "x").unwrap_err();
        assert_eq!(
            e.hint.as_deref(),
            Some("did you mean `kappa`? (the recipe format is in README.md)")
        );
        // Far from every field: no guess.
        let e = parse("[lattice]\nseed = \"sheet\"\nwobble = 0.0\n", "x").unwrap_err();
        assert_eq!(
            e.hint.as_deref(),
            Some("see the recipe format in README.md")
        );
        assert_eq!(edit_distance("angel", "angle"), 2);
        assert_eq!(edit_distance("", "abc"), 3);
    }
}
