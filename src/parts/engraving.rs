//! What is engraved on each strip: its ID (or compact ID) between the
//! eyelet flanges, else its part type's code, else a dot code, with the
//! orientation arrow.

use super::{Marking, Strip, Warning, types};
use crate::fabrication::{Fabrication, LabelStyle};
use crate::font;
use glam::DVec2;

use crate::fabrication::MIN_LABEL_HEIGHT;

/// Group the strips into part types and engrave each with the most specific
/// marking that fits; a warning says how many fell back to a code.
pub(super) fn engrave(
    strips: &mut [Strip],
    fab: &Fabrication,
    warnings: &mut Vec<Warning>,
) -> Vec<types::PartType> {
    let (of, mut types) = types::group(strips, fab.part_tolerance);
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
                "{typed} {} part type's code and {dotted} its dot code instead of {whose} ID (no room between the eyelets); strips of one type are interchangeable (see parts-types.csv)",
                if typed == 1 { "strip carries its" } else { "strips carry their" },
                whose = if typed == 1 { "its" } else { "their" }
            ),
        });
    }
    types
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::RodType;

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
