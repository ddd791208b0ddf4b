//! The `karigami` command: the only layer that reads and writes files.

mod cli;

fn main() {
    std::process::exit(cli::run());
}
