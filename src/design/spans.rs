//! Where each part of a design was written in the recipe, so that errors
//! found later (growth, strips) point at the text that causes them.

use super::Design;
use super::fabrication_bounds::FabricationSpans;
use super::raw::RawRow;
use crate::diagnostic::Diagnostic;
use crate::lattice::{GrowthError, Kind, Param};
use std::ops::Range;
use toml::Spanned;

/// Where each part of the design was written, for pointing errors.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Spans {
    pub(super) lattice: Range<usize>,
    pub(super) points: Range<usize>,
    pub(super) kappa: Range<usize>,
    /// Per seed edge, when kappa is written as an array.
    pub(super) kappa_edges: Vec<Range<usize>>,
    pub(super) fabrication: FabricationSpans,
    pub(super) grow: Option<FieldSpans>,
    /// One per `[[lattice.rows]]` entry.
    pub(super) entries: Vec<FieldSpans>,
    /// For each row, its entry (or `NO_ENTRY` for the `[lattice.grow]` default).
    pub(super) row_entry: Vec<u32>,
    /// Helix `cells`.
    pub(super) cells: Range<usize>,
    /// `[lattice.fit]`.
    pub(super) fit: Range<usize>,
    /// `[simulation] symmetry`, when the recipe sets it.
    pub(super) symmetry: Option<Range<usize>>,
    /// `[simulation] edge_length`, when the recipe sets it.
    pub(super) edge_length: Option<Range<usize>>,
    /// `[simulation] supports`: the list and each entry.
    pub(super) supports: super::supports::SupportSpans,
}

pub(super) const NO_ENTRY: u32 = u32::MAX;

#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct FieldSpans {
    pub(super) table: Range<usize>,
    pub(super) start: Option<Range<usize>>,
    pub(super) direction: Option<Range<usize>>,
    pub(super) left_leg: Option<Range<usize>>,
    pub(super) right_leg: Option<Range<usize>>,
    pub(super) target: Option<Range<usize>>,
    pub(super) candidate: Option<Range<usize>>,
    pub(super) front: Option<Range<usize>>,
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

impl Design {
    /// `[simulation] symmetry`, for errors about a symmetry the lattice
    /// does not have.
    pub(crate) fn symmetry_span(&self) -> Option<Range<usize>> {
        self.spans.symmetry.clone()
    }

    /// `[simulation] edge_length`, for errors about a mesh too fine.
    pub(crate) fn edge_length_span(&self) -> Option<Range<usize>> {
        self.spans.edge_length.clone()
    }

    /// The text that sets the lattice's size, for errors about a lattice too
    /// large to build: a helix's `cells`, `[lattice.fit]`, or the table that
    /// gives the last row.
    pub(crate) fn size_span(&self) -> Range<usize> {
        match (self.kind, &self.fit) {
            (Kind::Helix, _) => self.spans.cells.clone(),
            (_, Some(_)) => self.spans.fit.clone(),
            _ => self.row_table(self.rows.len().saturating_sub(1)),
        }
    }

    /// The text that sets row `i`'s front moves (its table when it has none).
    pub(crate) fn row_front_span(&self, i: usize) -> Range<usize> {
        self.row_span(i, Param::FrontMoves)
    }

    /// The text that sets row `i`'s leg direction, for errors about a row's strips.
    pub(crate) fn row_direction_span(&self, i: usize) -> Range<usize> {
        self.row_span(i, Param::Direction)
    }

    pub(crate) fn locate(&self, e: GrowthError) -> Diagnostic {
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

pub(super) fn field_spans(table: &Spanned<RawRow>) -> FieldSpans {
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
