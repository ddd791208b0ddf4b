//! Command-line interface. Exit codes: 0 ok, 1 design invalid or a check
//! failed, 2 usage error, 3 I/O error.

mod files;

use clap::{Args as ClapArgs, Parser, Subcommand};
use karigami::build::build as build_design;
use karigami::design::{self, Design, Overrides};
use karigami::lattice::{Lattice, verify};
use karigami::report;
use std::path::{Path, PathBuf};

pub const EXIT_INVALID: i32 = 1;
pub const EXIT_USAGE: i32 = 2;
pub const EXIT_IO: i32 = 3;

/// The design `karigami build` uses when given none.
const DEFAULT_DESIGN: &str = include_str!("../../templates/sheet.toml");

#[derive(Parser)]
#[command(
    name = "karigami",
    version,
    about = "Grow, verify and fabricate scissor lattices from TOML recipes"
)]
struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Grow a design and verify collapsibility, compatibility and the collapsed state.
    #[command(after_help = "Example:\n  karigami check examples/flat-sheet.toml")]
    Check {
        /// Recipe files (TOML).
        #[arg(required = true)]
        designs: Vec<PathBuf>,
    },
    /// Grow, verify and write the build files (lattice.json) into a folder.
    #[command(
        after_help = "Examples:\n  karigami build                      # the built-in sheet into ./karigami-out\n  karigami build examples/flat-sheet.toml --out out/flat"
    )]
    Build {
        /// Recipe file (TOML); without one, a built-in example sheet.
        design: Option<PathBuf>,
        /// Output folder. It is replaced as a whole; a folder that is not a
        /// previous karigami build is refused unless --force is given.
        #[arg(long, short, default_value = "karigami-out")]
        out: PathBuf,
        /// Replace the output folder even if it is not a previous karigami build.
        #[arg(long)]
        force: bool,
        #[command(flatten)]
        fabrication: FabricationFlags,
    },
    /// Tune a helix seed until it grows the cells the recipe asks for, and
    /// write the recipe with the tuned seed.
    #[command(
        after_help = "Example:\n  karigami tune my-bowl.toml --out my-bowl-tuned.toml\n\nThe recipe must give its seed as `points = [...]` with one kappa per edge.\nOnly the points and kappa change; comments and other settings are kept."
    )]
    Tune {
        /// Helix recipe file (TOML).
        design: PathBuf,
        /// Grow this many cells instead of the recipe's `cells`.
        #[arg(long)]
        cells: Option<usize>,
        /// Write the tuned recipe here (default: print it).
        #[arg(long, short)]
        out: Option<PathBuf>,
        /// Give up after this many tries.
        #[arg(long, default_value_t = 50_000)]
        iterations: usize,
    },
}

/// Fabrication settings that replace the recipe's.
#[derive(ClapArgs, Debug, Default)]
struct FabricationFlags {
    /// Sheet: a preset (600x400, glowforge, 12x24in, 12x20in, a3, a4) or WxH in mm.
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
}

impl FabricationFlags {
    fn overrides(&self) -> Overrides {
        Overrides {
            sheet: self.sheet.clone(),
            eyelet: self.eyelet.clone(),
            strip_width: self.strip_width,
            kerf: self.kerf,
            compensate_kerf: self.compensate_kerf.then_some(true),
            label: self.label.clone(),
            paper: self.paper.clone(),
        }
    }
}

/// Why a command stopped: already reported to the user, with an exit code.
struct Failed(i32);

pub fn run() -> i32 {
    let args = Args::parse();
    let result = match args.command {
        Command::Check { designs } => {
            // Check every design, even after one fails; report the first failure.
            let results: Vec<_> = designs.iter().map(|d| check(d)).collect();
            results.into_iter().find(Result::is_err).unwrap_or(Ok(()))
        }
        Command::Build {
            design,
            out,
            force,
            fabrication,
        } => build(design.as_deref(), &out, force, &fabrication.overrides()),
        Command::Tune {
            design,
            cells,
            out,
            iterations,
        } => tune(&design, cells, out.as_deref(), iterations),
    };
    match result {
        Ok(()) => 0,
        Err(Failed(code)) => code,
    }
}

/// A recipe as read: its text, its name for messages, its default design name.
struct Recipe {
    source: String,
    file: String,
    stem: String,
}

impl Recipe {
    fn read(path: &Path) -> Result<Self, Failed> {
        let source = files::read(path).map_err(|e| {
            eprintln!("error: cannot read {}: {e}", path.display());
            Failed(EXIT_IO)
        })?;
        Ok(Self {
            source,
            file: path.display().to_string(),
            stem: path
                .file_stem()
                .map_or("design".into(), |s| s.to_string_lossy().into_owned()),
        })
    }

    fn built_in() -> Self {
        Self {
            source: DEFAULT_DESIGN.to_string(),
            file: "(built-in sheet)".to_string(),
            stem: "karigami-sheet".to_string(),
        }
    }

    fn parse(&self, overrides: &Overrides) -> Result<Design, Failed> {
        design::parse_with(&self.source, &self.stem, overrides).map_err(|d| self.fail(&d))
    }

    /// Print a diagnostic against this recipe.
    fn fail(&self, d: &karigami::diagnostic::Diagnostic) -> Failed {
        eprint!("{}", d.render(&self.file, &self.source));
        Failed(if d.class == "usage" {
            EXIT_USAGE
        } else {
            EXIT_INVALID
        })
    }
}

fn grow(design: &Design, recipe: &Recipe) -> Result<Lattice, Failed> {
    design.grow().map_err(|d| recipe.fail(&d))
}

/// Verify a design, then run the fabrication checks and nesting (nothing
/// is written): a design a maker cannot cut is not valid either.
fn check(path: &Path) -> Result<(), Failed> {
    let recipe = Recipe::read(path)?;
    let design = recipe.parse(&Overrides::default())?;
    let lattice = grow(&design, &recipe)?;
    let report = verify(&lattice);
    print!("{}", report::check_text(&design, &lattice, &report));
    if !report.passed() {
        return Err(Failed(EXIT_INVALID));
    }
    let built = build_design(design).map_err(|d| recipe.fail(&d))?;
    print!("{}", built.summary());
    println!("result: PASS (geometry verified, every strip can be cut)");
    Ok(())
}

fn build(
    path: Option<&Path>,
    out: &Path,
    force: bool,
    overrides: &Overrides,
) -> Result<(), Failed> {
    let recipe = match path {
        Some(p) => Recipe::read(p)?,
        None => Recipe::built_in(),
    };
    let design = recipe.parse(overrides)?;
    let built = build_design(design).map_err(|d| recipe.fail(&d))?;
    let outputs = built.files();
    files::replace_dir(out, &outputs, force).map_err(|e| {
        eprintln!("error: cannot write {}: {e}", out.display());
        Failed(EXIT_IO)
    })?;
    print!("{}", built.summary());
    println!("wrote {} files to {}", outputs.len(), out.display());
    Ok(())
}

fn tune(
    path: &Path,
    cells: Option<usize>,
    out: Option<&Path>,
    iterations: usize,
) -> Result<(), Failed> {
    let recipe = Recipe::read(path)?;
    let design = recipe.parse(&Overrides::default())?;
    if design.kind != karigami::lattice::Kind::Helix {
        eprintln!(
            "error: {}: `karigami tune` tunes helix seeds; this recipe's seed is \"{}\"",
            recipe.file,
            design.kind.name()
        );
        return Err(Failed(EXIT_USAGE));
    }
    let target = cells.unwrap_or(design.helix_cells);
    // Legs shorter than the eyelet flange (plus a wall) cannot be built.
    let min_leg = design.fabrication.eyelet.flange + 2.0 * design::MIN_WALL;
    let tuned = design::tune::tune_helix(
        design.dim,
        &design.points,
        &design.kappa,
        target,
        min_leg,
        iterations,
    );
    let Some(text) = design.with_seed(&recipe.source, &tuned.points, &tuned.kappa) else {
        eprintln!(
            "error: {}: write the seed as `points = [...]` and `kappa = [...]` to tune it",
            recipe.file
        );
        return Err(Failed(EXIT_USAGE));
    };
    eprintln!(
        "tuned {} in {} tries: grows {} of {target} cells with legs of at least {min_leg:.1} mm (was {}); points moved up to {:.3} mm, kappa changed up to {:.3} mm",
        recipe.file,
        tuned.iterations,
        tuned.cells_after,
        tuned.cells_before,
        tuned.max_move,
        tuned.max_kappa_change
    );
    match out {
        Some(o) => files::write_atomic(o, text.as_bytes()).map_err(|e| {
            eprintln!("error: cannot write {}: {e}", o.display());
            Failed(EXIT_IO)
        })?,
        None => print!("{text}"),
    }
    if tuned.cells_after < target {
        eprintln!(
            "error: the tuner did not reach {target} cells: try fewer cells, more --iterations, or another start seed"
        );
        return Err(Failed(EXIT_INVALID));
    }
    Ok(())
}
