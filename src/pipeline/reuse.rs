//! Reusing the simulation of an earlier build (docs/physics.md, "Rebuilds";
//! docs/commands.md, "Build folders").
//!
//! The simulated deployed shape is a pure function of the lattice as built
//! (with its rigid-fit placement and joints), the strip section, the
//! material, the `[simulation]` settings and the code that solves it. A
//! simulated build writes `deployed.state`: the solver's exact state at
//! equilibrium (every variable, every reference frame, the held opening),
//! keyed by a fingerprint of all of those. A rebuild whose fingerprint
//! matches restores that state instead of solving, bit for bit, so every
//! file it writes is the one a fresh solve writes. Anything that does not
//! check out (another fingerprint, a file changed or cut short, a model of
//! another size) is never the user's problem: the build solves.
//!
//! The state is the build's chosen equilibrium, the one deploying ends in
//! (docs/physics.md, "The chosen equilibrium"), and the file keeps the
//! deployment path that found it, so a rebuild follows no path either.
//!
//! Exact reuse and not a warm start: a solve started from an earlier
//! equilibrium ends a few ulp away from a fresh one, and the files would
//! then depend on the folder's history instead of on the recipe.

use crate::hash::{Fnv1a, fnv1a};
use crate::sim::model::Frame;
use crate::sim::path::{Path, PathPoint};
use crate::sim::{Derived, Settings, Simulation, Stats, equilibrium, prepare_with};
use glam::DVec3;
use std::fmt::Write as _;
use std::time::Instant;

/// The state file's name in a build folder (next to deployed.json).
pub const STATE_FILE: &str = "deployed.state";

const HEAD: &str = "karigami simulation state";
/// Bumped when the layout of the state file changes.
const FORMAT: u32 = 2;

/// Each file (a path from the repository's root) with its text.
macro_rules! sources {
    ($($path:literal),* $(,)?) => {
        [$(($path, include_str!(concat!("../../", $path)))),*]
    };
}

/// The code an equilibrium comes from: a change to any of it (a solver
/// tolerance, a new energy term) gives another fingerprint, so a state
/// written by other code is never restored. `Cargo.lock` stands for the
/// versions of amd and glam. tests/rebuild.rs checks that the list names
/// every file of `src/sim/` and `crates/rods/src/`.
pub const SOURCES: [(&str, &str); 21] = sources![
    "src/sim/mod.rs",
    "src/sim/cost.rs",
    "src/sim/explore.rs",
    "src/sim/opening.rs",
    "src/sim/path.rs",
    "src/sim/results.rs",
    "src/sim/sensitivity.rs",
    "src/sim/states.rs",
    "src/sim/strips.rs",
    "src/sim/supports.rs",
    "src/sim/warm.rs",
    "crates/rods/src/adjoint.rs",
    "crates/rods/src/dual.rs",
    "crates/rods/src/frames.rs",
    "crates/rods/src/lib.rs",
    "crates/rods/src/model.rs",
    "crates/rods/src/rng.rs",
    "crates/rods/src/solver.rs",
    "crates/rods/src/sparse.rs",
    "src/pipeline/reuse.rs",
    "Cargo.lock",
];

/// What the solve reads, as one number: the karigami version, the code
/// (`SOURCES`), the lattice, its placement and joints, the strip section
/// and the settings. `Debug` prints every field and every f64 exactly
/// (shortest round-trip form). What only judges the result (the
/// allowable strain, `accept_overstrain`) is left out: the check runs on
/// the restored equilibrium as on a fresh one.
pub(crate) fn fingerprint(
    lattice: &crate::lattice::Lattice,
    derived: &Derived<'_>,
    width: f64,
    thickness: f64,
    settings: &Settings,
) -> u64 {
    let mut h = Fnv1a::new();
    let _ = writeln!(h, "karigami {} {FORMAT}", env!("CARGO_PKG_VERSION"));
    for (name, text) in SOURCES {
        let _ = writeln!(h, "{name} {}", text.len());
        h.bytes(text.as_bytes());
    }
    let mut solve = settings.clone();
    solve.accept_overstrain = false;
    solve.material.eps_allow = 0.0;
    let _ = write!(
        h,
        "{width:?} {thickness:?} {solve:?}\n{lattice:?}\n{:?}\n{:?}",
        derived.placed, derived.joints
    );
    h.0
}

/// The bytes of `deployed.state`: a text head (what the file is, its
/// format, the fingerprint, the payload's length and hash) and the payload,
/// little-endian 8-byte words.
pub(crate) fn state(run: &Simulation, path: Option<&Path>, fingerprint: u64) -> Vec<u8> {
    let m = &run.lm.model;
    let mut w = Words::default();
    w.count(m.q.len());
    w.count(m.ties.len());
    w.count(m.edges.len());
    w.count(m.joints.len());
    w.floats(&m.q);
    for t in &m.ties {
        w.float(t.offset);
    }
    for e in &m.edges {
        if let Frame::Ref { ts, as_, .. } = e.frame {
            w.vec(ts);
            w.vec(as_);
        }
    }
    for j in &m.joints {
        for v in j.frame {
            w.vec(v);
        }
    }
    let s = &run.equilibrium.stats;
    w.count(run.iterations);
    w.count(run.steps);
    w.count(s.iterations);
    w.count(usize::from(s.converged));
    w.floats(&[s.force, s.moment, s.lambda_min, s.energy]);
    w.count(usize::from(path.is_some()));
    if let Some(p) = path {
        w.path(p);
    }
    let payload = w.0;
    let mut out = head(fingerprint, &payload).into_bytes();
    out.extend_from_slice(&payload);
    out
}

fn head(fingerprint: u64, payload: &[u8]) -> String {
    format!(
        "{HEAD}\nformat {FORMAT}\nfingerprint {fingerprint:016x}\npayload {} bytes, fnv1a {:016x}\n\n",
        payload.len(),
        fnv1a(payload)
    )
}

/// Whether a state file was written for `fingerprint` and is whole (its
/// head names the fingerprint and its payload's length and hash).
pub(crate) fn written_for(bytes: &[u8], fingerprint: u64) -> bool {
    payload_for(bytes, fingerprint).is_some()
}

/// The payload of a state file written for `fingerprint` and whole.
fn payload_for(bytes: &[u8], fingerprint: u64) -> Option<&[u8]> {
    let split = bytes.windows(2).position(|w| w == b"\n\n")? + 2;
    let payload = &bytes[split..];
    (bytes[..split] == *head(fingerprint, payload).as_bytes()).then_some(payload)
}

/// The simulation a state file holds, if it was written for `fingerprint`
/// and is whole: the model prepared as `sim::simulate_with` prepares it,
/// then put in the stored state, with the deployment path that reached it
/// when the build followed one. None for anything else (the caller
/// solves).
pub(crate) fn restore(
    bytes: &[u8],
    fingerprint: u64,
    lattice: &crate::lattice::Lattice,
    derived: &Derived<'_>,
    width: f64,
    thickness: f64,
    settings: &Settings,
) -> Option<(Simulation, Option<Path>)> {
    let clock = Instant::now();
    let payload = payload_for(bytes, fingerprint)?;
    let mut lm = prepare_with(lattice, derived, width, thickness, settings);
    let mut r = Reader(payload);
    let m = &mut lm.model;
    let sizes = [m.q.len(), m.ties.len(), m.edges.len(), m.joints.len()];
    for size in sizes {
        (r.count()? == size).then_some(())?;
    }
    for q in &mut m.q {
        *q = r.float()?;
    }
    for t in &mut m.ties {
        t.offset = r.float()?;
    }
    for e in &mut m.edges {
        if let Frame::Ref { ts, as_, .. } = &mut e.frame {
            *ts = r.vec()?;
            *as_ = r.vec()?;
        }
    }
    for j in &mut m.joints {
        for v in &mut j.frame {
            *v = r.vec()?;
        }
    }
    let (iterations, steps) = (r.count()?, r.count()?);
    let stats = Stats {
        iterations: r.count()?,
        converged: r.count()? == 1,
        force: r.float()?,
        moment: r.float()?,
        lambda_min: r.float()?,
        energy: r.float()?,
    };
    let path = match r.count()? {
        0 => None,
        1 => Some(r.path()?),
        _ => return None,
    };
    // Only a converged state (every number is finite: `Reader::float`).
    if !r.0.is_empty() || !stats.converged {
        return None;
    }
    // The energy the solver ended with, recomputed: a last guard that the
    // state fits the model.
    let e = m.energy();
    if !((e - stats.energy).abs() <= 1e-9 * (stats.energy.abs() + m.e_scale)) {
        return None;
    }
    // What a fresh solve reports on its model, reported on this one.
    let run = Simulation {
        iterations,
        steps,
        theta: lm.held_opening(),
        equilibrium: equilibrium(&lm, stats, &settings.material),
        seconds: clock.elapsed().as_secs_f64(),
        lm,
    };
    Some((run, path))
}

#[derive(Default)]
struct Words(Vec<u8>);

impl Words {
    fn count(&mut self, n: usize) {
        self.0.extend_from_slice(&(n as u64).to_le_bytes());
    }
    fn float(&mut self, x: f64) {
        self.0.extend_from_slice(&x.to_bits().to_le_bytes());
    }
    fn floats(&mut self, xs: &[f64]) {
        xs.iter().for_each(|&x| self.float(x));
    }
    fn vec(&mut self, v: DVec3) {
        self.floats(&v.to_array());
    }
    fn text(&mut self, t: &str) {
        self.count(t.len());
        self.0.extend_from_slice(t.as_bytes());
    }
    fn path(&mut self, p: &Path) {
        self.floats(&[p.design, p.low, p.hysteresis]);
        self.count(p.steps);
        self.count(p.iterations);
        self.count(p.budget);
        for way in [&p.collapse, &p.deploy] {
            self.count(way.len());
            way.iter().for_each(|q| self.point(q));
        }
        self.count(usize::from(p.failed.is_some()));
        if let Some((theta, why)) = &p.failed {
            self.float(*theta);
            self.text(why);
        }
        self.count(usize::from(p.end_distance.is_some()));
        self.float(p.end_distance.unwrap_or(0.0));
    }
    fn point(&mut self, q: &PathPoint) {
        let (lo, hi) = q.openings;
        self.floats(&[q.theta, q.energy, q.strain, q.lambda_min, q.jump, lo, hi]);
        self.text(&q.rod);
        self.count(q.iterations);
        self.count(usize::from(q.leapt));
        self.count(q.points.len());
        q.points.iter().for_each(|&v| self.vec(v));
    }
}

struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn word(&mut self) -> Option<u64> {
        let (head, rest) = self.0.split_first_chunk::<8>()?;
        self.0 = rest;
        Some(u64::from_le_bytes(*head))
    }
    fn count(&mut self) -> Option<usize> {
        usize::try_from(self.word()?).ok()
    }
    /// A finite number: a NaN would slip through the comparisons that
    /// guard a restore.
    fn float(&mut self) -> Option<f64> {
        Some(f64::from_bits(self.word()?)).filter(|x| x.is_finite())
    }
    fn vec(&mut self) -> Option<DVec3> {
        Some(DVec3::new(self.float()?, self.float()?, self.float()?))
    }
    fn text(&mut self) -> Option<String> {
        let n = self.count()?;
        (n <= self.0.len()).then_some(())?;
        let (t, rest) = self.0.split_at(n);
        self.0 = rest;
        String::from_utf8(t.to_vec()).ok()
    }
    /// A count of items that each take at least `least` bytes: no larger
    /// than what is left (a damaged count must not allocate much).
    fn items(&mut self, least: usize) -> Option<usize> {
        let n = self.count()?;
        (n.saturating_mul(least) <= self.0.len()).then_some(n)
    }
    fn path(&mut self) -> Option<Path> {
        let (design, low, hysteresis) = (self.float()?, self.float()?, self.float()?);
        let (steps, iterations, budget) = (self.count()?, self.count()?, self.count()?);
        let mut ways = [Vec::new(), Vec::new()];
        for way in &mut ways {
            let n = self.items(8)?;
            for _ in 0..n {
                way.push(self.point()?);
            }
        }
        let failed = match self.count()? {
            0 => None,
            1 => Some((self.float()?, self.text()?)),
            _ => return None,
        };
        let known = self.count()? == 1;
        let d = self.float()?;
        let [collapse, deploy] = ways;
        Some(Path {
            design,
            low,
            steps,
            iterations,
            budget,
            collapse,
            deploy,
            failed,
            end_distance: known.then_some(d),
            hysteresis,
        })
    }
    fn point(&mut self) -> Option<PathPoint> {
        let f: Vec<f64> = (0..7).map(|_| self.float()).collect::<Option<_>>()?;
        let rod = self.text()?;
        let iterations = self.count()?;
        let leapt = match self.count()? {
            0 => false,
            1 => true,
            _ => return None,
        };
        let n = self.items(24)?;
        let points = (0..n).map(|_| self.vec()).collect::<Option<_>>()?;
        Some(PathPoint {
            theta: f[0],
            energy: f[1],
            strain: f[2],
            lambda_min: f[3],
            jump: f[4],
            openings: (f[5], f[6]),
            rod,
            iterations,
            leapt,
            points,
        })
    }
}
