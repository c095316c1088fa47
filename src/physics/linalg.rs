//! Small dense linear algebra for the simulators: row-major square matrices of a few dozen rows,
//! Gaussian elimination with partial pivoting, and a projected Gauss–Seidel solver for the
//! linear complementarity problems of unilateral constraints (ropes that only pull, floors that
//! only push). Sizes here are the number of bodies or constraints of one scene, so O(n³) is
//! nothing; what matters is that singular or non-finite systems are reported, never divided by.

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
/// rather than iterated. Returns the iterations used.
pub fn solve_lcp(a: &Matrix, q: &[f64], z: &mut [f64]) -> usize {
    let n = a.size();
    let scale = q.iter().fold(1e-300_f64, |acc, v| acc.max(v.abs()));
    let mut iterations = 0;
    for sweep in 0..1000 {
        iterations = sweep + 1;
        let mut change = 0.0_f64;
        for i in 0..n {
            let diagonal = a.get(i, i);
            if diagonal <= 0.0 {
                z[i] = 0.0;
                continue;
            }
            let residual: f64 = (0..n).map(|j| a.get(i, j) * z[j]).sum::<f64>() + q[i];
            let next = (z[i] - residual / diagonal).max(0.0);
            change = change.max((next - z[i]).abs() * diagonal);
            z[i] = next;
        }
        if change <= 1e-15 * scale {
            break;
        }
    }
    polish(a, q, z);
    iterations
}

/// Solves the subsystem of the constraints PGS left active exactly; keeps it if it is a
/// solution of the whole LCP.
fn polish(a: &Matrix, q: &[f64], z: &mut [f64]) {
    let active: Vec<usize> = (0..a.size()).filter(|&i| z[i] > 0.0).collect();
    if active.is_empty() {
        return;
    }
    let mut sub = Matrix::zeros(active.len());
    for (r, &i) in active.iter().enumerate() {
        for (c, &j) in active.iter().enumerate() {
            sub.add(r, c, a.get(i, j));
        }
    }
    let rhs: Vec<f64> = active.iter().map(|&i| -q[i]).collect();
    let Some(exact) = solve(&sub, &rhs) else {
        return;
    };
    let mut candidate = vec![0.0; a.size()];
    for (r, &i) in active.iter().enumerate() {
        candidate[i] = exact[r];
    }
    let scale = q.iter().fold(1e-300_f64, |acc, v| acc.max(v.abs()));
    let u: Vec<f64> = a
        .mul_vec(&candidate)
        .iter()
        .zip(q)
        .map(|(aq, qi)| aq + qi)
        .collect();
    let tolerance = 1e-12 * scale;
    if candidate.iter().all(|v| *v >= -tolerance) && u.iter().all(|v| *v >= -tolerance) {
        for (slot, value) in z.iter_mut().zip(candidate) {
            *slot = value.max(0.0);
        }
    }
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
}
