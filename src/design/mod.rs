//! A design: the validated recipe. `parse` turns TOML text into a `Design`
//! whose every problem is reported as a `Diagnostic` pointing at the text;
//! `Design::grow` grows it and points lattice errors back at the recipe.

mod errors;
mod fabrication_bounds;
mod fabrication_checks;
mod fabrication_table;
mod fabrication_tables;
pub mod fit;
pub(crate) mod optimise;
mod raw;
mod rows;
pub(crate) mod seed;
pub(crate) mod settings;
pub(crate) mod simulation;
mod spans;
pub(crate) mod supports;
mod values;

pub use fabrication_bounds::{MIN_WALL, Overrides};

use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::fabrication::Fabrication;
use crate::lattice::{Kind, RowParams};
use glam::DVec3;
use raw::RawDesign;
use seed::{dimension, helix_cell_count, seed_kappa, seed_points};
use spans::Spans;
// fit.rs, optimise.rs and simulation.rs check their numbers with these too.
use values::{choice, coords, count, finite};

/// A validated recipe: seed, rows and every setting, each problem already
/// reported with its place in the text.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    pub(crate) name: String,
    /// Seed topology: sheet, loop or helix.
    pub kind: Kind,
    /// Embedding dimension, 2 or 3, from the seed's coordinates.
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
    /// Strips, eyelets, laser and sheet (`[material]`, `[eyelet]`, `[strip]`,
    /// `[laser]`, `[sheet]`, with command-line overrides applied).
    pub fabrication: Fabrication,
    /// How close strips of one layer may come (`[clash]`).
    pub clash: optimise::ClashRule,
    /// The design optimiser's settings (`[optimise]`), for `karigami tune`.
    pub optimise: Option<optimise::Optimise>,
    /// `[simulation]`: material moduli and deployment for `simulate`.
    pub simulation: settings::Settings,
    /// `[target]`: the target file the design was made for, relative to
    /// the recipe, and its FNV-1a content hash (hex), for `check`.
    pub target: Option<(String, Option<String>)>,
    /// FNV-1a hash of the recipe text, written into the files' metadata.
    pub(crate) recipe_hash: u64,
    /// When the run's time is up (`--time-limit`, docs/commands.md): the
    /// simulation and the optimiser stop there.
    pub deadline: crate::budget::Deadline,
    spans: Spans,
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
    raw::check_values(source)?;
    let raw: RawDesign = toml::from_str(source).map_err(|e| {
        let message = e.message().trim_end().to_string();
        let hint = errors::did_you_mean(&message)
            .map_or("see the recipe format in docs/recipe.md".to_string(), |f| {
                format!("did you mean `{f}`? (the recipe format is in docs/recipe.md)")
            });
        Diagnostic::new(ErrorKind::Toml, errors::plain(&message, source, e.span()))
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
    let (fabrication, fabrication_spans) = fabrication_table::fabrication(&raw, overrides)?;
    let target = raw.target.as_ref().map(|t| {
        let t = t.get_ref();
        (
            t.file.get_ref().clone(),
            t.hash.as_ref().map(|h| h.get_ref().clone()),
        )
    });
    let clash = optimise::parse_clash(raw.clash.as_ref())?;
    let optimise = raw.optimise.as_ref().map(optimise::parse).transpose()?;
    let mut simulation = simulation::parse(raw.simulation.as_ref(), fabrication.material.preset)?;
    if let Some(memory) = overrides.memory {
        simulation.memory = memory;
    }
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
        symmetry: raw
            .simulation
            .as_ref()
            .and_then(|s| s.get_ref().symmetry.as_ref())
            .map(|n| n.span()),
        edge_length: raw
            .simulation
            .as_ref()
            .and_then(|s| s.get_ref().edge_length.as_ref())
            .map(|n| n.span()),
        ..Spans::default()
    };
    let edges = if kind == Kind::Loop {
        points.len()
    } else {
        points.len() - 1
    };
    let kappa = seed_kappa(&lat, edges, &mut spans)?;
    (simulation.supports, spans.supports) = supports::parse(raw.simulation.as_ref(), kind)?;
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
        rows = rows::rows(&lat, kind, dim, points.len(), &mut spans)?;
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
        target,
        recipe_hash: crate::hash::fnv1a(source.as_bytes()),
        deadline: overrides.deadline,
        spans,
    })
}

// `Design::grow` and `grow_with` are in solve/grow.rs: growing a fitted
// design runs a search, which sits above the recipe layer.
impl Design {
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
}
