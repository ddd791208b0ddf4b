//! `lattice.json` in the exchange schema of MATH.md 11: exact field names,
//! vertices/cells/rods/eyelets in lattice order, numbers at full f64
//! round-trip precision. One record per line keeps large files diffable.

use crate::lattice::{Lattice, VertexKey, joints};
use glam::DVec3;
use serde::Serialize;

#[derive(Serialize)]
struct VertexJson {
    key: [u32; 2],
    pos: Vec<f64>,
    z: f64,
}

#[derive(Serialize)]
struct CellJson {
    key: [u32; 2],
    ul: [u32; 2],
    ur: [u32; 2],
    ll: [u32; 2],
    lr: [u32; 2],
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
    cell: [u32; 2],
    #[serde(rename = "type")]
    kind: &'static str,
    start: [u32; 2],
    end: [u32; 2],
    legs: [f64; 2],
    length: f64,
    holes: [f64; 3],
    hole_pos: [Vec<f64>; 3],
}

#[derive(Serialize)]
struct EyeletJson {
    vertex: [u32; 2],
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

fn key(k: VertexKey) -> [u32; 2] {
    [k.row, k.col]
}

/// The lattice as lattice.json bytes.
pub fn write(lattice: &Lattice) -> Vec<u8> {
    let dim = lattice.dim;
    let pos = |p: DVec3| p.to_array()[..dim].to_vec();
    let vkey = |v: u32| key(lattice.vertex(v).key);
    let mut out = String::new();
    out.push_str(&format!(
        "{{\"kind\": \"{}\", \"dim\": {}, \"extrinsic\": true,\n",
        lattice.kind.name(),
        dim
    ));
    section(
        &mut out,
        "vertices",
        lattice.vertices.iter().map(|v| VertexJson {
            key: key(v.key),
            pos: pos(v.pos),
            z: v.z,
        }),
    );
    out.push_str(",\n");
    section(
        &mut out,
        "cells",
        lattice.cells.iter().map(|c| CellJson {
            key: [c.row, c.col],
            ul: vkey(c.ul),
            ur: vkey(c.ur),
            ll: vkey(c.ll),
            lr: vkey(c.lr),
            // An extrinsic lattice has one global frame; the frame index is the
            // row, as for intrinsic lattices whose rows each have their own.
            frame: c.row,
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
                cell: [cell.row, cell.col],
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
        joints(lattice).into_iter().map(|j| EyeletJson {
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
