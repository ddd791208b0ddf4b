//! The output folder of a run: checked before any work (not a file, not a
//! link, not holding an input, a build folder unless `--force`), locked,
//! and repaired after interrupted runs.

use crate::bounded::{Links, read_plain};
use crate::error::{Doing, Error, Untrusted, counted, left_as_it_was, shortlist};
use crate::interrupt::{self, Registered};
use crate::lock::take_lock;
use crate::marker::{
    Cleared, MARKER, STAGING, claim, clear, is_folder, leaves_folder, listed, own_entries,
    read_marker,
};
use crate::record::Earlier;
use crate::{dir_of, hidden, remove_any};
use std::collections::BTreeSet;
use std::ffi::{OsStr, OsString};
use std::fs::{self, File};
use std::io;
use std::path::{Path, PathBuf};

/// What an existing `--out` holds that a build replaces.
pub(crate) enum Previous {
    /// Nothing there yet, or an empty folder.
    Nothing,
    /// A build folder (it has the marker).
    Build,
    /// A folder that is not a build folder, replaced because of `--force`:
    /// the files that will be deleted (relative paths).
    Foreign(Vec<String>),
    /// A build folder holding files the build did not write, replaced
    /// because of `--force`: those files.
    Added(Vec<String>),
}

/// The checked, locked output folder of one run. Taken before any work, so
/// that a refusal or a busy folder is reported at once and writes nothing.
pub struct OutDir {
    pub(crate) target: PathBuf,
    pub(crate) parent: PathBuf,
    pub(crate) name: std::ffi::OsString,
    pub(crate) previous: Previous,
    /// What the lock holder repaired or cleaned, for the user.
    pub notes: Vec<String>,
    /// The records of the earlier build in it (`record`), if any.
    pub(crate) earlier: Option<Earlier>,
    /// The marker of the earlier build in it, as read when checked.
    marker: Option<String>,
    /// Every entry the folder held when checked under the lock (`entries`):
    /// all that a commit may delete. Whatever else appears in it while
    /// the build runs is someone's, and stops the commit (`appeared`).
    /// Kept byte for byte: two names that print alike are not the same.
    pub(crate) seen: BTreeSet<OsString>,
    lock: (PathBuf, File),
    /// The lock file, removed on an interrupt.
    _interrupt: Registered,
}
impl Drop for OutDir {
    fn drop(&mut self) {
        // Removed while still locked (see `take_lock`); unlocked on close.
        #[cfg(unix)]
        let _ = fs::remove_file(&self.lock.0);
    }
}

impl OutDir {
    /// Check `out` (a folder name, not a file, not a link, not holding an
    /// input of this run; a build folder unless `force`), take its lock and
    /// repair what interrupted runs left. Errors are whole sentences.
    pub fn open(out: &Path, inputs: &[PathBuf], force: bool) -> Result<Self, Error> {
        // `link/` (or `link/.`) names what the link leads to, not the link:
        // the folder's own name, without them, is what is checked.
        let out = &out.components().collect::<PathBuf>();
        let Some(name) = out.file_name().map(OsStr::to_os_string) else {
            return Err(Error::NotAFolderName { out: out.clone() });
        };
        let parent = dir_of(out).to_path_buf();
        // The first existing ancestor must be a folder.
        let existing = parent
            .ancestors()
            .find(|a| !a.as_os_str().is_empty() && fs::symlink_metadata(a).is_ok());
        if let Some(existing) = existing.filter(|e| !e.is_dir()) {
            return Err(Error::UnderAFile {
                out: out.clone(),
                file: existing.to_path_buf(),
            });
        }
        // A refusal writes nothing: check before creating the lock file
        // (and again under the lock, which is what counts).
        classify(out, inputs, force)?;
        fs::create_dir_all(&parent).map_err(|e| Error::io(Doing::Create, &parent, e))?;
        let lock_path = parent.join(hidden(&name, "lock"));
        let lock = take_lock(&lock_path, out)?;
        let _interrupt = interrupt::register(&lock_path);
        let mut dir = Self {
            target: out.to_path_buf(),
            parent,
            name,
            previous: Previous::Nothing,
            notes: Vec::new(),
            earlier: None,
            marker: None,
            seen: BTreeSet::new(),
            lock,
            _interrupt,
        };
        dir.recover().map_err(|e| Error::io(Doing::Tidy, out, e))?;
        (dir.previous, dir.seen) = classify(out, inputs, force)?;
        if matches!(dir.previous, Previous::Build | Previous::Added(_)) {
            dir.marker = read_marker(out);
            dir.earlier = dir.marker.as_deref().map(Earlier::parse);
        }
        Ok(dir)
    }

    /// Staging folders of earlier runs of this folder (we hold the lock, so
    /// their runs are over): a set-aside old build comes back if the folder
    /// is missing (a run died between the two renames of a commit); every
    /// other one is removed, but for what someone put in it while it was
    /// the folder (`tidy`).
    fn recover(&mut self) -> io::Result<()> {
        let new_prefix = hidden(&self.name, "new-");
        let old_prefix = hidden(&self.name, "old-");
        let mut stale: Vec<PathBuf> = Vec::new();
        let mut old: Vec<PathBuf> = Vec::new();
        for entry in fs::read_dir(&self.parent)? {
            let entry = entry?;
            let file = entry.file_name();
            for (prefix, list) in [(&new_prefix, &mut stale), (&old_prefix, &mut old)] {
                let pid = file
                    .as_encoded_bytes()
                    .strip_prefix(prefix.as_bytes())
                    .unwrap_or_default();
                if !pid.is_empty() && pid.iter().all(u8::is_ascii_digit) {
                    list.push(entry.path());
                }
            }
        }
        old.sort();
        let missing = fs::symlink_metadata(&self.target).is_err();
        let back = if missing { old.pop() } else { None };
        if let Some(back) = back {
            fs::rename(&back, &self.target)?;
            self.notes.push(format!(
                "restored the previous {} that an interrupted run had set aside",
                self.target.display()
            ));
        }
        stale.extend(old);
        let mut removed = 0;
        for path in &stale {
            removed += usize::from(self.tidy(path)?);
        }
        if removed > 0 {
            self.notes.push(format!(
                "removed {removed} staging folder{} left beside {} by interrupted runs",
                if removed == 1 { "" } else { "s" },
                self.target.display()
            ));
        }
        Ok(())
    }

    /// Remove a staging folder an interrupted run left. One still tagged
    /// (`STAGING`) was never the folder: all of it is the build's. Any
    /// other may have been (swapped out, the run killed before its
    /// removal), and what someone put in it then is theirs: only what its
    /// marker lists goes (nothing, without one: a folder `--force` was
    /// replacing), the rest is kept beside the folder, visible. Whether it
    /// was removed whole.
    fn tidy(&mut self, path: &Path) -> io::Result<bool> {
        let tagged = fs::symlink_metadata(path.join(STAGING)).is_ok();
        if tagged || !fs::symlink_metadata(path)?.is_dir() || only_folders(path)? {
            return remove_any(path).map(|()| true);
        }
        let marker = read_marker(path);
        let marked = fs::symlink_metadata(path.join(MARKER)).is_ok();
        let claimed = marker.as_deref().map(|m| claim(path, m));
        let (own, changed) = match &claimed {
            Some(Ok(c)) => (c.own.clone(), c.changed.clone()),
            _ => (BTreeSet::new(), Vec::new()),
        };
        let shown = self.target.display();
        let left = format!("a staging folder an interrupted run left beside {shown}");
        match clear(path, &own, &self.target)? {
            Cleared::Gone => return Ok(true),
            Cleared::Kept { aside, .. } if marker.is_none() && marked => self.notes.push(format!(
                "{left} has a marker that karigami cannot read as one (a link, a FIFO, too large), so nothing in it was deleted; it is kept in {}",
                aside.display()
            )),
            Cleared::Kept { aside, .. } if marker.is_none() => self.notes.push(format!(
                "the folder an interrupted run was replacing (with --force) was left beside {shown}; it is kept in {}: delete it if it is not needed",
                aside.display()
            )),
            Cleared::Kept { aside, .. } if matches!(claimed, Some(Err(_))) => {
                let bad = claimed.and_then(Result::err).unwrap_or_default();
                self.notes.push(format!(
                    "{left} has a marker that lists {bad}, a path outside it, so karigami did not write it and nothing in it was deleted; it is kept in {}",
                    aside.display()
                ));
            }
            Cleared::Kept { aside, .. } if !changed.is_empty() => self.notes.push(format!(
                "{left} held {} changed since the build wrote {}: {}; {} kept in {}",
                counted(&changed),
                if changed.len() == 1 { "it" } else { "them" },
                shortlist(&changed),
                if changed.len() == 1 { "it is" } else { "they are" },
                aside.display()
            )),
            Cleared::Kept { aside, theirs } => self.notes.push(if theirs {
                format!(
                    "{left} held files the build had not written (added while it was {shown}); they are kept in {}",
                    aside.display()
                )
            } else {
                format!(
                    "{left} could not be removed whole; what is left of it is in {}",
                    aside.display()
                )
            }),
            Cleared::Left => {
                return Err(io::Error::other(format!(
                    "{} holds files the build had not written and cannot be moved aside; move them out",
                    path.display()
                )));
            }
        }
        Ok(false)
    }

    /// `seen` without the earlier build's files whose content is not what
    /// it recorded (edited since it was built), checked in `old` (where the
    /// earlier build now is): what a commit may delete; and those files.
    pub(crate) fn unedited(&self, old: &Path) -> (BTreeSet<OsString>, Vec<String>) {
        let Some(Ok(c)) = self.marker.as_deref().map(|m| claim(old, m)) else {
            return (self.seen.clone(), Vec::new());
        };
        let mut seen = self.seen.clone();
        for file in &c.changed {
            seen.remove(OsStr::new(file));
        }
        (seen, c.changed)
    }
}

/// Whether `dir` holds nothing but folders (empty, or holding only
/// folders): what a run killed while it removed a build's folders leaves,
/// which holds nothing of anyone's.
fn only_folders(dir: &Path) -> io::Result<bool> {
    let mut files = false;
    crate::walk(dir, |_, folder| {
        files |= !folder;
        Ok(())
    })?;
    Ok(!files)
}

/// Whether the folder `dir` is where a file system is mounted (a bind
/// mount of a folder of the same file system too, where the system says).
#[cfg(target_os = "linux")]
fn mount_point(dir: &Path) -> bool {
    use rustix::fs::{AtFlags, CWD, StatxAttributes, StatxFlags, statx};
    if let Ok(st) = statx(CWD, dir, AtFlags::SYMLINK_NOFOLLOW, StatxFlags::BASIC_STATS)
        && st.stx_attributes_mask.contains(StatxAttributes::MOUNT_ROOT)
    {
        return st.stx_attributes.contains(StatxAttributes::MOUNT_ROOT);
    }
    other_device(dir)
}

#[cfg(all(unix, not(target_os = "linux")))]
fn mount_point(dir: &Path) -> bool {
    other_device(dir)
}

#[cfg(not(unix))]
fn mount_point(_: &Path) -> bool {
    false
}

/// Whether `dir` is on another device than the folder holding it.
#[cfg(unix)]
fn other_device(dir: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (fs::symlink_metadata(dir), fs::metadata(dir.join(".."))) {
        (Ok(d), Ok(up)) => d.dev() != up.dev(),
        _ => false,
    }
}

/// What `target` holds and every entry in it (`entries`), or why a build
/// must not replace it.
fn classify(
    target: &Path,
    inputs: &[PathBuf],
    force: bool,
) -> Result<(Previous, BTreeSet<OsString>), Error> {
    let out = target.to_path_buf();
    let unreadable = |e| Error::io(Doing::Read, target, e);
    let meta = match fs::symlink_metadata(target) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            return Ok((Previous::Nothing, BTreeSet::new()));
        }
        Err(e) => return Err(unreadable(e)),
        Ok(m) => m,
    };
    if meta.file_type().is_symlink() {
        return Err(Error::IsALink {
            to: fs::read_link(target).unwrap_or_default(),
            dangling: !target.exists(),
            out,
        });
    }
    if !meta.is_dir() {
        return Err(Error::IsAFile { out });
    }
    if mount_point(target) {
        return Err(Error::MountPoint { out });
    }
    let real = fs::canonicalize(target).map_err(unreadable)?;
    for input in inputs {
        if fs::canonicalize(input).is_ok_and(|i| i.starts_with(&real)) {
            let input = input.clone();
            return Err(Error::HoldsInput { out, input });
        }
    }
    if std::env::current_dir()
        .and_then(fs::canonicalize)
        .is_ok_and(|cwd| cwd.starts_with(&real))
    {
        return Err(Error::HoldsCurrentFolder { out });
    }
    let seen = entries(target).map_err(unreadable)?;
    let files = lossy(seen.iter().filter(|e| !is_folder(e)).cloned().collect());
    let marker = read_marker(target);
    let refused = |why| Error::NotABuildFolder {
        out: target.to_path_buf(),
        why,
        files: files.len(),
    };
    if let Some(bad) = marker.as_deref().and_then(leaves_folder) {
        if force {
            return Ok((Previous::Foreign(files), seen));
        }
        return Err(refused(Untrusted::ListsOutside(bad.to_string())));
    }
    if let Some(ours) = marker {
        // Files (and folders) someone added to a build folder are not the
        // tool's to delete without asking; the build's own folders are
        // those that hold its files.
        let own = own_entries(listed(&ours));
        let added = seen.iter().filter(|e| !own.contains(*e)).cloned().collect();
        let added = lossy(outermost(added));
        if added.is_empty() {
            return Ok((Previous::Build, seen));
        }
        if force {
            return Ok((Previous::Added(added), seen));
        }
        return Err(Error::OtherFiles { out, added });
    }
    if seen.is_empty() {
        return Ok((Previous::Nothing, seen));
    }
    if force {
        return Ok((Previous::Foreign(files), seen));
    }
    let older = ["lattice.json", "batch.json"]
        .iter()
        .any(|m| target.join(m).is_file());
    Err(refused(Untrusted::NoMarker { older }))
}

impl OutDir {
    /// A warning for `--force` replacing files that are not the tool's.
    pub fn force_warning(&self) -> Option<String> {
        let (what, files) = match &self.previous {
            Previous::Foreign(files) => ("is not a karigami build folder", files),
            Previous::Added(files) => ("holds files the build did not write", files),
            _ => return None,
        };
        Some(format!(
            "warning: --force: {} {what}; replacing it deletes {}: {}",
            self.target.display(),
            counted(files),
            shortlist(files)
        ))
    }

    /// The folder, as checked (without a trailing `/` or `/.`).
    pub fn path(&self) -> &Path {
        &self.target
    }

    /// A file an earlier build wrote into this folder (`rel` inside it, such
    /// as `disk/deployed.state`), for the pipeline to reuse: None unless the
    /// folder is a build folder and the file a plain file of at most
    /// `limit` bytes. Whatever is read is checked by its reader; a read
    /// that fails is no error (the build just does the work again).
    pub fn earlier_file(&self, rel: &str, limit: u64) -> Option<Vec<u8>> {
        let path = self.plain_file(Path::new(rel))?;
        read_plain(&path, limit, Links::Refuse).ok()
    }

    /// The path of `rel` inside the earlier build in this folder, if it is
    /// a plain file there (not a link, nor under one).
    pub(crate) fn plain_file(&self, rel: &Path) -> Option<PathBuf> {
        if !matches!(self.previous, Previous::Build | Previous::Added(_)) {
            return None;
        }
        // Every folder on the way must be a real folder inside this one: a
        // batch subfolder replaced by a link would lead outside it.
        let mut path = self.target.clone();
        for part in rel.parent().into_iter().flat_map(Path::components) {
            path.push(part);
            if !fs::symlink_metadata(&path).ok()?.is_dir() {
                return None;
            }
        }
        let path = self.target.join(rel);
        fs::symlink_metadata(&path).ok()?.is_file().then_some(path)
    }

    /// What the folder holds if a build does not commit.
    pub fn kept(&self) -> String {
        left_as_it_was(&self.target, self.had_anything())
    }

    /// Whether the folder held a build or files when checked (`Doing::Commit`).
    pub(crate) fn had_anything(&self) -> bool {
        !matches!(self.previous, Previous::Nothing)
    }
}

/// `entries` (sorted) without those inside a folder among them: a folder
/// someone added is named, not every file in it.
fn outermost(entries: Vec<OsString>) -> Vec<OsString> {
    // Sorted (byte by byte), a folder's contents follow it at once.
    let mut kept: Vec<OsString> = Vec::with_capacity(entries.len());
    let mut folder: Option<OsString> = None;
    for e in entries {
        let inside = |f: &OsString| e.as_encoded_bytes().starts_with(f.as_encoded_bytes());
        if folder.as_ref().is_some_and(inside) {
            continue;
        }
        if is_folder(&e) {
            folder = Some(e.clone());
        }
        kept.push(e);
    }
    kept
}

/// Entries as the user is told of them (names that are not UTF-8 shown
/// with a replacement character: for messages only, never to match).
fn lossy(entries: Vec<OsString>) -> Vec<String> {
    entries
        .into_iter()
        .map(|e| e.to_string_lossy().into_owned())
        .collect()
}

/// Every entry under `dir` (relative, sorted; a folder's name ends in
/// `/`), without following links: files, links, folders, empty or not.
/// Names are kept as they are: two that print alike stay apart.
pub(crate) fn entries(dir: &Path) -> io::Result<BTreeSet<OsString>> {
    let mut out = BTreeSet::new();
    crate::walk(dir, |path, folder| {
        let mut rel = path
            .strip_prefix(dir)
            .unwrap_or(path)
            .as_os_str()
            .to_owned();
        if folder {
            rel.push("/");
        }
        out.insert(rel);
        Ok(())
    })?;
    Ok(out)
}

impl OutDir {
    /// What `dir` (the folder, or the earlier build just swapped out of
    /// it) holds that it did not when checked (`seen`): entries someone
    /// added while the build ran, outermost first. A folder that is no
    /// longer a folder (a link, a file) is itself an entry that appeared.
    pub(crate) fn appeared(&self, dir: &Path) -> io::Result<Vec<String>> {
        match fs::symlink_metadata(dir) {
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
            Err(e) => return Err(e),
            Ok(m) if !m.is_dir() => return Ok(vec![String::new()]),
            Ok(_) => {}
        }
        let now = entries(dir)?;
        Ok(lossy(outermost(
            now.difference(&self.seen).cloned().collect(),
        )))
    }

    /// The refusal of a commit because the entries `appeared` came into
    /// the folder while the build ran.
    pub(crate) fn changed(&self, appeared: &[String]) -> Error {
        Error::Appeared {
            out: self.target.clone(),
            appeared: appeared.to_vec(),
        }
    }
}
