//! Optimal one-to-one assignment (the Hungarian method) for matching detections to tracks and to
//! ground truth.
//!
//! Input: a row count, a column count and a cost for each (row, column) pair, where `None` (or a
//! non-finite number) forbids the pair. Output: for each row, the column it is assigned to, if
//! any. Used by [`super::tracking`] and [`super::evaluation`]; depends on nothing else. Sizes in
//! this benchmark are at most a few dozen objects per frame, so the O(n²·m) method with
//! potentials is fast and exact.

/// The assignment that first pairs as many rows with allowed columns as possible, then, among
/// those, has the least total cost.
///
/// `cost(row, column)` is asked once per pair. Ties between equal-cost assignments resolve to
/// the same answer for the same costs (the lowest column wins at each step), so callers that
/// present rows and columns in a canonical order get a deterministic result.
///
/// Returns one entry per row: `Some(column)` or `None` when the row is left unmatched (no allowed
/// column remained for it).
pub fn assign(
    rows: usize,
    columns: usize,
    mut cost: impl FnMut(usize, usize) -> Option<f64>,
) -> Vec<Option<usize>> {
    if rows == 0 || columns == 0 {
        return vec![None; rows];
    }
    // Forbidden pairs get a cost above any difference allowed pairs can make, so the optimum
    // first maximises the number of allowed pairs (as SORT-style gating does), then the cost.
    let mut table: Vec<Option<f64>> = Vec::with_capacity(rows * columns);
    for row in 0..rows {
        for column in 0..columns {
            table.push(cost(row, column).filter(|c| c.is_finite()));
        }
    }
    let largest = table
        .iter()
        .flatten()
        .fold(0.0_f64, |acc, c| acc.max(c.abs()));
    let forbidden = 2.0 * (rows.max(columns) as f64 + 1.0) * (largest + 1.0);
    let at = |row: usize, column: usize| table[row * columns + column].unwrap_or(forbidden);

    // The method needs rows ≤ columns; solve the transpose otherwise.
    let transposed = rows > columns;
    let (n, m) = if transposed {
        (columns, rows)
    } else {
        (rows, columns)
    };
    let matrix = |i: usize, j: usize| if transposed { at(j, i) } else { at(i, j) };
    let row_of_column = hungarian(n, m, matrix);

    let mut result = vec![None; rows];
    for (j, i) in row_of_column.into_iter().enumerate() {
        let Some(i) = i else { continue };
        let (row, column) = if transposed { (j, i) } else { (i, j) };
        if table[row * columns + column].is_some() {
            result[row] = Some(column);
        }
    }
    result
}

/// Kuhn–Munkres with row and column potentials (the shortest-augmenting-path form), for
/// `n ≤ m`: every row is assigned. Returns, for each column, the row assigned to it.
fn hungarian(n: usize, m: usize, cost: impl Fn(usize, usize) -> f64) -> Vec<Option<usize>> {
    // 1-based internally; index 0 is the virtual start column / unassigned row.
    let mut u = vec![0.0_f64; n + 1];
    let mut v = vec![0.0_f64; m + 1];
    let mut row_of = vec![0_usize; m + 1];
    let mut way = vec![0_usize; m + 1];
    for i in 1..=n {
        row_of[0] = i;
        let mut j0 = 0;
        let mut min_reduced = vec![f64::INFINITY; m + 1];
        let mut used = vec![false; m + 1];
        loop {
            used[j0] = true;
            let i0 = row_of[j0];
            let mut delta = f64::INFINITY;
            let mut j1 = 0;
            for j in 1..=m {
                if used[j] {
                    continue;
                }
                let reduced = cost(i0 - 1, j - 1) - u[i0] - v[j];
                if reduced < min_reduced[j] {
                    min_reduced[j] = reduced;
                    way[j] = j0;
                }
                if min_reduced[j] < delta {
                    delta = min_reduced[j];
                    j1 = j;
                }
            }
            if j1 == 0 {
                // Unreachable with finite costs and n ≤ m; stop rather than loop.
                break;
            }
            for j in 0..=m {
                if used[j] {
                    u[row_of[j]] += delta;
                    v[j] -= delta;
                } else {
                    min_reduced[j] -= delta;
                }
            }
            j0 = j1;
            if row_of[j0] == 0 {
                break;
            }
        }
        // Flip the augmenting path.
        while j0 != 0 {
            let j1 = way[j0];
            row_of[j0] = row_of[j1];
            j0 = j1;
        }
    }
    row_of
        .into_iter()
        .skip(1)
        .map(|i| i.checked_sub(1))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solve(costs: &[&[Option<f64>]]) -> Vec<Option<usize>> {
        let columns = costs.first().map_or(0, |r| r.len());
        assign(costs.len(), columns, |r, c| costs[r][c])
    }

    fn total(costs: &[&[Option<f64>]], assignment: &[Option<usize>]) -> f64 {
        assignment
            .iter()
            .enumerate()
            .filter_map(|(r, c)| c.and_then(|c| costs[r][c]))
            .sum()
    }

    #[test]
    fn finds_the_cheapest_full_assignment() {
        // Greedy would take (0, 0) = 1 and then pay 10; the optimum is 2 + 3 = 5.
        let costs: &[&[Option<f64>]] = &[&[Some(1.0), Some(2.0)], &[Some(3.0), Some(10.0)]];
        let result = solve(costs);
        assert_eq!(result, vec![Some(1), Some(0)]);
        assert!((total(costs, &result) - 5.0).abs() < 1e-12);

        // Classic 3×3: rows 0..3 take columns 1, 0, 2 for 1 + 2 + 2 = 5.
        let costs: &[&[Option<f64>]] = &[
            &[Some(4.0), Some(1.0), Some(3.0)],
            &[Some(2.0), Some(0.0), Some(5.0)],
            &[Some(3.0), Some(2.0), Some(2.0)],
        ];
        let result = solve(costs);
        assert_eq!(result, vec![Some(1), Some(0), Some(2)]);
        assert!((total(costs, &result) - 5.0).abs() < 1e-12);
    }

    #[test]
    fn rectangular_and_forbidden_pairs() {
        // More rows than columns: one row stays unmatched.
        let costs: &[&[Option<f64>]] = &[&[Some(5.0)], &[Some(1.0)], &[Some(3.0)]];
        assert_eq!(solve(costs), vec![None, Some(0), None]);
        // More columns than rows.
        let costs: &[&[Option<f64>]] = &[&[Some(5.0), Some(1.0), Some(3.0)]];
        assert_eq!(solve(costs), vec![Some(1)]);
        // Forbidden pairs are never returned, and the count of allowed pairs comes first:
        // row 0 could take column 0 cheaply, but then row 1 (only column 0 allowed) would lose.
        let costs: &[&[Option<f64>]] = &[&[Some(0.1), Some(0.9)], &[Some(0.2), None]];
        assert_eq!(solve(costs), vec![Some(1), Some(0)]);
        let costs: &[&[Option<f64>]] = &[&[None, None], &[Some(f64::NAN), Some(0.3)]];
        assert_eq!(solve(costs), vec![None, Some(1)]);
        assert_eq!(assign(0, 3, |_, _| Some(1.0)), Vec::<Option<usize>>::new());
        assert_eq!(assign(2, 0, |_, _| Some(1.0)), vec![None, None]);
    }
}
