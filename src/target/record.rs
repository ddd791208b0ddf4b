//! Where a recipe `karigami design` writes finds its target again
//! (docs/design.md, "The recipe's record").

use std::path::{Path, PathBuf};

/// The target's path as the recipe records it (docs/design.md, "The
/// recipe's record"): relative to the recipe's folder when the two share a
/// tree (the target in or below that folder, or a common folder at least
/// two deep: `/work/project`, not `/` or `/tmp`), else absolute; both with
/// links resolved, as `..` is. As given when either cannot be resolved.
pub fn recorded_path(target: &Path, out: &Path) -> String {
    let dir = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    match (target.canonicalize(), dir.canonicalize()) {
        (Ok(t), Ok(d)) => {
            let common = t
                .components()
                .zip(d.components())
                .take_while(|(x, y)| x == y)
                .count();
            // The root is a component: two deep is three.
            if t.starts_with(&d) || common >= 3 {
                relative(&t, &d).display().to_string()
            } else {
                t.display().to_string()
            }
        }
        _ => target.display().to_string(),
    }
}

/// `to` relative to the folder `from` (both absolute).
fn relative(to: &Path, from: &Path) -> PathBuf {
    let (a, b): (Vec<_>, Vec<_>) = (to.components().collect(), from.components().collect());
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &a[common..] {
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::recorded_path;
    use std::path::Path;

    /// In one project: relative, up and down; from /tmp to a project:
    /// absolute; beside it: its name.
    #[test]
    fn a_target_in_the_recipes_tree_is_recorded_relative_else_absolute() {
        let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
        let target = repo.join("fixtures/targets/disk.toml");
        assert_eq!(
            recorded_path(&target, &repo.join("examples/x.toml")),
            "../fixtures/targets/disk.toml"
        );
        assert_eq!(
            recorded_path(&target, &repo.join("fixtures/targets/x.toml")),
            "disk.toml"
        );
        let tmp = std::env::temp_dir().canonicalize().unwrap();
        let away = recorded_path(&target, &tmp.join("x.toml"));
        if tmp.components().count() <= 2 && !repo.starts_with(&tmp) {
            assert_eq!(Path::new(&away), target.canonicalize().unwrap());
        }
    }
}
