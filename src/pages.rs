//! Memory taken from the kernel ahead of its use. A page's first write
//! traps into the kernel (about 3 us a page on the machine this was
//! measured on, BENCHMARKS.md): a buffer written once here, on a thread
//! that has nothing else to do, and cleared, keeps its pages for the work
//! that fills it later.

/// An empty vector with room for `n` elements, every page of which has
/// been written (with `value`).
pub(crate) fn touched<T: Clone>(n: usize, value: T) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    v.resize(n, value);
    // The writes are the point: kept even though nothing reads them.
    std::hint::black_box(v.as_mut_slice());
    v.clear();
    v
}
