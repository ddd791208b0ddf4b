//! `[simulation] supports`: lattice vertices held at their design
//! positions, as a table or base holds a vault's feet (docs/recipe.md,
//! "[simulation]"). Each is named as messages and report.txt name
//! vertices, `[row, column]` (`[index]` on a helix). The names' form is
//! checked here; that the grown lattice has them, and that they fix its
//! rigid motion, once it is grown (`Design::check_supports`).

use super::Design;
use super::raw::{RawSimulation, VertexName};
use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::lattice::{Kind, Lattice};
use glam::DVec3;
use std::ops::Range;
use toml::Spanned;

/// Where the supports were written: the list, and each entry.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct SupportSpans {
    pub(super) list: Option<Range<usize>>,
    pub(super) entries: Vec<Range<usize>>,
}

/// The fewest supports that fix a lattice in space: three not on one line.
pub(crate) const MIN_SUPPORTS: usize = 3;

/// A third support nearer the line through the farthest two than this
/// share of their distance counts as on it: the pins would leave the
/// lattice free to turn about that line.
pub(crate) const COLLINEAR: f64 = 1e-3;

const HINT: &str = "name each support as messages name vertices: [row, column], e.g. supports = [[0, 0], [0, 4], [3, 0]] ([index] on a helix); see the [simulation] table in docs/recipe.md";

/// The supports' keys `[row, column]` and where each was written; none
/// (and an empty list) when the recipe has no `supports`.
pub(super) fn parse(
    raw: Option<&Spanned<RawSimulation>>,
    kind: Kind,
) -> Result<(Vec<[u32; 2]>, SupportSpans), Diagnostic> {
    let Some(list) = raw.and_then(|r| r.get_ref().supports.as_ref()) else {
        return Ok((Vec::new(), SupportSpans::default()));
    };
    let mut keys: Vec<[u32; 2]> = Vec::new();
    let mut spans = SupportSpans {
        list: Some(list.span()),
        entries: Vec::new(),
    };
    for entry in list.get_ref() {
        let key = key(entry, kind)?;
        if let Some(first) = keys.iter().position(|k| *k == key) {
            return Err(Diagnostic::new(
                ErrorKind::DuplicateSupport,
                format!(
                    "[simulation] supports names vertex {} twice (entries {} and {})",
                    name(key, kind),
                    first + 1,
                    keys.len() + 1
                ),
            )
            .at(entry.span())
            .hint("remove the second entry: a vertex is held once"));
        }
        keys.push(key);
        spans.entries.push(entry.span());
    }
    if !keys.is_empty() && keys.len() < MIN_SUPPORTS {
        return Err(Diagnostic::new(
            ErrorKind::SupportsTooFew,
            format!(
                "[simulation] supports names {} {}; pins at fewer than {MIN_SUPPORTS} vertices do not fix the lattice's rigid motion",
                keys.len(),
                if keys.len() == 1 { "vertex" } else { "vertices" }
            ),
        )
        .at(list.span())
        .hint("name at least three vertices, not all on one line, or give supports = [] for a lattice that stands free"));
    }
    Ok((keys, spans))
}

/// One entry's key: `[row, column]`, or `[index]` on a helix (row 0).
fn key(entry: &VertexName, kind: Kind) -> Result<[u32; 2], Diagnostic> {
    let numbers = entry.get_ref();
    let wanted = if kind == Kind::Helix { 1 } else { 2 };
    let bad = |why: String| {
        Diagnostic::new(ErrorKind::SupportNotAVertexName, why)
            .at(entry.span())
            .hint(HINT)
    };
    if numbers.len() != wanted {
        return Err(bad(format!(
            "a support of a {} lattice is named by {wanted} whole {}, not {}",
            kind.name(),
            if wanted == 1 {
                "number ([index])"
            } else {
                "numbers ([row, column])"
            },
            numbers.len()
        )));
    }
    let mut key = [0u32; 2];
    for (k, n) in numbers.iter().enumerate() {
        let v = *n.get_ref();
        let Ok(v) = u32::try_from(v) else {
            return Err(bad(format!(
                "{v} is not a row or column: vertex names count from 0"
            )));
        };
        key[k + 2 - wanted] = v;
    }
    Ok(key)
}

/// A vertex key as messages name it (`Lattice::vertex_name`).
fn name(key: [u32; 2], kind: Kind) -> String {
    match kind {
        Kind::Helix => format!("[{}]", key[1]),
        _ => format!("[{}, {}]", key[0], key[1]),
    }
}

impl Design {
    /// The supports checked against the grown lattice: every one a vertex
    /// of it, and not all on one line (docs/recipe.md, "[simulation]").
    pub(crate) fn check_supports(&self, lattice: &Lattice) -> Result<(), Diagnostic> {
        let keys = &self.simulation.supports;
        if keys.is_empty() {
            return Ok(());
        }
        let spans = &self.spans.supports;
        let found = supported(lattice, keys);
        let mut points = Vec::with_capacity(keys.len());
        for (k, v) in found.iter().enumerate() {
            let Some(v) = v else {
                return Err(Diagnostic::new(
                    ErrorKind::UnknownSupport,
                    format!(
                        "[simulation] supports names vertex {}, which the lattice does not have",
                        name(keys[k], lattice.kind)
                    ),
                )
                .at_opt(spans.entries.get(k).cloned())
                .hint(format!(
                    "name vertices of the grown lattice ({}); report.txt and `karigami check` name them",
                    extent(lattice)
                )));
            };
            points.push(lattice.vertices[*v as usize].pos);
        }
        if let Some((a, b, _)) = off_line(&points).filter(|(_, _, off)| *off <= COLLINEAR) {
            return Err(Diagnostic::new(
                ErrorKind::SupportsTooFew,
                format!(
                    "the {} supports lie on one line (from vertex {} to vertex {}); pins on one line leave the lattice free to turn about it, so they do not fix its rigid motion",
                    keys.len(),
                    name(keys[a], lattice.kind),
                    name(keys[b], lattice.kind)
                ),
            )
            .at_opt(spans.list.clone())
            .hint("add a support off that line, e.g. a vertex of another row or column"));
        }
        Ok(())
    }
}

/// The index of each key's vertex in `lattice`, None for one it lacks.
pub(crate) fn supported(lattice: &Lattice, keys: &[[u32; 2]]) -> Vec<Option<u32>> {
    let by_key: std::collections::HashMap<[u32; 2], u32> = lattice
        .vertices
        .iter()
        .enumerate()
        .map(|(i, v)| ([v.key.row, v.key.col], i as u32))
        .collect();
    keys.iter().map(|k| by_key.get(k).copied()).collect()
}

/// The lattice's rows and columns, for the hint of an unknown support.
fn extent(lattice: &Lattice) -> String {
    let (rows, cols) = lattice
        .vertices
        .iter()
        .fold((0, 0), |(r, c), v| (r.max(v.key.row), c.max(v.key.col)));
    match lattice.kind {
        Kind::Helix => format!("[0] to [{cols}]"),
        _ => format!("rows 0 to {rows}, columns 0 to at most {cols}"),
    }
}

/// The farthest two points (indices) and how far the point farthest from
/// the line through them lies, as a share of their distance; None for
/// fewer than two points or all at one place.
pub(crate) fn off_line(points: &[DVec3]) -> Option<(usize, usize, f64)> {
    let (a, b) = farthest(points)?;
    let (p, q) = (points[a], points[b]);
    let span = p.distance(q);
    if span <= 0.0 {
        return None;
    }
    let u = (q - p) / span;
    let off = points
        .iter()
        .map(|&x| (x - p).reject_from_normalized(u).length())
        .fold(0.0, f64::max);
    Some((a, b, off / span))
}

/// The two points farthest apart (the first such pair): the supports' span.
pub(crate) fn farthest(points: &[DVec3]) -> Option<(usize, usize)> {
    let mut best: Option<(f64, usize, usize)> = None;
    for i in 0..points.len() {
        for j in i + 1..points.len() {
            let d = points[i].distance(points[j]);
            if best.is_none_or(|b| d > b.0) {
                best = Some((d, i, j));
            }
        }
    }
    best.map(|(_, i, j)| (i, j))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHEET: &str = "[lattice]\nseed = \"sheet\"\npoints = [[0.0, 0.0], [20.0, 0.0], [40.0, 0.0]]\nkappa = 0.0\n[lattice.grow]\nrows = 2\nangle = 45.0\n";

    #[test]
    fn an_empty_list_is_no_supports_and_names_are_row_then_column() {
        let free = crate::design::parse(&format!("{SHEET}[simulation]\nsupports = []\n"), "t")
            .expect("parses");
        assert!(free.simulation.supports.is_empty());
        let held = crate::design::parse(
            &format!("{SHEET}[simulation]\nsupports = [[0, 0], [0, 2], [2, 1]]\n"),
            "t",
        )
        .expect("parses");
        assert_eq!(held.simulation.supports, vec![[0, 0], [0, 2], [2, 1]]);
        let lattice = held.grow().expect("grows");
        let found = supported(&lattice, &held.simulation.supports);
        for (k, v) in found.iter().enumerate() {
            let v = v.expect("a vertex of the lattice");
            let key = lattice.vertices[v as usize].key;
            assert_eq!([key.row, key.col], held.simulation.supports[k]);
            assert_eq!(
                lattice.vertex_name(v),
                name(held.simulation.supports[k], lattice.kind)
            );
        }
    }

    #[test]
    fn points_on_a_line_are_found_and_a_point_off_it_is_not() {
        let on = [
            DVec3::ZERO,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(3.0, 3.0, 0.0),
        ];
        let (a, b, off) = off_line(&on).unwrap();
        assert_eq!((a, b), (0, 2));
        assert!(off < 1e-12, "{off}");
        let off_it = [
            DVec3::ZERO,
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(4.0, 0.0, 0.0),
        ];
        let (_, _, off) = off_line(&off_it).unwrap();
        assert!((off - 0.5).abs() < 1e-12, "{off}");
    }
}
