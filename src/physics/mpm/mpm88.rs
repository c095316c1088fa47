//! Taichi's `mpm88.py` example as a configuration of the MPM core, for parity and speed against
//! Taichi (`bench mpm88`, `benches/mpm88_taichi.py`). The example (taichi 1.7.4) fixes 8,192
//! particles on a 128² grid with `dt = 2e-4`; its 3-D twin `mpm3d.py` gives the 2-D setting for
//! 32,768 particles, a 256² grid with `dt = 1e-4`. Both: unit square, `dx = 1/n`, particle
//! volume `(dx/2)²`, density 1, pressure `E(J − 1)` with `E = 400`, gravity 9.8 down, walls three
//! nodes in at the low sides and two at the high sides (the example's `i > n − bound` with
//! `bound = 3`), initial velocity (0, −1), `J = 1`, `C = 0`.
//!
//! **Solids** ([`Mpm88Material`]): the same grid, substep, gravity, walls, particles and initial
//! state with the liquid swapped for an elastoplastic solid (fixed-corotated, von Mises on the
//! Hencky strain, [`super::elastic`]), so the solid's step rate sits next to the liquid's on the
//! same particle count; `benches/mpm88_taichi.py --material` runs the same solid in Taichi.
//!
//! Input: initial positions and the material. Output: a [`Solver`] and, after stepping, a
//! [`Summary`].

use std::str::FromStr;

use super::{
    ElastoplasticMaterial, GridSpec, LiquidMaterial, Material, MpmError, Settings, Solver, Walls,
};

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

/// Young's modulus of the solids, stress units. With [`SOLID_POISSON_RATIO`] it gives Lamé
/// `μ = 150`, `λ = 100`, so the P-wave modulus `λ + 2μ = 400` equals the liquid's bulk modulus
/// [`YOUNGS_MODULUS`]: at density 1 the solid's fastest wave travels at 20, like the liquid's
/// pressure wave, and the example's fixed substep keeps the same CFL number (0.51 of a cell a
/// substep at both configurations) the liquid is stable at. A stiffer solid would need a
/// smaller substep than the example's and so would not be the same run.
pub const SOLID_YOUNGS_MODULUS: f64 = 360.0;
/// Poisson's ratio of the solids (compressible like a rubber foam; far from the 0.5 where `λ`
/// and the wave speed blow up).
pub const SOLID_POISSON_RATIO: f64 = 0.2;
/// Von Mises yield stress of the plastic solid, stress units. The block's own weight at its base
/// (`ρ·g·h ≈ 9.8 × 0.4 ≈ 3.9`) and its landing at about 2 length/s push its deviatoric stress
/// past 2, so from the landing (about substep 600) on the block keeps flowing and the return map
/// projects a large share of the particles every substep (42% of the 16.4 M particle substeps of
/// a 2,000-substep run), not only in a few landing substeps; the elastic solid's yield stress is
/// infinite and its return map only checks the stretch range.
pub const PLASTIC_YIELD_STRESS: f64 = 2.0;

/// The particles' material: the example's liquid, or an elastoplastic solid on the same
/// configuration (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Mpm88Material {
    /// The example's weakly compressible liquid (pressure `E(J − 1)`, no viscosity).
    #[default]
    Liquid,
    /// A fixed-corotated elastic solid ([`SOLID_YOUNGS_MODULUS`], [`SOLID_POISSON_RATIO`]) that
    /// never yields.
    Elastic,
    /// The same solid with the finite yield stress [`PLASTIC_YIELD_STRESS`].
    Plastic,
}

/// A material name that is none of [`Mpm88Material::ALL`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown material `{0}`: expected one of {names}", names = Mpm88Material::names())]
pub struct UnknownMpm88Material(pub String);

impl Mpm88Material {
    /// Every material, in the order the benchmark runs them.
    pub const ALL: [Mpm88Material; 3] = [
        Mpm88Material::Liquid,
        Mpm88Material::Elastic,
        Mpm88Material::Plastic,
    ];

    /// The name (`liquid`, `elastic`, `plastic`).
    pub fn name(self) -> &'static str {
        match self {
            Mpm88Material::Liquid => "liquid",
            Mpm88Material::Elastic => "elastic",
            Mpm88Material::Plastic => "plastic",
        }
    }

    /// The names, comma separated.
    pub fn names() -> String {
        Mpm88Material::ALL.map(Mpm88Material::name).join(", ")
    }

    /// The MPM material at density 1.
    pub fn material(self) -> Material {
        let solid = |yield_stress| {
            Material::Elastoplastic(ElastoplasticMaterial {
                density: 1.0,
                youngs_modulus: SOLID_YOUNGS_MODULUS,
                poisson_ratio: SOLID_POISSON_RATIO,
                yield_stress,
            })
        };
        match self {
            Mpm88Material::Liquid => Material::Liquid(LiquidMaterial {
                density: 1.0,
                bulk_modulus: YOUNGS_MODULUS,
                viscosity: 0.0,
            }),
            Mpm88Material::Elastic => solid(f64::INFINITY),
            Mpm88Material::Plastic => solid(PLASTIC_YIELD_STRESS),
        }
    }
}

/// Accepts the names of [`Mpm88Material::name`], in any case.
impl FromStr for Mpm88Material {
    type Err = UnknownMpm88Material;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let lower = text.trim().to_ascii_lowercase();
        Mpm88Material::ALL
            .into_iter()
            .find(|material| material.name() == lower)
            .ok_or_else(|| UnknownMpm88Material(text.to_string()))
    }
}

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

    /// A solver holding the example's particles of `material` at `positions`.
    pub fn solver(
        &self,
        positions: &[[f64; 2]],
        material: Mpm88Material,
        threads: usize,
    ) -> Result<Solver, MpmError> {
        let grid = GridSpec {
            origin: [0.0, 0.0],
            spacing: self.spacing(),
            nodes: [self.nodes, self.nodes],
            walls: Walls { low: 3, high: 2 },
        };
        let settings = Settings {
            gravity: [0.0, -GRAVITY],
            threads,
            ..Settings::default()
        };
        let mut solver = Solver::new(grid, vec![material.material()], &[], settings)?;
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
    /// Mean volume ratio (solids: mean `det F`).
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
