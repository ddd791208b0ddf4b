//! The lock file beside an output folder that keeps two runs from writing
//! it at once.

use crate::error::{Doing, Error};
use std::fs::{self, File, OpenOptions};
use std::io;
use std::path::{Path, PathBuf};

/// Lock the lock file beside `out`, failing at once if another run holds
/// it. The holder removes the file when done, so a run that opened the
/// file just before it was removed checks that the path still names the
/// file it locked, and tries again if not.
pub(crate) fn take_lock(path: &Path, out: &Path) -> Result<(PathBuf, File), Error> {
    for _ in 0..100 {
        let file = open(path).map_err(|e| {
            let link = fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink());
            let why = if link {
                io::Error::other("it is a symbolic link, which karigami does not follow; remove it")
            } else {
                e
            };
            Error::io(Doing::Write, path, why)
        })?;
        match try_lock(&file) {
            Ok(true) => {}
            Ok(false) => {
                return Err(Error::Locked {
                    out: out.to_path_buf(),
                    lock: path.to_path_buf(),
                });
            }
            Err(e) => return Err(Error::io(Doing::Lock, path, e)),
        }
        if same_file(&file, path) {
            return Ok((path.to_path_buf(), file));
        }
    }
    let moving = io::Error::other("it keeps changing");
    Err(Error::io(Doing::Lock, path, moving))
}

/// Open (or create) the lock file, never through a link: one planted at
/// its name would have the lock created wherever it leads.
fn open(path: &Path) -> io::Result<File> {
    let mut options = OpenOptions::new();
    options.read(true).write(true).create(true).truncate(false);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        let flags = rustix::fs::OFlags::NOFOLLOW | rustix::fs::OFlags::NONBLOCK;
        options.custom_flags(flags.bits() as i32);
    }
    let file = options.open(path)?;
    if !file.metadata()?.is_file() {
        return Err(io::Error::other("it is not a regular file; remove it"));
    }
    Ok(file)
}

/// An exclusive lock without waiting: false when another process holds it.
/// Released when the file is closed, so a killed run releases it too.
#[cfg(unix)]
fn try_lock(file: &File) -> io::Result<bool> {
    use rustix::fs::{FlockOperation, flock};
    match flock(file, FlockOperation::NonBlockingLockExclusive) {
        Ok(()) => Ok(true),
        Err(e) if e == rustix::io::Errno::WOULDBLOCK => Ok(false),
        Err(e) => Err(e.into()),
    }
}

/// Elsewhere std's lock (Rust 1.89 and later).
#[cfg(not(unix))]
#[allow(clippy::incompatible_msrv)]
fn try_lock(file: &File) -> io::Result<bool> {
    match file.try_lock() {
        Ok(()) => Ok(true),
        Err(fs::TryLockError::WouldBlock) => Ok(false),
        Err(fs::TryLockError::Error(e)) => Err(e),
    }
}

#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_: &File, _: &Path) -> bool {
    true
}
