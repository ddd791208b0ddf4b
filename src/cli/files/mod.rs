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
//! killed runs left behind: whole if one was never `--out` (it is still
//! tagged), else only the files a build wrote, keeping the rest aside.
//! Build folders carry a marker file written only by builds, so that
//! nothing else is mistaken for one.

mod atomic;
mod bounded;
mod in_place;
mod input;
mod lock;
mod out_dir;
mod record;
mod remove;
mod staged;

use bounded::Links;

pub(super) use atomic::{OutFile, write_atomic};
pub(super) use input::{read, recipes, safe_component};
pub(super) use out_dir::OutDir;
pub(super) use record::{inputs, start_program_hash};
pub(super) use staged::Staged;

use std::collections::BTreeSet;
use std::ffi::{OsStr, OsString};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// The marker file of a build folder, and its first line.
pub(super) const MARKER: &str = ".karigami-build";
const MARKER_HEAD: &str = "karigami build folder";
/// A staging folder's tag until its marker is written: a staging folder
/// that still has it was never `--out`, and all of it is the build's.
const STAGING: &str = ".karigami-staging";
/// Bumped when the layout of a build folder changes incompatibly.
const FORMAT: u32 = 1;

/// The folder `path` is in: its parent, or `.` for a bare name (whose
/// parent is the empty path).
pub(super) fn dir_of(path: &Path) -> &Path {
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
        None => format!(
            "{}~{:016x}",
            name.to_string_lossy(),
            karigami::util::fnv1a(bytes)
        )
        .into(),
    };
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

/// The files a build folder's marker (its text) lists as the build's own.
fn listed(marker: &str) -> impl Iterator<Item = &str> {
    marker
        .split_once("\nfiles:\n")
        .map_or("", |(_, l)| l)
        .lines()
        .take_while(|l| !l.is_empty())
}

/// The first file a marker lists that is not a plain path inside its
/// folder (absolute, holding `..`): no build writes one, so the marker is
/// not to be trusted with any delete.
fn leaves_folder(marker: &str) -> Option<&str> {
    listed(marker).find(|f| !staged::stays_inside(Path::new(f)))
}

/// Larger markers are not read (a marker lists each file on a line and
/// records each build on one; the examples' batch has 18 KiB).
const MAX_MARKER_BYTES: u64 = 32 << 20;

/// The marker of the build folder `dir`, if it has one: a regular file
/// (not a link, a FIFO or a device), of at most `MAX_MARKER_BYTES`, in
/// UTF-8, starting with `MARKER_HEAD`.
fn read_marker(dir: &Path) -> Option<String> {
    let bytes = bounded::read_plain(&dir.join(MARKER), MAX_MARKER_BYTES, Links::Refuse).ok()?;
    String::from_utf8(bytes)
        .ok()
        .filter(|t| t.starts_with(MARKER_HEAD))
}

/// What a build folder's marker claims, checked against the folder `dir`.
struct Claim {
    /// The entries that are the build's own (`own_entries`): the files
    /// listed whose content is what the build recorded.
    own: BTreeSet<OsString>,
    /// Files listed whose content is not what was recorded (edited since,
    /// or never recorded): someone's now, never deleted.
    changed: Vec<String>,
}

/// Check each file `marker` lists against what it records (`Claim`); an
/// error is a listed path that leaves the folder (`leaves_folder`).
fn claim(dir: &Path, marker: &str) -> Result<Claim, String> {
    if let Some(bad) = leaves_folder(marker) {
        return Err(bad.to_string());
    }
    let earlier = record::Earlier::parse(marker);
    let recorded = earlier.recorded();
    let mut buf = vec![0; record::BUFFER];
    let (mut same, mut changed) = (Vec::new(), Vec::new());
    for file in listed(marker) {
        let path = dir.join(file);
        match recorded.get(file) {
            Some(&was) if record::unchanged(&path, was, &mut buf) => same.push(file),
            _ if fs::symlink_metadata(&path).is_ok() => changed.push(file.to_string()),
            _ => {}
        }
    }
    Ok(Claim {
        own: own_entries(same),
        changed,
    })
}

/// Whether an entry (as `out_dir::entries` lists them) is a folder: its
/// name ends in `/`.
fn is_folder(entry: &OsStr) -> bool {
    entry.as_encoded_bytes().ends_with(b"/")
}

/// The entries a build owns in its folder, as `out_dir::entries` lists
/// them: its `files`, the folders they are in, and the marker.
fn own_entries<'a>(files: impl IntoIterator<Item = &'a str>) -> BTreeSet<OsString> {
    let mut own = BTreeSet::from([OsString::from(MARKER)]);
    for file in files {
        own.insert(file.into());
        for folder in Path::new(file).ancestors().skip(1) {
            if !folder.as_os_str().is_empty() {
                let mut folder = folder.as_os_str().to_os_string();
                folder.push("/");
                own.insert(folder);
            }
        }
    }
    own
}

/// What became of a folder that may hold someone's entries (`clear`).
enum Cleared {
    /// It held only the build's own entries: it is gone.
    Gone,
    /// Entries were left: the folder was moved here (`aside`), beside the
    /// target, visible, for the user; `theirs` when any is someone's, not
    /// one of the build's that could not be removed.
    Kept { aside: PathBuf, theirs: bool },
    /// Someone's entries were left and it could not be moved: still there.
    Left,
}

/// Remove from `dir` (a folder that was, or may have been, the target) only
/// the entries `own` names; anything else is someone's, and the folder
/// holding it is moved beside `target` as `OUT.karigami-kept-N`, not left
/// at a staging name that a later run tidies away.
fn clear(dir: &Path, own: &BTreeSet<OsString>, target: &Path) -> io::Result<Cleared> {
    if remove::remove_seen(dir, own)? {
        return Ok(Cleared::Gone);
    }
    let theirs = out_dir::entries(dir).map_or(true, |left| left.iter().any(|e| !own.contains(e)));
    let name = target.file_name().unwrap_or_default();
    for n in 1..100 {
        // `OUT.karigami-kept-N`: `hidden`'s name (short enough) without its dot.
        let aside = target.with_file_name(&hidden(name, &format!("kept-{n}"))[1..]);
        if fs::symlink_metadata(&aside).is_err() && fs::rename(dir, &aside).is_ok() {
            return Ok(Cleared::Kept { aside, theirs });
        }
    }
    Ok(Cleared::Left)
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

    /// Finding 2: a listed path that is absolute or holds `..` is found.
    #[test]
    fn a_marker_listing_a_path_outside_is_found() {
        let marker = |f: &str| format!("{MARKER_HEAD}\nfiles:\na.svg\n{f}\n\nbuilds:\n");
        assert_eq!(leaves_folder(&marker("b/c.svg")), None);
        assert_eq!(leaves_folder(&marker("../x")), Some("../x"));
        assert_eq!(leaves_folder(&marker("/far/y")), Some("/far/y"));
        assert_eq!(leaves_folder(&marker("b/../../x")), Some("b/../../x"));
    }
}
