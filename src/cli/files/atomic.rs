//! Writing one file (a recipe, a report) so that it is either as it was
//! or complete.

use super::super::fault;
use super::hidden;
use std::fs::{self, OpenOptions};
use std::io::{self, Write};
use std::path::Path;

/// Write to a temporary file beside the target, then rename it over the
/// target: the target is either as it was or complete.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
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
