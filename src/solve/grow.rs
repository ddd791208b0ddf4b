//! Growing a design's lattice: the recipe's own rows, a helix, or the rows
//! a target fit's search chooses (`solve::fit`). This lives above design/
//! so that the recipe layer never calls a search.

use crate::design::Design;
use crate::diagnostic::Diagnostic;
use crate::lattice::{Kind, Lattice, grow, grow_helix};

impl Design {
    /// Grow the lattice; errors point at the recipe text that caused them.
    pub fn grow(&self) -> Result<Lattice, Diagnostic> {
        self.grow_with(&mut |_| {})
    }

    /// `grow`, telling `progress` about each fitted row (long fits).
    pub fn grow_with(&self, progress: &mut dyn FnMut(&str)) -> Result<Lattice, Diagnostic> {
        let result = match (self.kind, &self.fit) {
            (Kind::Helix, _) => grow_helix(self.dim, &self.points, &self.kappa, self.helix_cells),
            (_, Some(f)) => super::fit::grow(self, f, progress),
            _ => grow(self.kind, self.dim, &self.points, &self.kappa, &self.rows),
        };
        result.map_err(|e| self.locate(e))
    }
}
