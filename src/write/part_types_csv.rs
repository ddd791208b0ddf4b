//! parts-types.csv: one row per part type (interchangeable strips), with
//! how many there are, their geometry, what is engraved on them and which
//! strips they are.

use super::number::num;
use crate::parts::{Marking, Parts};

pub(crate) const HEADER: &str = "type,count,length_mm,pitch_1_mm,pitch_2_mm,turnable,engraved_id,engraved_type,engraved_dots,dot_code,strips";

/// `turnable`: the strip reads the same from either end (its arrow does not
/// matter). `engraved_*`: how many strips of the type carry their ID, the
/// type code, or the dot code (`dot_code` dots). `strips`: their IDs,
/// space-separated.
pub(crate) fn write(parts: &Parts) -> Vec<u8> {
    let mut out = String::from(HEADER);
    out.push('\n');
    for t in &parts.types {
        let of = |f: &dyn Fn(&Marking) -> bool| {
            t.strips
                .iter()
                .filter(|&&i| f(&parts.strips[i].marking))
                .count()
                .to_string()
        };
        let ids: Vec<&str> = t
            .strips
            .iter()
            .map(|&i| parts.strips[i].id.as_str())
            .collect();
        let fields = [
            t.code.clone(),
            t.strips.len().to_string(),
            num(t.length).to_string(),
            num(t.legs[0]).to_string(),
            num(t.legs[1]).to_string(),
            t.symmetric.to_string(),
            of(&|m| matches!(m, Marking::Id | Marking::Compact)),
            of(&|m| *m == Marking::Type),
            of(&|m| matches!(m, Marking::Dots(_))),
            t.dots.map_or(String::new(), |d| d.to_string()),
            ids.join(" "),
        ];
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    out.into_bytes()
}
