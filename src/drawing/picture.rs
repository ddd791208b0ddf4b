//! Pictures of the deployed lattice: an orthographic view fitted into a box
//! on a page, rods drawn far to near with a depth cue, pivots as dots.

use super::{Ink, Item, Shape};
use crate::lattice::Lattice;
use glam::{DVec2, DVec3};

/// An orthographic camera: page x along `right`, page y down along `-up`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub(crate) right: DVec3,
    pub(crate) up: DVec3,
    /// Where the viewer looks; larger `depth` is farther away.
    pub forward: DVec3,
}

impl Camera {
    /// Planar lattices from above; helices from the side, their seed turn
    /// at the top, looking 35 degrees down into them; other lattices in
    /// space along their mean facet normal, tilted 30 degrees so their
    /// relief shows.
    pub fn for_lattice(lattice: &Lattice) -> Self {
        Self::tilted(lattice, 50.0)
    }

    /// A lattice built flat, seen square on from its stacking side (no
    /// tilt), so its rows do not hide one another; otherwise as
    /// `for_lattice`.
    pub(crate) fn face_on(lattice: &Lattice) -> Self {
        if lattice.dim == 3 && lattice.kind != crate::lattice::Kind::Helix {
            Self::tilted(lattice, 0.0)
        } else {
            Self::for_lattice(lattice)
        }
    }

    /// Looking along `forward` with `up` up the page (made square to
    /// forward); None when they are parallel.
    pub(crate) fn looking(forward: DVec3, up: DVec3) -> Option<Self> {
        let forward = forward.try_normalize()?;
        let up = (up - up.dot(forward) * forward).try_normalize()?;
        Some(Self {
            right: forward.cross(up),
            up,
            forward,
        })
    }

    fn tilted(lattice: &Lattice, tilt_deg: f64) -> Self {
        if lattice.dim == 2 {
            return Self {
                right: DVec3::X,
                up: DVec3::Y,
                forward: DVec3::NEG_Z,
            };
        }
        if lattice.kind == crate::lattice::Kind::Helix
            && let Some(camera) = Self::down_the_axis(lattice)
        {
            return camera;
        }
        let normal: DVec3 = lattice
            .cells
            .iter()
            .map(|c| {
                let [ul, ur, ll, _] = lattice.corners(c);
                (ur - ul).cross(ll - ul).normalize_or_zero()
            })
            .sum();
        let n = if normal.length() > 1e-6 * lattice.cells.len() as f64 {
            normal.normalize()
        } else {
            DVec3::Z
        };
        let forward = -n;
        let along = lattice
            .vertices
            .get(1)
            .map_or(DVec3::X, |v| v.pos - lattice.vertices[0].pos);
        let right = (along - along.dot(forward) * forward)
            .try_normalize()
            .unwrap_or_else(|| forward.any_orthonormal_vector());
        let up = right.cross(forward);
        // Seed row at the top, as in planar pictures: if growth runs up the
        // page, turn the view half a turn about `right` (a rotation, never a
        // mirror image).
        let mean = |vs: &[crate::lattice::Vertex]| {
            vs.iter().map(|v| v.pos).sum::<DVec3>() / vs.len().max(1) as f64
        };
        let seed = mean(&lattice.vertices[..(lattice.width + 1).min(lattice.vertices.len())]);
        let (forward, up) = if (seed - mean(&lattice.vertices)).dot(up) < 0.0 {
            (-forward, -up)
        } else {
            (forward, up)
        };
        let tilt = tilt_deg.to_radians();
        let forward = tilt.cos() * forward + tilt.sin() * up;
        Self {
            right,
            up: right.cross(forward),
            forward,
        }
    }

    /// A helix's growth runs down its axis (from the seed turn's centre to
    /// the whole lattice's): view it from the side, seed turn up, from 35
    /// degrees above. None when the axis is not defined.
    fn down_the_axis(lattice: &Lattice) -> Option<Self> {
        let n = (lattice.width + 1).min(lattice.vertices.len());
        let mean = |vs: &[crate::lattice::Vertex]| {
            vs.iter().map(|v| v.pos).sum::<DVec3>() / vs.len().max(1) as f64
        };
        let seed = mean(&lattice.vertices[..n]);
        // The seed turn's plane normal, pointing the way the helix grows.
        let turn = &lattice.vertices[..n];
        let normal: DVec3 = turn
            .iter()
            .zip(turn.iter().skip(1))
            .map(|(a, b)| (a.pos - seed).cross(b.pos - seed))
            .sum();
        let normal = normal.try_normalize()?;
        let growth = mean(&lattice.vertices) - seed;
        let axis = if growth.dot(normal) < 0.0 {
            -normal
        } else {
            normal
        };
        let along = lattice.vertices[0].pos - seed;
        let right = (along - along.dot(axis) * axis).try_normalize()?;
        let side = axis.cross(right);
        let look = 35f64.to_radians();
        let forward = look.cos() * side + look.sin() * axis;
        // right x forward points down the axis; half a turn about `forward`
        // (a rotation, not a mirror) puts the seed turn at the top.
        Some(Self {
            right: -right,
            up: -right.cross(forward),
            forward,
        })
    }

    pub(crate) fn project(&self, p: DVec3) -> DVec2 {
        DVec2::new(p.dot(self.right), -p.dot(self.up))
    }
}

/// How to draw the rods of one cell (None hides them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RodStyle {
    pub(crate) colour: [u8; 3],
    /// Stroke width in mm on the page.
    pub(crate) width: f64,
}

/// A camera view fitted into a box of the page.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    camera: Camera,
    scale: f64,
    offset: DVec2,
    depth: (f64, f64),
}

impl Fit {
    /// Fit the whole lattice into the box at `origin` (top-left) of `size` mm.
    pub(crate) fn new(lattice: &Lattice, camera: Camera, origin: DVec2, size: DVec2) -> Self {
        let points = lattice
            .vertices
            .iter()
            .map(|v| v.pos)
            .chain(lattice.cells.iter().map(|c| c.pivot));
        Self::around(points, camera, origin, size)
    }

    /// Fit these points into the box at `origin` (top-left) of `size` mm.
    pub(crate) fn around(
        points: impl Iterator<Item = DVec3>,
        camera: Camera,
        origin: DVec2,
        size: DVec2,
    ) -> Self {
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        let (mut near, mut far) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in points {
            let q = camera.project(p);
            lo = lo.min(q);
            hi = hi.max(q);
            let d = p.dot(camera.forward);
            near = near.min(d);
            far = far.max(d);
        }
        if !lo.is_finite() {
            (lo, hi, near, far) = (DVec2::ZERO, DVec2::ONE, 0.0, 1.0);
        }
        let extent = (hi - lo).max(DVec2::splat(1e-9));
        let scale = (size.x / extent.x).min(size.y / extent.y);
        let offset = origin + (size - extent * scale) / 2.0 - lo * scale;
        Self {
            camera,
            scale,
            offset,
            depth: (near, far),
        }
    }

    pub(crate) fn map(&self, p: DVec3) -> DVec2 {
        self.offset + self.camera.project(p) * self.scale
    }

    /// 0 at the nearest point, 1 at the farthest.
    fn depth(&self, p: DVec3) -> f64 {
        let (near, far) = self.depth;
        if far - near < 1e-9 {
            0.0
        } else {
            (p.dot(self.camera.forward) - near) / (far - near)
        }
    }

    /// Millimetres on the page per millimetre of the lattice.
    pub(crate) fn scale(&self) -> f64 {
        self.scale
    }
}

/// Blend a colour towards white by `t` (0 keeps it, 1 is white).
fn pale(c: [u8; 3], t: f64) -> [u8; 3] {
    c.map(|v| (v as f64 + (255.0 - v as f64) * t).round() as u8)
}

pub(crate) const PIVOT: [u8; 3] = [230, 120, 20];
pub(crate) const VERTEX: [u8; 3] = [30, 90, 200];

/// Rods of every cell `style` shows, far ones first and paler, then dots at
/// the pivots and vertices of the cells shown.
pub(crate) fn lattice_picture(
    lattice: &Lattice,
    fit: &Fit,
    style: impl Fn(usize) -> Option<RodStyle>,
    dots: f64,
) -> Vec<Item> {
    let shown: Vec<usize> = (0..lattice.cells.len())
        .filter(|&c| style(c).is_some())
        .collect();
    let mut items = rods(lattice, fit, &shown, style);
    if dots > 0.0 {
        let mut shown_vertices = vec![false; lattice.vertices.len()];
        for &c in &shown {
            let cell = &lattice.cells[c];
            for v in cell.corner_ids() {
                shown_vertices[v as usize] = true;
            }
        }
        let vertices: Vec<usize> = (0..lattice.vertices.len())
            .filter(|&v| shown_vertices[v])
            .collect();
        items.extend(pivots_and_vertices(lattice, fit, &shown, &vertices, dots));
    }
    items
}

/// The rods of `cells` that `style` shows, far ones first and paler.
pub(crate) fn rods(
    lattice: &Lattice,
    fit: &Fit,
    cells: &[usize],
    style: impl Fn(usize) -> Option<RodStyle>,
) -> Vec<Item> {
    let mut rods: Vec<(f64, Item)> = Vec::with_capacity(2 * cells.len());
    for &c in cells {
        let Some(s) = style(c) else { continue };
        for rod in lattice.cell_rods(c) {
            // Through the pivot: straight in an extrinsic lattice, bent
            // where a placed intrinsic lattice's strips bend.
            let [a, p, b] = rod.hole_pos;
            let depth = fit.depth((a + b) / 2.0);
            let ink = Ink::line(pale(s.colour, 0.55 * depth), s.width * (1.0 - 0.35 * depth));
            rods.push((
                depth,
                Item::art(
                    ink,
                    Shape::polyline(&[fit.map(a), fit.map(p), fit.map(b)], false),
                ),
            ));
        }
    }
    rods.sort_by(|a, b| b.0.total_cmp(&a.0));
    rods.into_iter().map(|(_, i)| i).collect()
}

/// The rods of `cells` as a maker stacks them: each cell's rod A, then a
/// short white gap around its scissor pivot, then rod B on top, so the
/// picture shows which strip lies over which at every crossing. Cells are
/// drawn far to near.
pub(crate) fn crossing_rods(
    lattice: &Lattice,
    fit: &Fit,
    cells: &[usize],
    style: impl Fn(usize) -> Option<RodStyle>,
) -> Vec<Item> {
    let mut drawn: Vec<(f64, Vec<Item>)> = Vec::with_capacity(cells.len());
    for &c in cells {
        let Some(s) = style(c) else { continue };
        let [a, b] = lattice.cell_rods(c);
        let depth = fit.depth(lattice.cells[c].pivot);
        let ink = Ink::line(pale(s.colour, 0.55 * depth), s.width * (1.0 - 0.35 * depth));
        let path = |r: &crate::lattice::Rod| {
            let [p, q, t] = r.hole_pos;
            Shape::polyline(&[fit.map(p), fit.map(q), fit.map(t)], false)
        };
        // The gap: rod B's stretch around the pivot, in white and wider.
        let [p, q, t] = b.hole_pos.map(|x| fit.map(x));
        let reach = 3.5 * s.width + 1.0;
        let toward = |x: DVec2| q + (x - q).normalize_or_zero() * reach.min(0.45 * x.distance(q));
        let gap = Item::art(
            Ink::line([255, 255, 255], ink.width + 2.0 * (0.4 + 0.3 * s.width)),
            Shape::polyline(&[toward(p), q, toward(t)], false),
        );
        drawn.push((
            depth,
            vec![Item::art(ink, path(&a)), gap, Item::art(ink, path(&b))],
        ));
    }
    drawn.sort_by(|a, b| b.0.total_cmp(&a.0));
    drawn.into_iter().flat_map(|(_, i)| i).collect()
}

/// Dots of radius `radius` at the pivots of `cells`, then at `vertices`.
pub(crate) fn pivots_and_vertices(
    lattice: &Lattice,
    fit: &Fit,
    cells: &[usize],
    vertices: &[usize],
    radius: f64,
) -> Vec<Item> {
    let dot = |p: DVec3, colour| {
        Item::art(
            Ink::fill(colour),
            Shape::Circle {
                center: fit.map(p),
                radius,
            },
        )
    };
    cells
        .iter()
        .map(|&c| dot(lattice.cells[c].pivot, PIVOT))
        .chain(
            vertices
                .iter()
                .map(|&v| dot(lattice.vertices[v].pos, VERTEX)),
        )
        .collect()
}

/// The preview picture: the deployed lattice filling a page, with a title.
pub fn preview(lattice: &Lattice, strip_width: f64, title: &str) -> super::Page {
    preview_captioned(lattice, strip_width, title, None)
}

/// `preview` with a caption under the title saying which shape is shown
/// (the design or the simulated deployed shape).
pub fn preview_captioned(
    lattice: &Lattice,
    strip_width: f64,
    title: &str,
    caption: Option<&str>,
) -> super::Page {
    let (w, h) = (160.0, 120.0);
    // The caption's line is kept clear of the drawing.
    let below = if caption.is_some() { 21.0 } else { 18.0 };
    let fit = Fit::new(
        lattice,
        Camera::for_lattice(lattice),
        DVec2::new(6.0, 12.0),
        DVec2::new(w - 12.0, h - below),
    );
    let width = (0.7 * fit.scale() * strip_width).clamp(0.25, 1.5);
    let mut items = lattice_picture(
        lattice,
        &fit,
        |_| {
            Some(RodStyle {
                colour: [40, 40, 40],
                width,
            })
        },
        width * 0.9,
    );
    items.push(Item::art(
        Ink::fill([40, 40, 40]),
        Shape::Text {
            at: DVec2::new(6.0, 8.0),
            size: 4.0,
            text: crate::font::fitted(title, super::text::CAP_OF_SIZE * 4.0, w - 12.0),
            font: super::Font::Bold,
            align: super::Align::Left,
        },
    ));
    if let Some(caption) = caption {
        items.push(Item::art(
            Ink::fill([90, 90, 90]),
            Shape::Text {
                at: DVec2::new(6.0, h - 3.0),
                size: 2.6,
                text: caption.to_string(),
                font: super::Font::Regular,
                align: super::Align::Left,
            },
        ));
    }
    super::Page {
        width: w,
        height: h,
        title: title.to_string(),
        metadata: Vec::new(),
        laser: None,
        groups: vec![super::Group::new("preview", items)],
    }
}
