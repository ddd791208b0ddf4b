//! Fabrication settings: the strip material, eyelets, laser and sheet, with
//! the presets makers think in. All lengths in mm.

mod machine;
mod stock;
pub mod test_piece;

pub(crate) use machine::DEFAULT_MAT;
pub use machine::{MACHINE_PRESETS, MATS, MachinePreset, PLOTTER_MIN_HOLE, Plotter, PlotterSetup};
pub use stock::{LaserSetting, Machine, MachineSettings, STOCK_PRESETS, StockPreset};
pub(crate) use stock::{default_stock, stock_preset};

/// Smallest engraved text height (mm) before a label falls back to a shorter
/// form: nothing karigami prints or engraves is smaller (a maker must read it).
pub(crate) const MIN_LABEL_HEIGHT: f64 = 2.5;

/// Clearance (mm) added to the strip width unless the recipe sets one.
pub(crate) const DEFAULT_CLEARANCE: f64 = 1.0;

/// Flat strip stock.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub(crate) name: String,
    /// The stock preset it is (`[material] preset`), None for a material
    /// given by name alone (its laser settings and safety are unknown).
    pub preset: Option<&'static StockPreset>,
    /// Stock thickness (mm); the simulation's strip section uses it.
    pub thickness: f64,
    /// Strip width w.
    pub width: f64,
}

/// An eyelet (grommet) size: the hole it needs and the flange it covers.
#[derive(Clone, Debug, PartialEq)]
pub struct Eyelet {
    pub(crate) name: String,
    /// Diameter of the hole the eyelet needs (mm): what is cut.
    pub hole: f64,
    /// Outer diameter of the eyelet's flange (mm): holes of one strip must be at
    /// least this far apart.
    pub flange: f64,
}

/// Eyelet presets: typical hole and flange diameters for common eyelets
/// (measure yours: brands differ).
pub(crate) const EYELET_PRESETS: &[(&str, f64, f64)] = &[
    ("1/8in", 3.2, 6.5),
    ("5/32in", 4.0, 8.0),
    ("3/16in", 4.8, 9.5),
];

/// Sheet (laser bed) presets: name, width, height.
pub const SHEET_PRESETS: &[(&str, f64, f64)] = &[
    ("600x400", 600.0, 400.0),
    ("glowforge", 495.0, 279.0),
    ("12x24in", 609.6, 304.8),
    ("12x20in", 508.0, 304.8),
    ("a3", 420.0, 297.0),
    ("a4", 297.0, 210.0),
];

/// The sheet (laser bed) strips are nested on; lengths in mm.
#[derive(Clone, Debug, PartialEq)]
pub struct SheetSpec {
    /// How the sheet was chosen: a preset name, a `WxH` size from the command
    /// line, `custom` (a size in the recipe) or `auto`.
    pub name: String,
    /// Sheet width (mm), along x.
    pub width: f64,
    /// Sheet height (mm), along y.
    pub height: f64,
    /// Border kept free of parts.
    pub margin: f64,
    /// Minimum gap between parts.
    pub gap: f64,
}

impl SheetSpec {
    /// The usable area inside the margins.
    pub fn usable(&self) -> (f64, f64) {
        (
            self.width - 2.0 * self.margin,
            self.height - 2.0 * self.margin,
        )
    }
}

/// What is engraved on each strip.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum LabelStyle {
    /// The full strip ID, e.g. `R03-C05-A`, with an orientation arrow.
    Id,
    /// A shorter ID, e.g. `3.5A`, with the arrow.
    Compact,
    /// Only the orientation arrow.
    None,
}

impl LabelStyle {
    pub(crate) fn parse(s: &str) -> Option<Self> {
        match s {
            "id" => Some(Self::Id),
            "compact" => Some(Self::Compact),
            "none" => Some(Self::None),
            _ => None,
        }
    }
}

/// Paper for the printed assembly guide.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Paper {
    A4,
    Letter,
}

impl Paper {
    pub(crate) fn parse(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "a4" => Some(Paper::A4),
            "letter" | "us-letter" => Some(Paper::Letter),
            _ => None,
        }
    }

    /// Width and height in mm (portrait).
    pub(crate) fn size(self) -> (f64, f64) {
        match self {
            Paper::A4 => (210.0, 297.0),
            Paper::Letter => (215.9, 279.4),
        }
    }
}

/// The validated fabrication settings of a design; lengths in mm.
#[derive(Clone, Debug, PartialEq)]
pub struct Fabrication {
    /// The strip stock.
    pub material: Material,
    /// The eyelet every hole is cut for.
    pub eyelet: Eyelet,
    /// Distance from a strip's tip to its end hole centre (>= width / 2).
    pub end_margin: f64,
    pub(crate) label: LabelStyle,
    /// Laser kerf (width of the cut).
    pub(crate) kerf: f64,
    /// Whether the cut geometry is offset by half the kerf (outlines out,
    /// holes in) or left nominal for the laser software to offset.
    pub(crate) compensate_kerf: bool,
    /// The sheet strips are nested on.
    pub sheet: SheetSpec,
    /// Paper of the assembly guide.
    pub(crate) paper: Paper,
    // Parts, test piece and colours (issue 13): one block.
    /// Strips whose length and hole pitches agree within this (mm) are one part type.
    pub part_tolerance: f64,
    /// Whether the first sheet carries the kerf and eyelet test piece.
    pub test_piece: bool,
    /// Which colour each layer of the cut files gets.
    pub(crate) colours: ColourPreset,
    // Sheet advice, cutting by assembly step and holding tabs (issue 13).
    /// `preset = "auto"`: the build nests on the smallest preset that holds
    /// the job (`sheet` is then the preset with the longest side until it does).
    pub(crate) sheet_auto: bool,
    /// Each assembly step's strips in lanes of their own, steps in order,
    /// whatever it costs (`group = "step"`).
    pub(crate) group_by_step: bool,
    /// Grouped by step where that takes no more sheets (the default; off
    /// with `group = "none"`).
    pub(crate) group_if_free: bool,
    /// Width (mm) of the uncut bridges left in each outline; 0 for none.
    pub(crate) tabs: f64,
    /// The laser the cut files' settings and the guide's safety note are for.
    pub machine: Machine,
    /// A cutting plotter instead of the laser (`[machine] preset`): the
    /// sheet is its mat, the labels go on a pen layer.
    pub plotter: Option<PlotterSetup>,
    /// The SVG without `<use>` and the DXF without blocks (`--flat`): every
    /// strip drawn in full, for importers that skip references.
    pub(crate) flat: bool,
}

impl Fabrication {
    /// The preset's starting settings on this job's machine: None when the
    /// stock has no preset, must not be lasered, or the machine cannot cut it.
    pub fn laser_settings(&self) -> Option<MachineSettings> {
        if self.plotter.is_some() {
            return None;
        }
        self.material.preset.and_then(|p| p.settings(self.machine))
    }

    /// The guide's safety note for this stock on this machine; `name` is
    /// the material's name as the page has room for it.
    pub fn safety_note(&self, name: &str) -> String {
        if let Some(p) = &self.plotter {
            return self.plotter_note(p, name);
        }
        let Some(p) = self.material.preset else {
            return format!(
                "Safety: {name} has no stock preset: check it is safe to cut on {} before you start (no PVC \
                 or vinyl, no ABS, no polycarbonate; see docs/fabrication.md), and find its settings on a scrap.",
                self.machine.describe()
            );
        };
        let settings = match (p.laser_safe, self.laser_settings()) {
            (false, _) => String::new(),
            (true, None) => format!(
                " {} cannot cut it: the cut files carry no settings for it.",
                capitalised(self.machine.describe())
            ),
            (true, Some(s)) => format!(
                " Starting settings on {}: cut at {} mm/s and {} % power ({}), mark the labels at {} mm/s \
                 and {} % ({}){}.",
                self.machine.describe(),
                s.cut.speed,
                s.cut.power,
                passes(s.cut.passes),
                s.mark.speed,
                s.mark.power,
                passes(s.mark.passes),
                if p.settings_sourced {
                    ""
                } else {
                    "; these are a starting point: try them on the test piece first"
                }
            ),
        };
        format!("Safety: {}{settings}", p.safety)
    }

    /// The note for a cutting plotter: a blade makes no fumes, so what
    /// matters is the mat, the blade and the fingers.
    fn plotter_note(&self, p: &PlotterSetup, name: &str) -> String {
        let stock = match self.material.preset {
            Some(s) => s.plotter_safety.to_string(),
            None => format!(
                "{name} has no stock preset: a blade makes no fumes, but check the stock is thin enough for the \
                 blade and cut the test piece first."
            ),
        };
        format!(
            "Safety: {stock} On {} the sheet is the {} mat ({} x {} mm cutting area): keep fingers clear of the \
             carriage while it cuts, and lift the strips off the mat with a spatula, not by bending the stock. \
             Holes under {} mm are refused: the blade tears them.",
            p.plotter.describe(),
            p.mat,
            crate::diagnostic::shown((self.sheet.width * 10.0).round() / 10.0),
            crate::diagnostic::shown((self.sheet.height * 10.0).round() / 10.0),
            crate::diagnostic::shown(p.min_hole),
        )
    }
}

fn passes(n: u32) -> String {
    if n == 1 {
        "1 pass".into()
    } else {
        format!("{n} passes")
    }
}

pub(crate) fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|f| f.to_uppercase().collect::<String>() + c.as_str())
        .unwrap_or_default()
}

/// `--sheet auto` / `preset = "auto"`.
pub(crate) const SHEET_AUTO: &str = "auto";

/// The preset with the longest usable side: what `auto` checks strips
/// against before it picks a sheet.
pub(crate) fn longest_preset() -> (&'static str, f64, f64) {
    *SHEET_PRESETS
        .iter()
        .max_by(|a, b| a.1.max(a.2).total_cmp(&b.1.max(b.2)))
        .expect("presets")
}

/// Default tolerance (mm) within which two strips are the same part.
pub(crate) const PART_TOLERANCE: f64 = 0.05;

/// Named mappings of the cut-file layers to colours.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ColourPreset {
    /// karigami's own: holes blue, outlines red, labels black, reference green.
    Karigami,
    /// The box-generator convention (boxes.py): outer cut black, inner cut
    /// blue, etching green, annotation red.
    Boxes,
}

impl ColourPreset {
    pub(crate) const ALL: [ColourPreset; 2] = [ColourPreset::Karigami, ColourPreset::Boxes];

    pub(crate) fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == s)
    }

    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Karigami => "karigami",
            Self::Boxes => "boxes",
        }
    }
}

impl Default for Fabrication {
    /// The paper's build: 1 mm ABS strips 10 mm wide, 1/8 in eyelets, on a
    /// 600 x 400 mm bed.
    fn default() -> Self {
        let (name, hole, flange) = EYELET_PRESETS[0];
        let (sname, w, h) = SHEET_PRESETS[0];
        Self {
            material: Material {
                name: default_stock().name.into(),
                preset: Some(default_stock()),
                thickness: 1.0,
                width: 10.0,
            },
            eyelet: Eyelet {
                name: name.into(),
                hole,
                flange,
            },
            end_margin: 5.0,
            label: LabelStyle::Id,
            kerf: 0.15,
            compensate_kerf: false,
            sheet: SheetSpec {
                name: sname.into(),
                width: w,
                height: h,
                margin: 5.0,
                gap: 2.0,
            },
            paper: Paper::A4,
            part_tolerance: PART_TOLERANCE,
            test_piece: true,
            colours: ColourPreset::Karigami,
            sheet_auto: false,
            group_by_step: false,
            group_if_free: true,
            tabs: 0.0,
            machine: Machine::Co2,
            plotter: None,
            flat: false,
        }
    }
}

pub(crate) fn eyelet_preset(name: &str) -> Option<Eyelet> {
    EYELET_PRESETS
        .iter()
        .find(|p| p.0 == name)
        .map(|&(n, hole, flange)| Eyelet {
            name: n.into(),
            hole,
            flange,
        })
}

/// A sheet preset by name, or `WxH` in mm (e.g. `500x300`).
pub(crate) fn sheet_size(name: &str) -> Option<(String, f64, f64)> {
    if let Some(&(n, w, h)) = SHEET_PRESETS.iter().find(|p| p.0 == name) {
        return Some((n.into(), w, h));
    }
    let (w, h) = name.split_once('x')?;
    let (w, h): (f64, f64) = (w.trim().parse().ok()?, h.trim().parse().ok()?);
    (w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0).then(|| (name.into(), w, h))
}

pub(crate) fn preset_names(presets: &[(&str, f64, f64)]) -> String {
    presets
        .iter()
        .map(|p| format!("\"{}\"", p.0))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sheet_sizes_from_presets_and_dimensions() {
        assert_eq!(sheet_size("glowforge").unwrap().1, 495.0);
        assert_eq!(
            sheet_size("500x300").unwrap(),
            ("500x300".into(), 500.0, 300.0)
        );
        assert!(sheet_size("500x").is_none());
        assert!(sheet_size("-5x3").is_none());
        assert!(sheet_size("nanx3").is_none());
    }
}
