//! The analytic families of `[target]` (docs/design.md) as parametric
//! surfaces over the unit square, triangulated finely enough that every
//! triangle lies within 0.05 % of D of the surface (half the 0.1 % asked):
//! a triangle of circumradius c on a surface whose smallest radius of
//! curvature is rho strays about c^2 / (2 rho) from it, and a grid cell
//! of sides at most h splits into two right triangles with c^2 <= h^2 / 2,
//! so h = sqrt(4 rho tol) is enough.

use super::mesh::Mesh;
use glam::{DMat3, DVec2, DVec3};
use std::f64::consts::{PI, TAU};

/// Share of D the triangles may stray from the surface: half of 0.1 %.
pub(crate) const TOLERANCE: f64 = 0.0005;
/// Grid lines per parameter at most; a family that needs more (a very
/// thin tube) is refused rather than meshed coarser.
pub(crate) const MAX_LINES: usize = 1500;

/// An analytic family with its parameters in mm (angles in degrees).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Family {
    Disk {
        radius: f64,
    },
    SphereCap {
        radius: f64,
        height: f64,
    },
    SpheroidCap {
        axes: DVec3,
        height: f64,
    },
    Paraboloid {
        radius: f64,
        depth: f64,
    },
    Saddle {
        width: f64,
        length: f64,
        height: f64,
    },
    /// The hyperbolic paraboloid z = height (r / radius)^2 cos 2t between
    /// the circles of radius `hole` and `radius` in plan: a pringle band.
    SaddleRing {
        radius: f64,
        hole: f64,
        height: f64,
    },
    Cylinder {
        radius: f64,
        length: f64,
        angle: f64,
    },
    Torus {
        radius: f64,
        tube: f64,
    },
    /// Profile points (r, z), revolved about z.
    Revolution {
        profile: Vec<DVec2>,
    },
    /// Heights on a grid of `heights[row][col]` over width (x) by length (y).
    HeightField {
        width: f64,
        length: f64,
        heights: Vec<Vec<f64>>,
    },
}

/// How the unit square of parameters closes up: u round (a full turn),
/// v round, and rows of v that are one point (a cap's apex).
#[derive(Clone, Copy, Debug, Default)]
struct Closing {
    wrap_u: bool,
    wrap_v: bool,
    pole_v0: bool,
    pole_v1: bool,
}

impl Family {
    pub(crate) fn name(&self) -> &'static str {
        match self {
            Family::Disk { .. } => "disk",
            Family::SphereCap { .. } => "sphere-cap",
            Family::SpheroidCap { .. } => "spheroid-cap",
            Family::Paraboloid { .. } => "paraboloid",
            Family::Saddle { .. } => "saddle",
            Family::SaddleRing { .. } => "saddle-ring",
            Family::Cylinder { .. } => "cylinder",
            Family::Torus { .. } => "torus",
            Family::Revolution { .. } => "revolution",
            Family::HeightField { .. } => "height-field",
        }
    }

    /// The point at parameters (u, v) in the unit square, in the family's
    /// own frame (z up; caps and bowls rise from z = 0).
    pub(crate) fn point(&self, u: f64, v: f64) -> DVec3 {
        let around = |rho: f64, z: f64| DVec3::new(rho * (TAU * u).cos(), rho * (TAU * u).sin(), z);
        match self {
            Family::Disk { radius } => around(radius * v, 0.0),
            Family::SphereCap { radius, height } => {
                let phi = cap_angle(*radius, *height) * v;
                around(radius * phi.sin(), radius * phi.cos() - (radius - height))
            }
            Family::SpheroidCap { axes, height } => {
                let phi = cap_angle(axes.z, *height) * v;
                let (s, t) = ((TAU * u).sin(), (TAU * u).cos());
                DVec3::new(
                    axes.x * phi.sin() * t,
                    axes.y * phi.sin() * s,
                    axes.z * phi.cos() - (axes.z - height),
                )
            }
            Family::Paraboloid { radius, depth } => around(radius * v, depth * v * v),
            Family::Saddle {
                width,
                length,
                height,
            } => {
                let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
                DVec3::new(0.5 * width * x, 0.5 * length * y, height * (x * x - y * y))
            }
            Family::SaddleRing {
                radius,
                hole,
                height,
            } => {
                let rho = hole + (radius - hole) * v;
                let z = height * (rho / radius).powi(2) * (2.0 * TAU * u).cos();
                around(rho, z)
            }
            Family::Cylinder {
                radius,
                length,
                angle,
            } => {
                let theta = angle.to_radians() * (v - 0.5);
                DVec3::new(
                    length * (u - 0.5),
                    radius * theta.sin(),
                    radius * theta.cos(),
                )
            }
            Family::Torus { radius, tube } => {
                let psi = TAU * v;
                around(radius + tube * psi.cos(), tube * psi.sin())
            }
            Family::Revolution { profile } => {
                let q = along(profile, v);
                around(q.x, q.y)
            }
            Family::HeightField {
                width,
                length,
                heights,
            } => {
                let (rows, cols) = (heights.len(), heights[0].len());
                let (i, j) = (
                    (u * (cols - 1) as f64).round() as usize,
                    (v * (rows - 1) as f64).round() as usize,
                );
                DVec3::new(
                    width * (u - 0.5),
                    length * (v - 0.5),
                    heights[j.min(rows - 1)][i.min(cols - 1)],
                )
            }
        }
    }

    fn closing(&self) -> Closing {
        let cap = Closing {
            wrap_u: true,
            pole_v0: true,
            ..Closing::default()
        };
        match self {
            // A cap as high as the whole sphere closes at its bottom pole.
            Family::SphereCap { radius, height } => Closing {
                pole_v1: *height >= 2.0 * radius,
                ..cap
            },
            Family::SpheroidCap { axes, height } => Closing {
                pole_v1: *height >= 2.0 * axes.z,
                ..cap
            },
            Family::Disk { .. } | Family::Paraboloid { .. } => cap,
            Family::Saddle { .. } | Family::HeightField { .. } => Closing::default(),
            Family::Cylinder { angle, .. } => Closing {
                wrap_v: *angle >= 360.0,
                ..Closing::default()
            },
            Family::SaddleRing { .. } => Closing {
                wrap_u: true,
                ..Closing::default()
            },
            Family::Torus { .. } => Closing {
                wrap_u: true,
                wrap_v: true,
                ..Closing::default()
            },
            Family::Revolution { profile } => Closing {
                wrap_u: true,
                pole_v0: profile[0].x == 0.0,
                pole_v1: profile[profile.len() - 1].x == 0.0,
                ..Closing::default()
            },
        }
    }

    /// A lower bound on the largest extent D, for the tolerance.
    fn least_extent(&self) -> f64 {
        match self {
            Family::Disk { radius } | Family::Paraboloid { radius, .. } => 2.0 * radius,
            Family::SphereCap { radius, height } => {
                (2.0 * radius * cap_angle(*radius, *height).min(PI / 2.0).sin()).max(*height)
            }
            Family::SpheroidCap { axes, height } => {
                (2.0 * axes.x.min(axes.y) * cap_angle(axes.z, *height).min(PI / 2.0).sin())
                    .max(*height)
            }
            Family::Saddle { width, length, .. } | Family::HeightField { width, length, .. } => {
                width.max(*length)
            }
            Family::Cylinder { length, .. } => *length,
            Family::SaddleRing { radius, .. } => 2.0 * radius,
            Family::Torus { radius, tube } => 2.0 * (radius + tube),
            Family::Revolution { profile } => 2.0 * profile.iter().map(|p| p.x).fold(0.0, f64::max),
        }
    }

    /// The smallest radius of curvature (mm; infinite where flat), and the
    /// longest lines of constant v and of constant u (mm).
    fn curvature_and_lengths(&self) -> (f64, f64, f64) {
        match self {
            Family::Disk { radius } => (*radius, TAU * radius, *radius),
            Family::SphereCap { radius, height } => {
                let phi = cap_angle(*radius, *height);
                (
                    *radius,
                    TAU * radius * phi.min(PI / 2.0).sin(),
                    radius * phi,
                )
            }
            Family::SpheroidCap { axes, height } => {
                let (lo, hi) = (axes.min_element(), axes.max_element());
                let phi = cap_angle(axes.z, *height);
                (lo * lo / hi, TAU * axes.x.max(axes.y), hi * phi)
            }
            Family::Paraboloid { radius, depth } => {
                let apex = radius * radius / (2.0 * depth);
                (apex.min(*radius), TAU * radius, radius + 2.0 * depth)
            }
            Family::Saddle {
                width,
                length,
                height,
            } => {
                let rho = width.min(*length).powi(2) / (8.0 * height.abs().max(f64::MIN_POSITIVE));
                (rho, width + 2.0 * height.abs(), length + 2.0 * height.abs())
            }
            Family::SaddleRing {
                radius,
                hole,
                height,
            } => {
                // z = k (x^2 - y^2), k = height / radius^2: its tightest
                // radius of curvature, 1 / (2 k), is at the centre.
                let rho = radius * radius / (2.0 * height.abs().max(f64::MIN_POSITIVE));
                let wave = 8.0 * height.abs();
                (rho, TAU * radius + wave, radius - hole + 2.0 * height.abs())
            }
            Family::Cylinder {
                radius,
                length,
                angle,
            } => (*radius, *length, radius * angle.to_radians()),
            Family::Torus { radius, tube } => {
                (tube.min(radius - tube), TAU * (radius + tube), TAU * tube)
            }
            Family::Revolution { profile } => {
                let r = profile.iter().map(|p| p.x).fold(0.0, f64::max);
                let length: f64 = profile.windows(2).map(|w| w[0].distance(w[1])).sum();
                (r, TAU * r, length)
            }
            Family::HeightField { .. } => (f64::INFINITY, 0.0, 0.0),
        }
    }

    /// Grid lines along u and v: enough for `TOLERANCE` of D, or None when
    /// more than `MAX_LINES` would be needed.
    fn lines(&self) -> Option<(usize, usize)> {
        if let Family::HeightField { heights, .. } = self {
            // The grid's own triangles are the surface.
            return Some((heights[0].len() - 1, heights.len() - 1));
        }
        let tol = TOLERANCE * self.least_extent();
        let (rho, lu, lv) = self.curvature_and_lengths();
        let h = (4.0 * rho * tol).sqrt().min(self.least_extent() / 8.0);
        let closing = self.closing();
        let least_u = if closing.wrap_u { 12 } else { 4 };
        let least_v = if closing.wrap_v { 12 } else { 4 };
        let nu = ((lu / h).ceil() as usize).max(least_u);
        let nv = ((lv / h).ceil() as usize).max(least_v);
        (nu <= MAX_LINES && nv <= MAX_LINES).then_some((nu, nv))
    }

    /// The family triangulated, turned (degrees about x, then y, then z) and
    /// moved to `at`; None when it needs more than `MAX_LINES` lines.
    pub(crate) fn mesh(&self, turn: DVec3, at: DVec3) -> Option<Mesh> {
        let (nu, nv) = self.lines()?;
        let rotation = DMat3::from_rotation_z(turn.z.to_radians())
            * DMat3::from_rotation_y(turn.y.to_radians())
            * DMat3::from_rotation_x(turn.x.to_radians());
        let profile_v = self.refined_profile(nv);
        let mut mesh = grid(
            nu,
            profile_v.as_ref().map_or(nv, |p| p.len() - 1),
            self.closing(),
            |u, v, j| {
                // A revolution's rows sit on its refined profile's points.
                let v = profile_v.as_ref().map_or(v, |p| p[j]);
                self.point(u, v)
            },
        );
        for p in &mut mesh.positions {
            *p = rotation * *p + at;
        }
        Some(mesh)
    }

    /// A revolution's rows: the parameters of its profile points, each
    /// segment split into pieces no longer than the grid's step.
    fn refined_profile(&self, nv: usize) -> Option<Vec<f64>> {
        let Family::Revolution { profile } = self else {
            return None;
        };
        let total: f64 = profile.windows(2).map(|w| w[0].distance(w[1])).sum();
        let step = total / nv as f64;
        let mut out = vec![0.0];
        let mut s = 0.0;
        for w in profile.windows(2) {
            let len = w[0].distance(w[1]);
            let pieces = (len / step).ceil().max(1.0) as usize;
            for k in 1..=pieces {
                out.push((s + len * k as f64 / pieces as f64) / total);
            }
            s += len;
        }
        Some(out)
    }
}

/// The polar angle of a cap of `height` on a sphere (or spheroid axis) of
/// `radius`: cos phi = 1 - h / r.
fn cap_angle(radius: f64, height: f64) -> f64 {
    (1.0 - height / radius).clamp(-1.0, 1.0).acos()
}

/// The point at share `v` of the length along a polyline.
fn along(profile: &[DVec2], v: f64) -> DVec2 {
    let total: f64 = profile.windows(2).map(|w| w[0].distance(w[1])).sum();
    let mut left = v.clamp(0.0, 1.0) * total;
    for w in profile.windows(2) {
        let len = w[0].distance(w[1]);
        if left <= len {
            return w[0].lerp(w[1], left / len.max(f64::MIN_POSITIVE));
        }
        left -= len;
    }
    profile[profile.len() - 1]
}

/// A grid of nu x nv cells over the unit square, each split into two
/// triangles, closed up as `closing` says; `f(u, v, row)` places a point.
fn grid(nu: usize, nv: usize, closing: Closing, f: impl Fn(f64, f64, usize) -> DVec3) -> Mesh {
    let cols = if closing.wrap_u { nu } else { nu + 1 };
    let rows = if closing.wrap_v { nv } else { nv + 1 };
    let mut positions = Vec::with_capacity(cols * rows);
    let mut row_start = Vec::with_capacity(rows);
    for j in 0..rows {
        row_start.push(positions.len() as u32);
        let pole = (j == 0 && closing.pole_v0) || (j == nv && closing.pole_v1);
        let v = j as f64 / nv as f64;
        for i in 0..if pole { 1 } else { cols } {
            positions.push(f(i as f64 / nu as f64, v, j));
        }
    }
    let index = |i: usize, j: usize| -> u32 {
        let j = j % rows;
        let width = if j + 1 < rows {
            row_start[j + 1]
        } else {
            positions.len() as u32
        } - row_start[j];
        row_start[j] + (i % cols).min(width as usize - 1) as u32
    };
    let mut triangles = Vec::with_capacity(2 * nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            for t in [[a, b, c], [a, c, d]] {
                if t[0] != t[1] && t[1] != t[2] && t[2] != t[0] {
                    triangles.push(t);
                }
            }
        }
    }
    Mesh {
        positions,
        triangles,
    }
}
