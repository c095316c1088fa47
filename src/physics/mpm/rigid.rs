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

use super::collider::{Boundary, Collider, project};
use super::solver::ParticleState;

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
                    let bound = match boundary {
                        Boundary::Sticky => f64::INFINITY,
                        Boundary::Slip => 0.0,
                        Boundary::Separate { friction } => friction * normal_impulse,
                    };
                    let friction_impulse = stopping.min(bound);
                    impulse[0] += friction_impulse * direction[0];
                    impulse[1] += friction_impulse * direction[1];
                }
                self.velocity[0] += impulse[0] * inverse_mass;
                self.velocity[1] += impulse[1] * inverse_mass;
                self.angular_velocity +=
                    (offset[0] * impulse[1] - offset[1] * impulse[0]) * inverse_inertia;
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
