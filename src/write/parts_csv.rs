//! parts.csv: one row per strip in lattice.json's rod order, with where to
//! find it on the sheets.

use super::number::num;
use crate::layout::Layout;
use crate::parts::Strip;

pub(crate) const HEADER: &str = "id,rod,row,col,type,length_mm,hole_1_mm,hole_2_mm,hole_3_mm,pitch_1_mm,pitch_2_mm,sheet,x_mm,y_mm,rotation_deg,part_type";

/// `x_mm`, `y_mm`: the top-left corner of the strip's bounding box on its
/// sheet; rotation 0 runs along x with the start end on the left, 90 runs
/// down the sheet with the start end at the top. Holes are measured from the
/// start tip.
/// `part_type`: the strip's part type (parts-types.csv).
pub(crate) fn write(strips: &[Strip], layout: &Layout) -> Vec<u8> {
    let code = |i: usize| crate::parts::types::code(i);
    let mut place = vec![None; strips.len()];
    for (s, sheet) in layout.sheets.iter().enumerate() {
        for p in &sheet.placements {
            place[p.part] = Some((s + 1, *p));
        }
    }
    let mut out = String::from(HEADER);
    out.push('\n');
    for (strip, place) in strips.iter().zip(place) {
        let (sheet, p) = place.expect("every strip is placed");
        let fields = [
            strip.id.clone(),
            strip.rod.to_string(),
            strip.row.to_string(),
            strip.col.to_string(),
            strip.kind.letter().to_string(),
            num(strip.length).to_string(),
            num(strip.holes[0]).to_string(),
            num(strip.holes[1]).to_string(),
            num(strip.holes[2]).to_string(),
            num(strip.legs[0]).to_string(),
            num(strip.legs[1]).to_string(),
            sheet.to_string(),
            num(p.x).to_string(),
            num(p.y).to_string(),
            if p.rotated { "90" } else { "0" }.to_string(),
            code(strip.part_type),
        ];
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    out.into_bytes()
}
