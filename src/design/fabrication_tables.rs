//! The fabrication flags written as recipe tables (docs/recipe.md,
//! "Fabrication tables"), so that a recipe `karigami design` writes builds
//! as it was designed without the flags given again.

use super::Overrides;
use crate::words::toml_string;

impl Overrides {
    /// The tables that set what these flags set, with `thickness` (mm) in
    /// `[material]`; empty when nothing is set. The run's limits
    /// (`--memory`, `--time-limit`) belong to a run, not to the recipe,
    /// and are left out.
    pub fn as_tables(&self, thickness: Option<f64>) -> String {
        let text = |s: &Option<String>| s.as_deref().map(toml_string);
        // `{:?}` keeps a decimal point or an exponent: a TOML float.
        let number = |x: Option<f64>| x.map(|x| format!("{x:?}"));
        let switch = |b: Option<bool>| b.map(|b| b.to_string());
        let group = self
            .group_by_step
            .map(|g| toml_string(if g { "step" } else { "none" }));
        let tables = [
            (
                "material",
                vec![
                    ("thickness", number(thickness)),
                    ("width", number(self.strip_width)),
                ],
            ),
            ("eyelet", vec![("preset", text(&self.eyelet))]),
            ("strip", vec![("label", text(&self.label))]),
            (
                "laser",
                vec![
                    ("kerf", number(self.kerf)),
                    ("compensate", switch(self.compensate_kerf)),
                    ("colours", text(&self.colours)),
                    ("tabs", number(self.tabs)),
                    ("flat", switch(self.flat)),
                ],
            ),
            (
                "sheet",
                vec![
                    ("preset", text(&self.sheet)),
                    ("test_piece", switch(self.test_piece)),
                    ("group", group),
                ],
            ),
            ("machine", vec![("preset", text(&self.machine))]),
            ("guide", vec![("paper", text(&self.paper))]),
        ];
        let mut out = String::new();
        for (table, keys) in tables {
            let keys: Vec<String> = keys
                .into_iter()
                .filter_map(|(key, value)| value.map(|v| format!("{key} = {v}\n")))
                .collect();
            if !keys.is_empty() {
                out.push_str(&format!("[{table}]\n"));
                out.extend(keys);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::{parse, parse_with};

    const SEED: &str = "[lattice]\nseed = \"sheet\"\npoints = [[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]]\nkappa = 0.0\n[lattice.grow]\nrows = 1\nangle = [45.0, 0.0]\n";

    fn flags(machine: Option<&str>, sheet: Option<&str>) -> Overrides {
        Overrides {
            sheet: sheet.map(Into::into),
            eyelet: Some("5/32in".into()),
            strip_width: Some(12.5),
            kerf: Some(0.2),
            compensate_kerf: Some(true),
            label: Some("compact".into()),
            paper: Some("letter".into()),
            test_piece: Some(false),
            colours: Some("boxes".into()),
            group_by_step: Some(true),
            tabs: Some(1.0),
            flat: Some(true),
            machine: machine.map(Into::into),
            ..Overrides::default()
        }
    }

    /// Every flag, for a laser and for a plotter, and each flag alone:
    /// the recipe with the tables builds the same settings as the flags.
    #[test]
    fn the_tables_set_what_the_flags_set() {
        let mut cases = vec![
            flags(None, Some("a3")),
            flags(None, Some("321.5x200")),
            flags(Some("laser-diode"), Some("auto")),
            flags(Some("cricut"), Some("12x24in")),
            flags(Some("silhouette"), None),
        ];
        let all = flags(Some("laser-co2"), Some("glowforge"));
        let one = |f: &dyn Fn(&mut Overrides)| {
            let mut o = Overrides::default();
            f(&mut o);
            o
        };
        cases.extend([
            one(&|o| o.sheet = all.sheet.clone()),
            one(&|o| o.eyelet = all.eyelet.clone()),
            one(&|o| o.strip_width = all.strip_width),
            one(&|o| o.kerf = all.kerf),
            one(&|o| o.compensate_kerf = all.compensate_kerf),
            one(&|o| o.label = all.label.clone()),
            one(&|o| o.paper = all.paper.clone()),
            one(&|o| o.test_piece = all.test_piece),
            one(&|o| o.colours = all.colours.clone()),
            one(&|o| o.group_by_step = all.group_by_step),
            one(&|o| o.tabs = all.tabs),
            one(&|o| o.flat = all.flat),
            one(&|o| o.machine = all.machine.clone()),
        ]);
        cases.push(all.clone());
        for (k, o) in cases.iter().enumerate() {
            let flagged = parse_with(&format!("{SEED}[material]\nthickness = 0.8\n"), "t", o)
                .unwrap_or_else(|d| panic!("case {k}: {}", d.message));
            let tables = o.as_tables(Some(0.8));
            let written = parse(&format!("{SEED}{tables}"), "t")
                .unwrap_or_else(|d| panic!("case {k}:\n{tables}\n{}", d.message));
            assert_eq!(
                written.fabrication, flagged.fabrication,
                "case {k}:\n{tables}"
            );
        }
        assert_eq!(Overrides::default().as_tables(None), "");
    }
}
