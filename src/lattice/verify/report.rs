//! The public face of verification: the invariants checked, each one's
//! `Check` (its largest residual, where, and how it is recorded), and the
//! `Report` of a lattice.

use super::TOLERANCE;
use super::residuals::{Ratio, Rod, bend};

/// An invariant of docs/verification.md (docs/math.md 8.0-8.3) that verification checks; each is one
/// `Check` of a `Report`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Invariant {
    /// Each rod is straight through its pivot: the sine of its bend there.
    RodStraightness,
    /// Each leg equals the difference of the construction z at its two ends.
    LegsMatchZ,
    /// First row: `l4 - l1` equals the seed edge's kappa.
    SeedKappa,
    /// Collapsibility (H) between cells side by side in a row.
    HorizontalPores,
    /// Collapsibility (V) between a cell and the cell below it.
    VerticalPores,
    /// An edge shared by two cells has the same length in both.
    SharedEdges,
    /// Loops: rod B of cell 0, which ends where the round of transfers came
    /// back, is straight.
    LoopClosure,
    /// Four-map composition around an interior vertex (docs/math.md 8.2): slope - 1.
    CompatibilitySlope,
    /// Four-map composition: intercept over the squared left edge.
    CompatibilityIntercept,
    /// Four-map composition: intercept over its natural magnitude (better
    /// conditioned than over the edge).
    CompatibilityInterceptNatural,
    /// The z recomputed from the legs alone is single-valued at every vertex
    /// and pivot.
    CollapsedSingleValued,
    /// The recomputed z equals the construction z up to a constant.
    CollapsedMatchesConstruction,
    /// In the collapsed state each rod's z span equals its deployed length.
    CollapsedRodLength,
}

impl Invariant {
    /// What the invariant checks, in words for reports and messages.
    pub fn describe(self) -> &'static str {
        match self {
            Self::RodStraightness => "rod straightness (sine of the bend at the pivot)",
            Self::LegsMatchZ => "legs equal collapsed-z differences",
            Self::SeedKappa => "first row: l4 - l1 = seed kappa",
            Self::HorizontalPores => "collapsibility (H) at horizontal pores",
            Self::VerticalPores => "collapsibility (V) at vertical pores",
            Self::SharedEdges => "shared edges equal in both cells",
            Self::LoopClosure => "loop closure: sine of rod B's bend in cell 0",
            Self::CompatibilitySlope => "four-map composition: slope - 1",
            Self::CompatibilityIntercept => "four-map composition: intercept / |s|^2",
            Self::CompatibilityInterceptNatural => {
                "four-map composition: intercept / its magnitude"
            }
            Self::CollapsedSingleValued => "collapsed state: z single-valued",
            Self::CollapsedMatchesConstruction => "collapsed state: z equals construction z",
            Self::CollapsedRodLength => "collapsed state: rods keep their length",
        }
    }
}

/// The largest residual of one invariant and where it occurs.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// The invariant checked.
    pub invariant: Invariant,
    /// How many places were checked.
    pub(crate) count: usize,
    /// The largest residual found.
    pub max: f64,
    /// Where the largest residual occurs, if anywhere.
    pub site: Option<String>,
    /// What `max` must not exceed (see `tolerance_of`).
    pub(crate) tolerance: f64,
}

impl Check {
    pub(super) fn new(invariant: Invariant) -> Self {
        Self {
            invariant,
            count: 0,
            max: 0.0,
            site: None,
            tolerance: TOLERANCE,
        }
    }

    #[inline(always)]
    pub(super) fn record(&mut self, residual: f64, site: impl FnOnce() -> String) {
        self.count += 1;
        // One comparison for the common case: false for a residual above
        // the largest, for a NaN residual and for a NaN largest.
        if !(residual.abs() <= self.max) {
            self.raise(residual, site);
        }
    }

    /// A new largest residual: rare after the first cells, and its site's
    /// name (a formatted string) kept out of the checks' loop. A NaN
    /// residual must fail the check, so it sticks once seen.
    #[cold]
    #[inline(never)]
    fn raise(&mut self, residual: f64, site: impl FnOnce() -> String) {
        if self.max.is_nan() {
            return;
        }
        if residual.is_nan() || residual.abs() > self.max {
            self.max = residual.abs();
            self.site = Some(site());
        }
    }

    /// `record(ratio.value(), site)`, without the division when the
    /// quotient cannot exceed the largest residual so far: `|num| < 0.999
    /// max |den|` with `max |den|` a normal, finite number puts the exact
    /// quotient below `max` by far more than its rounding. Anything else
    /// (NaN, a zero or subnormal bound, an overflow, the first residuals
    /// while the largest is still 0) is divided and recorded as before, so
    /// the largest residual and its site are the same bits. Nearly every
    /// residual of a good lattice is below the largest one: the divisions,
    /// much of verification's time, are mostly skipped.
    #[inline(always)]
    pub(super) fn record_ratio(&mut self, ratio: Ratio, site: impl FnOnce() -> String) {
        let bound = self.max * ratio.den.abs();
        if bound.is_finite() && bound >= f64::MIN_POSITIVE && ratio.num.abs() < 0.999 * bound {
            self.count += 1;
            return;
        }
        self.record(ratio.value(), site);
    }

    /// `record(bend(rod), site)`, the same way without the square root and
    /// the division when the sine cannot exceed the largest so far (`|a x
    /// b|^2 < 0.998 (max la lb)^2`, see `record_ratio`).
    #[inline(always)]
    pub(super) fn record_bend(&mut self, rod: Rod, site: impl FnOnce() -> String) {
        let [(a, la), (b, lb)] = rod;
        let cross = a.cross(b).length_squared();
        let bound = self.max * (la * lb);
        let bound2 = bound * bound;
        if bound2.is_finite() && bound2 >= f64::MIN_POSITIVE && cross < 0.998 * bound2 {
            self.count += 1;
            return;
        }
        self.record(bend(rod), site);
    }

    pub(crate) fn passed(&self) -> bool {
        self.max <= self.tolerance
    }
}

/// The verification of one lattice: the largest residual of every
/// invariant, where it occurs, and the tolerance all were held to.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    pub(crate) cells: usize,
    pub(crate) vertices: usize,
    pub(crate) rods: usize,
    pub(crate) horizontal_pores: usize,
    pub(crate) vertical_pores: usize,
    pub(crate) interior_vertices: usize,
    /// One check per invariant, in `Invariant` order.
    pub checks: Vec<Check>,
    /// The tolerance every check was held to.
    pub tolerance: f64,
}

impl Report {
    /// True when every check is within the tolerance (a NaN residual fails).
    pub fn passed(&self) -> bool {
        self.checks.iter().all(Check::passed)
    }

    /// The check of `invariant`.
    pub fn check(&self, invariant: Invariant) -> &Check {
        self.checks
            .iter()
            .find(|c| c.invariant == invariant)
            .expect("every invariant is checked")
    }

    /// The largest residual over all invariants.
    pub fn worst(&self) -> f64 {
        self.checks
            .iter()
            .map(|c| c.max)
            .fold(0.0, |a, b| if b.is_nan() { b } else { a.max(b) })
    }
}
