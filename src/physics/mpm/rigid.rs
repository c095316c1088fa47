//! Rigid discs in the MPM grid, two-way coupled: each disc is a moving collider for the grid
//! (nodes with mass inside it lose the velocity that approaches it, relative to its surface, and
//! the tangential one up to Coulomb friction), and the momentum the grid loses there is given to
//! the disc as an impulse and a torque; gravity and contacts with the static colliders act on the
//! disc directly. Its particles are markers set on its pose after every substep (they carry its
//! motion for tracking and are not scattered), so a disc has no stress and no wave speed.
//!
//! **Why not particles averaged into a body.** Summing the gathered velocities of a body's own
//! particles lets only the outer layer of cells feel a contact each substep: a rigid disc resting
//! on a soft one sank into it at a steady 0.1 units/s (measured), and one on a floor sank until a
//! fifth of it was inside. **Why not a very stiff elastic material.** Its substep falls as
//! `dx/√(E/ρ)`: a rigid ball a thousand times stiffer than the soft ones would make every run
//! thirty times slower.
//!
//! **Contacts with the static colliders**: each substep, for each collider the disc's edge enters
//! (its centre's signed distance minus its radius below zero), sequential impulses at the deepest
//! point remove the approaching normal velocity (no restitution) and the tangential one up to
//! Coulomb friction; after the move the disc is pushed out by the depth. Discs do not touch each
//! other except through soft material (the ball scenario has one rigid ball a scene).
//!
//! Input: each disc's radius, mass, moment of inertia, pose and velocities; its marker offsets.
//! Output: per substep, the grid velocities projected, the discs' new poses, the markers' states.

use super::MpmError;
use super::collider::{Boundary, Collider, project};
use super::grid::{block_key, blocks_along, node_is_live};
use super::material::Material;
use super::solver::{ParticleState, Solver};
use super::transfer::{
    ParticleConstants, affine_norm_squared, clamp_position, grid_index, is_finite, speed_squared,
};

/// Sequential-impulse passes over a disc's collider contacts per substep (a wedge has two).
const CONTACT_PASSES: usize = 8;
/// A disc whose edge is this close to a collider (a fraction of its radius) is in contact: one
/// resting exactly on a surface must not fall freely for a substep before it touches.
const CONTACT_GAP: f64 = 1e-3;

/// One rigid disc.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBody {
    /// Id of its first marker particle; its markers are `first..first + offsets.len()`.
    pub first: u32,
    /// Each marker's offset from the centre at angle 0, in id order.
    pub offsets: Vec<[f64; 2]>,
    /// Radius of the disc.
    pub radius: f64,
    /// Coulomb friction against other material at its surface.
    pub friction: f64,
    /// Rolling resistance against the static colliders: the torque opposing its spin is at most
    /// this share of the normal force times the radius.
    pub rolling_resistance: f64,
    /// Coulomb friction against the static colliders in place of their boundary condition's.
    pub collider_friction: Option<f64>,
    /// Total mass.
    pub mass: f64,
    /// Moment of inertia about the centre.
    pub inertia: f64,
    /// Centre (of mass).
    pub center: [f64; 2],
    /// Rotation angle, radians, counter-clockwise.
    pub angle: f64,
    /// Velocity of the centre.
    pub velocity: [f64; 2],
    /// Angular velocity, rad/s, counter-clockwise.
    pub angular_velocity: f64,
}

/// The particles of one material taken as one body ([`Solver::body_motion`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyMotion {
    /// Centre of mass.
    pub centre: [f64; 2],
    /// Rigid spin about it, rad/s, counter-clockwise.
    pub spin: f64,
    /// Total mass.
    pub mass: f64,
    /// Moment of inertia about the centre.
    pub inertia: f64,
}

/// Grid momentum given to a disc during one grid update: (impulse, angular impulse).
pub(super) type Exchange = ([f64; 2], f64);

impl RigidBody {
    /// The offset of marker `index` at the current angle.
    #[inline]
    pub fn rotated_offset(&self, index: usize) -> [f64; 2] {
        let offset = self.offsets.get(index).copied().unwrap_or([0.0; 2]);
        let (sin, cos) = self.angle.sin_cos();
        [
            cos * offset[0] - sin * offset[1],
            sin * offset[0] + cos * offset[1],
        ]
    }

    /// The disc's velocity at `offset` from its centre.
    #[inline]
    fn velocity_at(&self, offset: [f64; 2]) -> [f64; 2] {
        [
            self.velocity[0] - self.angular_velocity * offset[1],
            self.velocity[1] + self.angular_velocity * offset[0],
        ]
    }

    /// Fastest point of the disc, for the time step.
    pub(super) fn top_speed(&self) -> f64 {
        self.velocity[0].hypot(self.velocity[1]) + self.angular_velocity.abs() * self.radius
    }

    /// Projects the velocity `[vx, vy, mass]` of a grid node at `position` if it lies inside the
    /// disc, by `boundary` relative to the disc's surface motion; adds the momentum the node
    /// lost to `exchange`.
    pub(super) fn couple_node(
        &self,
        node: &mut [f64; 3],
        position: [f64; 2],
        boundary: Boundary,
        exchange: &mut Exchange,
    ) {
        let mass = node[2];
        if mass <= 0.0 {
            return;
        }
        let offset = [position[0] - self.center[0], position[1] - self.center[1]];
        let distance = offset[0].hypot(offset[1]);
        if distance >= self.radius {
            return;
        }
        let normal = if distance > 0.0 {
            [offset[0] / distance, offset[1] / distance]
        } else {
            [0.0, 1.0]
        };
        let surface = self.velocity_at(offset);
        let relative = [node[0] - surface[0], node[1] - surface[1]];
        let projected = project(relative, normal, boundary);
        let change = [projected[0] - relative[0], projected[1] - relative[1]];
        node[0] += change[0];
        node[1] += change[1];
        // What the node gained, the disc loses (at the node's offset).
        let impulse = [-mass * change[0], -mass * change[1]];
        exchange.0[0] += impulse[0];
        exchange.0[1] += impulse[1];
        exchange.1 += offset[0] * impulse[1] - offset[1] * impulse[0];
    }

    /// One substep of the disc: the grid's impulse and gravity, contacts with the static
    /// colliders, the move, the push out of any collider it entered.
    pub(super) fn advance(
        &mut self,
        exchange: Exchange,
        gravity: [f64; 2],
        colliders: &[Collider],
        dt: f64,
    ) {
        self.velocity[0] += exchange.0[0] / self.mass + dt * gravity[0];
        self.velocity[1] += exchange.0[1] / self.mass + dt * gravity[1];
        if self.inertia > 0.0 {
            self.angular_velocity += exchange.1 / self.inertia;
        }
        self.collide(colliders);
        self.center[0] += dt * self.velocity[0];
        self.center[1] += dt * self.velocity[1];
        self.angle += dt * self.angular_velocity;
        for (depth, normal, _) in self.contacts(colliders, 0.0) {
            self.center[0] -= depth * normal[0];
            self.center[1] -= depth * normal[1];
        }
    }

    /// The colliders the disc's edge is within `gap` of: (signed depth, negative inside; the
    /// collider's outward normal at the centre; its boundary).
    fn contacts(&self, colliders: &[Collider], gap: f64) -> Vec<(f64, [f64; 2], Boundary)> {
        colliders
            .iter()
            .filter_map(|collider| {
                let (distance, normal) = collider.signed_distance(self.center);
                let depth = distance - self.radius;
                (depth < gap).then_some((depth, normal, collider.boundary))
            })
            .collect()
    }

    /// Removes approaching velocity at the contact points (see the module doc).
    fn collide(&mut self, colliders: &[Collider]) {
        let contacts = self.contacts(colliders, CONTACT_GAP * self.radius);
        if contacts.is_empty() {
            return;
        }
        let inverse_mass = 1.0 / self.mass;
        let inverse_inertia = if self.inertia > 0.0 {
            1.0 / self.inertia
        } else {
            0.0
        };
        for _ in 0..CONTACT_PASSES {
            for &(_, normal, boundary) in &contacts {
                // The deepest point of the disc towards the collider.
                let offset = [-self.radius * normal[0], -self.radius * normal[1]];
                let point_velocity = self.velocity_at(offset);
                let normal_speed = point_velocity[0] * normal[0] + point_velocity[1] * normal[1];
                if normal_speed >= 0.0 {
                    continue;
                }
                let tangent_velocity = [
                    point_velocity[0] - normal_speed * normal[0],
                    point_velocity[1] - normal_speed * normal[1],
                ];
                let tangent_speed = tangent_velocity[0].hypot(tangent_velocity[1]);
                // An impulse j along a unit direction d at the point changes its speed along d
                // by j·(1/m + (r × d)²/I); along the normal the arm is zero for a disc.
                let normal_impulse = -normal_speed / inverse_mass;
                let mut impulse = [normal_impulse * normal[0], normal_impulse * normal[1]];
                if tangent_speed > 0.0 {
                    let direction = [
                        -tangent_velocity[0] / tangent_speed,
                        -tangent_velocity[1] / tangent_speed,
                    ];
                    let arm = offset[0] * direction[1] - offset[1] * direction[0];
                    let stopping = tangent_speed / (inverse_mass + arm * arm * inverse_inertia);
                    let bound = match (self.collider_friction, boundary) {
                        (Some(friction), _) | (None, Boundary::Separate { friction }) => {
                            friction * normal_impulse
                        }
                        (None, Boundary::Sticky) => f64::INFINITY,
                        (None, Boundary::Slip) => 0.0,
                    };
                    let friction_impulse = stopping.min(bound);
                    impulse[0] += friction_impulse * direction[0];
                    impulse[1] += friction_impulse * direction[1];
                }
                self.velocity[0] += impulse[0] * inverse_mass;
                self.velocity[1] += impulse[1] * inverse_mass;
                self.angular_velocity +=
                    (offset[0] * impulse[1] - offset[1] * impulse[0]) * inverse_inertia;
                // Rolling resistance: an angular impulse against the spin of at most
                // `c · j_n · r`, never reversing it.
                let most = self.rolling_resistance * normal_impulse * self.radius * inverse_inertia;
                let spin = self.angular_velocity;
                self.angular_velocity = spin - spin.signum() * most.min(spin.abs());
            }
        }
    }

    /// Puts marker `index` where the disc's pose says, with the disc's velocity there and the
    /// affine matrix of its rotation.
    pub(super) fn place(&self, particle: &mut ParticleState, index: usize) {
        let offset = self.rotated_offset(index);
        let omega = self.angular_velocity;
        particle.position = [self.center[0] + offset[0], self.center[1] + offset[1]];
        particle.velocity = self.velocity_at(offset);
        // The velocity field of a rotation: ∇v = [[0, −ω], [ω, 0]].
        particle.affine = [0.0, -omega, omega, 0.0];
        particle.volume_ratio = 1.0;
        particle.deformation = super::elastic::IDENTITY;
    }

    /// The marker index of particle `id`, if it is one of this disc's markers.
    #[inline]
    fn index_of(&self, id: u32) -> Option<usize> {
        let index = id.checked_sub(self.first)? as usize;
        (index < self.offsets.len()).then_some(index)
    }
}

/// The discs of a solver, sorted by their first marker id.
#[derive(Debug, Clone, Default)]
pub(super) struct RigidBodies {
    pub(super) bodies: Vec<RigidBody>,
}

impl RigidBodies {
    /// The disc holding marker `id` and the marker's index in it.
    #[inline]
    pub(super) fn find(&self, id: u32) -> Option<(usize, usize)> {
        // Discs are sorted by `first`: the last one starting at or before `id`.
        let after = self.bodies.partition_point(|body| body.first <= id);
        let body = after.checked_sub(1)?;
        let index = self.bodies.get(body)?.index_of(id)?;
        Some((body, index))
    }

    /// Whether there are none.
    pub(super) fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }
}

/// Adding, coupling and moving the rigid discs of a solver.
impl Solver {
    /// Adds `change` to the velocity of every particle of `material`: an impulse on the body
    /// as a whole, which the caller computes between advances (a soft body's restitution at a
    /// contact). Returns whether any particle is of `material`.
    pub fn add_velocity(&mut self, material: usize, change: [f64; 2]) -> bool {
        let mut any = false;
        for (state, constants) in self.state.iter_mut().zip(&self.constants) {
            if constants.material as usize == material {
                state.velocity[0] += change[0];
                state.velocity[1] += change[1];
                any = true;
            }
        }
        any
    }

    /// Slows the rigid rotation of the particles of `material` about their centre of mass by up
    /// to `most` rad/s (a soft body's rolling resistance, which the caller applies between
    /// advances while the body touches a surface): that much spin leaves their velocities and
    /// APIC matrices, their linear momentum stays. Returns their spin before, `None` when no
    /// particle is of `material` or the spin is not a number.
    pub fn spin_down(&mut self, material: usize, most: f64) -> Option<f64> {
        let BodyMotion { centre, spin, .. } = self.body_motion(material)?;
        let change = -spin.signum() * spin.abs().min(most.max(0.0));
        self.rotate_about(material, centre, change);
        Some(spin)
    }

    /// Adds `change` rad/s of rigid rotation about their centre of mass to the particles of
    /// `material` (an angular impulse on a soft body as a whole: its friction at a contact,
    /// computed by the caller between advances); their linear momentum stays. Returns whether
    /// any particle is of `material`.
    pub fn add_spin(&mut self, material: usize, change: f64) -> bool {
        let Some(BodyMotion { centre, .. }) = self.body_motion(material) else {
            return false;
        };
        if change.is_finite() {
            self.rotate_about(material, centre, change);
        }
        true
    }

    /// The particles of `material` as one body: their centre of mass, rigid spin about it
    /// (angular momentum over moment of inertia, rad/s), mass and moment of inertia; `None` when
    /// there is none or the spin is not a number.
    pub fn body_motion(&self, material: usize) -> Option<BodyMotion> {
        let ours = |constants: &ParticleConstants| constants.material as usize == material;
        let (mut mass, mut moment) = (0.0, [0.0; 2]);
        for (state, constants) in self.state.iter().zip(&self.constants) {
            if ours(constants) {
                mass += constants.mass;
                moment[0] += constants.mass * state.position[0];
                moment[1] += constants.mass * state.position[1];
            }
        }
        if mass <= 0.0 {
            return None;
        }
        let centre = [moment[0] / mass, moment[1] / mass];
        let (mut angular_momentum, mut inertia) = (0.0, 0.0);
        for (state, constants) in self.state.iter().zip(&self.constants) {
            if ours(constants) {
                let r = [state.position[0] - centre[0], state.position[1] - centre[1]];
                angular_momentum +=
                    constants.mass * (r[0] * state.velocity[1] - r[1] * state.velocity[0]);
                inertia += constants.mass * (r[0] * r[0] + r[1] * r[1]);
            }
        }
        let spin = angular_momentum / inertia;
        (spin.is_finite() && inertia > 0.0).then_some(BodyMotion {
            centre,
            spin,
            mass,
            inertia,
        })
    }

    /// Adds a rigid rotation of `change` rad/s about `centre` to the particles of `material`:
    /// to their velocities and to their APIC matrices (a rotation's velocity gradient is
    /// `[[0, −ω], [ω, 0]]`).
    fn rotate_about(&mut self, material: usize, centre: [f64; 2], change: f64) {
        for (state, constants) in self.state.iter_mut().zip(&self.constants) {
            if constants.material as usize == material {
                let r = [state.position[0] - centre[0], state.position[1] - centre[1]];
                state.velocity[0] -= change * r[1];
                state.velocity[1] += change * r[0];
                state.affine[1] -= change;
                state.affine[2] += change;
            }
        }
    }

    /// Adds a rigid disc of `material` (a [`Material::Rigid`]) and `radius`, centred on the centroid
    /// of its marker particles at `positions` (each standing for `volume` of the disc: its mass
    /// and moment of inertia are theirs), moving with `velocity` and `angular_velocity` (rad/s,
    /// counter-clockwise); returns its index in [`Solver::rigid_bodies`].
    pub fn add_rigid_body(
        &mut self,
        material: usize,
        radius: f64,
        positions: &[[f64; 2]],
        velocity: [f64; 2],
        angular_velocity: f64,
        volume: f64,
    ) -> Result<usize, MpmError> {
        let (density, friction, rolling_resistance, collider_friction) =
            match self.materials.get(material) {
                Some(Material::Rigid(rigid)) => (
                    rigid.density,
                    rigid.friction,
                    rigid.rolling_resistance,
                    rigid.collider_friction,
                ),
                Some(_) => {
                    return Err(MpmError::RigidBody {
                        material,
                        reason: "a rigid body needs a rigid material".to_string(),
                    });
                }
                None => {
                    let at = positions.first().copied().unwrap_or([0.0; 2]);
                    return Err(MpmError::UnknownMaterial {
                        material,
                        count: self.materials.len(),
                        x: at[0],
                        y: at[1],
                    });
                }
            };
        let numbers_finite = [radius, volume, velocity[0], velocity[1], angular_velocity]
            .iter()
            .all(|value| value.is_finite());
        if positions.is_empty() || !numbers_finite || radius <= 0.0 || volume <= 0.0 {
            return Err(MpmError::RigidBody {
                material,
                reason: format!(
                    "a rigid disc needs markers, a positive radius and volume and finite \
                     velocities ({} markers, radius {radius}, volume {volume})",
                    positions.len()
                ),
            });
        }
        let count = positions.len() as f64;
        let center = positions.iter().fold([0.0; 2], |sum, position| {
            [sum[0] + position[0] / count, sum[1] + position[1] / count]
        });
        let offsets: Vec<[f64; 2]> = positions
            .iter()
            .map(|position| [position[0] - center[0], position[1] - center[1]])
            .collect();
        let mass = density * volume;
        let body = RigidBody {
            first: self.next_id,
            inertia: offsets
                .iter()
                .map(|offset| mass * (offset[0] * offset[0] + offset[1] * offset[1]))
                .sum(),
            mass: mass * count,
            radius,
            friction,
            rolling_resistance,
            collider_friction,
            offsets,
            center,
            angle: 0.0,
            velocity,
            angular_velocity,
        };
        for (index, &position) in positions.iter().enumerate() {
            let mut state = ParticleState::default();
            body.place(&mut state, index);
            self.add_any_particle(material, position, state.velocity, volume)?;
        }
        self.max_speed = self.max_speed.max(body.top_speed());
        let index = self.rigid.bodies.len();
        self.rigid.bodies.push(body);
        Ok(index)
    }

    /// The rigid bodies, in order of creation.
    pub fn rigid_bodies(&self) -> &[RigidBody] {
        &self.rigid.bodies
    }

    /// Each rigid disc projects the grid velocities inside it and takes the momentum they lose
    /// (see [`RigidBody::couple_node`]), then moves ([`RigidBody::advance`]). Discs in order,
    /// nodes in index order: the same sums for any thread count.
    pub(super) fn couple_rigid_bodies(&mut self, dt: f64) {
        let along = blocks_along(&self.grid);
        let columns = self.grid.nodes[1];
        let grid = self.grid;
        let gravity = self.settings.gravity;
        let colliders = self.colliders.colliders();
        for body in &mut self.rigid.bodies {
            let boundary = Boundary::Separate {
                friction: body.friction,
            };
            // The nodes the disc covers, clamped into the grid.
            let node_range = |axis: usize| {
                let low = (body.center[axis] - body.radius - grid.origin[axis]) / grid.spacing;
                let high = (body.center[axis] + body.radius - grid.origin[axis]) / grid.spacing;
                let last = grid.nodes[axis] - 1;
                (
                    grid_index(low.max(0.0)).min(last),
                    grid_index(high.ceil().max(0.0)).min(last),
                )
            };
            let (rows, cells) = (node_range(0), node_range(1));
            let mut exchange = ([0.0; 2], 0.0);
            for i in rows.0..=rows.1 {
                for j in cells.0..=cells.1 {
                    // Nodes of blocks no tile reached hold last substep's numbers: skip them.
                    if !node_is_live(&self.bins.tile_of, along, [i, j]) {
                        continue;
                    }
                    if let Some(node) = self.nodes.get_mut(i * columns + j) {
                        body.couple_node(node, grid.node_position(i, j), boundary, &mut exchange);
                    }
                }
            }
            body.advance(exchange, gravity, colliders, dt);
        }
    }

    /// The rigid discs' markers are put on their discs' poses, rebinned, checked and counted in
    /// the speed limits like the rest.
    pub(super) fn move_rigid_bodies(&mut self, dt: f64) -> Result<(), MpmError> {
        let step = self.step_constants(dt);
        let along = blocks_along(&self.grid);
        let limits = self.position_limits();
        let mut max_speed_squared = self.max_speed * self.max_speed;
        let mut max_affine_squared = self.max_affine * self.max_affine;
        let particles = self
            .state
            .iter_mut()
            .zip(&self.constants)
            .zip(self.base_of.iter_mut().zip(self.block_of.iter_mut()));
        for ((particle, constant), (base, block)) in particles {
            let Some((body, index)) = self.rigid.find(constant.id) else {
                continue;
            };
            if let Some(body) = self.rigid.bodies.get(body) {
                body.place(particle, index);
            }
            if clamp_position(&mut particle.position, limits) {
                self.counters.clamped += 1;
            }
            if !is_finite(particle) {
                return Err(MpmError::NotFinite {
                    id: constant.id,
                    substep: self.counters.substeps,
                    time: self.time,
                });
            }
            max_speed_squared = max_speed_squared.max(speed_squared(particle));
            max_affine_squared = max_affine_squared.max(affine_norm_squared(particle));
            *base = step.base_cell(particle.position);
            *block = block_key(*base, along);
        }
        self.max_speed = max_speed_squared.sqrt();
        self.max_affine = max_affine_squared.sqrt();
        Ok(())
    }
}
