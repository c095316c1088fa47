//! Neighbour search on a uniform grid: for each particle, the particles within the kernel radius,
//! in a fixed order (cells row by row, particles by index within a cell), so that every sum over
//! neighbours adds its terms in the same order on every run.
//!
//! Input: particle positions (units) and the kernel radius. Output: per particle, the indices of
//! its neighbours (itself excluded).

/// The neighbours of every particle, in a flat list with offsets.
#[derive(Debug, Default, Clone)]
pub(crate) struct Neighbours {
    /// `start[i]..start[i + 1]` indexes particle `i`'s entries in `index` and `distance`.
    start: Vec<usize>,
    index: Vec<usize>,
}

impl Neighbours {
    /// Finds, for each position, every other position closer than `radius` (units).
    ///
    /// Particles are counting-sorted into a dense grid of cells over their bounding box (row by
    /// row, each cell's particles by index), so the three cells of a row next to a particle's
    /// are one contiguous run: the neighbours come out row by row, cells left to right,
    /// particles by index.
    pub(crate) fn find(positions: &[[f64; 2]], radius: f64) -> Neighbours {
        let mut low = [f64::INFINITY; 2];
        let mut high = [f64::NEG_INFINITY; 2];
        for p in positions {
            for axis in 0..2 {
                low[axis] = low[axis].min(p[axis]);
                high[axis] = high[axis].max(p[axis]);
            }
        }
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "non-negative offsets over a positive radius, bounded below"
        )]
        let cell =
            |value: f64, axis: usize| ((value - low[axis]) / radius).floor().max(0.0) as usize;
        let columns = if positions.is_empty() {
            1
        } else {
            cell(high[0], 0) + 1
        };
        let rows = if positions.is_empty() {
            1
        } else {
            cell(high[1], 1) + 1
        };
        // A particle flung far away would make the dense grid huge: then the sorted search,
        // whose memory grows only with the particles.
        if columns.saturating_mul(rows) > 16 * positions.len() + (1 << 16) {
            return Neighbours::find_sorted(positions, radius);
        }
        let cell_of = |p: [f64; 2]| cell(p[1], 1) * columns + cell(p[0], 0);
        let mut cell_start = vec![0_usize; columns * rows + 1];
        for &p in positions {
            cell_start[cell_of(p) + 1] += 1;
        }
        for k in 1..cell_start.len() {
            cell_start[k] += cell_start[k - 1];
        }
        let mut filled = cell_start.clone();
        let mut sorted = vec![0_usize; positions.len()];
        for (index, &p) in positions.iter().enumerate() {
            let slot = &mut filled[cell_of(p)];
            sorted[*slot] = index;
            *slot += 1;
        }
        let squared = radius * radius;
        let mut start = Vec::with_capacity(positions.len() + 1);
        let mut index = Vec::new();
        for (i, &p) in positions.iter().enumerate() {
            start.push(index.len());
            let (row, column) = (cell(p[1], 1), cell(p[0], 0));
            let (first, last) = (column.saturating_sub(1), (column + 1).min(columns - 1));
            for r in row.saturating_sub(1)..=(row + 1).min(rows - 1) {
                let run =
                    &sorted[cell_start[r * columns + first]..cell_start[r * columns + last + 1]];
                for &j in run {
                    let q = positions[j];
                    let d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]);
                    if j != i && d2 < squared {
                        index.push(j);
                    }
                }
            }
        }
        start.push(index.len());
        Neighbours { start, index }
    }

    /// [`Neighbours::find`] for widely scattered particles: sorted by cell, each row's run found
    /// by binary search (the same order of neighbours).
    fn find_sorted(positions: &[[f64; 2]], radius: f64) -> Neighbours {
        let cell_of = |p: [f64; 2]| -> (i64, i64) {
            #[expect(
                clippy::cast_possible_truncation,
                reason = "finite positions over a positive radius are far inside i64"
            )]
            let cell = (
                (p[1] / radius).floor() as i64,
                (p[0] / radius).floor() as i64,
            );
            cell
        };
        let mut sorted: Vec<((i64, i64), usize)> = positions
            .iter()
            .enumerate()
            .map(|(index, &p)| (cell_of(p), index))
            .collect();
        sorted.sort_unstable();
        let squared = radius * radius;
        let mut start = Vec::with_capacity(positions.len() + 1);
        let mut index = Vec::new();
        for (i, &p) in positions.iter().enumerate() {
            start.push(index.len());
            let (row, column) = cell_of(p);
            for dy in -1..=1 {
                let from = sorted.partition_point(|&(cell, _)| cell < (row + dy, column - 1));
                let to = sorted.partition_point(|&(cell, _)| cell <= (row + dy, column + 1));
                for &(_, j) in &sorted[from..to] {
                    let q = positions[j];
                    let d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]);
                    if j != i && d2 < squared {
                        index.push(j);
                    }
                }
            }
        }
        start.push(index.len());
        Neighbours { start, index }
    }

    /// The neighbours of particle `i`.
    pub(crate) fn of(&self, i: usize) -> &[usize] {
        match (self.start.get(i), self.start.get(i + 1)) {
            (Some(&from), Some(&to)) => &self.index[from..to],
            _ => &[],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_are_exactly_the_particles_within_the_radius() {
        let positions: Vec<[f64; 2]> = (0..50)
            .map(|k| {
                let k = f64::from(k);
                [(k * 0.37).sin() * 0.5, (k * 0.91).cos() * 0.5]
            })
            .collect();
        let radius = 0.2;
        // One particle flung far away sends the search to its sorted fallback.
        let mut scattered = positions.clone();
        scattered.push([1e5, -1e5]);
        for (found, positions) in [
            (Neighbours::find(&positions, radius), &positions),
            (Neighbours::find(&scattered, radius), &scattered),
        ] {
            check(&found, positions, radius);
        }
    }

    fn check(found: &Neighbours, positions: &[[f64; 2]], radius: f64) {
        for (i, p) in positions.iter().enumerate() {
            let mut expected: Vec<usize> = positions
                .iter()
                .enumerate()
                .filter(|&(j, q)| j != i && (p[0] - q[0]).hypot(p[1] - q[1]) < radius)
                .map(|(j, _)| j)
                .collect();
            let mut got = found.of(i).to_vec();
            expected.sort_unstable();
            got.sort_unstable();
            assert_eq!(got, expected, "particle {i}");
        }
    }
}
