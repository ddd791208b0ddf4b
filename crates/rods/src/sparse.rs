//! The sparse Hessian's structure (docs/physics.md, "Solver"): its pattern,
//! a fill-reducing order and the factor's pattern, each worked out once per
//! model. The order is approximate minimum degree from the `amd` crate, a
//! port of SuiteSparse's AMD; the factor's pattern (elimination tree and
//! row reaches) is the textbook symbolic step, a few dozen lines.

/// A sparse pattern in compressed columns: column c's rows are
/// `row_idx[col_ptr[c]..col_ptr[c + 1]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Pattern {
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
}

impl Pattern {
    /// Its number of columns.
    pub fn n(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// Column c's rows.
    pub fn column(&self, c: usize) -> &[usize] {
        &self.row_idx[self.col_ptr[c]..self.col_ptr[c + 1]]
    }

    /// The transpose, each column's rows increasing.
    pub fn transpose(&self) -> Pattern {
        let n = self.n();
        let mut count = vec![0usize; n + 1];
        for &r in &self.row_idx {
            count[r + 1] += 1;
        }
        for c in 0..n {
            count[c + 1] += count[c];
        }
        let mut next = count.clone();
        let mut row_idx = vec![0usize; self.row_idx.len()];
        for c in 0..n {
            for &r in self.column(c) {
                row_idx[next[r]] = c;
                next[r] += 1;
            }
        }
        Pattern {
            col_ptr: count,
            row_idx,
        }
    }
}

/// The approximate-minimum-degree order of a symmetric matrix given by its
/// lower triangle (rows sorted, diagonal included): (perm, inverse), with
/// perm[new] = old. AMD is handed the upper triangle, sorted, so that it
/// orders the same adjacency lists a transposing front end would.
pub fn amd_order(lower: &Pattern) -> (Vec<usize>, Vec<usize>) {
    let n = lower.n();
    if n == 0 {
        return (Vec::new(), Vec::new());
    }
    let upper = lower.transpose();
    match amd::order::<usize>(n, &upper.col_ptr, &upper.row_idx, &amd::Control::default()) {
        Ok((perm, inv, _)) => (perm, inv),
        // Only an invalid pattern is refused, and `System::new` builds
        // valid ones; keep the natural order rather than fail the solve.
        Err(_) => ((0..n).collect(), (0..n).collect()),
    }
}

/// The Cholesky factor's pattern of the symmetric matrix whose upper
/// triangle is `upper` (any row order within a column): column j holds j
/// first, then the rows below it in increasing order.
pub fn factor_pattern(upper: &Pattern) -> Pattern {
    let n = upper.n();
    let parent = elimination_tree(upper);
    // Row k of the factor: the columns reached from A's column k up the
    // tree, walked twice: to count each column's rows, then to place them
    // (met in increasing k, after the diagonal).
    let mut mark = vec![usize::MAX; n];
    let mut count = vec![1usize; n];
    row_reaches(upper, &parent, &mut mark, |j, _| count[j] += 1);
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    for c in &count {
        col_ptr.push(col_ptr[col_ptr.len() - 1] + c);
    }
    let mut row_idx = vec![0usize; col_ptr[n]];
    let mut next: Vec<usize> = col_ptr[..n].to_vec();
    for (j, slot) in next.iter_mut().enumerate() {
        row_idx[*slot] = j;
        *slot += 1;
    }
    mark.fill(usize::MAX);
    row_reaches(upper, &parent, &mut mark, |j, k| {
        row_idx[next[j]] = k;
        next[j] += 1;
    });
    Pattern { col_ptr, row_idx }
}

/// Each (j, k) with L[k][j] != 0, j < k, in increasing k: the walks from
/// A's column k up the elimination tree (`mark` all usize::MAX).
fn row_reaches(
    upper: &Pattern,
    parent: &[usize],
    mark: &mut [usize],
    mut visit: impl FnMut(usize, usize),
) {
    for k in 0..upper.n() {
        mark[k] = k;
        for &i in upper.column(k) {
            let mut j = i;
            while j < k && mark[j] != k {
                visit(j, k);
                mark[j] = k;
                j = parent[j];
            }
        }
    }
}

/// Each column's parent in the elimination tree (usize::MAX at a root), by
/// Liu's algorithm with path compression.
fn elimination_tree(upper: &Pattern) -> Vec<usize> {
    let n = upper.n();
    let mut parent = vec![usize::MAX; n];
    let mut ancestor = vec![usize::MAX; n];
    for k in 0..n {
        for &i in upper.column(k) {
            let mut j = i;
            while j != usize::MAX && j < k {
                let next = ancestor[j];
                ancestor[j] = k;
                if next == usize::MAX {
                    parent[j] = k;
                }
                j = next;
            }
        }
    }
    parent
}

#[cfg(test)]
pub(crate) mod tests_support {
    use super::*;
    use crate::rng::Rng;

    /// A random symmetric lower pattern: a band with a few far entries.
    pub(crate) fn random_lower(n: usize, rng: &mut Rng) -> Pattern {
        let mut col_ptr = vec![0usize];
        let mut row_idx = Vec::new();
        for c in 0..n {
            row_idx.push(c);
            for r in c + 1..n {
                let p = if r - c <= 3 { 0.6 } else { 2.0 / n as f64 };
                if rng.uniform() < p {
                    row_idx.push(r);
                }
            }
            col_ptr.push(row_idx.len());
        }
        Pattern { col_ptr, row_idx }
    }
}

#[cfg(test)]
mod tests {
    use super::tests_support::random_lower;
    use super::*;
    use crate::rng::Rng;

    /// The factor's pattern by dense symbolic elimination: entry (i, j) of
    /// L is structurally non-zero when A's is, or when some earlier column
    /// k has both (i, k) and (j, k).
    fn dense_factor_pattern(upper: &Pattern) -> Vec<Vec<bool>> {
        let n = upper.n();
        let mut l = vec![vec![false; n]; n];
        for c in 0..n {
            for &r in upper.column(c) {
                l[c.max(r)][c.min(r)] = true;
            }
        }
        for k in 0..n {
            let below: Vec<usize> = (k + 1..n).filter(|&i| l[i][k]).collect();
            for &i in &below {
                for &j in &below {
                    if j <= i {
                        l[i][j] = true;
                    }
                }
            }
        }
        l
    }

    #[test]
    fn factor_pattern_matches_dense_elimination() {
        let mut rng = Rng::new(11);
        for case in 0..40 {
            let n = 1 + case * 2;
            let lower = random_lower(n, &mut rng);
            let upper = lower.transpose();
            let got = factor_pattern(&upper);
            let want = dense_factor_pattern(&upper);
            for j in 0..n {
                let rows: Vec<usize> = (j..n).filter(|&i| want[i][j]).collect();
                assert_eq!(got.column(j), &rows[..], "case {case}, column {j}");
            }
        }
    }

    #[test]
    fn amd_order_is_a_permutation_that_reduces_fill() {
        let mut rng = Rng::new(3);
        let (mut natural, mut ordered) = (0, 0);
        for case in 0..30 {
            let n = 10 + case * 5;
            let lower = random_lower(n, &mut rng);
            let (perm, inv) = amd_order(&lower);
            let mut seen = vec![false; n];
            for (new, &old) in perm.iter().enumerate() {
                assert!(!seen[old]);
                seen[old] = true;
                assert_eq!(inv[old], new);
            }
            natural += factor_pattern(&lower.transpose()).row_idx.len();
            ordered += factor_pattern(&permuted_upper(&lower, &inv)).row_idx.len();
        }
        assert!(ordered < natural, "fill {ordered} ordered vs {natural}");
    }

    /// The upper triangle of P A P^T from A's lower triangle.
    fn permuted_upper(lower: &Pattern, inv: &[usize]) -> Pattern {
        let n = lower.n();
        let mut cols: Vec<Vec<usize>> = vec![Vec::new(); n];
        for c in 0..n {
            for &r in lower.column(c) {
                let (a, b) = (inv[r], inv[c]);
                cols[a.max(b)].push(a.min(b));
            }
        }
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for mut c in cols {
            c.sort_unstable();
            row_idx.extend(c);
            col_ptr.push(row_idx.len());
        }
        Pattern { col_ptr, row_idx }
    }
}
