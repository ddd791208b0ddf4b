//! What an interrupted run must remove before it exits: the entries this
//! run made beside `--out` (its staging folder, up to a gigabyte, its
//! lock, a temporary file), registered while they exist (karigami's
//! docs/build-folders.md, "Interrupts and output"). The program waits for
//! the signals itself and calls `clean_up` on one: a library installs no
//! handler of its own, and the exit status is the program's to choose.

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// This run's entries to remove if it is interrupted, by registration.
static LEFT: Mutex<Vec<(u64, PathBuf)>> = Mutex::new(Vec::new());
/// Held through a commit: an interrupt then waits for it to finish.
static COMMIT: Mutex<()> = Mutex::new(());

/// Remove every registered entry, after any commit under way; then no
/// commit starts and nothing is registered or let go (the caller is to
/// exit at once).
pub fn clean_up() {
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

/// The entries registered now, oldest first: what `clean_up` would remove.
pub fn registered() -> Vec<PathBuf> {
    let left = LEFT.lock().unwrap_or_else(|e| e.into_inner());
    left.iter().map(|(_, p)| p.clone()).collect()
}
