//! The marker of a build folder: what it claims is the build's own, read
//! without being steered by it, and the clearing of a folder down to
//! those entries (karigami's docs/build-folders.md).

use crate::bounded::{Links, read_plain};
use crate::{hidden, out_dir, record, remove, staged};
use std::collections::BTreeSet;
use std::ffi::{OsStr, OsString};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// The marker file of a build folder.
pub const MARKER: &str = ".karigami-build";
/// A marker's first line.
pub(crate) const MARKER_HEAD: &str = "karigami build folder";
/// A staging folder's tag until its marker is written: a staging folder
/// that still has it was never `--out`, and all of it is the build's.
pub(crate) const STAGING: &str = ".karigami-staging";
/// Bumped when the layout of a build folder changes incompatibly.
pub(crate) const FORMAT: u32 = 1;

/// The files a build folder's marker (its text) lists as the build's own.
pub(crate) fn listed(marker: &str) -> impl Iterator<Item = &str> {
    marker
        .split_once("\nfiles:\n")
        .map_or("", |(_, l)| l)
        .lines()
        .take_while(|l| !l.is_empty())
}

/// The first file a marker lists that is not a plain path inside its
/// folder (absolute, holding `..`): no build writes one, so the marker is
/// not to be trusted with any delete.
pub(crate) fn leaves_folder(marker: &str) -> Option<&str> {
    listed(marker).find(|f| !staged::stays_inside(Path::new(f)))
}

/// Larger markers are not read (a marker lists each file on a line and
/// records each build on one; the examples' batch has 18 KiB).
const MAX_MARKER_BYTES: u64 = 32 << 20;

/// The marker of the build folder `dir`, if it has one: a regular file
/// (not a link, a FIFO or a device), of at most `MAX_MARKER_BYTES`, in
/// UTF-8, starting with `MARKER_HEAD`.
pub(crate) fn read_marker(dir: &Path) -> Option<String> {
    let bytes = read_plain(&dir.join(MARKER), MAX_MARKER_BYTES, Links::Refuse).ok()?;
    String::from_utf8(bytes)
        .ok()
        .filter(|t| t.starts_with(MARKER_HEAD))
}

/// What a build folder's marker claims, checked against the folder `dir`.
pub(crate) struct Claim {
    /// The entries that are the build's own (`own_entries`): the files
    /// listed whose content is what the build recorded.
    pub(crate) own: BTreeSet<OsString>,
    /// Files listed whose content is not what was recorded (edited since,
    /// or never recorded): someone's now, never deleted.
    pub(crate) changed: Vec<String>,
}

/// Check each file `marker` lists against what it records (`Claim`); an
/// error is a listed path that leaves the folder (`leaves_folder`).
pub(crate) fn claim(dir: &Path, marker: &str) -> Result<Claim, String> {
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
pub(crate) fn is_folder(entry: &OsStr) -> bool {
    entry.as_encoded_bytes().ends_with(b"/")
}

/// The entries a build owns in its folder, as `out_dir::entries` lists
/// them: its `files`, the folders they are in, and the marker.
pub(crate) fn own_entries<'a>(files: impl IntoIterator<Item = &'a str>) -> BTreeSet<OsString> {
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
pub(crate) enum Cleared {
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
pub(crate) fn clear(dir: &Path, own: &BTreeSet<OsString>, target: &Path) -> io::Result<Cleared> {
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
