//! Filesystem access: reading recipes and writing build folders so that no
//! reader ever sees a half-written file or a mix of two builds, nothing is
//! written outside `--out`, and no file that is not the tool's own output
//! is deleted without the user asking and being told.
//!
//! A build folder is written as a staging folder beside `--out`
//! (`.OUT.karigami-new-PID`) and swapped in whole: with one atomic
//! `renameat2(RENAME_EXCHANGE)` on Linux, else with two renames whose window
//! the next run repairs (the set-aside `.OUT.karigami-old-PID` is put back).
//! A lock file beside the folder (`.OUT.karigami-lock`) keeps two runs from
//! writing the same folder; whoever holds it removes staging folders that
//! killed runs left behind. Build folders carry a marker file written only
//! by builds, so that nothing else is mistaken for one.

mod atomic;
mod input;
mod lock;
mod out_dir;
mod record;
mod remove;
mod staged;

pub(super) use atomic::{OutFile, write_atomic};
pub(super) use input::{read, recipes, safe_component};
pub(super) use out_dir::OutDir;
pub(super) use record::{inputs, start_program_hash};
pub(super) use staged::Staged;

use std::ffi::OsStr;
use std::fs;
use std::io;
use std::path::Path;

/// The marker file of a build folder, and its first line.
pub(super) const MARKER: &str = ".karigami-build";
const MARKER_HEAD: &str = "karigami build folder";
/// Bumped when the layout of a build folder changes incompatibly.
const FORMAT: u32 = 1;

/// A hidden name beside `name` for the tool's own temporary entries; long
/// names are shortened (with a hash, so that two long names stay apart) to
/// leave room for the suffix within the 255-byte limit of a file name.
fn hidden(name: &OsStr, suffix: &str) -> String {
    let name = name.to_string_lossy();
    const ROOM: usize = 200;
    let short = if name.len() <= ROOM {
        name.into_owned()
    } else {
        let mut end = ROOM;
        while !name.is_char_boundary(end) {
            end -= 1;
        }
        let hash = karigami::util::fnv1a(name.as_bytes());
        format!("{}~{hash:016x}", &name[..end])
    };
    format!(".{short}.karigami-{suffix}")
}

/// Visit every entry under `root`, folders before their contents, without
/// following links: `visit(path, is_folder)`.
fn walk(root: &Path, mut visit: impl FnMut(&Path, bool) -> io::Result<()>) -> io::Result<()> {
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir)? {
            let entry = entry?;
            let path = entry.path();
            let folder = entry.file_type()?.is_dir();
            visit(&path, folder)?;
            if folder {
                stack.push(path);
            }
        }
    }
    Ok(())
}

fn remove_any(path: &Path) -> io::Result<()> {
    match fs::symlink_metadata(path) {
        Ok(m) if m.is_dir() => remove::remove_folder(path),
        Ok(_) => fs::remove_file(path),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e),
    }
}
