//! Deployment (MATH.md 8.4): the intrinsic configuration C(theta), its
//! valid range, the mobility of the ideal linkage at the design state, and
//! for planar lattices how far a rigid placement of the cells misses at
//! other angles.

use super::{Cell, Lattice};
use glam::{DVec2, DVec3};

/// Lattices up to this many cells get a mobility count (a dense-ish
/// elimination over every point of the linkage).
pub(crate) const MOBILITY_MAX_CELLS: usize = 2_000;

/// Fractions of the design angle at which a planar placement is tried.
pub(crate) const MISFIT_FRACTIONS: [f64; 3] = [0.99, 0.9, 0.5];

/// `cos(phi)` of one cell as an affine function `a + b cos(theta)` of the
/// reference cell's opening.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Affine {
    a: f64,
    b: f64,
}

impl Affine {
    fn at(self, cos_theta: f64) -> f64 {
        self.a + self.b * cos_theta
    }
}

/// The four edges of a cell: which corners they join, and their squared
/// length as `alpha + beta cos(phi)` (MATH.md 2).
fn edges(cell: &Cell, legs: [f64; 4]) -> [((u32, u32), f64, f64); 4] {
    let [l1, l2, l3, l4] = legs;
    [
        (key(cell.ul, cell.ur), l1 * l1 + l4 * l4, -2.0 * l1 * l4),
        (key(cell.ll, cell.lr), l2 * l2 + l3 * l3, -2.0 * l2 * l3),
        (key(cell.ul, cell.ll), l1 * l1 + l2 * l2, 2.0 * l1 * l2),
        (key(cell.ur, cell.lr), l3 * l3 + l4 * l4, 2.0 * l3 * l4),
    ]
}

fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// `cos(phi)` of a cell in its design state: the angle at the pivot between
/// the legs to UL and to UR.
fn design_cos(lattice: &Lattice, cell: &Cell) -> f64 {
    let [ul, ur, _, _] = lattice.corners(cell);
    (ul - cell.pivot)
        .normalize()
        .dot((ur - cell.pivot).normalize())
}

/// The intrinsic configuration C(theta): every cell's opening as a function
/// of the reference cell's.
#[derive(Clone, Debug)]
pub struct Configuration {
    cos_phi: Vec<Affine>,
    /// Opening of the reference cell in the design (radians).
    pub theta_design: f64,
    /// The reference opening at which the first cell reaches phi = pi.
    pub theta_max: f64,
    /// Largest disagreement of two propagation paths (MATH.md 8.4:
    /// compatibility is path independence).
    pub path_residual: f64,
    /// Largest |cos(phi(theta_design)) - cos(phi_design)| over the cells.
    pub design_residual: f64,
    /// Largest |cos(phi(0)) - 1|: theta = 0 collapses every cell.
    pub collapse_residual: f64,
    /// Cells the propagation did not reach (a disconnected lattice).
    pub unreached: usize,
}

impl Configuration {
    /// `phi` of every cell at the reference opening `theta`, or None for
    /// a theta outside [0, theta_max].
    pub fn angles(&self, theta: f64) -> Option<Vec<f64>> {
        if !(0.0..=self.theta_max).contains(&theta) {
            return None;
        }
        let c = theta.cos();
        Some(
            self.cos_phi
                .iter()
                .map(|f| f.at(c).clamp(-1.0, 1.0).acos())
                .collect(),
        )
    }
}

/// Propagate cos(phi) from the reference cell (cell 0) through shared edges
/// by breadth-first search. The cells sharing an edge are found through
/// their corners (a vertex's cells in increasing order, in flat arrays):
/// linear time and a few words a cell, where a map of edges took a heap
/// list per edge.
pub fn configuration(lattice: &Lattice) -> Configuration {
    let n = lattice.cells.len();
    let legs: Vec<[f64; 4]> = lattice.cells.iter().map(|c| lattice.legs(c)).collect();
    let corners = |c: &Cell| [c.ul, c.ur, c.ll, c.lr];
    // users[start[v]..start[v + 1]]: the cells with corner v, increasing.
    let mut start = vec![0u32; lattice.vertices.len() + 1];
    for cell in &lattice.cells {
        for v in corners(cell) {
            start[v as usize + 1] += 1;
        }
    }
    for v in 1..start.len() {
        start[v] += start[v - 1];
    }
    let mut users = vec![0u32; 4 * n];
    {
        let mut fill = start.clone();
        for (i, cell) in lattice.cells.iter().enumerate() {
            for v in corners(cell) {
                users[fill[v as usize] as usize] = i as u32;
                fill[v as usize] += 1;
            }
        }
    }
    let (cos_phi, reached, path_residual) = match edge_neighbours(lattice, &users, &start) {
        Some(nbr) => {
            drop((users, start));
            propagate(&nbr, &legs)
        }
        None => propagate_shared(lattice, &legs, &users, &start),
    };
    drop(legs);
    let unreached = reached.iter().filter(|r| !**r).count();
    let theta_design = lattice
        .cells
        .first()
        .map_or(0.0, |c| design_cos(lattice, c).clamp(-1.0, 1.0).acos());
    let c_design = theta_design.cos();
    let mut design_residual: f64 = 0.0;
    let mut collapse_residual: f64 = 0.0;
    // Each cos(phi) falls as cos(theta) falls; the range ends where the
    // first cell opens flat past pi (cos(phi) = -1).
    let mut c_min: f64 = -1.0;
    for (f, cell) in cos_phi.iter().zip(&lattice.cells) {
        design_residual = design_residual.max((f.at(c_design) - design_cos(lattice, cell)).abs());
        collapse_residual = collapse_residual.max((f.at(1.0) - 1.0).abs());
        if f.b > 0.0 {
            c_min = c_min.max((-1.0 - f.a) / f.b);
        }
    }
    Configuration {
        cos_phi,
        theta_design,
        theta_max: c_min.clamp(-1.0, 1.0).acos(),
        path_residual,
        design_residual,
        collapse_residual,
        unreached,
    }
}

/// The propagation of `configuration` when an edge has more than two
/// cells: every cell sharing each edge, found through its corners.
fn propagate_shared(
    lattice: &Lattice,
    legs: &[[f64; 4]],
    users: &[u32],
    start: &[u32],
) -> (Vec<Affine>, Vec<bool>, f64) {
    let n = lattice.cells.len();
    let mut cos_phi = vec![Affine { a: 1.0, b: 0.0 }; n];
    let mut reached = vec![false; n];
    let mut path_residual: f64 = 0.0;
    // A queue in which every cell enters once.
    let mut queue: Vec<u32> = Vec::with_capacity(n);
    if n > 0 {
        cos_phi[0] = Affine { a: 0.0, b: 1.0 };
        reached[0] = true;
        queue.push(0);
    }
    let mut head = 0;
    while head < queue.len() {
        let i = queue[head] as usize;
        head += 1;
        let f = cos_phi[i];
        for (k, alpha, beta) in edges(&lattice.cells[i], legs[i]) {
            // The squared edge as a function of cos(theta), then the
            // neighbour's cos(phi) from its own formula for that edge.
            let (ea, eb) = (alpha + beta * f.a, beta * f.b);
            let near = &users[start[k.0 as usize] as usize..start[k.0 as usize + 1] as usize];
            for (u, &j) in near.iter().enumerate() {
                let j = j as usize;
                // A cell with a repeated corner is listed twice.
                if j == i || (u > 0 && near[u - 1] as usize == j) {
                    continue;
                }
                for (kj, alpha_j, beta_j) in edges(&lattice.cells[j], legs[j]) {
                    if kj != k {
                        continue;
                    }
                    let g = Affine {
                        a: (ea - alpha_j) / beta_j,
                        b: eb / beta_j,
                    };
                    if reached[j] {
                        let h = cos_phi[j];
                        path_residual = path_residual.max((h.a - g.a).abs() + (h.b - g.b).abs())
                    } else {
                        cos_phi[j] = g;
                        reached[j] = true;
                        queue.push(j as u32);
                    }
                }
            }
        }
    }
    (cos_phi, reached, path_residual)
}

/// Marks "no cell" in `edge_neighbours`.
const NO_CELL: u32 = u32::MAX;

/// For every cell and each of its edges (in the order of `edges`), the
/// other cell sharing that edge as `cell | edge << 30` (`NO_CELL` on the
/// boundary); None when some edge has more than two cells or a cell has a
/// repeated corner (then `propagate_shared` does it).
fn edge_neighbours(lattice: &Lattice, users: &[u32], start: &[u32]) -> Option<Vec<[u32; 4]>> {
    if lattice.cells.len() >= 1 << 30 {
        return None;
    }
    let mut nbr = vec![[NO_CELL; 4]; lattice.cells.len()];
    for (i, cell) in lattice.cells.iter().enumerate() {
        let c = [cell.ul, cell.ur, cell.ll, cell.lr];
        if (0..4).any(|a| (a + 1..4).any(|b| c[a] == c[b])) {
            return None;
        }
        let keys = edge_keys(cell);
        for (e, k) in keys.into_iter().enumerate() {
            let near = &users[start[k.0 as usize] as usize..start[k.0 as usize + 1] as usize];
            for &j in near {
                if j as usize == i {
                    continue;
                }
                for (ej, kj) in edge_keys(&lattice.cells[j as usize])
                    .into_iter()
                    .enumerate()
                {
                    if kj == k {
                        if nbr[i][e] != NO_CELL {
                            return None;
                        }
                        nbr[i][e] = j | (ej as u32) << 30;
                    }
                }
            }
        }
    }
    Some(nbr)
}

/// The vertex pairs of a cell's edges, in the order of `edges`.
fn edge_keys(cell: &Cell) -> [(u32, u32); 4] {
    [
        key(cell.ul, cell.ur),
        key(cell.ll, cell.lr),
        key(cell.ul, cell.ll),
        key(cell.ur, cell.lr),
    ]
}

/// `alpha` and `beta` of edge `e` (in the order of `edges`) of a cell with
/// these legs: the same products as `edges`.
#[inline]
fn edge_coefficients(legs: [f64; 4], e: usize) -> (f64, f64) {
    let [l1, l2, l3, l4] = legs;
    match e {
        0 => (l1 * l1 + l4 * l4, -2.0 * l1 * l4),
        1 => (l2 * l2 + l3 * l3, -2.0 * l2 * l3),
        2 => (l1 * l1 + l2 * l2, 2.0 * l1 * l2),
        _ => (l3 * l3 + l4 * l4, 2.0 * l3 * l4),
    }
}

/// The breadth-first propagation of `configuration` over precomputed edge
/// neighbours: the same visits in the same order as `propagate_shared`,
/// touching a few words a cell (the search jumps across the lattice, so
/// what it reads is what it costs).
fn propagate(nbr: &[[u32; 4]], legs: &[[f64; 4]]) -> (Vec<Affine>, Vec<bool>, f64) {
    let n = nbr.len();
    let mut cos_phi = vec![Affine { a: 1.0, b: 0.0 }; n];
    let mut reached = vec![false; n];
    let mut path_residual: f64 = 0.0;
    let mut queue: Vec<u32> = Vec::with_capacity(n);
    if n > 0 {
        cos_phi[0] = Affine { a: 0.0, b: 1.0 };
        reached[0] = true;
        queue.push(0);
    }
    let mut head = 0;
    while head < queue.len() {
        let i = queue[head] as usize;
        head += 1;
        let f = cos_phi[i];
        for (e, &other) in nbr[i].iter().enumerate() {
            if other == NO_CELL {
                continue;
            }
            let (alpha, beta) = edge_coefficients(legs[i], e);
            let (ea, eb) = (alpha + beta * f.a, beta * f.b);
            let (j, ej) = ((other & ((1 << 30) - 1)) as usize, (other >> 30) as usize);
            let (alpha_j, beta_j) = edge_coefficients(legs[j], ej);
            let g = Affine {
                a: (ea - alpha_j) / beta_j,
                b: eb / beta_j,
            };
            if reached[j] {
                let h = cos_phi[j];
                path_residual = path_residual.max((h.a - g.a).abs() + (h.b - g.b).abs())
            } else {
                cos_phi[j] = g;
                reached[j] = true;
                queue.push(j as u32);
            }
        }
    }
    (cos_phi, reached, path_residual)
}

/// Internal degrees of freedom of the ideal linkage at the design state:
/// rods are rigid, scissor pivots revolute, vertex pivots revolute (2-D) or
/// spherical (3-D). Modelled on points (vertices and pivots): per rod two
/// hole distances and D - 1 collinearity conditions; the nullity of their
/// Jacobian minus the rigid motions. None for lattices larger than
/// `MOBILITY_MAX_CELLS` or with bent facets (no single deployed state).
pub fn mobility(lattice: &Lattice) -> Option<usize> {
    if lattice.cells.len() > MOBILITY_MAX_CELLS || !lattice.extrinsic() {
        return None;
    }
    let d = lattice.dim;
    let nv = lattice.vertices.len();
    // Columns ordered by lattice row (a pivot between its two rows) so that
    // the elimination stays banded.
    let mut points: Vec<(u64, usize)> = lattice
        .vertices
        .iter()
        .enumerate()
        .map(|(i, v)| ((v.key.row as u64 * 2) << 32 | i as u64, i))
        .collect();
    points.extend(
        lattice
            .cells
            .iter()
            .enumerate()
            .map(|(i, c)| ((c.row as u64 * 2 + 1) << 32 | i as u64, nv + i)),
    );
    points.sort_unstable();
    let mut column = vec![0; points.len()];
    for (k, &(_, p)) in points.iter().enumerate() {
        column[p] = k * d;
    }
    let n = points.len() * d;
    let mut rows: Vec<Vec<(usize, f64)>> = Vec::new();
    let push = |rows: &mut Vec<Vec<(usize, f64)>>, terms: &[(usize, DVec3, f64)]| {
        let mut row = Vec::new();
        for &(point, dir, weight) in terms {
            for axis in 0..d {
                let v = dir[axis] * weight;
                if v != 0.0 {
                    row.push((column[point] + axis, v));
                }
            }
        }
        rows.push(row);
    };
    for rod in lattice.rods() {
        let [s, p, e] = rod.hole_pos;
        let (si, pi, ei) = (rod.start as usize, nv + rod.cell, rod.end as usize);
        let u = (s - p).normalize();
        let w = (e - p).normalize();
        push(&mut rows, &[(si, u, 1.0), (pi, u, -1.0)]);
        push(&mut rows, &[(ei, w, 1.0), (pi, w, -1.0)]);
        let t = rod.legs[0] / rod.length();
        let axis = (e - s).normalize();
        for normal in normals(axis, d) {
            push(
                &mut rows,
                &[
                    (pi, normal, 1.0),
                    (si, normal, -(1.0 - t)),
                    (ei, normal, -t),
                ],
            );
        }
    }
    let rank = rank(rows, n);
    let rigid = if d == 2 { 3 } else { 6 };
    Some((n - rank).saturating_sub(rigid))
}

/// D - 1 unit vectors perpendicular to `axis` (in the plane when D = 2).
fn normals(axis: DVec3, d: usize) -> Vec<DVec3> {
    if d == 2 {
        return vec![DVec3::new(-axis.y, axis.x, 0.0)];
    }
    let helper = if axis.x.abs() < 0.9 {
        DVec3::X
    } else {
        DVec3::Y
    };
    let n1 = axis.cross(helper).normalize();
    vec![n1, axis.cross(n1)]
}

/// Numerical rank by Gaussian elimination with partial pivoting over sparse
/// rows (a pivot below 1e-9 of the largest entry counts as zero; rows are
/// unit-scaled geometric constraints).
fn rank(rows: Vec<Vec<(usize, f64)>>, n: usize) -> usize {
    // Rows as dense spans [lo, lo + len) so that banded rows stay short.
    let mut spans: Vec<(usize, Vec<f64>)> = rows
        .into_iter()
        .filter(|r| !r.is_empty())
        .map(|r| {
            let lo = r.iter().map(|t| t.0).min().unwrap_or(0);
            let hi = r.iter().map(|t| t.0).max().unwrap_or(0);
            let mut dense = vec![0.0; hi + 1 - lo];
            for (c, v) in r {
                dense[c - lo] += v;
            }
            (lo, dense)
        })
        .collect();
    spans.sort_by_key(|s| s.0);
    let scale = spans
        .iter()
        .flat_map(|s| s.1.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let tol = 1e-9 * scale.max(f64::MIN_POSITIVE);
    let mut rank = 0;
    let mut active: Vec<(usize, Vec<f64>)> = Vec::new();
    let mut next = 0;
    for col in 0..n {
        // Rows whose first possible non-zero is at or before this column.
        while next < spans.len() && spans[next].0 <= col {
            active.push(std::mem::take(&mut spans[next]));
            next += 1;
        }
        let entry = |r: &(usize, Vec<f64>)| r.1.get(col.wrapping_sub(r.0)).copied().unwrap_or(0.0);
        let Some(best) = (0..active.len())
            .max_by(|&a, &b| entry(&active[a]).abs().total_cmp(&entry(&active[b]).abs()))
        else {
            continue;
        };
        if entry(&active[best]).abs() <= tol {
            continue;
        }
        let pivot = active.swap_remove(best);
        rank += 1;
        let pv = entry(&pivot);
        for r in active.iter_mut() {
            let v = entry(r);
            if v == 0.0 {
                continue;
            }
            let factor = v / pv;
            let end = pivot.0 + pivot.1.len();
            if r.0 + r.1.len() < end {
                r.1.resize(end - r.0, 0.0);
            }
            for c in col..end {
                r.1[c - r.0] -= factor * pivot.1[c - pivot.0];
            }
        }
        // Rows that are now zero from here on can be dropped.
        active.retain(|r| {
            r.1[col.saturating_sub(r.0).min(r.1.len())..]
                .iter()
                .any(|v| v.abs() > tol)
        });
    }
    rank
}

/// The largest misfit (relative to the mean leg) of placing a planar
/// lattice's cells rigidly, in grid order, at the reference opening theta.
/// None for 3-D lattices and thetas outside the valid range.
pub fn planar_misfit(lattice: &Lattice, config: &Configuration, theta: f64) -> Option<f64> {
    if lattice.dim != 2 || !(0.0..=config.theta_max).contains(&theta) {
        return None;
    }
    // The arithmetic of `Configuration::angles`, a cell at a time.
    let cos_theta = theta.cos();
    let mut placed = vec![DVec2::ZERO; lattice.vertices.len()];
    let mut is_placed = vec![false; lattice.vertices.len()];
    let mut misfit: f64 = 0.0;
    for (i, cell) in lattice.cells.iter().enumerate() {
        let phi = config.cos_phi[i].at(cos_theta).clamp(-1.0, 1.0).acos();
        let corners = lattice.corners(cell);
        let p = cell.pivot;
        let [ul, ur, ll, lr] = corners;
        let legs = [
            p.distance(ul),
            p.distance(ll),
            p.distance(lr),
            p.distance(ur),
        ];
        let local = cell_at(corners, p, legs, phi);
        let ids = [cell.ul, cell.ur, cell.ll, cell.lr];
        let mut pairs = [(DVec2::ZERO, DVec2::ZERO); 4];
        let mut known = 0;
        for (&v, &q) in ids.iter().zip(&local) {
            if is_placed[v as usize] {
                pairs[known] = (q, placed[v as usize]);
                known += 1;
            }
        }
        let fit = rigid_fit(&pairs[..known]);
        let scale = legs.iter().sum::<f64>() / 4.0;
        for (&v, p) in ids.iter().zip(local) {
            let q = fit(p);
            if is_placed[v as usize] {
                misfit = misfit.max(placed[v as usize].distance(q) / scale);
            } else {
                placed[v as usize] = q;
                is_placed[v as usize] = true;
            }
        }
    }
    Some(misfit)
}

/// A cell's corners [UL, UR, LL, LR] at opening phi, in its own frame:
/// the leg to UL along +x from the pivot at the origin, the leg to UR
/// turned by phi on the same side as in the design. `corners` and `legs`
/// are the cell's (`Lattice::corners`, `Lattice::legs`).
fn cell_at(corners: [DVec3; 4], pivot: DVec3, legs: [f64; 4], phi: f64) -> [DVec2; 4] {
    let [ul, ur, _, _] = corners;
    let (a, b) = (ul - pivot, ur - pivot);
    let side = if a.x * b.y - a.y * b.x < 0.0 {
        -1.0
    } else {
        1.0
    };
    let [l1, l2, l3, l4] = legs;
    let dir_a = DVec2::X;
    let dir_b = DVec2::new(phi.cos(), side * phi.sin());
    [dir_a * l1, dir_b * l4, -dir_b * l2, -dir_a * l3]
}

/// The proper rigid motion taking the first points of `pairs` onto the
/// second (least squares); the identity when there are none.
fn rigid_fit(pairs: &[(DVec2, DVec2)]) -> impl Fn(DVec2) -> DVec2 + use<> {
    let n = pairs.len().max(1) as f64;
    let (cp, cq) = pairs
        .iter()
        .fold((DVec2::ZERO, DVec2::ZERO), |(a, b), (p, q)| {
            (a + *p, b + *q)
        });
    let (cp, cq) = (cp / n, cq / n);
    // The rotation angle maximising sum q'.R p' (2-D Kabsch).
    let (mut s, mut c) = (0.0, 0.0);
    for (p, q) in pairs {
        let (p, q) = (*p - cp, *q - cq);
        c += p.dot(q);
        s += p.x * q.y - p.y * q.x;
    }
    let angle = if pairs.len() < 2 { 0.0 } else { s.atan2(c) };
    let rot = DVec2::from_angle(angle);
    move |p: DVec2| cq + rot.rotate(p - cp)
}

/// Everything `karigami check` says about deployment.
#[derive(Clone, Debug)]
pub struct Deployment {
    /// The intrinsic configuration C(theta): every cell's opening as the
    /// reference cell opens.
    pub config: Configuration,
    /// Degrees of freedom of the ideal linkage at the design state (see
    /// `mobility`); None for large or bent-facet lattices.
    pub mobility: Option<usize>,
    /// (fraction of the design angle, misfit) for planar lattices.
    pub misfits: Vec<(f64, f64)>,
}

/// How `lattice` deploys: C(theta), the linkage's mobility and, for planar
/// lattices, the misfit of the cells at fractions of the design opening.
pub fn deployment(lattice: &Lattice) -> Deployment {
    let config = configuration(lattice);
    let misfits = MISFIT_FRACTIONS
        .iter()
        .filter_map(|&f| planar_misfit(lattice, &config, f * config.theta_design).map(|m| (f, m)))
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
                "a true mechanism: {m} internal degree{} of freedom, and its cells place exactly at every angle tried; it deploys by turning its pivots, strips straight",
                if m == 1 { "" } else { "s" }
            ),
            Some(m) if self.is_mechanism() => format!(
                "a mechanism at the design state: {m} internal degree{} of freedom (a first-order count); it can move by turning its pivots, strips straight",
                if m == 1 { "" } else { "s" }
            ),
            Some(m) if m > 0 => format!(
                "{m} internal degree{} of freedom at the design state, but the cells do not stay in place as it opens; it deploys through strip bending",
                if m == 1 { "" } else { "s" }
            ),
            Some(_) => "rigid as an ideal linkage (0 internal degrees of freedom): it deploys and collapses through strip bending, passing through incompatible states (docs/verification.md, Deployment)".into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Direction, Leg};
    use crate::lattice::{Kind, RowParams, grow};

    /// The propagation over precomputed neighbours visits the cells in the
    /// order of the general one and computes the same numbers, bit for bit.
    #[test]
    fn both_propagations_agree_bit_for_bit() {
        let points: Vec<DVec3> = (0..7)
            .map(|j| DVec3::new(10.0 * j as f64 + (j % 3) as f64, 0.3 * (j % 2) as f64, 0.0))
            .collect();
        let row = RowParams {
            start: 2,
            direction: Some(Direction::Angles {
                angle_deg: 50.0,
                tilt_deg: 0.0,
            }),
            left_leg: Leg::Match,
            right_leg: Leg::Match,
            ..RowParams::default()
        };
        let kappa = [0.5, -0.3, 0.2, 0.0, -0.4, 0.1];
        let lattice = grow(Kind::Sheet, 2, &points, &kappa, &vec![row; 5]).unwrap();
        let legs: Vec<[f64; 4]> = lattice.cells.iter().map(|c| lattice.legs(c)).collect();
        let corners = |c: &Cell| [c.ul, c.ur, c.ll, c.lr];
        let mut start = vec![0u32; lattice.vertices.len() + 1];
        for cell in &lattice.cells {
            for v in corners(cell) {
                start[v as usize + 1] += 1;
            }
        }
        for v in 1..start.len() {
            start[v] += start[v - 1];
        }
        let mut users = vec![0u32; 4 * lattice.cells.len()];
        let mut fill = start.clone();
        for (i, cell) in lattice.cells.iter().enumerate() {
            for v in corners(cell) {
                users[fill[v as usize] as usize] = i as u32;
                fill[v as usize] += 1;
            }
        }
        let nbr =
            edge_neighbours(&lattice, &users, &start).expect("a sheet's edges have two cells");
        let (fast, reached, residual) = propagate(&nbr, &legs);
        let (slow, reached_slow, residual_slow) = propagate_shared(&lattice, &legs, &users, &start);
        assert!(reached.iter().all(|r| *r));
        assert_eq!(reached, reached_slow);
        assert_eq!(residual.to_bits(), residual_slow.to_bits());
        assert!(residual > 0.0, "rounding differs along paths: {residual}");
        for (f, s) in fast.iter().zip(&slow) {
            assert_eq!(
                (f.a.to_bits(), f.b.to_bits()),
                (s.a.to_bits(), s.b.to_bits())
            );
        }
    }
}
