//! The bill of materials: strips by type with what is engraved on them,
//! eyelets by grip, the test piece, and a 1:1 ruler to check the print.

use super::{mm, spares};
use crate::drawing::flow::{BLACK, BODY, GREY, MARGIN, PageFlow, SMALL, text_item};
use crate::drawing::{Align, Font, Ink, Item, Shape};
use crate::pipeline::Build;
use crate::words::plural;
use glam::DVec2;

/// What is engraved on the strips of a type, e.g. "ID 12, code 3, 4 dots 2".
pub(super) fn engraved(b: &Build, t: &crate::parts::PartType) -> String {
    use crate::parts::Marking;
    let mut counts: Vec<(String, usize)> = Vec::new();
    for &s in &t.strips {
        let what = match b.parts.strips[s].marking {
            Marking::Id | Marking::Compact => "ID".to_string(),
            Marking::Type => "code".to_string(),
            Marking::Dots(n) => plural(n, "dot"),
            Marking::Arrow => "arrow only".to_string(),
        };
        match counts.iter_mut().find(|c| c.0 == what) {
            Some(c) => c.1 += 1,
            None => counts.push((what, 1)),
        }
    }
    if counts.len() == 1 {
        return counts.remove(0).0;
    }
    counts
        .iter()
        .map(|(what, n)| format!("{what} {n}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Eyelets by grip (the thickness of the stack they hold): (strips in the
/// stack, scissor pivots, vertex joints).
pub fn eyelets_by_grip(b: &Build) -> Vec<(usize, usize, usize)> {
    let mut by: std::collections::BTreeMap<usize, (usize, usize)> = Default::default();
    by.entry(2).or_default().0 += b.parts.pivot_eyelets;
    for j in b.joints.iter().filter(|j| j.needs_eyelet()) {
        by.entry(j.ends.len()).or_default().1 += 1;
    }
    by.into_iter()
        .filter(|(_, (p, v))| p + v > 0)
        .map(|(k, (p, v))| (k, p, v))
        .collect()
}

pub(super) fn materials(w: &mut PageFlow, b: &Build) {
    let fab = &b.design.fabrication;
    w.heading("Bill of materials");
    w.running_head = Some("Bill of materials".into());
    w.paragraph(
        &format!(
            "{} strips of {} part types. Strips of one type are the same part (length and hole pitches \
             within {} mm): any of them fits wherever the guide asks for that type.",
            b.parts.strips.len(),
            b.parts.types.len(),
            fab.part_tolerance
        ),
        SMALL,
        GREY,
    );
    types_table(w, b);
    strips_apart(w, b);
    w.running_head = None;
    eyelets_table(w, b);
    ruler(w);
}

/// The part types, in one table or two side by side.
fn types_table(w: &mut PageFlow, b: &Build) {
    w.y += 1.0;
    // Two tables side by side when there are many types.
    let halves = if b.parts.types.len() > 16 { 2 } else { 1 };
    let half = w.width() / halves as f64;
    // Pitches may read "123.4+123.4 both": room for it before Engraved.
    let columns = [0.0, 9.0, 27.0, 41.0, 67.0];
    let header = ["Type", "Strips", "Length", "Pitches", "Engraved"].map(String::from);
    let mut cells: Vec<String> = Vec::new();
    let mut header_cells = Vec::new();
    let mut header_columns = Vec::new();
    for h in 0..halves {
        header_columns.extend(columns.map(|x| x + h as f64 * half));
        header_cells.extend(header.clone());
    }
    w.row(&header_columns, &header_cells, Font::Bold, BLACK);
    w.text(
        "Lengths tip to tip and hole pitches (start to pivot + pivot to end) in mm; \"both\": either end first.",
        SMALL,
        Font::Regular,
        GREY,
    );
    w.rule();
    for chunk in b.parts.types.chunks(halves) {
        let mut row_columns = Vec::new();
        cells.clear();
        for (h, ty) in chunk.iter().enumerate() {
            row_columns.extend(columns.map(|x| x + h as f64 * half));
            let strips = if ty.strips.len() == 1 {
                b.parts.strips[ty.strips[0]].id.clone()
            } else {
                ty.strips.len().to_string()
            };
            cells.extend([
                ty.code.clone(),
                strips,
                format!("{:.1}", ty.length),
                format!(
                    "{:.1}+{:.1}{}",
                    ty.legs[0],
                    ty.legs[1],
                    if ty.symmetric { " both" } else { "" }
                ),
                engraved(b, ty),
            ]);
        }
        w.row(&row_columns, &cells, Font::Regular, BLACK);
    }
}

/// How to tell strips apart, and the strips of each type.
fn strips_apart(w: &mut PageFlow, b: &Build) {
    w.y += 2.0;
    let dots: Vec<String> = b
        .parts
        .types
        .iter()
        .filter_map(|t| t.dots.map(|n| format!("{n} = {}", t.code)))
        .collect();
    let mut how = String::from(
        "How to tell strips apart: a strip carries its ID (R03-C05-A: row 3, column 5, rod A) where it fits, \
         else its type code; the arrow < points to its upper end, the one joined to the row above. ",
    );
    if b.design.fabrication.label == crate::fabrication::LabelStyle::Compact {
        how.push_str(
            "This job engraves IDs in compact form: 3.5A is row 3, column 5, rod A (R03-C05-A). ",
        );
    }
    if !dots.is_empty() {
        how.push_str(&format!(
            "Strips too short for text carry a dot code: a row of engraved dots, counted to read the type ({}). ",
            dots.join(", ")
        ));
    }
    how.push_str(
        "Each step says which sheet and lane its strips were cut on, and the sheet maps show where that is. \
         parts.csv lists every strip with its type, sheet and position on the sheet; parts-types.csv lists \
         the types.",
    );
    w.paragraph(&how, SMALL, GREY);
    if b.parts.types.iter().any(|t| t.strips.len() > 1) {
        w.text("Strips of each type", 4.0, Font::Bold, BLACK);
        let lists: Vec<String> = b
            .parts
            .types
            .iter()
            .filter(|t| t.strips.len() > 1)
            .map(|ty| {
                let ids: Vec<&str> = ty
                    .strips
                    .iter()
                    .map(|&s| b.parts.strips[s].id.as_str())
                    .collect();
                format!("{}: {}.", ty.code, ids.join(" "))
            })
            .collect();
        w.paragraph(&lists.join("  "), SMALL, BLACK);
    }
}

/// Eyelets by grip, with how many to buy.
fn eyelets_table(w: &mut PageFlow, b: &Build) {
    let fab = &b.design.fabrication;
    let t = fab.material.thickness;
    w.y += 3.0;
    w.need(50.0);
    w.text("Eyelets, by grip", 4.5, Font::Bold, BLACK);
    w.paragraph(
        &format!(
            "The grip is the thickness of the stack an eyelet holds: strips x {t} mm. Use eyelets whose barrel \
             is a little longer than the grip. Every eyelet is a pivot: set it loose enough that the strips \
             still turn (roll the flange over, do not flatten the stack)."
        ),
        SMALL,
        GREY,
    );
    let columns = [0.0, 30.0, 55.0, 110.0];
    let header = ["Grip", "Eyelets", "Where", "Buy (with spares)"].map(String::from);
    w.row(&columns, &header, Font::Bold, BLACK);
    w.rule();
    let mut total = 0;
    let mut buy = 0;
    for (k, pivots, joints) in eyelets_by_grip(b) {
        let n = pivots + joints;
        let mut at = Vec::new();
        if pivots > 0 {
            at.push(format!("{pivots} scissor pivots"));
        }
        if joints > 0 {
            at.push(format!("{joints} joints"));
        }
        w.row(
            &columns,
            &[
                format!("{} ({k} strips)", mm(k as f64 * t)),
                n.to_string(),
                at.join(", "),
                (n + spares(n)).to_string(),
            ],
            Font::Regular,
            BLACK,
        );
        total += n;
        buy += n + spares(n);
    }
    w.text(
        &format!(
            "{total} {} eyelets in all; buy {buy} with spares",
            fab.eyelet.name
        ),
        BODY,
        Font::Bold,
        BLACK,
    );
}

/// Before step 1: the test piece on sheet 1 checks scale, kerf and eyelet fit.
pub(super) fn test_piece_block(w: &mut PageFlow, b: &Build) {
    let fab = &b.design.fabrication;
    w.need(40.0);
    w.y += 2.0;
    w.text(
        "Before step 1: cut and test the test piece",
        5.0,
        Font::Bold,
        BLACK,
    );
    let text = match crate::parts::test_piece(fab) {
        Some(piece) => {
            let diameters: Vec<String> = piece.holes.iter().map(|h| format!("{:.1}", h.1)).collect();
            let kerf = if fab.plotter.is_some() && fab.kerf == 0.0 {
                "A blade removes no material, so it must measure 100.0 mm tip to tip: if it does not, the SVG \
                 was scaled on import (import it at its own size, in mm)."
                    .to_string()
            } else if fab.compensate_kerf {
                "It is cut with kerf compensation on, so it must measure 100.0 mm tip to tip: if it does not, \
                 your kerf setting is off by the difference."
                    .to_string()
            } else {
                format!(
                    "It is cut without kerf compensation, so it measures 100 mm minus your laser's kerf: \
                     100.0 - measured = kerf (the recipe assumes {} mm).",
                    fab.kerf
                )
            };
            format!(
                "Cut sheet 1's test piece first (the 100 mm strip with the stepped holes) and check it before \
                 cutting the rest. Scale: measure it tip to tip. {kerf} Eyelet fit: set an eyelet in each hole \
                 ({} mm, labelled on the strip); the right hole is the smallest one the eyelet's barrel enters \
                 without forcing and still turns in. If that is not the {:.1} mm hole, set [eyelet] hole to its \
                 diameter in the recipe (docs/recipe.md) and build again.",
                diameters.join(", "),
                fab.eyelet.hole
            )
        }
        None => "The test piece is left out (--no-test-piece, or it does not fit the sheet): cut one strip first, \
                 measure it against the bill of materials and try an eyelet in its holes before cutting the rest."
            .to_string(),
    };
    w.paragraph(&text, SMALL, BLACK);
}
/// A 1:1 ruler: print at 100 % and it must measure what it says.
pub(super) fn ruler(w: &mut PageFlow) {
    let length = 150.0f64.min(w.width() - 10.0).floor();
    w.need(22.0);
    w.y += 3.0;
    w.text(
        &format!("Length gauge (1:1): this ruler must measure {length:.0} mm on paper"),
        BODY,
        Font::Bold,
        BLACK,
    );
    let y = w.y + 8.0;
    let x0 = MARGIN;
    let mut items = vec![Item::art(
        Ink::line(BLACK, 0.25),
        Shape::polyline(&[DVec2::new(x0, y), DVec2::new(x0 + length, y)], false),
    )];
    for k in 0..=(length as usize) {
        let tick = if k % 10 == 0 {
            5.0
        } else if k % 5 == 0 {
            3.5
        } else {
            2.0
        };
        let x = x0 + k as f64;
        items.push(Item::art(
            Ink::line(BLACK, 0.15),
            Shape::polyline(&[DVec2::new(x, y), DVec2::new(x, y - tick)], false),
        ));
        if k % 10 == 0 {
            items.push(text_item(
                DVec2::new(x, y + 3.5),
                2.5,
                &k.to_string(),
                Font::Regular,
                Align::Center,
                BLACK,
            ));
        }
    }
    w.push(items);
    w.y = y + 8.0;
}
