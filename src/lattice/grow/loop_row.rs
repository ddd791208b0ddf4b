//! A row grown on a closed front (docs/math.md 6.2): its direction is fixed by
//! closure, found by a scan and polished by Newton steps.

use super::*;

impl Grower {
    /// docs/math.md 6.2: a row on a closed front, its direction fixed by closure.
    pub(super) fn grow_loop_row(
        &mut self,
        i: usize,
        params: &RowParams,
    ) -> Result<(), GrowthError> {
        use ErrorKind as K;
        let x = self.front.clone();
        let dim = self.lattice.dim;
        let axis = -(x[1].pos - x[0].pos).normalize();
        let holonomy = Holonomy::new(&x);
        let record = match closure(&holonomy, axis, dim) {
            Closure::Free => {
                let v2 = free_direction(&x, i, params, dim)?;
                let residual = self.build_loop(&x, v2, i)?;
                ClosureRecord {
                    row: i,
                    free: true,
                    candidates: 0,
                    residual,
                    ill_conditioned: false,
                }
            }
            Closure::Fixed {
                directions,
                ill_conditioned,
            } => {
                let admissible = self.admissible(&x, directions, axis, dim, i)?;
                let pick = self.pick(&x, &admissible, &holonomy, dim, i, params)?;
                let count = admissible.len();
                let v2 = admissible[pick].0;
                let residual = self.build_loop(&x, v2, i)?;
                ClosureRecord {
                    row: i,
                    free: false,
                    candidates: count,
                    residual,
                    ill_conditioned,
                }
            }
        };
        if record.residual > CLOSURE_TOL {
            return Err(GrowthError::new(
                K::LoopClosureResidual,
                Param::Direction,
                Some(i),
                Some(0),
                format!(
                    "the loop closes only to {:.2e} (more than {CLOSURE_TOL:.0e})",
                    record.residual
                ),
                "the closure is ill-conditioned here: make the front more or less symmetric",
            ));
        }
        self.closures.push(record);
        Ok(())
    }

    /// The closing directions that build, each polished on the real
    /// construction first, nearest the cone axis of cell 0 first.
    fn admissible(
        &mut self,
        x: &[Point],
        directions: Vec<DVec3>,
        axis: DVec3,
        dim: usize,
        i: usize,
    ) -> Result<Vec<(DVec3, f64)>, GrowthError> {
        use ErrorKind as K;
        let mut admissible: Vec<(DVec3, f64)> = Vec::new();
        let mut last_error = None;
        for v in directions {
            let v = polish(x, v, dim);
            match self.build_loop(x, v, i) {
                Ok(residual) => admissible.push((v, residual)),
                Err(e) => last_error = Some(e),
            }
        }
        admissible.sort_by(|a, b| angle_between(a.0, axis).total_cmp(&angle_between(b.0, axis)));
        if admissible.is_empty() {
            let why = match last_error {
                Some(e) => format!(" (the closing directions fail: {})", e.message),
                None => {
                    " (the holonomy has no real fixed point: an elliptic planar front)".to_string()
                }
            };
            return Err(GrowthError::new(
                K::NoLoopClosure,
                Param::Front,
                Some(i),
                None,
                format!("no admissible leg direction closes this loop row{why}"),
                "make the front more symmetric (points evenly round a circle, kappa = 0 closes for every direction)",
            ));
        }
        Ok(admissible)
    }

    /// Which admissible direction the row takes: the one nearest its
    /// `direction` (which must close), its `candidate` (from 1), the one
    /// whose new vertex x[i+1][1] lands nearest its `target`, or the first.
    fn pick(
        &mut self,
        x: &[Point],
        admissible: &[(DVec3, f64)],
        holonomy: &Holonomy,
        dim: usize,
        i: usize,
        params: &RowParams,
    ) -> Result<usize, GrowthError> {
        use ErrorKind as K;
        let row = Some(i);
        Ok(if let Some(direction) = params.direction {
            let v = resolve_direction(direction, x[0].pos, x[1].pos, dim).map_err(|(m, h)| {
                GrowthError::new(K::BadDirection, Param::Direction, row, Some(0), m, h)
            })?;
            let (k, off) = admissible
                .iter()
                .map(|a| angle_between(a.0, v))
                .enumerate()
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .expect("some candidate");
            if holonomy.map(v).distance(v) > 1e-9 {
                return Err(GrowthError::new(
                    K::NoLoopClosure,
                    Param::Direction,
                    row,
                    Some(0),
                    format!(
                        "this direction does not close the loop: it comes back {:.6} deg off, and the nearest closing direction is {:.6} deg away",
                        angle_between(holonomy.map(v).normalize(), v).to_degrees(),
                        off.to_degrees()
                    ),
                    "leave `direction` out (the closing direction is found), or give `candidate = 1` or `2`",
                ));
            }
            k
        } else if let Some(c) = params.candidate {
            if c == 0 || c > admissible.len() {
                return Err(GrowthError::new(
                    K::NoLoopClosure,
                    Param::Candidate,
                    row,
                    None,
                    format!(
                        "candidate = {c}, but this row has {} admissible closing direction(s)",
                        admissible.len()
                    ),
                    format!(
                        "use candidate = 1{}",
                        if admissible.len() > 1 { " or 2" } else { "" }
                    ),
                ));
            }
            c - 1
        } else if let Some(target) = params.target {
            // The candidate whose new vertex x[i+1][1] lands nearest the target.
            let mut best = (0, f64::INFINITY);
            for (k, (v, _)) in admissible.iter().enumerate() {
                self.build_loop(x, *v, i)?;
                let d = self.next[1].expect("grown").pos.distance(target);
                if d < best.1 {
                    best = (k, d);
                }
            }
            best.0
        } else {
            0
        })
    }

    /// Build a loop row from `v2` at cell 0 by right transfers all the way
    /// round; returns the closure residual `|v2' - v2|`.
    fn build_loop(&mut self, x: &[Point], v2: DVec3, i: usize) -> Result<f64, GrowthError> {
        let n = x.len();
        self.pivots[0] = Some(start_pivot(x, 0, v2, i)?);
        for j in 0..n {
            let p = self.pivots[j].expect("pivot grown");
            let lr = right_transfer(x, j, p, i)?;
            self.next[wrap(j + 1, n)] = Some(lr);
            if j + 1 < n {
                self.pivots[j + 1] = Some(next_pivot(x, j, lr, i)?);
            }
        }
        let ll = self.next[0].expect("closing vertex");
        let p0 = self.pivots[0].expect("pivot grown");
        check_leg(ll.z - p0.z, "l2", i, 0)?;
        Ok((ll.pos - x[1].pos).normalize().distance(v2))
    }
}

/// Largest closure residual `|v2' - v2|` a loop row may keep.
pub(crate) const CLOSURE_TOL: f64 = 1e-9;

/// A free loop row's leg direction v2 at cell 0: the front is symmetric,
/// so every direction closes and the row's `target` or `direction` says
/// which it takes.
fn free_direction(
    x: &[Point],
    i: usize,
    params: &RowParams,
    dim: usize,
) -> Result<DVec3, GrowthError> {
    use ErrorKind as K;
    let row = Some(i);
    Ok(if let Some(target) = params.target {
        // Place x[i+1][1] towards the target: rod A of cell 0 points at it.
        let v1 = (target - x[0].pos).normalize();
        let p = pivot_from_v1(x[0], x[1], v1).map_err(|_| {
            GrowthError::new(
                K::InadmissibleDirection,
                Param::Target,
                row,
                Some(0),
                "the target is outside the admissible cone of cell 0 (seen from the cell's upper-left corner)",
                "move the target towards the growth side of the front",
            )
        })?;
        (p.pos - x[1].pos).normalize()
    } else if let Some(direction) = params.direction {
        resolve_direction(direction, x[0].pos, x[1].pos, dim).map_err(|(m, h)| {
            GrowthError::new(K::BadDirection, Param::Direction, row, Some(0), m, h)
        })?
    } else {
        return Err(GrowthError::new(
            K::LoopClosureFree,
            Param::Direction,
            row,
            None,
            "the front is symmetric (its holonomy is the identity), so every direction closes and the row needs one",
            "give this row an `angle`, a `direction`, or a `target` point for its vertex x[i+1][1]",
        ));
    })
}

/// The loop map computed by the real transfers (no admissibility checks),
/// for polishing: where `v2` at cell 0 comes back after one round.
pub(super) fn loop_map(x: &[Point], v2: DVec3) -> Option<DVec3> {
    let n = x.len();
    let mut p = pivot_from_v2(x[0], x[1], v2).ok()?;
    for j in 0..n {
        let v1 = (p.pos - x[j].pos).normalize();
        let lr = lower_right(x[j], x[wrap(j + 2, n)], v1).ok()?;
        let v = (lr.pos - x[wrap(j + 2, n)].pos).normalize();
        if j + 1 == n {
            return Some((lr.pos - x[1].pos).normalize());
        }
        p = pivot_from_v2(x[j + 1], x[wrap(j + 2, n)], v).ok()?;
    }
    None
}

/// A few Newton steps on `loop_map(v) = v` in tangent coordinates.
pub(super) fn polish(x: &[Point], v: DVec3, dim: usize) -> DVec3 {
    let basis: Vec<DVec3> = if dim == 2 {
        vec![DVec3::Z.cross(v).normalize()]
    } else {
        let a = v.any_orthonormal_vector();
        vec![a, v.cross(a)]
    };
    let residual = |v: DVec3| -> Option<Vec<f64>> {
        let w = loop_map(x, v)?;
        Some(basis.iter().map(|b| (w - v).dot(*b)).collect())
    };
    let mut v = v;
    for _ in 0..4 {
        let Some(r) = residual(v) else { return v };
        if r.iter().all(|e| e.abs() < 1e-15) {
            break;
        }
        let h = 1e-7;
        let cols: Option<Vec<Vec<f64>>> = basis
            .iter()
            .map(|b| {
                let rp = residual((v + h * *b).normalize())?;
                Some(rp.iter().zip(&r).map(|(a, b)| (a - b) / h).collect())
            })
            .collect();
        let Some(j) = cols else { return v };
        let step = if dim == 2 {
            if j[0][0].abs() < 1e-14 {
                return v;
            }
            vec![-r[0] / j[0][0]]
        } else {
            // Solve the 2x2 system J s = -r (J's columns are `cols`).
            let det = j[0][0] * j[1][1] - j[1][0] * j[0][1];
            if det.abs() < 1e-14 {
                return v;
            }
            vec![
                (-r[0] * j[1][1] + r[1] * j[1][0]) / det,
                (-r[1] * j[0][0] + r[0] * j[0][1]) / det,
            ]
        };
        let moved = (v + basis.iter().zip(&step).map(|(b, s)| *b * *s).sum::<DVec3>()).normalize();
        if residual(moved).is_none() {
            return v;
        }
        v = moved;
    }
    v
}
