//! The command line's schema: commands, flags and their help.

use clap::{Args as ClapArgs, Parser, Subcommand};
use karigami::Overrides;
use std::path::PathBuf;

/// Bounds of `karigami tune`: each try grows the helix, so a billion tries
/// would run for days; a helix of more cells than this is not tuned by
/// hand-held search.
pub(super) const MAX_TUNE_ITERATIONS: u64 = 5_000_000;
pub(super) const MAX_TUNE_CELLS: u64 = 100_000;

/// `--jobs N`: at least 1 (0 would run nothing, or be read as "all"),
/// at most `MAX_JOBS` threads.
fn jobs() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::<usize>::new().range(1..=MAX_JOBS)
}
const MAX_JOBS: u64 = 1024;

/// `--time-limit SECONDS` (docs/commands.md, "Time limits"): more than 0,
/// at most a year.
pub(super) fn seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(t) if t > 0.0 && t <= 3.2e7 => Ok(t),
        _ => Err("must be a number of seconds, more than 0 and at most 32000000".into()),
    }
}

/// The design `karigami build` uses when given none.
pub(super) const DEFAULT_TEMPLATE: &str = "sheet";

const EXIT_CODES: &str = "Exit status: 0 ok, 1 a design is invalid or fails a check, 2 usage error, 3 file error, 4 stopped at --time-limit.";

#[derive(Parser)]
#[command(
    name = "karigami",
    version,
    about = "Grow, verify and fabricate scissor lattices from TOML recipes",
    after_help = "Examples:\n  karigami new my-sheet                 # a starter recipe, my-sheet.toml\n  karigami check my-sheet.toml\n  karigami build my-sheet.toml --out my-sheet\n  karigami build examples/ --out gallery --jobs 2\n\nExit status: 0 ok, 1 a design is invalid or fails a check, 2 usage error, 3 file error, 4 stopped at --time-limit."
)]
pub(super) struct Args {
    #[command(subcommand)]
    pub command: Command,
    /// Print only errors.
    #[arg(long, short, global = true, conflicts_with = "verbose")]
    pub quiet: bool,
    /// Print more: the full verification report of each build, fit progress.
    #[arg(long, short, global = true)]
    pub verbose: bool,
}

#[derive(Subcommand)]
pub(super) enum Command {
    /// Simulate the deployed shape: strips as elastic rods joined by eyelets.
    #[command(after_help = format!("Examples:\n  karigami simulate examples/eggbox.toml\n  karigami simulate examples/mirror-arm.toml --theta 40\n  karigami simulate examples/eggbox.toml --explore 12\n  karigami simulate examples/saddle-ring.toml --path\n\nThe model and its limits: docs/physics.md.\n\n{EXIT_CODES}"))]
    Simulate {
        /// Recipe file (TOML).
        design: PathBuf,
        /// Opening held, in degrees: the mean of all cells' openings, or the first cell's with `[simulation] actuation = "first-cell"`; default: the recipe's [simulation] theta, else the design's.
        #[arg(long, value_name = "DEG")]
        theta: Option<f64>,
        /// Also solve from N seeded perturbations and list the distinct stable equilibria.
        #[arg(long, value_name = "N")]
        explore: Option<usize>,
        /// Also follow the deployment path: from the equilibrium down to nearly collapsed and back, with the energy, the largest strain and snap-throughs at every step.
        #[arg(long)]
        path: bool,
        /// Starts of --explore solved at once (default: all cores). The report does not depend on it.
        #[arg(long, short, value_name = "N", value_parser = jobs())]
        jobs: Option<usize>,
        /// The most memory the simulation may take, in MB (default 2048): a
        /// finer mesh is refused before it is made.
        #[arg(long, value_name = "MB", value_parser = clap::value_parser!(u64).range(16..=1_048_576))]
        memory: Option<u64>,
        /// Stop cleanly after this many seconds, writing nothing half-done (exit status 4); work estimated longer is refused up front (default ceiling 3600).
        #[arg(long, value_name = "SECONDS", value_parser = seconds)]
        time_limit: Option<f64>,
    },
    /// Grow designs and verify collapsibility, compatibility, the collapsed
    /// state and that every strip can be cut. Writes nothing.
    #[command(after_help = format!("Examples:\n  karigami check examples/flat-sheet.toml\n  karigami check examples/          # every recipe in the folder\n  karigami check my.toml --json     # a machine-readable report\n\n{EXIT_CODES}"))]
    Check {
        /// Recipe files (TOML) or folders of them.
        #[arg(required = true)]
        designs: Vec<PathBuf>,
        /// Print a JSON report on stdout instead of text.
        #[arg(long)]
        json: bool,
        /// A target shape (.obj, .stl, or .toml with a [target] table): report how well the design and its simulated shape fit it (docs/design.md).
        #[arg(long, value_name = "FILE")]
        target: Option<PathBuf>,
        /// A build folder of these recipes (`build --out DIR`): each one's simulated shape is restored from it when nothing the simulation depends on changed, else solved (docs/commands.md).
        #[arg(long, value_name = "DIR")]
        reuse: Option<PathBuf>,
        #[command(flatten)]
        fabrication: FabricationFlags,
    },
    /// Grow, verify and write the cut files, assembly guide and previews.
    #[command(after_help = format!(
        "Examples:\n  karigami build                          # the built-in sheet into ./karigami-out\n  karigami build examples/flat-sheet.toml --out out/flat\n  karigami build examples/ --out gallery  # a batch: gallery/<recipe>/ for each\n  karigami build a.toml b.toml --jobs 1 --json\n\nOne recipe builds into --out itself. Several recipes, or a folder, build\ninto a subfolder of --out each, named after the recipe file; --out then\nholds batch.json, the status of every recipe. A failing recipe does not\nstop the others. The output folder is always replaced as a whole, and\nonly once everything is written, so a kill or a full disk leaves the old\nbuild; a folder that is not a karigami build (no .karigami-build marker)\nis refused unless --force is given, which lists what it deletes, and a\nfolder holding an input recipe is always refused.\n\n{EXIT_CODES}"
    ))]
    Build {
        /// Recipe files (TOML) or folders of them; without any, a built-in sheet.
        designs: Vec<PathBuf>,
        /// Output folder, replaced as a whole.
        #[arg(long, short, default_value = "karigami-out")]
        out: PathBuf,
        /// Replace the output folder even if it is not a previous karigami build.
        #[arg(long)]
        force: bool,
        /// Recipes built at once (default: all cores). The files do not depend on it.
        #[arg(long, short, value_name = "N", value_parser = jobs())]
        jobs: Option<usize>,
        /// Print a JSON report on stdout instead of text.
        #[arg(long)]
        json: bool,
        /// A target shape (.obj, .stl, or .toml with a [target] table): report.txt says how well the design and its simulated shape fit it (one recipe only; docs/design.md).
        #[arg(long, value_name = "FILE")]
        target: Option<PathBuf>,
        #[command(flatten)]
        fabrication: FabricationFlags,
    },
    /// Tune a recipe and write it back: a helix seed until it grows the cells
    /// the recipe asks for, or, with an [optimise] table, the variables it
    /// frees for its objectives and hard constraints.
    #[command(after_help = format!(
        "Examples:\n  karigami tune my-bowl.toml --out my-bowl-tuned.toml\n  karigami tune examples/eggbox.toml --out eggbox-tuned.toml\n\nA helix recipe must give its seed as `points = [...]` with one kappa per edge.\nWith [optimise], `[optimise.target] shape = \"simulated\"` aims the curvature objective at the\nsimulated deployed shape (each design tried is simulated: keep the budget small; docs/recipe.md).\nOnly the tuned values change; comments and other settings are kept.\n\n{EXIT_CODES}"
    ))]
    Tune {
        /// Recipe file (TOML): a helix seed, or a recipe with an [optimise] table.
        design: PathBuf,
        /// Grow this many cells instead of the recipe's `cells`.
        #[arg(long, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=MAX_TUNE_CELLS))]
        cells: Option<usize>,
        /// Write the tuned recipe here (default: print it); an existing file other than the recipe only with --force, never a link.
        #[arg(long, short)]
        out: Option<PathBuf>,
        /// Give up after this many tries (at most 5000000).
        #[arg(long, default_value_t = 50_000, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=MAX_TUNE_ITERATIONS))]
        iterations: usize,
        /// Designs of `method = "evolution"` costed at once (default: all cores). The result does not depend on it.
        #[arg(long, short, value_name = "N", value_parser = jobs())]
        jobs: Option<usize>,
        /// Overwrite an existing --out file (the recipe itself is written back unless edited meanwhile).
        #[arg(long, requires = "out")]
        force: bool,
        /// Stop cleanly after this many seconds, writing nothing half-done (exit status 4); work estimated longer is refused up front (default ceiling 3600).
        #[arg(long, value_name = "SECONDS", value_parser = seconds)]
        time_limit: Option<f64>,
    },
    /// Design a recipe for a target shape: a mesh (.obj, .stl) or a [target] table (docs/design.md).
    #[command(after_help = format!(
        "Examples:\n  karigami design fixtures/targets/sphere-cap.toml --out cap.toml\n  karigami design bump.stl --out bump.toml --edge 50 --time-limit 120\n\n{EXIT_CODES}"
    ))]
    Design {
        /// The target: .obj, .stl, or .toml with a [target] table.
        target: PathBuf,
        /// Write the recipe here.
        #[arg(long, short)]
        out: PathBuf,
        /// Preferred cell edge in mm (default: six strip widths, and four of the eyelets' shortest leg).
        #[arg(long, value_name = "MM")]
        edge: Option<f64>,
        /// Seeds grown at once (default: all cores). The result does not depend on it.
        #[arg(long, short, value_name = "N", value_parser = jobs())]
        jobs: Option<usize>,
        /// Strip thickness in mm (default: the material's, 1.0 mm of ABS); written into the recipe's [material] table.
        #[arg(long, value_name = "MM")]
        thickness: Option<f64>,
        /// Write the best design even when its simulated shape misses the goal, the miss stated at the top of the recipe (docs/design.md, "The goal"); without it such a design is refused.
        #[arg(long)]
        keep_miss: bool,
        /// Overwrite an existing --out file.
        #[arg(long)]
        force: bool,
        #[command(flatten)]
        fabrication: FabricationFlags,
    },
    /// Write a starter recipe from a template.
    #[command(after_help = format!(
        "Examples:\n  karigami new my-sheet                   # writes my-sheet.toml\n  karigami new arm --template chain\n  karigami templates                      # what there is\n\n{EXIT_CODES}"
    ))]
    New {
        /// Name of the design; the recipe is NAME.toml (or NAME if it ends in .toml).
        name: String,
        /// Which template (see `karigami templates`).
        #[arg(long, short, default_value = DEFAULT_TEMPLATE)]
        template: String,
        /// Overwrite an existing file.
        #[arg(long)]
        force: bool,
    },
    /// List the templates of `karigami new`.
    #[command(after_help = "Example:\n  karigami templates")]
    Templates,
    /// Print a shell completion script.
    #[command(
        after_help = "Examples:\n  karigami completions bash > ~/.local/share/bash-completion/completions/karigami\n  karigami completions zsh > ~/.zfunc/_karigami\n  karigami completions fish > ~/.config/fish/completions/karigami.fish"
    )]
    Completions { shell: clap_complete::Shell },
}

/// Fabrication settings that replace the recipe's.
#[derive(ClapArgs, Debug, Default)]
pub(super) struct FabricationFlags {
    /// Sheet: a preset (600x400, glowforge, 12x24in, 12x20in, a3, a4), WxH in mm,
    /// or auto (the smallest preset that holds the job: fewest sheets, then least area).
    #[arg(long)]
    sheet: Option<String>,
    /// Eyelet preset: 1/8in, 5/32in or 3/16in.
    #[arg(long)]
    eyelet: Option<String>,
    /// Strip width in mm.
    #[arg(long, value_name = "MM")]
    strip_width: Option<f64>,
    /// Laser kerf in mm.
    #[arg(long, value_name = "MM")]
    kerf: Option<f64>,
    /// Offset the cut geometry by half the kerf (instead of leaving it nominal).
    #[arg(long)]
    compensate_kerf: bool,
    /// What to engrave on strips: id, compact or none.
    #[arg(long)]
    label: Option<String>,
    /// Paper of the assembly guide: a4 or letter.
    #[arg(long)]
    paper: Option<String>,
    /// Leave the kerf and eyelet test piece off the first sheet.
    #[arg(long)]
    no_test_piece: bool,
    /// Cut-file colours: karigami (outlines red) or boxes (outlines black, as box generators use).
    #[arg(long, value_name = "PRESET", visible_alias = "colors")]
    colours: Option<String>,
    /// Keep each assembly step's strips together: lanes of their own, steps in order.
    #[arg(long)]
    group_by_step: bool,
    /// Leave holding tabs of this width (mm) uncut in each outline, so the
    /// cut sheet holds its strips like a parts tray (0: none).
    #[arg(long, value_name = "MM")]
    tabs: Option<f64>,
    /// Write the SVG without <use> and the DXF without blocks: every strip
    /// drawn in full, for importers that skip references.
    #[arg(long)]
    flat: bool,
    /// The most memory the simulation may take, in MB (default 2048): a
    /// finer mesh is refused before it is made.
    #[arg(long, value_name = "MB", value_parser = clap::value_parser!(u64).range(16..=1_048_576))]
    memory: Option<u64>,
    /// Machine preset: laser-co2 (default), laser-diode, or a cutting plotter,
    /// cricut or silhouette (the sheet is its mat: --sheet 12x12in or 12x24in).
    #[arg(long, value_name = "PRESET")]
    machine: Option<String>,
    /// Stop cleanly after this many seconds, writing nothing half-done (exit status 4); work estimated longer is refused up front (default ceiling 3600).
    #[arg(long, value_name = "SECONDS", value_parser = seconds)]
    time_limit: Option<f64>,
}

impl FabricationFlags {
    /// The flags given, as a command line writes them (for the record
    /// `karigami design` keeps in its recipe).
    pub(super) fn given(&self) -> Vec<String> {
        let text = [
            ("--sheet", self.sheet.clone()),
            ("--eyelet", self.eyelet.clone()),
            ("--strip-width", self.strip_width.map(|x| x.to_string())),
            ("--kerf", self.kerf.map(|x| x.to_string())),
            ("--label", self.label.clone()),
            ("--paper", self.paper.clone()),
            ("--colours", self.colours.clone()),
            ("--tabs", self.tabs.map(|x| x.to_string())),
            ("--memory", self.memory.map(|x| x.to_string())),
            ("--machine", self.machine.clone()),
            ("--time-limit", self.time_limit.map(|x| x.to_string())),
        ];
        let switches = [
            ("--compensate-kerf", self.compensate_kerf),
            ("--no-test-piece", self.no_test_piece),
            ("--group-by-step", self.group_by_step),
            ("--flat", self.flat),
        ];
        let mut out: Vec<String> = text
            .into_iter()
            .filter_map(|(flag, v)| v.map(|v| format!("{flag} {v}")))
            .collect();
        out.extend(
            switches
                .into_iter()
                .filter(|s| s.1)
                .map(|s| s.0.to_string()),
        );
        out
    }

    pub(super) fn overrides(&self) -> Overrides {
        Overrides {
            sheet: self.sheet.clone(),
            eyelet: self.eyelet.clone(),
            strip_width: self.strip_width,
            kerf: self.kerf,
            compensate_kerf: self.compensate_kerf.then_some(true),
            label: self.label.clone(),
            paper: self.paper.clone(),
            test_piece: self.no_test_piece.then_some(false),
            colours: self.colours.clone(),
            group_by_step: self.group_by_step.then_some(true),
            tabs: self.tabs,
            flat: self.flat.then_some(true),
            memory: self.memory.map(|mb| mb << 20),
            machine: self.machine.clone(),
            deadline: deadline(self.time_limit),
        }
    }
}

/// The run's deadline from `--time-limit`, started now.
pub(super) fn deadline(limit: Option<f64>) -> karigami::Deadline {
    limit.map_or(karigami::Deadline::none(), karigami::Deadline::after)
}

/// How much to print.
#[derive(Clone, Copy)]
pub(super) struct Verbosity {
    pub quiet: bool,
    pub verbose: bool,
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// clap checks the schema only when a subcommand is parsed: two flags of
    /// one name (a command's own and a flattened group's) would panic then.
    #[test]
    fn every_subcommand_schema_is_consistent() {
        super::Args::command().debug_assert();
    }
}
