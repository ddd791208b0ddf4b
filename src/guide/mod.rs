//! The printable assembly guide, as drawing-model pages: a cover, the bill
//! of materials with a 1:1 ruler, one step per row, the collapsed state as a
//! 1:1 inspection gauge, and a checklist. Everything a maker needs to build
//! the lattice on a table without a screen.

mod checklist;
mod cover;
mod expect;
pub(crate) mod finding;
mod fit_text;
mod gauge;
mod labels;
mod materials;
mod sheet_map;
pub(crate) mod stacking;
mod step_labels;
mod step_page;
mod step_pictures;
mod step_text;
mod supports;

use crate::drawing::flow::{MARGIN, PageFlow, SMALL};
use crate::drawing::{Font, text};
use crate::drawing::{Page, Shape, Symbol};
use crate::lattice::shape::relief;
use crate::lattice::{Lattice, VertexKey};
use crate::measure::BUMP_DEG;
use crate::pipeline::Build;
use checklist::checklist;
use cover::cover;
pub use gauge::{GAUGE_OVERLAP, gauge_tiles};
use glam::DVec2;
pub use materials::eyelets_by_grip;
use materials::{materials, test_piece_block};
use step_page::{StepLayout, step_block};
use step_pictures::StepPictures;

/// The colour of what a step adds.
const NEW: [u8; 3] = [214, 40, 40];

fn key(k: VertexKey) -> String {
    format!("[{},{}]", k.row, k.col)
}

fn mm(x: f64) -> String {
    format!("{x:.1} mm")
}

/// How many spares to buy: a tenth more, at least two.
pub(crate) fn spares(n: usize) -> usize {
    n.div_ceil(10).max(2)
}

/// The guide's pages and the drawings they share.
#[derive(Clone, Debug, PartialEq)]
pub struct Guide {
    /// The guide's pages, in reading order.
    pub pages: Vec<Page>,
    /// The lattice's rows, drawn once each and placed on every step page
    /// that shows them (see `StepPictures`).
    pub symbols: Vec<Symbol>,
}

/// The guide for a build, on its paper (A4 or US Letter, portrait), its
/// cover showing the designed deployed shape.
pub fn guide(b: &Build) -> Guide {
    guide_showing(b, None)
}

/// The guide with the cover showing `simulated`, the simulated deployed
/// shape of a build that was simulated (what `build` writes), else the
/// designed one; the caption says which.
pub fn guide_showing(b: &Build, simulated: Option<&Lattice>) -> Guide {
    let fab = &b.design.fabrication;
    // The footer, "NAME assembly guide - page N", on one line of the text
    // width (room for a page number of 4 digits).
    let room = fab.paper.size().0
        - 2.0 * MARGIN
        - text::width(" assembly guide - page 0000", Font::Regular, SMALL);
    let name = fit_text::shortened(&b.design.name, Font::Regular, SMALL, room);
    let mut w = PageFlow::new(fab.paper.size(), format!("{name} assembly guide"));
    let steps = &b.steps;
    let side = stacking::side(&b.lattice);
    cover(&mut w, b, simulated, steps, &side);
    materials(&mut w, b);
    let spots = finding::Spots::new(b);
    sheet_map::sheet_maps(&mut w, b, &spots);
    test_piece_block(&mut w, b);
    let layout = StepLayout::new(b, steps, w.width());
    let pictures = StepPictures::new(b, steps, layout.overview());
    for step in steps {
        step_block(
            &mut w,
            b,
            step,
            steps.len(),
            &pictures,
            &layout,
            &side,
            &spots,
        );
    }
    // What opening it is like, before the checklist that asks to open it.
    expect::expect(&mut w, b);
    supports::supports(&mut w, b);
    // The checklist before the gauge: the gauge's pages are cut up.
    checklist(&mut w, b, steps);
    gauge::gauge(&mut w, b);
    w.finish_page();
    Guide {
        pages: w.pages,
        symbols: pictures.symbols,
    }
}

/// How a bent-facet lattice takes its shape, with its curved vertices
/// counted (interior vertices with an angle defect of at least +3 degrees,
/// dome-like: a bump or a cup, or at most -3, saddle-like), or None for a
/// lattice whose shape the geometry fixes. The counts are measured on the
/// shape the cover shows, the simulated one when the build simulated it
/// (what the strips make), and the text says which.
fn bumps(b: &Build, simulated: Option<&Lattice>) -> Option<String> {
    if !bent_facets(b) {
        return None;
    }
    let c = b.lattice.curvature();
    let (dome, saddle) = relief(&c, BUMP_DEG);
    let designed = format!(
        "the design makes {dome} of its {} inner vertices dome-like (a bump or a cup: angle defect \
         +{BUMP_DEG} deg or more) and {saddle} saddle-like (-{BUMP_DEG} deg or less)",
        c.len()
    );
    let shape = match simulated {
        Some(s) => {
            let (s_dome, s_saddle) = relief(&s.curvature(), BUMP_DEG);
            format!(
                "{designed}; in the simulated shape of preview.png and deployed.obj, where the strips' stiffness \
                 has its say, {s_dome} are dome-like and {s_saddle} saddle-like"
            )
        }
        None => format!(
            "{designed} (this build did not simulate the strips: how far the relief forms is not measured)"
        ),
    };
    // A dome-like vertex can stand out to either side of the sheet
    // (docs/physics.md, Multistability: the eggbox's bumps pop through).
    let push = if dome > 0 {
        " A bump that stands out to the wrong side may be pushed through to the other: such a lattice can \
         have several stable shapes (karigami simulate --explore lists those it finds)."
    } else {
        ""
    };
    Some(format!(
        "Bent facets: rows of this lattice grew on rebuilt fronts, so where two rows join, the strips must bend. \
         Assemble every joint with the strips straight; as you open the lattice the strips bend at the row joins \
         and the relief forms by itself: {shape}. Open it slowly and evenly; how far the bumps rise depends on \
         the strips' stiffness (docs/physics.md).{push}"
    ))
}

/// Whether the lattice has bent facets (rows on rebuilt fronts, in 3-D):
/// its strips bend at the row joins as it opens.
fn bent_facets(b: &Build) -> bool {
    !b.lattice.extrinsic() && b.lattice.dim != 2
}

/// A rectangle from its top-left corner and size (mm).
fn rect(x: f64, y: f64, w: f64, h: f64) -> Shape {
    Shape::polyline(
        &[
            DVec2::new(x, y),
            DVec2::new(x + w, y),
            DVec2::new(x + w, y + h),
            DVec2::new(x, y + h),
        ],
        true,
    )
}
