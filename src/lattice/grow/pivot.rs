//! The pivot helpers growth is made of: the start cell's pivot, the right
//! and left transfers (docs/math.md 4.2, 4.3), the leg direction at the start
//! site and the front-local frame.

use super::*;

/// The start cell's pivot from its direction (docs/math.md 4.2).
pub(super) fn start_pivot(
    x: &[Point],
    j0: usize,
    v2: DVec3,
    i: usize,
) -> Result<Point, GrowthError> {
    let n = x.len();
    let (ul, ur) = (x[j0], x[wrap(j0 + 1, n)]);
    pivot_from_v2(ul, ur, v2).map_err(|_| {
        let t = ur.pos - ul.pos;
        let kappa = ul.z - ur.z;
        let half = (kappa / t.length()).clamp(-1.0, 1.0).acos().to_degrees();
        let axis = angle_between(v2, -t.normalize()).to_degrees();
        GrowthError::new(
            ErrorKind::InadmissibleDirection,
            Param::Direction,
            Some(i),
            Some(j0),
            format!(
                "the leg direction is {axis:.3} deg from the cone axis (the direction back along the front edge), but it must be less than {half:.3} deg",
            ),
            "turn the direction towards the front edge (a smaller angle)",
        )
    })
}

/// Why a step of a chain of transfers stopped: small and `Copy`, so the
/// chains' loop carries no `GrowthError` (about 100 bytes) through every
/// step; `Fail::error` makes the message, off the growth loop's way.
#[derive(Clone, Copy, Debug)]
pub(super) enum Fail {
    /// `transfer_error` across the front's vertices `a` and `b`, at cell `j`.
    Transfer {
        refusal: Refusal,
        a: usize,
        b: usize,
        j: usize,
    },
    /// `propagated_cone` at cell `j`.
    Cone { j: usize },
    /// `check_leg` refused leg `name` of cell `j`.
    Leg {
        leg: f64,
        name: &'static str,
        j: usize,
    },
}

impl Fail {
    /// The growth error of row `i` grown on front `x`.
    #[cold]
    #[inline(never)]
    pub(super) fn error(self, x: &[Point], i: usize) -> GrowthError {
        match self {
            Fail::Transfer { refusal, a, b, j } => transfer_error(refusal, x, a, b, i, j),
            Fail::Cone { j } => propagated_cone(i, j),
            Fail::Leg { leg, name, j } => leg_error(leg, name, i, j),
        }
    }
}

/// `check_leg`'s test, with a `Fail`.
#[inline(always)]
fn leg(leg: f64, name: &'static str, j: usize) -> Result<(), Fail> {
    if positive_finite(leg) {
        Ok(())
    } else {
        Err(Fail::Leg { leg, name, j })
    }
}

/// Right transfer from cell j (4.3), indices mod the front length: the
/// lower-right corner of cell j, on rod A beyond its pivot `p`.
pub(super) fn right_transfer(
    x: &[Point],
    j: usize,
    p: Point,
    i: usize,
) -> Result<Point, GrowthError> {
    lower_right_of(x, j, p).map_err(|f| f.error(x, i))
}

#[inline(always)]
fn lower_right_of(x: &[Point], j: usize, p: Point) -> Result<Point, Fail> {
    let j2 = wrap(j + 2, x.len());
    let v1 = (p.pos - x[j].pos).normalize();
    let lr = lower_right(x[j], x[j2], v1).map_err(|refusal| Fail::Transfer {
        refusal,
        a: j,
        b: j2,
        j,
    })?;
    leg(lr.z - p.z, "l3", j)?;
    Ok(lr)
}

/// The pivot of cell j + 1, whose rod B runs from its upper-right corner
/// to `ll`, the lower-right corner just found for cell j.
pub(super) fn next_pivot(x: &[Point], j: usize, ll: Point, i: usize) -> Result<Point, GrowthError> {
    next_pivot_of(x, j, ll).map_err(|f| f.error(x, i))
}

#[inline(always)]
fn next_pivot_of(x: &[Point], j: usize, ll: Point) -> Result<Point, Fail> {
    let n = x.len();
    let (j1, j2) = (wrap(j + 1, n), wrap(j + 2, n));
    let v2 = (ll.pos - x[j2].pos).normalize();
    let cell = pivot_from_v2(x[j1], x[j2], v2).map_err(|_| Fail::Cone { j: j1 })?;
    leg(ll.z - cell.z, "l2", j1)?;
    Ok(cell)
}

/// One step right of the start: from the pivot `p` of cell j, the
/// lower-right corner of cell j and the pivot of cell j + 1.
#[inline(always)]
pub(super) fn right_step(x: &[Point], j: usize, p: Point) -> Result<(Point, Point), Fail> {
    let lr = lower_right_of(x, j, p)?;
    Ok((lr, next_pivot_of(x, j, lr)?))
}

/// One step left of the start: from the pivot `p` of cell j, the
/// lower-left corner of cell j and the pivot of cell j - 1.
#[inline(always)]
pub(super) fn left_step(x: &[Point], j: usize, p: Point) -> Result<(Point, Point), Fail> {
    let v2 = (p.pos - x[j + 1].pos).normalize();
    let ll = lower_left(x[j - 1], x[j + 1], v2).map_err(|refusal| Fail::Transfer {
        refusal,
        a: j - 1,
        b: j + 1,
        j,
    })?;
    leg(ll.z - p.z, "l2", j)?;
    let v1 = (ll.pos - x[j - 1].pos).normalize();
    let cell = pivot_from_v1(x[j - 1], x[j], v1).map_err(|_| Fail::Cone { j: j - 1 })?;
    leg(ll.z - cell.z, "l3", j - 1)?;
    Ok((ll, cell))
}

/// The unit leg direction `v2` at the start site, from what the design gave.
pub(crate) fn resolve_direction(
    direction: Direction,
    ul: DVec3,
    ur: DVec3,
    dim: usize,
) -> Result<DVec3, (String, String)> {
    match direction {
        Direction::Vector(v) => {
            let len = v.length();
            if !positive_finite(len) {
                return Err((
                    "the direction vector has zero length".into(),
                    "give a non-zero direction, e.g. [-0.87, -0.5]".into(),
                ));
            }
            Ok(v / len)
        }
        Direction::Angles {
            angle_deg,
            tilt_deg,
        } => {
            if dim == 2 && tilt_deg != 0.0 {
                return Err((
                    "a tilt angle needs a 3-D lattice".into(),
                    "give `angle` as one number in 2-D".into(),
                ));
            }
            let frame = front_frame(ul, ur).ok_or_else(|| {
                (
                    "the front edge at the start site is vertical (along z), so angles have no reference"
                        .to_string(),
                    "give `direction` as a vector for this row".to_string(),
                )
            })?;
            let (a, b) = (angle_deg.to_radians(), tilt_deg.to_radians());
            Ok(a.cos() * frame.axis + a.sin() * (b.cos() * frame.down + b.sin() * frame.out))
        }
    }
}

/// The front-local frame at a site: `axis` points from UR back to UL (the
/// cone axis of docs/math.md 4.2), `down` is the growth side within the plane of
/// the front and +z (in 2-D, the clockwise normal), `out` completes it.
#[derive(Clone, Copy, Debug)]
pub struct FrontFrame {
    /// Unit vector from UR back to UL along the front edge: the cone axis.
    pub axis: DVec3,
    /// Unit normal to the front edge on the growth side, in the plane of the
    /// edge and +z.
    pub down: DVec3,
    /// Unit vector `down` x (UL -> UR) that completes the frame: out of the
    /// front's plane (+z in 2-D).
    pub out: DVec3,
}

/// The front-local frame at the front edge from `ul` to `ur`; None when the
/// edge runs along z or has no length (no growth side is defined).
pub fn front_frame(ul: DVec3, ur: DVec3) -> Option<FrontFrame> {
    let along = (ur - ul).normalize();
    let down = along.cross(DVec3::Z);
    let len = down.length();
    if !(len > 1e-9) {
        return None;
    }
    let down = down / len;
    Some(FrontFrame {
        axis: -along,
        down,
        out: down.cross(along),
    })
}
