//! How a designer states a row's start leg: its direction and a free boundary
//! leg's length, value types shared by the design and the lattice.

use glam::DVec3;

/// A leg direction as a designer gives it for a row's start site.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Direction {
    /// `v2` at the start site in world coordinates (any length).
    Vector(DVec3),
    /// Angles in the front-local frame (see `lattice::front_frame`):
    /// `angle_deg` from the cone axis towards the growth side, then
    /// `tilt_deg` rotates out of the front's plane (3-D only).
    Angles {
        /// From the cone axis towards the growth side (degrees).
        angle_deg: f64,
        /// Out of the front's plane (degrees); must be 0 in 2-D.
        tilt_deg: f64,
    },
}

/// A free boundary leg (docs/math.md 4.5).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Leg {
    /// The leg's length (mm).
    Length(f64),
    /// The next row's boundary kappa is 0.
    #[default]
    Match,
}
