//! The file `tune --out` and `design --out` write a recipe to: checked
//! before the work and again just before it is written, whole or not at
//! all (`karigami_folder::replace_like`).

use crate::cli::error::Error;
use karigami::ErrorKind;
use karigami::util::plural;
use karigami_folder::{create_like, fault, replace_like};
use std::fs;
use std::io::{self, Write};
use std::path::Path;

/// The file `tune --out` or `design --out` writes a recipe to: checked
/// before the work and again just before the write, which is atomic
/// (`replace_like`). A link is always refused (the rename would replace
/// the link, not the file it leads to), and so is a folder; an existing
/// file other than the recipe only with `--force`; the recipe being tuned
/// is written back, unless it was edited meanwhile; the target being
/// designed for, never. What the work made is never lost: refused at the
/// write, it goes beside the file (`X.toml.tuned`, `X.toml.designed`) or
/// to stdout.
pub(crate) struct OutFile<'a> {
    path: &'a Path,
    force: bool,
    /// The command writing, for its words.
    by: Writer,
    /// The recipe's text as it was read, if `path` named the recipe being
    /// tuned (the same file).
    recipe: Option<&'a str>,
}

/// The command that writes an `OutFile`.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Writer {
    Tune,
    Design,
}

impl Writer {
    /// What the work made, as a past participle: "tuned".
    fn made(self) -> &'static str {
        match self {
            Self::Tune => "tuned",
            Self::Design => "designed",
        }
    }

    /// The work, as a gerund: "tuning".
    fn working(self) -> &'static str {
        match self {
            Self::Tune => "tuning",
            Self::Design => "designing",
        }
    }
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
            by: Writer::Tune,
            recipe: None,
        };
        out.recipe = fs::symlink_metadata(path)
            .is_ok_and(|m| same_file(&m, path, recipe))
            .then_some(text);
        out.refusal()?;
        Ok(out)
    }

    /// Check `path` before designing for `target`, which it must not name.
    pub(crate) fn check_design(path: &'a Path, target: &Path, force: bool) -> Result<Self, Error> {
        let out = Self {
            path,
            force,
            by: Writer::Design,
            recipe: None,
        };
        if fs::symlink_metadata(path).is_ok_and(|m| same_file(&m, path, target)) {
            return Err(Error::usage(format!(
                "--out {} is the target being designed for; give the recipe another name, such as --out design.toml",
                path.display()
            )));
        }
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
            let back = match self.by {
                Writer::Tune => " (`tune X.toml --out X.toml` writes the recipe back)",
                Writer::Design => "",
            };
            return Err(Error::usage(format!(
                "{shown} exists; choose another --out, or pass --force to overwrite it{back}"
            )));
        }
        Ok(())
    }

    /// Write `bytes` to the file, after checking it again: what appeared
    /// there while the work ran is not overwritten unasked either, nor an
    /// edit made to the recipe meanwhile; either way `bytes` go beside it.
    pub(crate) fn write(&self, bytes: &[u8]) -> Result<(), Error> {
        fault::edit(self.path);
        if let Err(refused) = self.refusal() {
            return Err(self.kept_beside(bytes, &refused));
        }
        if let Some(text) = self.recipe
            && fs::read(self.path).ok().as_deref() != Some(text.as_bytes())
        {
            let shown = self.path.display();
            let why = format!(
                "{shown} changed while tuning ran, so it was not overwritten (the change is kept)"
            );
            return Err(self.kept_beside(bytes, &Error::io(why)));
        }
        let like = fs::symlink_metadata(self.path).ok();
        replace_like(self.path, bytes, like.as_ref()).map_err(|e| {
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
            "{} has {} (it is the same file under {}); writing would give the {} text to this name only: give another --out{}",
            self.path.display(),
            plural(others as usize, "other hard link"),
            if others == 1 {
                "another name"
            } else {
                "other names"
            },
            self.by.made(),
            if self.by == Writer::Tune {
                ", or tune a copy"
            } else {
                ""
            }
        )))
    }

    #[cfg(not(unix))]
    fn other_links(&self, _: &fs::Metadata) -> Option<Error> {
        None
    }

    /// `refused` at the write, after the work: the file there is the
    /// user's and stays; the text made goes beside it, as `X.toml.tuned`
    /// (or `.designed`) if that name is free, else to stdout.
    fn kept_beside(&self, bytes: &[u8], refused: &Error) -> Error {
        let made = self.by.made();
        let mut beside = self.path.as_os_str().to_owned();
        beside.push(format!(".{made}"));
        let beside = Path::new(&beside);
        let like = fs::symlink_metadata(self.path).ok().filter(|m| m.is_file());
        let put = if create_like(beside, bytes, like.as_ref()).is_ok() {
            format!("the {made} recipe is in {}", beside.display())
        } else {
            let mut stdout = io::stdout().lock();
            let printed = stdout.write_all(bytes).and_then(|()| stdout.flush());
            crate::cli::console::noted(printed, crate::cli::console::Stream::Out);
            format!("the {made} recipe was printed on stdout")
        };
        let why = refused.message();
        let when = if self.recipe.is_some() {
            String::new()
        } else {
            format!(" (found at the write, after {} ran)", self.by.working())
        };
        Error::new(refused.kind, format!("{why}{when}; {put}"))
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
