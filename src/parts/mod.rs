//! Parts: one flat strip per rod (MATH.md 10.1) with its holes and
//! engraving, plus the eyelets, and the fabrication checks that name the
//! strip at fault. Strip geometry is in the strip's own frame, in mm: x runs
//! along the axis from the start tip (0) to the end tip (`length`), y across
//! it, pointing down when the strip lies with its start to the left.

pub mod clash;
pub mod font;

use crate::fabrication::{Fabrication, LabelStyle};
use crate::lattice::{Lattice, RodType, joints};
use glam::DVec2;

/// Eyelet flanges closer than this (mm) get a near-miss warning.
pub const FLANGE_CLEARANCE_WARNING: f64 = 1.0;
/// Hole centre to strip tip, in hole diameters, below which a warning says
/// the end may tear out (the usual edge-distance rule for holes).
pub const EDGE_DISTANCE: f64 = 1.5;
/// Smallest engraved text height (mm) before a label falls back to a shorter form.
pub const MIN_LABEL_HEIGHT: f64 = 2.0;

#[derive(Clone, Debug, PartialEq)]
pub struct Strip {
    /// Human-readable ID, e.g. `R03-C05-A` (cell row, column, rod letter).
    pub id: String,
    /// The rod's id in lattice.json.
    pub rod: usize,
    pub row: u32,
    pub col: u32,
    pub kind: RodType,
    /// Hole-to-hole distances: start vertex to pivot, pivot to end vertex.
    pub legs: [f64; 2],
    /// Nominal tip-to-tip length.
    pub length: f64,
    /// Hole centres along the axis, from the start tip.
    pub holes: [f64; 3],
    /// Engraved strokes (ID and orientation arrow), in the strip frame.
    pub engraving: Vec<Vec<DVec2>>,
}

/// The cut outline of a strip: nominal, or grown by the kerf when compensated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outline {
    pub length: f64,
    pub width: f64,
    /// Hole diameter as cut.
    pub hole: f64,
    /// How far the outline extends beyond the nominal tip (kerf / 2 or 0).
    pub grow: f64,
}

impl Outline {
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
pub struct Warning {
    pub strip: Option<String>,
    pub message: String,
}

/// A fabrication check that fails for at least one strip.
#[derive(Clone, Debug, PartialEq)]
pub struct PartsError {
    pub class: &'static str,
    /// The first strip at fault and its cell row (for pointing at the recipe).
    pub strip: String,
    pub row: u32,
    pub message: String,
    pub hint: String,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Parts {
    /// In lattice.json's rod order.
    pub strips: Vec<Strip>,
    /// Vertex pivots joining two or more rod ends.
    pub vertex_eyelets: usize,
    /// One per cell.
    pub pivot_eyelets: usize,
    pub warnings: Vec<Warning>,
}

impl Parts {
    pub fn eyelets(&self) -> usize {
        self.vertex_eyelets + self.pivot_eyelets
    }
}

/// Zero-padded index width for IDs: at least 2 digits, more for big lattices.
fn digits(max: u32) -> usize {
    max.to_string().len().max(2)
}

pub fn strip_id(row: u32, col: u32, kind: RodType, row_digits: usize, col_digits: usize) -> String {
    format!("R{row:0row_digits$}-C{col:0col_digits$}-{}", kind.letter())
}

/// The strips of a lattice, checked against the fabrication settings.
pub fn parts(lattice: &Lattice, fab: &Fabrication) -> Result<Parts, PartsError> {
    let max_row = lattice.cells.iter().map(|c| c.row).max().unwrap_or(0);
    let max_col = lattice.cells.iter().map(|c| c.col).max().unwrap_or(0);
    let (rd, cd) = (digits(max_row), digits(max_col));
    let margin = fab.end_margin;
    let mut warnings = Vec::new();
    let strips: Vec<Strip> = lattice
        .rods()
        .map(|rod| {
            let cell = &lattice.cells[rod.cell];
            let id = strip_id(cell.row, cell.col, rod.kind, rd, cd);
            let length = rod.length() + 2.0 * margin;
            let holes = [margin, margin + rod.legs[0], margin + rod.length()];
            let compact = format!("{}.{}{}", cell.row, cell.col, rod.kind.letter());
            let (engraving, warning) = engrave(&id, &compact, &holes, fab);
            if let Some(message) = warning {
                warnings.push(Warning {
                    strip: Some(id.clone()),
                    message,
                });
            }
            Strip {
                id,
                rod: rod.id,
                row: cell.row,
                col: cell.col,
                kind: rod.kind,
                legs: rod.legs,
                length,
                holes,
                engraving,
            }
        })
        .collect();
    check(&strips, fab, &mut warnings)?;
    let vertex_eyelets = joints(lattice).iter().filter(|j| j.needs_eyelet()).count();
    Ok(Parts {
        strips,
        vertex_eyelets,
        pivot_eyelets: lattice.cells.len(),
        warnings,
    })
}

/// Per-strip checks: eyelet flanges that overlap, strips longer than the sheet.
fn check(
    strips: &[Strip],
    fab: &Fabrication,
    warnings: &mut Vec<Warning>,
) -> Result<(), PartsError> {
    let flange = fab.eyelet.flange;
    let short: Vec<(&Strip, f64)> = strips
        .iter()
        .filter_map(|s| {
            let leg = s.legs[0].min(s.legs[1]);
            (leg < flange).then_some((s, leg))
        })
        .collect();
    if let Some(&(s, leg)) = short.first() {
        let others = if short.len() > 1 {
            format!(" ({} more strips too)", short.len() - 1)
        } else {
            String::new()
        };
        return Err(PartsError {
            class: "LegShorterThanFlange",
            strip: s.id.clone(),
            row: s.row,
            message: format!(
                "strip {}: two of its holes are {leg:.2} mm apart, less than the {flange} mm eyelet flange, so the eyelets would overlap{others}",
                s.id
            ),
            hint: "make this row's cells larger (seed spacing, legs or direction), or use a smaller eyelet".into(),
        });
    }
    for s in strips {
        let leg = s.legs[0].min(s.legs[1]);
        if leg - flange < FLANGE_CLEARANCE_WARNING {
            warnings.push(Warning {
                strip: Some(s.id.clone()),
                message: format!(
                    "eyelet flanges only {:.2} mm apart (holes {leg:.2} mm apart)",
                    leg - flange
                ),
            });
        }
    }
    let d = fab.eyelet.hole;
    if fab.end_margin < EDGE_DISTANCE * d {
        warnings.push(Warning {
            strip: None,
            message: format!(
                "end holes are {} mm from the tips, less than {EDGE_DISTANCE} hole diameters ({:.1} mm): strip ends may tear under load (raise strip.end_margin)",
                fab.end_margin,
                EDGE_DISTANCE * d
            ),
        });
    }
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
            class: "StripLongerThanSheet",
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

/// The engraving of a strip: an arrow pointing at the start end (the vertex
/// of the earlier row) followed by the ID, in the longest stretch between two
/// eyelet flanges, shrunk or shortened until it fits.
fn engrave(
    id: &str,
    compact: &str,
    holes: &[f64; 3],
    fab: &Fabrication,
) -> (Vec<Vec<DVec2>>, Option<String>) {
    let w = fab.material.width;
    let clear = fab.eyelet.flange / 2.0 + 0.5;
    let gaps = [
        (holes[0] + clear, holes[1] - clear),
        (holes[1] + clear, holes[2] - clear),
    ];
    let (a, b) = if gaps[1].1 - gaps[1].0 > gaps[0].1 - gaps[0].0 {
        gaps[1]
    } else {
        gaps[0]
    };
    let room = b - a;
    let max_height = (0.4 * w).min(4.0);
    let mut forms: Vec<String> = match fab.label {
        LabelStyle::Id => vec![format!("<{id}"), format!("<{compact}")],
        LabelStyle::Compact => vec![format!("<{compact}")],
        LabelStyle::None => vec![],
    };
    forms.push("<".into());
    for (k, text) in forms.iter().enumerate() {
        let arrow_only = text == "<";
        let height = (room / font::width(text, 1.0)).min(max_height);
        if height < if arrow_only { 0.5 } else { MIN_LABEL_HEIGHT } {
            continue;
        }
        let x0 = a + (room - font::width(text, height)) / 2.0;
        let strokes = font::text(text, height)
            .into_iter()
            .map(|s| {
                s.into_iter()
                    .map(|p| DVec2::new(x0 + p.x, height / 2.0 - p.y))
                    .collect()
            })
            .collect();
        let warning = if k == 0 {
            None
        } else if arrow_only {
            Some("no room for a label: only the orientation arrow is engraved".to_string())
        } else {
            Some(format!(
                "label shortened to \"{}\": the full ID does not fit between the eyelets",
                &text[1..]
            ))
        };
        return (strokes, warning);
    }
    (
        Vec::new(),
        Some("no room for any engraving between the eyelets".into()),
    )
}

/// A strip as a solid in the deployed lattice: the 8 corners of a box
/// `length x width x thickness` along its rod, lying in its cell's facet
/// plane and lifted by its stacking layer so strips stack at the joints.
/// Corner `k` is at `(k & 1) * length`, `((k >> 1) & 1) * width`,
/// `(k >> 2) * thickness` in the strip's (along, across, normal) frame.
pub fn solid(lattice: &Lattice, strip: &Strip, fab: &Fabrication) -> [glam::DVec3; 8] {
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

    #[test]
    fn engraving_stays_between_the_flanges_and_inside_the_strip() {
        let fab = Fabrication::default();
        let holes = [5.0, 45.0, 75.0];
        let (strokes, warning) = engrave("R03-C05-A", "3.5A", &holes, &fab);
        assert!(warning.is_none());
        let clear = fab.eyelet.flange / 2.0;
        for p in strokes.iter().flatten() {
            assert!(p.x > holes[0] + clear && p.x < holes[1] - clear, "{p}");
            assert!(p.y.abs() < fab.material.width / 2.0, "{p}");
        }
    }

    #[test]
    fn short_legs_fall_back_to_compact_labels_then_the_arrow() {
        let fab = Fabrication::default();
        let (_, w) = engrave("R03-C05-A", "3.5A", &[5.0, 25.0, 45.0], &fab);
        assert!(w.unwrap().contains("shortened to \"3.5A\""));
        let (strokes, w) = engrave("R03-C05-A", "3.5A", &[5.0, 13.0, 21.0], &fab);
        assert!(w.unwrap().contains("only the orientation arrow"));
        assert!(!strokes.is_empty());
    }
}
