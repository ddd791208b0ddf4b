//! The staged search of `karigami design` (docs/design.md, "Design your own
//! object"): a target in, the seed and rows of sheets that grow onto it out,
//! best first. Pure: the caller reads the files, builds the candidates with
//! the whole pipeline (the same refusals as `build`) and writes the recipe.
//!
//! Stages: (1) the topology, from the target's boundary loops; (2) seeds,
//! stretches of the boundary resampled at the cell edge, each oriented so
//! its sheet grows into the patch; (3) rows, the fit's row search on the
//! target (`solve::fit`, docs/math.md 6.1), as deep as it reaches; (4) the
//! designs ranked by their fit to the target (docs/design.md, "The fit
//! measures").

use crate::design::Design;
use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::jobs::Jobs;
use crate::lattice::Lattice;
use crate::target::{Target, Topology};
use glam::DVec3;
use std::sync::Arc;
use std::time::Instant;

mod bump;
pub use bump::BumpCover;
pub use level::OvalRim;
mod closed;
mod feet;
pub mod goal;
mod level;
mod loops;
mod material;
mod polish;
mod rounded;
mod sheets;
mod waved;

pub use feet::{flattens, with_feet};
pub use goal::miss;
pub use polish::{POLISH_SECONDS_PER_CELL, POLISH_WORK};

/// Cells across the target at most (docs/design.md, stage 1).
pub(crate) const MAX_CELLS_ACROSS: f64 = 60.0;

/// What `karigami design` asks of the search.
pub struct DesignAsk<'a> {
    /// The target, in its own frame (`Target::canonical`).
    pub target: Arc<Target>,
    /// Fabrication and simulation settings (a stub recipe with the flags).
    pub base: &'a Design,
    /// The preferred cell edge (mm).
    pub edge: f64,
    /// Stop starting new seeds after this instant.
    pub deadline: Option<Instant>,
    /// Threads; the result does not depend on them.
    pub jobs: Jobs,
    /// Cells costed at most in polishing a waved band's rings (`polish`;
    /// `POLISH_WORK` by default, 0 for none): each design costed counts
    /// its cells, grown and simulated.
    pub polish: usize,
}

/// One design found: its lattice as recipe text, and its fit to the target.
#[derive(Clone, Debug)]
pub struct Found {
    /// The recipe's `[lattice]` (and `[clash]`) tables: seed and rows.
    pub lattice: String,
    /// The grown lattice's cells.
    pub cells: usize,
    /// The design's fit to the target.
    pub fit: crate::target::Fit,
    /// Where the seed lies, for the recipe's comments.
    pub seed: String,
}

impl Found {
    /// Whether the design is a loop (its `[lattice]` seeds one), whose
    /// rings the bump's and the oval rim's hints speak of.
    pub fn is_loop(&self) -> bool {
        self.lattice.contains("seed = \"loop\"")
    }
}

/// The search's result: designs best first, and how they were found.
#[derive(Debug)]
pub struct Searched {
    /// The designs, best fit first.
    pub found: Vec<Found>,
    /// Seeds grown.
    pub tried: usize,
    /// The topology chosen, and why.
    pub topology: String,
    /// How much loops round a bump on a sheet can cover, when the target
    /// is one (`bump`).
    pub bump: Option<BumpCover>,
    /// The rim of a cap whose level rim is not a circle, when loops were
    /// grown round it (`level::OvalRim`).
    pub oval: Option<OvalRim>,
}

impl Searched {
    /// How far a candidate's simulated shape is from the goal (`miss`),
    /// with the bump's top judged apart on a bump (`goal::TOP_COVERED`),
    /// and that top's covered share: `sim` is the fit to `t` of the
    /// simulated `cells` (points and facets).
    pub fn judge(
        &self,
        t: &Target,
        sim: &crate::target::Fit,
        cells: (&[DVec3], &[[u32; 4]]),
    ) -> (f64, Option<f64>) {
        let top = self.bump.as_ref().map(|b| b.top_covered(t, sim, cells));
        let miss = miss(sim).max(top.map_or(0.0, goal::top_miss));
        (miss, top)
    }
}

/// The bump's top of `t` (one flag a triangle, in `t`'s own order), when
/// `search` finds `t` a round bump on a sheet, for `check` and a build's
/// report to judge it as the goal does (docs/design.md, "The goal").
pub fn bump_top(t: &Target) -> Option<Vec<bool>> {
    if t.topology != Topology::Patch {
        return None;
    }
    // As `search` sees it: in its own frame, its rim made level (both keep
    // the triangles' order).
    let levelled = level_rim(&Arc::new(t.canonical()));
    let boundary = sheets::inward_boundary(&levelled);
    if loops::circular_rim(&boundary, levelled.extent).is_some() {
        return None;
    }
    let bump = bump::round_bump(&levelled, &boundary)?;
    Some(bump::top(&levelled, bump))
}

/// The topology `search` grows on `t` (in its own frame) and why, or the
/// refusal of a target it cannot grow on or whose curvature the strips
/// do not reach: what `search` refuses first, for the caller to refuse
/// before it reckons the work.
pub fn admissible(t: &Target, base: &Design, edge: f64) -> Result<String, Diagnostic> {
    let topology = choose(t, edge)?;
    material::within_reach(t, base, edge)?;
    Ok(topology)
}

/// Search sheets for `ask.target`; `progress` hears about each seed.
pub fn search(ask: &DesignAsk<'_>, progress: &mut dyn FnMut(&str)) -> Result<Searched, Diagnostic> {
    let topology = admissible(&ask.target, ask.base, ask.edge)?;
    if matches!(ask.target.topology, Topology::Closed { .. })
        && let closed::Revolved::About { axis, .. } = closed::revolved(&ask.target)
    {
        return Ok(closed_loops(ask, axis, topology, progress));
    }
    let levelled = level_rim(&ask.target);
    let ask = &DesignAsk {
        target: levelled,
        base: ask.base,
        edge: ask.edge,
        deadline: ask.deadline,
        jobs: ask.jobs,
        polish: ask.polish,
    };
    let t = &ask.target;
    let boundary = sheets::inward_boundary(t);
    let ring = sheets::resample(&boundary, ask.edge);
    let rows = ((t.extent / ask.edge).ceil() as usize).clamp(2, 60);
    // A side from corner to corner first (a rectangle's rows run straight
    // across it), then stretches of the boundary.
    let seeds: Vec<(Vec<DVec3>, String)> = sheets::sides(&boundary, t.extent, ask.edge)
        .into_iter()
        .enumerate()
        .map(|(k, side)| {
            let note = format!(
                "{} cells along side {} of the boundary (from corner to corner, longest first)",
                side.len() - 1,
                k + 1
            );
            (side, note)
        })
        .collect();
    // Stretches of the boundary only where it has no sides (a round rim
    // that is not level): a stretch round a corner folds at it.
    let seeds = if seeds.is_empty() {
        sheets::seeds(&ring)
    } else {
        seeds
    };
    let mut found: Vec<Found> = Vec::new();
    // Built before the rest, whatever their fit: rings polished so that
    // every vertex carries the target's negative curvature (`polish`).
    let mut first: Vec<Found> = Vec::new();
    let mut tried = 0;
    let mut bumps = Vec::new();
    let mut cover = None;
    let mut oval = None;
    let mut topology = topology;
    let patch = t.topology == Topology::Patch;
    let round_rim = loops::circular_rim(&boundary, t.extent).filter(|_| patch);
    if let Some((centre, radius)) = round_rim {
        topology = format!(
            "loop: the target is an open patch whose boundary is a level circle (radius {radius:.1} mm), so a symmetric loop seeded round it closes every ring and each ring's vertex can be put on the target one edge further in (docs/math.md 6.2, as for the half ellipsoid)"
        );
        found.extend(loops::loops(
            ask,
            (centre, radius),
            "round the rim",
            &mut tried,
            progress,
        ));
    } else if patch && let Some(round) = bump::round_bump(t, &boundary) {
        // Sheets are grown too: on a low bump they may cover more.
        let (why, reach, grown) = bump::grow(ask, (round, &boundary), &mut tried, progress);
        (topology, cover, bumps) = (why, Some(reach), grown);
    }
    // A level rim of any other shape: loops at equal chords round it,
    // grown beside the sheets (which may cover a plate's corners better).
    if let Some(z) = level::level(&boundary, t.extent).filter(|_| patch && round_rim.is_none()) {
        let what = "at equal chords round the level rim";
        let grown = level::loops(ask, (&boundary, z), None, what, &mut tried, progress);
        if !grown.is_empty() {
            topology = level::topology(&topology, cover.is_some());
            if cover.is_none() && level::cap(t, &boundary).is_some() {
                oval = OvalRim::of(t, &boundary, z);
            }
        }
        bumps.extend(grown);
    }
    if let Some(rims) = loops::level_rims(t).filter(|_| !patch) {
        found.extend(loops::annulus(ask, rims, &mut tried, progress));
    } else if let Some(band) = waved_band(t) {
        let (polished, grown) = waved::loops(ask, band, &mut tried, progress);
        first.extend(polished);
        found.extend(grown);
    }
    // Sheets only on a patch where no loop grows: a loop round the rim
    // covers more.
    let seeds = if found.is_empty() && patch {
        seeds
    } else {
        Vec::new()
    };
    found.append(&mut bumps);
    // Each seed with each scan (`sheets::SCANS`) twice: rows grown as they
    // come (extrinsic), and rows on fronts laid back onto the target
    // (intrinsic, docs/math.md 7).
    let scans = sheets::SCANS.len();
    ask.jobs.in_order(
        2 * scans * seeds.len(),
        |k| {
            if ask.deadline.is_some_and(|d| Instant::now() > d) {
                return None;
            }
            let (seed, samples) = (&seeds[k / (2 * scans)].0, sheets::SCANS[k / 2 % scans]);
            Some(sheets::grow_seed(ask, seed, (rows, samples), k % 2 == 1))
        },
        |k, result| {
            let (samples, laid) = (sheets::SCANS[k / 2 % scans], k % 2 == 1);
            let k = k / (2 * scans);
            tried += 1;
            let (rows, lattice) = match result {
                Some(Ok(grown)) => grown,
                Some(Err(why)) => {
                    progress(&format!("seed {}/{}: {why}", k + 1, seeds.len()));
                    return;
                }
                None => return,
            };
            let fit = fit_of(t, &lattice);
            progress(&format!(
                "seed {}/{}: {} rows, {} cells; design {}",
                k + 1,
                seeds.len(),
                rows.len(),
                lattice.cells.len(),
                fit.summary("vertices")
            ));
            found.push(Found {
                lattice: sheets::sheet_toml(&seeds[k].0, &rows),
                cells: lattice.cells.len(),
                fit,
                seed: format!(
                    "{}; rows scanned over {samples} leg angles{}",
                    seeds[k].1,
                    if laid {
                        ", each on its front laid back onto the target"
                    } else {
                        ""
                    }
                ),
            });
        },
    );
    ranked(&mut found);
    first.append(&mut found);
    Ok(Searched {
        found: first,
        tried,
        topology,
        bump: cover,
        oval,
    })
}

/// The loops of a closed target of revolution (`closed::loops`), the
/// target turned so that its `axis` is z; best first.
fn closed_loops(
    ask: &DesignAsk<'_>,
    axis: DVec3,
    topology: String,
    progress: &mut dyn FnMut(&str),
) -> Searched {
    let turned = if axis == DVec3::Z {
        ask.target.clone()
    } else {
        Arc::new(ask.target.levelled(axis))
    };
    let ask = &DesignAsk {
        target: turned,
        base: ask.base,
        edge: ask.edge,
        deadline: ask.deadline,
        jobs: ask.jobs,
        polish: ask.polish,
    };
    let mut tried = 0;
    let mut found = closed::loops(ask, &mut tried, progress);
    ranked(&mut found);
    Searched {
        found,
        tried,
        topology,
        bump: None,
        oval: None,
    }
}

/// Best fit first (a stable sort: of equal fits, the earlier seed); a
/// target's symmetry grows the same design from several sides, kept once.
fn ranked(found: &mut Vec<Found>) {
    found.sort_by(|a, b| miss(&a.fit).total_cmp(&miss(&b.fit)));
    found.dedup_by(|a, b| {
        a.cells == b.cells && same(a.fit.rms, b.fit.rms) && same(a.fit.largest, b.fit.largest)
    });
}

/// Equal to a millionth: the same design turned by a symmetry of the target.
fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * a.abs().max(b.abs())
}

/// The target turned so that its rim's own plane is level, when that
/// plane is within 10 degrees of level already (a mesh's principal axes
/// are tilted slightly by uneven triangles); else as it is.
fn level_rim(t: &Arc<Target>) -> Arc<Target> {
    let ring = sheets::inward_boundary(t);
    if ring.len() < 3 {
        return t.clone();
    }
    let c = ring.iter().sum::<DVec3>() / ring.len() as f64;
    // Newell's normal of the rim polygon.
    let mut n = DVec3::ZERO;
    for k in 0..ring.len() {
        let (a, b) = (ring[k] - c, ring[(k + 1) % ring.len()] - c);
        n += a.cross(b);
    }
    let n = if n.z < 0.0 { -n } else { n };
    match n.try_normalize() {
        Some(u) if u.z > 10f64.to_radians().cos() && u.z < 1.0 - 1e-12 => Arc::new(t.levelled(u)),
        _ => t.clone(),
    }
}

/// Cells reckoned a square of the cell edge on the target, for the
/// estimate of `karigami design` (src/cli/design.rs): a loop round a
/// level, round rim or between two (rings 0.5 to 0.9 edges apart: the
/// sphere cap's 168 and the paraboloid's 160 cells, 2.7 and 3.5 a square),
/// a closed target's loop (pole to pole: sphere.toml's 288 cells, 2.1 a
/// square, whose search costs half a cap's a cell, so reckoned at 1), and
/// a sheet (rows about an edge apart: the saddle's 35, the plate's 42,
/// the bump's 30 cells, 0.7 to 1.3 a square, reckoned at the least), and
/// loops round a bump's axis on a sheet as well as its sheets (the
/// height field's 100 cells, 2.4 a square; the 360 mm square sheet's
/// 100, 2.8). The same tests of topology as `search`.
pub fn cells_per_square(t: &Arc<Target>) -> f64 {
    const LOOPS: f64 = 3.0;
    const CLOSED: f64 = 1.0;
    const SHEETS: f64 = 0.7;
    const BUMP: f64 = 2.4;
    match t.topology {
        Topology::Closed { .. } => CLOSED,
        Topology::Patch => {
            let levelled = level_rim(t);
            let boundary = sheets::inward_boundary(&levelled);
            if loops::circular_rim(&boundary, levelled.extent).is_some() {
                LOOPS
            } else if bump::round_bump(&levelled, &boundary).is_some() {
                BUMP
            } else if level::cap(&levelled, &boundary).is_some() {
                LOOPS
            } else {
                SHEETS
            }
        }
        _ => LOOPS,
    }
}

/// The waved band `search` grows on `t` (levelled): two rims, not both
/// level circles, round in plan about one vertical axis (`waved`).
fn waved_band(t: &Target) -> Option<waved::Band> {
    let banded = t.topology != Topology::Patch && loops::level_rims(t).is_none();
    banded.then(|| waved::band(t)).flatten()
}

/// Whether `search` polishes rings on this target (canonical, as
/// `search` takes it): a waved band (`polish`), for the estimate of
/// `karigami design`.
pub fn polishes(t: &Arc<Target>) -> bool {
    waved_band(&level_rim(t)).is_some()
}

/// Vertical lines dropped onto a target from above its highest point:
/// the heights `design` reads round circles and down meridians.
struct Plumb<'a> {
    t: &'a Target,
    top: f64,
}

impl<'a> Plumb<'a> {
    fn new(t: &'a Target) -> Self {
        let top = t
            .mesh
            .positions
            .iter()
            .map(|p| p.z)
            .fold(f64::NEG_INFINITY, f64::max);
        Plumb { t, top: top + 1.0 }
    }

    /// The height where the vertical line through plan point `p` first
    /// meets the target from above; None where it misses.
    fn height(&self, p: glam::DVec2) -> Option<f64> {
        let from = p.extend(self.top);
        self.t.ray(from, -DVec3::Z, 0.0).map(|h| self.top - h)
    }
}

/// The fit of a lattice's vertices and cells to the target.
pub fn fit_of(t: &Target, lattice: &Lattice) -> crate::target::Fit {
    let points: Vec<DVec3> = lattice.vertices.iter().map(|v| v.pos).collect();
    t.fit(&points, &lattice.facets())
}

/// The topology to grow, with why; a target it cannot grow on is refused
/// with what would work.
fn choose(t: &Target, edge: f64) -> Result<String, Diagnostic> {
    let refuse = |m: String, hint: &str| {
        Err(Diagnostic::new(ErrorKind::TargetTopology, m).hint(hint.to_string()))
    };
    if t.extent < 3.0 * edge {
        return Err(Diagnostic::new(
            ErrorKind::TargetParameter,
            format!(
                "the target is {:.1} mm across, under three cells of {edge:.1} mm",
                t.extent
            ),
        )
        .hint(format!(
            "give a smaller --edge (at most {:.1} mm), or scale the target up",
            t.extent / 3.0
        )));
    }
    if t.extent > MAX_CELLS_ACROSS * edge {
        return Err(Diagnostic::new(
            ErrorKind::TargetParameter,
            format!(
                "the target is {:.1} mm across, over 60 cells of {edge:.1} mm",
                t.extent
            ),
        )
        .hint(format!(
            "give a larger --edge (at least {:.1} mm)",
            t.extent / MAX_CELLS_ACROSS
        )));
    }
    match t.topology {
        Topology::Patch => Ok(
            "sheet: the target is an open patch (one boundary loop), so a sheet grows from a stretch of its boundary across it (docs/math.md 6.1)".into(),
        ),
        Topology::Annulus if loops::level_rims(t).is_some() => Ok(
            "loop: the target is an annulus whose two rims are level circles about one axis, so a symmetric loop seeded round one rim closes every ring and each ring's vertex can be put on the target one step further along, to the other rim (docs/math.md 6.2)".into(),
        ),
        Topology::Annulus if waved::band(t).is_some() => Ok(
            "loop: the target is an annulus whose two rims are circles in plan about one vertical axis but not level (a ring cut from a saddle), so a symmetric loop is seeded on its longer rim and every front is laid on the saddle fitted to the target at its radius, the fronts carrying the band's curvature (docs/math.md 7; docs/design.md, \"Saddle rings\")".into(),
        ),
        Topology::Annulus => refuse(
            "the target is an annulus or tube segment whose rims are neither both level circles about one axis nor both circles in plan about one vertical axis; karigami design grows loops only between such rims".into(),
            "cut the band open along one line from edge to edge, so that it is a patch, or make both rims circles about one axis",
        ),
        Topology::Closed { genus: 0 } => closed_topology(t),
        Topology::Closed { genus: 1 } => refuse(
            format!(
                "the target is {}: karigami design grows a loop from a rim or from a pole of a surface of revolution, and a torus has neither; a loop wound round its tube leaves its last ring unjoined to its seed, and the paper's (examples/torus.toml) simulates to 1.80 % of D rms with 70.8 % of the torus covered, short of the goal (docs/design.md, \"Measured fits of the examples\")",
                t.topology.describe()
            ),
            "cut it into a band whose two rims are level circles about its axis, such as its outer band within 45 degrees of the tube's outer equator (fixtures/targets/torus-band.toml), which karigami design grows as a loop from rim to rim; or into a patch with one boundary loop (docs/design.md, \"Closed targets\")",
        ),
        other => refuse(
            format!("the target is {}; karigami design grows sheets on open patches, loops on bands and closed surfaces of revolution", other.describe()),
            "cut the surface open where the design should end, so that it has one boundary loop",
        ),
    }
}

/// A closed target of genus 0: a loop from pole to pole when it is a
/// surface of revolution (`closed::revolved`); refused with why otherwise.
fn closed_topology(t: &Target) -> Result<String, Diagnostic> {
    let share = |mm: f64| 100.0 * mm / t.extent;
    let limit = 100.0 * closed::ROUND;
    let (m, hint) = match closed::revolved(t) {
        closed::Revolved::About { spread, .. } => {
            return Ok(format!(
                "loop: the target is a closed surface of revolution (its distance from its centre the same at every azimuth about one principal axis within {spread:.1} mm, {:.2} % of D), so a symmetric loop seeded round a small level circle near one pole closes every ring and each ring's vertex can be put on the target one step further along its meridian, to a small circle near the other pole; the caps left open at the poles count against the coverage (docs/math.md 6.2)",
                share(spread)
            ));
        }
        closed::Revolved::NotRound { spread } => (
            format!(
                "the target is a closed surface, but not one of revolution: about each of its principal axes its distance from its centre varies with the azimuth by {spread:.1} mm ({:.1} % of D) or more, over the {limit} % a loop needs, whose rings are level circles about one axis",
                share(spread)
            ),
            "make it round about one axis (a sphere, a spheroid, an egg), or cut it open into a patch with one boundary loop, which karigami design grows sheets on",
        ),
        closed::Revolved::NotStar => (
            "the target is a closed surface, but not star-shaped about its centre (a ray from its centroid misses it or crosses it more than once), so karigami design cannot trace its meridians from pole to pole".to_string(),
            "cut it open into a patch with one boundary loop, or into a band whose rims are level circles about one axis",
        ),
    };
    Err(Diagnostic::new(ErrorKind::TargetTopology, m).hint(hint.to_string()))
}

/// A recipe that parses, for the fabrication and simulation settings the
/// flags give (`parse_with`); its lattice is replaced by the search's.
pub const STUB: &str = "[lattice]\nseed = \"sheet\"\npoints = [[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]]\nkappa = 0.0\n[lattice.grow]\nrows = 1\nangle = [45.0, 0.0]\n";

/// The cell edge when none is asked: six strip widths, and at least four
/// of the shortest leg the eyelets take, so that cells stay open.
pub fn default_edge(base: &Design) -> f64 {
    (6.0 * base.fabrication.material.width).max(least_edge(base))
}

/// The smallest cell edge the design's remedies suggest: four of the
/// shortest leg the eyelets take (a hole's flange and a wall each side).
pub fn least_edge(base: &Design) -> f64 {
    4.0 * (base.fabrication.eyelet.flange + 2.0 * crate::design::MIN_WALL)
}

/// The recipe of a design found: `notes` as its opening comment, the
/// target recorded (`[target]`, its path and its content hash) when given,
/// `tables` (the settings the design was made with that the recipe
/// carries: `[material] thickness`), the seed and one row table per row
/// with every number written in full, so that it grows exactly as the
/// search grew it.
pub fn recipe(
    found: &Found,
    name: &str,
    notes: &[String],
    target: Option<(&str, u64)>,
    tables: &str,
) -> String {
    let mut s = String::new();
    for n in notes {
        s.push_str(&format!("# {n}\n"));
    }
    s.push_str(&format!("name = {}\n", crate::words::toml_string(name)));
    if let Some((file, hash)) = target {
        s.push_str(&format!(
            "\n[target]                # what `check` and `build` fit this design to\nfile = {}\nhash = \"{hash:016x}\"\n",
            crate::words::toml_string(file)
        ));
    }
    if !tables.is_empty() {
        s.push('\n');
        s.push_str(tables);
    }
    s.push('\n');
    s.push_str(&found.lattice);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn target(text: &str) -> Arc<Target> {
        let t = crate::target::read("t.toml", text.as_bytes(), None).unwrap();
        Arc::new(t.canonical())
    }

    /// A loop's tables say so, a sheet's do not.
    #[test]
    fn a_found_loop_is_told_from_a_sheet() {
        let fit = crate::target::Fit {
            motion: crate::target::Rigid::IDENTITY,
            rms: 0.0,
            largest: 0.0,
            extent: 1.0,
            coverage: None,
            points: 0,
        };
        let ring = loops::level_loop(DVec3::ZERO, 100.0, 8);
        let found = |lattice: String| Found {
            lattice,
            cells: 0,
            fit,
            seed: String::new(),
        };
        assert!(found(loops::seed_toml(&ring)).is_loop());
        assert!(!found("[lattice]\nseed = \"sheet\"\n".into()).is_loop());
    }

    /// The estimate's cells a square follow the topology the search takes:
    /// a cap with a round rim grows a loop, a rectangle a sheet, a whole
    /// sphere a closed loop, an annulus a loop between its rims, a bump on
    /// a sheet loops round its axis.
    #[test]
    fn the_cells_reckoned_a_square_follow_the_topology() {
        let cap = target("[target]\nfamily = \"sphere-cap\"\nradius = 200.0\nheight = 60.0\n");
        let plate = target(
            "[target]\nfamily = \"height-field\"\nwidth = 300.0\nlength = 200.0\nheights = [[0.0, 0.0], [0.0, 0.0]]\n",
        );
        let sphere = target("[target]\nfamily = \"sphere-cap\"\nradius = 150.0\nheight = 300.0\n");
        let band = target(
            "[target]\nfamily = \"revolution\"\nprofile = [[120.0, 0.0], [100.0, 100.0], [120.0, 200.0]]\n",
        );
        assert_eq!(cells_per_square(&cap), 3.0);
        assert_eq!(cells_per_square(&plate), 0.7);
        assert_eq!(cells_per_square(&sphere), 1.0);
        assert_eq!(cells_per_square(&band), 3.0);
        let bump = target(&std::fs::read_to_string("fixtures/targets/height-field.toml").unwrap());
        assert_eq!(cells_per_square(&bump), 2.4);
        let oval = target(&std::fs::read_to_string("fixtures/targets/oval-cap.toml").unwrap());
        assert_eq!(cells_per_square(&oval), 3.0);
    }
}
