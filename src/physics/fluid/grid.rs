//! Neighbour search on a uniform grid: for each particle, the particles within the kernel radius,
//! in a fixed order (cells row by row, particles by index within a cell), so that every sum over
//! neighbours adds its terms in the same order on every run.
//!
//! Input: particle positions (units) and the kernel radius. Output: per particle, the indices of
//! its neighbours (itself excluded).

use std::collections::HashMap;

/// The neighbours of every particle, in a flat list with offsets.
#[derive(Debug, Default, Clone)]
pub(crate) struct Neighbours {
    /// `start[i]..start[i + 1]` indexes particle `i`'s entries in `index` and `distance`.
    start: Vec<usize>,
    index: Vec<usize>,
}

impl Neighbours {
    /// Finds, for each position, every other position closer than `radius` (units).
    pub(crate) fn find(positions: &[[f64; 2]], radius: f64) -> Neighbours {
        let cell_of = |p: [f64; 2]| -> (i64, i64) {
            #[expect(
                clippy::cast_possible_truncation,
                reason = "finite positions over a positive radius are far inside i64"
            )]
            let cell = (
                (p[0] / radius).floor() as i64,
                (p[1] / radius).floor() as i64,
            );
            cell
        };
        // Cells are only looked up, never iterated, so their order cannot reach the output.
        let mut cells: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for (index, &p) in positions.iter().enumerate() {
            cells.entry(cell_of(p)).or_default().push(index);
        }
        let squared = radius * radius;
        let mut start = Vec::with_capacity(positions.len() + 1);
        let mut index = Vec::new();
        for (i, &p) in positions.iter().enumerate() {
            start.push(index.len());
            let (cx, cy) = cell_of(p);
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let Some(list) = cells.get(&(cx + dx, cy + dy)) else {
                        continue;
                    };
                    for &j in list {
                        let q = positions[j];
                        let d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]);
                        if j != i && d2 < squared {
                            index.push(j);
                        }
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
        let found = Neighbours::find(&positions, radius);
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
