//! The Nelder-Mead simplex (`method = "nelder-mead"`): derivative-free, the
//! textbook moves with the usual coefficients (reflect 1, expand 2,
//! contract 1/2, shrink 1/2). Written here rather than taken from a crate:
//! it is about 80 lines, where the optimisation framework it came from cost
//! 25 crates of compile time for this one solver.
//!
//! The order of the moves and of every cost evaluation is fixed (the
//! vertices kept sorted by cost, ties in their earlier order), so a run is
//! the same for the same start: the optimiser's output is deterministic.

/// The moves' coefficients.
const REFLECT: f64 = 1.0;
const EXPAND: f64 = 2.0;
const CONTRACT: f64 = 0.5;
const SHRINK: f64 = 0.5;

/// Minimise `cost` from the start `simplex` (dims + 1 points) for at most
/// `max_iterations` moves, stopping early once the standard deviation of
/// the vertices' costs is under `tolerance`. Returns the moves made.
pub(super) fn minimise(
    simplex: Vec<Vec<f64>>,
    tolerance: f64,
    max_iterations: usize,
    cost: &mut dyn FnMut(&[f64]) -> f64,
) -> usize {
    let mut vertices: Vec<(Vec<f64>, f64)> = simplex
        .into_iter()
        .map(|x| {
            let c = cost(&x);
            (x, c)
        })
        .collect();
    sort(&mut vertices);
    let mut moves = 0;
    while moves < max_iterations && !(spread(&vertices) < tolerance) {
        step(&mut vertices, cost);
        sort(&mut vertices);
        moves += 1;
    }
    moves
}

/// One move: reflect the worst vertex through the centroid of the others,
/// then expand, contract or shrink as the reflected point's cost says.
fn step(vertices: &mut [(Vec<f64>, f64)], cost: &mut dyn FnMut(&[f64]) -> f64) {
    let n = vertices.len();
    let centre = centroid(&vertices[..n - 1]);
    let (best, second_worst, worst) = (vertices[0].1, vertices[n - 2].1, vertices[n - 1].1);
    let reflected = along(&centre, &vertices[n - 1].0, -REFLECT);
    let c_reflected = cost(&reflected);
    let replacement = if c_reflected < second_worst && c_reflected >= best {
        Some((reflected, c_reflected))
    } else if c_reflected < best {
        let expanded = along(&centre, &reflected, EXPAND);
        let c_expanded = cost(&expanded);
        Some(if c_expanded < c_reflected {
            (expanded, c_expanded)
        } else {
            (reflected, c_reflected)
        })
    } else if c_reflected < worst {
        // Outside contraction: towards the reflected point.
        let contracted = along(&centre, &reflected, CONTRACT);
        let c = cost(&contracted);
        (c <= c_reflected).then_some((contracted, c))
    } else {
        // Inside contraction: towards the worst vertex.
        let contracted = along(&centre, &vertices[n - 1].0, CONTRACT);
        let c = cost(&contracted);
        (c < worst).then_some((contracted, c))
    };
    match replacement {
        Some(v) => vertices[n - 1] = v,
        None => shrink(vertices, cost),
    }
}

/// Every vertex but the best moved halfway towards the best, and costed.
fn shrink(vertices: &mut [(Vec<f64>, f64)], cost: &mut dyn FnMut(&[f64]) -> f64) {
    let best = vertices[0].0.clone();
    for (x, c) in vertices.iter_mut().skip(1) {
        *x = along(&best, x, SHRINK);
        *c = cost(x);
    }
}

/// `from + (to - from) * t`, component by component.
fn along(from: &[f64], to: &[f64], t: f64) -> Vec<f64> {
    from.iter().zip(to).map(|(a, b)| a + (b - a) * t).collect()
}

/// The mean of the points: summed in order, then scaled by 1 / count.
fn centroid(points: &[(Vec<f64>, f64)]) -> Vec<f64> {
    let mut sum = points[0].0.clone();
    for (p, _) in &points[1..] {
        for (s, v) in sum.iter_mut().zip(p) {
            *s += v;
        }
    }
    let scale = 1.0 / points.len() as f64;
    sum.iter().map(|s| s * scale).collect()
}

/// The sample standard deviation of the vertices' costs (NaN when a cost is
/// infinite, which never counts as converged).
fn spread(vertices: &[(Vec<f64>, f64)]) -> f64 {
    let n = vertices.len() as f64;
    let mean = vertices.iter().map(|v| v.1).sum::<f64>() / n;
    let squares: f64 = vertices.iter().map(|v| (v.1 - mean).powi(2)).sum();
    (1.0 / (n - 1.0) * squares).sqrt()
}

/// Sorted by cost, stable: equal costs keep their order.
fn sort(vertices: &mut [(Vec<f64>, f64)]) {
    vertices.sort_by(|a, b| a.1.partial_cmp(&b.1).unwrap_or(std::cmp::Ordering::Equal));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Rosenbrock valley's minimum at (1, 1), from a simplex about
    /// (-1.2, 1): found to 1e-6, and the evaluations are deterministic.
    #[test]
    fn finds_the_rosenbrock_minimum() {
        let run = || {
            let mut calls = Vec::new();
            let mut cost = |x: &[f64]| {
                let c = 100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2);
                calls.push(c);
                c
            };
            let start = vec![vec![-1.2, 1.0], vec![-1.1, 1.0], vec![-1.2, 1.1]];
            let moves = minimise(start, 1e-14, 2000, &mut cost);
            (moves, calls)
        };
        let (moves, calls) = run();
        let best = calls.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(best < 1e-10, "best cost {best} after {moves} moves");
        assert!(moves < 2000, "stopped by the tolerance, not the budget");
        assert_eq!(run(), (moves, calls));
    }

    /// A budget of zero moves costs the start simplex only.
    #[test]
    fn zero_moves_cost_the_start_only() {
        let mut n = 0;
        let moves = minimise(vec![vec![0.0], vec![1.0]], 0.0, 0, &mut |x| {
            n += 1;
            x[0]
        });
        assert_eq!((moves, n), (0, 2));
    }

    /// Each move of a 1-D simplex on |x - 3|: reflection, expansion and
    /// contraction bring the best point to 3.
    #[test]
    fn contracts_onto_a_kink() {
        let mut best = f64::INFINITY;
        let moves = minimise(vec![vec![0.0], vec![0.5]], 1e-12, 500, &mut |x| {
            let c = (x[0] - 3.0).abs();
            best = best.min(c);
            c
        });
        assert!(best < 1e-9 && moves < 500, "best {best}, moves {moves}");
    }
}
