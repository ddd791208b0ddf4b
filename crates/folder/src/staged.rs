//! Writing a build folder: into a staging folder beside the target that
//! replaces it whole on commit, with the marker written last.

use crate::error::{Doing, Error};
use crate::interrupt::{self, Registered};
use crate::marker::{Cleared, FORMAT, MARKER, MARKER_HEAD, STAGING, clear, own_entries};
use crate::words::plural;
use crate::{OutDir, fault, hidden, host, remove_any, warn};
use std::collections::BTreeSet;
use std::ffi::OsString;
use std::fs::{self, File};
use std::io::{self, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{SyncSender, sync_channel};
use std::thread::JoinHandle;

/// The line that starts the records in the marker, after the file list
/// and an empty line (which no file name can be).
pub(crate) const RECORDS_HEAD: &str = "builds (what each build's files are made from, and each file's length and xxh3-64 hash; a rebuild keeps the files that check out):";

/// Whether `rel` is a relative path of plain components that stays inside
/// the folder it is joined to.
pub(crate) fn stays_inside(rel: &Path) -> bool {
    rel.components().all(|c| match c {
        Component::Normal(n) => {
            let n = n.to_string_lossy();
            !n.is_empty() && !n.chars().any(char::is_control)
        }
        _ => false,
    })
}

/// A build folder being written: files go into a staging folder beside the
/// target, which replaces the target whole on `commit`. Dropped without a
/// commit, the staging folder is removed and the target untouched; killed,
/// the next run removes it.
pub struct Staged<'a> {
    pub(crate) out: &'a OutDir,
    pub(crate) fresh: PathBuf,
    kind: String,
    /// Every file written (relative paths), for the marker.
    pub(crate) written: std::sync::Mutex<Vec<String>>,
    /// Each build's record line (`record`), for the marker.
    records: std::sync::Mutex<Vec<String>>,
    /// Flushes the written files to the disk (`Syncer`).
    syncer: Syncer,
    committed: bool,
    /// Whether the staging folder has been the target (swapped in, then
    /// back): someone may have written into it meanwhile, so it is never
    /// removed whole again (`clear`).
    was_out: bool,
    /// The metadata of the folder the build replaces, if it was one: the
    /// new folder gets its owner and mode.
    like: Option<fs::Metadata>,
    /// The staging folder, removed on an interrupt until it is committed.
    interrupt: Option<Registered>,
}

/// A file written and its path in the build, to flush.
type Written = (File, String);

/// Written files are flushed to the disk (fsync) on threads of their own:
/// an fsync waits for the disk (a median 0.6 ms, up to 20 ms, here), and
/// the examples' batch waited 0.32 s for its 169 in all while the builds
/// could draw (karigami's BENCHMARKS.md of 003e36f, "Examples batch, third
/// round"). Several flush at once: the file system commits the flushes
/// that wait together in one journal commit, where one thread waited for
/// a commit a file (the examples' 163 files: 0.33 to 0.43 s one by one,
/// 0.04 s four at a time, "Examples batch, fifth round"). `commit` waits for every flush
/// before the marker.
struct Syncer {
    /// The queue to the flushing threads, and the threads; None when the
    /// system refused a thread: each file is then flushed as it is written.
    worker: Option<(SyncSender<Written>, Vec<Flusher>)>,
    /// Set when the staging folder is dropped uncommitted: its files are
    /// about to be deleted, so the flushes still queued are skipped.
    cancel: Arc<AtomicBool>,
}

/// A flushing thread: its first failure.
type Flusher = JoinHandle<io::Result<()>>;

/// Flushing threads: waits that come together share a journal commit.
/// The examples' flushes took 0.33 s one at a time and 0.04 s four or
/// sixteen at a time (no gain past four); eight lies between the two, and
/// a thread that waits for the disk costs no CPU.
const FLUSHERS: usize = 8;

impl Syncer {
    fn start() -> Self {
        // A bounded queue: a slow disk holds the writers back before they
        // hold hundreds of files open.
        let (send, files) = sync_channel::<Written>(64);
        let files = Arc::new(std::sync::Mutex::new(files));
        let cancel = Arc::new(AtomicBool::new(false));
        let threads: Vec<_> = (0..FLUSHERS)
            .map_while(|_| {
                let files = Arc::clone(&files);
                let skip = Arc::clone(&cancel);
                std::thread::Builder::new()
                    .name("fsync".into())
                    .spawn(move || {
                        let mut first = Ok(());
                        // The queue's lock is held only to take a file.
                        let next = || files.lock().unwrap_or_else(|e| e.into_inner()).recv();
                        while let Ok((f, rel)) = next() {
                            if !skip.load(Ordering::Relaxed) {
                                first = first.and(flush(&f, &rel));
                            }
                        }
                        first
                    })
                    .ok()
            })
            .collect();
        Self {
            worker: (!threads.is_empty()).then_some((send, threads)),
            cancel,
        }
    }

    fn push(&self, f: File, rel: String) -> io::Result<()> {
        match &self.worker {
            Some((send, _)) => send.send((f, rel)).or_else(|unsent| {
                let (f, rel) = unsent.0;
                flush(&f, &rel)
            }),
            None => flush(&f, &rel),
        }
    }

    /// Wait until every file pushed is flushed; the first failure.
    fn finish(&mut self) -> io::Result<()> {
        match self.worker.take() {
            Some((send, threads)) => {
                // The queue closed, the threads end once it is empty.
                drop(send);
                threads
                    .into_iter()
                    .map(|t| t.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
                    .fold(Ok(()), io::Result::and)
            }
            None => Ok(()),
        }
    }

    /// Stop flushing (the files are about to be deleted) and wait for the
    /// threads, without unwinding again if one panicked.
    fn abandon(&mut self) {
        self.cancel.store(true, Ordering::Relaxed);
        if let Some((send, threads)) = self.worker.take() {
            drop(send);
            for t in threads {
                let _ = t.join();
            }
        }
    }
}

/// Flush one written file to the disk (fsync), its error naming the file.
fn flush(f: &File, rel: &str) -> io::Result<()> {
    fault::sync(f).map_err(|e| flush_failed(rel, &e))
}

/// An fsync failure, with the file it was for (the error comes back from
/// `commit`, away from the build that wrote the file).
fn flush_failed(rel: &str, e: &io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("flushing {rel} to the disk: {e}"))
}

impl<'a> Staged<'a> {
    /// `kind` ("single" or "batch") goes into the marker.
    pub fn new(out: &'a OutDir, kind: &str) -> io::Result<Self> {
        let fresh = out
            .parent
            .join(hidden(&out.name, &format!("new-{}", std::process::id())));
        remove_any(&fresh)?;
        // Registered before it exists (the name is this process's own):
        // a signal between creating and registering it left it behind.
        let interrupt = Some(interrupt::register(&fresh));
        fs::create_dir(&fresh)?;
        // The folder it replaces keeps its owner, group and set-group-ID
        // bit (what is written into it then takes that group) from the
        // start, and its mode at `commit`: one without write permission
        // would refuse the build's files.
        let like = fs::symlink_metadata(&out.target)
            .ok()
            .filter(fs::Metadata::is_dir);
        if let Some(like) = &like {
            same_owner(&fresh, like)?;
        }
        File::create(fresh.join(STAGING))?;
        Ok(Self {
            out,
            fresh,
            kind: kind.to_string(),
            written: std::sync::Mutex::new(Vec::new()),
            records: std::sync::Mutex::new(Vec::new()),
            syncer: Syncer::start(),
            committed: false,
            was_out: false,
            like,
            interrupt,
        })
    }

    /// The marker, written last: what the folder is and every file the
    /// build wrote, so that a later build can tell them from files someone
    /// added; then each build's record, so that a later build can keep
    /// what did not change (`record`).
    fn write_marker(&self) -> io::Result<()> {
        let sorted = |list: &std::sync::Mutex<Vec<String>>| {
            let mut list = list.lock().unwrap_or_else(|e| e.into_inner()).clone();
            list.sort();
            list
        };
        let (files, records) = (sorted(&self.written), sorted(&self.records));
        let text = format!(
            "{MARKER_HEAD}\nformat {FORMAT}\nkind {}\nwritten by {}; a build replaces this folder whole\nfiles:\n{}\n{RECORDS_HEAD}\n{}",
            self.kind,
            host().program,
            files.iter().map(|f| format!("{f}\n")).collect::<String>(),
            records.iter().map(|r| format!("{r}\n")).collect::<String>()
        );
        fault::write(MARKER)?;
        let mut f = File::create(self.fresh.join(MARKER))?;
        f.write_all(text.as_bytes())?;
        fault::sync(&f)?;
        // The tag goes once the marker is there (the folder's own flush,
        // after this, makes it durable): a staging folder has one or the
        // other at every instant.
        fs::remove_file(self.fresh.join(STAGING))
    }

    /// Write files (paths relative to `sub` inside the folder). Each path
    /// must be plain relative components, so every write lands inside.
    pub fn write(&self, sub: &str, files: &[(String, Vec<u8>)]) -> io::Result<()> {
        for (name, bytes) in files {
            let rel = Path::new(sub).join(name);
            if !stays_inside(&rel) {
                return Err(io::Error::other(format!(
                    "refusing to write {}: not a plain path inside the output folder",
                    rel.display()
                )));
            }
            let path = self.fresh.join(&rel);
            debug_assert!(path.starts_with(&self.fresh));
            make_folders(&self.fresh, rel.parent())?;
            fault::write(&rel.display().to_string())?;
            // A file kept from the earlier build is a link to its file:
            // replaced, never truncated through the link.
            match fs::remove_file(&path) {
                Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(e),
                _ => {}
            }
            let mut f = File::create(&path)?;
            f.write_all(bytes)?;
            let rel = rel.display().to_string();
            self.syncer.push(f, rel.clone())?;
            self.written
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(rel);
        }
        Ok(())
    }

    /// Every file written so far (paths relative to the folder), in order.
    pub fn written(&self) -> Vec<String> {
        self.written
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    pub(crate) fn add_record(&self, line: String) {
        self.records
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(line);
    }

    /// Put the staging folder in the target's place, unless something
    /// appeared in the target while the build ran (`OutDir::appeared`):
    /// then nothing is committed, the target is left as it is, and the
    /// error names what appeared. Warnings go to `Host::warn`.
    pub fn commit(mut self) -> Result<(), Error> {
        // An interrupt from here on waits for the commit to end: the
        // staging folder may become --out at any moment.
        let _commit = interrupt::commit();
        let out = self.out;
        let target = &out.target;
        let fail = |e| {
            let earlier = out.had_anything();
            Error::io(Doing::Commit { earlier }, target, e)
        };
        self.seal().map_err(fail)?;
        fault::add(target, fault::Moment::BeforeCheck);
        let appeared = out.appeared(target).map_err(fail)?;
        if !appeared.is_empty() {
            return Err(out.changed(&appeared));
        }
        fault::add(target, fault::Moment::BeforeSwap);
        if fs::symlink_metadata(target).is_err() {
            fault::commit("rename into place");
            fs::rename(&self.fresh, target).map_err(fail)?;
            self.committed = true;
            self.interrupt = None;
        } else {
            let Some(old) = self.swap().map_err(fail)? else {
                // Committed in place: nothing was swapped out.
                return Ok(());
            };
            self.finish(&old)?;
        }
        if let Ok(parent) = File::open(&out.parent) {
            let _ = fault::sync(&parent);
        }
        Ok(())
    }

    /// Make the staging folder ready to be the target: every file and
    /// folder flushed, the marker written, the folder's mode and its own
    /// flush.
    fn seal(&mut self) -> io::Result<()> {
        sync_folders(&self.fresh, &self.syncer)?;
        self.syncer.finish()?;
        self.write_marker()?;
        if let Some(like) = &self.like {
            fs::set_permissions(&self.fresh, like.permissions())?;
        }
        fault::sync(&File::open(&self.fresh)?)
    }

    /// After the swap, the earlier build at `old`: removed but for what is
    /// someone's, or swapped back if entries came into it late.
    fn finish(&mut self, old: &Path) -> Result<(), Error> {
        let out = self.out;
        let target = &out.target;
        // From here on the new build is in place: an error says so.
        let fail = |e| {
            let old = old.to_path_buf();
            Error::io(Doing::Finish { old }, target, e)
        };
        // Entries that appeared after the check above (at the same
        // names, or through a handle held inside the folder) are now in
        // the swapped-out build: it is looked at again, and swapped
        // back if any are there.
        fault::add(target, fault::Moment::SwappedIn);
        let late = out.appeared(old).map_err(fail)?;
        if !late.is_empty() {
            return Err(self.undo(old, &late));
        }
        fault::add(old, fault::Moment::SwappedOut);
        fault::commit("remove the old build");
        // Only what was checked goes: whatever came in since stays, and
        // so does an edit made to the earlier build's files.
        let (seen, edited) = out.unedited(old);
        keep_aside(old, &seen, &edited, target);
        Ok(())
    }

    /// Entries (`late`) came into the earlier build as it was swapped out
    /// (at `old`): it goes back in the target's place, and the new build
    /// is removed but for what was written into it meanwhile. The error
    /// to return.
    fn undo(&mut self, old: &Path, late: &[String]) -> Error {
        let target = &self.out.target;
        if let Err(e) = self.swap_back(old) {
            // The earlier build kept whole, with what came into it.
            keep_aside(old, &BTreeSet::new(), &[], target);
            return Error::io(Doing::PutBack, target, e);
        }
        // What was written into the new build while it was the
        // folder is someone's: only the build's own files go.
        let written = self.written();
        let own = own_entries(written.iter().map(String::as_str));
        let shown = target.display();
        match clear(&self.fresh, &own, target) {
            Ok(Cleared::Gone) => {}
            Ok(Cleared::Kept {
                aside,
                theirs: true,
            }) => warn(&format!(
                "warning: files were written into {shown} while the new build was in its place; they are kept in {}",
                aside.display()
            )),
            Ok(Cleared::Kept { aside, .. }) => warn(&format!(
                "warning: the new build, not committed, could not be removed whole; what is left of it is in {}",
                aside.display()
            )),
            _ => warn(&format!(
                "warning: files may have been written into {shown} while the new build was in its place; they are in {}, and the next build into {shown} keeps them aside",
                self.fresh.display()
            )),
        }
        self.out.changed(late)
    }

    /// Swap the staging folder into the target's place (committed from
    /// then on); where the earlier build now is: None when the target
    /// cannot be moved at all and the build was committed into it instead
    /// (`in_place`).
    fn swap(&mut self) -> io::Result<Option<PathBuf>> {
        let target = &self.out.target;
        if exchange(&self.fresh, target)? {
            // The old build now sits at the staging name.
            self.committed = true;
            self.interrupt = None;
            self.was_out = true;
            return Ok(Some(self.fresh.clone()));
        }
        let old = self.out.parent.join(hidden(
            &self.out.name,
            &format!("old-{}", std::process::id()),
        ));
        remove_any(&old)?;
        fault::commit("set the old build aside");
        match fault::rename_folder(target, &old) {
            Err(e) if cross_device(&e) => {
                // Its files move out of the staging folder one by one.
                self.interrupt = None;
                self.in_place()?;
                self.committed = true;
                return Ok(None);
            }
            moved => moved?,
        }
        fault::commit("rename into place");
        if let Err(e) = fs::rename(&self.fresh, target) {
            let _ = fs::rename(&old, target);
            return Err(e);
        }
        self.committed = true;
        self.interrupt = None;
        self.was_out = true;
        Ok(Some(old))
    }

    /// Undo `swap`: the earlier build (at `old`) back in the target's place,
    /// the new one back at the staging name, which `drop` removes.
    fn swap_back(&mut self, old: &Path) -> io::Result<()> {
        let target = &self.out.target;
        if old == self.fresh {
            if !exchange(&self.fresh, target)? {
                return Err(io::Error::other("cannot swap the earlier build back"));
            }
        } else {
            fs::rename(target, &self.fresh)?;
            if let Err(e) = fs::rename(old, target) {
                // The new build back in place, as the error says.
                let _ = fs::rename(&self.fresh, target);
                return Err(e);
            }
        }
        self.committed = false;
        Ok(())
    }
}

/// Remove from a swapped-out build at `old` what the check saw (`seen`);
/// what is left (someone's, which came in as it was swapped out, or the
/// files `edited` since the earlier build wrote them) is moved to a
/// visible folder beside `target`, not left at a staging name, and the
/// user is told where.
fn keep_aside(old: &Path, seen: &BTreeSet<OsString>, edited: &[String], target: &Path) {
    let shown = target.display();
    match clear(old, seen, target) {
        Ok(Cleared::Gone) => {}
        Ok(Cleared::Kept { aside, .. }) if !edited.is_empty() => {
            let (n, list) = (edited.len(), edited.join(", "));
            let (it, is) = if n == 1 {
                ("it", "it is")
            } else {
                ("them", "they are")
            };
            warn(&format!(
                "warning: {} of the earlier build of {shown} changed since karigami wrote {it} ({list}); the rebuild replaced {it}, and {is} kept in {}",
                plural(n, "file"),
                aside.display()
            ));
        }
        Ok(Cleared::Kept {
            aside,
            theirs: true,
        }) => warn(&format!(
            "warning: files appeared in {shown} as the build replaced it; they are kept in {}",
            aside.display()
        )),
        Ok(Cleared::Kept { aside, .. }) => warn(&format!(
            "warning: the earlier build of {shown} could not be removed whole; what is left of it is in {}",
            aside.display()
        )),
        Ok(Cleared::Left) => warn(&format!(
            "warning: files appeared in {shown} as the build replaced it; they are in {}, and the next build into {shown} keeps them aside",
            old.display()
        )),
        Err(e) => warn(&format!(
            "warning: the earlier build of {shown} could not be removed from {}: {e}; the next build into {shown} tidies it",
            old.display()
        )),
    }
}

/// Make the folders of `rel` (a relative path, or none) inside `root`,
/// which must be there: a staging folder removed on an interrupt is not
/// made again by a writer still at work.
pub(crate) fn make_folders(root: &Path, rel: Option<&Path>) -> io::Result<()> {
    let mut dir = root.to_path_buf();
    for part in rel.into_iter().flat_map(Path::components) {
        dir.push(part);
        match fs::create_dir(&dir) {
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
            made => made?,
        }
    }
    Ok(())
}

/// Give the new folder `fresh` the owner and group of `like` (the folder
/// it replaces), and its set-group-ID bit, keeping write permission for
/// the build (`commit` sets the mode in full).
#[cfg(unix)]
fn same_owner(fresh: &Path, like: &fs::Metadata) -> io::Result<()> {
    use std::os::unix::fs::{MetadataExt, PermissionsExt};
    let mine = fs::symlink_metadata(fresh)?;
    if (mine.uid(), mine.gid()) != (like.uid(), like.gid()) {
        // Only root may give a folder away: a run of anyone else makes
        // the folder theirs, as any new file is.
        match std::os::unix::fs::chown(fresh, Some(like.uid()), Some(like.gid())) {
            Err(e) if e.kind() != io::ErrorKind::PermissionDenied => return Err(e),
            _ => {}
        }
    }
    let mode = like.permissions().mode() & 0o7777 | 0o700;
    fs::set_permissions(fresh, fs::Permissions::from_mode(mode))
}

#[cfg(not(unix))]
fn same_owner(_: &Path, _: &fs::Metadata) -> io::Result<()> {
    Ok(())
}

/// Flush every folder inside `root` to the disk, beside the files still
/// being flushed: a file's own fsync makes its bytes durable, not its name
/// in a folder made for it (`write`'s `create_dir_all`, or a link `keep`
/// made). `root` itself is flushed after the marker.
fn sync_folders(root: &Path, syncer: &Syncer) -> io::Result<()> {
    crate::walk(root, |path, folder| {
        if folder {
            let rel = path.strip_prefix(root).unwrap_or(path);
            syncer.push(File::open(path)?, format!("{}/", rel.display()))?;
        }
        Ok(())
    })
}

/// Swap two paths atomically; false where the system cannot.
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> io::Result<bool> {
    use rustix::fs::{CWD, RenameFlags, renameat_with};
    use rustix::io::Errno;
    if fault::no_exchange() {
        return Ok(false);
    }
    fault::commit("swap the folders");
    if fault::cross_device() {
        return Ok(false);
    }
    // EXDEV: an overlay file system's folder from a lower layer cannot be
    // renamed (a build folder made in an earlier container layer).
    match renameat_with(CWD, a, CWD, b, RenameFlags::EXCHANGE) {
        Ok(()) => Ok(true),
        Err(e) if [Errno::INVAL, Errno::NOSYS, Errno::XDEV].contains(&e) => Ok(false),
        Err(e) => Err(e.into()),
    }
}

/// Whether a rename failed because the path cannot be moved where it was
/// to go (EXDEV): an overlay file system's folder from a lower layer.
pub(crate) fn cross_device(e: &io::Error) -> bool {
    e.raw_os_error() == Some(EXDEV)
}

const EXDEV: i32 = 18;

#[cfg(not(target_os = "linux"))]
fn exchange(_: &Path, _: &Path) -> io::Result<bool> {
    Ok(false)
}

impl Drop for Staged<'_> {
    fn drop(&mut self) {
        self.syncer.abandon();
        if !self.committed && !self.was_out {
            let _ = remove_any(&self.fresh);
        }
    }
}
