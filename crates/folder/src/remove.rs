//! Removing a folder and everything in it, many files at a time: a build
//! removes the build it replaces (and what interrupted runs left). On this
//! machine's ext4 an unlink can wait for the journal (3 to 4 ms each while
//! the disk is busy), and unlinks that wait together share the wait: the
//! examples' 163 files took 0.65 s one by one and 0.09 s eight at a time
//! (karigami's BENCHMARKS.md of 003e36f, "Examples batch, fifth round").

use crate::fault;
use crate::marker::{MARKER, is_folder};
use std::collections::BTreeSet;
use std::ffi::OsString;
use std::io;
use std::path::Path;

/// Threads unlinking at once (each mostly waits for the disk).
const REMOVERS: usize = 8;

/// Remove the folder `path` and everything in it. The files go first,
/// unlinked side by side through handles of the folders they are in,
/// opened without following links (so that a folder swapped for a link
/// meanwhile leads nowhere); `fs::remove_dir_all` then removes what is
/// left, and its error is the one returned.
pub(crate) fn remove_folder(path: &Path) -> io::Result<()> {
    #[cfg(unix)]
    unlink_files(path, None);
    std::fs::remove_dir_all(path)
}

/// Remove from the folder `path` only the entries named in `seen`
/// (relative paths, a folder's ending in `/`, as `out_dir::entries` lists
/// them, byte for byte): files and links are unlinked, folders removed
/// once empty.
/// Whatever else is in it is someone's and stays, and so does every
/// folder on the way to it: false when anything stayed.
pub(crate) fn remove_seen(path: &Path, seen: &BTreeSet<OsString>) -> io::Result<bool> {
    // The marker goes after every file it lists: a run killed meanwhile
    // leaves a folder whose marker still names what is left, which the
    // next run removes, where one without a marker would be kept aside
    // as a folder that was not a build (review31c).
    let marker = OsString::from(MARKER);
    let mut files = seen.clone();
    let has_marker = files.remove(&marker);
    #[cfg(unix)]
    unlink_files(path, Some(&files));
    #[cfg(not(unix))]
    for rel in files.iter().filter(|e| !is_folder(e)) {
        let _ = std::fs::remove_file(path.join(rel));
    }
    if has_marker {
        let _ = std::fs::remove_file(path.join(&marker));
        // A kill here leaves folders and no marker: `OutDir::tidy` removes
        // a staging folder that holds nothing else.
        fault::commit("remove the build's folders");
    }
    // Deepest first: a folder's contents sort after it.
    for rel in seen.iter().rev().filter(|e| is_folder(e)) {
        let _ = std::fs::remove_dir(path.join(rel));
    }
    match std::fs::remove_dir(path) {
        Ok(()) => Ok(true),
        Err(_) if std::fs::read_dir(path)?.next().is_some() => Ok(false),
        Err(e) => Err(e),
    }
}

/// Remove from the folder `path` the files (and links) `files` names (as
/// `remove_seen`), in the folders it names; no folder is removed.
pub(crate) fn remove_files(path: &Path, files: &BTreeSet<OsString>) {
    #[cfg(unix)]
    unlink_files(path, Some(files));
    #[cfg(not(unix))]
    for rel in files.iter().filter(|e| !is_folder(e)) {
        let _ = std::fs::remove_file(path.join(rel));
    }
}

/// Unlink every non-folder under `path` (with `only`, only those it
/// names, in folders it names), `REMOVERS` at a time; whatever fails is
/// left for the caller.
#[cfg(unix)]
fn unlink_files(path: &Path, only: Option<&BTreeSet<OsString>>) {
    use rustix::fs::{AtFlags, CWD, Dir, FileType, Mode, OFlags, openat, statat, unlinkat};
    use std::ffi::{CString, OsStr};
    use std::os::fd::OwnedFd;
    use std::os::unix::ffi::OsStrExt;
    use std::sync::Arc;
    let flags = OFlags::RDONLY | OFlags::DIRECTORY | OFlags::NOFOLLOW | OFlags::CLOEXEC;
    let Ok(root) = openat(CWD, path, flags, Mode::empty()) else {
        return;
    };
    let named = |rel: &OsString| only.is_none_or(|seen| seen.contains(rel));
    // Each folder with its path inside `path` ("" or ending in `/`), its
    // bytes as they are: a lossy name could match someone else's entry.
    let mut folders = vec![(Arc::new(root), OsString::new())];
    let mut files: Vec<(Arc<OwnedFd>, CString)> = Vec::new();
    let mut next = 0;
    while let Some((folder, prefix)) = folders.get(next).cloned() {
        next += 1;
        let Ok(entries) = Dir::read_from(&*folder) else {
            continue;
        };
        for entry in entries.flatten() {
            let name = entry.file_name();
            if name.to_bytes() == b"." || name.to_bytes() == b".." {
                continue;
            }
            let mut rel = prefix.clone();
            rel.push(OsStr::from_bytes(name.to_bytes()));
            let kind = match entry.file_type() {
                // Not known from the listing: asked of the entry itself.
                FileType::Unknown if only.is_some() => {
                    match statat(&*folder, name, AtFlags::SYMLINK_NOFOLLOW) {
                        Ok(st) => FileType::from_raw_mode(st.st_mode),
                        Err(_) => continue,
                    }
                }
                kind => kind,
            };
            match kind {
                FileType::Directory => {
                    rel.push("/");
                    if !named(&rel) {
                        continue;
                    }
                    if let Ok(inner) = openat(&*folder, name, flags, Mode::empty()) {
                        folders.push((Arc::new(inner), rel));
                    }
                }
                // Not known from the listing: left for remove_dir_all.
                FileType::Unknown => {}
                _ if named(&rel) => files.push((Arc::clone(&folder), name.to_owned())),
                _ => {}
            }
        }
    }
    let per_thread = files.len().div_ceil(REMOVERS).max(1);
    std::thread::scope(|s| {
        for chunk in files.chunks(per_thread) {
            s.spawn(move || {
                for (folder, name) in chunk {
                    let _ = unlinkat(&**folder, name.as_c_str(), AtFlags::empty());
                }
            });
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    #[test]
    fn removes_a_tree_and_nothing_a_link_in_it_leads_to() {
        let base = std::env::temp_dir().join(format!("karigami-remove-{}", std::process::id()));
        let _ = fs::remove_dir_all(&base);
        let tree = base.join("tree");
        let outside = base.join("outside");
        fs::create_dir_all(tree.join("a/b")).unwrap();
        fs::create_dir_all(&outside).unwrap();
        fs::write(outside.join("keep.txt"), "kept").unwrap();
        for i in 0..40 {
            fs::write(tree.join(format!("a/b/{i}.txt")), "x").unwrap();
            fs::write(tree.join(format!("{i}.txt")), "y").unwrap();
        }
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&outside, tree.join("a/link")).unwrap();
            // The unlinks alone (what `remove_dir_all` would otherwise do
            // for them): every file and the link gone, the folders left.
            unlink_files(&tree, None);
            assert!(!tree.join("0.txt").exists() && !tree.join("a/b/0.txt").exists());
            assert!(fs::symlink_metadata(tree.join("a/link")).is_err());
            assert!(tree.join("a/b").is_dir());
        }
        remove_folder(&tree).unwrap();
        assert!(!tree.exists());
        // Only what was seen: the rest, and the folders on its way, stay.
        fs::create_dir_all(tree.join("a/b")).unwrap();
        fs::create_dir_all(tree.join("new/empty")).unwrap();
        for f in ["x", "a/y", "a/b/z", "a/b/mine"] {
            fs::write(tree.join(f), f).unwrap();
        }
        let seen: BTreeSet<OsString> = ["x", "a/", "a/y", "a/b/", "a/b/z"]
            .map(OsString::from)
            .into();
        assert!(!remove_seen(&tree, &seen).unwrap());
        assert_eq!(
            fs::read_to_string(tree.join("a/b/mine")).unwrap(),
            "a/b/mine"
        );
        assert!(tree.join("new/empty").is_dir());
        assert!(!tree.join("x").exists() && !tree.join("a/y").exists());
        assert!(!tree.join("a/b/z").exists());
        fs::remove_file(tree.join("a/b/mine")).unwrap();
        fs::remove_dir_all(tree.join("new")).unwrap();
        assert!(remove_seen(&tree, &seen).unwrap());
        assert!(!tree.exists());
        assert_eq!(
            fs::read_to_string(outside.join("keep.txt")).unwrap(),
            "kept"
        );
        fs::remove_dir_all(&base).unwrap();
    }
}
