//! SIGINT (Ctrl-C) and SIGTERM: the run's own entries beside --out (its
//! staging folder, up to a gigabyte, its lock, a temporary file) are
//! removed before it exits, instead of waiting for the next build into
//! the same folder (issue 36, finding 9). A thread of signal-hook's waits
//! for the signals (the package forbids `unsafe`, which a handler of our
//! own would need); on one it has the folder crate remove what it
//! registered, after a commit under way (`karigami_folder::interrupt`),
//! and exits as the signal would. The waiting stays here, in the binary:
//! which signals end a run, and with what status, is the program's choice,
//! not its library's.

/// Start waiting for SIGINT and SIGTERM (once a run; a system that
/// refuses leaves the default, which exits at once).
#[cfg(unix)]
pub(crate) fn start() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
        return;
    };
    let _ = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                karigami_folder::interrupt::clean_up();
                // The default action now: the parent sees the signal.
                let _ = signal_hook::low_level::emulate_default_handler(signal);
                std::process::exit(128 + signal);
            }
        });
}

#[cfg(not(unix))]
pub(crate) fn start() {}
