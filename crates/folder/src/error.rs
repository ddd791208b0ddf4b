//! Why a build folder was refused or could not be written: the facts (the
//! folder, what was being done, the system's error), and, shown, one
//! whole sentence that says what to change. The program maps each to its
//! own kind of error and exit status.

use crate::words::plural;
use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

/// Why an output folder was refused, or an operation on it failed. Each
/// variant's `out` is the folder as given (`--out`).
#[derive(Debug)]
pub enum Error {
    /// `doing` on `path` failed with `source`.
    Io {
        /// What was being done.
        doing: Doing,
        /// The file or folder it was done to.
        path: PathBuf,
        /// The system's error.
        source: io::Error,
    },
    /// `out` names no folder (`.`, `..`, `/`).
    NotAFolderName {
        /// The folder as given.
        out: PathBuf,
    },
    /// A folder on the way to `out` is the file `file`.
    UnderAFile {
        /// The folder as given.
        out: PathBuf,
        /// The first existing entry on the way, a file.
        file: PathBuf,
    },
    /// `out` is a symbolic link (to `to`, which may lead nowhere).
    IsALink {
        /// The folder as given.
        out: PathBuf,
        /// Where the link leads, as written in it.
        to: PathBuf,
        /// Whether nothing is there.
        dangling: bool,
    },
    /// `out` is a file.
    IsAFile {
        /// The folder as given.
        out: PathBuf,
    },
    /// A file system is mounted at `out`: it can be neither swapped nor
    /// removed.
    MountPoint {
        /// The folder as given.
        out: PathBuf,
    },
    /// `out` holds `input`, an input of this run.
    HoldsInput {
        /// The folder as given.
        out: PathBuf,
        /// The input inside it.
        input: PathBuf,
    },
    /// `out` is the current folder or holds it.
    HoldsCurrentFolder {
        /// The folder as given.
        out: PathBuf,
    },
    /// `out` is not a build folder, or its marker is not to be trusted,
    /// and `--force` was not given: replacing it would delete `files`.
    NotABuildFolder {
        /// The folder as given.
        out: PathBuf,
        /// Why it is not taken for a build folder.
        why: Untrusted,
        /// How many files it holds.
        files: usize,
    },
    /// `out` is a build folder but holds entries the build did not write
    /// (`added`, outermost only), and `--force` was not given.
    OtherFiles {
        /// The folder as given.
        out: PathBuf,
        /// The entries, a folder's ending in `/`.
        added: Vec<String>,
    },
    /// Entries appeared in `out` while the build ran, so it was not
    /// committed (`appeared`; an empty name: `out` itself was replaced).
    Appeared {
        /// The folder as given.
        out: PathBuf,
        /// The entries, a folder's ending in `/`.
        appeared: Vec<String>,
    },
    /// Another run holds the lock `lock` of `out`.
    Locked {
        /// The folder as given.
        out: PathBuf,
        /// The lock file beside it.
        lock: PathBuf,
    },
}

/// What was being done when an operation failed (`Error::Io`).
#[derive(Debug)]
pub enum Doing {
    /// Reading the entry.
    Read,
    /// Creating the folder.
    Create,
    /// Writing the file (the lock).
    Write,
    /// Locking the lock file.
    Lock,
    /// Tidying what interrupted runs left beside the folder.
    Tidy,
    /// Committing a build into the folder, which is left as it was:
    /// `earlier` when it held a build or files (else nothing was written).
    Commit {
        /// Whether the folder held anything before.
        earlier: bool,
    },
    /// Finishing a commit: the new build is in the folder's place, the
    /// earlier one at `old`, which the next build into it tidies.
    Finish {
        /// Where the earlier build is.
        old: PathBuf,
    },
    /// Putting the earlier build back, after entries appeared in it as it
    /// was swapped out: the new build is in the folder's place.
    PutBack,
}

/// Why a folder is not taken for a build folder (`Error::NotABuildFolder`).
#[derive(Debug)]
pub enum Untrusted {
    /// It has no marker; `older` when it holds a `lattice.json` or a
    /// `batch.json`, as builds of karigami before the marker did.
    NoMarker {
        /// Whether it looks like an older build.
        older: bool,
    },
    /// Its marker lists this path outside the folder, which no build
    /// writes.
    ListsOutside(String),
}

impl Error {
    /// An operation on `path` that failed.
    pub(crate) fn io(doing: Doing, path: &Path, source: io::Error) -> Self {
        Self::Io {
            doing,
            path: path.to_path_buf(),
            source,
        }
    }
}

/// What the folder holds after a commit that did not happen (`Doing::Commit`).
pub(crate) fn left_as_it_was(out: &Path, earlier: bool) -> String {
    if earlier {
        format!("{} was left as it was", out.display())
    } else {
        format!("nothing was written to {}", out.display())
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io {
                doing,
                path,
                source,
            } => io_sentence(f, doing, path, source),
            Self::NotAFolderName { out } => write!(
                f,
                "--out {} is not a folder name; give the folder to build into, such as --out my-build",
                out.display()
            ),
            Self::UnderAFile { out, file } => write!(
                f,
                "cannot create {}: {} is a file, not a folder",
                out.display(),
                file.display()
            ),
            Self::IsALink { out, to, dangling } => write!(
                f,
                "--out {} is a symbolic link (to {}{}); give the real folder as --out",
                out.display(),
                to.display(),
                if *dangling {
                    ", which does not exist"
                } else {
                    ""
                }
            ),
            Self::IsAFile { out } => write!(
                f,
                "--out {} is a file, not a folder; choose another --out (--force replaces only folders)",
                out.display()
            ),
            Self::MountPoint { out } => write!(
                f,
                "--out {} is a mount point (a file system is mounted there), which a build cannot replace: it writes a new folder beside it and swaps the two; give a folder inside it, such as --out {}",
                out.display(),
                out.join("build").display()
            ),
            Self::HoldsInput { out, input } => write!(
                f,
                "--out {} holds {}, an input of this run, and building would replace the folder with it; choose another --out",
                out.display(),
                input.display()
            ),
            Self::HoldsCurrentFolder { out } => write!(
                f,
                "--out {} is the current folder or holds it; run karigami from outside it or choose another --out",
                out.display()
            ),
            Self::NotABuildFolder { out, why, files } => not_a_build(f, out, why, *files),
            Self::OtherFiles { out, added } => {
                let it = it_or_them(added);
                write!(
                    f,
                    "{} is a karigami build folder but holds {} the build did not write: {}; move {it} out, or pass --force to replace the folder and delete {it}",
                    out.display(),
                    counted(added),
                    shortlist(added)
                )
            }
            Self::Appeared { out, appeared } => appeared_sentence(f, out, appeared),
            Self::Locked { out, lock } => write!(
                f,
                "another karigami run is writing {} right now (it holds {}); wait for it to finish or choose another --out",
                out.display(),
                lock.display()
            ),
        }
    }
}

fn io_sentence(
    f: &mut fmt::Formatter<'_>,
    doing: &Doing,
    path: &Path,
    e: &io::Error,
) -> fmt::Result {
    let shown = path.display();
    match doing {
        Doing::Read => write!(f, "cannot read {shown}: {e}"),
        Doing::Create => write!(f, "cannot create {shown}: {e}"),
        Doing::Write => write!(f, "cannot write {shown}: {e}"),
        Doing::Lock => write!(f, "cannot lock {shown}: {e}"),
        Doing::Tidy => write!(f, "cannot tidy up beside {shown}: {e}"),
        Doing::Commit { earlier } => write!(
            f,
            "cannot write {shown}: {e}; {}",
            left_as_it_was(path, *earlier)
        ),
        Doing::Finish { old } => write!(
            f,
            "cannot finish replacing {shown}: {e}; the new build is in its place, and the earlier one in {}, which the next build into {shown} tidies",
            old.display()
        ),
        Doing::PutBack => write!(
            f,
            "cannot put the earlier build back in {shown}: {e}; the new build is in its place"
        ),
    }
}

fn not_a_build(
    f: &mut fmt::Formatter<'_>,
    out: &Path,
    why: &Untrusted,
    files: usize,
) -> fmt::Result {
    let shown = out.display();
    let marker = crate::MARKER;
    let deleted = format!(
        "choose another --out, or pass --force to replace it (its {} would be deleted)",
        plural(files, "file")
    );
    match why {
        Untrusted::ListsOutside(bad) => write!(
            f,
            "{shown} has a {marker} marker that lists {bad}, a path outside the folder, so karigami did not write it; {deleted}"
        ),
        Untrusted::NoMarker { older: true } => write!(
            f,
            "{shown} has no {marker} marker: it may be a build of an older karigami, or a folder of yours; {deleted}"
        ),
        Untrusted::NoMarker { older: false } => write!(
            f,
            "{shown} exists and is not a karigami build folder (it has no {marker} marker); {deleted}"
        ),
    }
}

fn appeared_sentence(f: &mut fmt::Formatter<'_>, out: &Path, appeared: &[String]) -> fmt::Result {
    let shown = out.display();
    let it = it_or_them(appeared);
    let what = if appeared.iter().any(String::is_empty) {
        format!("{shown} was replaced by a file or a link while the build ran")
    } else {
        format!(
            "{} appeared in {shown} while the build ran: {}",
            counted(appeared),
            shortlist(appeared)
        )
    };
    write!(
        f,
        "{what}; the build was not committed and {shown} was left as it was ({it} too); move {it} out of {shown}, or build into another --out, and build again"
    )
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

fn it_or_them(entries: &[String]) -> &'static str {
    if entries.len() == 1 { "it" } else { "them" }
}

/// The first few of `files`, and how many more.
pub(crate) fn shortlist(files: &[String]) -> String {
    const SHOWN: usize = 10;
    let mut list: Vec<&str> = files.iter().take(SHOWN).map(String::as_str).collect();
    let more = format!("and {} more", files.len().saturating_sub(SHOWN));
    if files.len() > SHOWN {
        list.push(&more);
    }
    list.join(", ")
}

/// How many files, folders or both `entries` (from `out_dir::entries`: a
/// folder's ends in `/`) are: "1 file", "2 folders", "3 files and folders".
pub(crate) fn counted(entries: &[String]) -> String {
    let folders = entries.iter().filter(|e| e.ends_with('/')).count();
    match (folders, entries.len() - folders) {
        (0, files) => plural(files, "file"),
        (folders, 0) => plural(folders, "folder"),
        _ => format!("{} files and folders", entries.len()),
    }
}
