//! The rows of a sheet or loop: `[lattice.grow]` defaults, the
//! `[[lattice.rows]]` entries that override them, and rebuilt fronts.

use super::raw;
use super::raw::{RawFront, RawLattice, RawLeg, RawRow};
use super::spans::{NO_ENTRY, Spans, field_spans};
use super::values::{coords, count, finite};
use crate::diagnostic::{Diagnostic, ErrorKind, shown};
use crate::lattice::{Crank, FrontMoves, Kind, MAX_CELLS, PivotMove, RowParams, Saddle};
use crate::legs::{Direction, Leg};
use std::ops::Range;
use toml::Spanned;

/// One `RowParams` per row: `[lattice.grow]` defaults overridden by the
/// `[[lattice.rows]]` entries.
pub(super) fn rows(
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
        check_grow(g)?;
        spans.grow = Some(field_spans(g));
    }
    let max_rows = MAX_CELLS / width.max(1);
    let total = match defaults.and_then(|g| g.rows.as_ref()) {
        Some(n) => Some(count(n, "grow.rows", 1, max_rows as i64)?),
        None => None,
    };
    let entries = lat.rows.as_deref().unwrap_or(&[]);
    let mut row_entry = row_entries(entries, total, max_rows, spans)?;
    let total = total.unwrap_or(row_entry.len());
    if total == 0 {
        // [lattice.grow] without `rows` is where the count is missing.
        let (message, span) = match &lat.grow {
            Some(g) if entries.is_empty() => (
                "the design grows no rows: [lattice.grow] does not say how many (`rows`)",
                g.span(),
            ),
            _ => ("the design grows no rows", spans.lattice.clone()),
        };
        return Err(Diagnostic::new(ErrorKind::NoRows, message)
            .at(span)
            .hint("add [[lattice.rows]] entries, or [lattice.grow] with `rows = N` and a default direction"));
    }
    row_entry.resize(total, NO_ENTRY);
    let rows = resolve_rows(defaults, entries, &row_entry, kind, dim, last, spans)?;
    spans.row_entry = row_entry;
    Ok(rows)
}

/// `[lattice.grow]` holds the defaults of every row, so not the fields
/// that place one entry.
fn check_grow(g: &Spanned<RawRow>) -> Result<(), Diagnostic> {
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
    Ok(())
}

/// Which entry describes each row (`NO_ENTRY`: the default), up to the
/// last row an entry reaches; each entry's field spans go into `spans`.
fn row_entries(
    entries: &[Spanned<RawRow>],
    total: Option<usize>,
    max_rows: usize,
    spans: &mut Spans,
) -> Result<Vec<u32>, Diagnostic> {
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
            return Err(described_before(&row_entry, index, span));
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
    Ok(row_entry)
}

/// The error for an entry (at `span`) for row `index`, which the entries
/// already read reach past. A row no entry covers lies before an entry
/// already read: the entries are out of order, not given twice.
fn described_before(row_entry: &[u32], index: usize, span: Range<usize>) -> Diagnostic {
    let earlier = row_entry[index..]
        .iter()
        .find(|&&x| x != NO_ENTRY)
        .copied()
        .unwrap_or(NO_ENTRY);
    let earlier_row = row_entry.iter().position(|&x| x == earlier).unwrap_or(0);
    if row_entry[index] == NO_ENTRY {
        Diagnostic::new(
            ErrorKind::RowsOutOfOrder,
            format!(
                "this entry describes row {index}, but comes after the entry for row {earlier_row}"
            ),
        )
        .at(span)
        .hint("list [[lattice.rows]] entries in increasing row order")
    } else {
        Diagnostic::new(
            ErrorKind::RowGivenTwice,
            format!(
                "row {index} is already described by an earlier [[lattice.rows]] entry (the one from row {earlier_row})"
            ),
        )
        .at(span)
        .hint("describe each row once: remove this entry, or lower the earlier entry's `repeat`")
    }
}

/// Each row's parameters, from its entry or the default. Each distinct
/// (entry or default) is resolved once, then copied per row.
fn resolve_rows(
    defaults: Option<&RawRow>,
    entries: &[Spanned<RawRow>],
    row_entry: &[u32],
    kind: Kind,
    dim: usize,
    last: usize,
    spans: &Spans,
) -> Result<Vec<RowParams>, Diagnostic> {
    let default_row = defaults
        .map(|g| resolve(None, g, dim, last, &described(row_entry, NO_ENTRY)))
        .transpose()?
        .unwrap_or_default();
    let resolved: Vec<RowParams> = (0..entries.len())
        .map(|e| {
            let rows = described(row_entry, e as u32);
            resolve(defaults, entries[e].get_ref(), dim, last, &rows)
        })
        .collect::<Result<_, _>>()?;
    row_entry
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
        .collect::<Result<Vec<_>, _>>()
}

/// The rows entry `e` (`NO_ENTRY`: [lattice.grow]) describes, for
/// messages: "row 3", "rows 3 to 5", or the default rows.
fn described(row_entry: &[u32], e: u32) -> Described {
    let mut rows = (0..row_entry.len()).filter(|&i| row_entry[i] == e);
    let first = rows.next();
    let words = match (e == NO_ENTRY, first, rows.next_back()) {
        (true, ..) => "the default rows ([lattice.grow])".to_string(),
        (false, Some(a), Some(b)) => format!("rows {a} to {b}"),
        (false, Some(a), None) => format!("row {a}"),
        // Not reached: every entry describes at least one row.
        (false, None, _) => "a [[lattice.rows]] entry".to_string(),
    };
    Described { words, first }
}

/// The rows one entry (or [lattice.grow]) describes: in words for a
/// message, and the first of them for the lattice site.
struct Described {
    words: String,
    first: Option<usize>,
}

/// A row's parameters from its own fields, falling back on `defaults`;
/// `rows` are the rows they describe. A missing direction is reported
/// per row by the caller.
fn resolve(
    defaults: Option<&RawRow>,
    row: &RawRow,
    dim: usize,
    last: usize,
    rows: &Described,
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
                    format!("{name} is {}, but must be a positive length", shown(v)),
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
        Some(f) => Some(front_moves(f, last, rows)?),
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

/// `front.saddle = c` or `[c, d]`: the amplitudes (1/mm) of the saddle
/// the front is laid on (docs/recipe.md, "Rebuilt fronts"), for `rows`.
fn saddle(a: &Spanned<raw::RawAmplitudes>, rows: &Described) -> Result<Saddle, Diagnostic> {
    let given = &a.get_ref().0;
    let wrong = match given[..] {
        [c] if c.is_finite() => return Ok(Saddle { c, d: 0.0 }),
        [c, d] if c.is_finite() && d.is_finite() => return Ok(Saddle { c, d }),
        [] => "no amplitude".to_string(),
        [_] | [_, _] => {
            let bad = given
                .iter()
                .find(|v| !v.is_finite())
                .copied()
                .unwrap_or(f64::NAN);
            format!("the amplitude {}", shown(bad))
        }
        _ => format!("{} amplitudes", given.len()),
    };
    let d = Diagnostic::new(
        ErrorKind::FrontSaddleAmplitudes,
        format!(
            "front.saddle of {} has {wrong}, but takes one or two finite amplitudes (c, d in 1/mm)",
            rows.words
        ),
    )
    .at(a.span())
    .hint("give `saddle = c` or `saddle = [c, d]` (1/mm): the front laid on z' = r^2 (c cos 2t + d cos 6t)");
    Err(match rows.first {
        Some(r) => d.site(format!("row {r}")),
        None => d,
    })
}

/// The generators of a rebuilt front (docs/math.md 7), from `front = { ... }`.
/// `last` is the index of the front's last vertex (N, i.e. vertex 0 again, on a loop).
/// `rows` are the rows the moves are given for.
fn front_moves(
    f: &Spanned<RawFront>,
    last: usize,
    rows: &Described,
) -> Result<FrontMoves, Diagnostic> {
    let raw = f.get_ref();
    if raw.is_empty() {
        return Err(Diagnostic::new(
            ErrorKind::EmptyFront,
            "front = { } rebuilds the front with no move",
        )
        .at(f.span())
        .hint("give turn, bend, twist, saddle, pivot, crank or zigzag, or leave `front` out"));
    }
    let angles = |a: &Option<Spanned<raw::RawAngles>>,
                  what: &str|
     -> Result<Option<Vec<f64>>, Diagnostic> {
        match a {
            None => Ok(None),
            Some(a) if a.get_ref().0.iter().all(|v| v.is_finite()) && !a.get_ref().0.is_empty() => {
                Ok(Some(a.get_ref().0.clone()))
            }
            Some(a) => {
                let d = Diagnostic::new(
                    ErrorKind::FrontAnglesNotFinite,
                    format!("front.{what} of {} needs finite angles", rows.words),
                )
                .at(a.span())
                .hint("give an angle in degrees, or one per interior front vertex");
                Err(match rows.first {
                    Some(r) => d.site(format!("row {r}")),
                    None => d,
                })
            }
        }
    };
    let index = |n: &Spanned<i64>, what: &str| count(n, what, 0, last as i64);
    let mut moves = FrontMoves {
        turn: angles(&raw.turn, "turn")?,
        bend: angles(&raw.bend, "bend")?,
        twist: angles(&raw.twist, "twist")?,
        saddle: raw.saddle.as_ref().map(|a| saddle(a, rows)).transpose()?,
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
