//! Reading the input: recipe files within a size limit in UTF-8, the
//! recipes a folder holds, and names derived from them made safe to use as
//! a folder name.

use crate::cli::error::Error;
use karigami::ErrorKind;
use karigami_folder::{Links, read_plain};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

/// Recipes larger than this are refused before reading them whole.
pub(super) const MAX_RECIPE_BYTES: u64 = 1 << 20;

/// Longest name (in bytes) of a folder the tool derives from input.
pub(super) const MAX_NAME_BYTES: usize = 100;

/// Read a recipe: a regular file of at most `MAX_RECIPE_BYTES`, in UTF-8.
/// A link is followed; a folder, a FIFO or a device is refused at once
/// (never waited on, nor read without end).
pub(crate) fn read(path: &Path) -> io::Result<String> {
    let bytes = read_plain(path, MAX_RECIPE_BYTES, Links::Follow).map_err(|e| match e.kind() {
        io::ErrorKind::IsADirectory => io::Error::other("it is a folder, not a recipe file"),
        io::ErrorKind::InvalidInput => io::Error::other(format!("{e}; give a recipe file (.toml)")),
        io::ErrorKind::FileTooLarge => io::Error::other(format!("{e} for a recipe")),
        _ => e,
    })?;
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

/// `raw` (a recipe's file name, a folder's name) as a plain, portable,
/// single path component: separators, control and reserved characters
/// become `_`, leading dots (hidden, `.`, `..`) and trailing dots and
/// spaces go, names reserved on Windows get a `_`, and the length is capped.
pub(crate) fn safe_component(raw: &str) -> String {
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

/// The recipes named on the command line: files as given, folders as the
/// `.toml` files directly inside them, sorted by name.
pub(crate) fn recipes(args: &[PathBuf]) -> Result<Vec<PathBuf>, Error> {
    let mut out = Vec::new();
    for arg in args {
        if arg.is_dir() {
            let mut found: Vec<PathBuf> = fs::read_dir(arg)
                .map_err(|e| Error::io(format!("cannot read folder {}: {e}", arg.display())))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "toml"))
                .collect();
            if found.is_empty() {
                return Err(Error::new(
                    ErrorKind::NoRecipes,
                    format!("folder {} holds no .toml recipes", arg.display()),
                ));
            }
            found.sort();
            out.extend(found);
        } else {
            out.push(arg.clone());
        }
    }
    Ok(out)
}
