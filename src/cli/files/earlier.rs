//! An earlier build folder read for what `check --reuse` takes from it: the
//! simulation state each recipe's build saved (docs/commands.md, "Check
//! reuses a build's simulation"). Nothing here is written.

use crate::cli::error::Error;
use karigami_folder::{Links, MARKER, read_plain};
use std::path::{Path, PathBuf};

/// A build folder (`build --out DIR`) whose simulation states `check` may
/// restore.
pub(crate) struct EarlierBuild {
    dir: PathBuf,
}

impl EarlierBuild {
    /// `dir`, refused unless it is a folder holding a build's marker: a
    /// mistyped path says so rather than quietly solving everything again.
    pub(crate) fn open(dir: &Path) -> Result<Self, Error> {
        let shown = dir.display();
        let meta = std::fs::metadata(dir).map_err(|e| Error::unreadable(&shown.to_string(), &e))?;
        if !meta.is_dir() || !dir.join(MARKER).is_file() {
            return Err(Error::io(format!(
                "cannot reuse {shown}: it is not a karigami build folder (no {MARKER} in it); give the --out folder of `karigami build`"
            )));
        }
        Ok(Self {
            dir: dir.to_path_buf(),
        })
    }

    /// The folder as given.
    pub(crate) fn path(&self) -> &Path {
        &self.dir
    }

    /// The state file saved for the recipe named `stem`: in its subfolder
    /// when the folder holds a batch with one, else the folder's own (a
    /// build of one recipe). None when there is none to read: the check
    /// then solves, as a build does (the state's own fingerprint decides
    /// whether it fits the recipe as it is now).
    pub(crate) fn state(&self, stem: &str, limit: u64) -> Option<Vec<u8>> {
        let batch = self.dir.join(stem).join(karigami::STATE_FILE);
        let single = self.dir.join(karigami::STATE_FILE);
        [batch, single]
            .iter()
            .find_map(|p| read_plain(p, limit, Links::Refuse).ok())
    }
}
