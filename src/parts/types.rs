//! Part types: strips that are the same part, grouped so a maker can cut,
//! sort and pick them by a short code instead of a unique ID.
//!
//! Two strips are the same part when their hole pitches (start to pivot,
//! pivot to end) and their tip-to-tip lengths agree within the tolerance,
//! compared in each strip's own start-to-end order. The holes and outline are
//! all that is cut, so such strips are interchangeable; the engraved arrow
//! points at the start end, and comparing in start-to-end order keeps it
//! pointing at the same end of every strip of a type. A strip and its
//! reverse are therefore the same part only when the arrow does not matter:
//! when its two pitches agree within the tolerance (a symmetric strip reads
//! the same from either end), which this comparison already accepts.
//!
//! Grouping is complete-linkage: every two strips of a type agree within the
//! tolerance (no chains of near misses), so "same type" always means
//! "interchangeable".

use super::Strip;

/// One part type: strips that are interchangeable.
#[derive(Clone, Debug, PartialEq)]
pub struct PartType {
    /// A, B, ..., Z, AA, AB, ... (no I, O or Q): in order of each type's first strip.
    pub code: String,
    /// Indices into `Parts::strips`, in strip order.
    pub strips: Vec<usize>,
    /// The pitches and length of the first strip.
    pub(crate) legs: [f64; 2],
    pub(crate) length: f64,
    /// Whether the two pitches agree within the tolerance (the strip can be
    /// turned end for end, so its arrow does not matter).
    pub symmetric: bool,
    /// The dot count engraved on strips of this type that have no room for
    /// text (the fallback code), when any has.
    pub dots: Option<usize>,
}

/// The letters of type codes: the alphabet without I, O and Q, which the
/// engraving's stroke font makes hard to tell from 1, 0, D and O at 2.5 mm.
const CODE_LETTERS: &[u8; 23] = b"ABCDEFGHJKLMNPRSTUVWXYZ";

/// Spreadsheet-style code of the `index`-th type (0-based) over
/// `CODE_LETTERS`: A..Z, AA..AZ, BA.., with no I, O or Q anywhere.
pub(crate) fn code(index: usize) -> String {
    let base = CODE_LETTERS.len();
    let mut n = index + 1;
    let mut out = Vec::new();
    while n > 0 {
        n -= 1;
        out.push(CODE_LETTERS[n % base]);
        n /= base;
    }
    out.reverse();
    String::from_utf8(out).expect("ASCII letters")
}

fn key(s: &Strip) -> [f64; 3] {
    [s.legs[0], s.legs[1], s.length]
}

/// Group strips into types; returns each strip's type index and the types.
pub(crate) fn group(strips: &[Strip], tolerance: f64) -> (Vec<usize>, Vec<PartType>) {
    // Sorted by the first pitch, a strip can only join a type whose smallest
    // first pitch is within the tolerance: older types are closed for good.
    let mut order: Vec<usize> = (0..strips.len()).collect();
    order.sort_by(|&a, &b| {
        let (ka, kb) = (key(&strips[a]), key(&strips[b]));
        ka[0]
            .total_cmp(&kb[0])
            .then(ka[1].total_cmp(&kb[1]))
            .then(a.cmp(&b))
    });
    // Per open group: members and the min/max of each key component.
    struct Open {
        members: Vec<usize>,
        lo: [f64; 3],
        hi: [f64; 3],
    }
    let mut groups: Vec<Open> = Vec::new();
    let mut first_open = 0;
    for &i in &order {
        let k = key(&strips[i]);
        while first_open < groups.len() && groups[first_open].lo[0] < k[0] - tolerance {
            first_open += 1;
        }
        let fits = |g: &Open| (0..3).all(|c| g.hi[c].max(k[c]) - g.lo[c].min(k[c]) <= tolerance);
        match groups[first_open..].iter().position(fits) {
            Some(p) => {
                let g = &mut groups[first_open + p];
                g.members.push(i);
                for (c, &v) in k.iter().enumerate() {
                    g.lo[c] = g.lo[c].min(v);
                    g.hi[c] = g.hi[c].max(v);
                }
            }
            None => groups.push(Open {
                members: vec![i],
                lo: k,
                hi: k,
            }),
        }
    }
    // Codes in order of each type's first strip (assembly order).
    let mut members: Vec<Vec<usize>> = groups
        .into_iter()
        .map(|mut g| {
            g.members.sort_unstable();
            g.members
        })
        .collect();
    members.sort_by_key(|m| m[0]);
    let mut of = vec![0; strips.len()];
    let types = members
        .into_iter()
        .enumerate()
        .map(|(t, m)| {
            for &i in &m {
                of[i] = t;
            }
            let s = &strips[m[0]];
            PartType {
                code: code(t),
                legs: s.legs,
                length: s.length,
                symmetric: m
                    .iter()
                    .all(|&i| (strips[i].legs[0] - strips[i].legs[1]).abs() <= tolerance),
                strips: m,
                dots: None,
            }
        })
        .collect();
    (of, types)
}

/// One line for reports: the number of types with their counts, and how
/// many strips carry their ID, their type's code or its dot code.
pub(crate) fn summary(parts: &super::Parts) -> String {
    use super::Marking;
    let counts: Vec<String> = parts
        .types
        .iter()
        .take(12)
        .map(|t| format!("{} x{}", t.code, t.strips.len()))
        .collect();
    let more = if parts.types.len() > 12 { ", ..." } else { "" };
    let n = |f: &dyn Fn(&Marking) -> bool| parts.strips.iter().filter(|s| f(&s.marking)).count();
    format!(
        "part types: {} for {} strips ({}{more}); engraved: {} ID, {} type code, {} dot code, {} arrow only",
        parts.types.len(),
        parts.strips.len(),
        counts.join(", "),
        n(&|m| matches!(m, Marking::Id | Marking::Compact)),
        n(&|m| *m == Marking::Type),
        n(&|m| matches!(m, Marking::Dots(_))),
        n(&|m| *m == Marking::Arrow),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::RodType;

    fn strip(l0: f64, l1: f64) -> Strip {
        Strip {
            id: String::new(),
            rod: 0,
            row: 0,
            col: 0,
            kind: RodType::A,
            legs: [l0, l1],
            length: l0 + l1 + 10.0,
            holes: [5.0, 5.0 + l0, 5.0 + l0 + l1],
            engraving: vec![],
            part_type: 0,
            marking: super::super::Marking::Arrow,
            label_height: 0.0,
        }
    }

    #[test]
    fn codes_run_like_spreadsheet_columns() {
        assert_eq!(code(0), "A");
        assert_eq!(code(7), "H");
        assert_eq!(code(8), "J");
        assert_eq!(code(22), "Z");
        assert_eq!(code(23), "AA");
        assert_eq!(code(24), "AB");
        assert_eq!(code(23 + 23 * 23), "AAA");
        // No I, O or Q in any code, and every code distinct.
        let codes: Vec<String> = (0..2000).map(code).collect();
        assert!(codes.iter().all(|c| !c.contains(['I', 'O', 'Q'])));
        let set: std::collections::BTreeSet<&String> = codes.iter().collect();
        assert_eq!(set.len(), codes.len());
    }

    #[test]
    fn types_are_complete_linkage_and_respect_direction() {
        // A chain of near misses: 40.00, 40.04, 40.08 -- the ends differ by
        // more than the tolerance, so they cannot all be one type.
        let strips = vec![
            strip(40.0, 30.0),
            strip(40.04, 30.0),
            strip(40.08, 30.0),
            strip(30.0, 40.0), // the reverse of the first: a different part
            strip(35.0, 35.02),
            strip(35.02, 35.0), // symmetric: its reverse is itself
        ];
        let (of, types) = group(&strips, 0.05);
        assert_eq!(of[0], of[1]);
        assert_ne!(of[1], of[2]);
        assert_ne!(of[0], of[3]);
        assert_eq!(of[4], of[5]);
        assert!(types[of[4]].symmetric);
        assert!(!types[of[0]].symmetric);
        assert_eq!(types[0].code, "A");
        assert_eq!(types[0].strips, vec![0, 1]);
        for t in &types {
            for &a in &t.strips {
                for &b in &t.strips {
                    for c in 0..3 {
                        assert!((key(&strips[a])[c] - key(&strips[b])[c]).abs() <= 0.05);
                    }
                }
            }
        }
    }
}
