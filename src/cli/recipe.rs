//! Reading a recipe: its text, its name for messages and its default
//! design name, and running it through the pipeline.

use super::args::DEFAULT_TEMPLATE;
use super::error::Error;
use super::files;
use karigami::{Build, Design, Diagnostic, Overrides, Unsimulated, build_unsimulated, template};
use std::path::Path;

/// A recipe as read: its text, its name for messages, its default design name.
pub(super) struct Recipe {
    pub source: String,
    pub file: String,
    pub stem: String,
}

impl Recipe {
    pub(super) fn read(path: &Path) -> Result<Self, Error> {
        let file = path.display().to_string();
        let source = files::read(path).map_err(|e| Error::unreadable(&file, &e))?;
        Ok(Self {
            source,
            file,
            // The default design name reaches every output: plain text only.
            stem: files::safe_component(&stem(path)),
        })
    }

    pub(super) fn built_in() -> Self {
        Self {
            source: template::find(DEFAULT_TEMPLATE)
                .expect("the default template exists")
                .text
                .to_string(),
            file: "(built-in sheet)".to_string(),
            stem: "karigami-sheet".to_string(),
        }
    }

    pub(super) fn parse(&self, overrides: &Overrides) -> Result<Design, Error> {
        karigami::parse_with(&self.source, &self.stem, overrides).map_err(|d| self.error(&d))
    }

    /// A diagnostic against this recipe, rendered and as JSON.
    pub(super) fn error(&self, d: &Diagnostic) -> Error {
        Error::at(&self.file, &self.source, d)
    }
}

/// The file name without its extension: a recipe's default design name and
/// its subfolder in a batch.
pub(super) fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or("design".into(), |s| s.to_string_lossy().into_owned())
}

/// A build's first stage: the recipe parsed and built up to its
/// simulation (`karigami::build_unsimulated`).
pub(super) fn unsimulated(
    recipe: &Recipe,
    overrides: &Overrides,
    progress: &mut dyn FnMut(&str),
) -> Result<Unsimulated, Error> {
    build_unsimulated(recipe.parse(overrides)?, progress).map_err(|d| recipe.error(&d))
}

/// A build's last stage: the simulation of a build run up to it
/// (`karigami::build_unsimulated`), reusing the earlier build's in `out`
/// (the output folder and the recipe's subfolder in it) when nothing it
/// depends on changed (`karigami::Unsimulated::simulate`).
pub(super) fn simulate(
    recipe: &Recipe,
    unsimulated: Unsimulated,
    (out, sub): (&files::OutDir, &str),
) -> Result<Build, Error> {
    let state = unsimulated.simulates().then(|| {
        let state = Path::new(sub).join(karigami::STATE_FILE);
        out.earlier_file(&state.to_string_lossy(), STATE_LIMIT)
    });
    unsimulated
        .simulate(state.flatten().as_deref())
        .map_err(|d| recipe.error(&d))
}

/// Where a build's simulated deployed shape came from, for the terminal
/// and the JSON reports: "solved" or "reused"; None when it has none.
pub(super) fn simulation(b: &Build) -> Option<&'static str> {
    b.simulation_reused()
        .map(|reused| if reused { "reused" } else { "solved" })
}

/// The largest simulation state read back: the saddle ring's 120 cells
/// write about 0.3 MB, so a 2,000-cell lattice (the most `build`
/// simulates) about 5 MB; anything far beyond is not ours.
pub(super) const STATE_LIMIT: u64 = 64 << 20;
