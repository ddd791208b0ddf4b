//! Parts: one flat strip per rod (docs/math.md 10.1) with its holes and
//! engraving, plus the eyelets, and the fabrication checks that name the
//! strip at fault. Strip geometry is in the strip's own frame, in mm: x runs
//! along the axis from the start tip (0) to the end tip (`length`), y across
//! it, pointing down when the strip lies with its start to the left.
//!
//! Where things are: the strips are made here (`parts`); their eyelet holes
//! are placed and checked in `holes.rs`, their IDs, part-type codes and dot
//! codes engraved in `engraving.rs`; part types are grouped in `types.rs`,
//! strip clashes found in `clash.rs`, the test piece (drawn in `fabrication/test_piece.rs`, which the recipe's checks also read).

pub mod clash;
mod engraving;
mod holes;
pub use crate::fabrication::test_piece;
pub(crate) mod types;

pub(crate) use crate::fabrication::test_piece::TestPiece;
pub use crate::fabrication::test_piece::test_piece;
pub use engraving::DOT;
pub(crate) use types::PartType;

use crate::fabrication::Fabrication;
use crate::lattice::{Joint, Lattice, RodType, vertex_eyelets};
use glam::DVec2;

/// One flat strip cut for one rod: its holes, length and engraving, in the
/// strip frame (mm).
#[derive(Clone, Debug, PartialEq)]
pub struct Strip {
    /// Human-readable ID, e.g. `R03-C05-A` (cell row, column, rod letter).
    pub id: String,
    /// The rod's id in lattice.json.
    pub rod: usize,
    /// Row of the rod's cell (the growth step; the turn for a helix).
    pub row: u32,
    pub(crate) col: u32,
    pub(crate) kind: RodType,
    /// Hole-to-hole distances: start vertex to pivot, pivot to end vertex.
    pub legs: [f64; 2],
    /// Nominal tip-to-tip length.
    pub length: f64,
    /// Hole centres along the axis, from the start tip.
    pub(crate) holes: [f64; 3],
    /// Engraved strokes (ID and orientation arrow), in the strip frame.
    pub(crate) engraving: Vec<Vec<DVec2>>,
    /// Index into `Parts::types`.
    pub part_type: usize,
    /// What the engraving says.
    pub marking: Marking,
    /// Height (mm) of the engraved text; 0 when there is none (dots, or the
    /// arrow alone).
    pub label_height: f64,
}

/// What is engraved on a strip, from most to least specific.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Marking {
    /// The full ID and the arrow.
    Id,
    /// The compact ID (`label = "compact"`) and the arrow.
    Compact,
    /// The part type's code (with the arrow unless the strip is symmetric).
    Type,
    /// The type's dot code: this many engraved dots (no room for text).
    Dots(usize),
    /// Only the orientation arrow (`label = "none"`).
    Arrow,
}

/// The cut outline of a strip: nominal, or grown by the kerf when compensated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outline {
    /// Tip-to-tip length as cut (mm): nominal, plus the kerf when compensated.
    pub length: f64,
    /// Width as cut (mm): the strip width, plus the kerf when compensated.
    pub width: f64,
    /// Hole diameter as cut.
    pub(crate) hole: f64,
    /// How far the outline extends beyond the nominal tip (kerf / 2 or 0).
    pub grow: f64,
}

impl Outline {
    /// The outline of a strip of nominal length `strip_length` (mm) under
    /// `fab`'s kerf compensation.
    pub fn of(strip_length: f64, fab: &Fabrication) -> Self {
        let k = if fab.compensate_kerf { fab.kerf } else { 0.0 };
        Self {
            length: strip_length + k,
            width: fab.material.width + k,
            hole: fab.eyelet.hole - k,
            grow: k / 2.0,
        }
    }
}

/// Something a maker should look at but that does not stop the build.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Warning {
    pub(crate) strip: Option<String>,
    pub(crate) message: String,
}

/// A fabrication check that fails for at least one strip.
#[derive(Clone, Debug, PartialEq)]
pub struct PartsError {
    pub(crate) kind: crate::diagnostic::ErrorKind,
    /// The first strip at fault and its cell row (for pointing at the recipe).
    pub(crate) strip: String,
    pub(crate) row: u32,
    pub(crate) message: String,
    pub(crate) hint: String,
}

/// The strips of a lattice, grouped into part types, with their eyelets and
/// warnings.
#[derive(Clone, Debug, PartialEq)]
pub struct Parts {
    /// In lattice.json's rod order.
    pub strips: Vec<Strip>,
    /// Interchangeable strips grouped, in order of their first strip.
    pub types: Vec<PartType>,
    /// Vertex pivots joining two or more rod ends.
    pub(crate) vertex_eyelets: usize,
    /// One per cell.
    pub(crate) pivot_eyelets: usize,
    pub(crate) warnings: Vec<Warning>,
}

impl Parts {
    /// Eyelets the build needs: one per scissor pivot and one per vertex joint
    /// of two or more rod ends.
    pub fn eyelets(&self) -> usize {
        self.vertex_eyelets + self.pivot_eyelets
    }
}

/// Zero-padded index width for IDs: at least 2 digits, more for big lattices.
fn digits(max: u32) -> usize {
    max.to_string().len().max(2)
}

pub(crate) fn strip_id(
    row: u32,
    col: u32,
    kind: RodType,
    row_digits: usize,
    col_digits: usize,
) -> String {
    format!("R{row:0row_digits$}-C{col:0col_digits$}-{}", kind.letter())
}

/// The strips of a lattice, checked against the fabrication settings;
/// `joints` are the lattice's (`lattice::joints`), computed once by the caller.
pub fn parts(lattice: &Lattice, joints: &[Joint], fab: &Fabrication) -> Result<Parts, PartsError> {
    let max_row = lattice.cells.iter().map(|c| c.row).max().unwrap_or(0);
    let max_col = lattice.cells.iter().map(|c| c.col).max().unwrap_or(0);
    let (rd, cd) = (digits(max_row), digits(max_col));
    let margin = fab.end_margin;
    let mut warnings = Vec::new();
    let mut strips: Vec<Strip> = lattice
        .rods()
        .map(|rod| {
            let cell = &lattice.cells[rod.cell];
            Strip {
                id: strip_id(cell.row, cell.col, rod.kind, rd, cd),
                rod: rod.id,
                row: cell.row,
                col: cell.col,
                kind: rod.kind,
                legs: rod.legs,
                length: rod.length() + 2.0 * margin,
                holes: holes::centres(rod.legs, margin),
                engraving: Vec::new(),
                part_type: 0,
                marking: Marking::Arrow,
                label_height: 0.0,
            }
        })
        .collect();
    holes::check(&strips, fab, &mut warnings)?;
    check_length(&strips, fab)?;
    let types = engraving::engrave(&mut strips, fab, &mut warnings);
    let vertex_eyelets = vertex_eyelets(joints);
    Ok(Parts {
        strips,
        types,
        vertex_eyelets,
        pivot_eyelets: lattice.cells.len(),
        warnings,
    })
}

/// Strips longer than the sheet's usable length: refused.
fn check_length(strips: &[Strip], fab: &Fabrication) -> Result<(), PartsError> {
    let (uw, uh) = fab.sheet.usable();
    let longest = uw.max(uh);
    if let Some(s) = strips
        .iter()
        .find(|s| Outline::of(s.length, fab).length > longest)
    {
        let n = strips
            .iter()
            .filter(|s| Outline::of(s.length, fab).length > longest)
            .count();
        let others = if n > 1 {
            format!(" ({} more strips too)", n - 1)
        } else {
            String::new()
        };
        return Err(PartsError {
            kind: crate::diagnostic::ErrorKind::StripLongerThanSheet,
            strip: s.id.clone(),
            row: s.row,
            message: format!(
                "strip {} is {:.1} mm long, longer than the sheet's usable {uw:.1} x {uh:.1} mm{others}",
                s.id,
                Outline::of(s.length, fab).length
            ),
            hint: "use a larger sheet (--sheet or [sheet]) or a smaller design".into(),
        });
    }
    Ok(())
}

/// A strip as a solid in the deployed lattice: the 8 corners of a box
/// `length x width x thickness` along its rod, lying in its cell's facet
/// plane and lifted by its stacking layer so strips stack at the joints.
/// Corner `k` is at `(k & 1) * length`, `((k >> 1) & 1) * width`,
/// `(k >> 2) * thickness` in the strip's (along, across, normal) frame.
pub(crate) fn solid(lattice: &Lattice, strip: &Strip, fab: &Fabrication) -> [glam::DVec3; 8] {
    use glam::DVec3;
    let cell = &lattice.cells[strip.rod / 2];
    let [ul, ur, ll, _] = lattice.corners(cell);
    let rod = lattice.cell_rods(strip.rod / 2)[strip.rod % 2];
    let [start, _, end] = rod.hole_pos;
    let along = (end - start).normalize();
    let normal = (ur - ul).cross(ll - ul).try_normalize().unwrap_or(DVec3::Z);
    let across = normal.cross(along).normalize();
    let t = fab.material.thickness;
    let base = start - fab.end_margin * along - 0.5 * fab.material.width * across
        + lattice.layer(cell, strip.kind) as f64 * t * normal;
    std::array::from_fn(|k| {
        base + ((k & 1) as f64 * strip.length) * along
            + (((k >> 1) & 1) as f64 * fab.material.width) * across
            + ((k >> 2) as f64 * t) * normal
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_padded_to_the_lattice_size() {
        assert_eq!(strip_id(3, 5, RodType::A, 2, 2), "R03-C05-A");
        assert_eq!(strip_id(3, 5, RodType::B, 3, 2), "R003-C05-B");
        assert_eq!(digits(7), 2);
        assert_eq!(digits(123), 3);
    }
}
