//! Rebuilt fronts for intrinsic (bent-facet) growth (docs/math.md 7): a new front
//! with the same edge lengths (and so the same kappa and z) as the current
//! one, from generators a designer writes in the recipe.

use super::saddle::{Saddle, lay};
use glam::{DQuat, DVec3};

/// Rotate the front beyond vertex `at` rigidly about an axis through it.
#[derive(Clone, Debug, PartialEq)]
pub struct PivotMove {
    pub(crate) at: usize,
    /// Rotation axis; `None` means +z (the only choice in 2-D).
    pub(crate) axis: Option<DVec3>,
    pub(crate) angle_deg: f64,
}

/// Rotate the vertices strictly between `from` and `to` about the line
/// through those two vertices. Keeps a closed front closed.
#[derive(Clone, Debug, PartialEq)]
pub struct Crank {
    /// Front index of the first vertex on the rotation axis.
    pub from: usize,
    /// Front index of the second vertex on the rotation axis (at least two past
    /// `from`; on a loop it may be the front length, meaning vertex 0).
    pub to: usize,
    /// Rotation angle about the axis from `from` to `to` (degrees).
    pub angle_deg: f64,
}

/// How a row's front is rebuilt before the row grows on it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrontMoves {
    /// 2-D: turning angle at each interior vertex 1..m-1 (degrees), keeping
    /// the heading of the first edge.
    pub turn: Option<Vec<f64>>,
    /// 3-D: bending angle at each interior vertex (degrees)...
    pub bend: Option<Vec<f64>>,
    /// ...and the torsion angle that turns the bending plane (degrees), in a
    /// frame transported along the front.
    pub twist: Option<Vec<f64>>,
    /// 3-D loops: the front laid on a saddle in its own frame (in place of
    /// `turn`, `bend` and `twist`; src/lattice/saddle.rs).
    pub saddle: Option<Saddle>,
    /// Rigid rotations of the front beyond a vertex, applied after `turn`,
    /// `bend`/`twist` or `saddle`, in order.
    pub pivots: Vec<PivotMove>,
    /// Crankshaft rotations of the vertices between two others, applied last,
    /// in order.
    pub cranks: Vec<Crank>,
}

/// Why a rebuilt front is refused, for the recipe layer to locate.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FrontError {
    pub(crate) message: String,
    pub(crate) hint: String,
}

pub(crate) fn refuse(message: String, hint: &str) -> FrontError {
    FrontError {
        message,
        hint: hint.to_string(),
    }
}

/// A per-vertex angle list: one value per interior vertex, or one for all.
fn per_vertex(list: &[f64], count: usize, name: &str) -> Result<Vec<f64>, FrontError> {
    match list.len() {
        1 => Ok(vec![list[0]; count]),
        n if n == count => Ok(list.to_vec()),
        n => Err(refuse(
            format!("front.{name} has {n} angles, but the front has {count} interior vertices"),
            "give one angle per interior vertex, or a single angle for all",
        )),
    }
}

/// Rebuild `front` (closed: indices wrap, the last edge joins the last
/// vertex to the first). Edge lengths are kept exactly by construction;
/// a closed front must still close after the moves.
pub(crate) fn rebuild(
    front: &[DVec3],
    closed: bool,
    dim: usize,
    moves: &FrontMoves,
) -> Result<Vec<DVec3>, FrontError> {
    let n = front.len();
    let edges = if closed { n } else { n - 1 };
    let edge = |j: usize| front[(j + 1) % n] - front[j];
    // Vertices at which the heading may turn: 1..edges-1 (an open front's
    // ends have none; a closed front keeps its closing vertex 0 fixed).
    let interior = edges - 1;
    let mut out = front.to_vec();
    if let Some(s) = moves.saddle {
        out = saddled(front, closed, dim, moves, s)?;
    } else if moves.turn.is_some() || moves.bend.is_some() || moves.twist.is_some() {
        let mut dirs = vec![edge(0).normalize()];
        if dim == 2 {
            if moves.bend.is_some() || moves.twist.is_some() {
                return Err(refuse(
                    "front.bend and front.twist need a 3-D lattice".into(),
                    "use front.turn in 2-D",
                ));
            }
            let turn = per_vertex(moves.turn.as_deref().unwrap_or(&[0.0]), interior, "turn")?;
            let mut heading = dirs[0].y.atan2(dirs[0].x);
            for tau in turn {
                heading += tau.to_radians();
                dirs.push(DVec3::new(heading.cos(), heading.sin(), 0.0));
            }
        } else {
            if moves.turn.is_some() {
                return Err(refuse(
                    "front.turn is for planar lattices".into(),
                    "use front.bend and front.twist in 3-D",
                ));
            }
            let bend = per_vertex(moves.bend.as_deref().unwrap_or(&[0.0]), interior, "bend")?;
            let twist = per_vertex(moves.twist.as_deref().unwrap_or(&[0.0]), interior, "twist")?;
            // Transported frame: start with the growth-side normal of the
            // first edge (or any normal if the edge is vertical).
            let e0 = dirs[0];
            let mut normal = e0.cross(DVec3::Z);
            normal = if normal.length() > 1e-9 {
                normal.normalize()
            } else {
                e0.any_orthonormal_vector()
            };
            for (b, w) in bend.into_iter().zip(twist) {
                let e = *dirs.last().expect("first edge");
                let binormal = e.cross(normal);
                let (b, w) = (b.to_radians(), w.to_radians());
                let next =
                    (b.cos() * e + b.sin() * (w.cos() * normal + w.sin() * binormal)).normalize();
                // Parallel transport: the rotation taking e to next.
                normal = DQuat::from_rotation_arc(e, next) * normal;
                dirs.push(next);
            }
        }
        for j in 0..edges.min(n - 1) {
            out[j + 1] = out[j] + edge(j).length() * dirs[j];
        }
        if closed {
            let gap = (out[n - 1] + edge(n - 1).length() * dirs[n - 1]).distance(out[0]);
            check_closed(gap, front)?;
        }
    }
    for p in &moves.pivots {
        if p.at >= n {
            return Err(refuse(
                format!(
                    "front.pivot at = {}, but the front has vertices 0 to {}",
                    p.at,
                    n - 1
                ),
                "choose a vertex of the front",
            ));
        }
        let axis = match (p.axis, dim) {
            (Some(a), 3) if a.length() > 0.0 && a.is_finite() => a.normalize(),
            (Some(_), 3) => {
                return Err(refuse(
                    "front.pivot axis has zero length".into(),
                    "give a non-zero axis",
                ));
            }
            (Some(_), _) => {
                return Err(refuse(
                    "a pivot axis needs a 3-D lattice".into(),
                    "leave `axis` out in 2-D (the rotation is in the plane)",
                ));
            }
            (None, _) => DVec3::Z,
        };
        let q = DQuat::from_axis_angle(axis, p.angle_deg.to_radians());
        let centre = out[p.at];
        for v in &mut out[p.at + 1..] {
            *v = centre + q * (*v - centre);
        }
        if closed && p.at + 1 < n {
            check_closed(out[n - 1].distance(out[0]) - edge(n - 1).length(), front)?;
        }
    }
    for c in &moves.cranks {
        let last = if closed { n } else { n - 1 };
        if !(c.from < c.to && c.to <= last && c.to - c.from >= 2) {
            return Err(refuse(
                format!(
                    "front.crank from = {}, to = {} does not enclose a vertex of the front (0 to {last})",
                    c.from, c.to
                ),
                "give from < to with at least one vertex between them",
            ));
        }
        if dim == 2 {
            return Err(refuse(
                "a crankshaft move turns the front out of the plane".into(),
                "use a 3-D seed for crank moves",
            ));
        }
        let (a, b) = (out[c.from], out[c.to % n]);
        let axis = (b - a).normalize();
        let q = DQuat::from_axis_angle(axis, c.angle_deg.to_radians());
        for v in &mut out[c.from + 1..c.to] {
            *v = a + q * (*v - a);
        }
    }
    Ok(out)
}

/// The front laid on the saddle `s`: a 3-D loop's, and the only move
/// that rebuilds it whole.
fn saddled(
    front: &[DVec3],
    closed: bool,
    dim: usize,
    moves: &FrontMoves,
    s: Saddle,
) -> Result<Vec<DVec3>, FrontError> {
    if moves.turn.is_some() || moves.bend.is_some() || moves.twist.is_some() {
        return Err(refuse(
            "front.saddle lays the whole front, so it cannot be given with turn, bend or twist"
                .into(),
            "give either `saddle` or the turning angles (pivots and cranks may follow a saddle)",
        ));
    }
    if !closed || dim != 3 {
        return Err(refuse(
            "front.saddle is for the closed fronts of 3-D loops".into(),
            "use bend and twist on an open front",
        ));
    }
    lay(front, s)
}

fn check_closed(gap: f64, front: &[DVec3]) -> Result<(), FrontError> {
    let perimeter: f64 = front
        .iter()
        .zip(front.iter().cycle().skip(1))
        .map(|(a, b)| a.distance(*b))
        .sum();
    if gap.abs() <= 1e-9 * perimeter {
        Ok(())
    } else {
        Err(refuse(
            format!(
                "the rebuilt loop front does not close: it misses by {:.6} mm",
                gap.abs()
            ),
            "on a loop use crank moves (they keep the front closed), or turning angles that sum to a closed polygon",
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moves_keep_edge_lengths_and_closure() {
        let ring: Vec<DVec3> = (0..8)
            .map(|j| {
                let a = std::f64::consts::TAU * j as f64 / 8.0;
                DVec3::new(30.0 * a.cos(), 30.0 * a.sin(), 0.0)
            })
            .collect();
        let moves = FrontMoves {
            cranks: vec![
                Crank {
                    from: 0,
                    to: 2,
                    angle_deg: 25.0,
                },
                Crank {
                    from: 4,
                    to: 8,
                    angle_deg: -15.0,
                },
            ],
            ..FrontMoves::default()
        };
        let out = rebuild(&ring, true, 3, &moves).unwrap();
        for j in 0..8 {
            let (a, b) = (
                ring[j].distance(ring[(j + 1) % 8]),
                out[j].distance(out[(j + 1) % 8]),
            );
            assert!((a - b).abs() < 1e-12);
        }
        assert!(out[1].z.abs() > 1.0, "vertex 1 left the plane");
        let open = rebuild(
            &ring[..5],
            false,
            3,
            &FrontMoves {
                bend: Some(vec![10.0]),
                twist: Some(vec![30.0]),
                ..FrontMoves::default()
            },
        )
        .unwrap();
        for j in 0..4 {
            assert!((ring[j].distance(ring[j + 1]) - open[j].distance(open[j + 1])).abs() < 1e-12);
        }
    }
}
