//! The layers of docs/code.md's "Layout of the code", checked against the code:
//! every `crate::` path in a module of `src/` names a module of a lower
//! layer, so the list stays true and no import circle comes back.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The layer (1 = bottom) of each top-level module, read from docs/code.md's
/// numbered list: the backticked names outside parentheses, up to the
/// binary's item (`cli/`).
fn readme_layers() -> BTreeMap<String, usize> {
    let readme = std::fs::read_to_string("docs/code.md").unwrap();
    let section = readme
        .split("## Layout of the code")
        .nth(1)
        .expect("docs/code.md has a \"Layout of the code\" section");
    // Items with their continuation lines joined.
    let mut items: Vec<(usize, String)> = Vec::new();
    for line in section.lines().take_while(|l| !l.starts_with('|')) {
        let number = line.split_once(". ").and_then(|(n, _)| n.parse().ok());
        match (number, items.last_mut()) {
            (Some(n), _) => items.push((n, line.split_once(". ").unwrap().1.into())),
            (None, Some(last)) if line.starts_with("   ") => last.1.push_str(line),
            _ => {}
        }
    }
    let mut layers = BTreeMap::new();
    for (n, text) in items {
        let mut bare = String::new();
        let mut depth = 0;
        for c in text.chars() {
            match c {
                '(' => depth += 1,
                ')' => depth -= 1,
                _ if depth == 0 => bare.push(c),
                _ => {}
            }
        }
        let names: Vec<&str> = bare.split('`').skip(1).step_by(2).collect();
        if names.first().is_some_and(|n| n.ends_with('/')) {
            break;
        }
        for name in names {
            layers.insert(name.to_string(), n);
        }
    }
    layers
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level modules a file names after `crate::`, including each
/// first name of a `crate::{a, b::c}` group (comments left out).
fn crate_references(text: &str) -> Vec<String> {
    let code: String = text
        .lines()
        .map(|l| l.split("//").next().unwrap())
        .collect::<Vec<_>>()
        .join("\n");
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut refs = Vec::new();
    for (i, _) in code.match_indices("crate::") {
        let rest = &code[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            // Top-level names of the group: those at brace depth 0.
            let (mut depth, mut start) = (0, true);
            for (k, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => start = true,
                    c if start && !c.is_whitespace() => {
                        refs.push(ident(&group[k..]));
                        start = false;
                    }
                    _ => {}
                }
            }
        } else {
            refs.push(ident(rest));
        }
    }
    refs
}

#[test]
fn every_import_runs_down_the_layers_of_the_readme() {
    let layers = readme_layers();
    let mut files = Vec::new();
    rust_files(Path::new("src"), &mut files);
    files.sort();
    let mut wrong = Vec::new();
    for file in &files {
        let rel = file.strip_prefix("src").unwrap();
        let first = rel.iter().next().unwrap().to_str().unwrap();
        let module = first.trim_end_matches(".rs");
        if ["lib", "main", "cli"].contains(&module) {
            continue;
        }
        let Some(&own) = layers.get(module) else {
            wrong.push(format!("src/{module} is not in docs/code.md's layer list"));
            continue;
        };
        let text = std::fs::read_to_string(file).unwrap();
        for r in crate_references(&text) {
            if r == module || r == "self" || r.is_empty() {
                continue;
            }
            match layers.get(&r) {
                Some(&layer) if layer < own => {}
                Some(&layer) => wrong.push(format!(
                    "{} (layer {own}) imports {r} (layer {layer})",
                    file.display()
                )),
                None => wrong.push(format!(
                    "{} imports {r}, which is not in docs/code.md's layer list",
                    file.display()
                )),
            }
        }
    }
    assert!(
        layers.len() >= 17,
        "docs/code.md's layer list was not read: {layers:?}"
    );
    assert!(
        wrong.is_empty(),
        "imports against the layers:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn crate_references_are_read_from_paths_and_groups() {
    let text = "use crate::lattice::{Lattice, joints};\nuse crate::{build::Build, parts::{Outline, solid},\n    report};\n// crate::guide in a comment\nlet x = crate::sim::wanted(l);";
    assert_eq!(
        crate_references(text),
        ["lattice", "build", "parts", "report", "sim"]
    );
}
