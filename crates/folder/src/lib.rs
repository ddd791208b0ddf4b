//! karigami's build folders (karigami's docs/build-folders.md): written so
//! that no reader ever sees a half-written file or a mix of two builds,
//! nothing is written outside `--out`, and no file that is not the tool's
//! own output is deleted without the user asking and being told.
//!
//! A build folder is written as a staging folder beside `--out`
//! (`.OUT.karigami-new-PID`) and swapped in whole: with one atomic
//! `renameat2(RENAME_EXCHANGE)` on Linux, else with two renames whose window
//! the next run repairs (the set-aside `.OUT.karigami-old-PID` is put back).
//! A lock file beside the folder (`.OUT.karigami-lock`) keeps two runs from
//! writing the same folder; whoever holds it removes staging folders that
//! killed runs left behind: whole if one was never `--out` (it is still
//! tagged), else only the files a build wrote, keeping the rest aside.
//! Build folders carry a marker file written only by builds, so that
//! nothing else is mistaken for one.
//!
//! A crate of its own so that its transactions are tested apart from the
//! pipeline, and so that its fault hooks (`fault`) exist only in the
//! builds that ask for them (the feature `fault-injection`). It knows
//! nothing of recipes or lattices: its errors (`Error`) are facts that the
//! program maps to its own kinds and exit statuses.

mod atomic;
mod bounded;
mod error;
pub mod fault;
mod in_place;
pub mod interrupt;
mod lock;
mod marker;
mod out_dir;
mod record;
mod remove;
mod staged;
mod words;

pub use atomic::{create_like, replace_like, write_atomic};
pub use bounded::{Links, open_plain, read_plain};
pub use error::{Doing, Error, Untrusted};
pub use marker::MARKER;
pub use out_dir::OutDir;
pub use record::{inputs, start_program_hash};
pub use staged::Staged;

use std::ffi::OsStr;
use std::fs;
use std::io::{self, Write};
use std::path::Path;
use std::sync::OnceLock;

/// What the program writing build folders says of itself, set once a run
/// before any folder is opened (`set_host`).
pub struct Host {
    /// The program and its version, as each marker names its writer
    /// ("karigami 0.1.0").
    pub program: &'static str,
    /// Where a commit's warnings go, each a whole line without its
    /// newline: the program's stderr, whose failed writes fail its run.
    pub warn: fn(&str),
}

static HOST: OnceLock<Host> = OnceLock::new();

/// Say who writes the build folders of this run; a second call is
/// ignored (false), as the markers of one run name one program.
pub fn set_host(host: Host) -> bool {
    HOST.set(host).is_ok()
}

/// The host set, or this crate itself with warnings on stderr (tests).
fn host() -> &'static Host {
    HOST.get_or_init(|| Host {
        program: concat!("karigami-folder ", env!("CARGO_PKG_VERSION")),
        warn: |line| {
            let _ = writeln!(io::stderr(), "{line}");
        },
    })
}

/// A warning of a commit, for the user (`Host::warn`).
fn warn(line: &str) {
    (host().warn)(line);
}

/// The folder `path` is in: its parent, or `.` for a bare name (whose
/// parent is the empty path).
pub fn dir_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// A hidden name beside `name` for the tool's own temporary entries; long
/// names are shortened (with a hash, so that two long names stay apart) to
/// leave room for the suffix within the 255-byte limit of a file name.
fn hidden(name: &OsStr, suffix: &str) -> String {
    const ROOM: usize = 200;
    // A name that is not UTF-8 is shown with replacement characters, which
    // two names can share (`q\xfe`, `q\xfd`): the hash of its bytes keeps
    // their locks and staging folders apart.
    let bytes = name.as_encoded_bytes();
    let name = match name.to_str() {
        Some(plain) => std::borrow::Cow::Borrowed(plain),
        None => format!("{}~{:016x}", name.to_string_lossy(), words::fnv1a(bytes)).into(),
    };
    let short = if name.len() <= ROOM {
        name.into_owned()
    } else {
        let mut end = ROOM;
        while !name.is_char_boundary(end) {
            end -= 1;
        }
        let hash = words::fnv1a(name.as_bytes());
        format!("{}~{hash:016x}", &name[..end])
    };
    format!(".{short}.karigami-{suffix}")
}

/// Visit every entry under `root`, folders before their contents, without
/// following links: `visit(path, is_folder)`. An entry removed while it
/// is listed is skipped (someone tidying the folder), not an error.
fn walk(root: &Path, mut visit: impl FnMut(&Path, bool) -> io::Result<()>) -> io::Result<()> {
    let gone = |e: &io::Error| e.kind() == io::ErrorKind::NotFound;
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let list = match fs::read_dir(&dir) {
            Err(e) if gone(&e) && dir != root => continue,
            list => list?,
        };
        for entry in list {
            let entry = entry?;
            let path = entry.path();
            let folder = match entry.file_type() {
                Err(e) if gone(&e) => continue,
                kind => kind?.is_dir(),
            };
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Finding 10: two names that are not UTF-8 and print alike
    /// (`q\xfe`, `q\xfd`) get their own lock and staging folder.
    #[cfg(unix)]
    #[test]
    fn names_that_print_alike_stay_apart() {
        use std::os::unix::ffi::OsStrExt;
        let (a, b) = (OsStr::from_bytes(b"q\xfe"), OsStr::from_bytes(b"q\xfd"));
        assert_eq!(a.to_string_lossy(), b.to_string_lossy());
        assert_ne!(hidden(a, "lock"), hidden(b, "lock"));
        assert_ne!(hidden(a, "new-1"), hidden(b, "new-1"));
        assert_eq!(hidden(OsStr::new("out"), "lock"), ".out.karigami-lock");
    }
}
