//! Eyelet holes: where they go along a strip (one at each end, one at the
//! scissor pivot) and the checks on them (flanges that overlap or nearly
//! touch, holes too near the tips).

use super::{PartsError, Strip, Warning};
use crate::fabrication::Fabrication;

/// Eyelet flanges closer than this (mm) get a near-miss warning.
pub(crate) const FLANGE_CLEARANCE_WARNING: f64 = 1.0;
/// Hole centre to strip tip, in hole diameters, below which a warning says
/// the end may tear out (the usual edge-distance rule for holes).
pub(crate) const EDGE_DISTANCE: f64 = 1.5;

/// Hole centres along a strip, from its start tip: the start vertex, the
/// pivot and the end vertex of a rod with these legs, `margin` mm in from
/// each tip.
pub(super) fn centres(legs: [f64; 2], margin: f64) -> [f64; 3] {
    // margin + (legs[0] + legs[1]), as `Rod::length` adds them.
    [margin, margin + legs[0], margin + (legs[0] + legs[1])]
}

/// Eyelet flanges that overlap (refused) or nearly touch, and end holes too
/// near the tips (warnings).
pub(super) fn check(
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
    Ok(())
}
