//! The hooks read `KARIGAMI_FAULT` once a run (see `fault`).

use std::io;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicUsize, Ordering};

#[derive(Default)]
struct Plan {
    abort_at: Option<usize>,
    enospc_from: Option<usize>,
    no_exchange: bool,
    cross_device: bool,
    no_sync: bool,
    edit: bool,
    sync_fail_at: Option<usize>,
    first_note_ms: Option<u64>,
    /// `add`, `addlate`, `addgone` and `addnew` (`Moment`).
    add: [Option<String>; 4],
}

fn plan() -> &'static Plan {
    static PLAN: OnceLock<Plan> = OnceLock::new();
    PLAN.get_or_init(read_plan)
}

fn read_plan() -> Plan {
    let mut plan = Plan::default();
    let Ok(spec) = std::env::var("KARIGAMI_FAULT") else {
        return plan;
    };
    for item in spec.split(',') {
        match item.split_once('@') {
            Some(("abort", k)) => plan.abort_at = k.parse().ok(),
            Some(("enospc", k)) => plan.enospc_from = k.parse().ok(),
            Some(("syncfail", k)) => plan.sync_fail_at = k.parse().ok(),
            Some(("firstnote", ms)) => plan.first_note_ms = ms.parse().ok(),
            Some(("add", rel)) => plan.add[0] = Some(rel.to_string()),
            Some(("addlate", rel)) => plan.add[1] = Some(rel.to_string()),
            Some(("addgone", rel)) => plan.add[2] = Some(rel.to_string()),
            Some(("addnew", rel)) => plan.add[3] = Some(rel.to_string()),
            _ if item == "noexchange" => plan.no_exchange = true,
            _ if item == "exdev" => plan.cross_device = true,
            _ if item == "nosync" => plan.no_sync = true,
            _ if item == "edit" => plan.edit = true,
            _ => {}
        }
    }
    plan
}

/// A line of the hooks' own on stderr, for the safety tests' logs.
fn say(line: std::fmt::Arguments) {
    use std::io::Write;
    let _ = writeln!(io::stderr(), "{line}");
}

static STEP: AtomicUsize = AtomicUsize::new(0);
static SYNCS: AtomicUsize = AtomicUsize::new(0);

fn next(what: &str) -> usize {
    let k = STEP.fetch_add(1, Ordering::SeqCst) + 1;
    if plan().abort_at == Some(k) {
        say(format_args!("fault: abort at step {k} ({what})"));
        std::process::abort();
    }
    k
}

/// A file is about to be written.
pub(crate) fn write(what: &str) -> io::Result<()> {
    let k = next(what);
    match plan().enospc_from {
        Some(from) if k >= from => Err(io::Error::from_raw_os_error(28)),
        _ => Ok(()),
    }
}

/// A rename or removal of the commit is about to happen.
pub(crate) fn commit(what: &str) {
    next(what);
}

/// When a user adds an entry to a folder being committed.
#[derive(Clone, Copy)]
pub(crate) enum Moment {
    /// Before the commit checks what appeared (`add@REL`).
    BeforeCheck,
    /// After that check, before the swap (`addlate@REL`).
    BeforeSwap,
    /// Into the build swapped out, once checked again (`addgone@REL`).
    SwappedOut,
    /// Into the new build just swapped in, before the second check
    /// (`addnew@REL`).
    SwappedIn,
}

/// A user adds an entry to the folder `dir` at the moment `at`.
pub(crate) fn add(dir: &std::path::Path, at: Moment) {
    let Some(rel) = &plan().add[at as usize] else {
        return;
    };
    let path = dir.join(rel);
    let made = if let Some((name, to)) = rel.split_once("->") {
        link(to, &dir.join(name))
    } else if rel.ends_with('/') {
        std::fs::create_dir_all(&path)
    } else {
        path.parent()
            .map_or(Ok(()), std::fs::create_dir_all)
            .and_then(|()| std::fs::write(&path, "added while the build ran\n"))
    };
    if let Err(e) = made {
        say(format_args!("fault: cannot add {}: {e}", path.display()));
    }
}

#[cfg(unix)]
fn link(to: &str, at: &std::path::Path) -> io::Result<()> {
    std::os::unix::fs::symlink(to, at)
}

#[cfg(not(unix))]
fn link(_: &str, _: &std::path::Path) -> io::Result<()> {
    Err(io::Error::other("no symbolic links here"))
}

/// A user edits the file at `path`, or makes it if it is not there (`edit`).
pub fn edit(path: &std::path::Path) {
    if !plan().edit {
        return;
    }
    use std::io::Write;
    let edited = std::fs::OpenOptions::new()
        .append(true)
        .create(true)
        .open(path)
        .and_then(|mut f| f.write_all(b"# edited while tuning ran\n"));
    if let Err(e) = edited {
        say(format_args!("fault: cannot edit {}: {e}", path.display()));
    }
}

/// When a phase's first progress line is due (`firstnote@MS`), if set.
pub fn first_note() -> Option<std::time::Duration> {
    plan().first_note_ms.map(std::time::Duration::from_millis)
}

pub(crate) fn no_exchange() -> bool {
    plan().no_exchange
}

/// Folders cannot be moved (`exdev`).
pub(crate) fn cross_device() -> bool {
    plan().cross_device
}

/// Rename the folder `from` to `to`, or fail with EXDEV (`exdev`).
pub(crate) fn rename_folder(from: &std::path::Path, to: &std::path::Path) -> io::Result<()> {
    if plan().cross_device {
        return Err(io::Error::from_raw_os_error(18));
    }
    std::fs::rename(from, to)
}

/// Flush a file or folder to the disk (unless `nosync`).
pub(crate) fn sync(file: &std::fs::File) -> io::Result<()> {
    if let Some(k) = plan().sync_fail_at
        && SYNCS.fetch_add(1, Ordering::SeqCst) + 1 == k
    {
        return Err(io::Error::from_raw_os_error(5));
    }
    if plan().no_sync {
        return Ok(());
    }
    file.sync_all()
}
