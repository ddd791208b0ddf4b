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

use super::goal::{COVERED, TOP_COVERED, ratios};
use super::{DesignAsk, Found, Plumb, loops, miss, rounded};
use crate::target::{COVERED_WITHIN, Fit, Target};
use glam::{DVec2, DVec3};

/// Azimuths sampled round a circle about the axis.
const AZIMUTHS: usize = 64;

/// Circles sampled from near the axis to near the boundary's nearest
/// point.
const CIRCLES: usize = 9;

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
    /// The boundary's mean height: the sheet's, which the bump stands on.
    pub base: f64,
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
    let mut heights = Vec::with_capacity(CIRCLES);
    for k in 0..CIRCLES {
        // Near the axis and a hair inside the boundary; a line through
        // a mesh's vertex or edge may miss it, so a few misses are let be.
        let r = inscribed * (0.02 + 0.97 * k as f64 / (CIRCLES - 1) as f64);
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
    let rise = (heights[0] - heights[CIRCLES - 1]).abs();
    (rise >= RISE * t.extent).then_some(Bump {
        axis,
        inscribed,
        base,
    })
}

/// The plan centroid of the target's area weighted by how far its height
/// off the boundary's mean height `base` passes half the largest: the
/// axis of a bump on a flat sheet, wherever on the sheet it stands. Only
/// the bump's upper half counts, which a side near the bump does not cut
/// off as it cuts off the flank (the whole bump weighted by its height
/// put a bump 160 mm from a side 164.5 mm from it).
fn raised_centroid(t: &Target, base: f64) -> Option<DVec2> {
    let (centres, half) = raised(t, base);
    let (mut sum, mut weight) = (DVec2::ZERO, 0.0);
    for (c, a) in centres {
        let w = a * ((c.z - base).abs() - half).max(0.0);
        sum += w * c.truncate();
        weight += w;
    }
    (weight > 0.0).then(|| sum / weight)
}

/// The target's triangle centres with their areas, and half the largest
/// height of a centre off `base`.
fn raised(t: &Target, base: f64) -> (Vec<(DVec3, f64)>, f64) {
    let centres: Vec<(DVec3, f64)> = (0..t.mesh.triangles.len())
        .map(|k| {
            let c = t.mesh.corners(k).iter().sum::<DVec3>() / 3.0;
            (c, t.mesh.triangle_area(k))
        })
        .collect();
    let half = 0.5
        * centres
            .iter()
            .map(|(c, _)| (c.z - base).abs())
            .fold(0.0, f64::max);
    (centres, half)
}

/// The bump's top: a flag for each triangle of `t` whose centre stands
/// more than half the bump's height off the sheet.
pub(super) fn top(t: &Target, bump: Bump) -> Vec<bool> {
    let (centres, half) = raised(t, bump.base);
    centres
        .iter()
        .map(|(c, _)| (c.z - bump.base).abs() > half)
        .collect()
}

/// The plan distance from `axis` to the nearest edge of `ring`.
fn nearest_boundary(ring: &[DVec3], axis: DVec2) -> f64 {
    let plan: Vec<DVec2> = ring.iter().map(|p| p.truncate()).collect();
    rounded::distance(&plan, axis)
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

/// The search on a round bump: why loops are grown (the recipe's
/// topology line), how much of the target they can cover, said to
/// `progress`, and the loops: round circles about its axis (`loops`)
/// and round the rounded boxes inscribed in the sheet (`rounded`).
pub(super) fn grow(
    ask: &DesignAsk<'_>,
    (bump, boundary): (Bump, &[DVec3]),
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> (String, BumpCover, Vec<Found>) {
    let why = format!(
        "loop or sheet (the seed below says which): the target is an open patch whose surface is round about a vertical axis (a bump, {:.1} mm from the boundary's nearest point), so loops seeded round level circles about that axis, and round rounded boxes inscribed in the sheet, climb it as on a cap (docs/design.md, \"Round bumps\" and \"Rounded boxes\"), and sheets grow from stretches of its boundary across it (docs/math.md 6.1)",
        bump.inscribed
    );
    let boxes = rounded::boxes(&ask.target, boundary);
    let reach = cover(&ask.target, bump, boxes.as_ref());
    progress(&format!(
        "a round bump: loops reach at most {:.1} % of the target's area ({})",
        100.0 * reach.covers,
        reach.curve
    ));
    let mut found = loops(ask, bump, tried, progress);
    if let Some((frame, boxes)) = &boxes {
        found.extend(rounded::loops(
            ask,
            (frame, boxes),
            bump.axis,
            tried,
            progress,
        ));
    }
    (why, reach, found)
}

/// Loops seeded round level circles about the bump's axis, from the
/// boundary's nearest point to `REACH` past it, each at the mean height
/// the target has round it (`loops::loops` grows their rings).
fn loops(
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
        progress(&grown_line(
            &format!("the level circle of radius {radius:.1} mm about its axis"),
            &grown,
        ));
        out.extend(grown);
    }
    out
}

/// The progress line once one seed's loops have grown round `what`: how
/// many designs, and the best by fit.
pub(super) fn grown_line(what: &str, grown: &[Found]) -> String {
    let best = grown
        .iter()
        .min_by(|a, b| miss(&a.fit).total_cmp(&miss(&b.fit)));
    format!(
        "a round bump, loops round {what}: {} designs{}",
        grown.len(),
        best.map_or(String::new(), |f| format!(
            ", the best {} cells: {}",
            f.cells,
            f.fit.summary("vertices")
        ))
    )
}

/// How far short of the disk its widest seed circle reaches a loop's
/// cells cover: measured 2.9 % (a 40 mm dip on 300 x 260 mm at
/// `--edge 45`) to 6.2 % of the target's area. Where the disk covers
/// less than the goal's 85 % and this, no edge meets the goal.
const SHORT_OF_DISK: f64 = 0.025;

/// How much of a sheet loops round its bump can cover: the share of its
/// area that lies, in plan, within the widest seed (a circle about the
/// axis or a rounded box) and the `COVERED_WITHIN` of D about it that
/// counts as covered. Where that is under the goal's 85 % and
/// `SHORT_OF_DISK`, no loop can cover the sheet (docs/design.md, "Round
/// bumps").
#[derive(Clone, Debug, PartialEq)]
pub struct BumpCover {
    /// The share of the target's area (0 to 1).
    pub covers: f64,
    /// The seed that reaches it, for the refusal: "the disk of radius
    /// 242 mm about its axis".
    pub curve: String,
    /// The side of the square about the axis inside the boundary (mm).
    pub side: f64,
    /// How far the axis stands from the middle of the sheet's least box
    /// (mm), and the box's sides, when a rounded box lies over the sheet.
    pub off: Option<(f64, String)>,
    /// The bump's top (`top`): a flag for each of the target's triangles.
    pub top: Vec<bool>,
    /// How many times as long as wide the sheet's least box is (1 when no
    /// rounded box lies over the sheet).
    pub long: f64,
}

impl BumpCover {
    /// What to try when a design grown at `edge` misses the goal's
    /// coverage on this target (its simulated fit `sim`): a squarer sheet
    /// when loops cannot reach it, else the edge at which what the cells
    /// leave short of their seed's reach, going about as the edge, is
    /// within the goal (measured: docs/design.md, "Round bumps"), with
    /// the squarer sheet should it miss; the squarer sheet alone when
    /// that edge would be under the eyelets' `least`. None when the
    /// distances miss too: the goal's remedy says what then.
    pub fn remedy(&self, sim: &Fit, top: f64, (edge, least): (f64, f64)) -> Option<String> {
        if top < TOP_COVERED {
            return Some(if self.long > LONG_SHEET {
                self.bare_top(top)
            } else {
                self.open_pole(top, (edge, least))
            });
        }
        if ratios(sim).0 > 1.0
            && let Some(off) = self.off_middle(sim.extent)
        {
            return Some(off);
        }
        let covered = sim.coverage.filter(|&c| c < COVERED)?;
        if self.covers < COVERED + SHORT_OF_DISK {
            return Some(self.too_long());
        }
        if ratios(sim).0 > 1.0 {
            return None;
        }
        let wanted = (edge * (self.covers - COVERED) / (self.covers - covered)).floor();
        if wanted < least {
            return Some(self.too_long());
        }
        Some(format!(
            "try --edge {wanted:.0} (now {edge:.1} mm): a loop round the bump reaches up to about {:.0} % of this target ({}), and the share its cells leave short of that goes about as the edge; should that still miss, take a sheet about as wide as long with the bump at its middle, such as {:.0} x {:.0} mm (docs/design.md, \"Round bumps\")",
            100.0 * self.covers,
            self.curve,
            self.side,
            self.side
        ))
    }

    /// Where the distances miss on a bump off the sheet's middle (more
    /// than `OFF_MIDDLE` of D): the rings reach it unevenly, and a
    /// smaller edge measured worse (docs/design.md, "Rounded boxes").
    fn off_middle(&self, extent: f64) -> Option<String> {
        let (off, sides) = self.off.as_ref().filter(|o| o.0 > OFF_MIDDLE * extent)?;
        Some(format!(
            "the bump stands {off:.0} mm off the middle of the sheet (its least box, {sides}) and {:.0} mm from the nearest side, so a loop round a rounded box inscribed in the sheet climbs it unevenly and its rings stray from it; a smaller edge measured worse on such a bump; a sheet with the bump nearer its middle is designed within the goal (docs/design.md, \"Rounded boxes\")",
            self.side / 2.0
        ))
    }

    /// The share of the bump's top within `COVERED_WITHIN` of D of the
    /// cells `(points, facets)`, after the motion of their fit `sim` to `t`.
    pub fn top_covered(&self, t: &Target, sim: &Fit, cells: (&[DVec3], &[[u32; 4]])) -> f64 {
        t.covered_part(sim, cells, &self.top)
    }

    /// Where the whole target's coverage passes but the top's does not:
    /// the loop's rings step in from every side at one pace, so on a long
    /// sheet they meet along its long sides first and leave a slot over
    /// the bump (docs/design.md, "Rounded boxes").
    fn bare_top(&self, top: f64) -> String {
        let sheet = self
            .off
            .as_ref()
            .map_or(String::new(), |(_, sides)| format!(" of {sides}"));
        format!(
            "the bump's top (where it stands over half its height) is only {:.0} % covered, under {:.0} %: a loop's rings step in from every side of the sheet at one pace, so on a sheet{sheet} they meet along its long sides before they reach the top and leave a slot over it; a sheet about as wide as long with the bump at its middle, such as {:.0} x {:.0} mm, is covered (docs/design.md, \"Rounded boxes\")",
            100.0 * top,
            100.0 * TOP_COVERED,
            self.side,
            self.side
        )
    }

    /// Where the top is bare on a sheet about as wide as long: the rings
    /// stop short of the axis (`loops::HOLE`), and on a small top that
    /// leaves much of it open. The share left open went about as the
    /// edge cubed on 200 x 200 mm (49.1, 31.1 and 20.0 % at 60, 52 and 45
    /// mm); the edge offered takes it as the square, for a margin.
    fn open_pole(&self, top: f64, (edge, least): (f64, f64)) -> String {
        let wanted = (edge * ((1.0 - TOP_COVERED) / (1.0 - top)).sqrt()).floor();
        let what = format!(
            "the bump's top (where it stands over half its height) is only {:.0} % covered, under {:.0} %: the loops' rings stop short of the bump's axis and leave its pole open, which on a top this small is much of it",
            100.0 * top,
            100.0 * TOP_COVERED
        );
        if wanted < least {
            return format!(
                "{what}; the edge that would close it, {wanted:.0} mm, is under the least the eyelets take ({least:.0} mm): a larger bump, or smaller eyelets, would (docs/design.md, \"The goal\")"
            );
        }
        format!(
            "{what}; try --edge {wanted:.0} (now {edge:.1} mm): smaller cells bring the last ring nearer the axis (docs/design.md, \"The goal\")"
        )
    }

    fn too_long(&self) -> String {
        format!(
            "a loop round the bump covers less of this target than its widest seed reaches with the 3 % of D that counts as covered (about {:.0} % of its area: {}; a loop's cells cover 3 to 6 % less), so no edge would meet the goal, and no sheet found climbs the bump; a sheet about as wide as long with the bump at its middle, such as {:.0} x {:.0} mm, is covered (docs/design.md, \"Round bumps\")",
            100.0 * self.covers,
            self.curve,
            self.side,
            self.side
        )
    }
}

/// How many times as long as wide a sheet whose bump's top is bare must
/// be for the miss to be put down to a slot between the rings (600 x 300
/// mm, twice; 300 x 200's old designs, 1.5) rather than to the pole's
/// hole (docs/design.md, "The goal").
const LONG_SHEET: f64 = 1.4;

/// How far (a share of D) a bump's axis may stand off the middle of the
/// sheet's least box before a design whose distances miss is told to
/// move it: 6.5 % (36 mm on 420 x 360 mm) and 10.4 % (60 mm on 480 x 320)
/// met the goal, 13.0 % (72 mm) missed (docs/design.md, "Rounded boxes").
const OFF_MIDDLE: f64 = 0.05;

/// The cover of loops round `bump` on `t`, and round the rounded
/// `boxes` when any lies over the sheet.
fn cover(
    t: &Target,
    bump: Bump,
    boxes: Option<&(rounded::Frame, Vec<rounded::Rounded>)>,
) -> BumpCover {
    let widest = REACH.iter().copied().fold(0.0, f64::max);
    let radius = bump.inscribed + (widest + COVERED_WITHIN) * t.extent;
    let mut best = BumpCover {
        covers: rounded::area_share(t, |c| c.distance(bump.axis) <= radius),
        curve: format!("the disk of radius {radius:.0} mm about its axis"),
        side: 2.0 * bump.inscribed,
        off: None,
        top: top(t, bump),
        long: 1.0,
    };
    let Some((frame, boxes)) = boxes.filter(|b| !b.1.is_empty()) else {
        best.curve
            .push_str(", no rounded box inscribed in the sheet's least box lying over the sheet");
        return best;
    };
    for b in boxes {
        let covers = rounded::share(t, &b.ring);
        if covers > best.covers {
            best.covers = covers;
            best.curve = format!(
                "the rounded box of exponent {} inscribed in the sheet's least box, {}",
                b.exponent,
                rounded::sides(frame)
            );
        }
    }
    best.off = Some((frame.centre.distance(bump.axis), rounded::sides(frame)));
    best.long = frame.half.max_element() / frame.half.min_element().max(f64::MIN_POSITIVE);
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn target(text: &str) -> Target {
        crate::target::read("t.toml", text.as_bytes(), None)
            .unwrap()
            .canonical()
    }

    /// A height field: a Gaussian `(height, sigma)` about `axis` on a
    /// `(width, length)` sheet, on a grid of `[columns, rows]`.
    fn gaussian(
        (width, length): (f64, f64),
        [columns, rows]: [usize; 2],
        (height, sigma): (f64, f64),
        axis: DVec2,
    ) -> Target {
        let rows: Vec<String> = (0..rows)
            .map(|j| {
                let y = -length / 2.0 + length * j as f64 / (rows - 1) as f64;
                let row: Vec<String> = (0..columns)
                    .map(|i| {
                        let x = -width / 2.0 + width * i as f64 / (columns - 1) as f64;
                        let r2 = DVec2::new(x, y).distance_squared(axis);
                        format!("{:.3}", height * (-r2 / (2.0 * sigma * sigma)).exp())
                    })
                    .collect();
                format!("[{}]", row.join(", "))
            })
            .collect();
        target(&format!(
            "[target]\nfamily = \"height-field\"\nwidth = {width:.1}\nlength = {length:.1}\nheights = [{}]\n",
            rows.join(", ")
        ))
    }

    fn boundary(t: &Target) -> Vec<DVec3> {
        super::super::sheets::inward_boundary(t)
    }

    /// A fit of 10 points to a target of `extent` with the distances
    /// and the coverage given.
    fn fitted(extent: f64, (rms, largest): (f64, f64), coverage: f64) -> Fit {
        Fit {
            motion: crate::target::Rigid::IDENTITY,
            rms,
            largest,
            extent,
            coverage: Some(coverage),
            points: 10,
        }
    }

    /// The suite's bump, fixtures/targets/height-field.toml.
    fn suites_bump() -> Target {
        let path = format!(
            "{}/fixtures/targets/height-field.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        target(&std::fs::read_to_string(path).unwrap())
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

    /// Loops round the suite's bump reach a disk of 180 mm + 6.5 % of D
    /// (3.5 % past the long sides, 3 % counted covered): 89.2 % of the
    /// Gaussian's surface on the 420 x 360 sheet (integrated apart, on a
    /// 1000 x 1000 grid; the height field's triangles and the test by
    /// their centres stray about 1 %), so a smaller edge is offered. On a
    /// 480 x 320 sheet the disk of 160 mm + 6.5 % covers 73.0 %, and a
    /// coverage miss is told to take a sheet about as wide as long.
    #[test]
    fn a_sheet_too_long_for_its_bumps_loops_is_told_so() {
        let fit = |coverage| fitted(500.0, (1.0, 2.0), coverage);
        let t = suites_bump();
        let c = cover(&t, round_bump(&t, &boundary(&t)).unwrap(), None);
        let radius = 180.0 + 0.065 * t.extent;
        assert!(
            c.curve
                .starts_with(&format!("the disk of radius {radius:.0} mm about its axis")),
            "{c:?}"
        );
        assert!(
            (c.covers - 0.892).abs() < 0.015 && (c.side - 360.0).abs() < 2.0,
            "{c:?}"
        );
        // 60 (0.903 - 0.85) / (0.903 - 0.825) = 40.8 mm; from 80 %
        // covered, 30.9 mm, under the eyelets' 34 mm: the square alone.
        let hint = c.remedy(&fit(0.825), 1.0, (60.0, 34.0)).expect("an edge");
        assert!(
            hint.starts_with("try --edge 40 (now 60.0 mm)")
                && hint.contains("such as 360 x 360 mm"),
            "{hint}"
        );
        let hint = c.remedy(&fit(0.80), 1.0, (60.0, 34.0)).expect("a square");
        assert!(
            hint.starts_with("a loop round the bump covers less"),
            "{hint}"
        );
        let t = gaussian((480.0, 320.0), [17, 11], (60.0, 70.0), DVec2::ZERO);
        let ring = boundary(&t);
        let bump = round_bump(&t, &ring).expect("a round bump");
        let c = cover(&t, bump, None);
        assert!((c.covers - 0.730).abs() < 0.015, "{c:?}");
        let hint = c.remedy(&fit(0.80), 1.0, (60.0, 34.0)).expect("a remedy");
        assert!(
            hint.contains(
                "(about 73 % of its area: the disk of radius 197 mm about its axis, no rounded box"
            ) && hint.contains("320 x 320 mm"),
            "{hint}"
        );
        assert_eq!(c.remedy(&fit(0.90), 1.0, (60.0, 34.0)), None);
        // The rounded boxes inscribed in the sheet reach its corners: the
        // widest (exponent 4, 92.7 % of the box's area) with its band
        // covers nearly all, so an edge is offered.
        let boxes = rounded::boxes(&t, &ring).expect("a box");
        assert_eq!(boxes.1.len(), 3);
        let c = cover(&t, bump, Some(&boxes));
        assert!(c.covers > 0.97, "{c:?}");
        let hint = c.remedy(&fit(0.80), 1.0, (60.0, 34.0)).expect("an edge");
        assert!(
            hint.starts_with("try --edge ")
                && hint.contains("(the rounded box of exponent 4 inscribed in the sheet's least box, 480 x 320 mm)"),
            "{hint}"
        );
    }

    /// A bump 72 mm off the middle of a 420 x 360 mm sheet (at (60, -40),
    /// 140 mm from the nearest side, 13 % of D): where its design misses
    /// the distances, the refusal says to move it towards the middle, not
    /// a smaller edge (measured worse); the suite's bump at the middle
    /// leaves that to the goal's remedy.
    #[test]
    fn a_bump_off_the_middle_is_told_to_move() {
        // Levelled as `search` levels it: the bump off the middle turns the
        // canonical frame's principal axes.
        let t = gaussian(
            (420.0, 360.0),
            [15, 13],
            (70.0, 80.0),
            DVec2::new(60.0, -40.0),
        );
        let t = (*super::super::level_rim(&std::sync::Arc::new(t))).clone();
        let missed = fitted(t.extent, (0.02 * t.extent, 0.05 * t.extent), 0.81);
        let ring = boundary(&t);
        let bump = round_bump(&t, &ring).expect("a round bump");
        let c = cover(&t, bump, rounded::boxes(&t, &ring).as_ref());
        let (off, sides) = c.off.clone().expect("a box");
        assert!((off - 72.1).abs() < 3.0 && sides == "420 x 360 mm", "{c:?}");
        let hint = c.remedy(&missed, 1.0, (60.0, 34.0)).expect("a remedy");
        assert!(
            hint.starts_with("the bump stands 7") && hint.contains("nearer its middle"),
            "{hint}"
        );
        let t = suites_bump();
        let ring = boundary(&t);
        let bump = round_bump(&t, &ring).unwrap();
        let c = cover(&t, bump, rounded::boxes(&t, &ring).as_ref());
        assert!(c.off.as_ref().is_some_and(|o| o.0 < 1.0), "{c:?}");
        assert_eq!(
            c.remedy(
                &Fit {
                    extent: t.extent,
                    ..missed
                },
                1.0,
                (60.0, 34.0)
            ),
            None
        );
    }

    /// The top of a Gaussian bump of height H and sigma s is where it
    /// stands over H / 2: the disk of radius s sqrt(2 ln 2) (94.2 mm for
    /// s = 80), 27,900 mm^2 of plan, a little more of surface. A
    /// design whose simulated cells cover less of it than `TOP_COVERED`
    /// is told why, naming the sheet, whatever its whole coverage.
    #[test]
    fn a_bumps_top_is_its_upper_half_and_a_bare_top_is_told() {
        let t = gaussian((600.0, 300.0), [41, 21], (70.0, 80.0), DVec2::ZERO);
        let ring = boundary(&t);
        let bump = round_bump(&t, &ring).expect("a round bump");
        let c = cover(&t, bump, rounded::boxes(&t, &ring).as_ref());
        let (mut plan, mut radius) = (0.0, 0.0f64);
        for (k, _) in c.top.iter().enumerate().filter(|&(_, &on)| on) {
            let corners = t.mesh.corners(k);
            let [a, b, d] = corners.map(|p| p.truncate());
            plan += 0.5 * (b - a).perp_dot(d - a).abs();
            let centre = (corners.iter().sum::<DVec3>() / 3.0).truncate();
            radius = radius.max(centre.distance(bump.axis));
        }
        let disk = std::f64::consts::PI * (80.0f64 * (2.0 * 2f64.ln()).sqrt()).powi(2);
        assert!((plan - disk).abs() < 0.08 * disk, "{plan} against {disk}");
        assert!((radius - 94.2).abs() < 8.0, "{radius}");
        let fit = fitted(t.extent, (1.0, 2.0), 0.87);
        let hint = c.remedy(&fit, 0.44, (60.0, 34.0)).expect("a remedy");
        assert!(
            hint.starts_with("the bump's top (where it stands over half its height) is only 44 % covered, under 65 %")
                && hint.contains("on a sheet of 600 x 300 mm they meet along its long sides")
                && hint.contains("such as 300 x 300 mm"),
            "{hint}"
        );
        assert_eq!(c.remedy(&fit, 0.9, (60.0, 34.0)), None);
        // On a square sheet a bare top is the pole's hole: a smaller edge,
        // 60 sqrt(0.35 / 0.5) = 50.2 mm, or a larger bump under the
        // eyelets' least edge.
        let square = gaussian((240.0, 240.0), [9, 9], (40.0, 50.0), DVec2::ZERO);
        let ring = boundary(&square);
        let round = round_bump(&square, &ring).expect("a round bump");
        let s = cover(&square, round, rounded::boxes(&square, &ring).as_ref());
        assert!((s.long - 1.0).abs() < 1e-6, "{s:?}");
        let hint = s.remedy(&fit, 0.5, (60.0, 34.0)).expect("an edge");
        assert!(
            hint.contains("leave its pole open") && hint.contains("try --edge 50 (now 60.0 mm)"),
            "{hint}"
        );
        let hint = s.remedy(&fit, 0.5, (60.0, 55.0)).expect("a larger bump");
        assert!(hint.contains("a larger bump"), "{hint}");
        // Cells 20 mm square on the target: all of them cover the top;
        // without those whose corners all stand over half the bump's
        // height they cover 18 % of it, while the whole target's share
        // stays over the goal's 85 % (86.7 %).
        let h = |p: DVec2| 70.0 * (-p.length_squared() / (2.0 * 80.0 * 80.0)).exp();
        let (cols, rows) = (31, 16);
        let points: Vec<DVec3> = (0..rows)
            .flat_map(|j| {
                (0..cols)
                    .map(move |i| DVec2::new(-300.0 + 20.0 * i as f64, -150.0 + 20.0 * j as f64))
            })
            .map(|p| p.extend(h(p)))
            .collect();
        let quads: Vec<[u32; 4]> = (0..rows - 1)
            .flat_map(|j| (0..cols - 1).map(move |i| (i, j)))
            .map(|(i, j)| {
                let k = (j * cols + i) as u32;
                [k, k + 1, k + 1 + cols as u32, k + cols as u32]
            })
            .collect();
        let low: Vec<[u32; 4]> = quads
            .iter()
            .copied()
            .filter(|q| q.iter().all(|&k| points[k as usize].z < 0.5 * 70.0))
            .collect();
        let all = c.top_covered(&t, &fit, (&points, &quads));
        let slot = c.top_covered(&t, &fit, (&points, &low));
        let whole = t.fit(&points, &low).coverage.unwrap();
        assert!(
            all > 0.99 && slot < 0.35 && whole > 0.85,
            "{all} {slot} {whole}"
        );
    }
}
