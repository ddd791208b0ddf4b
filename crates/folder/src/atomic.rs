//! Writing one file (a recipe, a report) so that it is either as it was
//! or complete.

use crate::{dir_of, fault, hidden};
use std::fs::{self, OpenOptions};
use std::io::{self, Write};
use std::path::Path;

/// Write to a temporary file beside the target, then rename it over the
/// target: the target is either as it was or complete.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_whole(path, bytes, true, None)
}

/// `write_atomic`, the file written getting the mode and owner of `like`
/// (the metadata of the file it replaces).
pub fn replace_like(path: &Path, bytes: &[u8], like: Option<&fs::Metadata>) -> io::Result<()> {
    write_whole(path, bytes, true, like)
}

/// Write a file that must not exist yet, complete or not at all (as
/// `write_whole`), with the mode and owner of `like`.
pub fn create_like(path: &Path, bytes: &[u8], like: Option<&fs::Metadata>) -> io::Result<()> {
    write_whole(path, bytes, false, like)
}

/// `write_atomic`, or with `replace` false a file that must not exist yet:
/// the temporary file is linked to its name, which fails if it is taken
/// (however recently), then unlinked. With `like`, the file written gets
/// the mode and owner of the file it replaces (`like`'s metadata).
fn write_whole(
    path: &Path,
    bytes: &[u8],
    replace: bool,
    like: Option<&fs::Metadata>,
) -> io::Result<()> {
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::other("no file name"))?;
    let tmp = path.with_file_name(hidden(name, &format!("tmp-{}", std::process::id())));
    remove_stale_temporaries(path, &hidden(name, "tmp-"));
    let _interrupt = crate::interrupt::register(&tmp);
    let result = (|| {
        fault::write(&path.display().to_string())?;
        let mut f = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        if let Some(like) = like {
            same_identity(&f, like)?;
        }
        f.write_all(bytes)?;
        fault::sync(&f)?;
        fault::commit("rename over the target");
        if replace {
            fs::rename(&tmp, path)?;
        } else {
            fs::hard_link(&tmp, path)?;
            // Written either way: a temporary left is tidied by a later run.
            let _ = fs::remove_file(&tmp);
        }
        // The new name made durable too (a failure here loses nothing).
        if let Ok(folder) = fs::File::open(dir_of(path)) {
            let _ = fault::sync(&folder);
        }
        Ok(())
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Give the file `f` the owner and mode of `like` (the file it is to
/// replace): a 0600 recipe tuned in place stays 0600, and stays its
/// owner's. The owner first: changing it clears a set-user-ID bit.
#[cfg(unix)]
fn same_identity(f: &fs::File, like: &fs::Metadata) -> io::Result<()> {
    use rustix::fs::{Gid, Uid, fchown};
    use std::os::unix::fs::MetadataExt;
    let mine = f.metadata()?;
    if (mine.uid(), mine.gid()) != (like.uid(), like.gid()) {
        let (uid, gid) = (Uid::from_raw(like.uid()), Gid::from_raw(like.gid()));
        // Only root may give a file away: anyone else's run writes a file
        // of theirs, as any edit saved by rename does.
        match fchown(f, Some(uid), Some(gid)) {
            Err(e) if e != rustix::io::Errno::PERM => return Err(e.into()),
            _ => {}
        }
    }
    f.set_permissions(like.permissions())
}

#[cfg(not(unix))]
fn same_identity(f: &fs::File, like: &fs::Metadata) -> io::Result<()> {
    f.set_permissions(like.permissions())
}

/// Temporary files beside `path` (`prefix` + PID) of runs that were
/// killed: where the system lists live processes in /proc, those of dead
/// ones are removed.
fn remove_stale_temporaries(path: &Path, prefix: &str) {
    let proc = Path::new("/proc/self");
    let Ok(entries) = fs::read_dir(dir_of(path)) else {
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
