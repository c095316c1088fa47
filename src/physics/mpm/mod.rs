//! 2D MLS-MPM (moving least squares material point method, Hu et al. 2018) with APIC transfer and
//! quadratic B-splines: ContPRO's simulator for fluids and soft balls, a core plus materials
//! (liquids; elastoplastic solids, [`elastic`]; rigid bodies moved whole, [`RigidBody`]), any of
//! them in one grid.
//!
//! Units are the caller's (the fluid scenario uses its rescaled square; `mpm88` uses Taichi's unit
//! square), all in f64. `y` points up; gravity is a vector of the settings.
//!
//! **One substep** ([`Solver::step`]): particles are binned by grid block (a stable counting sort
//! by block, then by their order); each block scatters its particles' mass, momentum and
//! stress into a private tile (the particle's block holds its stencil's base node, so the 3 × 3
//! stencil reaches at most two nodes into the next block); tiles are added into the grid in block
//! order; grid nodes turn momentum into velocity, take gravity, the domain walls and the
//! colliders; particles gather velocity and the APIC affine matrix `C`, move, and update their
//! volume ratio `J` (solids: their deformation gradient `F ← (I + Δt·C)·F`, projected onto the
//! yield surface); rigid bodies then take their particles' momentum and move as one. Blocks and particles run in parallel on a rayon pool, but every addition
//! happens in the same order whatever the thread count, so serial and parallel runs give the same
//! bytes.
//!
//! **Time step** ([`Solver::stable_time_step`], [`Solver::advance`]): the substep comes from the
//! CFL condition on the fastest particle plus the fastest material's wave speed, the APIC term
//! (sparkl's estimate) and, for viscous materials, the explicit-diffusion limit, never a fixed
//! value that explodes on stiff parameters. Every substep checks that every particle is finite;
//! particles are clamped into the grid (and counted) so the stencil never leaves it.
//!
//! Input: a [`GridSpec`], [`Material`]s, [`Collider`]s, particles and [`Emitter`]s. Output:
//! particle states by particle id, the work done ([`WorkCounters`]), typed errors.

mod collider;
pub mod elastic;
mod emitter;
mod grid;
mod material;
pub mod mpm88;
mod rigid;
#[cfg(test)]
mod solid_tests;
mod solver;
#[cfg(test)]
mod tests;
mod transfer;

pub use collider::{Boundary, Collider, Shape};
pub use emitter::Emitter;
pub use material::{
    ElastoplasticMaterial, LiquidMaterial, Material, RigidMaterial, VOLUME_RATIO_RANGE,
};
pub use rigid::{BodyMotion, RigidBody};
pub use solver::{ParticleState, Settings, Solver, WorkCounters};

/// Errors of the MPM core; each names the value at fault.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MpmError {
    /// The grid description is unusable.
    #[error("MPM grid: {0}")]
    InvalidGrid(String),
    /// A material parameter is out of range.
    #[error("MPM material {index}: {reason}")]
    InvalidMaterial {
        /// The material's index in the solver's table.
        index: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// A particle names a material the solver does not have.
    #[error("MPM particle at ({x}, {y}) names material {material}, but only {count} exist")]
    UnknownMaterial {
        /// The material index given.
        material: usize,
        /// How many materials the solver has.
        count: usize,
        /// The particle's position.
        x: f64,
        /// The particle's position.
        y: f64,
    },
    /// A particle position or velocity given by the caller is not finite.
    #[error("MPM particle at ({x}, {y}) with velocity ({vx}, {vy}) is not finite")]
    NonFiniteInput {
        /// Position, x.
        x: f64,
        /// Position, y.
        y: f64,
        /// Velocity, x.
        vx: f64,
        /// Velocity, y.
        vy: f64,
    },
    /// The solver already holds as many particles as ids can count (2³² − 1).
    #[error("MPM: no more particles can be added ({0} exist)")]
    TooManyParticles(u32),
    /// A time step is not positive and finite.
    #[error("MPM time step {0} s is not positive and finite")]
    InvalidTimeStep(f64),
    /// A particle's state stopped being finite during a substep.
    #[error("MPM particle {id} is not finite after substep {substep} (t = {time} s)")]
    NotFinite {
        /// The particle's id (order of creation).
        id: u32,
        /// Substeps taken before this one.
        substep: u64,
        /// Simulated time at the start of the failing substep, s.
        time: f64,
    },
    /// The stable time step is so small that the requested duration would need more substeps
    /// than the settings allow.
    #[error(
        "MPM: {duration} s at the stable time step {time_step:e} s needs {needed} substeps, more \
         than the limit {limit} (a material too stiff or particles too fast for this grid)"
    )]
    TooManySubsteps {
        /// Requested simulated time, s.
        duration: f64,
        /// The stable substep, s.
        time_step: f64,
        /// Substeps that would be needed.
        needed: f64,
        /// The limit in the settings.
        limit: u64,
    },
    /// A rigid body was asked for with a material that is not rigid, or a rigid material's
    /// particle was added on its own.
    #[error("MPM material {material}: {reason}")]
    RigidBody {
        /// The material index given.
        material: usize,
        /// What is wrong.
        reason: String,
    },
    /// The thread pool could not be built.
    #[error("MPM thread pool: {0}")]
    ThreadPool(String),
}

/// Lattice points `spacing` apart (offset by half a spacing from `centre`, so no point sits on
/// it) inside the disc of `radius` about `centre`: the particles of a disc of material, each
/// standing for `spacing²` of area.
pub fn disc_lattice(centre: [f64; 2], radius: f64, spacing: f64) -> Vec<[f64; 2]> {
    if !(spacing > 0.0 && radius > 0.0 && (radius / spacing).is_finite()) {
        return Vec::new();
    }
    #[expect(
        clippy::cast_possible_truncation,
        reason = "a positive, finite ratio; a disc spans a modest count of lattice sites"
    )]
    let reach = (radius / spacing).ceil() as i64;
    let mut points = Vec::new();
    for i in -reach..=reach {
        for j in -reach..=reach {
            let offset = [(i as f64 + 0.5) * spacing, (j as f64 + 0.5) * spacing];
            if offset[0].hypot(offset[1]) < radius {
                points.push([centre[0] + offset[0], centre[1] + offset[1]]);
            }
        }
    }
    points
}

/// A uniform grid: nodes `(i, j)` at `origin + (i, j)·spacing`, `i < nodes[0]`, `j < nodes[1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridSpec {
    /// Position of node (0, 0).
    pub origin: [f64; 2],
    /// Node spacing `dx`.
    pub spacing: f64,
    /// Nodes along x and y (at least 8 each).
    pub nodes: [usize; 2],
    /// Domain walls, in nodes from each side: nodes with index below `low` or at or above
    /// `nodes − high` lose the velocity component that points out of the domain. Taichi's examples
    /// use `low = 3`, `high = 2` (the test `i > n − 3`).
    pub walls: Walls,
}

/// Domain wall thickness in nodes (see [`GridSpec::walls`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Walls {
    /// Nodes on the low side (x and y) whose outward velocity is removed.
    pub low: usize,
    /// Nodes on the high side.
    pub high: usize,
}

impl GridSpec {
    /// Checks the numbers.
    pub fn validate(&self) -> Result<(), MpmError> {
        if !(self.spacing.is_finite() && self.spacing > 0.0) {
            return Err(MpmError::InvalidGrid(format!(
                "spacing {} is not positive and finite",
                self.spacing
            )));
        }
        if !(self.origin[0].is_finite() && self.origin[1].is_finite()) {
            return Err(MpmError::InvalidGrid(format!(
                "origin {:?} is not finite",
                self.origin
            )));
        }
        if self.nodes[0] < 8 || self.nodes[1] < 8 || self.nodes[0] > 1 << 15 {
            return Err(MpmError::InvalidGrid(format!(
                "{} × {} nodes: need 8 to 32768 along each axis",
                self.nodes[0], self.nodes[1]
            )));
        }
        if self.nodes[1] > 1 << 15 {
            return Err(MpmError::InvalidGrid(format!(
                "{} nodes along y: at most 32768",
                self.nodes[1]
            )));
        }
        Ok(())
    }

    /// Position of node `(i, j)`.
    pub fn node_position(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.origin[0] + i as f64 * self.spacing,
            self.origin[1] + j as f64 * self.spacing,
        ]
    }
}
