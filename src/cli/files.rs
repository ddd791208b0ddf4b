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

use super::fault;
use karigami::words::plural;
use std::ffi::OsStr;
use std::fs::{self, File, OpenOptions};
use std::io::{self, Read, Write};
use std::path::{Component, Path, PathBuf};

/// The marker file of a build folder, and its first line.
pub(super) const MARKER: &str = ".karigami-build";
const MARKER_HEAD: &str = "karigami build folder";
/// Bumped when the layout of a build folder changes incompatibly.
const FORMAT: u32 = 1;

/// Recipes larger than this are refused before reading them whole.
pub(super) const MAX_RECIPE_BYTES: u64 = 1 << 20;

/// Longest name (in bytes) of a folder the tool derives from input.
pub(super) const MAX_NAME_BYTES: usize = 100;

/// Read a recipe: a regular file of at most `MAX_RECIPE_BYTES`, in UTF-8.
pub(super) fn read(path: &Path) -> io::Result<String> {
    let meta = fs::metadata(path)?;
    if meta.is_dir() {
        return Err(io::Error::other("it is a folder, not a recipe file"));
    }
    let mut bytes = Vec::new();
    File::open(path)?
        .take(MAX_RECIPE_BYTES + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_RECIPE_BYTES {
        return Err(io::Error::other(format!(
            "the file is larger than the limit of {} MiB for a recipe",
            MAX_RECIPE_BYTES >> 20
        )));
    }
    // The first NUL (binary data) or invalid UTF-8 byte, by line and column.
    let nul = bytes.iter().position(|&b| b == 0);
    let bad = match std::str::from_utf8(&bytes) {
        Ok(_) => nul,
        Err(e) => Some(nul.map_or(e.valid_up_to(), |n| n.min(e.valid_up_to()))),
    };
    let Some(at) = bad else {
        return Ok(String::from_utf8(bytes).expect("checked above"));
    };
    let before = &bytes[..at];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    // Characters before it on its line (the prefix is valid UTF-8).
    let col = String::from_utf8_lossy(&before[line_start..])
        .chars()
        .count()
        + 1;
    let what = if nul.is_some() {
        "binary data, not a TOML recipe"
    } else {
        "not UTF-8 text"
    };
    Err(io::Error::other(format!(
        "{what}: byte 0x{:02X} at line {line}, column {col}; save the recipe as UTF-8 text",
        bytes[at]
    )))
}

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
        // FNV-1a: stable across runs and platforms.
        let hash = name.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
        });
        format!("{}~{hash:016x}", &name[..end])
    };
    format!(".{short}.karigami-{suffix}")
}

/// Write to a temporary file beside the target, then rename it over the
/// target: the target is either as it was or complete.
pub(super) fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::other("no file name"))?;
    let tmp = path.with_file_name(hidden(name, &format!("tmp-{}", std::process::id())));
    remove_stale_temporaries(path, &hidden(name, "tmp-"));
    let result = (|| {
        fault::write(&path.display().to_string())?;
        let mut f = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        f.write_all(bytes)?;
        fault::sync(&f)?;
        fault::commit("rename over the target");
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Temporary files beside `path` (`prefix` + PID) of runs that were
/// killed: where the system lists live processes in /proc, those of dead
/// ones are removed.
fn remove_stale_temporaries(path: &Path, prefix: &str) {
    let proc = Path::new("/proc/self");
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    if !proc.exists() {
        return;
    }
    for entry in entries.flatten() {
        let file = entry.file_name().to_string_lossy().into_owned();
        let pid = file.strip_prefix(prefix).unwrap_or_default();
        if !pid.is_empty()
            && pid.bytes().all(|b| b.is_ascii_digit())
            && !Path::new("/proc").join(pid).exists()
        {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// `raw` (a recipe's file name, a folder's name) as a plain, portable,
/// single path component: separators, control and reserved characters
/// become `_`, leading dots (hidden, `.`, `..`) and trailing dots and
/// spaces go, names reserved on Windows get a `_`, and the length is capped.
pub(super) fn safe_component(raw: &str) -> String {
    let mapped: String = raw
        .chars()
        .map(|c| {
            if c.is_control() || matches!(c, '/' | '\\' | ':' | '*' | '?' | '"' | '<' | '>' | '|') {
                '_'
            } else {
                c
            }
        })
        .collect();
    let mut s = mapped.trim_start_matches(['.', ' ']).to_string();
    if s.len() > MAX_NAME_BYTES {
        let mut end = MAX_NAME_BYTES;
        while !s.is_char_boundary(end) {
            end -= 1;
        }
        s.truncate(end);
    }
    let mut s = s.trim_end_matches(['.', ' ']).to_string();
    if s.is_empty() {
        s = "recipe".to_string();
    }
    let base = s.split('.').next().unwrap_or_default().to_ascii_uppercase();
    let reserved = matches!(base.as_str(), "CON" | "PRN" | "AUX" | "NUL")
        || (base.len() == 4
            && (base.starts_with("COM") || base.starts_with("LPT"))
            && base.as_bytes()[3].is_ascii_digit());
    if reserved {
        s.push('_');
    }
    s
}

/// Whether `rel` is a relative path of plain components that stays inside
/// the folder it is joined to.
fn stays_inside(rel: &Path) -> bool {
    rel.components().all(|c| match c {
        Component::Normal(n) => {
            let n = n.to_string_lossy();
            !n.is_empty() && !n.chars().any(char::is_control)
        }
        _ => false,
    })
}

/// What an existing `--out` holds that a build replaces.
pub(super) enum Previous {
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
pub(super) struct OutDir {
    target: PathBuf,
    parent: PathBuf,
    name: std::ffi::OsString,
    pub previous: Previous,
    /// What the lock holder repaired or cleaned, for the user.
    pub notes: Vec<String>,
    lock: (PathBuf, File),
}

/// Lock the lock file beside `out`, failing at once if another run holds
/// it. The holder removes the file when done, so a run that opened the
/// file just before it was removed checks that the path still names the
/// file it locked, and tries again if not.
fn take_lock(path: &Path, out: &Path) -> Result<(PathBuf, File), String> {
    for _ in 0..100 {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        match try_lock(&file) {
            Ok(true) => {}
            Ok(false) => {
                return Err(format!(
                    "another karigami run is writing {} right now (it holds {}); wait for it to finish or choose another --out",
                    out.display(),
                    path.display()
                ));
            }
            Err(e) => {
                return Err(format!("cannot lock {}: {e}", path.display()));
            }
        }
        if same_file(&file, path) {
            return Ok((path.to_path_buf(), file));
        }
    }
    Err(format!("cannot lock {}: it keeps changing", path.display()))
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
    match (file.metadata(), fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_: &File, _: &Path) -> bool {
    true
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
    pub(super) fn open(out: &Path, inputs: &[PathBuf], force: bool) -> Result<Self, String> {
        let shown = out.display();
        let Some(name) = out.file_name().map(OsStr::to_os_string) else {
            return Err(format!(
                "--out {shown} is not a folder name; give the folder to build into, such as --out my-build"
            ));
        };
        let parent = match out.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        // The first existing ancestor must be a folder.
        let existing = parent
            .ancestors()
            .find(|a| !a.as_os_str().is_empty() && fs::symlink_metadata(a).is_ok());
        if let Some(existing) = existing.filter(|e| !e.is_dir()) {
            return Err(format!(
                "cannot create {shown}: {} is a file, not a folder",
                existing.display()
            ));
        }
        // A refusal writes nothing: check before creating the lock file
        // (and again under the lock, which is what counts).
        classify(out, inputs, force)?;
        fs::create_dir_all(&parent)
            .map_err(|e| format!("cannot create {}: {e}", parent.display()))?;
        let lock_path = parent.join(hidden(&name, "lock"));
        let lock = take_lock(&lock_path, out)?;
        let mut dir = Self {
            target: out.to_path_buf(),
            parent,
            name,
            previous: Previous::Nothing,
            notes: Vec::new(),
            lock,
        };
        dir.recover()
            .map_err(|e| format!("cannot tidy up beside {shown}: {e}"))?;
        dir.previous = classify(out, inputs, force)?;
        Ok(dir)
    }

    /// Staging folders of earlier runs of this folder (we hold the lock, so
    /// their runs are over): a set-aside old build comes back if the folder
    /// is missing (a run died between the two renames of a commit); every
    /// other one is removed.
    fn recover(&mut self) -> io::Result<()> {
        let new_prefix = hidden(&self.name, "new-");
        let old_prefix = hidden(&self.name, "old-");
        let mut stale: Vec<PathBuf> = Vec::new();
        let mut old: Vec<PathBuf> = Vec::new();
        for entry in fs::read_dir(&self.parent)? {
            let entry = entry?;
            let file = entry.file_name().to_string_lossy().into_owned();
            for (prefix, list) in [(&new_prefix, &mut stale), (&old_prefix, &mut old)] {
                let pid = file.strip_prefix(prefix.as_str()).unwrap_or_default();
                if !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()) {
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
        for path in &stale {
            remove_any(path)?;
        }
        if !stale.is_empty() {
            self.notes.push(format!(
                "removed {} staging folder{} left beside {} by interrupted runs",
                stale.len(),
                if stale.len() == 1 { "" } else { "s" },
                self.target.display()
            ));
        }
        Ok(())
    }
}

/// What `target` holds, or why a build must not replace it.
fn classify(target: &Path, inputs: &[PathBuf], force: bool) -> Result<Previous, String> {
    let shown = target.display();
    let meta = match fs::symlink_metadata(target) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Previous::Nothing),
        Err(e) => return Err(format!("cannot read {shown}: {e}")),
        Ok(m) => m,
    };
    if meta.file_type().is_symlink() {
        let to = fs::read_link(target)
            .map(|t| t.display().to_string())
            .unwrap_or_default();
        let dangling = if target.exists() {
            ""
        } else {
            ", which does not exist"
        };
        return Err(format!(
            "--out {shown} is a symbolic link (to {to}{dangling}); give the real folder as --out"
        ));
    }
    if !meta.is_dir() {
        return Err(format!(
            "--out {shown} is a file, not a folder; choose another --out (--force replaces only folders)"
        ));
    }
    let real = fs::canonicalize(target).map_err(|e| format!("cannot read {shown}: {e}"))?;
    for input in inputs {
        if fs::canonicalize(input).is_ok_and(|i| i.starts_with(&real)) {
            return Err(format!(
                "--out {shown} holds {}, an input of this run, and building would replace the folder with it; choose another --out",
                input.display()
            ));
        }
    }
    if std::env::current_dir()
        .and_then(fs::canonicalize)
        .is_ok_and(|cwd| cwd.starts_with(&real))
    {
        return Err(format!(
            "--out {shown} is the current folder or holds it; run karigami from outside it or choose another --out"
        ));
    }
    let files = list_files(target).map_err(|e| format!("cannot read {shown}: {e}"))?;
    if let Some(ours) = fs::read_to_string(target.join(MARKER))
        .ok()
        .filter(|t| t.starts_with(MARKER_HEAD))
    {
        // Files someone added to a build folder are not the tool's to delete
        // without asking.
        let listed: std::collections::BTreeSet<&str> = ours
            .split_once("\nfiles:\n")
            .map_or("", |(_, l)| l)
            .lines()
            .collect();
        let added: Vec<String> = files
            .iter()
            .filter(|f| f.as_str() != MARKER && !listed.contains(f.as_str()))
            .cloned()
            .collect();
        if added.is_empty() {
            return Ok(Previous::Build);
        }
        if force {
            return Ok(Previous::Added(added));
        }
        return Err(format!(
            "{shown} is a karigami build folder but holds {} the build did not write: {}; move {} out, or pass --force to replace the folder and delete {}",
            plural(added.len(), "file"),
            shortlist(&added),
            if added.len() == 1 { "it" } else { "them" },
            if added.len() == 1 { "it" } else { "them" },
        ));
    }
    let empty = fs::read_dir(target)
        .map_err(|e| format!("cannot read {shown}: {e}"))?
        .next()
        .is_none();
    if empty {
        return Ok(Previous::Nothing);
    }
    if force {
        return Ok(Previous::Foreign(files));
    }
    let older = ["lattice.json", "batch.json"]
        .iter()
        .any(|m| target.join(m).is_file());
    let what = if older {
        format!(
            "{shown} has no {MARKER} marker: it may be a build of an older karigami, or a folder of yours"
        )
    } else {
        format!("{shown} exists and is not a karigami build folder (it has no {MARKER} marker)")
    };
    Err(format!(
        "{what}; choose another --out, or pass --force to replace it (its {} would be deleted)",
        plural(files.len(), "file")
    ))
}

impl OutDir {
    /// A warning for `--force` replacing files that are not the tool's.
    pub(super) fn force_warning(&self) -> Option<String> {
        let (what, files) = match &self.previous {
            Previous::Foreign(files) => ("is not a karigami build folder", files),
            Previous::Added(files) => ("holds files the build did not write", files),
            _ => return None,
        };
        Some(format!(
            "warning: --force: {} {what}; replacing it deletes {}: {}",
            self.target.display(),
            plural(files.len(), "file"),
            shortlist(files)
        ))
    }

    pub(super) fn path(&self) -> &Path {
        &self.target
    }

    /// What the folder holds if a build does not commit.
    pub(super) fn kept(&self) -> String {
        match self.previous {
            Previous::Nothing => format!("nothing was written to {}", self.target.display()),
            _ => format!("{} was left as it was", self.target.display()),
        }
    }
}

/// The first few of `files`, and how many more.
fn shortlist(files: &[String]) -> String {
    const SHOWN: usize = 10;
    let mut list: Vec<&str> = files.iter().take(SHOWN).map(String::as_str).collect();
    let more = format!("and {} more", files.len().saturating_sub(SHOWN));
    if files.len() > SHOWN {
        list.push(&more);
    }
    list.join(", ")
}

/// Every file under `dir` (relative, sorted), without following links.
fn list_files(dir: &Path) -> io::Result<Vec<String>> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in fs::read_dir(&d)? {
            let entry = entry?;
            let path = entry.path();
            if entry.file_type()?.is_dir() {
                stack.push(path);
            } else {
                let rel = path.strip_prefix(dir).unwrap_or(&path);
                out.push(rel.display().to_string());
            }
        }
    }
    out.sort();
    Ok(out)
}

fn remove_any(path: &Path) -> io::Result<()> {
    match fs::symlink_metadata(path) {
        Ok(m) if m.is_dir() => fs::remove_dir_all(path),
        Ok(_) => fs::remove_file(path),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(e),
    }
}

/// A build folder being written: files go into a staging folder beside the
/// target, which replaces the target whole on `commit`. Dropped without a
/// commit, the staging folder is removed and the target untouched; killed,
/// the next run removes it.
pub(super) struct Staged<'a> {
    out: &'a OutDir,
    fresh: PathBuf,
    kind: String,
    /// Every file written (relative paths), for the marker.
    written: std::sync::Mutex<Vec<String>>,
    committed: bool,
}

impl<'a> Staged<'a> {
    /// `kind` ("single" or "batch") goes into the marker.
    pub(super) fn new(out: &'a OutDir, kind: &str) -> io::Result<Self> {
        let fresh = out
            .parent
            .join(hidden(&out.name, &format!("new-{}", std::process::id())));
        remove_any(&fresh)?;
        fs::create_dir(&fresh)?;
        Ok(Self {
            out,
            fresh,
            kind: kind.to_string(),
            written: std::sync::Mutex::new(Vec::new()),
            committed: false,
        })
    }

    /// The marker, written last: what the folder is and every file the
    /// build wrote, so that a later build can tell them from files someone
    /// added.
    fn write_marker(&self) -> io::Result<()> {
        let mut files = self
            .written
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone();
        files.sort();
        let text = format!(
            "{MARKER_HEAD}\nformat {FORMAT}\nkind {}\nwritten by karigami {}; a build replaces this folder whole\nfiles:\n{}",
            self.kind,
            env!("CARGO_PKG_VERSION"),
            files.iter().map(|f| format!("{f}\n")).collect::<String>()
        );
        fault::write(MARKER)?;
        let mut f = File::create(self.fresh.join(MARKER))?;
        f.write_all(text.as_bytes())?;
        fault::sync(&f)
    }

    /// Write files (paths relative to `sub` inside the folder). Each path
    /// must be plain relative components, so every write lands inside.
    pub(super) fn write(&self, sub: &str, files: &[(String, Vec<u8>)]) -> io::Result<()> {
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
            if let Some(dir) = path.parent() {
                fs::create_dir_all(dir)?;
            }
            fault::write(&rel.display().to_string())?;
            let mut f = File::create(&path)?;
            f.write_all(bytes)?;
            fault::sync(&f)?;
            self.written
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .push(rel.display().to_string());
        }
        Ok(())
    }

    /// Put the staging folder in the target's place.
    pub(super) fn commit(mut self) -> io::Result<()> {
        self.write_marker()?;
        fault::sync(&File::open(&self.fresh)?)?;
        let target = &self.out.target;
        if fs::symlink_metadata(target).is_err() {
            fault::commit("rename into place");
            fs::rename(&self.fresh, target)?;
            self.committed = true;
        } else if exchange(&self.fresh, target)? {
            // The old build now sits at the staging name.
            self.committed = true;
            fault::commit("remove the old build");
            remove_any(&self.fresh)?;
        } else {
            let old = self.out.parent.join(hidden(
                &self.out.name,
                &format!("old-{}", std::process::id()),
            ));
            remove_any(&old)?;
            fault::commit("set the old build aside");
            fs::rename(target, &old)?;
            fault::commit("rename into place");
            if let Err(e) = fs::rename(&self.fresh, target) {
                let _ = fs::rename(&old, target);
                return Err(e);
            }
            self.committed = true;
            fault::commit("remove the old build");
            remove_any(&old)?;
        }
        if let Ok(parent) = File::open(&self.out.parent) {
            let _ = fault::sync(&parent);
        }
        Ok(())
    }
}

/// Swap two paths atomically; false where the system cannot.
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> io::Result<bool> {
    use rustix::fs::{CWD, RenameFlags, renameat_with};
    if fault::no_exchange() {
        return Ok(false);
    }
    fault::commit("swap the folders");
    match renameat_with(CWD, a, CWD, b, RenameFlags::EXCHANGE) {
        Ok(()) => Ok(true),
        Err(e) if e == rustix::io::Errno::INVAL || e == rustix::io::Errno::NOSYS => Ok(false),
        Err(e) => Err(e.into()),
    }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_: &Path, _: &Path) -> io::Result<bool> {
    Ok(false)
}

impl Drop for Staged<'_> {
    fn drop(&mut self) {
        if !self.committed {
            let _ = remove_any(&self.fresh);
        }
    }
}

/// The recipes named on the command line: files as given, folders as the
/// `.toml` files directly inside them, sorted by name.
pub(super) fn recipes(args: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut out = Vec::new();
    for arg in args {
        if arg.is_dir() {
            let mut found: Vec<PathBuf> = fs::read_dir(arg)
                .map_err(|e| format!("cannot read folder {}: {e}", arg.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "toml"))
                .collect();
            if found.is_empty() {
                return Err(format!("folder {} holds no .toml recipes", arg.display()));
            }
            found.sort();
            out.extend(found);
        } else {
            out.push(arg.clone());
        }
    }
    Ok(out)
}
