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
use crate::design::fit::Fit;
use crate::diagnostic::{Diagnostic, ErrorKind};
use crate::jobs::Jobs;
use crate::lattice::{Kind, Lattice, RowParams, grow};
use crate::target::{Target, Topology};
use glam::DVec3;
use std::sync::Arc;
use std::time::Instant;

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

/// The search's result: designs best first, and how they were found.
#[derive(Debug)]
pub struct Searched {
    /// The designs, best fit first.
    pub found: Vec<Found>,
    /// Seeds grown.
    pub tried: usize,
    /// The topology chosen, and why.
    pub topology: String,
}

/// Leg angles a row's scan tries (and a tilt for every four, docs/recipe.md).
const SAMPLES: usize = 31;
/// Rows tried per seed over every backtrack of its search.
const ROW_BUDGET: usize = 40;
/// The seed stretches tried: shares of the boundary, and starts round it.
const SHARES: [f64; 2] = [0.25, 1.0 / 3.0];
const STARTS: usize = 4;

/// How far a fit is from issue 32's goal: the largest of rms over 1.5 % of
/// D, largest over 4 % of D and the uncovered share over 15 %; at most 1
/// meets it.
pub fn miss(f: &crate::target::Fit) -> f64 {
    let cov = f.coverage.unwrap_or(0.0);
    (f.rms / (0.015 * f.extent))
        .max(f.largest / (0.04 * f.extent))
        .max((1.0 - cov) / 0.15)
}

/// Search sheets for `ask.target`; `progress` hears about each seed.
pub fn search(ask: &DesignAsk<'_>, progress: &mut dyn FnMut(&str)) -> Result<Searched, Diagnostic> {
    let topology = choose(&ask.target, ask.edge)?;
    let levelled = level_rim(&ask.target);
    let ask = &DesignAsk {
        target: levelled,
        base: ask.base,
        edge: ask.edge,
        deadline: ask.deadline,
        jobs: ask.jobs,
    };
    let t = &ask.target;
    let boundary = inward_boundary(t);
    let ring = resample(&boundary, ask.edge);
    let rows = ((t.extent / ask.edge).ceil() as usize).clamp(2, 60);
    let seeds: Vec<(Vec<DVec3>, String)> = SHARES
        .iter()
        .flat_map(|&share| (0..STARTS).map(move |k| (share, k)))
        .map(|(share, k)| {
            let n = ring.len();
            let cells = ((share * n as f64).round() as usize).clamp(2, n - 1);
            let start = k * n / STARTS;
            let pts = (0..=cells).map(|j| ring[(start + j) % n]).collect();
            (
                pts,
                format!(
                    "{cells} cells along {:.0} % of the boundary from its point {start} of {n}",
                    100.0 * cells as f64 / n as f64
                ),
            )
        })
        .collect();
    let mut found: Vec<Found> = Vec::new();
    let mut tried = 0;
    let mut topology = topology;
    if let Some((centre, radius)) = circular_rim(&boundary, t.extent) {
        topology = format!(
            "loop: the target is an open patch whose boundary is a level circle (radius {radius:.1} mm), so a symmetric loop seeded round it closes every ring and each ring's vertex can be put on the target one edge further in (docs/math.md 6.2, as for the half ellipsoid)"
        );
        found.extend(loops(ask, centre, radius, &mut tried, progress));
    }
    // Sheets only where no loop grows: a loop round the rim covers more.
    let seeds = if found.is_empty() { seeds } else { Vec::new() };
    ask.jobs.in_order(
        seeds.len(),
        |k| {
            if ask.deadline.is_some_and(|d| Instant::now() > d) {
                return None;
            }
            grow_seed(ask, &seeds[k].0, rows)
        },
        |k, result| {
            tried += 1;
            let Some((rows, lattice)) = result else {
                progress(&format!("seed {}/{}: no row grows", k + 1, seeds.len()));
                return;
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
                lattice: sheet_toml(&seeds[k].0, &rows),
                cells: lattice.cells.len(),
                fit,
                seed: seeds[k].1.clone(),
            });
        },
    );
    // A stable sort: of equal fits, the earlier seed.
    found.sort_by(|a, b| miss(&a.fit).total_cmp(&miss(&b.fit)));
    Ok(Searched {
        found,
        tried,
        topology,
    })
}

/// The target turned so that its rim's own plane is level, when that
/// plane is within 10 degrees of level already (a mesh's principal axes
/// are tilted slightly by uneven triangles); else as it is.
fn level_rim(t: &Arc<Target>) -> Arc<Target> {
    let ring = inward_boundary(t);
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

/// A level, circular rim: its centre and radius, when every boundary
/// corner lies within 1 % of the radius of one circle in a plane z = const.
fn circular_rim(ring: &[DVec3], extent: f64) -> Option<(DVec3, f64)> {
    let n = ring.len() as f64;
    let c = ring.iter().sum::<DVec3>() / n.max(1.0);
    let r = ring
        .iter()
        .map(|p| (p - c).truncate().length())
        .sum::<f64>()
        / n.max(1.0);
    let level = ring.iter().all(|p| (p.z - c.z).abs() <= 0.002 * extent);
    let round = ring
        .iter()
        .all(|p| ((p - c).truncate().length() - r).abs() <= 0.01 * r);
    (level && round && r > 0.0 && ring.len() >= 8).then_some((c, r))
}

/// Loops of an even number of points round the rim (near one cell edge
/// apart, and two fewer), with a few ring counts: the rings' vertices
/// x[i][1] at equal steps of arc length down the target's meridian, the
/// last short of the axis by `HOLE` of it. Each count, and the same less
/// its last one or two rings (the likeliest to clash at the pole), is a
/// design.
fn loops(
    ask: &DesignAsk<'_>,
    centre: DVec3,
    radius: f64,
    tried: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Vec<Found> {
    let t = &ask.target;
    let n0 = ((std::f64::consts::TAU * radius / ask.edge / 2.0).round() as usize * 2).max(8);
    let mut out = Vec::new();
    for n in [n0, n0.saturating_sub(2).max(8)] {
        let points: Vec<DVec3> = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                centre + radius * DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let Some(meridian) = meridian(t, centre, points[1]) else {
            continue;
        };
        let length = meridian.last().map_or(0.0, |m| m.0);
        for per_edge in RING_STEPS {
            if ask.deadline.is_some_and(|d| Instant::now() > d) {
                return out;
            }
            *tried += 1;
            let rings = ((length / (per_edge * ask.edge)).round() as usize).clamp(2, MAX_RINGS);
            let targets: Vec<DVec3> = (1..=rings)
                .map(|i| along(&meridian, (1.0 - HOLE) * length * i as f64 / rings as f64))
                .collect();
            progress(&format!(
                "loop of {n} points round the rim, {rings} rings {:.1} mm apart down the meridian",
                (1.0 - HOLE) * length / rings as f64
            ));
            for rows in (rings.div_ceil(2).max(1)..=rings).rev() {
                let Some(lattice) = buildable_loop(ask.base, &points, &targets[..rows]) else {
                    continue;
                };
                out.push(Found {
                    lattice: loop_toml(&points, &targets[..rows]),
                    cells: lattice.cells.len(),
                    fit: fit_of(t, &lattice),
                    seed: format!(
                        "a loop of {n} points round the rim, {rows} of {rings} rings at equal steps down the meridian"
                    ),
                });
            }
        }
    }
    out
}

/// The loop's lattice, when it grows and `build` would take its strips
/// (`cost::refused`: parts and the clash rule, with columns stacked).
fn buildable_loop(base: &Design, points: &[DVec3], targets: &[DVec3]) -> Option<Lattice> {
    let mut d = base.clone();
    d.kind = Kind::Loop;
    d.dim = 3;
    d.points = points.to_vec();
    d.kappa = vec![0.0; points.len()];
    d.rows = loop_rows(targets);
    d.fit = None;
    d.clash.stacking = crate::lattice::Stacking::Columns;
    let lattice = d.grow().ok()?;
    let m = crate::measure::measure(&d, &lattice);
    super::cost::refused(&d, &lattice, &m)
        .is_none()
        .then_some(lattice)
}

/// Ring steps tried, as shares of the cell edge.
const RING_STEPS: [f64; 3] = [0.5, 0.7, 0.9];
/// The share of the meridian left open at the axis.
const HOLE: f64 = 0.1;
/// Rings a loop grows at most.
const MAX_RINGS: usize = 40;
/// Samples of a meridian.
const MERIDIAN: usize = 400;

/// Symmetric loop rows: each ring's vertex x[i+1][1] on the target point.
fn loop_rows(targets: &[DVec3]) -> Vec<RowParams> {
    targets
        .iter()
        .map(|&p| RowParams {
            target: Some(p),
            ..RowParams::default()
        })
        .collect()
}

/// The target's meridian from the rim point `from` to the axis through
/// `centre` along z, sampled where vertical lines meet it: (arc length,
/// point) pairs; None when a line misses the target.
fn meridian(t: &Target, centre: DVec3, from: DVec3) -> Option<Vec<(f64, DVec3)>> {
    let top = t
        .mesh
        .positions
        .iter()
        .map(|p| p.z)
        .fold(f64::NEG_INFINITY, f64::max)
        + 1.0;
    let d = (from - centre).truncate();
    let s0 = d.length();
    if !(s0 > 0.0) {
        return None;
    }
    let u = d / s0;
    let mut out = vec![(0.0, from)];
    for k in 1..=MERIDIAN {
        // A hair inside the rim, where the first line could miss.
        let s = s0 * (1.0 - k as f64 / MERIDIAN as f64);
        let p = DVec3::new(centre.x + s * u.x, centre.y + s * u.y, top);
        // A coarse mesh's rim is a polygon inside the circle: lines
        // between it and the circle miss, and are skipped.
        let Some(h) = t.ray(p, -DVec3::Z, 0.0) else {
            if out.len() == 1 {
                continue;
            }
            return None;
        };
        let q = p - h * DVec3::Z;
        let (walked, last) = *out.last().expect("one point");
        out.push((walked + q.distance(last), q));
    }
    Some(out)
}

/// The meridian's point at arc length `s` (straight between samples).
fn along(meridian: &[(f64, DVec3)], s: f64) -> DVec3 {
    let k = meridian
        .partition_point(|m| m.0 < s)
        .clamp(1, meridian.len() - 1);
    let ((a, p), (b, q)) = (meridian[k - 1], meridian[k]);
    p.lerp(
        q,
        ((s - a) / (b - a).max(f64::MIN_POSITIVE)).clamp(0.0, 1.0),
    )
}

/// A symmetric loop's recipe tables: columns in alternate layers (an even
/// loop; docs/assembly.md), the seed and each ring's target point.
fn loop_toml(points: &[DVec3], targets: &[DVec3]) -> String {
    let mut s = String::from(
        "[clash]\nstacking = \"columns\"    # neighbouring columns in alternate layers\n\n[lattice]\nseed = \"loop\"\nkappa = 0.0\npoints = [\n",
    );
    for p in points {
        s.push_str(&format!("    [{:?}, {:?}, {:?}],\n", p.x, p.y, p.z));
    }
    s.push_str("]\n");
    for p in targets {
        s.push_str(&format!(
            "\n[[lattice.rows]]\ntarget = [{:?}, {:?}, {:?}]\n",
            p.x, p.y, p.z
        ));
    }
    s
}

/// The fit of a lattice's vertices and cells to the target.
pub fn fit_of(t: &Target, lattice: &Lattice) -> crate::target::Fit {
    let facets: Vec<[u32; 4]> = lattice
        .cells
        .iter()
        .map(|c| [c.ul, c.ur, c.lr, c.ll])
        .collect();
    let points: Vec<DVec3> = lattice.vertices.iter().map(|v| v.pos).collect();
    t.fit(&points, &facets)
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
    if t.extent > 60.0 * edge {
        return Err(Diagnostic::new(
            ErrorKind::TargetParameter,
            format!(
                "the target is {:.1} mm across, over 60 cells of {edge:.1} mm",
                t.extent
            ),
        )
        .hint(format!(
            "give a larger --edge (at least {:.1} mm)",
            t.extent / 60.0
        )));
    }
    match t.topology {
        Topology::Patch => Ok(
            "sheet: the target is an open patch (one boundary loop), so a sheet grows from a stretch of its boundary across it (docs/math.md 6.1)".into(),
        ),
        Topology::Annulus => refuse(
            "the target is an annulus or tube segment; karigami design grows sheets on open patches so far".into(),
            "cut the band open along one line from edge to edge, so that it is a patch",
        ),
        other => refuse(
            format!("the target is {}; karigami design grows sheets on open patches", other.describe()),
            "cut the surface open where the design should end, so that it has one boundary loop",
        ),
    }
}

/// The target's longest boundary loop, running so that a sheet seeded on
/// it grows into the patch: clockwise seen from +z, because a front's
/// growth side is to its right (docs/recipe.md, "Row tables").
fn inward_boundary(t: &Target) -> Vec<DVec3> {
    let loops = t.mesh.boundary_loops();
    let Some(first) = loops.first() else {
        return Vec::new();
    };
    let mut pts: Vec<DVec3> = first
        .iter()
        .map(|&i| t.mesh.positions[i as usize])
        .collect();
    let area: f64 = (0..pts.len())
        .map(|k| {
            let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
            a.x * b.y - b.x * a.y
        })
        .sum();
    if area > 0.0 {
        pts.reverse();
    }
    pts
}

/// Points round a closed polyline at equal arc lengths near `edge`.
fn resample(ring: &[DVec3], edge: f64) -> Vec<DVec3> {
    let n = ring.len();
    let len: Vec<f64> = (0..n)
        .map(|k| ring[k].distance(ring[(k + 1) % n]))
        .collect();
    let total: f64 = len.iter().sum();
    let count = ((total / edge).round() as usize).max(4);
    let step = total / count as f64;
    let (mut out, mut k, mut walked) = (Vec::with_capacity(count), 0, 0.0);
    for j in 0..count {
        let want = j as f64 * step;
        while k + 1 < n && walked + len[k] < want {
            walked += len[k];
            k += 1;
        }
        let u = ((want - walked) / len[k].max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        out.push(ring[k].lerp(ring[(k + 1) % n], u));
    }
    out
}

/// The rows the fit's search reaches from one seed (with kappa 0) on the
/// target, and their lattice; None when no row grows.
fn grow_seed(
    ask: &DesignAsk<'_>,
    points: &[DVec3],
    rows: usize,
) -> Option<(Vec<RowParams>, Lattice)> {
    let mut d = ask.base.clone();
    d.kind = Kind::Sheet;
    d.dim = 3;
    d.points = points.to_vec();
    d.kappa = vec![0.0; points.len() - 1];
    d.rows.clear();
    let fit = Fit::on_target(ask.target.clone(), rows, SAMPLES);
    let found = super::fit::deepest_rows(&d, &fit, ROW_BUDGET).ok()?;
    let lattice = grow(Kind::Sheet, 3, &d.points, &d.kappa, &found).ok()?;
    d.rows.clone_from(&found);
    let m = crate::measure::measure(&d, &lattice);
    super::cost::refused(&d, &lattice, &m)
        .is_none()
        .then_some((found, lattice))
}

/// A recipe that parses, for the fabrication and simulation settings the
/// flags give (`parse_with`); its lattice is replaced by the search's.
pub const STUB: &str = "[lattice]\nseed = \"sheet\"\npoints = [[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]]\nkappa = 0.0\n[lattice.grow]\nrows = 1\nangle = [45.0, 0.0]\n";

/// The cell edge when none is asked: six strip widths, and at least four
/// of the shortest leg the eyelets take, so that cells stay open.
pub fn default_edge(base: &Design) -> f64 {
    let fab = &base.fabrication;
    let min_leg = fab.eyelet.flange + 2.0 * crate::design::MIN_WALL;
    (6.0 * fab.material.width).max(4.0 * min_leg)
}

/// The recipe of a design found: `notes` as its opening comment, the
/// target recorded (`[target]`, its path relative to the recipe and its
/// content hash) when given, the seed and one row table per row with every
/// number written in full, so that it grows exactly as the search grew it.
pub fn recipe(found: &Found, name: &str, notes: &[String], target: Option<(&str, u64)>) -> String {
    let mut s = String::new();
    for n in notes {
        s.push_str(&format!("# {n}\n"));
    }
    s.push_str(&format!("name = {}\n", toml_string(name)));
    if let Some((file, hash)) = target {
        s.push_str(&format!(
            "\n[target]                # what `check` fits this design to\nfile = {}\nhash = \"{hash:016x}\"\n",
            toml_string(file)
        ));
    }
    s.push('\n');
    s.push_str(&found.lattice);
    s
}

/// A sheet's `[lattice]`: its seed points and one row table per row,
/// every number in full so that it grows as the search grew it.
fn sheet_toml(points: &[DVec3], rows: &[RowParams]) -> String {
    let mut s = String::from("[lattice]\nseed = \"sheet\"\nkappa = 0.0\npoints = [\n");
    for p in points {
        s.push_str(&format!("    [{:?}, {:?}, {:?}],\n", p.x, p.y, p.z));
    }
    s.push_str("]\n");
    for r in rows {
        s.push_str("\n[[lattice.rows]]\n");
        if let Some(crate::legs::Direction::Angles {
            angle_deg,
            tilt_deg,
        }) = r.direction
        {
            s.push_str(&format!("angle = [{angle_deg:?}, {tilt_deg:?}]\n"));
        }
        for (key, leg) in [("left_leg", r.left_leg), ("right_leg", r.right_leg)] {
            if let crate::legs::Leg::Length(l) = leg {
                s.push_str(&format!("{key} = {l:?}\n"));
            }
        }
    }
    s
}

/// A TOML basic string.
fn toml_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
