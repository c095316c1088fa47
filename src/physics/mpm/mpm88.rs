//! Taichi's `mpm88.py` example as a configuration of the MPM core, for parity and speed against
//! Taichi (`bench mpm88`, `benches/mpm88_taichi.py`). The example (taichi 1.7.4) fixes 8,192
//! particles on a 128² grid with `dt = 2e-4`; its 3-D twin `mpm3d.py` gives the 2-D setting for
//! 32,768 particles, a 256² grid with `dt = 1e-4`. Both: unit square, `dx = 1/n`, particle
//! volume `(dx/2)²`, density 1, pressure `E(J − 1)` with `E = 400`, gravity 9.8 down, walls three
//! nodes in at the low sides and two at the high sides (the example's `i > n − bound` with
//! `bound = 3`), initial velocity (0, −1), `J = 1`, `C = 0`.
//!
//! Input: initial positions. Output: a [`Solver`] and, after stepping, a [`Summary`].

use super::{GridSpec, LiquidMaterial, Material, MpmError, Settings, Solver, Walls};

/// The example's constants for a particle count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mpm88 {
    /// Grid nodes along each axis.
    pub nodes: usize,
    /// Substep, s.
    pub time_step: f64,
}

/// Young's modulus `E` of the example (its bulk modulus), stress units.
pub const YOUNGS_MODULUS: f64 = 400.0;
/// Gravity of the example, length/s², downwards.
pub const GRAVITY: f64 = 9.8;

impl Mpm88 {
    /// The configuration for `particles` (8,192 or 32,768), or `None` for another count.
    pub fn for_particles(particles: usize) -> Option<Mpm88> {
        match particles {
            8192 => Some(Mpm88 {
                nodes: 128,
                time_step: 2e-4,
            }),
            32768 => Some(Mpm88 {
                nodes: 256,
                time_step: 1e-4,
            }),
            _ => None,
        }
    }

    /// Node spacing.
    pub fn spacing(&self) -> f64 {
        1.0 / self.nodes as f64
    }

    /// A solver holding the example's particles at `positions`.
    pub fn solver(&self, positions: &[[f64; 2]], threads: usize) -> Result<Solver, MpmError> {
        let grid = GridSpec {
            origin: [0.0, 0.0],
            spacing: self.spacing(),
            nodes: [self.nodes, self.nodes],
            walls: Walls { low: 3, high: 2 },
        };
        let material = Material::Liquid(LiquidMaterial {
            density: 1.0,
            bulk_modulus: YOUNGS_MODULUS,
            viscosity: 0.0,
        });
        let settings = Settings {
            gravity: [0.0, -GRAVITY],
            threads,
            ..Settings::default()
        };
        let mut solver = Solver::new(grid, vec![material], &[], settings)?;
        let volume = (self.spacing() * 0.5).powi(2);
        for &position in positions {
            solver.add_particle(0, position, [0.0, -1.0], volume)?;
        }
        Ok(solver)
    }
}

/// What the benchmark compares: means over particles, in particle id order.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Summary {
    /// Mean x position.
    pub mean_x: f64,
    /// Mean y position.
    pub mean_y: f64,
    /// `½ · Σ m |v|²`.
    pub kinetic_energy: f64,
    /// Mean volume ratio.
    pub mean_j: f64,
}

/// The summary of a solver's particles, summed in id order.
pub fn summary(solver: &Solver) -> Summary {
    let particles = solver.particles_by_id();
    let count = particles.len().max(1) as f64;
    let mut sums = [0.0; 4];
    for (state, _, mass) in &particles {
        sums[0] += state.position[0];
        sums[1] += state.position[1];
        sums[2] += 0.5 * mass * (state.velocity[0].powi(2) + state.velocity[1].powi(2));
        sums[3] += state.volume_ratio;
    }
    Summary {
        mean_x: sums[0] / count,
        mean_y: sums[1] / count,
        kinetic_energy: sums[2],
        mean_j: sums[3] / count,
    }
}
