//! The rows' pass compares each residual with its check's largest as it
//! is computed (`Watch`), and records again, one at a time and in the
//! order of the pass over the cells, only the cells that may raise it.

use super::report::Check;

/// A check's largest when a row starts, and the first and last cells of
/// the row with a residual that may exceed it: each residual is compared
/// as it is computed (no array of them stored and read again), and only
/// the cells from the first to the last of those are recorded again, one
/// residual at a time (`settle`): the others cannot raise the check.
#[derive(Clone, Copy)]
pub(super) struct Watch {
    max: f64,
    first: usize,
    last: usize,
}

/// A watch that lets no cell through (until `Row::measure` sets it).
impl Default for Watch {
    fn default() -> Self {
        Self {
            max: 0.0,
            first: usize::MAX,
            last: 0,
        }
    }
}

impl Watch {
    pub(super) fn of(check: &Check) -> Self {
        Self {
            max: check.max,
            first: usize::MAX,
            last: 0,
        }
    }

    /// Cell j's residuals, compared with the largest: `record`'s test, one
    /// comparison a residual and one branch a cell (a NaN residual, or a
    /// NaN largest, may raise).
    #[inline(always)]
    pub(super) fn cell<const K: usize>(&mut self, j: usize, residuals: [f64; K]) {
        let over = residuals
            .iter()
            .fold(false, |any, r| any | !(r.abs() <= self.max));
        if over {
            self.first = self.first.min(j);
            self.last = self.last.max(j);
        }
    }

    /// Count a row's `count` residuals into `check`, recording those of
    /// the cells that may raise it one at a time, cell by cell, each
    /// cell's in the order `residuals(j)` gives them: the order of the
    /// pass over the cells, so the largest, its site (the first attaining
    /// it) and the count are the same bits.
    #[inline(always)]
    pub(super) fn settle<I: IntoIterator<Item = f64>>(
        self,
        check: &mut Check,
        count: usize,
        residuals: impl Fn(usize) -> I,
        site: impl Fn(usize) -> String,
    ) {
        let before = check.count;
        if self.first <= self.last {
            replay(check, self.first..self.last + 1, residuals, site);
        }
        check.count = before + count;
    }
}

/// `Watch::settle` of a row that may hold a new largest.
#[cold]
#[inline(never)]
fn replay<I: IntoIterator<Item = f64>>(
    check: &mut Check,
    cells: std::ops::Range<usize>,
    residuals: impl Fn(usize) -> I,
    site: impl Fn(usize) -> String,
) {
    for k in cells {
        for r in residuals(k) {
            check.record(r, || site(k));
        }
    }
}
