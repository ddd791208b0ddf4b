//! karigami: grow scissor lattices from TOML recipes, verify them, and turn
//! them into fabrication files. Data flows one way:
//! design -> lattice -> parts -> layout -> drawing -> bytes.
//! Everything here is pure; only the binary touches files and the terminal.
//!
//! The modules are private; this file is the library's whole public face.
//! The main types and functions are flat (`karigami::parse`,
//! `karigami::build`, `karigami::Lattice`); a few groups whose names would
//! collide or read unclearly flat are small namespaces (`formats`,
//! `simulation`, `template`, `deploy`, `shape`). A recipe's way through:
//!
//! ```no_run
//! let source = std::fs::read_to_string("sheet.toml").unwrap();
//! let design = karigami::parse(&source, "sheet").unwrap();
//! let built = karigami::build(design).unwrap();
//! for (name, bytes) in karigami::files(&built) {
//!     println!("{name}: {} bytes", bytes.len());
//! }
//! ```

mod assembly;
mod budget;
mod design;
mod diagnostic;
mod drawing;
mod fabrication;
mod font;
mod guide;
mod hash;
mod jobs;
mod lattice;
mod layout;
mod legs;
mod measure;
mod output;
mod parts;
mod pipeline;
mod report;
mod rigid;
mod rng;
mod sim;
mod solve;
mod target;
mod templates;
mod words;
mod write;

// The pipeline's entry points: recipe text -> Design -> Build -> files,
// with the reports `check` and `build` print.
pub use output::files_on;
pub use output::{files, viewer_scene};
pub use pipeline::check_on;
pub use pipeline::{Build, Checked, Verified, build, build_with, check};
pub use pipeline::{
    MAX_FABRICATED_CELLS, build_cells, build_cost, contact, recipe_error, simulation_estimate,
};
pub use pipeline::{STATE_FILE, Unsimulated, build_unsimulated};
pub use report::{build_check_json, build_json, build_text, check_json, check_text, summary};

// Diagnostics: every error the library reports, with its kind and place.
pub use diagnostic::{Diagnostic, ErrorKind};

// How many threads the library may use, and how long it may run.
pub use budget::{DEFAULT_CEILING, Deadline, Estimate, SAY_ABOVE, Stopped, count, duration};
pub use jobs::Jobs;

// Design: the parsed recipe, its fabrication settings, and the solvers
// that search for a recipe's values.
pub use design::fit::{Coverage, Fit};
pub use design::optimise::{ClashRule, Optimise};
pub use design::{Design, MIN_WALL, Overrides, parse, parse_with};
pub use fabrication::{Eyelet, Fabrication, Material, SHEET_PRESETS, SheetSpec};
pub use fabrication::{LaserSetting, Machine, MachineSettings, STOCK_PRESETS, StockPreset};
pub use fabrication::{
    MACHINE_PRESETS, MATS, MachinePreset, PLOTTER_MIN_HOLE, Plotter, PlotterSetup,
};
pub use measure::{BUMP_DEG, Measures, Turn, measure, measure_assembled};
pub use solve::tune::{Tuned, tune_estimate, tune_helix, tune_helix_until, tune_within_time};
pub use solve::{Optimised, optimise};

// Lattice: growth from rows of parameters, the verified invariants, the
// joints, and the deployment (`deploy`) and curvature (`shape`) analyses.
pub use lattice::{
    Cell, Check as VerifyCheck, ClosureRecord, Crank, FrontMoves, Grower, GrowthError, Invariant,
    Joint, JointEnd, Kind, Lattice, PivotMove, Report as VerifyReport, Rod, RodType, RowParams,
    Saddle, Stacking, TOLERANCE, Vertex, VertexKey, grow, grow_helix, grow_sheet, joints, verify,
};
pub use lattice::{deploy, shape};
pub use legs::{Direction, Leg};

// Parts: the flat strips with their holes and markings, and the order
// they are assembled in.
pub use assembly::{Step, steps};
pub use parts::types::PartType;
pub use parts::{Marking, Outline, Parts, PartsError, Strip, parts};

// Layout: strips nested on sheets.
pub use layout::{Bounds, Layout, Placement, Sheet, nest};

// Drawing: one model of pages in millimetres that every writer reads, and
// the assembly guide drawn in it.
pub use drawing::{Align, Font, Group, Ink, Item, Layer, Page, Segment, Shape, Symbol};
pub use guide::{Guide, guide, guide_showing};

/// Bytes: one module per file format, each with its own `write`.
pub mod formats {
    pub use crate::write::{dxf, lbrn2, png, svg, viewer};
}

/// The elastic simulation of a lattice's strips (docs/physics.md): its
/// settings, the deployed equilibrium, and the search for other stable
/// shapes (`explore`).
pub mod simulation {
    pub use crate::design::simulation::{MAX_THETA, MIN_THETA};
    pub use crate::sim::results::StrainPeak;
    pub use crate::sim::{
        Actuation, Cost, DEFAULT_MEMORY, Equilibrium, Hold, LatticeModel, Material, Mesh, Reaction,
        Section, Settings, ShapeDistance, SimError, Simulation, Stats, VertexJoint, deploy,
        equilibrium, estimate, explore, kabsch_distance, path, placed_at, placed_lattice, prepare,
        resolve, seconds, section, sensitivity, shape_distance, simulate, simulate_until, states,
        supports, warm, within_memory, within_time,
    };
    /// The deployment path drawn: path.png's bytes.
    pub use crate::write::path_png::write as path_png;
}

/// Target shapes (docs/design.md): meshes and analytic families read and
/// validated, closest points, the best rigid fit of a point set, and the
/// share of a target its cells cover.
pub mod targets {
    pub use crate::target::{
        Bend, COVERED_WITHIN, Expect, Fit, MAX_TARGET_BYTES, MAX_TRIANGLES, Mesh, Rigid, Target,
        Topology, kabsch, read, recorded_path, refuse_early,
    };
}

/// The search of `karigami design`: a target in, sheets that grow onto it
/// out (docs/design.md, "Design your own object").
pub mod designing {
    pub use crate::solve::design::{
        BumpCover, DesignAsk, Found, OvalRim, POLISH_SECONDS_PER_CELL, POLISH_WORK, STUB, Searched,
        admissible, bump_top, cells_per_square, default_edge, fit_of, flattens, goal, least_edge,
        miss, polishes, recipe, search, with_feet,
    };
}

/// The starter recipes `karigami new` writes.
pub mod template {
    pub use crate::templates::{TEMPLATES, Template, find, instantiate, instantiate_as};
}

/// Small helpers the binary shares with the library; not part of its face.
#[doc(hidden)]
pub mod util {
    pub use crate::budget::reckoned_low;
    pub use crate::diagnostic::shown;
    pub use crate::hash::fnv1a;
    pub use crate::words::plural;
}

/// Internals the integration tests check directly; not part of the face.
#[doc(hidden)]
pub mod testing {
    pub use crate::design::fit;
    pub use crate::drawing::{TEST_PIECE_ID, picture, tabs, text};
    pub use crate::guide::{GAUGE_OVERLAP, eyelets_by_grip, gauge_tiles};
    pub use crate::lattice::{
        DRIFT_PER_LEG, FrontFrame, front_frame, grow_helix_partial, seed_defect,
    };
    pub use crate::layout::strip_length;
    pub use crate::parts::{DOT, clash, test_piece};
    pub use crate::pipeline::SIMULATION_SOURCES;
    pub use crate::sim::explore::perturb;

    /// The kerf the cut files' metadata records (mm).
    pub fn kerf(f: &crate::Fabrication) -> f64 {
        f.kerf
    }

    /// The stroke font the engravings and pages use.
    pub mod font {
        pub use crate::font::text;
    }
}
