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

/// A folder holds a previous build when it has a lattice.json (or is empty).
fn is_previous_build(dir: &Path) -> io::Result<bool> {
    let mut entries = fs::read_dir(dir)?;
    Ok(dir.join("lattice.json").is_file() || entries.next().is_none())
}

fn sibling(dir: &Path, tag: &str) -> PathBuf {
    let name = dir
        .file_name()
        .map_or("out".into(), |n| n.to_string_lossy().into_owned());
    dir.with_file_name(format!(".{name}.{tag}-{}", std::process::id()))
}

/// Write a whole build folder: every file goes into a fresh folder beside
/// `dir`, which then replaces `dir` in one rename. An existing `dir` that is
/// not a previous build is refused unless `force`.
pub fn replace_dir(dir: &Path, files: &[(String, Vec<u8>)], force: bool) -> io::Result<()> {
    if dir.exists() && !force && !is_previous_build(dir)? {
        return Err(io::Error::other(
            "the folder exists and is not a karigami build (no lattice.json); choose another --out or pass --force to replace it",
        ));
    }
    if let Some(parent) = dir.parent().filter(|p| !p.as_os_str().is_empty()) {
        fs::create_dir_all(parent)?;
    }
    let fresh = sibling(dir, "new");
    let _ = fs::remove_dir_all(&fresh);
    let result = (|| {
        for (name, bytes) in files {
            let path = fresh.join(name);
            fs::create_dir_all(path.parent().expect("a file inside the folder"))?;
            write_atomic(&path, bytes)?;
        }
        if dir.exists() {
            let old = sibling(dir, "old");
            let _ = fs::remove_dir_all(&old);
            fs::rename(dir, &old)?;
            fs::rename(&fresh, dir)?;
            fs::remove_dir_all(&old)
        } else {
            fs::rename(&fresh, dir)
        }
    })();
    if result.is_err() {
        let _ = fs::remove_dir_all(&fresh);
    }
    result
}
