//! The MPM solver: particle storage, the substep (bin, scatter, grid update, gather) and the
//! stable time step. See the module above for the method; this file owns the data layout.
//!
//! Layout: particle state that changes every substep ([`ParticleState`]: position, velocity,
//! APIC matrix, volume ratio) is one array of structs, read whole by both transfers; what does not
//! change (mass, volume, material, id) is a second array in the same order. Both are kept in block
//! order: when particles change block, the scatter writes both, reordered, into spare arrays that
//! then take their place (one copy, fused with a read the scatter does anyway). The grid is one array of `[momentum x, momentum y, mass]`, which the
//! grid update turns into `[velocity x, velocity y, mass]` in place.

use rayon::prelude::*;

use super::collider::{Collider, ColliderGrid};
use super::elastic::{IDENTITY, Matrix2};
use super::elastic::{Projection, determinant};
use super::emitter::Emitter;
use super::grid::{
    Bins, GridUpdate, block_corner, block_key, blocks_along, index_u32, merge_and_update,
};
use super::material::{Material, VOLUME_RATIO_RANGE};
use super::rigid::RigidBodies;
use super::transfer::{
    ParticleConstants, StepConstants, TILE, affine_norm_squared, clamp_position, gather_particle,
    is_finite, scatter_particle, speed_squared,
};
use super::{GridSpec, MpmError};

/// Particles per parallel gather task.
const GATHER_CHUNK: usize = 1024;

/// What moves: one particle's state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ParticleState {
    /// Position.
    pub position: [f64; 2],
    /// Velocity.
    pub velocity: [f64; 2],
    /// APIC affine matrix `C` (the velocity gradient), row-major.
    pub affine: [f64; 4],
    /// Volume ratio `J` (current volume over initial).
    pub volume_ratio: f64,
    /// Elastic deformation gradient `F`, row-major: the identity at rest; updated only for
    /// materials that carry one ([`Material::has_deformation`]), so `J = det F` there.
    pub deformation: Matrix2,
}

/// Solver settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// Gravity, length/s².
    pub gravity: [f64; 2],
    /// CFL number of the adaptive substep (fraction of a cell a wave or particle crosses).
    pub cfl: f64,
    /// Most substeps one [`Solver::advance`] may take before it reports the case as too stiff.
    pub max_substeps: u64,
    /// Worker threads (1 = serial; results are the same bytes for any count).
    pub threads: usize,
    /// How far outside a collider's surface grid nodes are still held by it, in cells. At 0
    /// only nodes inside are held, and the first held row lies anywhere from 0 to a cell under
    /// the surface as the collider sits against the grid: a solid reaching the surface before
    /// the grid stops it is put back with its approaching velocity removed, so an elastic
    /// disc regains from 33% to 89% of its drop height with that offset (dx 0.1). At 0.5 the held
    /// row lies within half a cell of the surface and the restitution stays within 0.01.
    pub collider_layer: f64,
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            gravity: [0.0, -9.8],
            cfl: 0.5,
            max_substeps: 2_000_000,
            threads: 1,
            collider_layer: 0.0,
        }
    }
}

/// Work done so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct WorkCounters {
    /// Substeps taken.
    pub substeps: u64,
    /// Particles × substeps.
    pub particle_substeps: u64,
    /// Particles released by emitters.
    pub emitted: u64,
    /// Times a particle was clamped back into the grid (zero in a healthy run).
    pub clamped: u64,
    /// Times a volume ratio was clamped into its range (zero in a healthy run).
    pub volume_ratio_clamped: u64,
    /// Times a particle that ended a substep inside a collider was put back on its surface.
    pub pushed_out: u64,
    /// Times a solid particle's deformation was projected onto its yield surface (plastic flow).
    pub yielded: u64,
    /// Times a solid particle's stretch was clamped into its range (zero in a healthy run).
    pub stretch_clamped: u64,
}

/// The MPM solver.
#[derive(Debug)]
pub struct Solver {
    pub(super) grid: GridSpec,
    pub(super) settings: Settings,
    pub(super) materials: Vec<Material>,
    pub(super) emitters: Vec<Emitter>,
    /// The colliders, rasterised onto the nodes.
    pub(super) colliders: ColliderGrid,
    pub(super) state: Vec<ParticleState>,
    pub(super) constants: Vec<ParticleConstants>,
    /// Where the scatter writes the particles in their new order when binning reorders them;
    /// swapped with `state` and `constants` after it.
    pub(super) spare_state: Vec<ParticleState>,
    pub(super) spare_constants: Vec<ParticleConstants>,
    pub(super) nodes: Vec<[f64; 3]>,
    /// One tile per non-empty block, in block order.
    pub(super) tiles: Vec<[f64; 3]>,
    /// Each particle's block, from its position at the end of the last substep.
    pub(super) block_of: Vec<u32>,
    /// Each particle's stencil base node, from the same position (see
    /// [`StepConstants::base_cell`]); kept in the particles' order like `state`.
    pub(super) base_of: Vec<[u32; 2]>,
    pub(super) spare_base: Vec<[u32; 2]>,
    pub(super) bins: Bins,
    pub(super) time: f64,
    pub(super) next_id: u32,
    /// Largest particle speed and APIC norm after the last gather (for the stable step).
    pub(super) max_speed: f64,
    pub(super) max_affine: f64,
    pub(super) counters: WorkCounters,
    pub(super) rigid: RigidBodies,
    pub(super) pool: std::sync::Arc<rayon::ThreadPool>,
}

impl Solver {
    /// A solver with no particles. Colliders are rasterised onto the grid nodes here.
    pub fn new(
        grid: GridSpec,
        materials: Vec<Material>,
        colliders: &[Collider],
        settings: Settings,
    ) -> Result<Solver, MpmError> {
        grid.validate()?;
        for (index, material) in materials.iter().enumerate() {
            material.validate(index)?;
        }
        if let Some(bad) = colliders.iter().position(|collider| !collider.is_valid()) {
            return Err(MpmError::InvalidGrid(format!(
                "collider {bad} has non-finite numbers, a negative radius or friction, or a \
                 normal that is not a unit vector"
            )));
        }
        if !(settings.cfl.is_finite() && settings.cfl > 0.0 && settings.cfl <= 1.0) {
            return Err(MpmError::InvalidGrid(format!(
                "CFL number {} is not in (0, 1]",
                settings.cfl
            )));
        }
        if !(settings.collider_layer.is_finite() && (0.0..=1.0).contains(&settings.collider_layer))
        {
            return Err(MpmError::InvalidGrid(format!(
                "collider layer {} is not 0 to 1 cells",
                settings.collider_layer
            )));
        }
        if !(settings.gravity[0].is_finite() && settings.gravity[1].is_finite()) {
            return Err(MpmError::InvalidGrid(format!(
                "gravity {:?} is not finite",
                settings.gravity
            )));
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(settings.threads.max(1))
            .build()
            .map_err(|error| MpmError::ThreadPool(error.to_string()))
            .map(std::sync::Arc::new)?;
        let colliders = ColliderGrid::new(&grid, colliders, settings.collider_layer);
        let node_count = grid.nodes[0] * grid.nodes[1];
        Ok(Solver {
            grid,
            settings,
            materials,
            emitters: Vec::new(),
            colliders,
            state: Vec::new(),
            constants: Vec::new(),
            spare_state: Vec::new(),
            spare_constants: Vec::new(),
            nodes: vec![[0.0; 3]; node_count],
            tiles: Vec::new(),
            block_of: Vec::new(),
            base_of: Vec::new(),
            spare_base: Vec::new(),
            bins: Bins::default(),
            time: 0.0,
            next_id: 0,
            max_speed: 0.0,
            max_affine: 0.0,
            counters: WorkCounters::default(),
            rigid: RigidBodies::default(),
            pool,
        })
    }

    /// Adds a particle of `material` with `volume` (area in 2D) at rest deformation; returns its
    /// id (ids count up from 0 in order of creation, emitted particles included). Particles of a
    /// rigid material come only in bodies ([`Solver::add_rigid_body`]).
    pub fn add_particle(
        &mut self,
        material: usize,
        position: [f64; 2],
        velocity: [f64; 2],
        volume: f64,
    ) -> Result<u32, MpmError> {
        if let Some(Material::Rigid(_)) = self.materials.get(material) {
            return Err(MpmError::RigidBody {
                material,
                reason: "particles of a rigid material are added as a body (add_rigid_body)"
                    .to_string(),
            });
        }
        self.add_any_particle(material, position, velocity, volume)
    }

    pub(super) fn add_any_particle(
        &mut self,
        material: usize,
        position: [f64; 2],
        velocity: [f64; 2],
        volume: f64,
    ) -> Result<u32, MpmError> {
        let Some(found) = self.materials.get(material) else {
            return Err(MpmError::UnknownMaterial {
                material,
                count: self.materials.len(),
                x: position[0],
                y: position[1],
            });
        };
        let finite = position
            .iter()
            .chain(velocity.iter())
            .all(|value| value.is_finite());
        if !finite {
            return Err(MpmError::NonFiniteInput {
                x: position[0],
                y: position[1],
                vx: velocity[0],
                vy: velocity[1],
            });
        }
        let mass = found.density() * volume;
        let id = self.next_id;
        self.next_id = id.checked_add(1).ok_or(MpmError::TooManyParticles(id))?;
        let mut state = ParticleState {
            position,
            velocity,
            affine: [0.0; 4],
            volume_ratio: 1.0,
            deformation: IDENTITY,
        };
        if self.clamp_into_grid(&mut state.position) {
            self.counters.clamped += 1;
        }
        self.speed_seen(&state);
        let base = self.step_constants(0.0).base_cell(state.position);
        self.block_of
            .push(block_key(base, blocks_along(&self.grid)));
        self.base_of.push(base);
        self.state.push(state);
        self.constants.push(ParticleConstants {
            mass,
            volume,
            material: index_u32(material),
            id,
        });
        Ok(id)
    }

    /// Adds an emitter; it releases particles during later substeps.
    pub fn add_emitter(&mut self, emitter: Emitter) -> Result<(), MpmError> {
        if emitter.material >= self.materials.len() {
            return Err(MpmError::UnknownMaterial {
                material: emitter.material,
                count: self.materials.len(),
                x: emitter.center[0],
                y: emitter.center[1],
            });
        }
        if !emitter.is_valid() {
            return Err(MpmError::InvalidGrid(format!(
                "emitter at {:?}: its numbers must be finite, its direction a unit vector and \
                 its width, speed and spacing positive",
                emitter.center
            )));
        }
        self.emitters.push(emitter);
        Ok(())
    }

    /// The grid.
    pub fn grid(&self) -> &GridSpec {
        &self.grid
    }

    /// The materials, by index.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Work done so far.
    pub fn counters(&self) -> WorkCounters {
        self.counters
    }

    /// Number of particles.
    pub fn particle_count(&self) -> usize {
        self.state.len()
    }

    /// Total particle mass (exactly the sum of what was added: masses never change).
    pub fn total_mass(&self) -> f64 {
        let mut by_id: Vec<(u32, f64)> = self
            .constants
            .iter()
            .map(|constants| (constants.id, constants.mass))
            .collect();
        by_id.sort_unstable_by_key(|(id, _)| *id);
        by_id.iter().map(|(_, mass)| mass).sum()
    }

    /// Particle states indexed by id, with each particle's material and mass.
    pub fn particles_by_id(&self) -> Vec<(ParticleState, usize, f64)> {
        let mut out = vec![(ParticleState::default(), 0, 0.0); self.state.len()];
        for (state, constants) in self.state.iter().zip(&self.constants) {
            if let Some(slot) = out.get_mut(constants.id as usize) {
                *slot = (*state, constants.material as usize, constants.mass);
            }
        }
        out
    }

    /// The largest stable substep for the current state: the CFL limit on the fastest particle
    /// (with sparkl's APIC term) plus the fastest wave, and the explicit-viscosity limit.
    pub fn stable_time_step(&self) -> f64 {
        let dx = self.grid.spacing;
        let wave = self
            .materials
            .iter()
            .map(Material::wave_speed)
            .fold(0.0, f64::max);
        let diffusion = self
            .materials
            .iter()
            .map(Material::kinematic_viscosity)
            .fold(0.0, f64::max);
        let apic = 6.0 * std::f64::consts::SQRT_2 * dx / 4.0 * self.max_affine;
        let speed = self.max_speed + apic + wave;
        let mut dt = if speed > 0.0 {
            self.settings.cfl * dx / speed
        } else {
            f64::INFINITY
        };
        if diffusion > 0.0 {
            dt = dt.min(self.settings.cfl * dx * dx / (2.0 * diffusion));
        }
        // A particle at rest with no wave to limit it (rigid bodies) still falls: within one step
        // gravity alone must not carry it more than the CFL share of a cell, `½·g·Δt² ≤ cfl·dx/2`.
        // Never the binding limit where a material has waves (the fluids' bytes are unchanged).
        let gravity = self.settings.gravity[0].hypot(self.settings.gravity[1]);
        if gravity > 0.0 {
            dt = dt.min((self.settings.cfl * dx / gravity).sqrt());
        }
        dt
    }

    /// Advances by `duration` seconds in substeps of at most the stable step (the last one
    /// shortened to land on the duration).
    pub fn advance(&mut self, duration: f64) -> Result<(), MpmError> {
        if !(duration.is_finite() && duration >= 0.0) {
            return Err(MpmError::InvalidTimeStep(duration));
        }
        let end = self.time + duration;
        let mut taken = 0u64;
        while self.time < end {
            let stable = self.stable_time_step();
            let remaining = end - self.time;
            let needed = (remaining / stable).ceil();
            if taken as f64 + needed > self.settings.max_substeps as f64 {
                return Err(MpmError::TooManySubsteps {
                    duration,
                    time_step: stable,
                    needed: taken as f64 + needed,
                    limit: self.settings.max_substeps,
                });
            }
            // Equal substeps up to the end rather than one short tail.
            let dt = remaining / needed.max(1.0);
            self.step(dt)?;
            taken += 1;
            if needed <= 1.0 {
                self.time = end;
            }
        }
        Ok(())
    }

    /// One substep of `dt` seconds.
    pub fn step(&mut self, dt: f64) -> Result<(), MpmError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(MpmError::InvalidTimeStep(dt));
        }
        self.emit(dt)?;
        let pool = std::sync::Arc::clone(&self.pool);
        pool.install(|| self.substep(dt))
    }

    fn emit(&mut self, dt: f64) -> Result<(), MpmError> {
        let mut released = Vec::new();
        let mut emitters = std::mem::take(&mut self.emitters);
        for emitter in &mut emitters {
            released.clear();
            emitter.emit(self.time, dt, &mut released);
            let volume = emitter.spacing * emitter.spacing;
            for &(position, velocity) in &released {
                self.add_particle(emitter.material, position, velocity, volume)?;
                self.counters.emitted += 1;
            }
        }
        self.emitters = emitters;
        Ok(())
    }

    fn substep(&mut self, dt: f64) -> Result<(), MpmError> {
        self.bin_by_block();
        self.scatter(dt);
        self.update_grid(dt);
        if !self.rigid.is_empty() {
            self.couple_rigid_bodies(dt);
        }
        self.gather(dt)?;
        self.time += dt;
        self.counters.substeps += 1;
        self.counters.particle_substeps += self.state.len() as u64;
        Ok(())
    }

    /// Bins the particles by block (their keys were computed by the last gather or on adding).
    fn bin_by_block(&mut self) {
        let along = blocks_along(&self.grid);
        self.bins.bin(&self.block_of, along[0] * along[1]);
    }

    /// Particle to grid: each block into its tile in parallel. When the binning reordered the
    /// particles, each block reads its particles through the permutation and writes them, in
    /// the new order, into the spare buffers, which then become the particle arrays.
    fn scatter(&mut self, dt: f64) {
        let along = blocks_along(&self.grid);
        let step = self.step_constants(dt);
        self.tiles
            .resize(self.bins.blocks.len() * TILE * TILE, [0.0; 3]);
        let materials = &self.materials;
        let blocks = &self.bins.blocks;
        let tiles = self
            .tiles
            .par_chunks_mut(TILE * TILE)
            .zip(blocks.par_iter());
        if self.bins.sorted {
            let state = &self.state;
            let constants = &self.constants;
            let base_of = &self.base_of;
            tiles.for_each(|(tile, &(block, start, end))| {
                tile.fill([0.0; 3]);
                let corner = block_corner(block, along);
                let range = start as usize..end as usize;
                let (Some(particles), Some(constants), Some(bases)) = (
                    state.get(range.clone()),
                    constants.get(range.clone()),
                    base_of.get(range),
                ) else {
                    return;
                };
                for ((particle, constant), &base) in particles.iter().zip(constants).zip(bases) {
                    if let Some(material) = materials.get(constant.material as usize)
                        && material.scatters()
                    {
                        scatter_particle(tile, corner, particle, base, constant, material, &step);
                    }
                }
            });
            return;
        }
        let count = self.state.len();
        self.spare_state.resize(count, ParticleState::default());
        self.spare_constants
            .resize(count, ParticleConstants::default());
        self.spare_base.resize(count, [0; 2]);
        // Each block's slots of the spare buffers, cut in block order.
        let mut slots = Vec::with_capacity(blocks.len());
        let mut rest_state = self.spare_state.as_mut_slice();
        let mut rest_constants = self.spare_constants.as_mut_slice();
        let mut rest_base = self.spare_base.as_mut_slice();
        for &(_, start, end) in blocks {
            let length = (end - start) as usize;
            let (state_here, state_after) = rest_state.split_at_mut(length.min(rest_state.len()));
            let (constants_here, constants_after) =
                rest_constants.split_at_mut(length.min(rest_constants.len()));
            let (base_here, base_after) = rest_base.split_at_mut(length.min(rest_base.len()));
            slots.push((state_here, constants_here, base_here, start as usize));
            rest_state = state_after;
            rest_constants = constants_after;
            rest_base = base_after;
        }
        let state = &self.state;
        let constants = &self.constants;
        let base_of = &self.base_of;
        let order = &self.bins.order;
        tiles.zip(slots.into_par_iter()).for_each(
            |((tile, &(block, _, _)), (states_out, constants_out, bases_out, start))| {
                tile.fill([0.0; 3]);
                let corner = block_corner(block, along);
                let sources = order.get(start..start + states_out.len()).unwrap_or(&[]);
                let outputs = states_out
                    .iter_mut()
                    .zip(constants_out.iter_mut())
                    .zip(bases_out);
                for (((state_out, constant_out), base_out), &source) in outputs.zip(sources) {
                    let source = source as usize;
                    let (Some(particle), Some(constant), Some(&base)) = (
                        state.get(source),
                        constants.get(source),
                        base_of.get(source),
                    ) else {
                        continue;
                    };
                    *state_out = *particle;
                    *constant_out = *constant;
                    *base_out = base;
                    if let Some(material) = materials.get(constant.material as usize)
                        && material.scatters()
                    {
                        scatter_particle(tile, corner, particle, base, constant, material, &step);
                    }
                }
            },
        );
        std::mem::swap(&mut self.state, &mut self.spare_state);
        std::mem::swap(&mut self.constants, &mut self.spare_constants);
        std::mem::swap(&mut self.base_of, &mut self.spare_base);
    }

    /// Tiles into grid velocities (see [`merge_and_update`]).
    fn update_grid(&mut self, dt: f64) {
        let update = GridUpdate {
            grid: &self.grid,
            gravity: [dt * self.settings.gravity[0], dt * self.settings.gravity[1]],
            colliders: &self.colliders,
            tiles: &self.tiles,
            tile_of: &self.bins.tile_of,
        };
        merge_and_update(&mut self.nodes, &update);
    }

    /// Grid to particle: velocity, APIC matrix, position, volume ratio; checks finiteness and
    /// computes each particle's block for the next binning.
    fn gather(&mut self, dt: f64) -> Result<(), MpmError> {
        let step = self.step_constants(dt);
        let nodes = &self.nodes;
        let columns = self.grid.nodes[1];
        let along = blocks_along(&self.grid);
        let limits = self.position_limits();
        let colliders = &self.colliders;
        let any_collider = colliders.has_colliders();
        let materials = &self.materials;
        // Liquids alone (the fluid scenario) never read the constants here.
        let any_deformation = materials.iter().any(Material::has_deformation);
        self.block_of.resize(self.state.len(), 0);
        self.base_of.resize(self.state.len(), [0; 2]);
        let outcome = self
            .state
            .par_chunks_mut(GATHER_CHUNK)
            .zip(self.block_of.par_chunks_mut(GATHER_CHUNK))
            .zip(self.base_of.par_chunks_mut(GATHER_CHUNK))
            .zip(self.constants.par_chunks(GATHER_CHUNK))
            .enumerate()
            .map(|(chunk, (((particles, blocks), bases), constants))| {
                let mut outcome = GatherOutcome::default();
                let each = particles.iter_mut().zip(blocks).zip(bases).zip(constants);
                for (offset, (((particle, block), base), constant)) in each.enumerate() {
                    gather_particle(particle, *base, nodes, columns, &step);
                    let solid = if any_deformation {
                        materials
                            .get(constant.material as usize)
                            .filter(|material| material.has_deformation())
                    } else {
                        None
                    };
                    if let Some(material) = solid {
                        match deform(particle, material, dt) {
                            Projection::Elastic => {}
                            Projection::Yielded => outcome.yielded += 1,
                            Projection::Clamped => outcome.stretch_clamped += 1,
                        }
                    }
                    if any_collider {
                        let nearest = step.nearest_node(particle.position, columns);
                        outcome.pushed_out += u64::from(colliders.push_out(particle, nearest));
                    }
                    outcome.clamped += u64::from(clamp_position(&mut particle.position, limits));
                    let ratio = particle.volume_ratio;
                    if solid.is_none()
                        && (ratio < VOLUME_RATIO_RANGE.0 || ratio > VOLUME_RATIO_RANGE.1)
                    {
                        particle.volume_ratio =
                            ratio.clamp(VOLUME_RATIO_RANGE.0, VOLUME_RATIO_RANGE.1);
                        outcome.ratio_clamped += 1;
                    }
                    if !is_finite(particle) && outcome.first_bad.is_none() {
                        outcome.first_bad = Some(chunk * GATHER_CHUNK + offset);
                    }
                    outcome.max_speed_squared =
                        outcome.max_speed_squared.max(speed_squared(particle));
                    outcome.max_affine_squared = outcome
                        .max_affine_squared
                        .max(affine_norm_squared(particle));
                    *base = step.base_cell(particle.position);
                    *block = block_key(*base, along);
                }
                outcome
            })
            .reduce(GatherOutcome::default, GatherOutcome::merge);
        if let Some(index) = outcome.first_bad {
            return Err(MpmError::NotFinite {
                id: self.constants.get(index).map_or(u32::MAX, |c| c.id),
                substep: self.counters.substeps,
                time: self.time,
            });
        }
        self.counters.clamped += outcome.clamped;
        self.counters.volume_ratio_clamped += outcome.ratio_clamped;
        self.counters.pushed_out += outcome.pushed_out;
        self.counters.yielded += outcome.yielded;
        self.counters.stretch_clamped += outcome.stretch_clamped;
        self.max_speed = outcome.max_speed_squared.sqrt();
        self.max_affine = outcome.max_affine_squared.sqrt();
        if !self.rigid.is_empty() {
            self.move_rigid_bodies(dt)?;
        }
        Ok(())
    }

    pub(super) fn step_constants(&self, dt: f64) -> StepConstants {
        StepConstants {
            origin: self.grid.origin,
            dx: self.grid.spacing,
            inverse: 1.0 / self.grid.spacing,
            dt,
        }
    }

    /// Positions stay within `[dx/2, (n − 3/2)·dx)` of the origin: the widest range whose 3 × 3
    /// stencil (`base = ⌊x/dx − 1/2⌋ ∈ [0, n − 3]`) stays in the grid. A narrower range would move
    /// particles a healthy run leaves alone (Taichi's mpm88 lets them reach `126.03·dx` of 128).
    pub(super) fn position_limits(&self) -> [[f64; 2]; 2] {
        let dx = self.grid.spacing;
        // The margin keeps `⌊x/dx − 1/2⌋` below `n − 2` after rounding of the division.
        let high_cells = |nodes: usize| nodes as f64 - 1.5 - STENCIL_MARGIN;
        let low = [
            self.grid.origin[0] + 0.5 * dx,
            self.grid.origin[1] + 0.5 * dx,
        ];
        let high = [
            self.grid.origin[0] + high_cells(self.grid.nodes[0]) * dx,
            self.grid.origin[1] + high_cells(self.grid.nodes[1]) * dx,
        ];
        [low, high]
    }

    fn clamp_into_grid(&self, position: &mut [f64; 2]) -> bool {
        clamp_position(position, self.position_limits())
    }

    fn speed_seen(&mut self, state: &ParticleState) {
        self.max_speed = self.max_speed.max(speed_squared(state).sqrt());
    }
}

/// A solid particle's deformation gradient after the gather: `F ← (I + Δt·C)·F` with the new
/// velocity gradient `C`, projected by the material's plasticity; its volume ratio is `det F`.
#[inline]
fn deform(particle: &mut ParticleState, material: &Material, dt: f64) -> Projection {
    let c = particle.affine;
    let step = [1.0 + dt * c[0], dt * c[1], dt * c[2], 1.0 + dt * c[3]];
    particle.deformation = super::elastic::multiply(&step, &particle.deformation);
    let projection = material.project(&mut particle.deformation);
    particle.volume_ratio = determinant(&particle.deformation);
    projection
}

/// Fraction of a cell kept between a clamped particle and the edge of the stencil range.
const STENCIL_MARGIN: f64 = 1e-9;

/// Per-task results of the gather, merged with max/min/sum of integers (order-independent).
#[derive(Debug, Default, Clone, Copy)]
struct GatherOutcome {
    first_bad: Option<usize>,
    clamped: u64,
    ratio_clamped: u64,
    pushed_out: u64,
    yielded: u64,
    stretch_clamped: u64,
    max_speed_squared: f64,
    max_affine_squared: f64,
}

impl GatherOutcome {
    fn merge(a: GatherOutcome, b: GatherOutcome) -> GatherOutcome {
        GatherOutcome {
            first_bad: match (a.first_bad, b.first_bad) {
                (Some(x), Some(y)) => Some(x.min(y)),
                (x, y) => x.or(y),
            },
            clamped: a.clamped + b.clamped,
            ratio_clamped: a.ratio_clamped + b.ratio_clamped,
            pushed_out: a.pushed_out + b.pushed_out,
            yielded: a.yielded + b.yielded,
            stretch_clamped: a.stretch_clamped + b.stretch_clamped,
            max_speed_squared: a.max_speed_squared.max(b.max_speed_squared),
            max_affine_squared: a.max_affine_squared.max(b.max_affine_squared),
        }
    }
}
