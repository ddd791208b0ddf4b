//! What the fabrication tables are read against: the settings the command
//! line overrides, the physical bounds of each setting, and where each was
//! written (for errors found later). Shared by the parsing
//! (`fabrication_table.rs`) and the checks across settings
//! (`fabrication_checks.rs`).

use std::ops::Range;

/// Fabrication settings given on the command line; each replaces the
/// recipe's value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    /// A sheet preset name or `WxH` in mm.
    pub sheet: Option<String>,
    /// `--eyelet`: an eyelet preset name.
    pub eyelet: Option<String>,
    /// `--strip-width`: strip width in mm.
    pub strip_width: Option<f64>,
    /// `--kerf`: laser kerf in mm.
    pub kerf: Option<f64>,
    /// `--compensate-kerf`: Some(true) offsets the cut geometry by half the kerf.
    pub compensate_kerf: Option<bool>,
    /// `--label`: what to engrave on strips (id, compact or none).
    pub label: Option<String>,
    /// Paper of the assembly guide: a4 or letter.
    pub paper: Option<String>,
    /// `--no-test-piece`: Some(false) leaves the test piece out.
    pub test_piece: Option<bool>,
    /// `--colours`: a colour preset name.
    pub colours: Option<String>,
    /// `--group-by-step`: Some(true) keeps each step's strips together.
    pub group_by_step: Option<bool>,
    /// `--tabs`: holding tab width in mm (0 for none).
    pub tabs: Option<f64>,
    /// `--flat`: Some(true) writes the SVG and DXF without references.
    pub flat: Option<bool>,
    /// `--machine`: a machine preset (laser-co2, laser-diode, cricut, silhouette).
    pub machine: Option<String>,
    /// `--memory`: the most memory the simulation may take (bytes).
    pub memory: Option<u64>,
    /// `--time-limit`: when the run's time is up (`Design::deadline`).
    pub deadline: crate::budget::Deadline,
}

/// Where the settings were written, for errors found later (per strip).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct FabricationSpans {
    pub(crate) width: Option<Range<usize>>,
    pub(crate) eyelet: Option<Range<usize>>,
    pub(crate) end_margin: Option<Range<usize>>,
    pub(crate) sheet: Option<Range<usize>>,
    /// `laser.kerf`, when the recipe's kerf is the one used.
    pub(crate) kerf: Option<Range<usize>>,
    /// `machine.min_hole`, else `machine.preset`, when a plotter from the
    /// recipe is the machine.
    pub(crate) plotter: Option<Range<usize>>,
}

/// Thinnest wall of material kept between a hole and a strip edge or tip.
pub const MIN_WALL: f64 = 1.0;

/// The largest sheet side: beyond the beds of large-format lasers (3 x 2 m),
/// and it bounds the memory of the sheet pictures.
pub(crate) const MAX_SHEET: f64 = 5000.0;

/// The physical range of each length setting (mm): beyond these no laser
/// cuts, no stock is sold, and later arithmetic (solids, layout) would
/// lose its meaning. Sheet sides are bounded by `MAX_SHEET`.
pub(crate) const MAX_THICKNESS: f64 = 50.0;
/// The thinnest stock (mm), foil or film: thinner, a strip's bending
/// stiffness (which goes with the cube of the thickness) underflows in the
/// simulation; examples/eggbox.toml at 0.05 mm and 1 MPa still solves,
/// stable.
pub(crate) const MIN_THICKNESS: f64 = 0.05;
pub(crate) const MAX_STRIP_WIDTH: f64 = 500.0;
pub(crate) const MAX_EYELET: f64 = 100.0;
/// The narrowest eyelet hole (mm), as the test piece's smallest step: a
/// hole of 1e-300 mm was written as a circle of radius 0.
pub(crate) const MIN_HOLE: f64 = 0.5;
pub(crate) const MAX_END_MARGIN: f64 = 1000.0;
pub(crate) const MAX_KERF: f64 = 5.0;
pub(crate) const MAX_SHEET_MARGIN: f64 = 1000.0;
/// Largest tolerance for grouping strips into one part type, mm.
pub(crate) const MAX_PART_TOLERANCE: f64 = 10.0;
