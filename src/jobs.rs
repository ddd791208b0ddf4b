//! How many threads the library may use (`Jobs`), and the two shapes of
//! parallel work it runs: independent halves (`Jobs::join`) and
//! independent pieces handed back in their order (`Jobs::in_order`). A
//! stage says what may run in parallel; `Jobs` decides whether it does,
//! and every result is the same computation either way, so what is made
//! of it does not depend on the number of threads.

use std::collections::BTreeMap;
use std::num::NonZeroUsize;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::thread;

/// The threads a piece of work may use, at least one. The CLI makes it
/// from `--jobs` (or the machine's cores); the library only divides it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Jobs(NonZeroUsize);

impl Jobs {
    /// One thread: the calling one.
    pub const ONE: Jobs = Jobs(NonZeroUsize::MIN);

    /// `n` threads (0 is taken as 1).
    pub fn new(n: usize) -> Jobs {
        Jobs(NonZeroUsize::new(n).unwrap_or(NonZeroUsize::MIN))
    }

    /// How many threads.
    pub fn get(self) -> usize {
        self.0.get()
    }

    /// Run `a` and `b`, which are independent, at the same time when there
    /// are two threads or more (`b` on a new one), else one after the
    /// other. Each is handed its share of the threads, so nested work
    /// never uses more than there are. A panic in either is resumed here.
    pub(crate) fn join<A: Send, B: Send>(
        self,
        a: impl FnOnce(Jobs) -> A + Send,
        b: impl FnOnce(Jobs) -> B + Send,
    ) -> (A, B) {
        let n = self.get();
        if n < 2 {
            return (a(Jobs::ONE), b(Jobs::ONE));
        }
        let (mine, theirs) = (Jobs::new(n - n / 2), Jobs::new(n / 2));
        thread::scope(|s| {
            let other = s.spawn(move || b(theirs));
            let first = a(mine);
            let second = other
                .join()
                .unwrap_or_else(|p| std::panic::resume_unwind(p));
            (first, second)
        })
    }

    /// Run `work(k)` for every k in 0..n on these threads, and hand each
    /// result to `each` in the order of k (`in_order`).
    pub(crate) fn in_order<T: Send>(
        self,
        n: usize,
        work: impl Fn(usize) -> T + Sync,
        each: impl FnMut(usize, T),
    ) {
        in_order(n, self.get(), work, each);
    }
}

/// Run `work(k)` for every k in 0..n, `jobs` at a time (on the calling
/// thread alone when `jobs` < 2), and hand each result to `each` in the
/// order of k as soon as every earlier one has been: a result that comes
/// early waits, and only those are held.
fn in_order<T: Send>(
    n: usize,
    jobs: usize,
    work: impl Fn(usize) -> T + Sync,
    mut each: impl FnMut(usize, T),
) {
    let jobs = jobs.clamp(1, n.max(1));
    if jobs == 1 {
        (0..n).for_each(|k| each(k, work(k)));
        return;
    }
    let next = AtomicUsize::new(0);
    let (send, receive) = mpsc::channel();
    thread::scope(|s| {
        for _ in 0..jobs {
            let send = send.clone();
            let (next, work) = (&next, &work);
            s.spawn(move || {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    if k >= n || send.send((k, work(k))).is_err() {
                        break;
                    }
                }
            });
        }
        drop(send);
        let mut early = BTreeMap::new();
        let mut due = 0;
        for (k, result) in receive {
            early.insert(k, result);
            while let Some(result) = early.remove(&due) {
                each(due, result);
                due += 1;
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::{Jobs, in_order};

    #[test]
    fn join_runs_both_halves_and_shares_the_threads() {
        for n in [1, 2, 3, 8] {
            let (a, b) = Jobs::new(n).join(|j| (j.get(), 1), |j| (j.get(), 2));
            assert_eq!((a.1, b.1), (1, 2));
            assert_eq!(
                a.0 + b.0,
                n.max(2),
                "{n} threads shared as {} + {}",
                a.0,
                b.0
            );
        }
        assert_eq!(Jobs::new(0), Jobs::ONE);
    }

    #[test]
    fn results_come_back_in_order_whatever_the_jobs() {
        for jobs in [0, 1, 2, 3, 8] {
            let mut seen = Vec::new();
            // Later pieces finish first: the order is the handing back's.
            in_order(
                20,
                jobs,
                |k| {
                    std::thread::sleep(std::time::Duration::from_micros(200 * (20 - k as u64)));
                    k * k
                },
                |k, v| seen.push((k, v)),
            );
            assert_eq!(
                seen,
                (0..20).map(|k| (k, k * k)).collect::<Vec<_>>(),
                "{jobs}"
            );
        }
        in_order(0, 2, |k| k, |_, _| panic!("nothing to do"));
    }
}
