//! Position-based fluids in 2D: the fluid scenario's truth solver, configured as the release
//! configured Obi Fluid in 2D mode (`FORMAT.md` §3.1, DESIGN.md §10). `--dynamics simulate`
//! predicts fluids with a different method (MLS-MPM), so that its accuracy measures prediction,
//! not reconstruction.
//!
//! Units are the scene's: lengths in units (the tank is 5 × 2.5), time in seconds, one update
//! 1/60 s; `y` points up and gravity is −4.8 units/s² as in the release.
//!
//! **Method** (Macklin & Müller 2013, "Position Based Fluids", with the multi-fluid number
//! density of Solenthaler & Pajarola 2008). Each update: emitters add particles; velocities take
//! gravity and positions are predicted; then [`FluidParameters::density_iterations`] times, each
//! particle's number density `δᵢ = Σⱼ W(xᵢ − xⱼ)` (poly6 kernel) is held at the rest number
//! density of a square lattice of the particle spacing by the constraint `Cᵢ = δᵢ/δ₀ − 1 ≤ 0`
//! (only compression is resisted, so free surfaces do not clump), each correction weighted by
//! the particle's inverse mass (mass ∝ rest density), colliders counting as filled with particles
//! at rest (`FluidWorld::wall_density`): where fluids of different density meet,
//! the lighter one gives way, and the denser one sinks. After each iteration every particle's
//! move is stopped at the colliders (continuous collision, [`Collider`]). Velocities follow from
//! the positions, then XSPH viscosity blends each particle's velocity with its neighbours' and,
//! near a collider, towards rest (a no-slip wall).
//! Every update checks that every position and velocity is finite.
//!
//! Surface tension is cohesion between neighbours, strongest at the free surface
//! ([`COHESION_ACCELERATION`]); the viscosity mapping from Obi's values is [`xsph_coefficient`].
//! Obi's buoyancy −1 means the fluid falls under the full gravity, which is what this solver does.
//! At rest a block of 20 × 16 particles in a tank holds its number density within 2.5% and its
//! surface within a spacing of its rest height (0.381 units against 0.3875); its particles
//! jitter (mean speed 0.045 units/s, 99% under 0.23), most at the free surface. A floating
//! square block rounds into a drop within two seconds.
//!
//! Input: [`FluidParameters`], fluids, colliders and emitters. Output: particle positions and
//! velocities after each update, and which fluid each particle belongs to.

mod collide;
mod grid;

pub use collide::{Collider, cross, segment_distance, segments_intersect};

use rand::Rng as _;
use rand_chacha::ChaCha8Rng;

use grid::Neighbours;

/// Gravity of the release's fluid solver, units/s² (downwards).
pub const GRAVITY: f64 = -4.8;
/// One update of the release (one captured frame advances 1/60 s), seconds.
pub const UPDATE_SECONDS: f64 = 1.0 / 60.0;

/// The pull one neighbour exerts on a particle at surface tension 1, units/s², at the cohesion
/// kernel's peak (half the kernel radius; Akinci's spline). Obi does not
/// publish its scale; at this value a surface particle is pulled inwards by about gravity's
/// size, which rounds a floating block into a drop within a second without shaking a fluid at
/// rest (the hydrostatic test holds with it).
pub const COHESION_ACCELERATION: f64 = 1.0;

/// The most one density iteration moves a particle, in spacings.
const MAX_CORRECTION_SPACINGS: f64 = 0.5;

/// Solver settings.
#[derive(Debug, Clone, PartialEq)]
pub struct FluidParameters {
    /// Particle spacing at rest, units (Obi resolution 40: 1/40).
    pub spacing: f64,
    /// Kernel radius over spacing.
    pub kernel_ratio: f64,
    /// Density iterations per update (the release: 12).
    pub density_iterations: usize,
    /// Update length, seconds.
    pub update_seconds: f64,
    /// Gravity, units/s² along `y`.
    pub gravity: f64,
}

impl Default for FluidParameters {
    fn default() -> Self {
        FluidParameters {
            spacing: 1.0 / 40.0,
            kernel_ratio: 2.5,
            density_iterations: 12,
            update_seconds: UPDATE_SECONDS,
            gravity: GRAVITY,
        }
    }
}

/// One fluid's material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FluidMaterial {
    /// Rest density (the release's pools: {1600, 3000, 4400} and {1200, 2600, 4000, 5400}).
    pub rest_density: f64,
    /// Obi viscosity: 0.02 (Non-Sticky) or 10 (Sticky).
    pub viscosity: f64,
    /// Obi surface tension (the release: 1 for every fluid); see [`COHESION_ACCELERATION`].
    pub surface_tension: f64,
}

/// An edge emitter: rows of particles across a `width`-wide edge, leaving along `direction`.
#[derive(Debug, Clone, PartialEq)]
pub struct Emitter {
    /// Index of the fluid it emits.
    pub fluid: usize,
    /// Centre of the edge, units.
    pub centre: [f64; 2],
    /// Direction of emission (normalised on use).
    pub direction: [f64; 2],
    /// Edge width, units (the release: 0.5).
    pub width: f64,
    /// Emission speed, units/s (the release: 0.7).
    pub speed: f64,
    /// Largest random velocity added to each particle, units/s (the release: 0.4).
    pub random_velocity: f64,
    /// Particles it emits in all (the release: 1,500).
    pub capacity: usize,
    /// The first update it emits at (the release: 2, or 460 for a later emitter).
    pub opens_at: usize,
}

/// Why the solver stopped.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum FluidError {
    /// A position or velocity became NaN or infinite.
    #[error("fluid particle {particle} is not finite after update {update}")]
    NonFinite {
        /// The update that produced it.
        update: usize,
        /// The particle.
        particle: usize,
    },
    /// A setting is out of its range.
    #[error("fluid solver setting `{name}` is {value}: {expected}")]
    Setting {
        /// The setting.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
}

/// A fluid scene being simulated.
#[derive(Debug, Clone)]
pub struct FluidWorld {
    parameters: FluidParameters,
    fluids: Vec<FluidMaterial>,
    colliders: Vec<Collider>,
    emitters: Vec<Emitter>,
    /// Per emitter: particles emitted so far and the distance travelled since its last row.
    emitted: Vec<(usize, f64)>,
    positions: Vec<[f64; 2]>,
    velocities: Vec<[f64; 2]>,
    fluid_of: Vec<usize>,
    rest_number_density: f64,
    update: usize,
    rng: ChaCha8Rng,
}

/// The XSPH blend of a particle's velocity towards its neighbours' per update for an Obi
/// viscosity value: `v / (1 + v)`, so Non-Sticky (0.02) blends 2% and Sticky (10) 91%. Obi does
/// not publish its scale; this mapping keeps both in `[0, 1)` and their order and contrast.
pub fn xsph_coefficient(viscosity: f64) -> f64 {
    let v = viscosity.max(0.0);
    v / (1.0 + v)
}

impl FluidWorld {
    /// An empty scene; `seed` drives the emitters' random velocities.
    ///
    /// # Errors
    /// A setting out of range.
    pub fn new(
        parameters: FluidParameters,
        fluids: Vec<FluidMaterial>,
        colliders: Vec<Collider>,
        emitters: Vec<Emitter>,
        seed: u64,
    ) -> Result<FluidWorld, FluidError> {
        let positive = |name, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(FluidError::Setting {
                    name,
                    value,
                    expected: "must be positive and finite",
                })
            }
        };
        positive("spacing", parameters.spacing)?;
        positive("kernel_ratio", parameters.kernel_ratio)?;
        positive("update_seconds", parameters.update_seconds)?;
        for fluid in &fluids {
            positive("rest_density", fluid.rest_density)?;
        }
        let rest_number_density = lattice_number_density(&parameters);
        let emitted = vec![(0, 0.0); emitters.len()];
        Ok(FluidWorld {
            parameters,
            fluids,
            colliders,
            emitters,
            emitted,
            positions: Vec::new(),
            velocities: Vec::new(),
            fluid_of: Vec::new(),
            rest_number_density,
            update: 0,
            rng: crate::util::seeded_rng(seed),
        })
    }

    /// Adds a particle of `fluid` at `position` (units) moving at `velocity` (units/s).
    pub fn add_particle(&mut self, fluid: usize, position: [f64; 2], velocity: [f64; 2]) {
        self.positions.push(position);
        self.velocities.push(velocity);
        self.fluid_of.push(fluid);
    }

    /// Particle positions, units.
    pub fn positions(&self) -> &[[f64; 2]] {
        &self.positions
    }

    /// Particle velocities, units/s.
    pub fn velocities(&self) -> &[[f64; 2]] {
        &self.velocities
    }

    /// The fluid of each particle.
    pub fn fluid_of(&self) -> &[usize] {
        &self.fluid_of
    }

    /// Updates done so far.
    pub fn update_count(&self) -> usize {
        self.update
    }

    /// The rest number density the density constraint holds (particles per unit area, kernel
    /// weighted).
    pub fn rest_number_density(&self) -> f64 {
        self.rest_number_density
    }

    /// Each particle's number density over the rest one (1 at rest, above 1 when compressed).
    pub fn density_ratios(&self) -> Vec<f64> {
        let h = self.kernel_radius();
        let neighbours = Neighbours::find(&self.positions, h);
        (0..self.positions.len())
            .map(|i| {
                let (wall, _) = self.wall_density(self.positions[i]);
                (number_density(&self.positions, &neighbours, i, h) + wall)
                    / self.rest_number_density
            })
            .collect()
    }

    fn kernel_radius(&self) -> f64 {
        self.parameters.spacing * self.parameters.kernel_ratio
    }

    /// Advances one update.
    ///
    /// # Errors
    /// A particle's position or velocity is not finite afterwards.
    pub fn step(&mut self) -> Result<(), FluidError> {
        self.emit();
        let dt = self.parameters.update_seconds;
        let start = self.positions.clone();
        let mut predicted: Vec<[f64; 2]> = start
            .iter()
            .zip(self.velocities.iter_mut())
            .map(|(x, v)| {
                v[1] += self.parameters.gravity * dt;
                [x[0] + v[0] * dt, x[1] + v[1] * dt]
            })
            .collect();
        // Friction and stickiness act once per update, on the predicted move; the density
        // iterations' corrections are only kept out of the colliders.
        self.collide(&start, &mut predicted, true);
        let h = self.kernel_radius();
        // Relative to 1000, which cancels in each constraint's λ.
        let inverse_mass: Vec<f64> = self
            .fluid_of
            .iter()
            .map(|&f| {
                self.fluids
                    .get(f)
                    .map_or(1.0, |fluid| 1000.0 / fluid.rest_density)
            })
            .collect();
        for _ in 0..self.parameters.density_iterations {
            let neighbours = Neighbours::find(&predicted, h);
            let corrections = self.density_corrections(&predicted, &neighbours, &inverse_mass);
            let before = predicted.clone();
            let largest = MAX_CORRECTION_SPACINGS * self.parameters.spacing;
            for (p, c) in predicted.iter_mut().zip(&corrections) {
                // Two particles almost on top of each other (a fast emitter row landing on
                // the last one) would be thrown apart by the kernel's steep gradient: no
                // iteration moves a particle more than half a spacing.
                let length = norm(c[0], c[1]);
                let shrink = if length > largest {
                    largest / length
                } else {
                    1.0
                };
                p[0] += c[0] * shrink;
                p[1] += c[1] * shrink;
            }
            // Corrections move particles too: stop them at the colliders, from where they were.
            self.collide(&before, &mut predicted, false);
        }
        for ((v, p), x) in self.velocities.iter_mut().zip(&predicted).zip(&start) {
            *v = [(p[0] - x[0]) / dt, (p[1] - x[1]) / dt];
        }
        let neighbours = Neighbours::find(&predicted, h);
        self.viscosity(&predicted, &neighbours, h);
        self.surface_tension(&predicted, &neighbours, h);
        self.positions = predicted;
        self.update += 1;
        self.check_finite()
    }

    fn collide(&self, from: &[[f64; 2]], predicted: &mut [[f64; 2]], with_friction: bool) {
        let radius = 0.5 * self.parameters.spacing;
        let smooth: Vec<Collider>;
        let colliders = if with_friction {
            &self.colliders
        } else {
            smooth = self
                .colliders
                .iter()
                .map(|collider| Collider {
                    friction: 0.0,
                    stickiness: 0.0,
                    ..*collider
                })
                .collect();
            &smooth
        };
        for (start, p) in from.iter().zip(predicted.iter_mut()) {
            for collider in colliders {
                collider.resolve(*start, p, radius);
            }
        }
    }

    /// One density iteration's position corrections (Macklin & Müller's λ, weighted by each
    /// particle's inverse mass).
    fn density_corrections(
        &self,
        predicted: &[[f64; 2]],
        neighbours: &Neighbours,
        inverse_mass: &[f64],
    ) -> Vec<[f64; 2]> {
        let h = self.kernel_radius();
        let count = predicted.len();
        let scale = 1.0 / self.rest_number_density;
        // A small compliance keeps λ finite for a particle with few neighbours.
        let peak = scale * spiky_gradient_peak(h);
        let compliance = 1e-6 * peak * peak;
        let walls: Vec<(f64, [f64; 2])> = predicted.iter().map(|&p| self.wall_density(p)).collect();
        let mut lambda = vec![0.0; count];
        for i in 0..count {
            let (wall, wall_gradient) = walls[i];
            let constraint = (number_density(predicted, neighbours, i, h) + wall) * scale - 1.0;
            if constraint <= 0.0 {
                continue;
            }
            let mut own = [wall_gradient[0] * scale, wall_gradient[1] * scale];
            let mut sum = 0.0;
            for &j in neighbours.of(i) {
                let g = spiky_gradient(predicted[i], predicted[j], h);
                let g = [g[0] * scale, g[1] * scale];
                own[0] += g[0];
                own[1] += g[1];
                sum += inverse_mass[j] * (g[0] * g[0] + g[1] * g[1]);
            }
            sum += inverse_mass[i] * (own[0] * own[0] + own[1] * own[1]);
            lambda[i] = -constraint / (sum + compliance);
        }
        (0..count)
            .map(|i| {
                // The colliders take no correction (they do not move): the particle takes its
                // constraint's whole push away from them.
                let wall_gradient = walls[i].1;
                let mut delta = [
                    lambda[i] * scale * wall_gradient[0],
                    lambda[i] * scale * wall_gradient[1],
                ];
                for &j in neighbours.of(i) {
                    let g = spiky_gradient(predicted[i], predicted[j], h);
                    let weight = (lambda[i] + lambda[j]) * scale;
                    delta[0] += weight * g[0];
                    delta[1] += weight * g[1];
                }
                [delta[0] * inverse_mass[i], delta[1] * inverse_mass[i]]
            })
            .collect()
    }

    /// The number density the colliders add at `point` and its gradient: each collider's inside
    /// counts as filled with particles on the rest lattice, rows from half a spacing behind its
    /// surface, so that a particle resting against a wall counts as many neighbours as one inside
    /// the fluid (without this, particles at walls pack tighter and the fluid loses volume).
    fn wall_density(&self, point: [f64; 2]) -> (f64, [f64; 2]) {
        let h = self.kernel_radius();
        let mut density = 0.0;
        let mut gradient = [0.0, 0.0];
        for collider in &self.colliders {
            if !collider.near(point, h) {
                continue;
            }
            let (gap, normal) = collider.surface_gap(point);
            if gap >= h {
                continue;
            }
            let (amount, slope) = half_plane_density(gap.max(0.0), self.parameters.spacing, h);
            density += amount;
            gradient[0] += slope * normal[0];
            gradient[1] += slope * normal[1];
        }
        (density, gradient)
    }

    fn viscosity(&mut self, positions: &[[f64; 2]], neighbours: &Neighbours, h: f64) {
        let scale = 1.0 / self.rest_number_density;
        let old = self.velocities.clone();
        for (i, v) in self.velocities.iter_mut().enumerate() {
            let coefficient = self
                .fluids
                .get(self.fluid_of[i])
                .map_or(0.0, |f| xsph_coefficient(f.viscosity));
            let mut blend = [0.0, 0.0];
            for &j in neighbours.of(i) {
                let w = poly6(positions[i], positions[j], h) * scale;
                blend[0] += (old[j][0] - old[i][0]) * w;
                blend[1] += (old[j][1] - old[i][1]) * w;
            }
            // A collider counts as a neighbour at rest: a particle within the kernel radius of
            // its surface blends towards standing still by `(1 − d/h)²` of the coefficient, the
            // no-slip wall of viscous fluids, so a sticky fluid clings to a stick where a
            // runny one slides off.
            let wall = self
                .colliders
                .iter()
                .filter(|collider| collider.near(positions[i], h + 0.5 * self.parameters.spacing))
                .map(|collider| {
                    let gap = collider.surface_gap(positions[i]).0 - 0.5 * self.parameters.spacing;
                    if gap < h {
                        let near = 1.0 - gap.max(0.0) / h;
                        near * near
                    } else {
                        0.0
                    }
                })
                .fold(0.0, f64::max);
            blend[0] -= old[i][0] * wall;
            blend[1] -= old[i][1] * wall;
            v[0] += coefficient * blend[0];
            v[1] += coefficient * blend[1];
        }
    }

    /// Surface tension as cohesion (Akinci, Akinci & Teschner 2013, "Versatile surface tension
    /// and adhesion for SPH fluids"): neighbours pull each other together along the cohesion
    /// kernel, the pull scaled by `2δ₀/(δᵢ + δⱼ)` so that it acts mostly where the number density
    /// is low, at the free surface; inside the fluid the pulls cancel. A pair pulls with the mean
    /// of its two fluids' tensions. Applied to the velocities, like viscosity, and taking effect
    /// in the next update's prediction.
    fn surface_tension(&mut self, positions: &[[f64; 2]], neighbours: &Neighbours, h: f64) {
        let tension: Vec<f64> = self
            .fluid_of
            .iter()
            .map(|&f| {
                self.fluids
                    .get(f)
                    .map_or(0.0, |fluid| fluid.surface_tension)
            })
            .collect();
        if tension.iter().all(|&t| t == 0.0) {
            return;
        }
        let densities: Vec<f64> = (0..positions.len())
            .map(|i| {
                (number_density(positions, neighbours, i, h) + self.wall_density(positions[i]).0)
                    .max(f64::MIN_POSITIVE)
            })
            .collect();
        let dt = self.parameters.update_seconds;
        let rest = self.rest_number_density;
        for (i, v) in self.velocities.iter_mut().enumerate() {
            let mut pull = [0.0, 0.0];
            for &j in neighbours.of(i) {
                let offset = [
                    positions[j][0] - positions[i][0],
                    positions[j][1] - positions[i][1],
                ];
                let distance = norm(offset[0], offset[1]);
                if distance <= 1e-12 {
                    continue;
                }
                let strength =
                    0.5 * (tension[i] + tension[j]) * cohesion_shape(distance, h) * 2.0 * rest
                        / (densities[i] + densities[j]);
                pull[0] += strength * offset[0] / distance;
                pull[1] += strength * offset[1] / distance;
            }
            v[0] += COHESION_ACCELERATION * pull[0] * dt;
            v[1] += COHESION_ACCELERATION * pull[1] * dt;
        }
    }

    fn emit(&mut self) {
        let spacing = self.parameters.spacing;
        let dt = self.parameters.update_seconds;
        for (k, emitter) in self.emitters.iter().enumerate() {
            let (count, travelled) = &mut self.emitted[k];
            if self.update < emitter.opens_at || *count >= emitter.capacity {
                continue;
            }
            let length = norm(emitter.direction[0], emitter.direction[1]);
            if !(length.is_finite() && length > 0.0) {
                continue;
            }
            let direction = [emitter.direction[0] / length, emitter.direction[1] / length];
            let across = [-direction[1], direction[0]];
            *travelled += emitter.speed * dt;
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a positive width over a positive spacing, rounded, is a small count"
            )]
            let per_row = ((emitter.width / spacing).round().max(1.0)) as usize;
            while *travelled >= spacing && *count < emitter.capacity {
                *travelled -= spacing;
                for slot in 0..per_row {
                    if *count >= emitter.capacity {
                        break;
                    }
                    let offset = (slot as f64 + 0.5 - per_row as f64 / 2.0) * spacing;
                    let ahead = *travelled;
                    let position = [
                        emitter.centre[0] + across[0] * offset + direction[0] * ahead,
                        emitter.centre[1] + across[1] * offset + direction[1] * ahead,
                    ];
                    // A random velocity of up to `random_velocity` in a random direction.
                    let angle = self.rng.random::<f64>() * std::f64::consts::TAU;
                    let size = self.rng.random::<f64>() * emitter.random_velocity;
                    let velocity = [
                        direction[0] * emitter.speed + size * angle.cos(),
                        direction[1] * emitter.speed + size * angle.sin(),
                    ];
                    self.positions.push(position);
                    self.velocities.push(velocity);
                    self.fluid_of.push(emitter.fluid);
                    *count += 1;
                }
            }
        }
    }

    fn check_finite(&self) -> Result<(), FluidError> {
        let bad = self
            .positions
            .iter()
            .zip(&self.velocities)
            .position(|(p, v)| !p.iter().chain(v).all(|value| value.is_finite()));
        match bad {
            Some(particle) => Err(FluidError::NonFinite {
                update: self.update,
                particle,
            }),
            None => Ok(()),
        }
    }
}

/// The length of `(x, y)`: a square root, which is correctly rounded (the same bits in every
/// build) and several times faster than `hypot`, whose overflow care these small lengths do not
/// need.
pub(crate) fn norm(x: f64, y: f64) -> f64 {
    (x * x + y * y).sqrt()
}

/// The 2D poly6 kernel of radius `radius`, normalised to integrate to 1 over the plane, between
/// points `first` and `second`.
fn poly6(first: [f64; 2], second: [f64; 2], radius: f64) -> f64 {
    // Products, not `powi`: the same bytes in debug and release builds.
    let offset = [first[0] - second[0], first[1] - second[1]];
    let squared = offset[0] * offset[0] + offset[1] * offset[1];
    let radius_squared = radius * radius;
    if squared >= radius_squared {
        0.0
    } else {
        let gap = radius_squared - squared;
        let r4 = radius_squared * radius_squared;
        4.0 / (std::f64::consts::PI * r4 * r4) * gap * gap * gap
    }
}

/// Akinci's cohesion spline at distance `distance` for kernel radius `radius`, scaled to peak at
/// 1: attracting at most distances, repelling closer than about a sixth of the radius, so that
/// cohesion never collapses particles onto each other.
fn cohesion_shape(distance: f64, radius: f64) -> f64 {
    if distance >= radius || distance <= 0.0 {
        return 0.0;
    }
    let gap = radius - distance;
    let cubic = gap * gap * gap * distance * distance * distance;
    let r6 = radius * radius * radius * radius * radius * radius;
    let value = if 2.0 * distance > radius {
        cubic
    } else {
        2.0 * cubic - r6 / 64.0
    };
    // The spline peaks at `distance = radius/2`, where it is `radius⁶/64`.
    value * 64.0 / r6
}

/// The largest magnitude of the 2D spiky kernel's gradient (at distance → 0) for kernel radius
/// `radius`.
fn spiky_gradient_peak(radius: f64) -> f64 {
    30.0 / (std::f64::consts::PI * radius * radius * radius)
}

/// The gradient with respect to `first` of the 2D spiky kernel `10/(π h⁵) (h − r)³` (`h` the
/// kernel radius `radius`, `r` the distance to `second`).
fn spiky_gradient(first: [f64; 2], second: [f64; 2], radius: f64) -> [f64; 2] {
    let offset = [first[0] - second[0], first[1] - second[1]];
    if offset[0] * offset[0] + offset[1] * offset[1] >= radius * radius {
        return [0.0, 0.0];
    }
    let distance = norm(offset[0], offset[1]);
    if distance >= radius || distance <= 1e-12 {
        return [0.0, 0.0];
    }
    let gap = radius - distance;
    let r5 = radius * radius * radius * radius * radius;
    let magnitude = -30.0 / (std::f64::consts::PI * r5) * gap * gap;
    [
        magnitude * offset[0] / distance,
        magnitude * offset[1] / distance,
    ]
}

/// The number density at `gap` (units) in front of a half plane filled with particles on the
/// square lattice of `spacing`, rows from half a spacing behind its surface, for kernel radius
/// `radius`; and its derivative along the surface's outward normal (spiky gradient, negative:
/// the density falls away from the surface).
fn half_plane_density(gap: f64, spacing: f64, radius: f64) -> (f64, f64) {
    #[expect(
        clippy::cast_possible_truncation,
        reason = "the kernel radius over the spacing is a small positive number"
    )]
    let columns = (radius / spacing).ceil() as i64;
    let mut density = 0.0;
    let mut slope = 0.0;
    for row in 0_i32.. {
        let depth = gap + (f64::from(row) + 0.5) * spacing;
        if depth >= radius {
            break;
        }
        for column in -columns..=columns {
            #[expect(clippy::cast_precision_loss, reason = "small lattice offsets")]
            let virtual_particle = [column as f64 * spacing, -depth];
            density += poly6([0.0, 0.0], virtual_particle, radius);
            slope += spiky_gradient([0.0, 0.0], virtual_particle, radius)[1];
        }
    }
    (density, slope)
}

/// Particle `i`'s kernel-weighted number density, itself included.
fn number_density(positions: &[[f64; 2]], neighbours: &Neighbours, i: usize, h: f64) -> f64 {
    let own = poly6(positions[i], positions[i], h);
    neighbours
        .of(i)
        .iter()
        .fold(own, |sum, &j| sum + poly6(positions[i], positions[j], h))
}

/// The number density of a particle inside an endless square lattice of the spacing: the rest
/// state the density constraint holds.
fn lattice_number_density(parameters: &FluidParameters) -> f64 {
    let h = parameters.spacing * parameters.kernel_ratio;
    #[expect(
        clippy::cast_possible_truncation,
        reason = "the kernel ratio is a small positive number"
    )]
    let reach = parameters.kernel_ratio.ceil() as i64 + 1;
    let mut sum = 0.0;
    for y in -reach..=reach {
        for x in -reach..=reach {
            #[expect(clippy::cast_precision_loss, reason = "small lattice offsets")]
            let point = [x as f64 * parameters.spacing, y as f64 * parameters.spacing];
            sum += poly6([0.0, 0.0], point, h);
        }
    }
    sum
}

#[cfg(test)]
mod tests;
