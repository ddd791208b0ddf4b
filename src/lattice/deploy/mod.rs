//! Deployment (docs/math.md 8.4): the intrinsic configuration C(theta), its
//! valid range, the mobility of the ideal linkage at the design state, and
//! for planar lattices how far a rigid placement of the cells misses at
//! other angles.

use super::Lattice;
use crate::words::plural;

mod configuration;
mod misfit;
mod mobility;

pub use configuration::{Configuration, configuration};
pub use misfit::{planar_misfit, planar_misfits};
pub use mobility::{MOBILITY_MAX_CELLS, mobility};

/// Fractions of the design angle at which a planar placement is tried.
pub(crate) const MISFIT_FRACTIONS: [f64; 3] = [0.99, 0.9, 0.5];

/// Everything `karigami check` says about deployment.
#[derive(Clone, Debug)]
pub struct Deployment {
    /// The intrinsic configuration C(theta): every cell's opening as a function
    /// of the reference cell's.
    pub config: Configuration,
    /// Internal degrees of freedom of the ideal linkage at the design state,
    /// for lattices small enough to count them.
    pub mobility: Option<usize>,
    /// (fraction of the design angle, misfit) for planar lattices.
    pub misfits: Vec<(f64, f64)>,
}

/// Deployment of `lattice`: its C(theta) path, mobility and planar misfits.
///
/// A planar grown sheet is placed as C(theta) takes its cells, in order
/// with their corners and legs at hand (`configuration_with`), rather than
/// in a second pass reading every cell again: every opening is placed, and
/// those outside the valid range, known once every cell is taken, dropped.
/// Each opening's placement is computed on its own (`misfit::LANES`), so
/// its misfit is the second pass's bit for bit. Any other lattice (not a
/// grown sheet's grid, or corners spread wider than the ring) is measured
/// by the second pass.
pub fn deployment(lattice: &Lattice) -> Deployment {
    let thetas = MISFIT_FRACTIONS.map(|f| f * configuration::theta_design(lattice));
    let mut placing = (lattice.dim == 2 && !lattice.cells.is_empty())
        .then(|| misfit::Placements::new(thetas.map(f64::cos), lattice.vertex_rings().0));
    let (config, in_order) =
        configuration::configuration_with(lattice, |cell, corners, legs, f| {
            if let Some(p) = &mut placing
                && !p.add(cell, corners, *legs, f)
            {
                placing = None;
            }
        });
    let placed = match placing {
        Some(p) if in_order => {
            let misfit = p.finish();
            (0..thetas.len())
                .map(|k| config.holds(thetas[k]).then(|| misfit[k].sqrt()))
                .collect()
        }
        _ => planar_misfits(lattice, &config, &thetas),
    };
    let misfits = MISFIT_FRACTIONS
        .iter()
        .zip(placed)
        .filter_map(|(&f, m)| Some((f, m?)))
        .collect();
    Deployment {
        mobility: mobility(lattice),
        config,
        misfits,
    }
}

impl Deployment {
    /// A mechanism: the ideal linkage moves at the design state and, in
    /// the plane, the cells also place without misfit at other angles (in
    /// space only the first-order count is known).
    pub fn is_mechanism(&self) -> bool {
        self.mobility.is_some_and(|m| m > 0) && self.misfits.iter().all(|&(_, m)| m < 1e-6)
    }

    /// The verdict in plain words.
    pub fn verdict(&self, lattice: &Lattice) -> String {
        if !lattice.extrinsic() {
            return "deploys through strip bending: its facets are bent (intrinsic growth), so no rigid deployed state holds every cell".into();
        }
        match self.mobility {
            None => format!(
                "mobility not computed (more than {MOBILITY_MAX_CELLS} cells); C(theta) is valid for theta up to {:.1} deg",
                self.config.theta_max.to_degrees()
            ),
            Some(m) if self.is_mechanism() && lattice.dim == 2 => format!(
                "a true mechanism: {} of freedom, and its cells place exactly at every angle tried; it deploys by turning its pivots, strips straight",
                plural(m, "internal degree")
            ),
            Some(m) if self.is_mechanism() => format!(
                "a mechanism at the design state: {} of freedom (a first-order count); it can move by turning its pivots, strips straight",
                plural(m, "internal degree")
            ),
            Some(m) if m > 0 => format!(
                "{} of freedom at the design state, but the cells do not stay in place as it opens; it deploys through strip bending",
                plural(m, "internal degree")
            ),
            Some(_) => "rigid as an ideal linkage (0 internal degrees of freedom): it deploys and collapses through strip bending, passing through incompatible states (docs/verification.md, Deployment)".into(),
        }
    }
}
