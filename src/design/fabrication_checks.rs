//! Checks of the fabrication settings that concern every strip alike: the
//! eyelet against the strip, the margins against the sheet, the kerf
//! compensation against the holes. Each points at the setting to change
//! (or names the flag that set it).

use super::fabrication_bounds::{FabricationSpans, MAX_SHEET, MIN_WALL, Overrides};
use super::raw::RawDesign;
use crate::diagnostic::{Diagnostic, ErrorKind, shown};
use crate::fabrication::Fabrication;
use crate::fabrication::test_piece::test_piece;

/// The smallest hole a compensated cut may leave (mm): the cut files print
/// lengths to 0.1 micrometre, so a hole narrower than this is written as a
/// circle of radius 0 or less, which no laser cuts.
const MIN_CUT_HOLE: f64 = 0.001;

pub(super) fn check_settings(
    f: &Fabrication,
    raw: &RawDesign,
    o: &Overrides,
    spans: &FabricationSpans,
) -> Result<(), Diagnostic> {
    let w = f.material.width;
    let d = f.eyelet.hole;
    // The recipe's eyelet values, unless `--eyelet` replaced them.
    let eyelet = raw
        .eyelet
        .as_ref()
        .filter(|_| spans.eyelet.is_some())
        .map(|e| e.get_ref());
    let hole_span = eyelet
        .and_then(|e| e.hole.as_ref().map(|h| h.span()))
        .or(spans.eyelet.clone());
    if f.eyelet.flange <= d {
        let span = eyelet
            .and_then(|e| e.flange.as_ref().map(|f| f.span()))
            .or(hole_span.clone());
        return Err(Diagnostic::new(
            ErrorKind::FlangeNotWiderThanHole,
            format!(
                "the eyelet's flange ({} mm) is no wider than its hole ({} mm): the eyelet would pull through",
                shown(f.eyelet.flange),
                shown(d)
            ),
        )
        .at_opt(span)
        .hint("eyelet.flange is the outer diameter of the eyelet's rim, larger than eyelet.hole (a 1/8 in eyelet: hole 3.2, flange 6.5)"));
    }
    if d > w - 2.0 * MIN_WALL {
        return Err(Diagnostic::new(
            ErrorKind::HoleWiderThanStrip,
            format!(
                "the {} mm eyelet hole leaves less than {MIN_WALL} mm of material on each side of a {} mm strip",
                shown(d),
                shown(w)
            ),
        )
        .at_opt(hole_span.clone().or(spans.width.clone()))
        .hint(format!(
            "use wider strips (material.width >= {}) or a smaller eyelet",
            shown(d + 2.0 * MIN_WALL)
        )));
    }
    // The rounded end needs end_margin >= w / 2; with the hole check above
    // that also leaves at least MIN_WALL between an end hole and the tip.
    if f.end_margin < w / 2.0 {
        return Err(Diagnostic::new(
            ErrorKind::HoleTooCloseToEnd,
            format!(
                "strip.end_margin is {} mm: the end holes would sit closer to the tips than the rounded end allows (at least half the {} mm width, {} mm)",
                shown(f.end_margin),
                shown(w),
                shown(w / 2.0)
            ),
        )
        .at_opt(spans.end_margin.clone())
        .hint(format!("raise strip.end_margin to {} mm or more", shown(w / 2.0))));
    }
    if f.sheet.width.max(f.sheet.height) > MAX_SHEET {
        return Err(Diagnostic::new(
            ErrorKind::SheetTooLarge,
            format!(
                "the sheet is {} x {} mm; karigami lays out sheets of at most {MAX_SHEET} mm a side",
                shown(f.sheet.width),
                shown(f.sheet.height)
            ),
        )
        .at_opt(spans.sheet.clone())
        .hint("give the size of your laser's bed or of the stock you cut, in mm"));
    }
    check_margin(f, raw, spans)?;
    check_blade(f, spans, hole_span.clone())?;
    check_kerf(f, raw, o, spans, hole_span)
}

/// A cutting plotter's drag blade tears a hole smaller than its preset's
/// minimum: refused before anything is cut or written.
fn check_blade(
    f: &Fabrication,
    spans: &FabricationSpans,
    hole_span: Option<std::ops::Range<usize>>,
) -> Result<(), Diagnostic> {
    let Some(p) = &f.plotter else {
        return Ok(());
    };
    let cut = if f.compensate_kerf {
        f.eyelet.hole - f.kerf
    } else {
        f.eyelet.hole
    };
    // On the files' 0.1 micrometre grid, so 3.2 - 0.2 is not below 3.
    if (cut * 1e4).round() >= (p.min_hole * 1e4).round() {
        return Ok(());
    }
    let compensated = if f.compensate_kerf {
        format!(" (cut {} mm narrower for the kerf)", shown(f.kerf))
    } else {
        String::new()
    };
    Err(Diagnostic::new(
        ErrorKind::HoleTooSmallForBlade,
        format!(
            "every strip's eyelet holes (the {} eyelet's) are {} mm across{compensated}, smaller than the {} mm {} cuts cleanly: its blade would tear them",
            f.eyelet.name,
            shown((cut * 1e4).round() / 1e4),
            shown(p.min_hole),
            p.plotter.describe()
        ),
    )
    .at_opt(hole_span.or(spans.plotter.clone()))
    .hint(format!(
        "use larger eyelets (eyelet.preset = \"1/8in\" cuts {} mm holes, \"5/32in\" 4 mm), cut on a laser (machine.preset = \"laser-co2\"), or, if your blade cuts smaller holes cleanly on a scrap, lower machine.min_hole",
        shown(crate::fabrication::EYELET_PRESETS[0].1)
    )))
}

/// The usable area inside the margins must hold a strip's width; a margin
/// that leaves nothing at all is named as the cause.
fn check_margin(
    f: &Fabrication,
    raw: &RawDesign,
    spans: &FabricationSpans,
) -> Result<(), Diagnostic> {
    let w = f.material.width;
    let (uw, uh) = f.sheet.usable();
    if uw >= w && uh >= w {
        return Ok(());
    }
    let margin = raw
        .sheet
        .as_ref()
        .and_then(|s| s.get_ref().margin.as_ref())
        .map(|m| m.span());
    let short_side = f.sheet.width.min(f.sheet.height);
    // A margin the recipe sets is what to change when it leaves no room,
    // or room narrower than a strip on a sheet wide enough without it.
    let no_room = uw <= 0.0 || uh <= 0.0;
    if let Some(span) = margin.filter(|_| no_room || short_side >= w) {
        let what = if no_room {
            "twice that is at least the".to_string()
        } else {
            format!(
                "inside the margins {} x {} mm is left of the",
                shown(uw),
                shown(uh)
            )
        };
        return Err(Diagnostic::new(
            ErrorKind::SheetTooSmall,
            format!(
                "sheet.margin is {} mm: {what} {} x {} mm sheet, no room for a {} mm strip",
                shown(f.sheet.margin),
                shown(f.sheet.width),
                shown(f.sheet.height),
                shown(w)
            ),
        )
        .at(span)
        .hint(format!(
            "make sheet.margin at most {} mm (it is kept free on every side), or use a larger sheet",
            shown(largest_margin(short_side, w))
        )));
    }
    Err(Diagnostic::new(
        ErrorKind::SheetTooSmall,
        format!(
            "the sheet's usable area ({} x {} mm inside the margins) is narrower than one strip ({} mm)",
            shown(uw.max(0.0)),
            shown(uh.max(0.0)),
            shown(w)
        ),
    )
    .at_opt(spans.sheet.clone())
    .hint("use a larger sheet or a smaller sheet.margin"))
}

/// With kerf compensation on, every hole is cut the kerf narrower: the
/// eyelet holes and the test piece's smaller steps must stay holes.
fn check_kerf(
    f: &Fabrication,
    raw: &RawDesign,
    o: &Overrides,
    spans: &FabricationSpans,
    hole_span: Option<std::ops::Range<usize>>,
) -> Result<(), Diagnostic> {
    if !f.compensate_kerf {
        return Ok(());
    }
    let k = f.kerf;
    // Lengths to the files' 0.1 micrometre, without float noise
    // (3.0000000000000004): a hole closes when it is written below
    // `MIN_CUT_HOLE`.
    let grid = |x: f64| (x * 1e4).round() / 1e4;
    let closed = |hole: f64| grid(hole - k) < MIN_CUT_HOLE;
    let piece = test_piece(f);
    let smallest_step = piece
        .as_ref()
        .and_then(|p| p.holes.iter().map(|h| h.1).min_by(f64::total_cmp))
        .filter(|&s| s < f.eyelet.hole);
    let (hole, what) = if closed(f.eyelet.hole) {
        (f.eyelet.hole, "the eyelet holes")
    } else {
        match smallest_step {
            Some(s) if closed(s) => (s, "the test piece's smallest hole"),
            _ => return Ok(()),
        }
    };
    let mm = |x: f64| shown(grid(x));
    let message = format!(
        "kerf compensation closes {what}: a {} mm hole cut {} mm narrower (the kerf) is {} mm across",
        mm(hole),
        mm(k),
        mm(hole - k)
    );
    let smallest = smallest_step.unwrap_or(f.eyelet.hole);
    let mut hint = format!(
        "use a kerf of at most {} mm, a larger eyelet, or leave the geometry nominal (no compensation) and set the kerf offset in the laser software",
        mm(smallest - MIN_CUT_HOLE)
    );
    if smallest_step.is_some() {
        hint.push_str(&format!(
            " (the test piece's holes go down to {} mm; --no-test-piece or sheet.test_piece = false leaves it out)",
            mm(smallest)
        ));
    }
    if o.kerf.is_some() {
        return Err(Diagnostic::new(
            ErrorKind::KerfClosesHoleFlag,
            format!("--kerf {}: {message}", shown(k)),
        )
        .hint(hint));
    }
    let compensate = raw
        .laser
        .as_ref()
        .and_then(|l| l.get_ref().compensate.as_ref())
        .map(|c| c.span());
    Err(Diagnostic::new(ErrorKind::KerfClosesHole, message)
        .at_opt(spans.kerf.clone().or(hole_span).or(compensate))
        .hint(hint))
}

/// The largest margin, in whole hundredths of a mm, that leaves a `w` mm
/// strip room across a `side` mm sheet side, as a hint can print it and
/// the check pass it (98.65 on 210 mm for 12.7 mm strips leaves
/// 12.699999999999989 in binary: 98.64).
fn largest_margin(side: f64, w: f64) -> f64 {
    let mut hundredths = ((side - w) / 2.0 * 100.0).round();
    while hundredths > 0.0 && side - 2.0 * (hundredths / 100.0) < w {
        hundredths -= 1.0;
    }
    (hundredths / 100.0).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::largest_margin;

    #[test]
    fn the_margin_a_hint_gives_passes_the_check() {
        assert_eq!(largest_margin(400.0, 10.0), 195.0);
        assert_eq!(largest_margin(210.0, 12.7), 98.64);
        assert_eq!(largest_margin(5.0, 10.0), 0.0);
        for (side, w) in [(297.0, 4.2), (210.0, 4.2), (400.0, 12.7), (304.8, 9.53)] {
            let m = largest_margin(side, w);
            assert!(side - 2.0 * m >= w, "{side} {w}: {m}");
            let next = ((m * 100.0).round() + 1.0) / 100.0;
            assert!(side - 2.0 * next < w, "{side} {w}: {m} is not the largest");
        }
    }
}
