//! Progress on stderr: a bar redrawn in place when stderr is a terminal,
//! plain lines otherwise (logs, CI), nothing with --quiet.

use std::io::{IsTerminal, Write};
use std::sync::mpsc;
use std::time::{Duration, Instant};

pub(super) struct Progress {
    total: usize,
    done: usize,
    tty: bool,
    quiet: bool,
    /// Width of the line last drawn in place, to clear it.
    drawn: usize,
    /// When a note was last printed as a line (off a terminal).
    noted: Option<Instant>,
}

impl Progress {
    pub(super) fn new(total: usize, quiet: bool) -> Self {
        Self {
            total,
            done: 0,
            tty: std::io::stderr().is_terminal(),
            quiet,
            drawn: 0,
            noted: None,
        }
    }

    pub(super) fn is_tty(&self) -> bool {
        self.tty && !self.quiet
    }

    /// A recipe has finished: `status` is "ok" or why it failed.
    pub(super) fn finished(&mut self, name: &str, status: &str, seconds: f64) {
        self.done += 1;
        if self.quiet {
            return;
        }
        if self.tty {
            self.draw(&format!("{name} {status}"));
        } else {
            errln!(
                "[{}/{}] {name}: {status} ({seconds:.2} s)",
                self.done,
                self.total
            );
        }
    }

    /// A note while a single long job runs (a fit's rows): drawn in place
    /// on a terminal, else printed as a line every few seconds at most.
    pub(super) fn note(&mut self, text: &str) {
        if self.is_tty() {
            self.draw(text);
        } else if !self.quiet && self.noted.is_none_or(|t| t.elapsed() >= NOTE_EVERY) {
            errln!("{text}");
            self.noted = Some(Instant::now());
        }
    }

    /// Print a block (an error report) above the bar.
    pub(super) fn print(&mut self, text: &str) {
        self.clear();
        err!("{text}");
        if self.tty && !self.quiet && self.done > 0 && self.done < self.total {
            self.draw("");
        }
    }

    fn draw(&mut self, what: &str) {
        const WIDTH: usize = 24;
        let filled = (WIDTH * self.done).checked_div(self.total).unwrap_or(WIDTH);
        let mut line = format!(
            "[{}{}] {}/{} {what}",
            "#".repeat(filled),
            "-".repeat(WIDTH - filled),
            self.done,
            self.total
        );
        line.truncate(line.char_indices().nth(78).map_or(line.len(), |(i, _)| i));
        let pad = self.drawn.saturating_sub(line.chars().count());
        err!("\r{line}{}", " ".repeat(pad));
        let _ = std::io::stderr().flush();
        self.drawn = line.chars().count();
    }

    /// Remove the bar (before the final summary).
    pub(super) fn clear(&mut self) {
        if self.drawn > 0 {
            err!("\r{}\r", " ".repeat(self.drawn));
            let _ = std::io::stderr().flush();
            self.drawn = 0;
        }
    }
}

/// How often a line of progress is printed off a terminal.
const NOTE_EVERY: Duration = Duration::from_secs(5);

/// How long a phase runs off a terminal before its first line: 2 s, or
/// the tests' `firstnote@MS` (`karigami_folder::fault`).
fn first_note() -> Duration {
    karigami_folder::fault::first_note().unwrap_or(Duration::from_secs(2))
}

/// Run `work`, and while it runs longer than a second say so on stderr:
/// the elapsed time redrawn in place on a terminal, a line every
/// `NOTE_EVERY` otherwise (logs, CI); nothing when `quiet`. For phases that
/// report no progress of their own (growing, verifying, laying out,
/// tuning).
pub(super) fn heartbeat<T>(what: &str, quiet: bool, work: impl FnOnce() -> T) -> T {
    heartbeat_saying(|seconds| format!("{what}: {seconds} s"), quiet, work)
}

/// `heartbeat` with its line written by `line` from the seconds elapsed
/// (for phases that count their own progress: `simulate --explore`).
pub(super) fn heartbeat_saying<T>(
    line: impl Fn(u64) -> String + Send,
    quiet: bool,
    work: impl FnOnce() -> T,
) -> T {
    if quiet {
        return work();
    }
    let tty = std::io::stderr().is_terminal();
    let (done, wait) = mpsc::channel::<()>();
    std::thread::scope(|s| {
        s.spawn(move || {
            let started = Instant::now();
            let (first, every) = if tty {
                (Duration::from_secs(1), Duration::from_millis(500))
            } else {
                (first_note(), NOTE_EVERY)
            };
            let mut next = first;
            let mut drawn = 0;
            loop {
                let left = next.saturating_sub(started.elapsed());
                match wait.recv_timeout(left) {
                    Err(mpsc::RecvTimeoutError::Timeout) => {}
                    _ => break,
                }
                let line = line(started.elapsed().as_secs());
                if tty {
                    err!("\r{line}");
                    let _ = std::io::stderr().flush();
                    drawn = line.chars().count();
                } else {
                    errln!("{line}");
                }
                next += every;
            }
            if drawn > 0 {
                err!("\r{}\r", " ".repeat(drawn));
                let _ = std::io::stderr().flush();
            }
        });
        let result = work();
        drop(done);
        result
    })
}

/// A fitted row has been grown: shown in place on a terminal, as a line with --verbose.
pub(super) fn fit_note(note: &str, v: super::args::Verbosity, bar: &mut Progress) {
    if v.verbose {
        errln!("{note}");
    } else {
        bar.note(note);
    }
}
