//! Small dense linear algebra for the simulators: row-major square matrices of a few dozen rows,
//! Gaussian elimination with partial pivoting, and a projected Gauss–Seidel solver for the linear
//! complementarity problems of unilateral constraints (ropes that only pull, floors that only push)
//! and boxed ones (bearing friction within a bound). Sizes here are the number of bodies or
//! constraints of one scene, so O(n³) is nothing; what matters is that singular or non-finite
//! systems are reported, never divided by.

/// A square matrix, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct Matrix {
    n: usize,
    values: Vec<f64>,
}

impl Matrix {
    /// The `n × n` zero matrix.
    pub fn zeros(n: usize) -> Matrix {
        Matrix {
            n,
            values: vec![0.0; n * n],
        }
    }

    /// Rows (and columns).
    pub fn size(&self) -> usize {
        self.n
    }

    /// Entry `(row, column)`.
    pub fn get(&self, row: usize, column: usize) -> f64 {
        self.values[row * self.n + column]
    }

    /// Adds `value` to entry `(row, column)`.
    pub fn add(&mut self, row: usize, column: usize, value: f64) {
        self.values[row * self.n + column] += value;
    }

    /// `self · x`.
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        (0..self.n)
            .map(|row| {
                (0..self.n)
                    .map(|column| self.get(row, column) * x[column])
                    .sum()
            })
            .collect()
    }
}

/// Solves `a · x = b` by Gaussian elimination with partial pivoting. `None` when a pivot is
/// below `1e-14` times the largest entry (singular to working precision) or anything is not
/// finite.
pub fn solve(matrix: &Matrix, rhs: &[f64]) -> Option<Vec<f64>> {
    let size = matrix.size();
    let mut work = matrix.values.clone();
    let mut solution = rhs.to_vec();
    let scale = work.iter().fold(0.0_f64, |acc, v| acc.max(v.abs()));
    if !scale.is_finite() || scale == 0.0 || solution.iter().any(|v| !v.is_finite()) {
        return None;
    }
    for column in 0..size {
        let pivot_row = (column..size).max_by(|&i, &j| {
            work[i * size + column]
                .abs()
                .total_cmp(&work[j * size + column].abs())
        })?;
        if work[pivot_row * size + column].abs() <= 1e-14 * scale {
            return None;
        }
        if pivot_row != column {
            for k in 0..size {
                work.swap(pivot_row * size + k, column * size + k);
            }
            solution.swap(pivot_row, column);
        }
        let pivot = work[column * size + column];
        for row in column + 1..size {
            let factor = work[row * size + column] / pivot;
            if factor != 0.0 {
                for k in column..size {
                    work[row * size + k] -= factor * work[column * size + k];
                }
                solution[row] -= factor * solution[column];
            }
        }
    }
    for row in (0..size).rev() {
        let tail: f64 = (row + 1..size)
            .map(|k| work[row * size + k] * solution[k])
            .sum();
        solution[row] = (solution[row] - tail) / work[row * size + row];
    }
    solution.iter().all(|v| v.is_finite()).then_some(solution)
}

/// Solves the LCP `u = a·z + q ≥ 0, z ≥ 0, zᵀu = 0` for a symmetric positive semi-definite `a`
/// (a constraint-space mass matrix), starting from `z` (a warm start).
///
/// Projected Gauss–Seidel finds the active set; the active subsystem is then solved exactly and
/// kept when it satisfies every condition to `1e-12` relative, so the usual answer is exact
/// rather than iterated. Returns the iterations used. The same as [`solve_boxed_lcp`] with every
/// variable in `[0, ∞)`.
pub fn solve_lcp(a: &Matrix, q: &[f64], z: &mut [f64]) -> usize {
    let lower = vec![0.0; z.len()];
    let upper = vec![f64::INFINITY; z.len()];
    solve_boxed_lcp(a, q, &lower, &upper, z)
}

/// Solves the boxed LCP (mixed complementarity problem) `u = a·z + q` with each `zᵢ` in
/// `[lowerᵢ, upperᵢ]` and `uᵢ ≥ 0` where `zᵢ = lowerᵢ`, `uᵢ ≤ 0` where `zᵢ = upperᵢ`, `uᵢ = 0`
/// in between, for a symmetric positive semi-definite `a`, starting from `z` (a warm start).
///
/// For such an `a` this is the convex quadratic program `min ½ zᵀa z + qᵀz` over the box, so
/// projected Gauss–Seidel (each variable relaxed in turn and clamped to its box) converges.
/// Ropes and contacts are `[0, ∞)`; Coulomb friction with a known bound `b` is `[−b, b]`, and a
/// force known in advance is the one-point box `[f, f]` (`lowerᵢ ≤ upperᵢ` always). As in
/// [`solve_lcp`], the subsystem of the variables PGS leaves strictly inside their boxes is then
/// solved exactly and kept when it is a solution of the whole problem. Returns the sweeps used.
pub fn solve_boxed_lcp(
    a: &Matrix,
    q: &[f64],
    lower: &[f64],
    upper: &[f64],
    z: &mut [f64],
) -> usize {
    let n = a.size();
    // Warm start: in a time-stepped simulation the set of active constraints rarely changes
    // from one step to the next, so the exact solve on the warm start's active set is usually
    // already the solution, and the iterations are skipped.
    let mut trial = z.to_vec();
    if polish(a, q, lower, upper, &mut trial) {
        z.copy_from_slice(&trial);
        return 0;
    }
    let scale = q.iter().fold(1e-300_f64, |acc, v| acc.max(v.abs()));
    let mut iterations = 0;
    for sweep in 0..1000 {
        iterations = sweep + 1;
        let mut change = 0.0_f64;
        for i in 0..n {
            let diagonal = a.get(i, i);
            if diagonal <= 0.0 {
                // The variable moves nothing; the force closest to zero its box allows.
                z[i] = 0.0_f64.max(lower[i]).min(upper[i]);
                continue;
            }
            let residual: f64 = (0..n).map(|j| a.get(i, j) * z[j]).sum::<f64>() + q[i];
            // `max` then `min` (not `clamp`) so that `[0, ∞)` rounds exactly as the plain
            // LCP's `max(0.0)` always has, bit for bit.
            let next = (z[i] - residual / diagonal).max(lower[i]).min(upper[i]);
            change = change.max((next - z[i]).abs() * diagonal);
            z[i] = next;
        }
        if change <= 1e-15 * scale {
            break;
        }
    }
    // When the iterations did not settle the active set exactly, their result stands.
    let _exact = polish(a, q, lower, upper, z);
    iterations
}

/// Solves exactly the subsystem of the variables PGS left strictly inside their boxes (the
/// others held at the bound they reached); keeps it, and returns `true`, if it is a solution of
/// the whole problem.
fn polish(a: &Matrix, q: &[f64], lower: &[f64], upper: &[f64], z: &mut [f64]) -> bool {
    let size = a.size();
    let at_lower: Vec<bool> = (0..size).map(|i| z[i] <= lower[i]).collect();
    let at_upper: Vec<bool> = (0..size).map(|i| z[i] >= upper[i]).collect();
    let active: Vec<usize> = (0..size)
        .filter(|&i| !at_lower[i] && !at_upper[i])
        .collect();
    // Held variables sit exactly on a bound; an unbounded-below or -above side is never held.
    let mut candidate = vec![0.0; size];
    for i in 0..size {
        if at_lower[i] {
            candidate[i] = lower[i];
        } else if at_upper[i] {
            candidate[i] = upper[i];
        }
    }
    let mut sub = Matrix::zeros(active.len());
    for (r, &i) in active.iter().enumerate() {
        for (c, &j) in active.iter().enumerate() {
            sub.add(r, c, a.get(i, j));
        }
    }
    let rhs: Vec<f64> = active
        .iter()
        .map(|&i| {
            // Only held forces that are not zero move the right-hand side; skipping the zero
            // ones keeps the plain LCP's right-hand side (`−q`) exact to the sign of a zero.
            (0..size)
                .filter(|&j| (at_lower[j] || at_upper[j]) && candidate[j] != 0.0)
                .fold(-q[i], |acc, j| acc - a.get(i, j) * candidate[j])
        })
        .collect();
    if !active.is_empty() {
        let Some(exact) = solve(&sub, &rhs) else {
            return false;
        };
        for (r, &i) in active.iter().enumerate() {
            candidate[i] = exact[r];
        }
    }
    let scale = q.iter().fold(1e-300_f64, |acc, v| acc.max(v.abs()));
    let residuals: Vec<f64> = a
        .mul_vec(&candidate)
        .iter()
        .zip(q)
        .map(|(aq, qi)| aq + qi)
        .collect();
    let tolerance = 1e-12 * scale;
    // Inside its box (to the tolerance); a variable that could still grow must not want to
    // (residual `u ≥ 0`), one that could still shrink must not want to (`u ≤ 0`). The free
    // variables' residuals are zero up to the rounding of the solve and are held to the same
    // one-sided test as the plain LCP's.
    let feasible = (0..size).all(|i| {
        let inside = candidate[i] >= lower[i] - tolerance && candidate[i] <= upper[i] + tolerance;
        let growth = at_upper[i] || residuals[i] >= -tolerance;
        let shrink = !at_upper[i] || at_lower[i] || residuals[i] <= tolerance;
        inside && growth && shrink
    });
    if feasible {
        for (i, (slot, value)) in z.iter_mut().zip(candidate).enumerate() {
            *slot = value.max(lower[i]).min(upper[i]);
        }
    }
    feasible
}

#[cfg(test)]
mod tests {
    use super::*;

    fn matrix(rows: &[&[f64]]) -> Matrix {
        let mut m = Matrix::zeros(rows.len());
        for (i, row) in rows.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                m.add(i, j, *v);
            }
        }
        m
    }

    #[test]
    fn solves_a_system_that_needs_pivoting() {
        let a = matrix(&[&[0.0, 2.0, 1.0], &[1.0, 1.0, 0.0], &[3.0, 0.0, 1.0]]);
        let x = solve(&a, &[5.0, 3.0, 6.0]).unwrap();
        for (got, want) in x.iter().zip([1.4, 1.6, 1.8]) {
            assert!((got - want).abs() < 1e-12, "{x:?}");
        }
        assert!(solve(&matrix(&[&[1.0, 2.0], &[2.0, 4.0]]), &[1.0, 2.0]).is_none());
        assert!(solve(&matrix(&[&[f64::NAN]]), &[1.0]).is_none());
    }

    #[test]
    fn lcp_keeps_pulling_constraints_and_drops_pushing_ones() {
        // Constraint 0 wants a positive impulse, constraint 1 would need a negative one.
        let a = matrix(&[&[2.0, 0.5], &[0.5, 1.0]]);
        let q = [-4.0, 3.0];
        let mut z = [0.0, 0.0];
        solve_lcp(&a, &q, &mut z);
        assert!((z[0] - 2.0).abs() < 1e-14 && z[1] == 0.0, "{z:?}");
        let u1 = 0.5 * z[0] + 3.0;
        assert!(u1 > 0.0);
    }

    /// A rope row (masses 1 and 1, gradient (−1, −1)) and a friction row on the first body
    /// (gradient (−1, 0)): `A = [[2, 1], [1, 1]]`, with `q = (−3, −0.5)`.
    fn rope_and_friction() -> (Matrix, [f64; 2]) {
        (matrix(&[&[2.0, 1.0], &[1.0, 1.0]]), [-3.0, -0.5])
    }

    #[test]
    fn boxed_lcp_holds_inside_the_bound_and_slides_at_it() {
        let (a, q) = rope_and_friction();
        let upper_rope = f64::INFINITY;
        // A wide bound holds: the unconstrained solution A⁻¹(−q) = (2.5, −2), both u = 0.
        let mut z = [0.0, 0.0];
        solve_boxed_lcp(&a, &q, &[0.0, -3.0], &[upper_rope, 3.0], &mut z);
        assert!(
            (z[0] - 2.5).abs() < 1e-14 && (z[1] + 2.0).abs() < 1e-14,
            "{z:?}"
        );
        // A bound of 1 cannot: friction at −1, the rope row alone gives z₀ = (3 − 1)/2 = 2,
        // and the friction row's u = z₀ + z₁ − 0.5 = 0.5 ≥ 0 (it slides the way it resists).
        let mut z = [0.0, 0.0];
        solve_boxed_lcp(&a, &q, &[0.0, -1.0], &[upper_rope, 1.0], &mut z);
        assert!(
            (z[0] - 2.0).abs() < 1e-14 && (z[1] + 1.0).abs() < 1e-14,
            "{z:?}"
        );
        // A one-point box is a known force: z₁ = 0.7, z₀ = (3 − 0.7)/2.
        let mut z = [0.0, 0.0];
        solve_boxed_lcp(&a, &q, &[0.0, 0.7], &[upper_rope, 0.7], &mut z);
        assert!(
            (z[0] - 1.15).abs() < 1e-14 && (z[1] - 0.7).abs() < 1e-14,
            "{z:?}"
        );
        // The upper bound reached: q₁ = −5 pushes z₁ up to +1, so z₀ = (3 − 1)/2 = 1 and the
        // friction row's u = z₀ + z₁ − 5 = −3 ≤ 0.
        let mut z = [0.0, 0.0];
        solve_boxed_lcp(&a, &[-3.0, -5.0], &[0.0, -1.0], &[upper_rope, 1.0], &mut z);
        assert!(
            (z[0] - 1.0).abs() < 1e-14 && (z[1] - 1.0).abs() < 1e-14,
            "{z:?}"
        );
    }

    #[test]
    fn plain_lcp_solutions_are_complementary() {
        let a = matrix(&[&[2.0, 0.5, 0.1], &[0.5, 1.0, 0.3], &[0.1, 0.3, 0.7]]);
        for q in [[-4.0, 3.0, -1.0], [-1.0, -2.0, -3.0], [1.0, 2.0, 3.0]] {
            let mut z = [0.1, 0.0, 0.2];
            solve_lcp(&a, &q, &mut z);
            // z ≥ 0, u = a·z + q ≥ 0, zᵀu = 0.
            let u: Vec<f64> = a.mul_vec(&z).iter().zip(q).map(|(x, y)| x + y).collect();
            for (zi, ui) in z.iter().zip(&u) {
                assert!(
                    *zi >= 0.0 && *ui >= -1e-12 && (zi * ui).abs() < 1e-12,
                    "{z:?} {u:?}"
                );
            }
        }
        // The last q needs no force at all.
        let mut z = [0.1, 0.0, 0.2];
        solve_lcp(&a, &[1.0, 2.0, 3.0], &mut z);
        assert!(z.iter().all(|v| v.abs() < 1e-14), "{z:?}");
    }
}
