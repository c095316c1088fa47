//! One soft body: its particles, its rest shape, and the shape-matching projection with
//! plasticity that keeps them together.
//!
//! **Shape matching** (Müller et al. 2005, one cluster per ball). Each projection finds the
//! particles' centre `c`, the best linear map `A = (Σ m pᵢ qᵢᵀ)(Σ m qᵢ qᵢᵀ)⁻¹` from the rest
//! offsets `qᵢ` to the current offsets `pᵢ = xᵢ − c`, and its rotation `R`. The goal transform
//! blends the two by the deformation resistance `s`: `T = s·R + (1 − s)·Â`, with `Â = A/∛det A`
//! (the linear fit at the rest volume; Obi softbodies keep their volume). Every particle then
//! moves to `T qᵢ + c`. At `s = 1` the ball is rigid; below 1 a squash or stretch decays by the
//! factor `1 − s` per projection, which is what makes a soft ball spring back after a contact.
//! The projection moves no centre of mass: `Σ m qᵢ = 0`, so the goals' centre is `c`.
//!
//! **Plasticity** (Obi's plastic yield, creep, maximum deformation and recovery). The rest
//! offsets are `qᵢ = P rᵢ` with `rᵢ` the ball's original offsets and `P` a plastic stretch
//! (identity at first, determinant 1). After each substep, when the elastic stretch `S = Rᵀ Â`
//! (of the linear fit at the rest volume) is further than the yield from the identity (Frobenius
//! norm), `P` absorbs the share `min(1, creep · h / update)` of it: Obi's creep read as the share
//! absorbed per update (1/60 s). Read per second (2 a second), a 2.5-unit drop left the plastic
//! ball a dent of 0.01, invisible, where the release meant this ball to look plastic; read per
//! update, the same drop leaves a dent of 0.10 (its height 0.87 of its width). `P` is kept
//! within the maximum deformation of the identity; recovery pulls it back at its rate.
//!
//! Units: lengths in scene units, times in seconds, masses in kilograms.

use super::UPDATE_SECONDS;
use crate::physics::vector3::{self as matrix, IDENTITY, Matrix, NO_ROTATION, Quaternion, Vector};

/// Particles of a ball: its centre, a shell of 18 halfway out and a shell of 72 at the surface
/// (the release's balls have 91).
pub const SPHERE_PARTICLES: usize = 91;
/// Particles of the inner shell.
const INNER_SHELL: usize = 18;
/// Rotation-extraction steps per projection (warm-started from the last one).
const ROTATION_ITERATIONS: usize = 4;

/// How a body resists and keeps deformation (the release's Obi softbody parameters).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SoftMaterial {
    /// Obi's deformation resistance, in `[0, 1]`: 1 is rigid.
    pub deformation_resistance: f64,
    /// Plastic behaviour, if any.
    pub plasticity: Option<Plasticity>,
}

/// Obi's plasticity parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plasticity {
    /// The largest plastic deformation, as the Frobenius distance of `P` from the identity.
    pub max_deformation: f64,
    /// The elastic deformation (Frobenius distance of `S` from the identity) above which the
    /// rest shape starts to creep.
    pub yield_strain: f64,
    /// The share of the elastic deformation absorbed per second past the yield.
    pub creep: f64,
    /// The share of the plastic deformation undone per second.
    pub recovery: f64,
}

/// The release's `Elastic` ball ("Ball More Elastic": deformation resistance 0.17).
pub const ELASTIC: SoftMaterial = SoftMaterial {
    deformation_resistance: 0.17,
    plasticity: None,
};
/// The release's `Rigid` ball ("Ball Less Elastic": deformation resistance 1).
pub const RIGID: SoftMaterial = SoftMaterial {
    deformation_resistance: 1.0,
    plasticity: None,
};
/// The release's `Plastic` ball (deformation resistance 0.136, maximum deformation 0.622,
/// plastic yield 0.2, creep 2, recovery 0).
pub const PLASTIC: SoftMaterial = SoftMaterial {
    deformation_resistance: 0.136,
    plasticity: Some(Plasticity {
        max_deformation: 0.622,
        yield_strain: 0.2,
        creep: 2.0,
        recovery: 0.0,
    }),
};

/// The particle offsets of a ball of particle-centre radius `radius`: the centre, 18 points at
/// half the radius and 72 at the radius, each shell a Fibonacci lattice (nearly even spacing,
/// no pole clusters), the inner one turned by half the golden angle against the outer.
pub fn sphere_offsets(radius: f64) -> Vec<Vector> {
    let golden_angle = std::f64::consts::PI * (3.0 - 5.0_f64.sqrt());
    let shell = |count: usize, shell_radius: f64, turn: f64| {
        (0..count).map(move |index| {
            let height = 1.0 - 2.0 * (index as f64 + 0.5) / count as f64;
            let ring = (1.0 - height * height).max(0.0).sqrt();
            let angle = index as f64 * golden_angle + turn;
            [
                shell_radius * ring * angle.cos(),
                shell_radius * height,
                shell_radius * ring * angle.sin(),
            ]
        })
    };
    let mut offsets = vec![[0.0; 3]];
    offsets.extend(shell(INNER_SHELL, 0.5 * radius, 0.5 * golden_angle));
    offsets.extend(shell(SPHERE_PARTICLES - 1 - INNER_SHELL, radius, 0.0));
    offsets
}

/// A soft body being simulated.
#[derive(Debug, Clone)]
pub struct Body {
    pub(super) material: SoftMaterial,
    /// Mass of each particle, kg.
    pub(super) particle_mass: f64,
    /// The original rest offsets `rᵢ` (centred: they sum to zero).
    original: Vec<Vector>,
    /// The current rest offsets `qᵢ = P rᵢ`.
    rest: Vec<Vector>,
    /// `(Σ qᵢ qᵢᵀ)⁻¹` of the current rest offsets.
    rest_inverse: Matrix,
    /// The plastic stretch `P`.
    plastic: Matrix,
    /// The last rotation found (the warm start of the next).
    rotation: Quaternion,
    /// The last linear fit `A` (maps current rest offsets to current offsets).
    transform: Matrix,
    pub(super) positions: Vec<Vector>,
    pub(super) previous: Vec<Vector>,
    pub(super) velocities: Vec<Vector>,
    /// Whether the body takes part (a counterfactual run removes bodies).
    pub(super) active: bool,
}

impl Body {
    /// A body of `material` with particles at `centre + offsets[i]`, each of `particle_mass`
    /// kg, at rest. `None` when the offsets span no volume.
    pub fn new(
        centre: Vector,
        offsets: &[Vector],
        particle_mass: f64,
        material: SoftMaterial,
    ) -> Option<Body> {
        let count = offsets.len() as f64;
        let mean = offsets
            .iter()
            .fold([0.0; 3], |acc, offset| matrix::add(acc, *offset));
        let mean = matrix::scale(mean, 1.0 / count);
        let original: Vec<Vector> = offsets
            .iter()
            .map(|offset| matrix::sub(*offset, mean))
            .collect();
        let rest_inverse = second_moment_inverse(&original)?;
        let positions: Vec<Vector> = original
            .iter()
            .map(|offset| matrix::add(centre, *offset))
            .collect();
        Some(Body {
            material,
            particle_mass,
            rest: original.clone(),
            original,
            rest_inverse,
            plastic: IDENTITY,
            rotation: NO_ROTATION,
            transform: IDENTITY,
            previous: positions.clone(),
            velocities: vec![[0.0; 3]; positions.len()],
            positions,
            active: true,
        })
    }

    /// Particle positions, units.
    pub fn positions(&self) -> &[Vector] {
        &self.positions
    }

    /// Particle velocities, units/s.
    pub fn velocities(&self) -> &[Vector] {
        &self.velocities
    }

    /// Whether the body is simulated.
    pub fn is_active(&self) -> bool {
        self.active
    }

    /// The material.
    pub fn material(&self) -> SoftMaterial {
        self.material
    }

    /// The particles' centre (mean position: particles have equal masses), units.
    pub fn centre(&self) -> Vector {
        mean(&self.positions)
    }

    /// The centre's velocity, units/s.
    pub fn centre_velocity(&self) -> Vector {
        mean(&self.velocities)
    }

    /// The map from the original rest offsets to the current ones (`T P`): what a mesh of the
    /// ball is drawn with.
    pub fn deformation(&self) -> Matrix {
        matrix::multiply(&self.transform, &self.plastic)
    }

    /// The plastic stretch `P` (the identity for a ball never deformed past its yield).
    pub fn plastic_deformation(&self) -> Matrix {
        self.plastic
    }

    /// The rotation of the last projection.
    pub fn rotation(&self) -> Matrix {
        matrix::rotation_matrix(self.rotation)
    }

    /// Gives the body velocity `velocity` (units/s), every particle the same.
    pub fn set_velocity(&mut self, velocity: Vector) {
        for value in &mut self.velocities {
            *value = velocity;
        }
    }

    /// Moves every particle the share `blend` of the way to its rigid shape-matching goal (one
    /// projection), and keeps the linear fit for drawing and plasticity.
    pub(super) fn project_shape(&mut self, blend: f64) {
        let centre = mean(&self.positions);
        let mut moment = [[0.0; 3]; 3];
        for (position, rest) in self.positions.iter().zip(&self.rest) {
            let offset = matrix::sub(*position, centre);
            moment = matrix::add_scaled(&moment, &matrix::outer(offset, *rest), 1.0);
        }
        self.transform = matrix::multiply(&moment, &self.rest_inverse);
        self.rotation = matrix::extract_rotation(&moment, self.rotation, ROTATION_ITERATIONS);
        let rotation = matrix::rotation_matrix(self.rotation);
        for (position, rest) in self.positions.iter_mut().zip(&self.rest) {
            let goal = matrix::add(centre, matrix::apply(&rotation, *rest));
            *position = matrix::add(
                *position,
                matrix::scale(matrix::sub(goal, *position), blend),
            );
        }
    }

    /// Moves the body as one rigid piece so that particle `index` moves by `correction`
    /// (units): the position-level impulse of a rigid body against a static collider (Müller et
    /// al. 2020, "Detailed Rigid Body Simulation with Extended Position Based Dynamics"), with
    /// the particles' mass and their moment of inertia about the centre, taken isotropic
    /// (`I = ⅔ Σ m |rᵢ|²`, exact for a ball's even shells).
    pub(super) fn move_rigidly(&mut self, index: usize, correction: Vector) {
        let length = matrix::norm(correction);
        let Some(&point) = self.positions.get(index) else {
            return;
        };
        if length <= 0.0 || !length.is_finite() {
            return;
        }
        let centre = mean(&self.positions);
        let mass = self.particle_mass * self.positions.len() as f64;
        let inertia = 2.0 / 3.0
            * self.particle_mass
            * self
                .positions
                .iter()
                .map(|position| {
                    matrix::dot(
                        matrix::sub(*position, centre),
                        matrix::sub(*position, centre),
                    )
                })
                .sum::<f64>();
        if inertia <= 0.0 {
            return;
        }
        let arm = matrix::sub(point, centre);
        let lever = matrix::cross(arm, matrix::scale(correction, 1.0 / length));
        let weight = 1.0 / mass + matrix::dot(lever, lever) / inertia;
        let shift = matrix::scale(correction, 1.0 / (mass * weight));
        let turn = matrix::scale(matrix::cross(arm, correction), 1.0 / (inertia * weight));
        let angle = matrix::norm(turn);
        let rotation = if angle > 0.0 {
            let half = 0.5 * angle;
            let axis = matrix::scale(turn, half.sin() / angle);
            matrix::rotation_matrix([half.cos(), axis[0], axis[1], axis[2]])
        } else {
            IDENTITY
        };
        for position in &mut self.positions {
            let offset = matrix::apply(&rotation, matrix::sub(*position, centre));
            *position = matrix::add(matrix::add(centre, offset), shift);
        }
    }

    /// Lets the rest shape absorb deformation past the yield, after a substep of `h` seconds.
    pub(super) fn creep(&mut self, h: f64) {
        let Some(plasticity) = self.material.plasticity else {
            return;
        };
        let rotation = matrix::rotation_matrix(self.rotation);
        let determinant = matrix::determinant(&self.transform);
        if !(determinant > 1e-6 && determinant.is_finite()) {
            return;
        }
        let volume_kept = matrix::scale_matrix(&self.transform, 1.0 / determinant.cbrt());
        let stretch = matrix::multiply(&matrix::transpose(&rotation), &volume_kept);
        // The symmetric part: rotation extraction leaves a small antisymmetric rest.
        let symmetric = matrix::scale_matrix(
            &matrix::add_scaled(&stretch, &matrix::transpose(&stretch), 1.0),
            0.5,
        );
        let strain = matrix::distance(&symmetric, &IDENTITY);
        let mut plastic = self.plastic;
        if strain > plasticity.yield_strain {
            let share = (plasticity.creep * h / UPDATE_SECONDS).min(1.0);
            let step = matrix::add_scaled(
                &IDENTITY,
                &matrix::add_scaled(&symmetric, &IDENTITY, -1.0),
                share,
            );
            plastic = matrix::multiply(&step, &plastic);
        }
        if plasticity.recovery > 0.0 {
            let share = (plasticity.recovery * h).min(1.0);
            plastic = matrix::add_scaled(
                &plastic,
                &matrix::add_scaled(&IDENTITY, &plastic, -1.0),
                share,
            );
        }
        let excess = matrix::distance(&plastic, &IDENTITY);
        if excess > plasticity.max_deformation {
            let kept = plasticity.max_deformation / excess;
            plastic = matrix::add_scaled(
                &IDENTITY,
                &matrix::add_scaled(&plastic, &IDENTITY, -1.0),
                kept,
            );
        }
        let determinant = matrix::determinant(&plastic);
        if !(determinant > 1e-6 && determinant.is_finite()) || plastic == self.plastic {
            return;
        }
        let plastic = matrix::scale_matrix(&plastic, 1.0 / determinant.cbrt());
        let rest: Vec<Vector> = self
            .original
            .iter()
            .map(|offset| matrix::apply(&plastic, *offset))
            .collect();
        // A plastic stretch that leaves no volume to invert is not taken.
        let (Some(rest_inverse), Some(plastic_inverse)) =
            (second_moment_inverse(&rest), matrix::inverse(&plastic))
        else {
            return;
        };
        // The goal transform now refers to the new rest shape: `T P` (what is drawn) is kept.
        self.transform = matrix::multiply(
            &matrix::multiply(&self.transform, &self.plastic),
            &plastic_inverse,
        );
        self.plastic = plastic;
        self.rest = rest;
        self.rest_inverse = rest_inverse;
    }
}

/// The mean of some vectors.
pub(super) fn mean(values: &[Vector]) -> Vector {
    let sum = values
        .iter()
        .fold([0.0; 3], |acc, value| matrix::add(acc, *value));
    matrix::scale(sum, 1.0 / values.len().max(1) as f64)
}

/// `(Σ qᵢ qᵢᵀ)⁻¹`, or `None` when the offsets span no volume.
fn second_moment_inverse(offsets: &[Vector]) -> Option<Matrix> {
    let moment = offsets.iter().fold([[0.0; 3]; 3], |acc, offset| {
        matrix::add_scaled(&acc, &matrix::outer(*offset, *offset), 1.0)
    });
    matrix::inverse(&moment)
}
