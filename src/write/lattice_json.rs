//! `lattice.json`, format 2: the grown lattice as exchanged with other
//! tools. Only what was grown is written (vertices; each cell's corner
//! vertices, pivot and stacking layers); what follows from it (legs,
//! kappa, phi, the rods and the eyelets) is left to the reader, with the
//! formulas in docs/lattice-json.md. Numbers at full f64 round-trip
//! precision; one record per line keeps large files diffable.
//!
//! Format 1 also wrote the derived numbers and every vertex key again in
//! each cell, rod and eyelet: 14.2 MB for a 100 x 100 sheet, 2.25 MB now.

use crate::lattice::{Cell, Kind, Lattice, RodType, VertexKey};
use glam::DVec3;
use serde::Serialize;

/// The format written; docs/lattice-json.md says what changed from 1.
pub(crate) const FORMAT: u32 = 2;

#[derive(Serialize)]
struct VertexJson {
    key: Vec<u32>,
    pos: Vec<f64>,
    z: f64,
}

#[derive(Serialize)]
struct CellJson {
    key: Vec<u32>,
    /// Indices into `vertices` of UL, UR, LL, LR.
    vertices: [u32; 4],
    /// Only in a lattice that is not extrinsic.
    #[serde(skip_serializing_if = "Option::is_none")]
    frame: Option<u32>,
    /// UL and UR in the cell's frame, only where the row rebuilt its front
    /// (elsewhere they are the vertices' positions).
    #[serde(skip_serializing_if = "Option::is_none")]
    top: Option<[Vec<f64>; 2]>,
    pivot: Vec<f64>,
    z_pivot: f64,
    /// Stacking layers of rod A and rod B at their joints.
    layers: [u32; 2],
}

/// `[i, j]`, or `[k]` for a helix.
fn key(lattice: &Lattice, k: VertexKey) -> Vec<u32> {
    match lattice.kind {
        Kind::Helix => vec![k.col],
        _ => vec![k.row, k.col],
    }
}

fn cell_key(lattice: &Lattice, c: &Cell) -> Vec<u32> {
    match lattice.kind {
        Kind::Helix => vec![c.row * lattice.width as u32 + c.col],
        _ => vec![c.row, c.col],
    }
}

/// The lattice as lattice.json bytes. Its joints (`lattice::joints`) are
/// not written: they follow from the cells' corners and layers.
pub(crate) fn write(lattice: &Lattice) -> Vec<u8> {
    let dim = lattice.dim;
    let pos = |p: DVec3| p.to_array()[..dim].to_vec();
    let extrinsic = lattice.extrinsic();
    let rebuilt = |row: u32| {
        lattice
            .fronts
            .get(row as usize)
            .is_some_and(|f| !f.is_empty())
    };
    // The frame a row's cells are stored in: the last row at or before it
    // that grew on a rebuilt front (0 when none did).
    let mut frames = Vec::with_capacity(lattice.fronts.len());
    let mut last = 0;
    for row in 0..lattice.fronts.len() as u32 {
        if rebuilt(row) {
            last = row;
        }
        frames.push(last);
    }
    let frame_of = |row: u32| frames.get(row as usize).copied().unwrap_or(last);
    let mut out = String::new();
    out.push_str(&format!(
        "{{\"format\": {FORMAT}, \"kind\": \"{}\", \"dim\": {}, \"extrinsic\": {},\n",
        lattice.kind.name(),
        dim,
        extrinsic
    ));
    section(
        &mut out,
        "vertices",
        lattice.vertices.iter().map(|v| VertexJson {
            key: key(lattice, v.key),
            pos: pos(v.pos),
            z: v.z,
        }),
    );
    out.push_str(",\n");
    section(
        &mut out,
        "cells",
        lattice.cells.iter().map(|c| {
            let [ul, ur, _, _] = lattice.corners(c);
            CellJson {
                key: cell_key(lattice, c),
                vertices: c.corner_ids(),
                frame: (!extrinsic).then(|| frame_of(c.row)),
                top: rebuilt(c.row).then(|| [pos(ul), pos(ur)]),
                pivot: pos(c.pivot),
                z_pivot: c.z_pivot,
                layers: [lattice.layer(c, RodType::A), lattice.layer(c, RodType::B)],
            }
        }),
    );
    out.push_str("\n}\n");
    out.into_bytes()
}

fn section<T: Serialize>(out: &mut String, name: &str, items: impl Iterator<Item = T>) {
    out.push_str(&format!(" \"{name}\": ["));
    let mut first = true;
    for item in items {
        out.push_str(if first { "\n  " } else { ",\n  " });
        first = false;
        out.push_str(&serde_json::to_string(&item).expect("plain data serialises"));
    }
    out.push_str(if first { "]" } else { "\n ]" });
}
