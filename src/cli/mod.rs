//! Command-line interface. Exit codes: 0 ok, 1 design invalid or a check
//! failed, 2 usage error, 3 I/O error or --out refused.

/// Print on stdout, ignoring a closed pipe (`karigami check --json | head`):
/// what was asked for has been said, and a panic would be noise.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stdout(), $($arg)*);
    }};
}
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

mod batch;
mod fault;
mod files;
mod optimise;
mod progress;
mod simulate;

use clap::{Args as ClapArgs, CommandFactory, Parser, Subcommand};
use karigami::build::{Build, assemble_with, build_with, too_large_to_fabricate};
use karigami::design::{self, Design, Overrides};
use karigami::diagnostic::Diagnostic;
use karigami::lattice::deploy::deployment;
use karigami::lattice::verify;
use karigami::{report, templates};
use progress::Progress;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub const EXIT_INVALID: i32 = 1;
pub const EXIT_USAGE: i32 = 2;
pub const EXIT_IO: i32 = 3;

/// Bounds of `karigami tune`: each try grows the helix, so a billion tries
/// would run for days; a helix of more cells than this is not tuned by
/// hand-held search.
const MAX_TUNE_ITERATIONS: u64 = 5_000_000;
const MAX_TUNE_CELLS: u64 = 100_000;

/// The design `karigami build` uses when given none.
const DEFAULT_TEMPLATE: &str = "sheet";

const EXIT_CODES: &str =
    "Exit status: 0 ok, 1 a design is invalid or fails a check, 2 usage error, 3 file error.";

#[derive(Parser)]
#[command(
    name = "karigami",
    version,
    about = "Grow, verify and fabricate scissor lattices from TOML recipes",
    after_help = "Examples:\n  karigami new my-sheet                 # a starter recipe, my-sheet.toml\n  karigami check my-sheet.toml\n  karigami build my-sheet.toml --out my-sheet\n  karigami build examples/ --out gallery --jobs 2\n\nExit status: 0 ok, 1 a design is invalid or fails a check, 2 usage error, 3 file error."
)]
struct Args {
    #[command(subcommand)]
    command: Command,
    /// Print only errors.
    #[arg(long, short, global = true, conflicts_with = "verbose")]
    quiet: bool,
    /// Print more: the full verification report of each build, fit progress.
    #[arg(long, short, global = true)]
    verbose: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate the deployed shape: strips as elastic rods joined by eyelets.
    #[command(after_help = format!("Examples:\n  karigami simulate examples/eggbox.toml\n  karigami simulate examples/mirror-arm.toml --theta 40\n  karigami simulate examples/eggbox.toml --explore 12\n\nThe model and its limits: docs/physics.md.\n\n{EXIT_CODES}"))]
    Simulate {
        /// Recipe file (TOML).
        design: PathBuf,
        /// Opening of the reference cell (cell 0) in degrees; default: the recipe's [simulation] theta, else the design's.
        #[arg(long, value_name = "DEG")]
        theta: Option<f64>,
        /// Also solve from N seeded perturbations and list the distinct stable equilibria.
        #[arg(long, value_name = "N")]
        explore: Option<usize>,
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
        #[arg(long, short, value_name = "N")]
        jobs: Option<usize>,
        /// Print a JSON report on stdout instead of text.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        fabrication: FabricationFlags,
    },
    /// Tune a helix seed until it grows the cells the recipe asks for, and
    /// write the recipe with the tuned seed.
    #[command(after_help = format!(
        "Example:\n  karigami tune my-bowl.toml --out my-bowl-tuned.toml\n\nThe recipe must give its seed as `points = [...]` with one kappa per edge.\nOnly the points and kappa change; comments and other settings are kept.\n\n{EXIT_CODES}"
    ))]
    Tune {
        /// Helix recipe file (TOML).
        design: PathBuf,
        /// Grow this many cells instead of the recipe's `cells`.
        #[arg(long, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=MAX_TUNE_CELLS))]
        cells: Option<usize>,
        /// Write the tuned recipe here (default: print it).
        #[arg(long, short)]
        out: Option<PathBuf>,
        /// Give up after this many tries (at most 5000000).
        #[arg(long, default_value_t = 50_000, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=MAX_TUNE_ITERATIONS))]
        iterations: usize,
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
struct FabricationFlags {
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
            test_piece: self.no_test_piece.then_some(false),
            colours: self.colours.clone(),
            group_by_step: self.group_by_step.then_some(true),
            tabs: self.tabs,
        }
    }
}

/// How much to print.
#[derive(Clone, Copy)]
pub struct Verbosity {
    pub quiet: bool,
    pub verbose: bool,
}

/// Why a command stopped: already reported to the user, with an exit code.
pub struct Failed(pub i32);

pub fn run() -> i32 {
    let args = match Args::try_parse() {
        Ok(args) => args,
        Err(e) if !e.use_stderr() => e.exit(),
        Err(e) => {
            // A usage error is still one JSON document when --json was asked.
            if std::env::args_os().any(|a| a == "--json") {
                let rendered = e.to_string();
                let message = rendered
                    .lines()
                    .next()
                    .unwrap_or_default()
                    .trim_start_matches("error: ")
                    .to_string();
                let _ = e.print();
                outln!(
                    "{}",
                    serde_json::to_string_pretty(&json!({
                        "status": "error",
                        "error": { "class": "usage", "message": message, "detail": e.to_string() }
                    }))
                    .expect("JSON")
                );
                return EXIT_USAGE;
            }
            e.exit()
        }
    };
    let v = Verbosity {
        quiet: args.quiet,
        verbose: args.verbose,
    };
    let result = match args.command {
        Command::Check {
            designs,
            json,
            fabrication,
        } => check(&designs, json, &fabrication.overrides(), v),
        Command::Simulate {
            design,
            theta,
            explore,
        } => simulate::simulate(&design, theta, explore, v),
        Command::Build {
            designs,
            out,
            force,
            jobs,
            json,
            fabrication,
        } => {
            let jobs = jobs
                .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
                .max(1);
            build(
                &designs,
                &out,
                force,
                jobs,
                json,
                &fabrication.overrides(),
                v,
            )
        }
        Command::Tune {
            design,
            cells,
            out,
            iterations,
        } => tune(&design, cells, out.as_deref(), iterations, v),
        Command::New {
            name,
            template,
            force,
        } => new(&name, &template, force, v),
        Command::Templates => {
            for t in templates::TEMPLATES {
                outln!("{:<8} {}", t.name, t.about);
            }
            Ok(())
        }
        Command::Completions { shell } => {
            clap_complete::generate(
                shell,
                &mut Args::command(),
                "karigami",
                &mut std::io::stdout(),
            );
            Ok(())
        }
    };
    match result {
        Ok(()) => 0,
        Err(Failed(code)) => code,
    }
}

/// A recipe as read: its text, its name for messages, its default design name.
pub struct Recipe {
    pub source: String,
    pub file: String,
    pub stem: String,
}

impl Recipe {
    pub fn read(path: &Path) -> Result<Self, RecipeError> {
        let file = path.display().to_string();
        let source = files::read(path).map_err(|e| RecipeError {
            code: EXIT_IO,
            text: format!("error: cannot read {file}: {e}\n"),
            json: json!({ "class": "io", "message": format!("cannot read {file}: {e}"), "file": file }),
        })?;
        Ok(Self {
            source,
            file,
            // The default design name reaches every output: plain text only.
            stem: files::safe_component(&stem(path)),
        })
    }

    fn built_in() -> Self {
        Self {
            source: templates::find(DEFAULT_TEMPLATE)
                .expect("the default template exists")
                .text
                .to_string(),
            file: "(built-in sheet)".to_string(),
            stem: "karigami-sheet".to_string(),
        }
    }

    pub fn parse(&self, overrides: &Overrides) -> Result<Design, RecipeError> {
        design::parse_with(&self.source, &self.stem, overrides).map_err(|d| self.error(&d))
    }

    /// A diagnostic against this recipe, rendered and as JSON.
    pub fn error(&self, d: &Diagnostic) -> RecipeError {
        let (line, column) = d.line_col(&self.source).unzip();
        RecipeError {
            code: d.kind.exit_code(),
            text: d.render(&self.file, &self.source),
            json: json!({
                "class": d.kind.name(),
                "message": d.message,
                "file": self.file,
                "line": line,
                "column": column,
                "site": d.site,
                "hint": d.hint,
            }),
        }
    }
}

/// The file name without its extension: a recipe's default design name and
/// its subfolder in a batch.
pub fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or("design".into(), |s| s.to_string_lossy().into_owned())
}

/// A recipe that failed: its exit code, the rendered error, and the error as JSON.
pub struct RecipeError {
    pub code: i32,
    pub text: String,
    pub json: Value,
}

/// Parse, grow, verify and assemble one recipe (the build and batch paths;
/// `check` goes step by step to print the report even when it fails).
pub fn run_recipe(
    recipe: &Recipe,
    overrides: &Overrides,
    progress: &mut dyn FnMut(&str),
) -> Result<Build, RecipeError> {
    let design = recipe.parse(overrides)?;
    build_with(design, progress).map_err(|d| recipe.error(&d))
}

fn check(paths: &[PathBuf], json: bool, overrides: &Overrides, v: Verbosity) -> Result<(), Failed> {
    let paths = files::recipes(paths).map_err(|e| fail(json, "usage", &e, EXIT_USAGE))?;
    let mut reports = Vec::new();
    let mut worst = 0;
    let mut bar = Progress::new(paths.len(), v.quiet || json);
    for path in &paths {
        let what = format!("checking {}", path.display());
        let (code, report) = progress::heartbeat(&what, v.quiet || json, || {
            check_one(path, json, overrides, v, &mut bar)
        });
        worst = worst.max(code);
        reports.push(report);
    }
    bar.clear();
    if json {
        outln!(
            "{}",
            serde_json::to_string_pretty(&Value::Array(reports)).expect("JSON")
        );
    }
    match worst {
        0 => Ok(()),
        code => Err(Failed(code)),
    }
}

/// Check one recipe: print its report (text unless `json`), return the exit
/// code and the JSON report.
fn check_one(
    path: &Path,
    json: bool,
    overrides: &Overrides,
    v: Verbosity,
    bar: &mut Progress,
) -> (i32, Value) {
    let file = path.display().to_string();
    let fail = |e: RecipeError, bar: &mut Progress| {
        if !json {
            bar.print(&e.text);
        }
        (
            e.code,
            json!({ "file": file, "status": "error", "error": e.json }),
        )
    };
    let recipe = match Recipe::read(path) {
        Ok(r) => r,
        Err(e) => return fail(e, bar),
    };
    let design = match recipe.parse(overrides) {
        Ok(d) => d,
        Err(e) => return fail(e, bar),
    };
    let lattice = match design.grow_with(&mut |note| fit_note(note, v, bar)) {
        Ok(l) => l,
        Err(d) => return fail(recipe.error(&d), bar),
    };
    bar.clear();
    let report = verify(&lattice);
    let deploy = deployment(&lattice);
    let check = report::check_json(&design, &lattice, &report, &deploy);
    if !json && !v.quiet {
        out!(
            "{}",
            report::check_text(&design, &lattice, &report, &deploy)
        );
    }
    if !report.passed() {
        return (
            EXIT_INVALID,
            json!({ "file": file, "status": "fail", "check": check }),
        );
    }
    if let Some(why) = too_large_to_fabricate(&design, &lattice) {
        if !json && !v.quiet {
            outln!(
                "fabrication: not checked ({})\nresult: PASS (geometry verified)",
                why.message
            );
        }
        return (0, json!({ "file": file, "status": "pass", "check": check }));
    }
    match assemble_with(design, lattice, report, deploy) {
        Ok(built) => {
            if !json && !v.quiet {
                out!("{}", built.summary());
                outln!("result: PASS (geometry verified, every strip can be cut)");
            }
            (
                0,
                json!({ "file": file, "status": "pass", "check": check, "build": report::build_json(&built) }),
            )
        }
        Err(d) => {
            let (code, mut value) = fail(recipe.error(&d), bar);
            value["check"] = check;
            (code, value)
        }
    }
}

/// A fitted row has been grown: shown in place on a terminal, as a line with --verbose.
fn fit_note(note: &str, v: Verbosity, bar: &mut Progress) {
    if v.verbose {
        eprintln!("{note}");
    } else {
        bar.note(note);
    }
}

fn usage(message: &str) -> Failed {
    eprintln!("error: {message}");
    Failed(EXIT_USAGE)
}

fn build(
    paths: &[PathBuf],
    out: &Path,
    force: bool,
    jobs: usize,
    json: bool,
    overrides: &Overrides,
    v: Verbosity,
) -> Result<(), Failed> {
    let batch = paths.len() > 1 || paths.iter().any(|p| p.is_dir());
    if batch {
        let recipes = files::recipes(paths).map_err(|e| fail(json, "usage", &e, EXIT_USAGE))?;
        return batch::build(&recipes, out, force, jobs, json, overrides, v);
    }
    let dir = open_out(out, paths, force, json, v)?;
    let recipe = match paths.first() {
        Some(p) => Recipe::read(p),
        None => Ok(Recipe::built_in()),
    };
    let started = Instant::now();
    let mut bar = Progress::new(1, v.quiet || json);
    let what = format!(
        "building {}",
        paths
            .first()
            .map_or("the built-in sheet".into(), |p| p.display().to_string())
    );
    let built = progress::heartbeat(&what, v.quiet || json, || {
        recipe.and_then(|r| run_recipe(&r, overrides, &mut |n| fit_note(n, v, &mut bar)))
    });
    bar.clear();
    let built = match built {
        Ok(b) => b,
        Err(e) => {
            eprint!("{}", e.text);
            if json {
                outln!(
                    "{}",
                    serde_json::to_string_pretty(&json!({ "status": "error", "error": e.json }))
                        .expect("JSON")
                );
            }
            return Err(Failed(e.code));
        }
    };
    let outputs = progress::heartbeat("drawing the files", v.quiet || json, || built.files());
    let written = files::Staged::new(&dir, "single").and_then(|staged| {
        staged.write("", &outputs)?;
        staged.commit()
    });
    if let Err(e) = written {
        return Err(fail(
            json,
            "io",
            &format!("cannot write {}: {e}; {}", out.display(), dir.kept()),
            EXIT_IO,
        ));
    }
    if json {
        let value = json!({
            "file": paths.first().map(|p| p.display().to_string()),
            "status": "ok",
            "out": out.display().to_string(),
            "files": outputs.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>(),
            "seconds": started.elapsed().as_secs_f64(),
            "check": report::check_json(
                &built.design,
                &built.lattice,
                &built.report,
                &built.deployment,
            ),
            "build": report::build_json(&built),
        });
        outln!("{}", serde_json::to_string_pretty(&value).expect("JSON"));
    } else if !v.quiet {
        if v.verbose {
            out!(
                "{}",
                report::check_text(
                    &built.design,
                    &built.lattice,
                    &built.report,
                    &built.deployment,
                )
            );
        }
        out!("{}", built.summary());
        outln!("wrote {} files to {}", outputs.len(), out.display());
    }
    Ok(())
}

/// Check and lock the output folder before any work; say what interrupted
/// runs left and was repaired, and what `--force` deletes.
pub fn open_out(
    out: &Path,
    inputs: &[PathBuf],
    force: bool,
    json: bool,
    v: Verbosity,
) -> Result<files::OutDir, Failed> {
    let dir = files::OutDir::open(out, inputs, force).map_err(|e| fail(json, "io", &e, EXIT_IO))?;
    if !v.quiet {
        for note in &dir.notes {
            eprintln!("note: {note}");
        }
    }
    if let Some(warning) = dir.force_warning() {
        eprintln!("{warning}");
    }
    Ok(dir)
}

/// Report a failure that has no recipe: a line on stderr and, with
/// `--json`, the one JSON document on stdout.
pub fn fail(json: bool, class: &str, message: &str, code: i32) -> Failed {
    eprintln!("error: {message}");
    if json {
        outln!(
            "{}",
            serde_json::to_string_pretty(
                &json!({ "status": "error", "error": { "class": class, "message": message } })
            )
            .expect("JSON")
        );
    }
    Failed(code)
}

fn tune(
    path: &Path,
    cells: Option<usize>,
    out: Option<&Path>,
    iterations: usize,
    v: Verbosity,
) -> Result<(), Failed> {
    let recipe = Recipe::read(path).map_err(report_error)?;
    let design = recipe.parse(&Overrides::default()).map_err(report_error)?;
    if design.optimise.is_some() {
        return optimise::run(&recipe, &design, out, v);
    }
    if design.kind != karigami::lattice::Kind::Helix {
        return Err(usage(&format!(
            "{}: `karigami tune` tunes helix seeds; this recipe's seed is \"{}\"",
            recipe.file,
            design.kind.name()
        )));
    }
    let target = cells.unwrap_or(design.helix_cells);
    // Legs shorter than the eyelet flange (plus a wall) cannot be built.
    let min_leg = design.fabrication.eyelet.flange + 2.0 * design::MIN_WALL;
    let what = format!("tuning {} (up to {iterations} tries)", recipe.file);
    let tuned = progress::heartbeat(&what, v.quiet, || {
        design::tune::tune_helix(
            design.dim,
            &design.points,
            &design.kappa,
            target,
            min_leg,
            iterations,
        )
    });
    let Some(text) = design.with_seed(&recipe.source, &tuned.points, &tuned.kappa) else {
        return Err(usage(&format!(
            "{}: write the seed as `points = [...]` and `kappa = [...]` to tune it",
            recipe.file
        )));
    };
    if !v.quiet {
        eprintln!(
            "tuned {} in {} tries: grows {} of {target} cells with legs of at least {min_leg:.1} mm (was {}); points moved up to {:.3} mm, kappa changed up to {:.3} mm",
            recipe.file,
            tuned.iterations,
            tuned.cells_after,
            tuned.cells_before,
            tuned.max_move,
            tuned.max_kappa_change
        );
    }
    // Only a seed that reached the target is written: a failed tune leaves
    // the --out file (often the recipe itself) as it was.
    if tuned.cells_after < target {
        let kept = out.map_or(String::new(), |o| {
            format!("; {} was not written", o.display())
        });
        eprintln!(
            "error: the tuner did not reach {target} cells: try fewer cells, more --iterations, or another start seed{kept}"
        );
        return Err(Failed(EXIT_INVALID));
    }
    match out {
        Some(o) => files::write_atomic(o, text.as_bytes()).map_err(|e| {
            eprintln!(
                "error: cannot write {}: {e}; it was left as it was",
                o.display()
            );
            Failed(EXIT_IO)
        })?,
        None => out!("{text}"),
    }
    Ok(())
}

fn report_error(e: RecipeError) -> Failed {
    eprint!("{}", e.text);
    Failed(e.code)
}

fn new(name: &str, template: &str, force: bool, v: Verbosity) -> Result<(), Failed> {
    let Some(t) = templates::find(template) else {
        let names: Vec<_> = templates::TEMPLATES.iter().map(|t| t.name).collect();
        return Err(usage(&format!(
            "no template \"{template}\"; there are: {}",
            names.join(", ")
        )));
    };
    let file = Path::new(name)
        .file_name()
        .map(|f| f.to_string_lossy().into_owned());
    let plain = file
        .as_deref()
        .filter(|f| !f.starts_with('.') && !f.chars().any(char::is_control) && *f != ".toml");
    if plain.is_none() || name.chars().any(char::is_control) {
        return Err(usage(&format!(
            "{name:?} is not a usable recipe name: give a name that does not start with a dot and has no control characters, such as `karigami new my-sheet`"
        )));
    }
    let path = if name.ends_with(".toml") {
        PathBuf::from(name)
    } else {
        PathBuf::from(format!("{name}.toml"))
    };
    if path.exists() && !force {
        return Err(usage(&format!(
            "{} exists; choose another name or pass --force to overwrite it",
            path.display()
        )));
    }
    let design_name = stem(&path);
    files::write_atomic(
        &path,
        templates::instantiate_as(t, &design_name, &path.display().to_string()).as_bytes(),
    )
    .map_err(|e| {
        eprintln!("error: cannot write {}: {e}", path.display());
        Failed(EXIT_IO)
    })?;
    if !v.quiet {
        outln!(
            "wrote {} from the {} template; next: karigami check {0}",
            path.display(),
            t.name
        );
    }
    Ok(())
}
