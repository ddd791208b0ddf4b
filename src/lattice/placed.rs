//! The assembled shape of an intrinsic lattice, for pictures: each row
//! grown on a rebuilt front is stored in its own frame (docs/math.md 7); here it
//! is moved rigidly so that its rebuilt front lies as close as possible
//! (least squares) on the row it hangs from. Where the two differ the real
//! strips bend; the picture joins them halfway.

use super::Lattice;
use glam::{DMat3, DQuat, DVec3};
use std::borrow::Cow;

impl Lattice {
    /// This lattice with every rebuilt row placed onto the one above it;
    /// an extrinsic lattice is returned as it is, borrowed (not copied:
    /// `check` of millions of cells measures the assembled lattice).
    pub fn placed(&self) -> Cow<'_, Lattice> {
        if self.extrinsic() {
            Cow::Borrowed(self)
        } else {
            Cow::Owned(self.placed_with_gaps().0)
        }
    }

    /// `placed`, with how far each rebuilt front vertex missed its row's
    /// vertex before the two were joined halfway (one list per row; empty
    /// for a row grown on the row above).
    pub(crate) fn placed_with_gaps(&self) -> (Lattice, Vec<Vec<f64>>) {
        let mut out = self.clone();
        let mut gaps = vec![Vec::new(); self.rows()];
        if self.extrinsic() {
            return (out, gaps);
        }
        let mut by_row: Vec<Vec<usize>> = vec![Vec::new(); self.rows() + 1];
        for (i, v) in self.vertices.iter().enumerate() {
            if let Some(r) = by_row.get_mut(v.key.row as usize) {
                r.push(i);
            }
        }
        // The motion of the current frame: identity until the first rebuilt row.
        let mut motion = (DQuat::IDENTITY, DVec3::ZERO);
        let apply = |m: (DQuat, DVec3), p: DVec3| m.0 * p + m.1;
        for row in 0..self.rows() {
            if let Some(front) = self.fronts.get(row).filter(|f| !f.is_empty()) {
                // The rebuilt front onto this row's vertices as already placed.
                let pairs: Vec<(DVec3, DVec3)> = by_row[row]
                    .iter()
                    .map(|&i| {
                        let col = self.vertices[i].key.col as usize;
                        (front[col], out.vertices[i].pos)
                    })
                    .collect();
                motion = rigid_fit(&pairs, motion.0);
                out.fronts[row] = front.iter().map(|&p| apply(motion, p)).collect();
                // The strips bend to meet halfway: draw both at the midpoint.
                for &i in &by_row[row] {
                    let col = self.vertices[i].key.col as usize;
                    gaps[row].push(out.fronts[row][col].distance(out.vertices[i].pos));
                    let mid = (out.fronts[row][col] + out.vertices[i].pos) / 2.0;
                    out.fronts[row][col] = mid;
                    out.vertices[i].pos = mid;
                }
            }
            for &i in &by_row[row + 1] {
                out.vertices[i].pos = apply(motion, self.vertices[i].pos);
            }
            for (c, cell) in self.cells.iter().enumerate() {
                if cell.row as usize == row {
                    out.cells[c].pivot = apply(motion, cell.pivot);
                }
            }
        }
        (out, gaps)
    }
}

/// The proper rotation and translation taking the first points of `pairs`
/// onto the second in the least-squares sense (Horn's quaternion method).
/// A pull towards `prefer` (the previous row's rotation) keeps the rows
/// facing one way: a front on a line leaves the turn about the line free,
/// and a zig-zag front fits a zig-zag of the other phase best upside down.
fn rigid_fit(pairs: &[(DVec3, DVec3)], prefer: DQuat) -> (DQuat, DVec3) {
    let n = pairs.len().max(1) as f64;
    let cp = pairs.iter().map(|p| p.0).sum::<DVec3>() / n;
    let cq = pairs.iter().map(|p| p.1).sum::<DVec3>() / n;
    let mut s = [[0.0f64; 3]; 3];
    for (p, q) in pairs {
        let (p, q) = (*p - cp, *q - cq);
        for (a, pa) in p.to_array().into_iter().enumerate() {
            for (b, qb) in q.to_array().into_iter().enumerate() {
                s[a][b] += pa * qb;
            }
        }
    }
    let spread: f64 = pairs.iter().map(|p| (p.0 - cp).length_squared()).sum();
    let pull = DMat3::from_quat(prefer);
    for (b, row) in s.iter_mut().enumerate() {
        for (a, x) in row.iter_mut().enumerate() {
            // Maximise sum q.Rp + lambda tr(R^T R_prefer): s[b][a] += lambda R_ab.
            *x += 0.05 * spread.max(1e-12) * pull.col(b)[a];
        }
    }
    let rotation = crate::rigid::horn_rotation(s);
    let rotation = if rotation.is_finite() {
        rotation
    } else {
        DQuat::IDENTITY
    };
    (rotation, cq - rotation * cp)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rigid_fit_recovers_a_rotation_and_translation() {
        let q = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 1.1);
        let t = DVec3::new(3.0, -4.0, 7.0);
        let pts = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(10.0, 1.0, 0.0),
            DVec3::new(2.0, 8.0, 1.0),
            DVec3::new(-3.0, 2.0, 5.0),
        ];
        let pairs: Vec<_> = pts.iter().map(|&p| (p, q * p + t)).collect();
        let (r, s) = rigid_fit(&pairs, q);
        for (p, target) in &pairs {
            assert!((r * *p + s).distance(*target) < 1e-9);
        }
    }

    #[test]
    fn points_on_a_line_keep_the_preferred_turn() {
        let pairs: Vec<_> = (0..5)
            .map(|i| {
                let p = DVec3::new(10.0 * i as f64, 0.0, 0.0);
                (p, p + DVec3::new(0.0, -40.0, 0.0))
            })
            .collect();
        let (r, t) = rigid_fit(&pairs, DQuat::IDENTITY);
        assert!(r.angle_between(DQuat::IDENTITY) < 1e-6, "{r:?}");
        assert!(t.distance(DVec3::new(0.0, -40.0, 0.0)) < 1e-6);
    }
}
