//! Filesystem access: reading recipes and writing build folders so that no
//! reader ever sees a half-written file or a mix of two builds.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

pub fn read(path: &Path) -> io::Result<String> {
    fs::read_to_string(path)
}

/// Write to a temporary file beside the target, then rename it over the
/// target.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::other("no file name"))?;
    let tmp = path.with_file_name(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// What marks a folder as karigami's own: a single build's lattice.json or
/// a batch's batch.json.
pub const MARKERS: [&str; 2] = ["lattice.json", "batch.json"];

/// A folder holds a previous build when it has a marker (or is empty).
fn is_previous_build(dir: &Path) -> io::Result<bool> {
    let mut entries = fs::read_dir(dir)?;
    Ok(MARKERS.iter().any(|m| dir.join(m).is_file()) || entries.next().is_none())
}

fn sibling(dir: &Path, tag: &str) -> PathBuf {
    let name = dir
        .file_name()
        .map_or("out".into(), |n| n.to_string_lossy().into_owned());
    dir.with_file_name(format!(".{name}.{tag}-{}", std::process::id()))
}

/// A build folder being written: files go into a fresh folder beside the
/// target, which replaces the target in one rename on `commit`. Dropped
/// without a commit, the fresh folder is removed and the target untouched.
pub struct Staged {
    target: PathBuf,
    fresh: PathBuf,
    committed: bool,
}

impl Staged {
    /// Refuses an existing `dir` that is not a previous build unless `force`.
    pub fn new(dir: &Path, force: bool) -> io::Result<Self> {
        if dir.exists() && !force && !is_previous_build(dir)? {
            return Err(io::Error::other(
                "the folder exists and is not a karigami build (no lattice.json or batch.json); choose another --out or pass --force to replace it",
            ));
        }
        if let Some(parent) = dir.parent().filter(|p| !p.as_os_str().is_empty()) {
            fs::create_dir_all(parent)?;
        }
        let fresh = sibling(dir, "new");
        let _ = fs::remove_dir_all(&fresh);
        fs::create_dir_all(&fresh)?;
        Ok(Self {
            target: dir.to_path_buf(),
            fresh,
            committed: false,
        })
    }

    /// Write files (paths relative to `sub` inside the folder), each atomically.
    pub fn write(&self, sub: &str, files: &[(String, Vec<u8>)]) -> io::Result<()> {
        for (name, bytes) in files {
            let path = self.fresh.join(sub).join(name);
            fs::create_dir_all(path.parent().expect("a file inside the folder"))?;
            write_atomic(&path, bytes)?;
        }
        Ok(())
    }

    /// Replace the target with the fresh folder.
    pub fn commit(mut self) -> io::Result<()> {
        if self.target.exists() {
            let old = sibling(&self.target, "old");
            let _ = fs::remove_dir_all(&old);
            fs::rename(&self.target, &old)?;
            fs::rename(&self.fresh, &self.target)?;
            self.committed = true;
            fs::remove_dir_all(&old)
        } else {
            fs::rename(&self.fresh, &self.target)?;
            self.committed = true;
            Ok(())
        }
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_dir_all(&self.fresh);
        }
    }
}

/// Write a whole build folder in one step (see `Staged`).
pub fn replace_dir(dir: &Path, files: &[(String, Vec<u8>)], force: bool) -> io::Result<()> {
    let staged = Staged::new(dir, force)?;
    staged.write("", files)?;
    staged.commit()
}

/// The recipes named on the command line: files as given, folders as the
/// `.toml` files directly inside them, sorted by name.
pub fn recipes(args: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
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
