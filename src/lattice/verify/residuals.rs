//! Each invariant's residual, written once (docs/verification.md, "The
//! invariants"; docs/math.md 8.0-8.3). Both traversals, the pass over the cells
//! (`cells.rs`) and the rows of a grid (`rows.rs`), compute every residual
//! by these functions from the same stored operands, so they agree bit for
//! bit by construction. What differs between them is only where the
//! operands are read from (a neighbour found through the incidence table,
//! or the next column of a row's arrays).
//!
//! A residual that is a quotient is returned as a `Ratio`, a bend as a
//! `Rod`: `Check::record_ratio` and `Check::record_bend` skip the division
//! and the square root when the quotient cannot raise the check, and
//! `Ratio::value` and `bend` give the same bits when it is needed.

use crate::lattice::Legs;
use glam::DVec3;

/// A residual `num / den`, kept apart until it is recorded.
#[derive(Clone, Copy)]
pub(super) struct Ratio {
    pub(super) num: f64,
    pub(super) den: f64,
}

impl Ratio {
    /// The residual.
    #[inline(always)]
    pub(super) fn value(self) -> f64 {
        self.num / self.den
    }
}

/// One rod through a pivot: the vectors of its two legs (from a corner to
/// the pivot, or from the pivot to a corner: the sine is the same) and
/// their lengths.
pub(super) type Rod = [(DVec3, f64); 2];

/// The vectors from a cell's corners `[UL, UR, LL, LR]` to its pivot `p`,
/// in the order of its legs (UL, LL, LR, UR): their lengths are the legs
/// (`p.distance(c)` is `|p - c|`).
#[inline(always)]
pub(super) fn to_pivot(p: DVec3, [ul, ur, ll, lr]: [DVec3; 4]) -> [DVec3; 4] {
    [p - ul, p - ll, p - lr, p - ur]
}

/// Rods A (UL-pivot-LR) and B (UR-pivot-LL) of a cell, from `to_pivot` and
/// its legs.
#[inline(always)]
pub(super) fn rods([d1, d2, d3, d4]: [DVec3; 4], [l1, l2, l3, l4]: Legs) -> [Rod; 2] {
    [[(d1, l1), (d3, l3)], [(d4, l4), (d2, l2)]]
}

/// Rod straightness (and, for rod B of a loop's cell 0, loop closure): the
/// sine of the angle between the rod's two legs. `(p - a) x (b - p)` is
/// `-((p - a) x (p - b))` exactly, so the same sine either way round.
#[inline(always)]
pub(super) fn bend([(a, la), (b, lb)]: Rod) -> f64 {
    a.cross(b).length() / (la * lb)
}

/// Legs against the construction z: each leg against the difference of z
/// at its ends (`z` of UL, UR, LL, LR; `zp` the pivot's; `inv` 1 / the
/// mean leg).
#[inline(always)]
pub(super) fn legs_z(
    [l1, l2, l3, l4]: Legs,
    [zul, zur, zll, zlr]: [f64; 4],
    zp: f64,
    inv: f64,
) -> [f64; 4] {
    [
        (zp - zul - l1) * inv,
        (zp - zur - l4) * inv,
        (zll - zp - l2) * inv,
        (zlr - zp - l3) * inv,
    ]
}

/// First row: `l4 - l1` against the seed edge's kappa (`z(UL) - z(UR)`).
#[inline(always)]
pub(super) fn seed_kappa([l1, _, _, l4]: Legs, kappa: f64, inv: f64) -> f64 {
    ((l4 - l1) - kappa) * inv
}

/// The scale of a residual between two cells: the mean of their mean legs.
#[inline(always)]
fn pair_scale(mean_a: f64, mean_b: f64) -> f64 {
    0.5 * (mean_a + mean_b)
}

/// Collapsibility (H) between cell `a` and its right neighbour `b` (B.UL =
/// A.UR, B.LL = A.LR), from their legs and mean legs.
#[inline(always)]
pub(super) fn horizontal_pore(
    ([_, _, l3, l4], mean_a): (Legs, f64),
    ([m1, m2, _, _], mean_b): (Legs, f64),
) -> Ratio {
    Ratio {
        num: (l3 + l4) - (m1 + m2),
        den: pair_scale(mean_a, mean_b),
    }
}

/// Collapsibility (V) between cell `a` and the cell `b` below it (B.UL =
/// A.LL, B.UR = A.LR).
#[inline(always)]
pub(super) fn vertical_pore(
    ([_, l2, l3, _], mean_a): (Legs, f64),
    ([m1, _, _, m4], mean_b): (Legs, f64),
) -> Ratio {
    Ratio {
        num: (l2 + m1) - (l3 + m4),
        den: pair_scale(mean_a, mean_b),
    }
}

/// Shared edges: `(|a - b| - |c - d|) / s`, the relative difference of an
/// edge `a`-`b` of one cell and `c`-`d` of its neighbour, on the scale `s`
/// of their pore. The same stored points make the same distance, so an
/// edge whose two cells hold the same corners (every extrinsic lattice) is
/// `same_edge`, without a square root; the result is the full formula's
/// bit for bit.
#[inline]
pub(super) fn shared_edge(a: DVec3, b: DVec3, c: DVec3, d: DVec3, s: f64) -> f64 {
    if a == c && b == d && a.is_finite() && b.is_finite() {
        same_edge(a, b, s)
    } else {
        (a.distance(b) - c.distance(d)) / s
    }
}

/// `shared_edge(a, b, a, b, s)`, for the edge a cell shares with a
/// neighbour holding the same stored corners: 0 when both points are
/// finite and `s` is neither 0 nor NaN (what `0.0 / s` gives, without the
/// division), else NaN (`|a - b|` of a non-finite point is NaN or
/// infinite, and its difference with itself NaN). The sign of a zero does
/// not matter to a residual.
#[inline(always)]
pub(super) fn same_edge(a: DVec3, b: DVec3, s: f64) -> f64 {
    if a.is_finite() && b.is_finite() && s != 0.0 && !s.is_nan() {
        0.0
    } else {
        f64::NAN
    }
}

/// `|UL - LL|^2`, a cell's squared left edge: the scale of the
/// compatibility's intercept at its UL vertex.
#[inline(always)]
pub(super) fn left_edge_squared(ul: DVec3, ll: DVec3) -> f64 {
    ul.distance_squared(ll)
}

/// The four-map composition around an interior vertex: its slope - 1, its
/// intercept over the squared left edge `s2` of the cell below-right of the
/// vertex, and the intercept over its natural magnitude.
#[derive(Clone, Copy)]
pub(super) struct Compatibility {
    pub(super) slope: f64,
    pub(super) intercept: Ratio,
    pub(super) natural: Ratio,
}

/// The four-map composition around an interior vertex (docs/math.md 8.2), from
/// the legs of the cells in which it is UL (`a`), LL (`b`), LR (`c`) and UR
/// (`d`), and the squared left edge of `a` (`left_edge_squared`).
#[inline(always)]
pub(super) fn compatibility(a: Legs, b: Legs, cc: Legs, d: Legs, s2: f64) -> Compatibility {
    // f^(a,b,c)(S) = gamma - eta S as (slope, intercept), docs/math.md 2.
    // One division a map: `-(lc / la)` is `-lc / la`, bit for bit
    // (division rounds the same either side of 0; a NaN differs at most in
    // its sign, which every residual's `abs` drops).
    let f = |la: f64, lb: f64, lc: f64| {
        let q = lc / la;
        (-q, lb * lb + lc * lc + q * (la * la + lb * lb))
    };
    let maps = [
        f(a[1], a[0], a[3]),    // f_a^(2,1,4): left edge -> top edge
        f(b[2], b[1], b[0]),    // f_b^(3,2,1): bottom edge -> left edge
        f(cc[3], cc[2], cc[1]), // f_c^(4,3,2): right edge -> bottom edge
        f(d[0], d[3], d[2]),    // f_d^(1,4,3): top edge -> right edge
    ];
    let (mut m, mut k, mut magnitude) = (1.0, 0.0, 0.0);
    for (mi, ci) in maps.iter().rev() {
        // Outermost map first: accumulate the product of the slopes
        // applied after each intercept, as in the natural magnitude.
        magnitude += (m * ci).abs();
        k += m * ci;
        m *= mi;
    }
    Compatibility {
        slope: m - 1.0,
        intercept: Ratio { num: k, den: s2 },
        natural: Ratio {
            num: k,
            den: magnitude,
        },
    }
}

/// Collapsed state, single-valued: a corner's z `z` against the `expect`ed
/// z from the pivot through this cell's leg (`inv` 1 / its mean leg).
#[inline(always)]
pub(super) fn single_valued(z: f64, expect: f64, inv: f64) -> f64 {
    (z - expect) * inv
}

/// Collapsed state, matching the construction: a recomputed z `zc`
/// against the construction's `z`, as the difference and `|z|`; the
/// residual is their `on_scale` (a front's or row's differences are
/// bounded before the scale is known: `Collapsed`'s blocks).
#[inline(always)]
pub(super) fn matches_construction(zc: f64, z: f64) -> (f64, f64) {
    (zc - z, z.abs())
}

/// `matches_construction`'s residual on the scale of the lattice's mean leg
/// `global` (plus `|z|`, for points far from the origin).
#[inline(always)]
pub(super) fn on_scale((num, magnitude): (f64, f64), global: f64) -> Ratio {
    Ratio {
        num,
        den: global + magnitude,
    }
}

/// `|LR - UL|` and `|LL - UR|` of corners `[UL, UR, LL, LR]`: the rods'
/// lengths the collapsed state must keep.
#[inline(always)]
pub(super) fn rod_spans([ul, ur, ll, lr]: [DVec3; 4]) -> [f64; 2] {
    [ul.distance(lr), ur.distance(ll)]
}

/// Collapsed rods' lengths: each rod's z span (`zs` the recomputed z of UL,
/// UR, LL, LR) against its deployed length (`rod_spans`).
#[inline(always)]
pub(super) fn collapsed_rods(
    [zul, zur, zll, zlr]: [f64; 4],
    [a, b]: [f64; 2],
    inv: f64,
) -> [f64; 2] {
    [(zlr - zul - a) * inv, (zll - zur - b) * inv]
}
