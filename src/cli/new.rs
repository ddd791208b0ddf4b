//! `karigami new`: a starter recipe from a template; `karigami templates`.

use super::args::Verbosity;
use super::error::Error;
use super::files;
use super::recipe::stem;
use karigami::template;
use std::path::{Path, PathBuf};

/// `karigami templates`: what `new` can start from.
pub(super) fn list() {
    for t in template::TEMPLATES {
        outln!("{:<8} {}", t.name, t.about);
    }
}

pub(super) fn new(name: &str, template: &str, force: bool, v: Verbosity) -> Result<(), Error> {
    let Some(t) = template::find(template) else {
        let names: Vec<_> = template::TEMPLATES.iter().map(|t| t.name).collect();
        return Err(Error::usage(format!(
            "no template \"{template}\"; there are: {}",
            names.join(", ")
        )));
    };
    let file = Path::new(name)
        .file_name()
        .map(|f| f.to_string_lossy().into_owned());
    let plain = file
        .as_deref()
        .filter(|f| !f.starts_with('.') && !f.chars().any(char::is_control) && *f != ".toml");
    // `sub/`, `sub/.` and `sub/..` name a folder, not a file in it (whose
    // name `Path::file_name` would take to be `sub`).
    let last = name
        .rsplit(std::path::is_separator)
        .next()
        .unwrap_or_default();
    let folder = matches!(last, "" | "." | "..");
    if plain.is_none() || folder || name.chars().any(char::is_control) {
        return Err(Error::usage(format!(
            "{name:?} is not a usable recipe name: give a file name that does not start with a dot, end in a separator or have control characters, such as `karigami new my-sheet`"
        )));
    }
    let path = if name.ends_with(".toml") {
        PathBuf::from(name)
    } else {
        PathBuf::from(format!("{name}.toml"))
    };
    // A link counts as there even if it leads nowhere: writing would
    // replace it.
    if std::fs::symlink_metadata(&path).is_ok() && !force {
        return Err(Error::usage(format!(
            "{} exists; choose another name or pass --force to overwrite it",
            path.display()
        )));
    }
    let design_name = stem(&path);
    files::write_atomic(
        &path,
        template::instantiate_as(t, &design_name, &path.display().to_string()).as_bytes(),
    )
    .map_err(|e| Error::io(format!("cannot write {}: {e}", path.display())))?;
    if !v.quiet {
        outln!(
            "wrote {} from the {} template; next: karigami check {0}",
            path.display(),
            t.name
        );
    }
    Ok(())
}
