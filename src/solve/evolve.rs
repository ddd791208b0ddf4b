//! The seeded evolution strategy (`method = "evolution"`).

use super::*;

/// Generations of the evolution strategy between restarts.
pub(super) const ROUND: usize = 500;

/// A seeded (mu/mu_w, lambda) evolution strategy (Hansen's recombination
/// weights, step size by the one-fifth success rule against the mean).
/// Nelder-Mead stalls on a helix seed: one cell's admissibility cuts the
/// cost into many basins, and a population steps over them. Returns the
/// generations used; the best design tried is kept in `problem.best`.
/// Written here (about 40 lines), beside the simplex: a particle swarm
/// would want box bounds the seed variables do not have.
pub(super) fn evolve(problem: &Problem, opt: &Optimise, dims: usize, rng: &mut Rng) -> usize {
    let lambda = (4 + (3.0 * (dims as f64).ln()) as usize).max(8) + 4;
    let mu = lambda / 2;
    let w: Vec<f64> = (0..mu)
        .map(|i| (mu as f64 + 0.5).ln() - ((i + 1) as f64).ln())
        .collect();
    let sum: f64 = w.iter().sum();
    let w: Vec<f64> = w.iter().map(|v| v / sum).collect();
    let (mut mean, mut f_mean, mut sigma) = (Vec::new(), 0.0, 0.0);
    let floor = opt.step / 80.0;
    for generation in 0..opt.budget {
        // Every ROUND generations a fresh start about the best so far.
        if generation % ROUND == 0 {
            let best = problem.best.borrow();
            (mean, f_mean, sigma) = (best.1.clone(), best.0, opt.step);
        }
        let ys: Vec<Vec<f64>> = (0..lambda)
            .map(|_| mean.iter().map(|m| m + sigma * rng.normal()).collect())
            .collect();
        let mut pop: Vec<(f64, Vec<f64>)> = problem.evaluate_all(&ys).into_iter().zip(ys).collect();
        // Ties (two unadmissible designs) keep their draw order: deterministic.
        pop.sort_by(|a, b| a.0.total_cmp(&b.0));
        let success = pop.iter().filter(|p| p.0 < f_mean).count() as f64 / lambda as f64;
        mean = (0..dims)
            .map(|i| w.iter().zip(&pop).map(|(w, p)| w * p.1[i]).sum())
            .collect();
        f_mean = problem.evaluate(&mean);
        sigma = (sigma * ((success - 0.2) * 0.15).exp()).max(floor);
        if generation % 10 == 0 {
            (problem.progress.borrow_mut())(&format!(
                "optimise: generation {generation}, step {sigma:.3}, best cost {:.6}",
                problem.best.borrow().0
            ));
        }
    }
    opt.budget
}
