//! Helpers shared by the integration tests.
#![allow(dead_code)]

use glam::DVec3;

pub(crate) fn v2(x: f64, y: f64) -> DVec3 {
    DVec3::new(x, y, 0.0)
}

/// Assert two numbers agree to `tol` (absolute), with a useful message.
#[track_caller]
pub(crate) fn close(actual: f64, expected: f64, tol: f64, what: &str) {
    assert!(
        (actual - expected).abs() <= tol,
        "{what}: got {actual:.15}, expected {expected:.15} (tol {tol:e})"
    );
}

#[track_caller]
pub(crate) fn close_vec(actual: DVec3, expected: DVec3, tol: f64, what: &str) {
    assert!(
        actual.distance(expected) <= tol,
        "{what}: got {actual:?}, expected {expected:?} (tol {tol:e})"
    );
}

/// A small deterministic generator (SplitMix64) for property tests, so the
/// cases are the same on every run and need no extra crate.
pub(crate) struct Rng(u64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [lo, hi).
    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }

    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// One item of a non-empty slice.
    pub(crate) fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}
