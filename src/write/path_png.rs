//! path.png: the deployment path (docs/physics.md, "The deployment path")
//! as two plots against the held opening, the energy above and the largest
//! strain below, the collapse in grey and the deploy in blue, the design
//! opening and the allowable strain marked. Drawn as a page of the drawing
//! model and rasterised as every other picture (`png`), labels in the
//! single-stroke font.

use crate::drawing::{Align, Font, Group, Ink, Item, Page, Shape};
use crate::sim::path::{Path, PathPoint};
use glam::DVec2;

/// The page (mm) and its resolution.
pub(crate) const WIDTH: f64 = 160.0;
pub(crate) const HEIGHT: f64 = 120.0;
const PX_PER_MM: f64 = 6.0;

/// Margins of a plot: left for the values, below for the openings.
const LEFT: f64 = 24.0;
const RIGHT: f64 = 8.0;

const AXIS: [u8; 3] = [60, 60, 60];
const GRID: [u8; 3] = [215, 215, 215];
const COLLAPSE: [u8; 3] = [150, 150, 150];
const DEPLOY: [u8; 3] = [20, 90, 200];
const MARK: [u8; 3] = [200, 40, 40];

/// The PNG of `path`, strains against `allow` (a fraction).
pub fn write(path: &Path, allow: f64, title: &str) -> Vec<u8> {
    super::png::write(&page(path, allow, title), PX_PER_MM, 1.0)
}

/// The plot as a drawing page.
pub(crate) fn page(path: &Path, allow: f64, title: &str) -> Page {
    let mut items = vec![text(
        DVec2::new(WIDTH / 2.0, 8.0),
        title,
        4.0,
        Align::Center,
    )];
    let x_range = (
        path.low.to_degrees().min(0.0),
        path.design.to_degrees() * 1.05,
    );
    let energy = |p: &PathPoint| p.energy;
    let strain = |p: &PathPoint| 100.0 * p.strain;
    let e_top = path.points().map(energy).fold(0.0, f64::max);
    let s_top = path.points().map(strain).fold(100.0 * allow, f64::max);
    plot(
        &mut items,
        path,
        Panel {
            top: 16.0,
            height: 36.0,
            x: x_range,
            y: (0.0, nice(e_top)),
            label: "energy (N mm)",
            value: &energy,
        },
        None,
    );
    plot(
        &mut items,
        path,
        Panel {
            top: 66.0,
            height: 36.0,
            x: x_range,
            y: (0.0, nice(s_top)),
            label: "largest strain (percent)",
            value: &strain,
        },
        Some(100.0 * allow),
    );
    items.push(text(
        DVec2::new(LEFT + (WIDTH - LEFT - RIGHT) / 2.0, HEIGHT - 4.0),
        "held opening (deg), grey: collapsing, blue: deploying",
        3.0,
        Align::Center,
    ));
    Page {
        width: WIDTH,
        height: HEIGHT,
        title: title.to_string(),
        metadata: Vec::new(),
        groups: vec![Group::new("path", items)],
        laser: None,
    }
}

/// One plot: where it stands on the page, its ranges and what it shows.
#[derive(Clone, Copy)]
struct Panel<'a> {
    top: f64,
    height: f64,
    x: (f64, f64),
    y: (f64, f64),
    label: &'a str,
    value: &'a dyn Fn(&PathPoint) -> f64,
}

impl Panel<'_> {
    fn at(&self, x: f64, y: f64) -> DVec2 {
        let w = WIDTH - LEFT - RIGHT;
        let fx = (x - self.x.0) / (self.x.1 - self.x.0).max(1e-12);
        let fy = (y - self.y.0) / (self.y.1 - self.y.0).max(1e-12);
        DVec2::new(LEFT + w * fx, self.top + self.height * (1.0 - fy))
    }
}

fn plot(items: &mut Vec<Item>, path: &Path, p: Panel<'_>, limit: Option<f64>) {
    let line = |a: DVec2, b: DVec2, ink: Ink| Item::art(ink, Shape::polyline(&[a, b], false));
    // Grid and values: five divisions of each axis.
    for k in 0..=4 {
        let f = k as f64 / 4.0;
        let y = p.y.0 + (p.y.1 - p.y.0) * f;
        let (a, b) = (p.at(p.x.0, y), p.at(p.x.1, y));
        items.push(line(a, b, Ink::line(GRID, 0.15)));
        items.push(text(
            a + DVec2::new(-1.5, 1.0),
            &value(y),
            2.8,
            Align::Right,
        ));
        let x = p.x.0 + (p.x.1 - p.x.0) * f;
        let (a, b) = (p.at(x, p.y.0), p.at(x, p.y.1));
        items.push(line(a, b, Ink::line(GRID, 0.15)));
        items.push(text(
            a + DVec2::new(0.0, 4.0),
            &format!("{x:.0}"),
            2.8,
            Align::Center,
        ));
    }
    let corners = [p.at(p.x.0, p.y.1), p.at(p.x.0, p.y.0), p.at(p.x.1, p.y.0)];
    items.push(Item::art(
        Ink::line(AXIS, 0.3),
        Shape::polyline(&corners, false),
    ));
    items.push(text(
        p.at(p.x.0, p.y.1) + DVec2::new(0.0, -2.0),
        p.label,
        3.0,
        Align::Left,
    ));
    // The design opening, and the allowable.
    let d = path.design.to_degrees();
    items.push(line(p.at(d, p.y.0), p.at(d, p.y.1), Ink::line(MARK, 0.3)));
    items.push(text(
        p.at(d, p.y.1) + DVec2::new(-1.0, 3.0),
        "design",
        2.6,
        Align::Right,
    ));
    if let Some(l) = limit {
        items.push(line(p.at(p.x.0, l), p.at(p.x.1, l), Ink::line(MARK, 0.3)));
        items.push(text(
            p.at(p.x.0, l) + DVec2::new(1.5, -1.0),
            "allowable",
            2.6,
            Align::Left,
        ));
    }
    for (way, colour) in [(&path.collapse, COLLAPSE), (&path.deploy, DEPLOY)] {
        let points: Vec<DVec2> = way
            .iter()
            .map(|q| p.at(q.theta.to_degrees(), (p.value)(q)))
            .collect();
        if points.len() > 1 {
            items.push(Item::art(
                Ink::line(colour, 0.5),
                Shape::polyline(&points, false),
            ));
        }
        for &q in &points {
            items.push(Item::art(
                Ink::fill(colour),
                Shape::Circle {
                    center: q,
                    radius: 0.7,
                },
            ));
        }
    }
}

fn text(at: DVec2, s: &str, size: f64, align: Align) -> Item {
    Item::art(
        Ink::line(AXIS, 0.25),
        Shape::Text {
            at,
            size,
            text: s.to_string(),
            font: Font::Regular,
            align,
        },
    )
}

/// A round top for an axis at or above `x`: 1, 2 or 5 times a power of 10
/// (1 for nothing to show).
fn nice(x: f64) -> f64 {
    if !(x > 1e-9) || !x.is_finite() {
        return 1.0;
    }
    let p = 10f64.powf(x.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&t| t >= x * (1.0 - 1e-12))
        .unwrap_or(10.0 * p)
}

/// An axis value in few digits.
fn value(y: f64) -> String {
    if y == 0.0 {
        "0".into()
    } else if y.abs() >= 10.0 {
        format!("{y:.0}")
    } else if y.abs() >= 1.0 {
        format!("{y:.1}")
    } else {
        format!("{y:.2}")
    }
}

#[cfg(test)]
mod tests {
    use super::nice;

    #[test]
    fn axis_tops_are_round_and_above() {
        for (x, top) in [
            (0.0, 1.0),
            (0.3, 0.5),
            (1.0, 1.0),
            (1.2, 2.0),
            (7.0, 10.0),
            (150.3, 200.0),
        ] {
            assert!((nice(x) - top).abs() < 1e-9, "{x}: {}", nice(x));
        }
    }
}
