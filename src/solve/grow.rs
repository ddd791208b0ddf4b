//! Growing a design's lattice: the recipe's own rows, a helix, or the rows
//! a target fit's search chooses (`solve::fit`). This lives above design/
//! so that the recipe layer never calls a search.

use crate::design::Design;
use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::lattice::{Kind, Lattice, Stacking, grow, grow_helix};

impl Design {
    /// Grow the lattice; errors point at the recipe text that caused them.
    pub fn grow(&self) -> Result<Lattice, Diagnostic> {
        self.grow_with(&mut |_| {})
    }

    /// `grow`, telling `progress` about each fitted row (long fits).
    pub(crate) fn grow_with(&self, progress: &mut dyn FnMut(&str)) -> Result<Lattice, Diagnostic> {
        let columns = self.clash.stacking == Stacking::Columns;
        let n = self.points.len();
        if columns && (self.kind != Kind::Loop || !n.is_multiple_of(2)) {
            return Err(Diagnostic::new(
                ErrorKind::StackingNeedsEvenLoop,
                format!(
                    "clash.stacking = \"columns\" needs a loop of an even number of columns, but this seed is a {} of {n} points",
                    self.kind.name()
                ),
            )
            .at_opt(self.clash.span.clone())
            .hint("use stacking = \"rows\", or give the loop an even number of points"));
        }
        let result = match (self.kind, &self.fit) {
            (Kind::Helix, _) => grow_helix(self.dim, &self.points, &self.kappa, self.helix_cells),
            (_, Some(f)) => super::fit::grow(self, f, progress),
            _ => grow(self.kind, self.dim, &self.points, &self.kappa, &self.rows),
        };
        let mut lattice = result.map_err(|e| self.locate(e))?;
        self.check_supports(&lattice)?;
        lattice.stacking = self.clash.stacking;
        Ok(lattice)
    }
}
