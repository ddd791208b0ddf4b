//! Round bumps for `karigami design`: a patch whose boundary is not a
//! circle (a bump on a rectangular sheet) but whose surface is round
//! about a vertical axis near its middle. Sheets grown from a side do not
//! climb such a bump (docs/design.md, "The bump's rows"); a loop seeded
//! round a level circle about its axis does, as on a cap, its rings
//! stepping down the meridian to the top (docs/math.md 6.2).
//!
//! The circle may reach a little past the boundary where the boundary
//! comes nearest the axis: the loop then covers more of the sheet, and
//! its joints there lie as far outside as the circle reaches, which the
//! goal's largest distance bounds (docs/design.md, "Round bumps").

use super::{DesignAsk, Found, Plumb, loops, miss};
use crate::target::Target;
use glam::{DVec2, DVec3};

/// Azimuths sampled round a circle about the axis.
const AZIMUTHS: usize = 64;

/// Circles sampled between the axis and the boundary's nearest point.
const CIRCLES: usize = 8;

/// How far (a share of D) heights round one circle may spread about
/// their mean for the surface to count as round about the axis.
const LEVEL: f64 = 0.01;

/// How far (a share of D) the heights must rise or fall from the
/// boundary's nearest circle to the axis: less is a plate, which sheets
/// grow flat.
const RISE: f64 = 0.03;

/// How far (shares of D) past the boundary's nearest point the seed
/// circles reach: within the goal's largest distance of 4 % of D.
const REACH: [f64; 4] = [0.0, 0.02, 0.03, 0.035];

/// A round bump: its axis (a plan point) and the radius of the largest
/// circle about it inside the boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Bump {
    pub axis: DVec2,
    pub inscribed: f64,
}

/// The round bump of a patch `t` with boundary `ring` (clockwise, as
/// `sheets::inward_boundary` gives it), when its surface is round about a
/// vertical axis out to the boundary's nearest point and rises or falls
/// by `RISE` of D over it.
pub(super) fn round_bump(t: &Target, ring: &[DVec3]) -> Option<Bump> {
    if ring.len() < 3 {
        return None;
    }
    let base = ring.iter().map(|p| p.z).sum::<f64>() / ring.len() as f64;
    let axis = raised_centroid(t, base)?;
    let inscribed = nearest_boundary(ring, axis);
    if !(inscribed > 0.0) {
        return None;
    }
    let mut heights = Vec::with_capacity(CIRCLES + 1);
    for k in 0..=CIRCLES {
        // Near the axis and a hair inside the boundary; a line through
        // a mesh's vertex or edge may miss it, so a few misses are let be.
        let r = inscribed * (0.02 + 0.97 * k as f64 / CIRCLES as f64);
        let h = circle_heights(t, axis, r);
        if h.len() < AZIMUTHS * 9 / 10 {
            return None;
        }
        let mean = h.iter().sum::<f64>() / h.len() as f64;
        if h.iter().any(|z| (z - mean).abs() > LEVEL * t.extent) {
            return None;
        }
        heights.push(mean);
    }
    let rise = (heights[0] - heights[CIRCLES]).abs();
    (rise >= RISE * t.extent).then_some(Bump { axis, inscribed })
}

/// The plan centroid of the target's area weighted by its height off the
/// boundary's mean height `base`: the axis of a bump on a flat sheet,
/// wherever on the sheet it stands.
fn raised_centroid(t: &Target, base: f64) -> Option<DVec2> {
    let (mut sum, mut weight) = (DVec2::ZERO, 0.0);
    for k in 0..t.mesh.triangles.len() {
        let c = t.mesh.corners(k).iter().sum::<DVec3>() / 3.0;
        let w = t.mesh.triangle_area(k) * (c.z - base).abs();
        sum += w * c.truncate();
        weight += w;
    }
    (weight > 0.0).then(|| sum / weight)
}

/// The plan distance from `axis` to the nearest edge of `ring`.
fn nearest_boundary(ring: &[DVec3], axis: DVec2) -> f64 {
    (0..ring.len())
        .map(|k| {
            let (a, b) = (ring[k].truncate(), ring[(k + 1) % ring.len()].truncate());
            let ab = b - a;
            let u =
                ((axis - a).dot(ab) / ab.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
            axis.distance(a + u * ab)
        })
        .fold(f64::INFINITY, f64::min)
}

/// The target's heights round the circle of radius `r` about `axis`,
/// where vertical lines meet it.
fn circle_heights(t: &Target, axis: DVec2, r: f64) -> Vec<f64> {
    let plumb = Plumb::new(t);
    (0..AZIMUTHS)
        .filter_map(|k| {
            let a = std::f64::consts::TAU * k as f64 / AZIMUTHS as f64;
            plumb.height(axis + r * DVec2::from_angle(a))
        })
        .collect()
}

/// Loops seeded round level circles about the bump's axis, from the
/// boundary's nearest point to `REACH` past it, each at the mean height
/// the target has round it (`loops::loops` grows their rings).
pub(super) fn loops(
    ask: &DesignAsk<'_>,
    bump: Bump,
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Vec<Found> {
    let t = &ask.target;
    let mut out = Vec::new();
    for reach in REACH {
        let radius = bump.inscribed + reach * t.extent;
        let h = circle_heights(t, bump.axis, radius);
        if h.is_empty() {
            continue;
        }
        let z = h.iter().sum::<f64>() / h.len() as f64;
        let centre = bump.axis.extend(z);
        let what = format!("round the level circle of radius {radius:.1} mm about the bump's axis");
        let grown = loops::loops(ask, (centre, radius), &what, tried, progress);
        let best = grown
            .iter()
            .min_by(|a, b| miss(&a.fit).total_cmp(&miss(&b.fit)));
        progress(&format!(
            "a round bump, loops round the level circle of radius {radius:.1} mm about its axis: {} designs{}",
            grown.len(),
            best.map_or(String::new(), |f| format!(
                ", the best {} cells: {}",
                f.cells,
                f.fit.summary("vertices")
            ))
        ));
        out.extend(grown);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn target(text: &str) -> Target {
        crate::target::read("t.toml", text.as_bytes(), None)
            .unwrap()
            .canonical()
    }

    fn boundary(t: &Target) -> Vec<DVec3> {
        super::super::sheets::inward_boundary(t)
    }

    /// The suite's bump (scripts/make-targets: a Gaussian 70 mm high on a
    /// 420 x 360 mm sheet) stands at the middle, 180 mm from the long
    /// sides; a plate and a saddle are no bumps.
    #[test]
    fn the_suites_bump_is_round_and_a_plate_and_a_saddle_are_not() {
        let read = |name: &str| {
            let path = format!("{}/fixtures/targets/{name}", env!("CARGO_MANIFEST_DIR"));
            target(&std::fs::read_to_string(path).unwrap())
        };
        let t = read("height-field.toml");
        let bump = round_bump(&t, &boundary(&t)).expect("a round bump");
        assert!(bump.axis.length() < 1.0, "{bump:?}");
        assert!((bump.inscribed - 180.0).abs() < 1.0, "{bump:?}");
        for name in ["plate.toml", "saddle.toml", "cylinder.toml"] {
            let t = read(name);
            assert_eq!(round_bump(&t, &boundary(&t)), None, "{name}");
        }
    }
}
