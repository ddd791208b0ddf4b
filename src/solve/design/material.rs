//! Curvature the strips reach (docs/design.md): a strip bent flatwise to a
//! radius R strains its faces by t / (2 R) (docs/physics.md, "Strain and
//! what is allowed"), so at the allowable strain it bends to R = t / (2
//! eps) and no tighter. A target that bends tighter, at the scale of a
//! cell, is refused before the search with what would reach it.

use crate::design::Design;
use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::target::Target;

/// The tightest radius the strips of `base` bend to at their allowable
/// strain (mm).
pub(super) fn least_radius(base: &Design) -> f64 {
    base.fabrication.material.thickness / (2.0 * base.simulation.material.eps_allow)
}

/// Refuse a target whose tightest bend over a cell of `edge` (the target's
/// largest principal curvature at that scale, `Target::tightest_bend`) is
/// tighter than the strips reach: with both radii, the thickness that
/// would reach it and the factor to scale the target by.
pub(super) fn within_reach(t: &Target, base: &Design, edge: f64) -> Result<(), Diagnostic> {
    let bend = t.tightest_bend(edge);
    let least = least_radius(base);
    if bend.curvature * least <= 1.0 {
        return Ok(());
    }
    let radius = 1.0 / bend.curvature;
    let m = &base.fabrication.material;
    let eps = base.simulation.material.eps_allow;
    let thinner = 2.0 * eps * radius;
    let sold = m.preset.map_or(String::new(), |p| {
        if thinner < p.thickness.0 {
            format!(
                " ({} is sold from {} mm: another material, or the larger target)",
                p.name, p.thickness.0
            )
        } else {
            String::new()
        }
    });
    let diagnostic = Diagnostic::new(
        ErrorKind::TargetTooCurved,
        format!(
            "the target bends to a radius of {radius:.1} mm (its largest principal curvature over {:.0} to {edge:.0} mm, a cell), tighter than the {least:.1} mm that {} mm strips of {} bend to at their allowable strain of {} % (flatwise strain = t / (2 R))",
            edge / 2.0,
            m.thickness,
            m.name,
            100.0 * eps
        ),
    );
    // To the hundredth below, but for the estimate's last thousandth (a
    // radius of 24.999 mm asks 0.75 mm, not 0.74).
    let thickness = (thinner * 100.0 * 1.001).floor() / 100.0;
    let scale = (least / radius * 100.0 / 1.001).ceil() / 100.0;
    Err(diagnostic.hint(format!(
        "strips at most {thickness:.2} mm thick (--thickness {thickness:.2}){sold}, or the target scaled up {scale:.2} times (docs/design.md, \"Curvature the strips reach\")"
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base(thickness: f64) -> Design {
        let text = format!(
            "{}[material]\nthickness = {thickness}\n",
            super::super::STUB
        );
        crate::design::parse(&text, "t").unwrap()
    }

    /// The half pipe of radius 25 mm of fixtures/targets/too-curved.toml:
    /// refused with 1 mm ABS (33.3 mm at 1.5 %), with the 0.75 mm that
    /// reaches it; taken with 0.7 mm strips.
    #[test]
    fn a_target_tighter_than_the_strips_bend_is_refused_with_the_thickness_that_reaches_it() {
        let text =
            "[target]\nfamily = \"cylinder\"\nradius = 25.0\nlength = 300.0\nangle = 180.0\n";
        let t = crate::target::read("t.toml", text.as_bytes(), None).unwrap();
        assert!((least_radius(&base(1.0)) - 100.0 / 3.0).abs() < 1e-9);
        let e = within_reach(&t, &base(1.0), 60.0).unwrap_err();
        assert_eq!(e.kind, ErrorKind::TargetTooCurved);
        assert!(
            e.message.contains("a radius of 25.0 mm") && e.message.contains("33.3 mm"),
            "{}",
            e.message
        );
        let hint = e.hint.unwrap();
        assert!(
            hint.contains("--thickness 0.75") && hint.contains("scaled up 1.34 times"),
            "{hint}"
        );
        assert!(within_reach(&t, &base(0.7), 60.0).is_ok());
    }
}
