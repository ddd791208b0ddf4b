//! Progress on stderr: a bar redrawn in place when stderr is a terminal,
//! plain lines otherwise (logs, CI), nothing with --quiet.

use std::io::{IsTerminal, Write};

pub struct Progress {
    total: usize,
    done: usize,
    tty: bool,
    quiet: bool,
    /// Width of the line last drawn in place, to clear it.
    drawn: usize,
}

impl Progress {
    pub fn new(total: usize, quiet: bool) -> Self {
        Self {
            total,
            done: 0,
            tty: std::io::stderr().is_terminal(),
            quiet,
            drawn: 0,
        }
    }

    pub fn is_tty(&self) -> bool {
        self.tty && !self.quiet
    }

    /// A recipe has finished: `status` is "ok" or why it failed.
    pub fn finished(&mut self, name: &str, status: &str, seconds: f64) {
        self.done += 1;
        if self.quiet {
            return;
        }
        if self.tty {
            self.draw(&format!("{name} {status}"));
        } else {
            eprintln!(
                "[{}/{}] {name}: {status} ({seconds:.2} s)",
                self.done, self.total
            );
        }
    }

    /// A note while a single long job runs (a fit's rows).
    pub fn note(&mut self, text: &str) {
        if self.is_tty() {
            self.draw(text);
        }
    }

    /// Print a block (an error report) above the bar.
    pub fn print(&mut self, text: &str) {
        self.clear();
        eprint!("{text}");
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
        eprint!("\r{line}{}", " ".repeat(pad));
        let _ = std::io::stderr().flush();
        self.drawn = line.chars().count();
    }

    /// Remove the bar (before the final summary).
    pub fn clear(&mut self) {
        if self.drawn > 0 {
            eprint!("\r{}\r", " ".repeat(self.drawn));
            let _ = std::io::stderr().flush();
            self.drawn = 0;
        }
    }
}
