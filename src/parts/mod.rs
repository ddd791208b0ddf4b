//! Parts: one flat strip per rod (MATH.md 10.1) with its holes and
//! engraving, plus the eyelets, and the fabrication checks that name the
//! strip at fault. Strip geometry is in the strip's own frame, in mm: x runs
//! along the axis from the start tip (0) to the end tip (`length`), y across
//! it, pointing down when the strip lies with its start to the left.

pub mod clash;
pub mod test_piece;
pub(crate) mod types;

pub use test_piece::{TestPiece, test_piece};
pub use types::PartType;

use crate::fabrication::{Fabrication, LabelStyle};
use crate::font;
use crate::lattice::{Joint, Lattice, RodType, vertex_eyelets};
use glam::DVec2;

/// Eyelet flanges closer than this (mm) get a near-miss warning.
pub(crate) const FLANGE_CLEARANCE_WARNING: f64 = 1.0;
/// Hole centre to strip tip, in hole diameters, below which a warning says
/// the end may tear out (the usual edge-distance rule for holes).
pub(crate) const EDGE_DISTANCE: f64 = 1.5;
/// Smallest engraved text height (mm) before a label falls back to a shorter
/// form: nothing karigami prints or engraves is smaller (a maker must read it).
pub(crate) const MIN_LABEL_HEIGHT: f64 = 2.5;

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
                holes: [margin, margin + rod.legs[0], margin + rod.length()],
                engraving: Vec::new(),
                part_type: 0,
                marking: Marking::Arrow,
                label_height: 0.0,
            }
        })
        .collect();
    check(&strips, fab, &mut warnings)?;
    let (of, mut types) = types::group(&strips, fab.part_tolerance);
    let mut next_dots = 0;
    for (s, t) in strips.iter_mut().zip(of) {
        s.part_type = t;
        let ty = &mut types[t];
        let compact = format!("{}.{}{}", s.row, s.col, s.kind.letter());
        let type_text = if ty.symmetric {
            ty.code.clone()
        } else {
            format!("<{}", ty.code)
        };
        let forms: Vec<(String, Marking)> = match fab.label {
            LabelStyle::Id => vec![
                (format!("<{}", s.id), Marking::Id),
                (type_text, Marking::Type),
            ],
            LabelStyle::Compact => vec![
                (format!("<{compact}"), Marking::Compact),
                (type_text, Marking::Type),
            ],
            LabelStyle::None => vec![("<".into(), Marking::Arrow)],
        };
        let gap = label_gap(&s.holes, fab);
        let found = forms.into_iter().find_map(|(text, marking)| {
            let min = if marking == Marking::Arrow {
                0.5
            } else {
                MIN_LABEL_HEIGHT
            };
            engrave_text(&text, gap, min, fab).map(|(strokes, h)| (strokes, h, marking))
        });
        match found {
            Some((strokes, height, marking)) => {
                s.engraving = strokes;
                s.marking = marking;
                if marking != Marking::Arrow {
                    s.label_height = height;
                }
            }
            None => {
                let n = *ty.dots.get_or_insert_with(|| {
                    next_dots += 1;
                    next_dots
                });
                match dot_code(n, s, gap, fab) {
                    Some(strokes) => {
                        s.engraving = strokes;
                        s.marking = Marking::Dots(n);
                    }
                    None => warnings.push(Warning {
                        strip: Some(s.id.clone()),
                        message: format!(
                            "no room for any engraving: this strip (type {}) cannot be told apart once cut",
                            ty.code
                        ),
                    }),
                }
            }
        }
    }
    let count = |m: fn(&Marking) -> bool| strips.iter().filter(|s| m(&s.marking)).count();
    let (typed, dotted) = (
        count(|m| *m == Marking::Type),
        count(|m| matches!(m, Marking::Dots(_))),
    );
    if typed + dotted > 0 {
        warnings.push(Warning {
            strip: None,
            message: format!(
                "{typed} strips carry their part type's code and {dotted} its dot code instead of their ID (no room between the eyelets); strips of one type are interchangeable (see parts-types.csv)"
            ),
        });
    }
    let vertex_eyelets = vertex_eyelets(joints);
    Ok(Parts {
        strips,
        types,
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
            kind: crate::diagnostic::ErrorKind::LegShorterThanFlange,
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

/// The longest stretch between two eyelet flanges (with 0.5 mm to spare),
/// where a label stays readable after assembly.
fn label_gap(holes: &[f64; 3], fab: &Fabrication) -> (f64, f64) {
    let clear = fab.eyelet.flange / 2.0 + 0.5;
    let gaps = [
        (holes[0] + clear, holes[1] - clear),
        (holes[1] + clear, holes[2] - clear),
    ];
    if gaps[1].1 - gaps[1].0 > gaps[0].1 - gaps[0].0 {
        gaps[1]
    } else {
        gaps[0]
    }
}

/// `text` centred in the gap, as large as fits up to 0.4 of the strip width
/// (4 mm at most), and its height; None when it would be smaller than
/// `min_height`.
fn engrave_text(
    text: &str,
    (a, b): (f64, f64),
    min_height: f64,
    fab: &Fabrication,
) -> Option<(Vec<Vec<DVec2>>, f64)> {
    let room = b - a;
    let height = (room / font::width(text, 1.0)).min((0.4 * fab.material.width).min(4.0));
    if !(height >= min_height) {
        return None;
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
    Some((strokes, height))
}

/// Side of an engraved dot and the distance between dot centres (mm).
pub const DOT: f64 = 0.6;
pub(crate) const DOT_PITCH: f64 = 1.2;

/// Centres (along the strip, from the first dot) of an `n`-dot code: dots
/// in groups of five, with one extra pitch between groups so they count
/// like tally marks.
pub(crate) fn dot_offsets(n: usize) -> Vec<f64> {
    (0..n).map(|k| (k + k / 5) as f64 * DOT_PITCH).collect()
}

/// The fallback code: `n` dots, in the label gap when they fit there, else
/// along the strip beside the holes (under the eyelet flanges, readable
/// until the eyelets are set), starting at the start end and continuing on
/// the other edge when one is too short, with the arrow in the label gap when
/// it fits. None only if the strip is too short for the dots.
fn dot_code(
    n: usize,
    strip: &Strip,
    gap: (f64, f64),
    fab: &Fabrication,
) -> Option<Vec<Vec<DVec2>>> {
    let offsets = dot_offsets(n);
    let span = offsets.last().copied().unwrap_or(0.0) + DOT;
    let w = fab.material.width;
    let square = |x: f64, y: f64, s: f64| {
        let h = s / 2.0;
        vec![
            DVec2::new(x - h, y - h),
            DVec2::new(x + h, y - h),
            DVec2::new(x + h, y + h),
            DVec2::new(x - h, y + h),
            DVec2::new(x - h, y - h),
        ]
    };
    if span <= gap.1 - gap.0 {
        let x0 = (gap.0 + gap.1 - span) / 2.0 + DOT / 2.0;
        return Some(offsets.iter().map(|&o| square(x0 + o, 0.0, DOT)).collect());
    }
    // Beside the holes: halfway between a hole's edge and the strip's edge,
    // which is at least 1 mm wide (the wall check), on the straight part.
    let r = fab.eyelet.hole / 2.0;
    let band = w / 2.0 - r;
    let size = DOT.min(0.6 * band);
    let y = r + band / 2.0;
    let (start, end) = (w / 2.0 + size, strip.length - w / 2.0 - size);
    // Whole groups of five along one edge; what does not fit continues
    // along the other edge, again from the start end.
    let group = 6.0 * DOT_PITCH;
    let groups_per_band = ((end - start + DOT_PITCH) / group).floor() as usize;
    let fits_one = start + span <= end;
    if !fits_one && 2 * groups_per_band * 5 < n {
        return None;
    }
    let mut strokes: Vec<Vec<DVec2>> = offsets
        .iter()
        .enumerate()
        .map(|(k, &o)| {
            let g = k / 5;
            if fits_one || g < groups_per_band {
                square(start + o, y, size)
            } else {
                square(start + o - (groups_per_band as f64) * group, -y, size)
            }
        })
        .collect();
    if let Some((arrow, _)) = engrave_text("<", gap, 0.5, fab) {
        strokes.extend(arrow);
    }
    Some(strokes)
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

    #[test]
    fn engraving_stays_between_the_flanges_and_inside_the_strip() {
        let fab = Fabrication::default();
        let holes = [5.0, 45.0, 75.0];
        let (strokes, _) = engrave_text("<R03-C05-A", label_gap(&holes, &fab), 2.0, &fab).unwrap();
        let clear = fab.eyelet.flange / 2.0;
        for p in strokes.iter().flatten() {
            assert!(p.x > holes[0] + clear && p.x < holes[1] - clear, "{p}");
            assert!(p.y.abs() < fab.material.width / 2.0, "{p}");
        }
    }

    #[test]
    fn short_gaps_refuse_text_but_always_take_the_dot_code() {
        let fab = Fabrication::default();
        let holes = [5.0, 13.0, 21.0];
        let gap = label_gap(&holes, &fab);
        assert!(engrave_text("<R03-C05-A", gap, 2.0, &fab).is_none());
        assert!(engrave_text("<AB", gap, 2.0, &fab).is_none());
        let strip = Strip {
            id: "x".into(),
            rod: 0,
            row: 0,
            col: 0,
            kind: RodType::A,
            legs: [8.0, 8.0],
            length: 26.0,
            holes,
            engraving: vec![],
            part_type: 0,
            marking: Marking::Arrow,
            label_height: 0.0,
        };
        let dots = dot_code(7, &strip, gap, &fab).unwrap();
        // Seven closed squares, and the arrow, which still fits the gap.
        assert_eq!(dots.iter().filter(|s| s.len() == 5).count(), 7);
        assert_eq!(dots.len(), 8);
        let r = fab.eyelet.hole / 2.0;
        for p in dots.iter().flatten() {
            for h in holes {
                assert!(p.distance(DVec2::new(h, 0.0)) > r + 0.2, "{p} on a hole");
            }
            assert!(p.y.abs() < fab.material.width / 2.0 - 0.2, "{p}");
            assert!(p.x > 0.0 && p.x < 26.0, "{p}");
        }
        // Many dots on a short strip: both edges, never on a hole.
        let many = dot_code(17, &strip, gap, &fab).unwrap();
        let squares: Vec<&Vec<DVec2>> = many.iter().filter(|s| s.len() == 5).collect();
        assert_eq!(squares.len(), 17);
        assert!(squares.iter().any(|s| s[0].y > 0.0) && squares.iter().any(|s| s[0].y < 0.0));
        for p in squares.iter().copied().flatten() {
            for h in holes {
                assert!(p.distance(DVec2::new(h, 0.0)) > r + 0.2, "{p} on a hole");
            }
            assert!(
                p.x > 0.0 && p.x < 26.0 && p.y.abs() < fab.material.width / 2.0,
                "{p}"
            );
        }
        for (i, a) in squares.iter().enumerate() {
            for b in &squares[i + 1..] {
                assert!(a[0].distance(b[0]) > DOT, "overlapping dots");
            }
        }
        let steps: Vec<f64> = dot_offsets(6).iter().map(|o| o / DOT_PITCH).collect();
        for (s, want) in steps.iter().zip([0.0, 1.0, 2.0, 3.0, 4.0, 6.0]) {
            assert!((s - want).abs() < 1e-12, "{steps:?}");
        }
    }
}
