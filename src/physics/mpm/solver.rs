//! The MPM solver: particle storage, the substep (bin, scatter, grid update, gather) and the
//! stable time step. See the module above for the method; this file owns the data layout.
//!
//! Layout: particle state that changes every substep ([`ParticleState`]: position, velocity,
//! APIC matrix, volume ratio) is one array of structs, read whole by both transfers; what does not
//! change (mass, volume, material, id) is a second array in the same order. Both are reordered by
//! grid block each substep. The grid is one array of `[momentum x, momentum y, mass]`, which the
//! grid update turns into `[velocity x, velocity y, mass]` in place.

use rayon::prelude::*;

use super::collider::{Collider, ColliderGrid, project};
use super::emitter::Emitter;
use super::material::{Material, VOLUME_RATIO_RANGE};
use super::{GridSpec, MpmError};

/// Nodes along each side of a block: the unit of binning and of parallel scattering.
const BLOCK: usize = 8;
/// A block's private tile: its nodes plus the two the quadratic stencil reaches beyond.
const TILE: usize = BLOCK + 2;
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
}

/// What does not move: a particle's constants.
#[derive(Debug, Clone, Copy, PartialEq)]
struct ParticleConstants {
    mass: f64,
    volume: f64,
    material: u32,
    id: u32,
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
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            gravity: [0.0, -9.8],
            cfl: 0.5,
            max_substeps: 2_000_000,
            threads: 1,
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
}

/// The MPM solver.
#[derive(Debug)]
pub struct Solver {
    grid: GridSpec,
    settings: Settings,
    materials: Vec<Material>,
    emitters: Vec<Emitter>,
    /// The colliders, rasterised onto the nodes.
    colliders: ColliderGrid,
    state: Vec<ParticleState>,
    constants: Vec<ParticleConstants>,
    nodes: Vec<[f64; 3]>,
    tiles: Vec<[f64; 3]>,
    block_of: Vec<u32>,
    /// Non-empty blocks after binning: (block index, first particle, end).
    blocks: Vec<(u32, u32, u32)>,
    time: f64,
    next_id: u32,
    /// Largest particle speed and APIC norm after the last gather (for the stable step).
    max_speed: f64,
    max_affine: f64,
    counters: WorkCounters,
    pool: std::sync::Arc<rayon::ThreadPool>,
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
        let colliders = ColliderGrid::new(&grid, colliders);
        let node_count = grid.nodes[0] * grid.nodes[1];
        Ok(Solver {
            grid,
            settings,
            materials,
            emitters: Vec::new(),
            colliders,
            state: Vec::new(),
            constants: Vec::new(),
            nodes: vec![[0.0; 3]; node_count],
            tiles: Vec::new(),
            block_of: Vec::new(),
            blocks: Vec::new(),
            time: 0.0,
            next_id: 0,
            max_speed: 0.0,
            max_affine: 0.0,
            counters: WorkCounters::default(),
            pool,
        })
    }

    /// Adds a particle of `material` with `volume` (area in 2D) at rest deformation; returns its
    /// id (ids count up from 0 in order of creation, emitted particles included).
    pub fn add_particle(
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
        };
        if self.clamp_into_grid(&mut state.position) {
            self.counters.clamped += 1;
        }
        self.speed_seen(&state);
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
        self.gather(dt)?;
        self.time += dt;
        self.counters.substeps += 1;
        self.counters.particle_substeps += self.state.len() as u64;
        Ok(())
    }

    fn blocks_along(&self) -> [usize; 2] {
        [
            self.grid.nodes[0].div_ceil(BLOCK),
            self.grid.nodes[1].div_ceil(BLOCK),
        ]
    }

    /// Reorders particles by block (stable), and lists the non-empty blocks.
    fn bin_by_block(&mut self) {
        let inverse = 1.0 / self.grid.spacing;
        let origin = self.grid.origin;
        let along = self.blocks_along();
        self.block_of.resize(self.state.len(), 0);
        self.block_of
            .par_iter_mut()
            .zip(self.state.par_iter())
            .for_each(|(block, state)| {
                let base = base_node(state.position, origin, inverse);
                *block = index_u32((base[0] / BLOCK) * along[1] + base[1] / BLOCK);
            });
        if !self.block_of.is_sorted() {
            let mut starts = vec![0u32; along[0] * along[1] + 1];
            for &block in &self.block_of {
                starts[block as usize + 1] += 1;
            }
            for index in 1..starts.len() {
                starts[index] += starts[index - 1];
            }
            let mut order = vec![0u32; self.state.len()];
            for (index, &block) in self.block_of.iter().enumerate() {
                let slot = &mut starts[block as usize];
                order[*slot as usize] = index_u32(index);
                *slot += 1;
            }
            let state = &self.state;
            let constants = &self.constants;
            let block_of = &self.block_of;
            let reordered: Vec<(ParticleState, ParticleConstants, u32)> = order
                .par_iter()
                .map(|&index| {
                    let index = index as usize;
                    (state[index], constants[index], block_of[index])
                })
                .collect();
            for (slot, (state, constants, block)) in reordered.into_iter().enumerate() {
                self.state[slot] = state;
                self.constants[slot] = constants;
                self.block_of[slot] = block;
            }
        }
        self.blocks.clear();
        let mut start = 0usize;
        for index in 1..=self.block_of.len() {
            if index == self.block_of.len() || self.block_of[index] != self.block_of[start] {
                self.blocks
                    .push((self.block_of[start], index_u32(start), index_u32(index)));
                start = index;
            }
        }
    }

    /// Particle to grid: each block into its tile in parallel, then the tiles into the grid in
    /// block order.
    fn scatter(&mut self, dt: f64) {
        let dx = self.grid.spacing;
        let inverse = 1.0 / dx;
        let origin = self.grid.origin;
        let along = self.blocks_along();
        let nodes = self.grid.nodes;
        self.tiles.clear();
        self.tiles.resize(self.blocks.len() * TILE * TILE, [0.0; 3]);
        let state = &self.state;
        let constants = &self.constants;
        let materials = &self.materials;
        self.tiles
            .par_chunks_mut(TILE * TILE)
            .zip(self.blocks.par_iter())
            .for_each(|(tile, &(block, start, end))| {
                let corner = block_corner(block, along);
                let range = start as usize..end as usize;
                for (particle, constant) in state[range.clone()].iter().zip(&constants[range]) {
                    let material = &materials[constant.material as usize];
                    scatter_particle(
                        tile, corner, particle, constant, material, origin, dx, inverse, dt,
                    );
                }
            });
        self.nodes.par_iter_mut().for_each(|node| *node = [0.0; 3]);
        for (tile, &(block, _, _)) in self.tiles.chunks(TILE * TILE).zip(&self.blocks) {
            let corner = block_corner(block, along);
            for a in 0..TILE.min(nodes[0] - corner[0]) {
                let row = (corner[0] + a) * nodes[1] + corner[1];
                let width = TILE.min(nodes[1] - corner[1]);
                for (node, value) in self.nodes[row..row + width]
                    .iter_mut()
                    .zip(&tile[a * TILE..a * TILE + width])
                {
                    node[0] += value[0];
                    node[1] += value[1];
                    node[2] += value[2];
                }
            }
        }
    }

    /// Momentum to velocity, gravity, domain walls, colliders; row by row in parallel.
    fn update_grid(&mut self, dt: f64) {
        let nodes = self.grid.nodes;
        let walls = self.grid.walls;
        let gravity = [dt * self.settings.gravity[0], dt * self.settings.gravity[1]];
        let colliders = &self.colliders;
        self.nodes
            .par_chunks_mut(nodes[1])
            .enumerate()
            .for_each(|(i, row)| {
                for (j, node) in row.iter_mut().enumerate() {
                    if node[2] <= 0.0 {
                        node[0] = 0.0;
                        node[1] = 0.0;
                        continue;
                    }
                    let mut velocity = [
                        node[0] / node[2] + gravity[0],
                        node[1] / node[2] + gravity[1],
                    ];
                    if i < walls.low && velocity[0] < 0.0
                        || i >= nodes[0] - walls.high && velocity[0] > 0.0
                    {
                        velocity[0] = 0.0;
                    }
                    if j < walls.low && velocity[1] < 0.0
                        || j >= nodes[1] - walls.high && velocity[1] > 0.0
                    {
                        velocity[1] = 0.0;
                    }
                    if let Some((normal, boundary)) = colliders.constraint(i * nodes[1] + j) {
                        velocity = project(velocity, normal, boundary);
                    }
                    node[0] = velocity[0];
                    node[1] = velocity[1];
                }
            });
    }

    /// Grid to particle: velocity, APIC matrix, position, volume ratio; checks finiteness.
    fn gather(&mut self, dt: f64) -> Result<(), MpmError> {
        let dx = self.grid.spacing;
        let inverse = 1.0 / dx;
        let origin = self.grid.origin;
        let nodes = &self.nodes;
        let columns = self.grid.nodes[1];
        let limits = self.position_limits();
        let colliders = &self.colliders;
        let outcome = self
            .state
            .par_chunks_mut(GATHER_CHUNK)
            .enumerate()
            .map(|(chunk, particles)| {
                let mut outcome = GatherOutcome::default();
                for (offset, particle) in particles.iter_mut().enumerate() {
                    gather_particle(particle, nodes, columns, origin, dx, inverse, dt);
                    let nearest = nearest_node(particle.position, origin, inverse, columns);
                    outcome.pushed_out += u64::from(colliders.push_out(particle, nearest));
                    outcome.clamped += u64::from(clamp_position(&mut particle.position, limits));
                    let ratio = particle.volume_ratio;
                    if ratio < VOLUME_RATIO_RANGE.0 || ratio > VOLUME_RATIO_RANGE.1 {
                        particle.volume_ratio =
                            ratio.clamp(VOLUME_RATIO_RANGE.0, VOLUME_RATIO_RANGE.1);
                        outcome.ratio_clamped += 1;
                    }
                    if !is_finite(particle) && outcome.first_bad.is_none() {
                        outcome.first_bad = Some(chunk * GATHER_CHUNK + offset);
                    }
                    outcome.max_speed = outcome.max_speed.max(speed(particle));
                    outcome.max_affine = outcome.max_affine.max(affine_norm(particle));
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
        self.max_speed = outcome.max_speed;
        self.max_affine = outcome.max_affine;
        Ok(())
    }

    /// Positions stay within `[dx/2, (n − 3/2)·dx)` of the origin: the widest range whose 3 × 3
    /// stencil (`base = ⌊x/dx − 1/2⌋ ∈ [0, n − 3]`) stays in the grid. A narrower range would move
    /// particles a healthy run leaves alone (Taichi's mpm88 lets them reach `126.03·dx` of 128).
    fn position_limits(&self) -> [[f64; 2]; 2] {
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
        self.max_speed = self.max_speed.max(speed(state));
    }
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
    max_speed: f64,
    max_affine: f64,
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
            max_speed: a.max_speed.max(b.max_speed),
            max_affine: a.max_affine.max(b.max_affine),
        }
    }
}

fn speed(state: &ParticleState) -> f64 {
    (state.velocity[0] * state.velocity[0] + state.velocity[1] * state.velocity[1]).sqrt()
}

fn affine_norm(state: &ParticleState) -> f64 {
    state
        .affine
        .iter()
        .map(|value| value * value)
        .sum::<f64>()
        .sqrt()
}

fn is_finite(state: &ParticleState) -> bool {
    state.position.iter().all(|value| value.is_finite())
        && state.velocity.iter().all(|value| value.is_finite())
        && state.affine.iter().all(|value| value.is_finite())
        && state.volume_ratio.is_finite()
}

fn clamp_position(position: &mut [f64; 2], limits: [[f64; 2]; 2]) -> bool {
    let mut clamped = false;
    for axis in 0..2 {
        let value = position[axis];
        if value < limits[0][axis] || value > limits[1][axis] {
            position[axis] = value.clamp(limits[0][axis], limits[1][axis]);
            clamped = true;
        }
    }
    clamped
}

/// The node at the low corner of a particle's 3 × 3 stencil.
#[inline]
fn base_node(position: [f64; 2], origin: [f64; 2], inverse: f64) -> [usize; 2] {
    let x = (position[0] - origin[0]) * inverse - 0.5;
    let y = (position[1] - origin[1]) * inverse - 0.5;
    [grid_index(x), grid_index(y)]
}

/// Index of the grid node nearest to `position` (clamped positions keep it in the grid).
#[inline]
fn nearest_node(position: [f64; 2], origin: [f64; 2], inverse: f64, columns: usize) -> usize {
    let i = grid_index(((position[0] - origin[0]) * inverse).round());
    let j = grid_index(((position[1] - origin[1]) * inverse).round());
    i * columns + j
}

/// A grid coordinate (in cells) as a node index: positions are clamped into the grid, so it is
/// ≥ 0 and small; `as` saturates anyway.
#[inline]
#[expect(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    reason = "clamped positions give small non-negative cell coordinates"
)]
fn grid_index(cells: f64) -> usize {
    cells.floor() as usize
}

/// A particle, block or material index as stored: particle ids are `u32` (`add_particle` refuses
/// the 2³²-th), and grids have at most 2³⁰ nodes.
#[inline]
#[expect(
    clippy::cast_possible_truncation,
    reason = "indices are bounded by the u32 particle ids and the grid size"
)]
fn index_u32(index: usize) -> u32 {
    index as u32
}

fn block_corner(block: u32, along: [usize; 2]) -> [usize; 2] {
    let block = block as usize;
    [(block / along[1]) * BLOCK, (block % along[1]) * BLOCK]
}

/// Quadratic B-spline weights along one axis for fractional offset `fx ∈ [0.5, 1.5)`.
#[inline]
fn weights(fx: f64) -> [f64; 3] {
    [
        0.5 * (1.5 - fx) * (1.5 - fx),
        0.75 - (fx - 1.0) * (fx - 1.0),
        0.5 * (fx - 0.5) * (fx - 0.5),
    ]
}

#[allow(clippy::too_many_arguments)]
#[inline]
fn scatter_particle(
    tile: &mut [[f64; 3]],
    corner: [usize; 2],
    particle: &ParticleState,
    constant: &ParticleConstants,
    material: &Material,
    origin: [f64; 2],
    dx: f64,
    inverse: f64,
    dt: f64,
) {
    let scaled = [
        (particle.position[0] - origin[0]) * inverse,
        (particle.position[1] - origin[1]) * inverse,
    ];
    let base = base_node(particle.position, origin, inverse);
    let fx = [scaled[0] - base[0] as f64, scaled[1] - base[1] as f64];
    let w = [weights(fx[0]), weights(fx[1])];
    let stress = material.kirchhoff_stress(particle.volume_ratio, &particle.affine);
    let scale = -dt * 4.0 * constant.volume * inverse * inverse;
    let mass = constant.mass;
    let affine = [
        scale * stress[0] + mass * particle.affine[0],
        scale * stress[1] + mass * particle.affine[1],
        scale * stress[2] + mass * particle.affine[2],
        scale * stress[3] + mass * particle.affine[3],
    ];
    let momentum = [mass * particle.velocity[0], mass * particle.velocity[1]];
    let local = [base[0] - corner[0], base[1] - corner[1]];
    for (i, wi) in w[0].iter().enumerate() {
        let dpos_x = (i as f64 - fx[0]) * dx;
        let row = (local[0] + i) * TILE + local[1];
        for (j, wj) in w[1].iter().enumerate() {
            let dpos_y = (j as f64 - fx[1]) * dx;
            let weight = wi * wj;
            let node = &mut tile[row + j];
            node[0] += weight * (momentum[0] + (affine[0] * dpos_x + affine[1] * dpos_y));
            node[1] += weight * (momentum[1] + (affine[2] * dpos_x + affine[3] * dpos_y));
            node[2] += weight * mass;
        }
    }
}

#[inline]
fn gather_particle(
    particle: &mut ParticleState,
    nodes: &[[f64; 3]],
    columns: usize,
    origin: [f64; 2],
    dx: f64,
    inverse: f64,
    dt: f64,
) {
    let scaled = [
        (particle.position[0] - origin[0]) * inverse,
        (particle.position[1] - origin[1]) * inverse,
    ];
    let base = base_node(particle.position, origin, inverse);
    let fx = [scaled[0] - base[0] as f64, scaled[1] - base[1] as f64];
    let w = [weights(fx[0]), weights(fx[1])];
    let mut velocity = [0.0; 2];
    let mut affine = [0.0; 4];
    for (i, wi) in w[0].iter().enumerate() {
        let dpos_x = (i as f64 - fx[0]) * dx;
        let row = (base[0] + i) * columns + base[1];
        for (j, wj) in w[1].iter().enumerate() {
            let dpos_y = (j as f64 - fx[1]) * dx;
            let weight = wi * wj;
            // Positions are clamped so the stencil is in the grid; a miss reads zero.
            let node = nodes.get(row + j).copied().unwrap_or([0.0; 3]);
            velocity[0] += weight * node[0];
            velocity[1] += weight * node[1];
            let scaled_weight = 4.0 * weight;
            affine[0] += scaled_weight * node[0] * dpos_x;
            affine[1] += scaled_weight * node[0] * dpos_y;
            affine[2] += scaled_weight * node[1] * dpos_x;
            affine[3] += scaled_weight * node[1] * dpos_y;
        }
    }
    let inverse_squared = inverse * inverse;
    for value in &mut affine {
        *value *= inverse_squared;
    }
    particle.velocity = velocity;
    particle.position[0] += dt * velocity[0];
    particle.position[1] += dt * velocity[1];
    particle.volume_ratio *= 1.0 + dt * (affine[0] + affine[3]);
    particle.affine = affine;
}
