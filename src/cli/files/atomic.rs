//! Writing one file (a recipe, a report) so that it is either as it was
//! or complete.

use super::super::fault;
use super::{dir_of, hidden};
use crate::cli::error::Error;
use karigami::ErrorKind;
use karigami::util::plural;
use std::fs::{self, OpenOptions};
use std::io::{self, Write};
use std::path::Path;

/// Write to a temporary file beside the target, then rename it over the
/// target: the target is either as it was or complete.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_whole(path, bytes, true, None)
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
    let _interrupt = crate::cli::interrupt::register(&tmp);
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

/// The file `tune --out` writes the tuned recipe to: checked before the
/// work and again just before the write, which is atomic (`write_atomic`).
/// A link is always refused (the rename would replace the link, not the
/// file it leads to), and so is a folder; an existing file other than the
/// recipe only with `--force`; the recipe itself is written back, unless
/// it was edited meanwhile.
pub(crate) struct OutFile<'a> {
    path: &'a Path,
    force: bool,
    /// The recipe's text as it was read, if `path` named the recipe being
    /// tuned (the same file).
    recipe: Option<&'a str>,
}

impl<'a> OutFile<'a> {
    /// Check `path` before any work (`recipe`: the file being tuned, and
    /// its text as read).
    pub(crate) fn check(
        path: &'a Path,
        (recipe, text): (&Path, &'a str),
        force: bool,
    ) -> Result<Self, Error> {
        let mut out = Self {
            path,
            force,
            recipe: None,
        };
        out.recipe = fs::symlink_metadata(path)
            .is_ok_and(|m| same_file(&m, path, recipe))
            .then_some(text);
        out.refusal()?;
        Ok(out)
    }

    pub(crate) fn path(&self) -> &Path {
        self.path
    }

    /// Why the file must not be written now, if it must not.
    fn refusal(&self) -> Result<(), Error> {
        let shown = self.path.display();
        // `link/` names what the link leads to: the link itself is checked.
        let bare: std::path::PathBuf = self.path.components().collect();
        let meta = match fs::symlink_metadata(&bare) {
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
            Err(e) => return Err(Error::io(format!("cannot read {shown}: {e}"))),
            Ok(m) => m,
        };
        if meta.file_type().is_symlink() {
            let to = fs::read_link(&bare)
                .map(|t| t.display().to_string())
                .unwrap_or_default();
            return Err(Error::new(
                ErrorKind::OutIsALink,
                format!(
                    "--out {shown} is a symbolic link (to {to}); writing would replace the link, so give the file itself as --out"
                ),
            ));
        }
        if meta.is_dir() {
            return Err(Error::usage(format!(
                "--out {shown} is a folder; give the name of the file to write, such as --out tuned.toml"
            )));
        }
        if let Some(refused) = self.other_links(&meta) {
            return Err(refused);
        }
        if self.recipe.is_none() && !self.force {
            return Err(Error::usage(format!(
                "{shown} exists; choose another --out, or pass --force to overwrite it (`tune X.toml --out X.toml` writes the recipe back)"
            )));
        }
        Ok(())
    }

    /// Write `bytes` to the file, after checking it again: what appeared
    /// there while tuning is not overwritten unasked either, nor an edit
    /// made to the recipe meanwhile (`edited`).
    pub(crate) fn write(&self, bytes: &[u8]) -> Result<(), Error> {
        self.refusal()?;
        fault::edit(self.path);
        if let Some(text) = self.recipe
            && fs::read(self.path).ok().as_deref() != Some(text.as_bytes())
        {
            return Err(self.edited(bytes));
        }
        let like = fs::symlink_metadata(self.path).ok();
        write_whole(self.path, bytes, true, like.as_ref()).map_err(|e| {
            Error::io(format!(
                "cannot write {}: {e}; it was left as it was",
                self.path.display()
            ))
        })
    }
}

impl OutFile<'_> {
    /// The refusal to replace a file with other hard links (`meta` its
    /// metadata): the new text would reach this name only, and the other
    /// names would keep the old one.
    #[cfg(unix)]
    fn other_links(&self, meta: &fs::Metadata) -> Option<Error> {
        use std::os::unix::fs::MetadataExt;
        let others = meta.nlink().checked_sub(1).filter(|n| *n > 0)?;
        Some(Error::usage(format!(
            "{} has {} (it is the same file under {}); writing would give the tuned text to this name only: give another --out, or tune a copy",
            self.path.display(),
            plural(others as usize, "other hard link"),
            if others == 1 {
                "another name"
            } else {
                "other names"
            }
        )))
    }

    #[cfg(not(unix))]
    fn other_links(&self, _: &fs::Metadata) -> Option<Error> {
        None
    }

    /// The recipe written back was edited (or removed) while tuning ran:
    /// the edit is the user's and stays; the tuned text goes beside it,
    /// as `X.toml.tuned` if that name is free, else to stdout.
    fn edited(&self, bytes: &[u8]) -> Error {
        let shown = self.path.display();
        let mut beside = self.path.as_os_str().to_owned();
        beside.push(".tuned");
        let beside = Path::new(&beside);
        let like = fs::symlink_metadata(self.path).ok();
        let put = if write_whole(beside, bytes, false, like.as_ref()).is_ok() {
            format!("the tuned recipe is in {}", beside.display())
        } else {
            let mut stdout = io::stdout().lock();
            let printed = stdout.write_all(bytes).and_then(|()| stdout.flush());
            crate::cli::console::noted(printed, crate::cli::console::Stream::Out);
            "the tuned recipe was printed on stdout".to_string()
        };
        Error::io(format!(
            "{shown} changed while tuning ran, so it was not overwritten (the change is kept); {put}"
        ))
    }
}

/// Whether `meta` (of `path`, not followed) is the file at `other`.
#[cfg(unix)]
fn same_file(meta: &fs::Metadata, _: &Path, other: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    fs::metadata(other).is_ok_and(|o| o.dev() == meta.dev() && o.ino() == meta.ino())
}

#[cfg(not(unix))]
fn same_file(_: &fs::Metadata, path: &Path, other: &Path) -> bool {
    matches!(
        (fs::canonicalize(path), fs::canonicalize(other)),
        (Ok(a), Ok(b)) if a == b
    )
}
