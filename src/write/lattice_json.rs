//! `lattice.json` in the exchange schema of MATH.md 11: exact field names,
//! vertices/cells/rods/eyelets in lattice order, numbers at full f64
//! round-trip precision. One record per line keeps large files diffable.

use crate::lattice::{Cell, Joint, Kind, Lattice, VertexKey};
use glam::DVec3;
use serde::Serialize;

#[derive(Serialize)]
struct VertexJson {
    key: Vec<u32>,
    pos: Vec<f64>,
    z: f64,
}

#[derive(Serialize)]
struct CellJson {
    key: Vec<u32>,
    ul: Vec<u32>,
    ur: Vec<u32>,
    ll: Vec<u32>,
    lr: Vec<u32>,
    frame: u32,
    pivot: Vec<f64>,
    z_pivot: f64,
    corners: [Vec<f64>; 4],
    legs: [f64; 4],
    kappa: f64,
    phi: f64,
}

#[derive(Serialize)]
struct RodJson {
    id: usize,
    cell: Vec<u32>,
    #[serde(rename = "type")]
    kind: &'static str,
    start: Vec<u32>,
    end: Vec<u32>,
    legs: [f64; 2],
    length: f64,
    holes: [f64; 3],
    hole_pos: [Vec<f64>; 3],
}

#[derive(Serialize)]
struct EyeletJson {
    vertex: Vec<u32>,
    n_rods: usize,
    needs_eyelet: bool,
    rods: Vec<EyeletRodJson>,
}

#[derive(Serialize)]
struct EyeletRodJson {
    rod: usize,
    #[serde(rename = "type")]
    kind: &'static str,
    end: &'static str,
    layer: u32,
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

/// The frame a row's cells are stored in: the last row at or before it
/// that grew on a rebuilt front (0 when none did).
fn frame(lattice: &Lattice, row: u32) -> u32 {
    (0..=row as usize)
        .rev()
        .find(|&r| lattice.fronts.get(r).is_some_and(|f| !f.is_empty()))
        .unwrap_or(0) as u32
}

/// The lattice as lattice.json bytes, with its joints (`lattice::joints`).
pub(crate) fn write(lattice: &Lattice, joints: &[Joint]) -> Vec<u8> {
    let dim = lattice.dim;
    let pos = |p: DVec3| p.to_array()[..dim].to_vec();
    let vkey = |v: u32| key(lattice, lattice.vertex(v).key);
    let mut out = String::new();
    out.push_str(&format!(
        "{{\"kind\": \"{}\", \"dim\": {}, \"extrinsic\": {},\n",
        lattice.kind.name(),
        dim,
        lattice.extrinsic()
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
        lattice.cells.iter().map(|c| CellJson {
            key: cell_key(lattice, c),
            ul: vkey(c.ul),
            ur: vkey(c.ur),
            ll: vkey(c.ll),
            lr: vkey(c.lr),
            frame: frame(lattice, c.row),
            pivot: pos(c.pivot),
            z_pivot: c.z_pivot,
            corners: lattice.corners(c).map(pos),
            legs: lattice.legs(c),
            kappa: lattice.kappa(c),
            phi: lattice.phi(c),
        }),
    );
    out.push_str(",\n");
    section(
        &mut out,
        "rods",
        lattice.rods().map(|r| {
            let cell = &lattice.cells[r.cell];
            RodJson {
                id: r.id,
                cell: cell_key(lattice, cell),
                kind: r.kind.letter(),
                start: vkey(r.start),
                end: vkey(r.end),
                legs: r.legs,
                length: r.length(),
                holes: r.holes(),
                hole_pos: r.hole_pos.map(pos),
            }
        }),
    );
    out.push_str(",\n");
    section(
        &mut out,
        "eyelets",
        joints.iter().map(|j| EyeletJson {
            vertex: vkey(j.vertex),
            n_rods: j.ends.len(),
            needs_eyelet: j.needs_eyelet(),
            rods: j
                .ends
                .iter()
                .map(|e| EyeletRodJson {
                    rod: e.rod,
                    kind: e.kind.letter(),
                    end: e.end.name(),
                    layer: e.layer,
                })
                .collect(),
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
