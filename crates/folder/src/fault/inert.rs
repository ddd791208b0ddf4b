//! The hooks without the feature `fault-injection`: each is the plain
//! operation, or nothing, and the environment is never read.

use std::fs::File;
use std::io;
use std::path::Path;

/// When a user adds an entry to a folder being committed (see `injected`).
#[derive(Clone, Copy)]
pub(crate) enum Moment {
    BeforeCheck,
    BeforeSwap,
    SwappedOut,
    SwappedIn,
}

#[inline]
pub(crate) fn write(_: &str) -> io::Result<()> {
    Ok(())
}

#[inline]
pub(crate) fn commit(_: &str) {}

#[inline]
pub(crate) fn add(_: &Path, _: Moment) {}

/// Nothing: no test edits the file (see `injected::edit`).
#[inline]
pub fn edit(_: &Path) {}

/// None: progress keeps its own clock (see `injected::first_note`).
#[inline]
pub fn first_note() -> Option<std::time::Duration> {
    None
}

#[inline]
pub(crate) fn no_exchange() -> bool {
    false
}

#[inline]
pub(crate) fn cross_device() -> bool {
    false
}

#[inline]
pub(crate) fn rename_folder(from: &Path, to: &Path) -> io::Result<()> {
    std::fs::rename(from, to)
}

#[inline]
pub(crate) fn sync(file: &File) -> io::Result<()> {
    file.sync_all()
}
