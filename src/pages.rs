//! Memory taken from the kernel ahead of its use. A page's first write
//! traps into the kernel (about 3 us a page on the machine this was
//! measured on, BENCHMARKS.md): a buffer written once here, on a thread
//! that has nothing else to do, and cleared, keeps its pages for the work
//! that fills it later.

use std::sync::atomic::{AtomicBool, Ordering};

/// Elements written between two looks at the stop flag: a writer no
/// longer needed (growth failed) stops within a few milliseconds.
const STEP: usize = 1 << 16;

/// An empty vector with room for `n` elements, every page of which has
/// been written (with `value`), or as many as were written before `stop`
/// was set.
pub(crate) fn touched<T: Clone>(n: usize, value: T, stop: &AtomicBool) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    while v.len() < n && !stop.load(Ordering::Relaxed) {
        v.resize((v.len() + STEP).min(n), value.clone());
    }
    // The writes are the point: kept even though nothing reads them.
    std::hint::black_box(v.as_mut_slice());
    v.clear();
    v
}
