//! Independent pieces of work shared out over threads and handed back in
//! their order, so that what is made of them does not depend on how many
//! threads there were (`simulate --explore`'s starts, the evolution
//! strategy's designs).

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;
use std::thread;

/// Run `work(k)` for every k in 0..n, `jobs` at a time (on the calling
/// thread alone when `jobs` < 2), and hand each result to `each` in the
/// order of k as soon as every earlier one has been: a result that comes
/// early waits, and only those are held.
pub(crate) fn in_order<T: Send>(
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
    use super::in_order;

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
