//! The intrinsic configuration C(theta) (docs/math.md 8.4): every cell's
//! opening as an affine function of the reference cell's, propagated
//! through shared edges, with how far two paths disagree.

use super::super::{Cell, Lattice, Legs};
use glam::DVec3;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// `cos(phi)` of one cell as an affine function `a + b cos(theta)` of the
/// reference cell's opening.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Affine {
    pub(crate) a: f64,
    pub(crate) b: f64,
}

impl Affine {
    #[inline]
    pub(crate) fn at(self, cos_theta: f64) -> f64 {
        self.a + self.b * cos_theta
    }
}

/// The vertex pairs of a cell's edges, in the order of `edge_coefficients`:
/// top, bottom, left, right.
fn edge_keys(cell: &Cell) -> [(u32, u32); 4] {
    [
        key(cell.ul, cell.ur),
        key(cell.ll, cell.lr),
        key(cell.ul, cell.ll),
        key(cell.ur, cell.lr),
    ]
}

fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// `alpha` and `beta` of edge `e` (in the order of `edge_keys`) of a cell
/// with these legs: its squared length is `alpha + beta cos(phi)` (docs/math.md 2).
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

/// `cos(phi)` of a cell in its design state: the angle at the pivot between
/// the legs to UL and to UR.
pub(super) fn design_cos(lattice: &Lattice, cell: &Cell) -> f64 {
    let [ul, ur, _, _] = lattice.corners(cell);
    (ul - cell.pivot)
        .normalize()
        .dot((ur - cell.pivot).normalize())
}

/// `design_cos` from the cell's corners and legs (`Lattice::legs`): a leg
/// is the length `normalize` divides by (`p - q` is exactly `-(q - p)`, so
/// their squares and roots agree bit for bit), and no square root is taken
/// again.
fn design_cos_with(corners: [DVec3; 4], pivot: DVec3, legs: &Legs) -> f64 {
    let [ul, ur, _, _] = corners;
    ((ul - pivot) * (1.0 / legs[0])).dot((ur - pivot) * (1.0 / legs[3]))
}

/// The reference cell's (cell 0's) opening in the design (radians; 0
/// without cells): `Configuration::theta_design`.
pub(super) fn theta_design(lattice: &Lattice) -> f64 {
    lattice
        .cells
        .first()
        .map_or(0.0, |c| design_cos(lattice, c).clamp(-1.0, 1.0).acos())
}

/// The intrinsic configuration C(theta): every cell's opening as a function
/// of the reference cell's.
#[derive(Clone, Debug)]
pub struct Configuration {
    pub(super) cos_phi: Vec<Affine>,
    /// Opening of the reference cell in the design (radians).
    pub theta_design: f64,
    /// The reference opening at which the first cell reaches phi = pi.
    pub theta_max: f64,
    /// Largest disagreement of two propagation paths (docs/math.md 8.4:
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
    /// Whether the reference opening `theta` lies in [0, theta_max].
    pub fn holds(&self, theta: f64) -> bool {
        (0.0..=self.theta_max).contains(&theta)
    }

    /// `phi` of every cell at the reference opening `theta`, or None for
    /// a theta outside [0, theta_max].
    pub fn angles(&self, theta: f64) -> Option<Vec<f64>> {
        if !self.holds(theta) {
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

/// The cells with each corner, in flat arrays: `users[start[v]..start[v + 1]]`
/// are the cells with corner v, in increasing order (a cell with a repeated
/// corner is listed twice in a row).
struct Users {
    start: Vec<u32>,
    users: Vec<u32>,
}

impl Users {
    fn new(lattice: &Lattice) -> Self {
        let corners = |c: &Cell| c.corner_ids();
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
        Self { start, users }
    }

    /// Every other cell sharing edge `e` of cell `i`, with the index of the
    /// edge in that cell: `visit(j, ej)`, in increasing j.
    fn sharers(&self, lattice: &Lattice, i: usize, e: usize, mut visit: impl FnMut(usize, usize)) {
        let k = edge_keys(&lattice.cells[i])[e];
        let (lo, hi) = (self.start[k.0 as usize], self.start[k.0 as usize + 1]);
        let near = &self.users[lo as usize..hi as usize];
        for (u, &j) in near.iter().enumerate() {
            let j = j as usize;
            if j == i || (u > 0 && near[u - 1] as usize == j) {
                continue;
            }
            for (ej, kj) in edge_keys(&lattice.cells[j]).into_iter().enumerate() {
                if kj == k {
                    visit(j, ej);
                }
            }
        }
    }
}

/// Marks "no cell" in `edge_neighbours`.
const NO_CELL: u32 = u32::MAX;

/// For every cell and each of its edges, the other cell sharing that edge
/// as `cell | edge << 30` (`NO_CELL` on the boundary); None when some edge
/// has more than two cells or a cell has a repeated corner (then the
/// propagation asks `Users::sharers` each time).
fn edge_neighbours(lattice: &Lattice, users: &Users) -> Option<Vec<[u32; 4]>> {
    if lattice.cells.len() >= 1 << 30 {
        return None;
    }
    let mut nbr = vec![[NO_CELL; 4]; lattice.cells.len()];
    for (i, cell) in lattice.cells.iter().enumerate() {
        let c = cell.corner_ids();
        if (0..4).any(|a| (a + 1..4).any(|b| c[a] == c[b])) {
            return None;
        }
        for e in 0..4 {
            // An edge found from the cell before that shares it is known;
            // that cell saw every cell on the edge, so a third one was
            // caught there.
            if nbr[i][e] != NO_CELL {
                continue;
            }
            let mut more = false;
            users.sharers(lattice, i, e, |j, ej| {
                more |= nbr[i][e] != NO_CELL;
                nbr[i][e] = j as u32 | (ej as u32) << 30;
                nbr[j][ej] = i as u32 | (e as u32) << 30;
            });
            if more {
                return None;
            }
        }
    }
    Some(nbr)
}

/// Propagate cos(phi) from the reference cell (cell 0) through shared
/// edges. The cells sharing an edge are read off the grid of a grown sheet
/// (`grid_width`), or else found through their corners (precomputed once
/// when every edge has at most two cells).
///
/// The cells are taken in increasing index among those reached and not
/// yet taken, not breadth first: growth stores the cells row by row, so
/// this walks the arrays in order (a breadth-first wave crosses every row
/// at each step, one cache miss a cell) and takes a cell from the cell
/// before it or the row above, the shortest path. A cell reached behind
/// the scan waits in a small heap.
pub fn configuration(lattice: &Lattice) -> Configuration {
    configuration_with(lattice, |_, _, _, _| {}).0
}

/// `configuration`, showing `each(cell, corners, legs, cos_phi)` every cell
/// in cell order as the propagation over a grown sheet's grid takes it
/// (`grid_width`), its corners and legs at hand and its cos(phi) final;
/// true when it did (else `each` saw no cell, or not all in order).
pub(super) fn configuration_with(
    lattice: &Lattice,
    mut each: impl FnMut(&Cell, [DVec3; 4], &Legs, Affine),
) -> (Configuration, bool) {
    let n = lattice.cells.len();
    let theta_design = theta_design(lattice);
    let c_design = theta_design.cos();
    let mut design_residual: f64 = 0.0;
    // How far a cell's cos(phi) at the design opening misses its own.
    let mut design_check = |corners: [DVec3; 4], pivot: DVec3, f: Affine, legs: &Legs| {
        let design = design_cos_with(corners, pivot, legs);
        design_residual = design_residual.max((f.at(c_design) - design).abs());
    };
    // The next cell `each` expects: all of them, in order, or it says so.
    let mut next = 0;
    let grid = grid_width(lattice);
    let (cos_phi, reached, path_residual) = match grid {
        // A grown sheet: the neighbours are read off the grid (no lists of
        // corner users and edge neighbours: 144 MB on 4 M cells), and the
        // legs of the cells within a row of the one taken kept in a ring
        // (`LegRing`; 128 MB for every cell's). Every cell is taken, and
        // checked against its design opening then, with its corners and
        // legs at hand.
        Some(w) => {
            let mut ring = LegRing::new(lattice, w);
            let taken = |i: usize, f: Affine, legs: &Legs| {
                let cell = &lattice.cells[i];
                let corners = lattice.corners(cell);
                design_check(corners, cell.pivot, f, legs);
                if i == next {
                    each(cell, corners, legs, f);
                    next += 1;
                } else {
                    next = usize::MAX;
                }
            };
            propagate(n, |k| ring.get(k), grid_neighbours(n, w), taken)
        }
        None => {
            next = usize::MAX;
            let legs: Vec<Legs> = lattice.cells.iter().map(|c| lattice.legs(c)).collect();
            let users = Users::new(lattice);
            let found = match edge_neighbours(lattice, &users) {
                Some(nbr) => {
                    drop(users);
                    propagate(
                        n,
                        |k| legs[k],
                        |i, visit| {
                            for (e, &other) in nbr[i].iter().enumerate() {
                                if other != NO_CELL {
                                    let (j, ej) = (
                                        (other & ((1 << 30) - 1)) as usize,
                                        (other >> 30) as usize,
                                    );
                                    visit(e, j, ej);
                                }
                            }
                        },
                        |_, _, _| {},
                    )
                }
                None => propagate(
                    n,
                    |k| legs[k],
                    |i, visit| {
                        for e in 0..4 {
                            users.sharers(lattice, i, e, |j, ej| visit(e, j, ej));
                        }
                    },
                    |_, _, _| {},
                ),
            };
            // Every cell, reached or not (an unreached one keeps cos(phi) = 1).
            for ((cell, legs), &f) in lattice.cells.iter().zip(&legs).zip(&found.0) {
                design_check(lattice.corners(cell), cell.pivot, f, legs);
            }
            found
        }
    };
    let unreached = reached.iter().filter(|r| !**r).count();
    let mut collapse_residual: f64 = 0.0;
    // Each cos(phi) falls as cos(theta) falls; the range ends where the
    // first cell opens flat past pi (cos(phi) = -1).
    let mut c_min: f64 = -1.0;
    for f in &cos_phi {
        collapse_residual = collapse_residual.max((f.at(1.0) - 1.0).abs());
        if f.b > 0.0 {
            c_min = c_min.max((-1.0 - f.a) / f.b);
        }
    }
    let config = Configuration {
        cos_phi,
        theta_design,
        theta_max: c_min.clamp(-1.0, 1.0).acos(),
        path_residual,
        design_residual,
        collapse_residual,
        unreached,
    };
    (config, next == n)
}

/// The width `w` of a lattice whose cells form a grid numbered as growth
/// numbers a sheet: cell `i` in row `r = i / w`, column `c = i % w`, with
/// corners `x[r][c]`, `x[r][c + 1]`, `x[r + 1][c]`, `x[r + 1][c + 1]`, vertex
/// `x[r][c]` numbered `r (w + 1) + c`, and whole rows. Distinct grid points
/// have distinct numbers, so each edge belongs to the two cells the grid
/// puts on either side of it and to no other (`grid_neighbours`): exactly
/// what `edge_neighbours` would find. None for any other lattice.
fn grid_width(lattice: &Lattice) -> Option<usize> {
    let (n, w) = (lattice.cells.len(), lattice.width);
    if w == 0 || n == 0 || n % w != 0 {
        return None;
    }
    let grid = lattice.cells.chunks_exact(w).enumerate().all(|(r, row)| {
        row.iter().zip(r * (w + 1)..).all(|(cell, ul)| {
            cell.corner_ids().map(|v| v as usize) == [ul, ul + 1, ul + w + 1, ul + w + 2]
        })
    });
    grid.then_some(w)
}

/// The cells sharing each edge of cell i of a grid `w` cells wide
/// (`grid_width`), as `propagate` asks for them: `visit(e, j, ej)` in edge
/// order top, bottom, left, right (`edge_keys`).
fn grid_neighbours(n: usize, w: usize) -> impl Fn(usize, &mut dyn FnMut(usize, usize, usize)) {
    move |i, visit| {
        let c = i % w;
        if i >= w {
            visit(0, i - w, 1);
        }
        if i + w < n {
            visit(1, i + w, 0);
        }
        if c > 0 {
            visit(2, i - 1, 3);
        }
        if c + 1 < w {
            visit(3, i + 1, 2);
        }
    }
}

/// The legs (`Lattice::legs`) of a grid's cells (`grid_width`) in a ring:
/// the propagation over a grid takes its cells in order, each asking for
/// its own legs and its neighbours' (one row before it to one row after
/// it), so the ring holds two rows and computes each cell's legs once, as
/// the cells a row ahead are first asked for.
struct LegRing<'a> {
    lattice: &'a Lattice,
    legs: Vec<Legs>,
    mask: usize,
    /// The cells below this have their legs computed.
    next: usize,
}

impl<'a> LegRing<'a> {
    fn new(lattice: &'a Lattice, w: usize) -> Self {
        // Never more slots than cells: a one-row sheet is as wide as it is long.
        let window = (2 * w + 2)
            .min(lattice.cells.len().max(1))
            .next_power_of_two();
        Self {
            lattice,
            legs: vec![[0.0; 4]; window],
            mask: window - 1,
            next: 0,
        }
    }

    /// The legs of cell k, which lies in the ring's window.
    #[inline]
    fn get(&mut self, k: usize) -> Legs {
        while self.next <= k {
            self.legs[self.next & self.mask] = self.lattice.legs(&self.lattice.cells[self.next]);
            self.next += 1;
        }
        assert!(k + self.legs.len() >= self.next, "cell {k} behind the ring");
        self.legs[k & self.mask]
    }
}

/// The propagation of `configuration` over `neighbours(i, visit)`, which
/// calls `visit(e, j, ej)` for each cell j sharing edge e of cell i as its
/// edge ej; `taken(i, cos_phi, legs)` sees each cell as it is taken, its
/// cos(phi) final.
fn propagate(
    n: usize,
    mut legs: impl FnMut(usize) -> Legs,
    neighbours: impl Fn(usize, &mut dyn FnMut(usize, usize, usize)),
    mut taken: impl FnMut(usize, Affine, &Legs),
) -> (Vec<Affine>, Vec<bool>, f64) {
    let mut cos_phi = vec![Affine { a: 1.0, b: 0.0 }; n];
    let mut reached = vec![false; n];
    let mut path_residual: f64 = 0.0;
    if n == 0 {
        return (cos_phi, reached, path_residual);
    }
    cos_phi[0] = Affine { a: 0.0, b: 1.0 };
    reached[0] = true;
    // Cells below `scan` are taken or wait in `behind`.
    let mut behind: BinaryHeap<Reverse<u32>> = BinaryHeap::new();
    let mut scan = 0;
    loop {
        let i = match behind.pop() {
            Some(Reverse(i)) => i as usize,
            None => {
                while scan < n && !reached[scan] {
                    scan += 1;
                }
                if scan == n {
                    break;
                }
                scan += 1;
                scan - 1
            }
        };
        let f = cos_phi[i];
        let legs_i = legs(i);
        taken(i, f, &legs_i);
        neighbours(i, &mut |e, j, ej| {
            // The squared edge as a function of cos(theta), then the
            // neighbour's cos(phi) from its own formula for that edge.
            let (alpha, beta) = edge_coefficients(legs_i, e);
            let (ea, eb) = (alpha + beta * f.a, beta * f.b);
            let (alpha_j, beta_j) = edge_coefficients(legs(j), ej);
            let g = Affine {
                a: (ea - alpha_j) / beta_j,
                b: eb / beta_j,
            };
            if reached[j] {
                let h = cos_phi[j];
                path_residual = path_residual.max((h.a - g.a).abs() + (h.b - g.b).abs());
            } else {
                cos_phi[j] = g;
                reached[j] = true;
                if j < scan {
                    behind.push(Reverse(j as u32));
                }
            }
        });
    }
    (cos_phi, reached, path_residual)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::fixtures;
    use glam::DVec3;

    /// A sheet of uneven seed spacing and kappa: cells of every shape.
    fn uneven_sheet() -> Lattice {
        let points: Vec<DVec3> = (0..7)
            .map(|j| DVec3::new(10.0 * j as f64 + (j % 3) as f64, 0.3 * (j % 2) as f64, 0.0))
            .collect();
        let kappa = [0.5, -0.3, 0.2, 0.0, -0.4, 0.1];
        fixtures::sheet(&points, &kappa, 2, 50.0, 5)
    }

    /// The propagation over precomputed neighbours and the one asking the
    /// corners each time visit the same cells in the same order and compute
    /// the same numbers, bit for bit.
    #[test]
    fn both_neighbour_searches_agree_bit_for_bit() {
        let lattice = uneven_sheet();
        let n = lattice.cells.len();
        let legs: Vec<[f64; 4]> = lattice.cells.iter().map(|c| lattice.legs(c)).collect();
        let users = Users::new(&lattice);
        let nbr = edge_neighbours(&lattice, &users).expect("a sheet's edges have two cells");
        // Each edge's other cell, found from one side, is what asking the
        // corners from each side finds.
        for (i, row) in nbr.iter().enumerate() {
            for (e, &o) in row.iter().enumerate() {
                let mut asked = NO_CELL;
                users.sharers(&lattice, i, e, |j, ej| asked = j as u32 | (ej as u32) << 30);
                assert_eq!(o, asked, "cell {i} edge {e}");
            }
        }
        let (fast, reached, residual) = propagate(
            n,
            |k| legs[k],
            |i, visit| {
                for (e, &o) in nbr[i].iter().enumerate() {
                    if o != NO_CELL {
                        visit(e, (o & ((1 << 30) - 1)) as usize, (o >> 30) as usize);
                    }
                }
            },
            |_, _, _| {},
        );
        let (slow, reached_slow, residual_slow) = propagate(
            n,
            |k| legs[k],
            |i, visit| {
                for e in 0..4 {
                    users.sharers(&lattice, i, e, |j, ej| visit(e, j, ej));
                }
            },
            |_, _, _| {},
        );
        assert!(reached.iter().all(|r| *r));
        assert_eq!(reached, reached_slow);
        // The grid's neighbours are the ones found through the corners.
        let w = grid_width(&lattice).expect("a grown sheet is a grid");
        let grid = grid_neighbours(n, w);
        for (i, row) in nbr.iter().enumerate() {
            let mut seen = Vec::new();
            grid(i, &mut |e, j, ej| {
                seen.push((e, j as u32 | (ej as u32) << 30));
            });
            let listed: Vec<_> = (0..4)
                .filter(|&e| row[e] != NO_CELL)
                .map(|e| (e, row[e]))
                .collect();
            assert_eq!(seen, listed, "cell {i}");
        }
        // Every cell of a grid is taken once, in order, its cos(phi) final.
        let mut taken = Vec::new();
        let (on_grid, reached_grid, residual_grid) =
            propagate(n, |k| legs[k], &grid, |i, f, _| taken.push((i, f)));
        let in_order: Vec<_> = (0..n).map(|i| (i, on_grid[i])).collect();
        assert_eq!(taken, in_order);
        assert_eq!(reached, reached_grid);
        assert_eq!(residual.to_bits(), residual_grid.to_bits());
        assert_eq!(on_grid, fast);
        // `configuration` itself: the grid and the ring of legs.
        let config = configuration(&lattice);
        assert_eq!(config.cos_phi, fast);
        assert_eq!(config.path_residual.to_bits(), residual.to_bits());
        let c_design = config.theta_design.cos();
        let design = lattice
            .cells
            .iter()
            .zip(&fast)
            .fold(0.0f64, |m, (cell, f)| {
                m.max((f.at(c_design) - design_cos(&lattice, cell)).abs())
            });
        assert_eq!(config.design_residual.to_bits(), design.to_bits());
        assert_eq!(residual.to_bits(), residual_slow.to_bits());
        assert!(residual > 0.0, "rounding differs along paths: {residual}");
        for (f, s) in fast.iter().zip(&slow) {
            assert_eq!(
                (f.a.to_bits(), f.b.to_bits()),
                (s.a.to_bits(), s.b.to_bits())
            );
        }
        // Cells reached behind the scan (a lattice stored out of order) are
        // still taken: with the cells reversed and the middle one first,
        // every cell after it in the grid is reached from behind.
        let mut reversed = lattice.clone();
        reversed.cells.reverse();
        reversed.cells.swap(0, n / 2);
        assert_eq!(grid_width(&reversed), None);
        let back = configuration(&reversed);
        assert_eq!(back.unreached, 0);
        assert!(back.path_residual < 1e-12, "{}", back.path_residual);
    }

    /// The design opening from the shared legs is the one from normalising
    /// the legs' vectors, bit for bit.
    #[test]
    fn the_design_opening_from_the_legs_is_bit_for_bit_the_same() {
        let lattice = uneven_sheet();
        let mut rng = crate::rng::Rng::new(9);
        let mut moved = lattice.clone();
        for v in &mut moved.vertices {
            v.pos += DVec3::new(rng.signed(), rng.signed(), rng.signed());
        }
        for lattice in [&lattice, &moved] {
            for cell in &lattice.cells {
                let legs = lattice.legs(cell);
                assert_eq!(
                    design_cos_with(lattice.corners(cell), cell.pivot, &legs).to_bits(),
                    design_cos(lattice, cell).to_bits()
                );
            }
        }
    }
}
