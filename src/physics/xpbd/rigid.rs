//! Rigid boxes for the cloth solver: pose, velocities, mass and inertia of a cuboid, and the two
//! operations XPBD needs of a body (Müller et al., "Detailed Rigid Body Simulation with Extended
//! Position Based Dynamics", 2020): its generalised inverse mass along a direction at a point, and
//! a positional correction applied at a point.
//!
//! Units: metres, kilograms, seconds; orientations are unit quaternions `[w, x, y, z]` rotating
//! the box's local axes into the world (`y` up). Input: half extents, mass and a start pose.
//! Output: the pose and velocities after each substep.

use crate::physics::vector3::{
    self as v3, Matrix, Quaternion, Vector, quaternion_product, rotation_matrix,
};

/// A rigid cuboid.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxBody {
    /// Half its size along its local x, y, z, metres.
    pub half_extents: Vector,
    /// Mass, kilograms.
    pub mass: f64,
    /// Centre of mass, metres.
    pub position: Vector,
    /// Orientation.
    pub orientation: Quaternion,
    /// Velocity of the centre, m/s.
    pub velocity: Vector,
    /// Angular velocity in the world frame, rad/s.
    pub angular_velocity: Vector,
    /// Pose at the start of the current substep (for the velocity update and static friction).
    pub(super) previous_position: Vector,
    pub(super) previous_orientation: Quaternion,
    /// The rotation matrix of `previous_orientation` (read for every contact's friction).
    previous_rotation: Matrix,
    /// Principal moments of inertia in the box's frame, kg m² (the gyroscopic term).
    inertia: Vector,
    /// Their inverses, 1/(kg m²).
    inverse_inertia: Vector,
    /// The rotation matrix of `orientation`, refreshed whenever it changes.
    rotation: Matrix,
}

impl BoxBody {
    /// A box at rest with the given half extents (m), mass (kg), centre and orientation.
    pub fn new(
        half_extents: Vector,
        mass: f64,
        position: Vector,
        orientation: Quaternion,
    ) -> BoxBody {
        let [a, b, c] = half_extents.map(|h| h * h);
        // A solid cuboid: I_x = m (b² + c²) / 3 with half extents.
        let inertia = [
            mass * (b + c) / 3.0,
            mass * (a + c) / 3.0,
            mass * (a + b) / 3.0,
        ];
        let orientation = normalised(orientation);
        let inverse_inertia = inertia.map(|moment| 1.0 / moment);
        BoxBody {
            half_extents,
            mass,
            position,
            orientation,
            velocity: [0.0; 3],
            angular_velocity: [0.0; 3],
            previous_position: position,
            previous_orientation: orientation,
            previous_rotation: rotation_matrix(orientation),
            // As the inverse's inverse, the value the gyroscopic term has always used.
            inertia: inverse_inertia.map(|inverse| 1.0 / inverse),
            inverse_inertia,
            rotation: rotation_matrix(orientation),
        }
    }

    /// `1 / mass`.
    pub fn inverse_mass(&self) -> f64 {
        1.0 / self.mass
    }

    /// The rotation matrix of the current orientation.
    pub fn rotation(&self) -> &Matrix {
        &self.rotation
    }

    /// A point given in the box's frame, in the world.
    pub fn to_world(&self, local: Vector) -> Vector {
        v3::add(self.position, v3::apply(&self.rotation, local))
    }

    /// A world point in the box's frame.
    pub fn to_local(&self, world: Vector) -> Vector {
        v3::apply(
            &v3::transpose(&self.rotation),
            v3::sub(world, self.position),
        )
    }

    /// Where the body point that is at `local` now was at the start of the substep.
    pub fn previous_world(&self, local: Vector) -> Vector {
        v3::add(
            self.previous_position,
            v3::apply(&self.previous_rotation, local),
        )
    }

    /// The eight corners in the world.
    pub fn corners(&self) -> [Vector; 8] {
        let [hx, hy, hz] = self.half_extents;
        std::array::from_fn(|index| {
            let sign = |bit: usize| if index & bit == 0 { -1.0 } else { 1.0 };
            self.to_world([sign(1) * hx, sign(2) * hy, sign(4) * hz])
        })
    }

    /// `I⁻¹ · v` with the inertia in the world frame.
    pub fn inverse_inertia_times(&self, world: Vector) -> Vector {
        let local = v3::apply(&v3::transpose(&self.rotation), world);
        let scaled = [
            local[0] * self.inverse_inertia[0],
            local[1] * self.inverse_inertia[1],
            local[2] * self.inverse_inertia[2],
        ];
        v3::apply(&self.rotation, scaled)
    }

    /// The generalised inverse mass `1/m + (r × n)ᵀ I⁻¹ (r × n)` for a correction along unit
    /// `direction` at world offset `arm` from the centre.
    pub fn generalised_inverse_mass(&self, arm: Vector, direction: Vector) -> f64 {
        let torque = v3::cross(arm, direction);
        self.inverse_mass() + v3::dot(torque, self.inverse_inertia_times(torque))
    }

    /// Applies the positional impulse `impulse` (kg m) at world offset `arm`: the centre moves by
    /// `impulse / m`, the orientation turns by `I⁻¹ (arm × impulse)`.
    pub fn apply_correction(&mut self, arm: Vector, impulse: Vector) {
        self.position = v3::add(self.position, v3::scale(impulse, self.inverse_mass()));
        let turn = self.inverse_inertia_times(v3::cross(arm, impulse));
        self.rotate_by(turn, 1.0);
    }

    /// Applies the velocity impulse `impulse` (kg m/s) at world offset `arm`.
    pub fn apply_velocity_impulse(&mut self, arm: Vector, impulse: Vector) {
        self.velocity = v3::add(self.velocity, v3::scale(impulse, self.inverse_mass()));
        let spin = self.inverse_inertia_times(v3::cross(arm, impulse));
        self.angular_velocity = v3::add(self.angular_velocity, spin);
    }

    /// Velocity of the body point at world offset `arm`.
    pub fn point_velocity(&self, arm: Vector) -> Vector {
        v3::add(self.velocity, v3::cross(self.angular_velocity, arm))
    }

    /// Starts a substep of `h` seconds: remembers the pose, adds gravity (m/s²), and
    /// moves by the velocities (with the gyroscopic term, which keeps a spinning plate's angular
    /// momentum instead of its angular velocity).
    pub(super) fn predict(&mut self, h: f64, gravity: Vector) {
        self.previous_position = self.position;
        self.previous_orientation = self.orientation;
        self.previous_rotation = self.rotation;
        self.velocity = v3::add(self.velocity, v3::scale(gravity, h));
        self.position = v3::add(self.position, v3::scale(self.velocity, h));
        let body = v3::apply(&v3::transpose(&self.rotation), self.angular_velocity);
        let inertia = self.inertia;
        let momentum = [
            body[0] * inertia[0],
            body[1] * inertia[1],
            body[2] * inertia[2],
        ];
        let gyroscopic = v3::cross(body, momentum);
        let body = [
            body[0] - h * gyroscopic[0] * self.inverse_inertia[0],
            body[1] - h * gyroscopic[1] * self.inverse_inertia[1],
            body[2] - h * gyroscopic[2] * self.inverse_inertia[2],
        ];
        self.angular_velocity = v3::apply(&self.rotation, body);
        self.rotate_by(self.angular_velocity, h);
    }

    /// Ends a substep of `h` seconds: velocities from the pose change.
    pub(super) fn derive_velocities(&mut self, h: f64) {
        self.velocity = v3::scale(v3::sub(self.position, self.previous_position), 1.0 / h);
        let [real, i, j, k] = self.previous_orientation;
        let change = quaternion_product(self.orientation, [real, -i, -j, -k]);
        let sign = if change[0] < 0.0 { -1.0 } else { 1.0 };
        self.angular_velocity = [
            2.0 * sign * change[1] / h,
            2.0 * sign * change[2] / h,
            2.0 * sign * change[3] / h,
        ];
    }

    /// Whether pose and velocities are all finite.
    pub fn is_finite(&self) -> bool {
        self.position
            .iter()
            .chain(&self.orientation)
            .chain(&self.velocity)
            .chain(&self.angular_velocity)
            .all(|value| value.is_finite())
    }

    /// Turns the orientation by `h · omega` (first order, then renormalised).
    fn rotate_by(&mut self, omega: Vector, h: f64) {
        let spin = quaternion_product([0.0, omega[0], omega[1], omega[2]], self.orientation);
        let turned: Quaternion = std::array::from_fn(|k| self.orientation[k] + 0.5 * h * spin[k]);
        self.orientation = normalised(turned);
        self.rotation = rotation_matrix(self.orientation);
    }
}

/// `q / |q|`; a zero or non-finite quaternion is returned as it is, so that the step's
/// finiteness check reports it instead of a made-up rotation hiding it.
fn normalised(q: Quaternion) -> Quaternion {
    let length = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if length.is_finite() && length > 0.0 {
        q.map(|v| v / length)
    } else {
        q
    }
}
