//! Command-line interface: the only layer that reads and writes files.
//! Exit codes: 0 ok, 1 design invalid or a check failed, 2 usage error,
//! 3 I/O error or --out refused (`ErrorKind::exit_code`).
//!
//! `args` is the clap schema, `error` the one error type and the JSON
//! reports' printing, `recipe` reads recipes; one file per command
//! (`check`, `build` and `batch`, `tune` and `optimise`, `simulate`,
//! `new`); `files` owns every write, `progress` the terminal.

/// Print on stdout (`console`: a closed pipe is ignored, any other
/// failure fails the run).
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let written = write!(std::io::stdout(), $($arg)*);
        $crate::cli::console::noted(written, $crate::cli::console::Stream::Out);
    }};
}
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let written = writeln!(std::io::stdout(), $($arg)*);
        $crate::cli::console::noted(written, $crate::cli::console::Stream::Out);
    }};
}
/// Print on stderr, likewise (where `eprintln!` would panic).
macro_rules! err {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let written = write!(std::io::stderr(), $($arg)*);
        $crate::cli::console::noted(written, $crate::cli::console::Stream::Err);
    }};
}
macro_rules! errln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let written = writeln!(std::io::stderr(), $($arg)*);
        $crate::cli::console::noted(written, $crate::cli::console::Stream::Err);
    }};
}

mod args;
mod batch;
mod build;
mod check;
mod console;
mod design;
mod error;
mod files;
mod interrupt;
mod new;
mod optimise;
mod progress;
mod recipe;
mod simulate;
mod stages;
mod tune;

use args::{Args, Command, Verbosity};
use clap::{CommandFactory, Parser};
use error::{Error, ErrorJson};
use karigami::ErrorKind;

pub(crate) fn run() -> i32 {
    interrupt::start();
    files::start();
    let code = run_command();
    console::exit_code(code)
}

/// A usage error from clap: its own text, or one JSON document when
/// `--json` was asked.
fn usage_error(e: &clap::Error) -> i32 {
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
        let error = Error {
            kind: ErrorKind::Usage,
            text: String::new(),
            json: Some(Box::new(ErrorJson::Plain {
                class: ErrorKind::Usage.name(),
                message,
                file: None,
                detail: Some(rendered),
            })),
        };
        error.report(true);
        return error.exit_code();
    }
    e.exit()
}

fn run_command() -> i32 {
    let args = match Args::try_parse() {
        Ok(args) => args,
        // --help and --version, on stdout.
        Err(e) if !e.use_stderr() => {
            console::noted(e.print(), console::Stream::Out);
            return e.exit_code();
        }
        Err(e) => return usage_error(&e),
    };
    // Commands with --json print every error as their one JSON document.
    let json = matches!(
        args.command,
        Command::Check { json: true, .. } | Command::Build { json: true, .. }
    );
    let v = Verbosity {
        quiet: args.quiet,
        verbose: args.verbose,
    };
    let result = match args.command {
        Command::Check {
            designs,
            json,
            target,
            reuse,
            fabrication,
        } => check::check(
            &designs,
            check::Asked {
                json,
                target: target.as_deref(),
                reuse: reuse.as_deref(),
            },
            &fabrication.overrides(),
            v,
        ),
        Command::Simulate {
            design,
            theta,
            explore,
            path,
            jobs,
            memory,
            time_limit,
        } => simulate::simulate(
            &design,
            theta,
            explore,
            path,
            (jobs_or_cores(jobs), memory, args::deadline(time_limit)),
            v,
        ),
        Command::Build {
            designs,
            out,
            force,
            jobs,
            json,
            target,
            fabrication,
        } => {
            let jobs = jobs_or_cores(jobs);
            let overrides = fabrication.overrides();
            // Several recipes, or a folder, build as a batch.
            let batch = designs.len() > 1 || designs.iter().any(|p| p.is_dir());
            if batch && target.is_some() {
                Err(Error::usage(
                    "--target is for one recipe: build each recipe with its own target",
                ))
            } else if batch {
                files::recipes(&designs).and_then(|recipes| {
                    batch::build(&recipes, &out, force, jobs, json, &overrides, v)
                })
            } else {
                let run = build::Run {
                    jobs,
                    json,
                    target: target.as_deref(),
                };
                build::build(&designs, &out, force, run, &overrides, v)
            }
        }
        Command::Design {
            target,
            out,
            edge,
            jobs,
            thickness,
            keep_miss,
            force,
            fabrication,
        } => design::design(
            &design::Ask {
                target: &target,
                out: &out,
                force,
                edge,
                thickness,
                keep_miss,
                overrides: fabrication.overrides(),
                flags: fabrication.given(),
                jobs: jobs_or_cores(jobs),
            },
            v,
        ),
        Command::Tune {
            design,
            cells,
            out,
            iterations,
            jobs,
            force,
            time_limit,
        } => tune::tune(
            &design,
            cells,
            out.as_deref().map(|o| (o, force)),
            iterations,
            (jobs_or_cores(jobs), args::deadline(time_limit)),
            v,
        ),
        Command::New {
            name,
            template,
            force,
        } => new::new(&name, &template, force, v),
        Command::Templates => {
            new::list();
            Ok(())
        }
        Command::Completions { shell } => {
            // Into memory first: the generator panics on a failed write.
            let mut script = Vec::new();
            clap_complete::generate(shell, &mut Args::command(), "karigami", &mut script);
            out!("{}", String::from_utf8_lossy(&script));
            Ok(())
        }
    };
    match result {
        Ok(()) => 0,
        Err(e) => {
            e.report(json);
            e.exit_code()
        }
    }
}

/// `--jobs` (at least 1, `args::jobs`), or every core when it is not given.
fn jobs_or_cores(jobs: Option<usize>) -> usize {
    jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
}
