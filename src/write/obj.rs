//! lattice.obj: the deployed lattice for Blender or MeshLab, one object per
//! strip (named by its ID) as a box of the strip's size, stacked at joints.
//! Coordinates to 3 decimals: a micrometre is far below any kerf and any
//! screen, and a 10,000-cell file is 3 % smaller than at 4 (lattice.json
//! keeps the exact numbers).

use super::number::num;
use glam::DVec3;
use std::fmt::Write as _;

/// Quads of a box whose corner k has bits (along, across, normal), wound
/// counter-clockwise seen from outside.
const FACES: [[usize; 4]; 6] = [
    [0, 2, 3, 1], // bottom
    [4, 5, 7, 6], // top
    [0, 1, 5, 4], // one side
    [2, 6, 7, 3], // other side
    [0, 4, 6, 2], // start end
    [1, 3, 7, 5], // far end
];

/// `x` mm to 0.001 (1 um), trailing zeros trimmed: `num` of the nearest
/// thousandth, so the same value always prints the same way.
fn micro(x: f64) -> super::number::Text {
    num((x * 1e3).round() / 1e3)
}

/// `solids`: each strip's ID and box corners (see `parts::solid`).
pub(crate) fn write(title: &str, solids: &[(String, [DVec3; 8])]) -> Vec<u8> {
    let mut out = format!(
        "# {title}\n# karigami {}; units mm, to 0.001 (exact numbers in lattice.json); one object per strip\n",
        env!("CARGO_PKG_VERSION")
    );
    for (id, corners) in solids {
        let _ = writeln!(out, "o {id}");
        for c in corners {
            let _ = writeln!(out, "v {} {} {}", micro(c.x), micro(c.y), micro(c.z));
        }
        // Relative indices (-1 is the vertex just written), as the OBJ
        // format allows and Blender, MeshLab and trimesh read: every box's
        // faces read the same, "f -8 -6 -5 -7", where absolute indices grew
        // to six digits (a quarter of a 100 x 100 sheet's file).
        for f in FACES {
            let i = |k: usize| f[k] as i64 - 8;
            let _ = writeln!(out, "f {} {} {} {}", i(0), i(1), i(2), i(3));
        }
    }
    out.into_bytes()
}
