//! Particle soft bodies held together by shape matching: the ball scenario's truth solver,
//! configured as the release configured Obi Softbody (`FORMAT.md` §5.1, DESIGN.md §10). The
//! release ran in 3D mode with gravity −9.8, 4 substeps per update and 3 shape-matching
//! iterations, balls of about 91 particles, and the deformation resistances, plastic yield, creep
//! and maximum deformation of [`ELASTIC`], [`RIGID`] and [`PLASTIC`]. `--dynamics simulate`
//! predicts balls with a different method (elastoplastic MPM), so that its accuracy measures
//! prediction, not reconstruction.
//!
//! Units are the scene's: lengths in units, time in seconds, one update 1/60 s; `y` points up.
//!
//! **Method** (position-based dynamics, Müller et al. 2007; shape matching, Müller et al. 2005;
//! contact friction after Macklin et al. 2014). Each substep of `h` seconds: velocities take
//! gravity and positions are predicted; then [`SoftBodyParameters::iterations`] times, each body
//! is projected onto its shape ([`Body`]), every particle is pushed out of the slabs it
//! penetrates (a particle is a sphere of [`SoftBodyParameters::particle_radius`]), and particles
//! of different bodies closer than two radii are pushed apart (mass weighted, so momentum is
//! kept). Particles pushed by a slab then lose their tangential motion of the substep up to
//! static friction, or by the dynamic friction times the push. Velocities follow from the
//! positions; plastic bodies let their rest shape creep. Every substep checks that every position
//! and velocity is finite.
//!
//! No tunnelling: a particle moves at most [`SoftBodyParameters::max_speed`] × `h` in a substep,
//! less than a particle radius plus half the thinnest slab, so a particle that enters a slab is
//! always pushed back out of the face it came through ([`SoftBodyWorld::new`] checks the
//! settings against each other).
//!
//! Input: [`SoftBodyParameters`], slabs and bodies. Output: particle positions and velocities
//! after each update, each body's centre and deformation.

mod body;
mod collider;

pub use body::{
    Body, ELASTIC, PLASTIC, Plasticity, RIGID, SPHERE_PARTICLES, SoftMaterial, sphere_offsets,
};
pub use collider::{Contact, Slab};

use crate::physics::vector3::{self as matrix, Vector};

/// Gravity of the release's softbody solver, units/s² (downwards).
pub const GRAVITY: f64 = -9.8;
/// One update of the release, seconds.
pub const UPDATE_SECONDS: f64 = 1.0 / 60.0;

/// Solver settings.
#[derive(Debug, Clone, PartialEq)]
pub struct SoftBodyParameters {
    /// Update length, seconds.
    pub update_seconds: f64,
    /// Substeps per update (the release: 4).
    pub substeps: usize,
    /// Constraint iterations per substep (the release: 3).
    pub iterations: usize,
    /// Gravity, units/s² along `y`.
    pub gravity: f64,
    /// Contact radius of a particle, units.
    pub particle_radius: f64,
    /// Coulomb friction against slabs below which a touching particle does not slide.
    pub static_friction: f64,
    /// Coulomb friction against slabs while sliding.
    pub dynamic_friction: f64,
    /// Particle speeds are capped here, units/s: a bound the scene never reaches in free fall
    /// (a 7-unit drop reaches 12 units/s), kept so that no substep can carry a particle through
    /// a slab.
    pub max_speed: f64,
}

impl Default for SoftBodyParameters {
    fn default() -> Self {
        SoftBodyParameters {
            update_seconds: UPDATE_SECONDS,
            substeps: 4,
            iterations: 3,
            gravity: GRAVITY,
            particle_radius: 0.12,
            static_friction: 0.3,
            dynamic_friction: 0.3,
            max_speed: 30.0,
        }
    }
}

/// Why the solver stopped.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SoftBodyError {
    /// A position or velocity became NaN or infinite.
    #[error("soft body {body} particle {particle} is not finite after update {update}")]
    NonFinite {
        /// The update that produced it.
        update: usize,
        /// The body.
        body: usize,
        /// The particle.
        particle: usize,
    },
    /// A setting is out of its range.
    #[error("soft body solver setting `{name}` is {value}: {expected}")]
    Setting {
        /// The setting.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
    /// A body's particles span no volume.
    #[error("soft body {body} has particles that span no volume")]
    Flat {
        /// The body.
        body: usize,
    },
}

/// A scene of soft bodies and static slabs being simulated.
#[derive(Debug, Clone)]
pub struct SoftBodyWorld {
    parameters: SoftBodyParameters,
    slabs: Vec<Slab>,
    bodies: Vec<Body>,
    /// Per body and particle: the slab push of this substep (summed depth) and its last normal.
    pushes: Vec<Vec<(f64, [f64; 2])>>,
    update: usize,
}

impl SoftBodyWorld {
    /// An empty scene with `slabs`.
    ///
    /// # Errors
    /// A setting out of range, or a speed cap that would let a particle cross the thinnest slab
    /// in one substep.
    pub fn new(parameters: SoftBodyParameters, slabs: Vec<Slab>) -> Result<Self, SoftBodyError> {
        let positive = |name, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(SoftBodyError::Setting {
                    name,
                    value,
                    expected: "must be positive and finite",
                })
            }
        };
        positive("update_seconds", parameters.update_seconds)?;
        positive("particle_radius", parameters.particle_radius)?;
        positive("max_speed", parameters.max_speed)?;
        positive("substeps", parameters.substeps as f64)?;
        positive("iterations", parameters.iterations as f64)?;
        if !parameters.gravity.is_finite() {
            return Err(SoftBodyError::Setting {
                name: "gravity",
                value: parameters.gravity,
                expected: "must be finite",
            });
        }
        for (name, value) in [
            ("static_friction", parameters.static_friction),
            ("dynamic_friction", parameters.dynamic_friction),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(SoftBodyError::Setting {
                    name,
                    value,
                    expected: "must be finite and not negative",
                });
            }
        }
        for slab in &slabs {
            positive("slab thickness", slab.thickness)?;
        }
        let thinnest = slabs
            .iter()
            .map(|slab| slab.thickness)
            .fold(f64::INFINITY, f64::min);
        let travel = parameters.max_speed * parameters.update_seconds / parameters.substeps as f64;
        if travel >= parameters.particle_radius + 0.5 * thinnest {
            return Err(SoftBodyError::Setting {
                name: "max_speed",
                value: parameters.max_speed,
                expected: "must keep a substep's travel below a particle radius plus half the thinnest slab",
            });
        }
        Ok(SoftBodyWorld {
            parameters,
            slabs,
            bodies: Vec::new(),
            pushes: Vec::new(),
            update: 0,
        })
    }

    /// Adds a ball of `radius` units (its surface: the outer particles' spheres reach it) and
    /// `mass` kg centred at `centre`, at rest; returns its index.
    ///
    /// # Errors
    /// A radius not above two particle radii, or a mass not positive.
    pub fn add_sphere(
        &mut self,
        centre: Vector,
        radius: f64,
        mass: f64,
        material: SoftMaterial,
    ) -> Result<usize, SoftBodyError> {
        let particle_radius = self.parameters.particle_radius;
        if !(radius.is_finite() && radius > 2.0 * particle_radius) {
            return Err(SoftBodyError::Setting {
                name: "sphere radius",
                value: radius,
                expected: "must exceed two particle radii",
            });
        }
        if !(mass.is_finite() && mass > 0.0) {
            return Err(SoftBodyError::Setting {
                name: "sphere mass",
                value: mass,
                expected: "must be positive and finite",
            });
        }
        let offsets = sphere_offsets(radius - particle_radius);
        let particle_mass = mass / offsets.len() as f64;
        let body =
            Body::new(centre, &offsets, particle_mass, material).ok_or(SoftBodyError::Flat {
                body: self.bodies.len(),
            })?;
        self.pushes.push(vec![(0.0, [0.0, 0.0]); offsets.len()]);
        self.bodies.push(body);
        Ok(self.bodies.len() - 1)
    }

    /// The bodies, in the order added.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// Body `index`, mutably (to set its velocity or take it out of the run).
    pub fn body_mut(&mut self, index: usize) -> Option<&mut Body> {
        self.bodies.get_mut(index)
    }

    /// Takes body `index` out of the simulation (a counterfactual run removes balls) or puts it
    /// back.
    pub fn set_active(&mut self, index: usize, active: bool) {
        if let Some(body) = self.bodies.get_mut(index) {
            body.active = active;
        }
    }

    /// The slabs.
    pub fn slabs(&self) -> &[Slab] {
        &self.slabs
    }

    /// Updates done so far.
    pub fn update_count(&self) -> usize {
        self.update
    }

    /// The settings.
    pub fn parameters(&self) -> &SoftBodyParameters {
        &self.parameters
    }

    /// Advances one update.
    ///
    /// # Errors
    /// A particle's position or velocity is not finite.
    pub fn step(&mut self) -> Result<(), SoftBodyError> {
        let h = self.parameters.update_seconds / self.parameters.substeps as f64;
        for _ in 0..self.parameters.substeps {
            self.predict(h);
            for pushes in &mut self.pushes {
                pushes.fill((0.0, [0.0, 0.0]));
            }
            let iterations = self.parameters.iterations;
            for _ in 0..iterations {
                for body in self.bodies.iter_mut().filter(|body| body.active) {
                    let kept = 1.0 - body.material.deformation_resistance.clamp(0.0, 1.0);
                    body.project_shape(1.0 - kept.powf(1.0 / iterations as f64));
                }
                self.collide_slabs();
                self.collide_bodies();
            }
            self.apply_friction();
            self.finish_substep(h)?;
        }
        self.update += 1;
        Ok(())
    }

    /// Gravity, then the predicted positions (speeds capped at `max_speed`).
    fn predict(&mut self, h: f64) {
        let gravity = self.parameters.gravity;
        let max_speed = self.parameters.max_speed;
        for body in self.bodies.iter_mut().filter(|body| body.active) {
            for ((position, previous), velocity) in body
                .positions
                .iter_mut()
                .zip(&mut body.previous)
                .zip(&mut body.velocities)
            {
                velocity[1] += gravity * h;
                let speed = matrix::norm(*velocity);
                if speed > max_speed {
                    *velocity = matrix::scale(*velocity, max_speed / speed);
                }
                *previous = *position;
                *position = matrix::add(*position, matrix::scale(*velocity, h));
            }
        }
    }

    /// Pushes every particle out of the slabs it is closer to than its radius. A rigid body
    /// (deformation resistance 1) is moved whole, by its deepest particle's push per slab: a
    /// push on one particle would reach the rest only through the rigid projection, 1/91 of it
    /// an iteration, and the penetration left over would be undone in later substeps as an
    /// upward speed (a rigid ball dropped 2.5 units bounced back 0.64 that way).
    fn collide_slabs(&mut self) {
        let radius = self.parameters.particle_radius;
        for (body, pushes) in self.bodies.iter_mut().zip(&mut self.pushes) {
            if !body.active {
                continue;
            }
            if body.material.deformation_resistance >= 1.0 {
                for slab in &self.slabs {
                    let mut deepest: Option<(f64, [f64; 2])> = None;
                    for (position, push) in body.positions.iter().zip(pushes.iter_mut()) {
                        let contact = slab.contact(*position);
                        if contact.distance < radius {
                            let depth = radius - contact.distance;
                            *push = (push.0 + depth, contact.normal);
                            if deepest.is_none_or(|(most, _)| depth > most) {
                                deepest = Some((depth, contact.normal));
                            }
                        }
                    }
                    if let Some((depth, normal)) = deepest {
                        for position in &mut body.positions {
                            position[0] += depth * normal[0];
                            position[1] += depth * normal[1];
                        }
                    }
                }
                continue;
            }
            for (position, push) in body.positions.iter_mut().zip(pushes.iter_mut()) {
                for slab in &self.slabs {
                    let contact = slab.contact(*position);
                    if contact.distance < radius {
                        let depth = radius - contact.distance;
                        position[0] += depth * contact.normal[0];
                        position[1] += depth * contact.normal[1];
                        *push = (push.0 + depth, contact.normal);
                    }
                }
            }
        }
    }

    /// Pushes apart particles of different bodies closer than two radii, mass weighted.
    fn collide_bodies(&mut self) {
        let reach = 2.0 * self.parameters.particle_radius;
        for second in 1..self.bodies.len() {
            let (before, after) = self.bodies.split_at_mut(second);
            let Some(b) = after.first_mut() else {
                continue;
            };
            if !b.active {
                continue;
            }
            let (centre_b, extent_b) = bounds(b);
            for a in before.iter_mut().filter(|body| body.active) {
                let (centre_a, extent_a) = bounds(a);
                if matrix::norm(matrix::sub(centre_a, centre_b)) > extent_a + extent_b + reach {
                    continue;
                }
                let (inverse_a, inverse_b) = (1.0 / a.particle_mass, 1.0 / b.particle_mass);
                let share_a = inverse_a / (inverse_a + inverse_b);
                for position_a in &mut a.positions {
                    for position_b in &mut b.positions {
                        let between = matrix::sub(*position_b, *position_a);
                        let distance = matrix::norm(between);
                        if distance >= reach || distance <= 0.0 {
                            continue;
                        }
                        let correction = matrix::scale(between, (reach - distance) / distance);
                        *position_a = matrix::sub(*position_a, matrix::scale(correction, share_a));
                        *position_b =
                            matrix::add(*position_b, matrix::scale(correction, 1.0 - share_a));
                    }
                }
            }
        }
    }

    /// Coulomb friction for the particles a slab pushed this substep.
    fn apply_friction(&mut self) {
        let (static_friction, dynamic_friction) = (
            self.parameters.static_friction,
            self.parameters.dynamic_friction,
        );
        for (body, pushes) in self.bodies.iter_mut().zip(&self.pushes) {
            if !body.active {
                continue;
            }
            let rigid = body.material.deformation_resistance >= 1.0;
            let mut corrections = Vec::new();
            for (index, ((position, previous), (depth, normal))) in body
                .positions
                .iter_mut()
                .zip(&body.previous)
                .zip(pushes)
                .enumerate()
            {
                if *depth <= 0.0 {
                    continue;
                }
                let moved = matrix::sub(*position, *previous);
                let normal = [normal[0], normal[1], 0.0];
                let tangential =
                    matrix::sub(moved, matrix::scale(normal, matrix::dot(moved, normal)));
                let slide = matrix::norm(tangential);
                if slide <= 0.0 {
                    continue;
                }
                let kept = if slide < static_friction * depth {
                    0.0
                } else {
                    1.0 - (dynamic_friction * depth / slide).min(1.0)
                };
                let correction = matrix::scale(tangential, kept - 1.0);
                if rigid {
                    corrections.push((index, correction));
                } else {
                    *position = matrix::add(*position, correction);
                }
            }
            // A rigid body takes friction whole, as a push and a turn (it rolls); a push on its
            // contact particle alone would reach the rest 1/91 at a time.
            for (index, correction) in corrections.drain(..) {
                body.move_rigidly(index, correction);
            }
        }
    }

    /// Velocities from the positions, plastic creep, and the finite check.
    ///
    /// A particle a slab pushed this substep leaves it with no normal speed of its own: the push
    /// only undoes penetration, and contacts have no restitution (Obi's have none), so a ball
    /// bounces by springing back from its squash, not from the contact.
    fn finish_substep(&mut self, h: f64) -> Result<(), SoftBodyError> {
        for (index, (body, pushes)) in self.bodies.iter_mut().zip(&self.pushes).enumerate() {
            if !body.active {
                continue;
            }
            for (((velocity, position), previous), (depth, normal)) in body
                .velocities
                .iter_mut()
                .zip(&body.positions)
                .zip(&body.previous)
                .zip(pushes)
            {
                *velocity = matrix::scale(matrix::sub(*position, *previous), 1.0 / h);
                if *depth > 0.0 {
                    let normal = [normal[0], normal[1], 0.0];
                    let outward = matrix::dot(*velocity, normal);
                    if outward > 0.0 {
                        *velocity = matrix::sub(*velocity, matrix::scale(normal, outward));
                    }
                }
            }
            body.creep(h);
            let finite = |v: &Vector| v.iter().all(|x| x.is_finite());
            if let Some(particle) = body
                .positions
                .iter()
                .zip(&body.velocities)
                .position(|(position, velocity)| !(finite(position) && finite(velocity)))
            {
                return Err(SoftBodyError::NonFinite {
                    update: self.update,
                    body: index,
                    particle,
                });
            }
        }
        Ok(())
    }
}

/// A body's centre and the largest distance of a particle from it.
fn bounds(body: &Body) -> (Vector, f64) {
    let centre = body.centre();
    let extent = body
        .positions
        .iter()
        .map(|position| matrix::norm(matrix::sub(*position, centre)))
        .fold(0.0, f64::max);
    (centre, extent)
}

#[cfg(test)]
mod tests;
