//! Starter recipes for `karigami new`: the files in templates/, built into
//! the binary so that a new design needs nothing but the program.

/// A starter recipe built into the binary.
pub struct Template {
    /// The name `karigami new` takes, e.g. `sheet`.
    pub name: &'static str,
    /// One line for `karigami templates`.
    pub about: &'static str,
    /// The recipe's TOML text (`templates/NAME.toml`).
    pub text: &'static str,
}

/// Every starter recipe, in the order `karigami templates` lists them.
pub const TEMPLATES: &[Template] = &[
    Template {
        name: "sheet",
        about: "a flat sheet, 6 cells wide and 5 rows, one row opening wider",
        text: include_str!("../templates/sheet.toml"),
    },
    Template {
        name: "chain",
        about: "a one-cell-wide chain of equal scissors (a lazy-tongs arm)",
        text: include_str!("../templates/chain.toml"),
    },
    Template {
        name: "curved",
        about: "a sheet in space, seeded on an arc, its rows tilted so it wraps",
        text: include_str!("../templates/curved.toml"),
    },
    Template {
        name: "tube",
        about: "a straight tube grown from a loop seed round a circle",
        text: include_str!("../templates/tube.toml"),
    },
    Template {
        name: "helix",
        about: "a helix seed on a shrinking spiral, one cell a growth step (see `karigami tune`)",
        text: include_str!("../templates/helix.toml"),
    },
    Template {
        name: "disk",
        about: "a flat disk fitted to a circle from a quarter-arc seed",
        text: include_str!("../templates/disk.toml"),
    },
    Template {
        name: "bumps",
        about: "an intrinsic (bent-facet) sheet whose rebuilt fronts zig-zag into bumps",
        text: include_str!("../templates/bumps.toml"),
    },
];

/// The template called `name`, if there is one.
pub fn find(name: &str) -> Option<&'static Template> {
    TEMPLATES.iter().find(|t| t.name == name)
}

/// The template's text with its `name = "..."` line set to `name`, as the
/// file `<name>.toml`.
pub fn instantiate(template: &Template, name: &str) -> String {
    instantiate_as(template, name, &format!("{name}.toml"))
}

/// The template's text with its `name = "..."` line set to `name`, and the
/// commands in its comments naming `file` (the recipe as written) and
/// `--out <name>` instead of the template's own file and design name.
pub fn instantiate_as(template: &Template, name: &str, file: &str) -> String {
    let own_file = format!("{}.toml", template.name);
    let own_out = format!("--out {}", template.name);
    let out_dir = file.strip_suffix(".toml").unwrap_or(file);
    let mut out = String::with_capacity(template.text.len());
    let mut renamed = false;
    for line in template.text.split_inclusive('\n') {
        if !renamed && line.starts_with("name = ") {
            out.push_str(&format!("name = {}\n", crate::words::toml_string(name)));
            renamed = true;
        } else if line.starts_with('#') && line.contains("karigami ") {
            // Whole words only: `helix.toml` but not `my-helix.toml`.
            let words: Vec<String> = line
                .split(' ')
                .map(|w| {
                    let bare = w.trim_end_matches(['`', '.', ',', '\n']);
                    let tail = &w[bare.len()..];
                    if bare == own_file {
                        format!("{file}{tail}")
                    } else {
                        w.to_string()
                    }
                })
                .collect();
            let line = words.join(" ");
            out.push_str(&line.replace(&own_out, &format!("--out {out_dir}")));
        } else {
            out.push_str(line);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_template_is_listed_once_and_renames() {
        let mut names: Vec<_> = TEMPLATES.iter().map(|t| t.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), TEMPLATES.len());
        for t in TEMPLATES {
            let text = instantiate(t, "my \"arm\"");
            let d = crate::design::parse(&text, "x").unwrap();
            assert_eq!(d.name, "my \"arm\"", "{}", t.name);
        }
    }

    #[test]
    fn commands_in_the_comments_name_the_new_file() {
        for t in TEMPLATES {
            let text = instantiate_as(t, "bridge", "bridge.toml");
            for line in text.lines().filter(|l| l.contains("karigami ")) {
                assert!(
                    !line.contains(&format!(" {}.toml", t.name))
                        && !line.contains("templates/")
                        && line.contains("bridge.toml"),
                    "{}: {line}",
                    t.name
                );
            }
        }
        let helix = instantiate_as(find("helix").unwrap(), "spiral", "spiral.toml");
        assert!(
            helix.contains("karigami tune spiral.toml --out spiral.toml"),
            "{helix}"
        );
        let sheet = instantiate_as(find("sheet").unwrap(), "my-sheet", "my-sheet.toml");
        assert!(
            sheet.contains("`karigami build my-sheet.toml --out my-sheet`"),
            "{sheet}"
        );
    }
}
