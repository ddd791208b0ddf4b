//! Real strip stock: the `[material] preset` table. Each preset carries what
//! the simulation needs (Young's modulus, allowable strain), the thickness
//! range it is sold in, whether it is safe to cut on a laser, and starting
//! laser settings per operation for the two common hobby lasers. The
//! sources of every number are in docs/fabrication.md ("Strip stock"); a
//! setting no source gives is a starting point to be tried on the test
//! piece, and says so.

/// One laser operation's settings: LightBurn's speed (mm/s), maximum power
/// (percent) and number of passes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaserSetting {
    /// Head speed (mm/s).
    pub speed: f64,
    /// Maximum power (percent of the tube or diode).
    pub power: f64,
    /// Passes over each line.
    pub passes: u32,
}

/// Settings for one kind of laser: cutting holes and outlines, and marking
/// the labels (a low-power vector score).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MachineSettings {
    /// Holes and outlines.
    pub cut: LaserSetting,
    /// Labels: a score that marks without cutting through.
    pub mark: LaserSetting,
}

/// The laser a job is set up for (`[laser] machine`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Machine {
    /// A common 40-60 W CO2 laser (10.6 um).
    Co2,
    /// A 5-10 W blue diode laser (about 450 nm).
    Diode,
}

impl Machine {
    pub(crate) const ALL: [Machine; 2] = [Machine::Co2, Machine::Diode];

    /// The recipe's name of the machine.
    pub fn name(self) -> &'static str {
        match self {
            Machine::Co2 => "co2",
            Machine::Diode => "diode",
        }
    }

    /// The machine as the guide names it.
    pub fn describe(self) -> &'static str {
        match self {
            Machine::Co2 => "a 40-60 W CO2 laser",
            Machine::Diode => "a 5-10 W diode laser",
        }
    }

    pub(crate) fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == s)
    }
}

/// A kind of strip stock a maker can buy.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StockPreset {
    /// The recipe's key (`preset = "pp"`).
    pub key: &'static str,
    /// The name printed on the guide and in the files.
    pub name: &'static str,
    /// Sheet thicknesses (mm) the strips work in: thinner ones are too
    /// floppy to hold a shape, thicker ones too stiff to bend at the joints.
    pub thickness: (f64, f64),
    /// The thickness a preset alone gives (mm).
    pub default_thickness: f64,
    /// Young's modulus (MPa) for the simulation.
    pub youngs: f64,
    /// Poisson's ratio for the simulation.
    pub poisson: f64,
    /// Allowable corner-fibre strain (fraction) the report judges against.
    pub allowable_strain: f64,
    /// Whether the stock may be cut on a laser at all.
    pub laser_safe: bool,
    /// What to know before cutting it: fumes, fire, what works instead.
    pub safety: &'static str,
    /// What to know before cutting it on a cutting plotter: the blade and
    /// the mat (a blade makes no fumes).
    pub plotter_safety: &'static str,
    /// Starting settings on a CO2 laser, None where it must not be lasered.
    pub co2: Option<MachineSettings>,
    /// Starting settings on a diode laser, None where a diode cannot cut it.
    pub diode: Option<MachineSettings>,
    /// Whether `co2`/`diode` are sourced figures (false: a starting point,
    /// to be tried on the test piece first).
    pub settings_sourced: bool,
}

impl StockPreset {
    /// The settings for a machine, if the stock may and can be cut on it.
    pub fn settings(&self, machine: Machine) -> Option<MachineSettings> {
        match machine {
            Machine::Co2 => self.co2,
            Machine::Diode => self.diode,
        }
    }
}

const fn setting(speed: f64, power: f64, passes: u32) -> LaserSetting {
    LaserSetting {
        speed,
        power,
        passes,
    }
}

/// The stock presets. ABS first: the paper's models are ABS, and it stays
/// the simulation's default, but it is on makerspace do-not-cut lists.
pub const STOCK_PRESETS: &[StockPreset] = &[
    StockPreset {
        key: "abs",
        name: "ABS",
        thickness: (0.5, 1.5),
        default_thickness: 1.0,
        youngs: 2200.0,
        poisson: 0.35,
        allowable_strain: 0.015,
        laser_safe: false,
        safety: "ABS must not be cut on a laser: it melts instead of vaporising, catches fire easily and its \
                 fumes contain hydrogen cyanide (makerspace do-not-cut lists; ABS safety data sheets list \
                 hydrogen cyanide among its combustion products). Cut ABS on a cutting plotter or by hand, or \
                 build with a laser-safe stock such as preset \"pp\" or \"petg\".",
        plotter_safety: "ABS is safe to cut on a cutting plotter: a blade makes no fumes. Cut thin sheet (0.5 mm; thicker ABS \
                         takes several passes, or a Cricut Maker's knife blade), hold it on a strong-grip mat, and cut \
                         the test piece first to set the blade depth and the passes.",
        co2: None,
        diode: None,
        settings_sourced: false,
    },
    StockPreset {
        key: "pp",
        name: "polypropylene (PP)",
        thickness: (0.5, 1.5),
        default_thickness: 0.8,
        youngs: 1300.0,
        poisson: 0.42,
        allowable_strain: 0.02,
        laser_safe: true,
        safety: "Polypropylene cuts on a CO2 laser with a slightly melted edge; keep air assist and extraction \
                 on and never leave the laser running unwatched (thin plastic can flame). Solid sheet only: \
                 polypropylene foam is on do-not-cut lists. A diode laser's blue light passes through natural \
                 and clear polypropylene: use a CO2 laser.",
        plotter_safety: "Polypropylene is safe to cut on a cutting plotter: a blade makes no fumes. It is slippery: use a \
                         strong-grip mat and thin sheet (0.5 mm), and cut the test piece first to set the blade depth \
                         and the passes.",
        co2: Some(MachineSettings {
            cut: setting(15.0, 40.0, 1),
            mark: setting(100.0, 12.0, 1),
        }),
        diode: None,
        settings_sourced: false,
    },
    StockPreset {
        key: "pom",
        name: "acetal (POM, Delrin)",
        thickness: (0.5, 1.0),
        default_thickness: 0.5,
        youngs: 2900.0,
        poisson: 0.35,
        allowable_strain: 0.016,
        laser_safe: true,
        safety: "Acetal cuts cleanly on a CO2 laser but gives off formaldehyde: run the extraction to the \
                 outside, keep the lid closed until the fumes clear, and never leave the laser unwatched. A \
                 diode laser does not cut white acetal: use a CO2 laser.",
        plotter_safety: "Acetal is safe to cut on a cutting plotter: the formaldehyde comes from lasering it, and a blade \
                         makes no fumes. Use thin sheet (0.5 mm) on a strong-grip mat, and cut the test piece first to \
                         set the blade depth and the passes.",
        co2: Some(MachineSettings {
            cut: setting(12.0, 45.0, 1),
            mark: setting(100.0, 12.0, 1),
        }),
        diode: None,
        settings_sourced: false,
    },
    StockPreset {
        key: "petg",
        name: "PETG",
        thickness: (0.5, 1.0),
        default_thickness: 0.75,
        youngs: 2200.0,
        poisson: 0.38,
        allowable_strain: 0.019,
        laser_safe: true,
        safety: "PETG cuts on a CO2 laser with a melted edge; keep air assist and extraction on and never \
                 leave the laser running unwatched. A diode laser's blue light passes through clear PETG: \
                 use a CO2 laser.",
        plotter_safety: "PETG is safe to cut on a cutting plotter: a blade makes no fumes. Use thin sheet (0.5 mm) on a \
                         strong-grip mat, and cut the test piece first to set the blade depth and the passes.",
        co2: Some(MachineSettings {
            cut: setting(15.0, 40.0, 1),
            mark: setting(100.0, 12.0, 1),
        }),
        diode: None,
        settings_sourced: false,
    },
    StockPreset {
        key: "pet-film",
        name: "polyester film (PET, Mylar)",
        thickness: (0.25, 0.5),
        default_thickness: 0.35,
        youngs: 4800.0,
        poisson: 0.38,
        allowable_strain: 0.016,
        laser_safe: true,
        safety: "Polyester film cuts on a CO2 laser at low power; weigh it flat, keep extraction on and never \
                 leave the laser unwatched. Clear film does not absorb a diode laser's light: use a CO2 laser \
                 or a cutting plotter.",
        plotter_safety: "Polyester film is safe to cut on a cutting plotter and cuts cleanly: a standard-grip mat and the \
                         fine-point blade, and cut the test piece first to set the blade depth.",
        co2: Some(MachineSettings {
            cut: setting(30.0, 20.0, 1),
            mark: setting(150.0, 8.0, 1),
        }),
        diode: None,
        settings_sourced: false,
    },
    StockPreset {
        key: "card",
        name: "card (prototypes)",
        thickness: (0.3, 0.6),
        default_thickness: 0.4,
        youngs: 3000.0,
        poisson: 0.3,
        allowable_strain: 0.008,
        laser_safe: true,
        safety: "Card cuts on any laser but burns: use air assist, keep the bed clean of scraps and never \
                 leave the laser unwatched. Card creases instead of bending back: it is for trying a design \
                 out, not for a piece that opens and closes often.",
        plotter_safety: "Card is safe to cut on a cutting plotter: a standard-grip mat and the fine-point blade. Card creases \
                         instead of bending back: it is for trying a design out, not for a piece that opens and closes \
                         often.",
        co2: Some(MachineSettings {
            cut: setting(30.0, 20.0, 1),
            mark: setting(150.0, 8.0, 1),
        }),
        diode: Some(MachineSettings {
            cut: setting(10.0, 100.0, 2),
            mark: setting(50.0, 20.0, 1),
        }),
        settings_sourced: false,
    },
];

/// A stock preset by its key.
pub(crate) fn stock_preset(key: &str) -> Option<&'static StockPreset> {
    STOCK_PRESETS.iter().find(|p| p.key == key)
}

/// The stock the paper's models and every recipe without a preset use.
pub(crate) fn default_stock() -> &'static StockPreset {
    &STOCK_PRESETS[0]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_unique_and_in_range() {
        for (i, p) in STOCK_PRESETS.iter().enumerate() {
            assert!(STOCK_PRESETS[..i].iter().all(|q| q.key != p.key));
            assert!(p.thickness.0 <= p.default_thickness && p.default_thickness <= p.thickness.1);
            assert!(p.youngs > 0.0 && (0.0..0.5).contains(&p.poisson));
            assert!(p.allowable_strain > 0.0 && p.allowable_strain < 0.1);
            // Unsafe stock has no laser settings; safe stock has CO2 ones.
            assert_eq!(p.co2.is_some(), p.laser_safe, "{}", p.key);
            assert!(p.laser_safe || p.diode.is_none());
            for m in Machine::ALL {
                if let Some(s) = p.settings(m) {
                    for op in [s.cut, s.mark] {
                        assert!(op.speed > 0.0 && (0.0..=100.0).contains(&op.power));
                        assert!(op.passes >= 1);
                    }
                    assert!(s.mark.power < s.cut.power, "a mark must not cut through");
                }
            }
        }
        assert_eq!(default_stock().key, "abs");
        assert_eq!(stock_preset("pp").unwrap().name, "polypropylene (PP)");
        assert!(stock_preset("PVC").is_none());
    }
}
