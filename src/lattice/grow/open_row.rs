//! A row grown on an open front (docs/math.md 5): the start cell, transfers to
//! either side, and the boundary legs.

use super::*;

impl Grower {
    /// docs/math.md 5 on an open front.
    pub(super) fn grow_open_row(
        &mut self,
        i: usize,
        params: &RowParams,
    ) -> Result<(), GrowthError> {
        use ErrorKind as K;
        let m = self.lattice.width;
        self.pivots.iter_mut().for_each(|p| *p = None);
        self.next.iter_mut().for_each(|p| *p = None);
        let x = &self.front;
        let row = Some(i);

        let j0 = params.start;
        if j0 >= m {
            return Err(GrowthError::new(
                K::StartOutOfRange,
                Param::Start,
                row,
                None,
                format!("start = {j0}, but a row has cells 0 to {}", m - 1),
                format!("use a start site between 0 and {}", m - 1),
            ));
        }
        let Some(direction) = params.direction else {
            return Err(GrowthError::new(
                K::BadDirection,
                Param::Direction,
                row,
                Some(j0),
                "the row has no leg direction",
                "give `angle` (degrees) or `direction` for this row",
            ));
        };
        let v2 = resolve_direction(direction, x[j0].pos, x[j0 + 1].pos, self.lattice.dim).map_err(
            |(msg, hint)| {
                GrowthError::new(K::BadDirection, Param::Direction, row, Some(j0), msg, hint)
            },
        )?;
        let start = start_pivot(x, j0, v2, i)?;
        self.pivots[j0] = Some(start);
        self.transfer_chains(i, j0, start)?;
        self.boundary_legs(i, params)
    }

    /// The transfers right and left of the start cell `j0` (docs/math.md 5):
    /// each cell's pivot, and the corner of the next front that it fixes.
    fn transfer_chains(&mut self, i: usize, j0: usize, start: Point) -> Result<(), GrowthError> {
        let m = self.lattice.width;
        let x = &self.front;
        // The two chains of transfers, right and left of j0, depend on
        // nothing of each other: grown in one loop, a step of each at a
        // time, their square roots and divisions overlap (half the time
        // of a row). Any refusal grows the row again one chain after the
        // other, so that the error reported is the one the sequential
        // order meets first.
        let right_steps = m.saturating_sub(1).saturating_sub(j0);
        let (mut right, mut left) = (start, start);
        let mut ok = true;
        for k in 0..right_steps.max(j0) {
            if k < right_steps {
                match right_step(x, j0 + k, right) {
                    Ok((lr, p)) => {
                        self.next[j0 + k + 1] = Some(lr);
                        self.pivots[j0 + k + 1] = Some(p);
                        right = p;
                    }
                    Err(_) => {
                        ok = false;
                        break;
                    }
                }
            }
            if k < j0 {
                match left_step(x, j0 - k, left) {
                    Ok((ll, p)) => {
                        self.next[j0 - k] = Some(ll);
                        self.pivots[j0 - k - 1] = Some(p);
                        left = p;
                    }
                    Err(_) => {
                        ok = false;
                        break;
                    }
                }
            }
        }
        if !ok {
            // Right of j0: rod A of cell j fixes the lower-right corner,
            // which fixes rod B (and so the pivot) of cell j + 1.
            for j in j0..m.saturating_sub(1) {
                let p = self.pivots[j].expect("pivot grown");
                let (lr, next) = right_step(x, j, p).map_err(|f| f.error(x, i))?;
                self.next[j + 1] = Some(lr);
                self.pivots[j + 1] = Some(next);
            }
            // Left of j0, the mirror image.
            for j in (1..=j0).rev() {
                let p = self.pivots[j].expect("pivot grown");
                let (ll, cell) = left_step(x, j, p).map_err(|f| f.error(x, i))?;
                self.next[j] = Some(ll);
                self.pivots[j - 1] = Some(cell);
            }
        }
        Ok(())
    }

    /// The two free boundary legs (docs/math.md 4.5): the next front's end
    /// corners, at the given lengths or matched to their neighbours.
    fn boundary_legs(&mut self, i: usize, params: &RowParams) -> Result<(), GrowthError> {
        use ErrorKind as K;
        let m = self.lattice.width;
        let x = &self.front;
        let row = Some(i);
        let p_first = self.pivots[0].expect("pivot grown");
        let p_last = self.pivots[m - 1].expect("pivot grown");
        let matched_left = self.next[1].map(|q| q.z - p_first.z);
        let matched_right = self.next[m - 1].map(|q| q.z - p_last.z);
        let (l2, l3) = match (params.left_leg, params.right_leg) {
            (Leg::Length(a), Leg::Length(b)) => (a, b),
            (Leg::Length(a), Leg::Match) => (a, matched_right.unwrap_or(a)),
            (Leg::Match, Leg::Length(b)) => (matched_left.unwrap_or(b), b),
            (Leg::Match, Leg::Match) => match (matched_left, matched_right) {
                (Some(a), Some(b)) => (a, b),
                _ => {
                    return Err(GrowthError::new(
                        K::MatchNeedsLength,
                        Param::LeftLeg,
                        row,
                        Some(0),
                        "both end legs are \"match\", but in a one-cell-wide row each end matches the other",
                        "give left_leg or right_leg as a length in mm",
                    ));
                }
            },
        };
        check_boundary_leg(l2, Param::LeftLeg, i, 0)?;
        check_boundary_leg(l3, Param::RightLeg, i, m - 1)?;
        let v2_first = (p_first.pos - x[1].pos).normalize();
        let v1_last = (p_last.pos - x[m - 1].pos).normalize();
        self.next[0] = Some(Point {
            pos: p_first.pos + l2 * v2_first,
            z: p_first.z + l2,
        });
        self.next[m] = Some(Point {
            pos: p_last.pos + l3 * v1_last,
            z: p_last.z + l3,
        });
        Ok(())
    }
}
