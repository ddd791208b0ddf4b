//! Bounded work (docs/commands.md, "Time limits"): the `--time-limit` of a
//! run as a `Deadline` the long loops check, once a Newton iteration, a
//! start or a design, and the `Stopped` they return on expiry, saying how
//! far they got. Work estimated above the limit (`Deadline::allows`) is
//! refused before it starts.
//!
//! A command uses it so: the CLI makes one `Deadline::after(limit)` when
//! it starts (or `Deadline::none()`), hands it down (`Overrides::deadline`
//! puts it in the `Design`), and each loop asks `expired()` between pieces
//! of work; an expired one ends the loop with `stopped(done, of, what)`,
//! which the command reports as `ErrorKind::TimeLimit` (exit status 4)
//! and writes nothing. Without a limit nothing changes: `expired()` is
//! always false and the results are those of a run without the check.
//!
//! Work allowed but reckoned at `SAY_ABOVE` seconds or more is said before
//! it starts, one line on stderr (`Estimate::said`), so that a long run is
//! never a surprise.

use std::time::{Duration, Instant};

/// Work estimated above this is refused unless `--time-limit` allows
/// more: one hour.
pub const DEFAULT_CEILING: f64 = 3600.0;

/// Estimates below this are not worth a line up front (seconds).
pub const SAY_ABOVE: f64 = 5.0;

/// When a run's time is up, if ever.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Deadline {
    start: Option<Instant>,
    limit: Option<Duration>,
}

impl Deadline {
    /// No limit: `expired` is never true.
    pub const fn none() -> Self {
        Deadline {
            start: None,
            limit: None,
        }
    }

    /// A limit of `seconds` from now (`--time-limit`).
    pub fn after(seconds: f64) -> Self {
        Deadline {
            start: Some(Instant::now()),
            limit: Some(Duration::from_secs_f64(seconds.clamp(0.0, 1e9))),
        }
    }

    /// The instant the time is up, for solvers that take one.
    pub fn at(&self) -> Option<Instant> {
        Some(self.start? + self.limit?)
    }

    /// The limit in seconds, if any.
    pub fn limit(&self) -> Option<f64> {
        self.limit.map(|l| l.as_secs_f64())
    }

    /// Seconds since the limit started (0 without one).
    pub fn elapsed(&self) -> f64 {
        self.start.map_or(0.0, |s| s.elapsed().as_secs_f64())
    }

    /// The same start with `seconds` less time (none left at most), for
    /// work that must leave some of the limit to what follows it.
    pub fn less(&self, seconds: f64) -> Self {
        Deadline {
            start: self.start,
            limit: self
                .limit
                .map(|l| l.saturating_sub(Duration::from_secs_f64(seconds.clamp(0.0, 1e9)))),
        }
    }

    /// Whether the time is up.
    pub fn expired(&self) -> bool {
        self.at().is_some_and(|at| Instant::now() >= at)
    }

    /// The most work a run may be estimated to take (seconds): the limit,
    /// or `DEFAULT_CEILING` without one.
    pub fn ceiling(&self) -> f64 {
        self.limit().unwrap_or(DEFAULT_CEILING)
    }

    /// Whether work estimated at `seconds` may start.
    pub fn allows(&self, seconds: f64) -> bool {
        seconds <= self.ceiling()
    }

    /// How far a loop stopped by this deadline got: `done` of `of` `what`.
    pub fn stopped(&self, done: usize, of: usize, what: &str) -> Stopped {
        Stopped {
            done,
            of,
            what: what.to_string(),
            seconds: self.elapsed(),
            limit: self.limit().unwrap_or(0.0),
        }
    }
}

/// Work stopped at its deadline: how far it got.
#[derive(Clone, Debug, PartialEq)]
pub struct Stopped {
    /// Pieces finished.
    pub done: usize,
    /// Pieces asked for (0: not known ahead).
    pub of: usize,
    /// What a piece is: "starts", "designs", "Newton iterations".
    pub what: String,
    /// Seconds run.
    pub seconds: f64,
    /// The limit (seconds).
    pub limit: f64,
}

impl std::fmt::Display for Stopped {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let of = if self.of > 0 {
            format!(" of {}", self.of)
        } else {
            String::new()
        };
        write!(
            f,
            "stopped at {}{of} {} after {:.1} s, the time limit of {} s",
            self.done, self.what, self.seconds, self.limit
        )
    }
}

/// The tests' hook (the `fault-injection` feature, which the released
/// binary is built without): `KARIGAMI_FAULT_RECKON=F` scales a
/// simulation's, the helix tuner's or `design`'s reckoned seconds by F, so that a test
/// can run one that is allowed past its `--time-limit` in a fraction of a
/// second and see it stop (tests/limits.rs).
#[cfg(feature = "fault-injection")]
pub fn reckoned_low(seconds: f64) -> f64 {
    std::env::var("KARIGAMI_FAULT_RECKON")
        .ok()
        .and_then(|f| f.parse::<f64>().ok())
        .map_or(seconds, |f| seconds * f)
}

/// Without the `fault-injection` feature: the seconds as reckoned.
#[cfg(not(feature = "fault-injection"))]
pub fn reckoned_low(seconds: f64) -> f64 {
    seconds
}

/// Work reckoned from the input before it starts (docs/commands.md,
/// "Time limits"): its seconds and what they count.
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// The seconds reckoned.
    pub seconds: f64,
    /// What was counted: "simulation: 3,400 rod nodes x ~11 Newton
    /// iterations".
    pub what: String,
}

impl Estimate {
    /// The line said on stderr before work reckoned at `SAY_ABOVE` seconds
    /// or more starts, with the limit it runs under; None for shorter work,
    /// and for work the limit refuses (its refusal says the estimate).
    pub fn said(&self, deadline: &Deadline) -> Option<String> {
        if !(self.seconds >= SAY_ABOVE && deadline.allows(self.seconds)) {
            return None;
        }
        let bound = match deadline.limit() {
            Some(l) => format!("it stops at the --time-limit of {}", duration(l)),
            None => "give --time-limit SECONDS to bound it".to_string(),
        };
        Some(format!(
            "{SAID}{} ({}); {bound}",
            duration(self.seconds),
            self.what
        ))
    }
}

/// How a line `Estimate::said` gives starts.
const SAID: &str = "estimated ";

impl Estimate {
    /// Whether `line` is one `said` gave, for a caller that hears it among
    /// progress notes (the optimiser's) and says it as its own line.
    pub fn is_said(line: &str) -> bool {
        line.starts_with(SAID)
    }
}

/// A duration for a message: microseconds below a millisecond,
/// milliseconds below a second, seconds below
/// two minutes, then minutes, then hours.
pub fn duration(seconds: f64) -> String {
    if !seconds.is_finite() {
        "forever".to_string()
    } else if seconds < 1e-3 {
        format!("{:.0} us", seconds * 1e6)
    } else if seconds < 1.0 {
        format!("{:.0} ms", seconds * 1000.0)
    } else if seconds < 120.0 {
        format!("{seconds:.1} s")
    } else if seconds < 3600.0 {
        format!("{:.0} min", seconds / 60.0)
    } else {
        format!("{:.1} h", seconds / 3600.0)
    }
}

/// A count for an estimate, rounded, its thousands grouped: "188,472".
pub fn count(n: f64) -> String {
    if !(n.is_finite() && n.abs() < 1e15) {
        return format!("{n:e}");
    }
    let digits = format!("{:.0}", n.abs());
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    if n < -0.5 {
        out.insert(0, '-');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_limit_never_expires_and_a_zero_limit_at_once() {
        assert!(!Deadline::none().expired());
        assert_eq!(Deadline::none().ceiling(), DEFAULT_CEILING);
        assert!(Deadline::after(0.0).expired());
        assert!(!Deadline::after(3600.0).expired());
        assert!(Deadline::after(5.0).allows(5.0) && !Deadline::after(5.0).allows(5.1));
    }

    #[test]
    fn stopped_says_how_far() {
        let s = Stopped {
            done: 12,
            of: 60,
            what: "starts".into(),
            seconds: 30.04,
            limit: 30.0,
        };
        assert_eq!(
            s.to_string(),
            "stopped at 12 of 60 starts after 30.0 s, the time limit of 30 s"
        );
        assert_eq!(duration(68000.0), "18.9 h");
        assert_eq!(duration(300.0), "5 min");
        assert_eq!(duration(3600.0), "1.0 h");
        assert_eq!(duration(0.017), "17 ms");
        assert_eq!(duration(1.66e-5), "17 us");
        assert_eq!(count(188_471.6), "188,472");
        assert_eq!(count(999.0), "999");
        assert_eq!(count(5_000_000.0), "5,000,000");
    }

    #[test]
    fn an_estimate_is_said_from_five_seconds() {
        let e = |seconds| Estimate {
            seconds,
            what: "simulation: 3,400 rod nodes x ~11 Newton iterations".into(),
        };
        assert_eq!(e(4.99).said(&Deadline::none()), None);
        assert_eq!(e(f64::NAN).said(&Deadline::none()), None);
        assert_eq!(e(40.0).said(&Deadline::after(30.0)), None);
        assert_eq!(
            e(40.0).said(&Deadline::none()).as_deref(),
            Some(
                "estimated 40.0 s (simulation: 3,400 rod nodes x ~11 Newton iterations); give --time-limit SECONDS to bound it"
            )
        );
        assert_eq!(
            e(5.0).said(&Deadline::after(60.0)).as_deref(),
            Some(
                "estimated 5.0 s (simulation: 3,400 rod nodes x ~11 Newton iterations); it stops at the --time-limit of 60.0 s"
            )
        );
    }
}
