//! Machine presets (`[machine] preset`, `--machine`): a laser, whose cut
//! files and settings are today's, or a cutting plotter (Cricut,
//! Silhouette), which cuts with a drag blade on a sticky mat. A plotter's
//! sheet is its mat's cutting area, its labels go on a pen layer, and a
//! hole smaller than the blade cuts cleanly is refused. The figures and
//! their sources are in docs/fabrication.md ("Cutting plotters").

use super::Machine;

/// A cutting plotter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plotter {
    /// Cricut Maker or Explore (Design Space).
    Cricut,
    /// Silhouette Cameo (Silhouette Studio).
    Silhouette,
}

impl Plotter {
    /// The machine as the guide names it.
    pub fn describe(self) -> &'static str {
        match self {
            Plotter::Cricut => "a Cricut Maker or Explore cutting plotter",
            Plotter::Silhouette => "a Silhouette Cameo cutting plotter",
        }
    }

    /// The program the cut files are imported into.
    pub fn software(self) -> &'static str {
        match self {
            Plotter::Cricut => "Cricut Design Space",
            Plotter::Silhouette => "Silhouette Studio",
        }
    }

    /// What the user clicks so the labels are drawn, not cut.
    pub fn draw_steps(self) -> &'static str {
        match self {
            Plotter::Cricut => {
                "in Design Space upload the sheet's SVG, select the layer group \"draw\" and set its Operation to \
                 Pen (Draw), then select all and Attach so every piece keeps its place on the mat"
            }
            Plotter::Silhouette => {
                "in Silhouette Studio open the sheet's SVG, and in the Send panel's Line tab set black to Sketch \
                 (a sketch pen in tool 2) and blue and red to Cut"
            }
        }
    }
}

/// The machine a job is cut on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MachinePreset {
    /// A laser (the cut files and settings for `Machine`).
    Laser(Machine),
    /// A cutting plotter.
    Plotter(Plotter),
}

/// Every preset, by its key, in the order errors list them.
pub const MACHINE_PRESETS: &[(&str, MachinePreset)] = &[
    ("laser-co2", MachinePreset::Laser(Machine::Co2)),
    ("laser-diode", MachinePreset::Laser(Machine::Diode)),
    ("cricut", MachinePreset::Plotter(Plotter::Cricut)),
    ("silhouette", MachinePreset::Plotter(Plotter::Silhouette)),
];

impl MachinePreset {
    pub(crate) fn parse(s: &str) -> Option<Self> {
        MACHINE_PRESETS.iter().find(|p| p.0 == s).map(|p| p.1)
    }

    /// The keys, quoted, for a hint.
    pub(crate) fn names() -> String {
        let keys: Vec<String> = MACHINE_PRESETS
            .iter()
            .map(|p| format!("\"{}\"", p.0))
            .collect();
        keys.join(", ")
    }
}

/// A mat: its name and the cutting area (mm), width (along the feed) by
/// height (across the rollers): 11.5 x 11.5 in and 23.5 x 11.5 in, 1/4 in
/// clear of each edge of the 12 in wide sticky area (docs/fabrication.md).
/// Written in mm, as printed (11.5 * 25.4 is 292.09999999999997).
pub const MATS: &[(&str, f64, f64)] = &[("12x12in", 292.1, 292.1), ("12x24in", 596.9, 292.1)];

/// The mat a plotter job uses unless the sheet names another: the one
/// every machine comes with.
pub(crate) const DEFAULT_MAT: usize = 0;

/// The smallest eyelet hole (mm) a plotter preset cuts: karigami's own
/// conservative figure (no maker gives one; docs/fabrication.md says why),
/// which `[machine] min_hole` replaces.
pub const PLOTTER_MIN_HOLE: f64 = 3.0;

/// A cutting plotter job: the machine, its mat and the smallest hole.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotterSetup {
    /// The machine.
    pub plotter: Plotter,
    /// The mat's name (`MATS`).
    pub mat: &'static str,
    /// The smallest hole the blade cuts cleanly (mm).
    pub min_hole: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_parse_and_mats_fit_inside_their_mats() {
        for (key, p) in MACHINE_PRESETS {
            assert_eq!(MachinePreset::parse(key), Some(*p));
        }
        assert_eq!(MachinePreset::parse("Cricut"), None);
        // The cutting area is inside the mat it is named after.
        for (name, w, h) in MATS {
            let (mw, mh) = name.trim_end_matches("in").split_once('x').unwrap();
            let (mw, mh): (f64, f64) = (mw.parse().unwrap(), mh.parse().unwrap());
            assert!(w.max(*h) < 25.4 * mw.max(mh) && w.min(*h) < 25.4 * mw.min(mh));
        }
        for (_, w, h) in MATS {
            for side in [w, h] {
                assert!(
                    (side / 25.4 * 2.0 - (side / 25.4 * 2.0).round()).abs() < 1e-9,
                    "{side}: whole half inches"
                );
            }
        }
    }
}
