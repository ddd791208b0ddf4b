//! Which equilibrium a simulation reports and what tells it from the others
//! (docs/physics.md, "The chosen equilibrium", "Multistability"): the
//! relief of each state, its bumps popped through against another state or
//! the design, and the text that lists them.

use super::path::Path;
use super::strips::LatticeModel;
use super::{Equilibrium, placed_at, shape_distance};
use crate::lattice::Lattice;
use crate::lattice::shape::{CURVED_DEG, VertexCurvature};
use glam::DVec3;
use std::fmt::Write as _;

/// The least height (mm) of a bump over its neighbours that counts.
pub const BUMP_MM: f64 = 0.5;

pub use super::path::SAME_MM;

/// The relief of one state: each interior vertex's angle defect and how
/// far it stands out of the sheet (`Lattice::heights`).
pub struct Relief {
    curvature: Vec<VertexCurvature>,
    height: Vec<f64>,
}

/// A vertex that differs between two states: its name (`[row, column]`)
/// and its measure in each (height in mm, or defect in degrees).
#[derive(Clone, Debug, PartialEq)]
pub struct Change {
    /// The vertex as reports name it.
    pub vertex: String,
    /// Its measure in the first state.
    pub from: f64,
    /// Its measure in the second.
    pub to: f64,
}

impl Relief {
    /// The relief of the lattice as it stands (the design).
    pub fn of(lattice: &Lattice) -> Relief {
        let curvature = lattice.curvature();
        let height = lattice.heights(&curvature);
        Relief { curvature, height }
    }

    /// The relief of a simulated state (`Equilibrium::points`).
    pub fn at(lattice: &Lattice, lm: &LatticeModel, points: &[DVec3]) -> Relief {
        Relief::of(&placed_at(lattice, lm, points))
    }

    /// The bumps of `self` turned inside out in `other` (docs/physics.md,
    /// "Multistability"): dome-like in both, standing at least `BUMP_MM`
    /// out to one side in one and to the other side in the other.
    pub fn popped(&self, other: &Relief, lattice: &Lattice) -> Vec<Change> {
        (0..self.curvature.len().min(other.curvature.len()))
            .filter_map(|i| {
                let (x, y) = (&self.curvature[i], &other.curvature[i]);
                let (ha, hb) = (self.height[i], other.height[i]);
                let domes =
                    x.defect.to_degrees() >= CURVED_DEG && y.defect.to_degrees() >= CURVED_DEG;
                let turned = ha * hb < 0.0 && ha.abs() >= BUMP_MM && hb.abs() >= BUMP_MM;
                (domes && turned).then(|| Change {
                    vertex: lattice.vertex_name(x.vertex),
                    from: ha,
                    to: hb,
                })
            })
            .collect()
    }

    /// The interior vertices curved one way in `self` and the other way in
    /// `other` (beyond `CURVED_DEG` both times), with their defects.
    pub fn flipped(&self, other: &Relief, lattice: &Lattice) -> Vec<Change> {
        let c = CURVED_DEG;
        self.curvature
            .iter()
            .zip(&other.curvature)
            .filter_map(|(x, y)| {
                let (dx, dy) = (x.defect.to_degrees(), y.defect.to_degrees());
                let flipped = (dx >= c && dy <= -c) || (dx <= -c && dy >= c);
                flipped.then(|| Change {
                    vertex: lattice.vertex_name(x.vertex),
                    from: dx,
                    to: dy,
                })
            })
            .collect()
    }
}

/// Bumps as listed: `[3, 7] -3.1 -> +2.5 mm`, at most 8, or "none".
pub fn listed(changes: &[Change], unit: &str) -> String {
    if changes.is_empty() {
        return "none".to_string();
    }
    let shown: Vec<String> = changes
        .iter()
        .take(8)
        .map(|c| format!("{} {:+.1} -> {:+.1} {unit}", c.vertex, c.from, c.to))
        .collect();
    let more = changes.len() - shown.len();
    format!(
        "{}{}",
        shown.join(", "),
        if more > 0 {
            format!(", and {more} more")
        } else {
            String::new()
        }
    )
}

/// The bumps of the chosen state that stand the other way from the
/// design's: the ones a maker pops through by hand.
pub fn against_design(lattice: &Lattice, lm: &LatticeModel, eq: &Equilibrium) -> Vec<Change> {
    Relief::of(lattice).popped(&Relief::at(lattice, lm, &eq.points), lattice)
}

/// The chosen state and the other stable state the path knows, in words
/// (report.txt, `simulate`): the state reached from the design when
/// deploying ends elsewhere, with its energy and its popped bumps.
pub fn known(lattice: &Lattice, lm: &LatticeModel, eq: &Equilibrium, path: &Path) -> String {
    if !eq.supports.is_empty() {
        return held(lattice, lm, eq, path);
    }
    let mut o = String::new();
    let deployed = path.end_distance.is_some();
    let _ = writeln!(
        o,
        "equilibrium reported (docs/physics.md, \"The chosen equilibrium\"): {}, energy {:.3} N mm",
        if deployed {
            "the state deploying from the nearly collapsed end reaches"
        } else {
            "the state reached from the design (the path did not deploy to the design opening)"
        },
        eq.energy.total()
    );
    let mine = popped_from_design(&mut o, lattice, lm, &eq.points);
    let Some(start) = path.collapse.first().filter(|_| deployed) else {
        return o;
    };
    let apart = shape_distance(&start.points, &eq.points).max;
    if apart <= SAME_MM {
        let _ = writeln!(
            o,
            "  the same state as the one solved from the design (within {SAME_MM} mm)"
        );
        return o;
    }
    let theirs = Relief::at(lattice, lm, &start.points);
    let _ = writeln!(
        o,
        "  also stable: the state solved from the design, energy {:.3} N mm ({:+.3}), {:.3} mm away; bumps popped through against it: {}",
        start.energy,
        start.energy - eq.energy.total(),
        apart,
        listed(&mine.popped(&theirs, lattice), "mm")
    );
    o
}

/// The line of the bumps of `points` standing the other way from the
/// design's, written to `o`; their relief, to compare other states with.
fn popped_from_design(
    o: &mut String,
    lattice: &Lattice,
    lm: &LatticeModel,
    points: &[DVec3],
) -> Relief {
    let mine = Relief::at(lattice, lm, points);
    let design = Relief::of(lattice);
    let _ = writeln!(
        o,
        "  bumps standing the other way from the design's: {}",
        listed(&design.popped(&mine, lattice), "mm")
    );
    mine
}

/// `known` for a lattice held at supports: the state reported is solved
/// from the design with the pins held; the path, walked standing free,
/// starts from the free equilibrium (docs/physics.md, "Supports").
fn held(lattice: &Lattice, lm: &LatticeModel, eq: &Equilibrium, path: &Path) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "equilibrium reported (docs/physics.md, \"Supports\"): the state solved from the design with its {} supports held, energy {:.3} N mm",
        eq.supports.len(),
        eq.energy.total()
    );
    popped_from_design(&mut o, lattice, lm, &eq.points);
    if let Some(free) = path.collapse.first() {
        let _ = writeln!(
            o,
            "  standing free (its supports released, where the deployment path starts): energy {:.3} N mm, {:.3} mm away after the best rigid fit",
            free.energy,
            shape_distance(&free.points, &eq.points).max
        );
    }
    o
}
