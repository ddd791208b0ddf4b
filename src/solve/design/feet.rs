//! Feet for a sheet whose simulated shape flattens (docs/design.md,
//! "Supports"): a surface that unrolls without stretching, a cylindrical
//! vault, takes no stress to lie flat, so a free sheet of straight strips
//! relaxes flat and only its feet, held where the design has them, keep
//! its depth. The feet are the lattice's boundary vertices within a
//! quarter edge of the lowest height of each of the two opposite sides
//! that lie lowest: the sides along the vault's length.

use super::Found;
use crate::design::supports::{COLLINEAR, off_line};
use crate::lattice::{Kind, Lattice};
use glam::DVec3;
use std::collections::BTreeMap;

/// A simulated shape has flattened when its spread across its thinnest
/// axis is under this share of the design's (the cylinder's 70-cell
/// sheet: 3.9 mm against 32.0 mm).
pub(super) const FLATTENED: f64 = 0.5;

/// Whether the simulated joints `simulated` lie flatter than the design
/// `design` (the same points in the same order): their spread across
/// their own thinnest axis under `FLATTENED` of the design's.
pub fn flattens(design: &[DVec3], simulated: &[DVec3]) -> bool {
    let (d, s) = (thinnest_spread(design), thinnest_spread(simulated));
    d > 0.0 && s < FLATTENED * d
}

/// The standard deviation of points across their thinnest principal axis.
fn thinnest_spread(points: &[DVec3]) -> f64 {
    if points.len() < 3 {
        return 0.0;
    }
    let (axes, centre) = crate::target::principal(points.iter().map(|&p| (p, 1.0)));
    let n = points.len() as f64;
    (points
        .iter()
        .map(|&p| (p - centre).dot(axes.z_axis).powi(2))
        .sum::<f64>()
        / n)
        .sqrt()
}

/// The feet of a sheet lattice, as `[row, column]` keys in order, for
/// cells of `edge` (mm); None when the lattice is not a sheet or its
/// feet would not fix it in space (fewer than three, or on one line).
pub(super) fn feet(lattice: &Lattice, edge: f64) -> Option<Vec<[u32; 2]>> {
    if lattice.kind != Kind::Sheet || lattice.cells.is_empty() {
        return None;
    }
    let pos: Vec<DVec3> = lattice.vertices.iter().map(|v| v.pos).collect();
    let (axes, centre) = crate::target::principal(pos.iter().map(|&p| (p, 1.0)));
    let height = |v: usize| (pos[v] - centre).dot(axes.z_axis);
    let boundary = boundary(lattice);
    let sides = sides(lattice);
    // Of the two pairs of opposite sides, each way up, the pair lowest
    // below the mean height: the vault's feet, where its depth is.
    let mean = |vs: &[usize], sign: f64| {
        vs.iter().map(|&v| sign * height(v)).sum::<f64>() / vs.len().max(1) as f64
    };
    let (pair, sign) = [(0usize, 1.0), (1, 1.0), (0, -1.0), (1, -1.0)]
        .into_iter()
        .min_by(|a, b| {
            let low = |&(p, s): &(usize, f64)| {
                let (x, y): &(Vec<usize>, Vec<usize>) = &sides[p];
                mean(x, s) + mean(y, s)
            };
            low(a).total_cmp(&low(b))
        })?;
    let (one, other) = &sides[pair];
    let mut keys: Vec<[u32; 2]> = Vec::new();
    for side in [one, other] {
        let low = side
            .iter()
            .map(|&v| sign * height(v))
            .fold(f64::INFINITY, f64::min);
        for &v in side {
            if boundary[v] && sign * height(v) <= low + edge / 4.0 {
                let k = lattice.vertices[v].key;
                keys.push([k.row, k.col]);
            }
        }
    }
    keys.sort_unstable();
    keys.dedup();
    let at: Vec<DVec3> = crate::design::supports::supported(lattice, &keys)
        .into_iter()
        .flatten()
        .map(|v| pos[v as usize])
        .collect();
    let fixed = at.len() >= crate::design::supports::MIN_SUPPORTS
        && off_line(&at).is_some_and(|(_, _, off)| off > COLLINEAR);
    fixed.then_some(keys)
}

/// Whether each vertex is on the lattice's boundary: fewer than four
/// cells meet there.
fn boundary(lattice: &Lattice) -> Vec<bool> {
    let mut cells = vec![0u8; lattice.vertices.len()];
    for c in &lattice.cells {
        for v in [c.ul, c.ur, c.ll, c.lr] {
            cells[v as usize] = cells[v as usize].saturating_add(1);
        }
    }
    cells.iter().map(|&n| n < 4).collect()
}

/// A sheet's two pairs of opposite sides, as vertex indices: its first
/// and last rows, and the first and last vertex of every row.
fn sides(lattice: &Lattice) -> [(Vec<usize>, Vec<usize>); 2] {
    let mut rows: BTreeMap<u32, Vec<(u32, usize)>> = BTreeMap::new();
    for (i, v) in lattice.vertices.iter().enumerate() {
        rows.entry(v.key.row).or_default().push((v.key.col, i));
    }
    for r in rows.values_mut() {
        r.sort_unstable();
    }
    let row = |r: Option<&Vec<(u32, usize)>>| -> Vec<usize> {
        r.map(|r| r.iter().map(|x| x.1).collect())
            .unwrap_or_default()
    };
    let first = row(rows.values().next());
    let last = row(rows.values().next_back());
    let left = rows
        .values()
        .filter_map(|r| r.first().map(|x| x.1))
        .collect();
    let right = rows
        .values()
        .filter_map(|r| r.last().map(|x| x.1))
        .collect();
    [(first, last), (left, right)]
}

/// `found` with its feet as `[simulation] supports` (a table after its
/// lattice, the recipe's comments saying which and why), or None when
/// the lattice has no feet that fix it (`feet`).
pub fn with_feet(found: &Found, lattice: &Lattice, edge: f64) -> Option<Found> {
    let keys = feet(lattice, edge)?;
    let names: Vec<String> = keys
        .iter()
        .map(|k| format!("[{}, {}]", k[0], k[1]))
        .collect();
    let table = format!(
        "\n# Supports: a vault unrolls flat without stretching, so left free the strips relax and\n\
         # the simulated sheet flattens. Its {} feet (the boundary vertices within a quarter edge\n\
         # of the lowest height of the two sides along the vault's length) are pinned to the base\n\
         # where the design has them, which keeps its depth (docs/design.md, \"Supports\").\n\
         [simulation]\nsupports = [{}]\n",
        keys.len(),
        names.join(", ")
    );
    Some(Found {
        lattice: format!("{}{table}", found.lattice),
        seed: format!(
            "{}; its {} feet pinned to the base ([simulation] supports)",
            found.seed,
            keys.len()
        ),
        ..found.clone()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The small vault's feet (fixtures/designs/vault.toml, which `design`
    /// wrote): the first and last vertex of each of its six rows, the two
    /// sides along its length; its seed row, across the arc, is not one.
    #[test]
    fn a_vaults_feet_are_its_two_lowest_sides() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/designs/vault.toml");
        let text = std::fs::read_to_string(path).expect("recipe");
        let d = crate::design::parse(&text, "vault").expect("parses");
        let lattice = d.grow().expect("grows");
        let keys = feet(&lattice, 60.0).expect("feet");
        let want: Vec<[u32; 2]> = (0..6).flat_map(|r| [[r, 0], [r, 4]]).collect();
        assert_eq!(keys, want);
        assert_eq!(d.simulation.supports, want);
        // Turned upside down its feet are the same vertices: the side
        // pairs are judged both ways up.
        let mut turned = lattice.clone();
        for v in &mut turned.vertices {
            v.pos = -v.pos;
        }
        assert_eq!(feet(&turned, 60.0), Some(want));
    }

    #[test]
    fn a_flat_copy_flattens_and_the_design_itself_does_not() {
        // A shallow vault across x, and the same points pressed flat.
        let vault: Vec<DVec3> = (0..5)
            .flat_map(|i| (0..5).map(move |j| (i, j)))
            .map(|(i, j)| {
                let x = i as f64 * 50.0 - 100.0;
                DVec3::new(x, j as f64 * 50.0, 0.002 * (100.0 * 100.0 - x * x))
            })
            .collect();
        let flat: Vec<DVec3> = vault
            .iter()
            .map(|p| DVec3::new(p.x, p.y, 0.1 * p.z))
            .collect();
        assert!(flattens(&vault, &flat));
        assert!(!flattens(&vault, &vault));
    }
}
