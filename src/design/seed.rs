//! The seed front: the generators a designer types instead of every point
//! (line, arc, polyline), and the recipe's seed read and checked.

use super::raw::{RawKappa, RawLattice};
use super::spans::Spans;
use super::values::{coords, count, finite};
use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::lattice::{Kind, MAX_CELLS};
use glam::DVec3;
use std::ops::Range;
use toml::Spanned;

/// `cells + 1` evenly spaced points from `from` to `to`.
pub(crate) fn line(from: DVec3, to: DVec3, cells: usize) -> Vec<DVec3> {
    (0..=cells)
        .map(|k| from.lerp(to, k as f64 / cells as f64))
        .collect()
}

/// Which coordinate plane an arc lies in (3-D seeds).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Plane {
    Xy,
    Xz,
    Yz,
}

impl Plane {
    pub(crate) fn parse(name: &str) -> Option<Self> {
        match name {
            "xy" => Some(Plane::Xy),
            "xz" => Some(Plane::Xz),
            "yz" => Some(Plane::Yz),
            _ => None,
        }
    }

    fn axes(self) -> (DVec3, DVec3) {
        match self {
            Plane::Xy => (DVec3::X, DVec3::Y),
            Plane::Xz => (DVec3::X, DVec3::Z),
            Plane::Yz => (DVec3::Y, DVec3::Z),
        }
    }
}

/// `cells + 1` points on a circular arc from angle `from_deg` to `to_deg`
/// (counter-clockwise when `to > from`), measured in `plane` from its first axis.
pub(crate) fn arc(
    center: DVec3,
    radius: f64,
    from_deg: f64,
    to_deg: f64,
    cells: usize,
    plane: Plane,
) -> Vec<DVec3> {
    let (e1, e2) = plane.axes();
    (0..=cells)
        .map(|k| {
            let a = (from_deg + (to_deg - from_deg) * k as f64 / cells as f64).to_radians();
            center + radius * (a.cos() * e1 + a.sin() * e2)
        })
        .collect()
}

/// Each segment of the polyline split into `per_segment` equal edges.
pub(crate) fn polyline(points: &[DVec3], per_segment: usize) -> Vec<DVec3> {
    let mut out = vec![points[0]];
    for pair in points.windows(2) {
        out.extend((1..=per_segment).map(|k| pair[0].lerp(pair[1], k as f64 / per_segment as f64)));
    }
    out
}

pub(super) type SeedPoint = (DVec3, (usize, Range<usize>));

/// The seed front from exactly one of `points`, `[lattice.line]`,
/// `[lattice.arc]`, `[lattice.polyline]`; each point with its dimension and span.
pub(super) fn seed_points(
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
        all(line(from, to, cells), d1, first.clone())
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
            arc(center, radius, from, to, cells, plane),
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
        let mut pts = arc(center, radius, from, from + 360.0, n, plane);
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
        all(polyline(&pts, per), corners[0].1, first.clone())
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
fn plane(p: &Option<Spanned<String>>, dim: usize, what: &str) -> Result<Plane, Diagnostic> {
    match p {
        None => Ok(Plane::Xy),
        Some(p) if dim == 2 && p.get_ref() != "xy" => Err(Diagnostic::new(
            ErrorKind::PlanarSeedOffPlane,
            format!("a planar {what} lies in the xy plane"),
        )
        .at(p.span())
        .hint(format!(
            "give {what}.center 3 coordinates to use another plane"
        ))),
        Some(p) => Plane::parse(p.get_ref()).ok_or_else(|| {
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
pub(super) fn helix_cell_count(lat: &RawLattice, spans: &Spans) -> Result<usize, Diagnostic> {
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
pub(super) fn dimension(points: &[SeedPoint]) -> Result<usize, Diagnostic> {
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

pub(super) fn seed_kappa(
    lat: &RawLattice,
    edges: usize,
    spans: &mut Spans,
) -> Result<Vec<f64>, Diagnostic> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generators_produce_cells_plus_one_points() {
        assert_eq!(line(DVec3::ZERO, DVec3::X * 10.0, 5).len(), 6);
        let a = arc(DVec3::ZERO, 2.0, 0.0, 90.0, 3, Plane::Xz);
        assert_eq!(a.len(), 4);
        assert!((a[3] - DVec3::new(0.0, 0.0, 2.0)).length() < 1e-12);
        let p = polyline(&[DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0)], 2);
        assert_eq!(p.len(), 5);
        assert_eq!(p[2], DVec3::X);
    }
}
