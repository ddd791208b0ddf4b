//! The order of a batch's work. Each recipe passes through three stages,
//! one after the other: started (read, kept from the earlier build, or
//! grown, verified and assembled up to its simulation), simulated, and
//! drawn (its files made and written). Any job takes any stage of any
//! recipe, in this priority: start the next recipe while the builds held
//! in memory are few, else the dearest simulation, else the dearest
//! drawing. A simulation is the longest single piece of a batch (a second
//! of CPU for the examples' saddle ring, against a tenth for its files):
//! run first and side by side, the simulations end about together while
//! the files, many and short, fill the jobs' time around them, and no job
//! is left alone with a long simulation at the end. The order decides
//! only when each piece runs: every file is the same in any order.

use std::collections::VecDeque;
use std::sync::{Condvar, Mutex, MutexGuard};

/// The cells of the builds a batch holds in memory at once (started and
/// not yet written): the most one build makes parts for, so the largest
/// are started one at a time, and a recipe is started whenever none is
/// held. Held builds (lattice, parts, layout) took about 2.8 KiB a cell
/// (4 copies of a 5,000-cell sheet, 41 MiB more than one at a time,
/// BENCHMARKS.md of 003e36f "Examples batch, fifth round"), so
/// some 55 MiB at the bound; drawing one peaks at about 13 KiB a cell
/// (BENCHMARKS.md). The examples all fit.
pub(super) const HELD_CELLS: usize = karigami::MAX_FABRICATED_CELLS;

/// A stage of one recipe (its index in the batch), as handed to a job.
pub(super) enum Task<S, D> {
    Start(usize),
    Simulate(usize, S),
    /// `alone`: nothing else is queued or running, so the drawing may
    /// take a second thread (`karigami::files_on`).
    Draw {
        recipe: usize,
        work: D,
        alone: bool,
    },
}

/// The queue of stages, shared by the jobs. Every task taken is reported
/// back once, by `simulate`, `draw` or `finish`.
pub(super) struct Stages<S, D> {
    state: Mutex<State<S, D>>,
    changed: Condvar,
}

struct State<S, D> {
    /// Recipes not started, in the order to start them, with the cells
    /// each is expected to hold (`karigami::build_cells`).
    next: VecDeque<(usize, usize)>,
    /// Each recipe's cells while it is held (0 before and after).
    held_by: Vec<usize>,
    held: usize,
    /// Simulations and drawings waiting, with their cost (the lattice's
    /// cells) and recipe.
    simulate: Vec<(usize, usize, S)>,
    draw: Vec<(usize, usize, D)>,
    /// Tasks taken and not yet reported back.
    running: usize,
    stopped: bool,
}

impl<S, D> Stages<S, D> {
    /// `order`: every recipe's index (each once) with the cells it is
    /// expected to hold, in the order to start them.
    pub(super) fn new(order: Vec<(usize, usize)>) -> Self {
        Self {
            state: Mutex::new(State {
                held_by: vec![0; order.len()],
                next: order.into(),
                held: 0,
                simulate: Vec::new(),
                draw: Vec::new(),
                running: 0,
                stopped: false,
            }),
            changed: Condvar::new(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, State<S, D>> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The next task, waiting while every one left waits for a task that
    /// runs; None when the batch is done or stopped.
    pub(super) fn take(&self) -> Option<Task<S, D>> {
        let mut s = self.lock();
        loop {
            if s.stopped {
                return None;
            }
            if let Some(&(i, cells)) = s.next.front()
                && (s.held == 0 || s.held + cells <= HELD_CELLS)
            {
                s.next.pop_front();
                s.held += cells;
                s.held_by[i] = cells;
                s.running += 1;
                return Some(Task::Start(i));
            }
            if let Some((_, i, work)) = dearest(&mut s.simulate) {
                s.running += 1;
                return Some(Task::Simulate(i, work));
            }
            if let Some((_, recipe, work)) = dearest(&mut s.draw) {
                let alone = s.running == 0
                    && s.next.is_empty()
                    && s.simulate.is_empty()
                    && s.draw.is_empty();
                s.running += 1;
                return Some(Task::Draw {
                    recipe,
                    work,
                    alone,
                });
            }
            if s.running == 0 {
                return None;
            }
            s = self.changed.wait(s).unwrap_or_else(|e| e.into_inner());
        }
    }

    /// A task of `recipe` ended with its simulation to run, of `cost`.
    pub(super) fn simulate(&self, recipe: usize, cost: usize, work: S) {
        self.reported(|s| s.simulate.push((cost, recipe, work)));
    }

    /// A task of `recipe` ended with its files to draw, of `cost`.
    pub(super) fn draw(&self, recipe: usize, cost: usize, work: D) {
        self.reported(|s| s.draw.push((cost, recipe, work)));
    }

    /// A task of `recipe` ended it: written, kept or failed.
    pub(super) fn finish(&self, recipe: usize) {
        self.reported(|s| {
            let cells = std::mem::take(&mut s.held_by[recipe]);
            s.held -= cells;
        });
    }

    /// Hand out no more tasks (a write failed: the batch cannot commit).
    pub(super) fn stop(&self) {
        self.lock().stopped = true;
        self.changed.notify_all();
    }

    fn reported(&self, f: impl FnOnce(&mut State<S, D>)) {
        let mut s = self.lock();
        s.running -= 1;
        f(&mut s);
        drop(s);
        self.changed.notify_all();
    }
}

/// Stops the stages when a job panics with a task taken, so that the other
/// jobs do not wait for it forever (the panic then reaches the batch).
pub(super) struct StopOnPanic<'a, S, D>(pub &'a Stages<S, D>);

impl<S, D> Drop for StopOnPanic<'_, S, D> {
    fn drop(&mut self) {
        if std::thread::panicking() {
            self.0.stop();
        }
    }
}

/// The dearest entry of `list`, taken out; ties go to the first recipe.
fn dearest<T>(list: &mut Vec<(usize, usize, T)>) -> Option<(usize, usize, T)> {
    let k = (0..list.len()).max_by_key(|&k| (list[k].0, std::cmp::Reverse(list[k].1)))?;
    Some(list.swap_remove(k))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What a task is, without its work.
    fn name(t: &Task<(), ()>) -> String {
        match t {
            Task::Start(i) => format!("start {i}"),
            Task::Simulate(i, ()) => format!("simulate {i}"),
            Task::Draw { recipe, alone, .. } => {
                format!("draw {recipe}{}", if *alone { " alone" } else { "" })
            }
        }
    }

    #[test]
    fn simulations_run_before_any_drawing_dearest_first() {
        let stages = Stages::<(), ()>::new(vec![(2, 10), (0, 10), (1, 10)]);
        let mut seen = Vec::new();
        // One job: every recipe is started first (they fit in memory),
        // then the simulations by cost, then the drawings by cost.
        while let Some(t) = stages.take() {
            seen.push(name(&t));
            match t {
                Task::Start(i) if i == 1 => stages.draw(i, 5, ()),
                Task::Start(i) => stages.simulate(i, [30, 0, 70][i], ()),
                Task::Simulate(i, ()) => stages.draw(i, [30, 0, 70][i], ()),
                Task::Draw { recipe, .. } => stages.finish(recipe),
            }
        }
        assert_eq!(
            seen,
            [
                "start 2",
                "start 0",
                "start 1",
                "simulate 2",
                "simulate 0",
                "draw 2",
                "draw 0",
                "draw 1 alone"
            ]
        );
    }

    #[test]
    fn recipes_held_in_memory_are_bounded() {
        let big = HELD_CELLS / 2 + 1;
        let stages = Stages::<(), ()>::new(vec![(0, big), (1, big), (2, 5)]);
        // Two jobs: the second recipe waits for the first to be written.
        assert_eq!(name(&stages.take().unwrap()), "start 0");
        stages.draw(0, big, ());
        assert_eq!(name(&stages.take().unwrap()), "draw 0");
        stages.finish(0);
        assert_eq!(name(&stages.take().unwrap()), "start 1");
        // The small one fits beside it.
        assert_eq!(name(&stages.take().unwrap()), "start 2");
        stages.finish(2);
        stages.finish(1);
        assert!(stages.take().is_none());
    }

    #[test]
    fn a_job_waits_for_the_stage_another_runs() {
        let stages = Stages::<(), ()>::new(vec![(0, 1)]);
        std::thread::scope(|s| {
            assert_eq!(name(&stages.take().unwrap()), "start 0");
            let waiting = s.spawn(|| stages.take().map(|t| name(&t)));
            std::thread::sleep(std::time::Duration::from_millis(20));
            stages.simulate(0, 1, ());
            assert_eq!(waiting.join().unwrap().as_deref(), Some("simulate 0"));
            stages.finish(0);
            assert!(stages.take().is_none());
        });
    }

    #[test]
    fn a_stopped_batch_hands_out_nothing() {
        let stages = Stages::<(), ()>::new(vec![(0, 1), (1, 1)]);
        assert_eq!(name(&stages.take().unwrap()), "start 0");
        stages.stop();
        assert!(stages.take().is_none());
    }
}
