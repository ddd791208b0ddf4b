//! Command-line interface. Exit codes: 0 ok, 1 design invalid or a check
//! failed, 2 usage error, 3 I/O error.

mod files;

use clap::{Parser, Subcommand};
use karigami::design::{self, Design};
use karigami::lattice::{Lattice, verify};
use karigami::report;
use karigami::write::lattice_json;
use std::path::{Path, PathBuf};

pub const EXIT_INVALID: i32 = 1;
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
        /// Output folder.
        #[arg(long, short, default_value = "karigami-out")]
        out: PathBuf,
    },
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
        Command::Build { design, out } => build(design.as_deref(), &out),
    };
    match result {
        Ok(()) => 0,
        Err(Failed(code)) => code,
    }
}

/// A recipe read and parsed, or the error already printed.
fn load(path: &Path) -> Result<Design, Failed> {
    let source = files::read(path).map_err(|e| {
        eprintln!("error: cannot read {}: {e}", path.display());
        Failed(EXIT_IO)
    })?;
    let stem = path
        .file_stem()
        .map_or("design".into(), |s| s.to_string_lossy().into_owned());
    parse(&source, &stem, &path.display().to_string())
}

fn parse(source: &str, name: &str, file: &str) -> Result<Design, Failed> {
    design::parse(source, name).map_err(|d| {
        eprint!("{}", d.render(file, source));
        Failed(EXIT_INVALID)
    })
}

fn grow(design: &Design, file: &str, source: &str) -> Result<Lattice, Failed> {
    design.grow().map_err(|d| {
        eprint!("{}", d.render(file, source));
        Failed(EXIT_INVALID)
    })
}

fn check(path: &Path) -> Result<(), Failed> {
    let design = load(path)?;
    let source = files::read(path).unwrap_or_default();
    let lattice = grow(&design, &path.display().to_string(), &source)?;
    let report = verify(&lattice);
    print!("{}", report::check_text(&design, &lattice, &report));
    if report.passed() {
        Ok(())
    } else {
        Err(Failed(EXIT_INVALID))
    }
}

fn build(path: Option<&Path>, out: &Path) -> Result<(), Failed> {
    let (design, source, file) = match path {
        Some(p) => {
            let design = load(p)?;
            (
                design,
                files::read(p).unwrap_or_default(),
                p.display().to_string(),
            )
        }
        None => {
            let file = "(built-in sheet)".to_string();
            (
                parse(DEFAULT_DESIGN, "karigami-sheet", &file)?,
                DEFAULT_DESIGN.to_string(),
                file,
            )
        }
    };
    let lattice = grow(&design, &file, &source)?;
    let report = verify(&lattice);
    if !report.passed() {
        print!("{}", report::check_text(&design, &lattice, &report));
        eprintln!("error: {file} failed verification; nothing written");
        return Err(Failed(EXIT_INVALID));
    }
    let io = |e: std::io::Error| {
        eprintln!("error: cannot write into {}: {e}", out.display());
        Failed(EXIT_IO)
    };
    files::create_dir(out).map_err(io)?;
    files::write_atomic(&out.join("lattice.json"), &lattice_json::write(&lattice)).map_err(io)?;
    println!(
        "built {}: {} cells, {} rods -> {}",
        design.name,
        lattice.cells.len(),
        2 * lattice.cells.len(),
        out.join("lattice.json").display()
    );
    Ok(())
}
