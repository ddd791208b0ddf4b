//! A target's triangles and what is checked of them (docs/design.md,
//! "Validation"): finite corners, no zero-area triangle, every edge on at
//! most two triangles, one piece, a size in millimetres that looks right;
//! and its topology, from its boundary loops and Euler characteristic.

use super::Expect;
use crate::diagnostic::shown;
use glam::DVec3;
use rustc_hash::FxHashMap;

/// Triangles in millimetres.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Corner positions (mm).
    pub positions: Vec<DVec3>,
    /// Each triangle's three corners, indices into `positions`.
    pub triangles: Vec<[u32; 3]>,
}

/// The topology of a connected triangle mesh, from its boundary loops b
/// and Euler characteristic chi = V - E + F.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Topology {
    /// One boundary loop, chi = 1: a disk's topology (a cap, a plate).
    Patch,
    /// Two boundary loops, chi = 0: a band or a tube segment.
    Annulus,
    /// No boundary: a closed surface with `genus` handles (chi = 2 - 2g).
    Closed {
        /// 0 for a sphere, 1 for a torus.
        genus: i64,
    },
    /// Anything else: a patch with handles or holes.
    Other {
        /// Boundary loops.
        boundaries: usize,
        /// V - E + F.
        euler: i64,
    },
}

impl Topology {
    /// In words, for reports and messages.
    pub fn describe(self) -> String {
        match self {
            Topology::Patch => "an open patch (one boundary loop)".into(),
            Topology::Annulus => "an annulus or tube segment (two boundary loops)".into(),
            Topology::Closed { genus: 0 } => {
                "a closed surface (no boundary; a sphere's topology)".into()
            }
            Topology::Closed { genus: 1 } => {
                "a closed surface (no boundary; a torus's topology)".into()
            }
            Topology::Closed { genus } => format!("a closed surface (no boundary, genus {genus})"),
            Topology::Other { boundaries, euler } => format!(
                "a surface with {boundaries} boundary loops and Euler characteristic {euler}"
            ),
        }
    }

    fn is(self, expect: Expect) -> bool {
        matches!(
            (self, expect),
            (Topology::Patch, Expect::Patch)
                | (Topology::Annulus, Expect::Annulus)
                | (Topology::Closed { .. }, Expect::Closed)
        )
    }
}

/// What is wrong with a mesh, and where: a triangle or a corner in the
/// numbering of the mesh given to `validated` (the reader maps it to its
/// file's face or line).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Fault {
    pub(crate) kind: crate::diagnostic::ErrorKind,
    pub(crate) message: String,
    pub(crate) hint: String,
    pub(crate) triangle: Option<usize>,
    pub(crate) corner: Option<usize>,
}

impl Fault {
    fn new(kind: crate::diagnostic::ErrorKind, message: String, hint: &str) -> Self {
        Self {
            kind,
            message,
            hint: hint.to_string(),
            triangle: None,
            corner: None,
        }
    }
}

/// Sizes karigami makes: a target whose largest extent lies outside was
/// almost surely written in other units than millimetres.
pub(crate) const MIN_EXTENT: f64 = 20.0;
pub(crate) const MAX_EXTENT: f64 = 10_000.0;

/// A triangle is degenerate when its height is below this share of its
/// longest edge: zero area up to rounding, not merely a thin sliver.
const DEGENERATE: f64 = 1e-10;

impl Mesh {
    /// The sum of the triangles' areas.
    /// The boundary loops, each as corner indices in the order its
    /// triangles run, the longest loop (in corners) first, each starting at
    /// its lowest index: deterministic.
    pub fn boundary_loops(&self) -> Vec<Vec<u32>> {
        let mut count: FxHashMap<(u32, u32), u32> = FxHashMap::default();
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        let mut next: FxHashMap<u32, u32> = FxHashMap::default();
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if count[&(a.min(b), a.max(b))] == 1 {
                    next.insert(a, b);
                }
            }
        }
        let mut starts: Vec<u32> = next.keys().copied().collect();
        starts.sort_unstable();
        let mut seen = rustc_hash::FxHashSet::default();
        let mut loops = Vec::new();
        for s in starts {
            let mut chain = Vec::new();
            let mut v = s;
            while seen.insert(v) {
                chain.push(v);
                match next.get(&v) {
                    Some(&n) => v = n,
                    None => break,
                }
            }
            if !chain.is_empty() {
                loops.push(chain);
            }
        }
        loops.sort_by_key(|l| std::cmp::Reverse(l.len()));
        loops
    }

    pub(crate) fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| self.triangle_area(t))
            .sum()
    }

    pub(crate) fn corners(&self, t: usize) -> [DVec3; 3] {
        self.triangles[t].map(|i| self.positions[i as usize])
    }

    pub(crate) fn triangle_area(&self, t: usize) -> f64 {
        let [a, b, c] = self.corners(t);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Corners at the same position made one (bit for bit, so a file's
    /// shared corners join and nothing else does), unused corners dropped.
    fn welded(&self) -> Mesh {
        let mut index: FxHashMap<[u64; 3], u32> = FxHashMap::default();
        let mut positions = Vec::new();
        let key = |p: DVec3| (p + DVec3::ZERO).to_array().map(f64::to_bits);
        let triangles = self
            .triangles
            .iter()
            .map(|t| {
                t.map(|i| {
                    let p = self.positions[i as usize];
                    *index.entry(key(p)).or_insert_with(|| {
                        positions.push(p);
                        (positions.len() - 1) as u32
                    })
                })
            })
            .collect();
        Mesh {
            positions,
            triangles,
        }
    }
}

/// The mesh validated, welded, with its topology and largest extent D;
/// or the first fault found, in the order of docs/design.md.
/// `name` says a triangle's place in the file: "triangle 12", "face 7".
pub(crate) fn validated(
    mesh: &Mesh,
    expect: Option<Expect>,
    name: &dyn Fn(usize) -> String,
) -> Result<(Mesh, Topology, f64), Fault> {
    use crate::diagnostic::ErrorKind;
    if mesh.triangles.is_empty() {
        return Err(Fault::new(
            ErrorKind::TargetEmpty,
            "the target has no triangles".into(),
            "export the surface as triangles (or polygons) in millimetres",
        ));
    }
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for &i in tri {
            if !mesh.positions[i as usize].is_finite() {
                let mut f = Fault::new(
                    ErrorKind::TargetNotFinite,
                    format!(
                        "{} has a corner that is not a finite point: {:?}",
                        name(t),
                        mesh.positions[i as usize].to_array()
                    ),
                    "every coordinate must be an ordinary number; export the mesh again or remove the triangle",
                );
                f.triangle = Some(t);
                f.corner = Some(i as usize);
                return Err(f);
            }
        }
    }
    let welded = mesh.welded();
    degenerate(&welded, name)?;
    let topology = topology(&welded, name)?;
    let extent = super::extent::diameter(&welded.positions);
    units(extent)?;
    if let Some(want) = expect
        && !topology.is(want)
    {
        return Err(Fault::new(
            ErrorKind::TargetTopology,
            format!(
                "the target is {}, but {} was expected",
                topology.describe(),
                match want {
                    Expect::Patch => "an open patch (one boundary loop)",
                    Expect::Annulus => "an annulus (two boundary loops)",
                    Expect::Closed => "a closed surface",
                }
            ),
            "cut the surface open where the design should end (a cap of a closed shape, a band of a tube), or ask for the topology it has",
        ));
    }
    Ok((welded, topology, extent))
}

fn degenerate(mesh: &Mesh, name: &dyn Fn(usize) -> String) -> Result<(), Fault> {
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        let longest = a.distance(b).max(b.distance(c)).max(c.distance(a));
        let height = 2.0 * mesh.triangle_area(t) / longest.max(f64::MIN_POSITIVE);
        if !(height > DEGENERATE * longest) {
            let mut f = Fault::new(
                crate::diagnostic::ErrorKind::TargetDegenerate,
                format!(
                    "{} is degenerate: its corners {} lie on a line (area {} mm^2)",
                    name(t),
                    [a, b, c]
                        .map(|p| format!("({}, {}, {})", shown(p.x), shown(p.y), shown(p.z)))
                        .join(", "),
                    shown(mesh.triangle_area(t))
                ),
                "remove the triangle or merge its corners (a modeller's 'clean up' or 'merge by distance')",
            );
            f.triangle = Some(t);
            return Err(f);
        }
    }
    Ok(())
}

/// Each edge's triangles; an edge on three or more is non-manifold.
fn edges(
    mesh: &Mesh,
    name: &dyn Fn(usize) -> String,
) -> Result<FxHashMap<(u32, u32), [usize; 2]>, Fault> {
    let mut edges: FxHashMap<(u32, u32), [usize; 2]> = FxHashMap::default();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            let slot = edges.entry(key).or_insert([usize::MAX; 2]);
            if slot[0] == usize::MAX {
                slot[0] = t;
            } else if slot[1] == usize::MAX {
                slot[1] = t;
            } else {
                let mut f = Fault::new(
                    crate::diagnostic::ErrorKind::TargetNonManifold,
                    format!(
                        "{} shares an edge with {} and {}: an edge of a surface joins at most two triangles (non-manifold)",
                        name(t),
                        name(slot[0]),
                        name(slot[1])
                    ),
                    "remove the extra triangle, or split the mesh where the sheets meet",
                );
                f.triangle = Some(t);
                return Err(f);
            }
        }
    }
    Ok(edges)
}

/// Boundary loops and the Euler characteristic, after checking the mesh is
/// one piece and each boundary corner has exactly two boundary edges.
fn topology(mesh: &Mesh, name: &dyn Fn(usize) -> String) -> Result<Topology, Fault> {
    use crate::diagnostic::ErrorKind;
    let edges = edges(mesh, name)?;
    let mut pieces = UnionFind::new(mesh.positions.len());
    for tri in &mesh.triangles {
        pieces.join(tri[0], tri[1]);
        pieces.join(tri[1], tri[2]);
    }
    let root = pieces.find(0);
    if let Some(t) = mesh
        .triangles
        .iter()
        .position(|t| pieces.find(t[0]) != root)
    {
        let mut f = Fault::new(
            ErrorKind::TargetPieces,
            format!(
                "the target is more than one piece: {} is not joined to {}",
                name(t),
                name(0)
            ),
            "give one connected surface; remove the loose parts or join them",
        );
        f.triangle = Some(t);
        return Err(f);
    }
    // Boundary edges: on one triangle. Each boundary corner has two.
    let mut boundary_degree: FxHashMap<u32, u32> = FxHashMap::default();
    let mut loops = UnionFind::new(mesh.positions.len());
    let mut sorted: Vec<_> = edges.iter().filter(|(_, t)| t[1] == usize::MAX).collect();
    sorted.sort_unstable_by_key(|(e, _)| **e);
    for (&(a, b), t) in sorted {
        loops.join(a, b);
        for v in [a, b] {
            let d = boundary_degree.entry(v).or_insert(0);
            *d += 1;
            if *d > 2 {
                let mut f = Fault::new(
                    ErrorKind::TargetNonManifold,
                    format!(
                        "{} meets the rest of the surface at a single corner: more than two boundary edges end there (non-manifold)",
                        name(t[0])
                    ),
                    "separate the surfaces that touch at one point, or fill the gap between them",
                );
                f.triangle = Some(t[0]);
                f.corner = Some(v as usize);
                return Err(f);
            }
        }
    }
    let mut roots: Vec<u32> = boundary_degree.keys().map(|&v| loops.find(v)).collect();
    roots.sort_unstable();
    roots.dedup();
    let b = roots.len();
    let euler = mesh.positions.len() as i64 - edges.len() as i64 + mesh.triangles.len() as i64;
    Ok(match (b, euler) {
        (0, e) => Topology::Closed { genus: (2 - e) / 2 },
        (1, 1) => Topology::Patch,
        (2, 0) => Topology::Annulus,
        (boundaries, euler) => Topology::Other { boundaries, euler },
    })
}

/// A largest extent outside `MIN_EXTENT..=MAX_EXTENT` mm is refused, with
/// the scale that would bring it to a size karigami makes.
fn units(extent: f64) -> Result<(), Fault> {
    if (MIN_EXTENT..=MAX_EXTENT).contains(&extent) {
        return Ok(());
    }
    // The usual units a modeller writes, and the scale from each to mm.
    let units = [
        ("metres", 1000.0),
        ("inches", 25.4),
        ("centimetres", 10.0),
        ("micrometres", 0.001),
    ];
    let aim = (MIN_EXTENT * MAX_EXTENT).sqrt().ln();
    let (unit, scale) = units
        .iter()
        .filter(|(_, s)| (MIN_EXTENT..=MAX_EXTENT).contains(&(extent * s)))
        .min_by(|a, b| {
            let off = |s: f64| ((extent * s).ln() - aim).abs();
            off(a.1).total_cmp(&off(b.1))
        })
        .copied()
        .unwrap_or(("other units", 1.0));
    let (size, bound) = if extent < MIN_EXTENT {
        ("small", format!("at least {} mm", shown(MIN_EXTENT)))
    } else {
        ("large", format!("at most {} m", shown(MAX_EXTENT / 1000.0)))
    };
    let hint = if scale == 1.0 {
        "coordinates are read as millimetres: scale the target to a size between 20 mm and 10 m"
            .to_string()
    } else {
        format!(
            "coordinates are read as millimetres: if the file is in {unit}, scale it by {} (to {} mm across)",
            shown(scale),
            shown((extent * scale * 10.0).round() / 10.0)
        )
    };
    let across = if extent >= MAX_EXTENT {
        format!("{} m", shown((extent / 100.0).round() / 10.0))
    } else {
        format!(
            "{} mm",
            shown(format!("{extent:.4}").parse().unwrap_or(extent))
        )
    };
    Err(Fault::new(
        crate::diagnostic::ErrorKind::TargetUnits,
        format!(
            "the target is {across} across, too {size} for a karigami design ({bound}): its units look wrong"
        ),
        &hint,
    ))
}

struct UnionFind(Vec<u32>);

impl UnionFind {
    fn new(n: usize) -> Self {
        Self((0..n as u32).collect())
    }

    fn find(&mut self, mut v: u32) -> u32 {
        while self.0[v as usize] != v {
            let up = self.0[self.0[v as usize] as usize];
            self.0[v as usize] = up;
            v = up;
        }
        v
    }

    fn join(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.0[a.max(b) as usize] = a.min(b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle(t: usize) -> String {
        format!("triangle {}", t + 1)
    }

    fn grid(n: u32, wrap: bool) -> Mesh {
        // An n x n grid of unit squares, 100 mm each; `wrap` joins the
        // last column to the first (a tube).
        let cols = if wrap { n } else { n + 1 };
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..cols {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                positions.push(if wrap {
                    DVec3::new(100.0 * a.cos(), 100.0 * a.sin(), 100.0 * j as f64)
                } else {
                    DVec3::new(100.0 * i as f64, 100.0 * j as f64, 0.0)
                });
            }
        }
        let at = |i: u32, j: u32| j * cols + i % cols;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
        Mesh {
            positions,
            triangles,
        }
    }

    #[test]
    fn boundary_loops_and_euler_give_the_topology() {
        let (_, t, _) = validated(&grid(3, false), None, &triangle).unwrap();
        assert_eq!(t, Topology::Patch);
        let (_, t, _) = validated(&grid(6, true), None, &triangle).unwrap();
        assert_eq!(t, Topology::Annulus);
        // A plate with a hole is an annulus too.
        let mut holed = grid(3, false);
        holed.triangles.drain(8..10);
        let (_, t, _) = validated(&holed, None, &triangle).unwrap();
        assert_eq!(t, Topology::Annulus);
        // With two holes: squares (1, 1) and (3, 3) of a 5 x 5 grid.
        let mut holed = grid(5, false);
        holed.triangles.drain(36..38);
        holed.triangles.drain(12..14);
        let (_, t, _) = validated(&holed, None, &triangle).unwrap();
        assert_eq!(
            t,
            Topology::Other {
                boundaries: 3,
                euler: -1
            }
        );
        let e = validated(&grid(3, false), Some(Expect::Annulus), &triangle).unwrap_err();
        assert_eq!(e.kind, crate::diagnostic::ErrorKind::TargetTopology);
    }

    #[test]
    fn a_tetrahedron_is_closed_of_genus_zero() {
        let mesh = Mesh {
            positions: vec![
                DVec3::ZERO,
                DVec3::X * 100.0,
                DVec3::Y * 100.0,
                DVec3::Z * 100.0,
            ],
            triangles: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
        };
        let (_, t, d) = validated(&mesh, None, &triangle).unwrap();
        assert_eq!(t, Topology::Closed { genus: 0 });
        assert!((d - 100.0 * 2f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn units_suggest_the_scale_that_makes_millimetres() {
        let hint = |d: f64| units(d).unwrap_err().hint;
        assert!(
            hint(0.3).contains("metres, scale it by 1000 (to 300 mm"),
            "{}",
            hint(0.3)
        );
        assert!(
            hint(12.0).contains("inches, scale it by 25.4"),
            "{}",
            hint(12.0)
        );
        assert!(hint(300_000.0).contains("micrometres, scale it by 0.001 (to 300 mm"));
        assert!(units(450.0).is_ok() && units(20.0).is_ok() && units(10_000.0).is_ok());
    }
}
