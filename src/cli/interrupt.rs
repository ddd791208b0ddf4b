//! SIGINT (Ctrl-C) and SIGTERM: the run's own entries beside --out (its
//! staging folder, up to a gigabyte, its lock, a temporary file) are
//! removed before it exits, instead of waiting for the next build into
//! the same folder (issue 36, finding 9). A thread of signal-hook's waits
//! for the signals (the package forbids `unsafe`, which a handler of our
//! own would need); on one it waits for a commit under way to finish
//! (`commit`), removes what is registered, and exits as the signal would.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// This run's entries to remove if it is interrupted, by registration.
static LEFT: Mutex<Vec<(u64, PathBuf)>> = Mutex::new(Vec::new());
/// Held through a commit: an interrupt then waits for it to finish.
static COMMIT: Mutex<()> = Mutex::new(());

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
                clean_up();
                // The default action now: the parent sees the signal.
                let _ = signal_hook::low_level::emulate_default_handler(signal);
                std::process::exit(128 + signal);
            }
        });
}

#[cfg(not(unix))]
pub(crate) fn start() {}

/// Remove every registered entry, after any commit under way.
fn clean_up() {
    // Never released: the process exits holding it, so no commit starts.
    let commit = COMMIT.lock().unwrap_or_else(|e| e.into_inner());
    std::mem::forget(commit);
    let left = LEFT.lock().unwrap_or_else(|e| e.into_inner());
    // Newest first: a staging folder before the lock that guards it.
    for (_, path) in left.iter().rev() {
        remove_entry(path);
    }
    std::mem::forget(left);
}

/// Remove a file or folder this run made (a link is removed, never
/// followed), trying again if a folder is still being written into.
fn remove_entry(path: &Path) {
    for _ in 0..5 {
        let removed = match fs::symlink_metadata(path) {
            Ok(m) if m.is_dir() => fs::remove_dir_all(path),
            Ok(_) => fs::remove_file(path),
            Err(_) => return,
        };
        if removed.is_ok() {
            return;
        }
    }
}

/// An entry removed if the run is interrupted, until this is dropped.
pub(crate) struct Registered(u64);

/// Register `path` (a file or folder this run made, and only it).
pub(crate) fn register(path: &Path) -> Registered {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let id = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let mut left = LEFT.lock().unwrap_or_else(|e| e.into_inner());
    left.push((id, path.to_path_buf()));
    Registered(id)
}

impl Drop for Registered {
    fn drop(&mut self) {
        let mut left = LEFT.lock().unwrap_or_else(|e| e.into_inner());
        left.retain(|(id, _)| *id != self.0);
    }
}

/// A commit under way: an interrupt waits until this is dropped.
pub(crate) fn commit() -> MutexGuard<'static, ()> {
    COMMIT.lock().unwrap_or_else(|e| e.into_inner())
}
