//! Committing a build into a folder that cannot be moved: on an overlay
//! file system, a folder from a lower layer (a build folder made in an
//! earlier container layer) can be neither renamed nor swapped (EXDEV),
//! so the new build's files are moved into it instead. Not atomic: a run
//! killed meanwhile leaves a build folder holding some of each build's
//! files, which the next build replaces; nothing of anyone's is deleted
//! on the way (what the check did not see stays, an edited file is kept
//! aside first).

use crate::marker::{MARKER, STAGING, is_folder};
use crate::words::plural;
use crate::{Staged, fault, hidden, remove, remove_any, warn};
use std::collections::BTreeSet;
use std::ffi::{OsStr, OsString};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

impl Staged<'_> {
    /// Put the new build's files in the target folder itself: the earlier
    /// build's own files go (not its marker yet), those edited since it was
    /// built are kept aside, the new files come in, the new marker last.
    pub(crate) fn in_place(&mut self) -> io::Result<()> {
        let out = self.out;
        let target = &out.target;
        let (seen, edited) = out.unedited(target);
        let kept = keep_edits(target, &edited)?;
        let mut files: BTreeSet<OsString> = seen.clone();
        files.remove(OsStr::new(MARKER));
        remove::remove_files(target, &files);
        fault::commit("move the new build in");
        move_into(&self.fresh, target)?;
        fault::commit("move the marker in");
        fs::rename(self.fresh.join(MARKER), target.join(MARKER))?;
        // The earlier build's folders that are empty now (deepest first:
        // a folder's contents sort after it).
        for rel in seen.iter().rev().filter(|e| is_folder(e)) {
            let _ = fs::remove_dir(target.join(rel));
        }
        remove_any(&self.fresh)?;
        if let Some(aside) = kept {
            warn(&format!(
                "warning: {} of the earlier build of {} changed since karigami wrote them ({}); the rebuild replaced them, and they are kept in {}",
                plural(edited.len(), "file"),
                target.display(),
                edited.join(", "),
                aside.display()
            ));
        }
        Ok(())
    }
}

/// Move the files `edited` (paths inside `target`) to a new, visible
/// folder beside it (`OUT.karigami-kept-N`); where, if there were any.
fn keep_edits(target: &Path, edited: &[String]) -> io::Result<Option<PathBuf>> {
    if edited.is_empty() {
        return Ok(None);
    }
    let name = target.file_name().unwrap_or_default();
    let aside = (1..100)
        .map(|n| target.with_file_name(&hidden(name, &format!("kept-{n}"))[1..]))
        .find(|a| fs::create_dir(a).is_ok())
        .ok_or_else(|| io::Error::other("no free name for a folder to keep edited files in"))?;
    for rel in edited {
        let to = aside.join(rel);
        if let Some(dir) = to.parent() {
            fs::create_dir_all(dir)?;
        }
        fs::rename(target.join(rel), to)?;
    }
    Ok(Some(aside))
}

/// Move every entry of `from` but its marker into `to`, merging folders:
/// a file never replaces one that is there (something that appeared).
fn move_into(from: &Path, to: &Path) -> io::Result<()> {
    let mut entries: Vec<(PathBuf, bool)> = Vec::new();
    crate::walk(from, |path, folder| {
        entries.push((
            path.strip_prefix(from).unwrap_or(path).to_path_buf(),
            folder,
        ));
        Ok(())
    })?;
    for (rel, folder) in entries {
        if rel == Path::new(MARKER) || rel == Path::new(STAGING) {
            continue;
        }
        let dest = to.join(&rel);
        if folder {
            match fs::create_dir(&dest) {
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists && dest.is_dir() => {}
                made => made?,
            }
        } else {
            rename_new(&from.join(&rel), &dest)?;
        }
    }
    Ok(())
}

/// Rename a file to a name that must be free.
#[cfg(target_os = "linux")]
fn rename_new(from: &Path, to: &Path) -> io::Result<()> {
    use rustix::fs::{CWD, RenameFlags, renameat_with};
    match renameat_with(CWD, from, CWD, to, RenameFlags::NOREPLACE) {
        Err(e) if e == rustix::io::Errno::INVAL => plain_rename_new(from, to),
        done => done.map_err(|e| taken(to, e.into())),
    }
}

#[cfg(not(target_os = "linux"))]
fn rename_new(from: &Path, to: &Path) -> io::Result<()> {
    plain_rename_new(from, to)
}

/// Where the system cannot rename without replacing: checked first.
fn plain_rename_new(from: &Path, to: &Path) -> io::Result<()> {
    if fs::symlink_metadata(to).is_ok() {
        return Err(taken(to, io::Error::from(io::ErrorKind::AlreadyExists)));
    }
    fs::rename(from, to)
}

fn taken(to: &Path, e: io::Error) -> io::Error {
    if e.kind() == io::ErrorKind::AlreadyExists {
        io::Error::other(format!(
            "{} appeared while the build ran, where a file of the build goes",
            to.display()
        ))
    } else {
        e
    }
}
