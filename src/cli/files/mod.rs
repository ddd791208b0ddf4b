//! Files: recipes read (`input`), the file `tune --out` writes
//! (`out_file`), and the build folders of the `karigami-folder` crate
//! (crates/folder: staged, locked, repaired, docs/build-folders.md), told
//! here who writes them and where their warnings go.

mod earlier;
mod input;
mod out_file;

pub(super) use earlier::EarlierBuild;
pub(super) use input::{read, recipes, safe_component};
pub(super) use karigami_folder::{
    OutDir, Staged, dir_of, inputs, start_program_hash, write_atomic,
};
pub(super) use out_file::OutFile;

/// Name this program in the markers it writes and send a commit's
/// warnings to stderr through `errln!` (whose failures fail the run).
pub(super) fn start() {
    karigami_folder::set_host(karigami_folder::Host {
        program: concat!("karigami ", env!("CARGO_PKG_VERSION")),
        warn: |line| errln!("{line}"),
    });
}
