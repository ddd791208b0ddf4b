//! Seed-point generators: what a designer types instead of every point.

use glam::DVec3;

/// `cells + 1` evenly spaced points from `from` to `to`.
pub fn line(from: DVec3, to: DVec3, cells: usize) -> Vec<DVec3> {
    (0..=cells)
        .map(|k| from.lerp(to, k as f64 / cells as f64))
        .collect()
}

/// Which coordinate plane an arc lies in (3-D seeds).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plane {
    Xy,
    Xz,
    Yz,
}

impl Plane {
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "xy" => Some(Plane::Xy),
            "xz" => Some(Plane::Xz),
            "yz" => Some(Plane::Yz),
            _ => None,
        }
    }

    fn axes(self) -> (DVec3, DVec3) {
        match self {
            Plane::Xy => (DVec3::X, DVec3::Y),
            Plane::Xz => (DVec3::X, DVec3::Z),
            Plane::Yz => (DVec3::Y, DVec3::Z),
        }
    }
}

/// `cells + 1` points on a circular arc from angle `from_deg` to `to_deg`
/// (counter-clockwise when `to > from`), measured in `plane` from its first axis.
pub fn arc(
    center: DVec3,
    radius: f64,
    from_deg: f64,
    to_deg: f64,
    cells: usize,
    plane: Plane,
) -> Vec<DVec3> {
    let (e1, e2) = plane.axes();
    (0..=cells)
        .map(|k| {
            let a = (from_deg + (to_deg - from_deg) * k as f64 / cells as f64).to_radians();
            center + radius * (a.cos() * e1 + a.sin() * e2)
        })
        .collect()
}

/// Each segment of the polyline split into `per_segment` equal edges.
pub fn polyline(points: &[DVec3], per_segment: usize) -> Vec<DVec3> {
    let mut out = vec![points[0]];
    for pair in points.windows(2) {
        out.extend((1..=per_segment).map(|k| pair[0].lerp(pair[1], k as f64 / per_segment as f64)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generators_produce_cells_plus_one_points() {
        assert_eq!(line(DVec3::ZERO, DVec3::X * 10.0, 5).len(), 6);
        let a = arc(DVec3::ZERO, 2.0, 0.0, 90.0, 3, Plane::Xz);
        assert_eq!(a.len(), 4);
        assert!((a[3] - DVec3::new(0.0, 0.0, 2.0)).length() < 1e-12);
        let p = polyline(&[DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0)], 2);
        assert_eq!(p.len(), 5);
        assert_eq!(p[2], DVec3::X);
    }
}
