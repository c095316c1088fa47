//! The dynamics' ingredients: the mass matrix (with pulley inertia), gravity, the unilateral
//! constraints (ropes, floor contacts, segment stops), the bearing-friction rows, the
//! constraint-space system `J M⁻¹ Jᵀ`, and the numeric derivatives and checks they use.

use super::super::linalg::{Matrix, solve};
use super::GRAVITY;
use super::mechanism::Mechanism;
use super::network::SimulationError;

/// Time step (s) of the difference that gives the rope flow a driven point causes in the
/// instantaneous solve. Drives move linearly, so the difference is exact away from a drive's
/// start and end; its rounding is about `eps · L / h`, 1e-10 m/s for ropes of tens of metres.
const DRIVE_PROBE: f64 = 1e-4;

/// One unilateral constraint `g(y) ≤ 0` with gradient `J`.
#[derive(Clone)]
pub(super) struct Constraint {
    /// `g(y)`, m: positive when violated.
    pub(super) gap: f64,
    /// `J = ∂g/∂y`.
    pub(super) gradient: Vec<f64>,
    /// Velocity-product term of `g̈` (`J̇·v`), for the instantaneous solve.
    pub(super) curvature: f64,
}

/// One bearing-friction row: a pass of a rope over a pulley whose bearing resists the flow.
pub(super) struct FrictionRow {
    /// Index into [`Mechanism::passes`].
    pub(super) pass: usize,
    /// Gradient of the rope length up to the pulley, dimensionless (the rope flows forward over
    /// the pulley at `−gradient · v`, m/s).
    pub(super) gradient: Vec<f64>,
    /// The largest friction force at the rim, N: `friction_torque / R`.
    pub(super) bound: f64,
}

impl Mechanism {
    pub(super) fn mass_matrix(&self, heights: &[f64]) -> Matrix {
        self.mass_matrix_turning(heights, |_| true)
    }

    /// The mass matrix at `y` with the inertia of the pulleys that the ropes `turning(rope)`
    /// pass over (a slack rope does not turn its pulleys, so they add nothing to its bodies).
    pub(super) fn mass_matrix_turning(
        &self,
        heights: &[f64],
        turning: impl Fn(usize) -> bool,
    ) -> Matrix {
        let count = heights.len();
        let mut matrix = Matrix::zeros(count);
        for (i, body) in self.network.bodies.iter().enumerate() {
            matrix.add(i, i, body.mass);
        }
        for &(rope, position, pulley, _) in &self.passes {
            let p = &self.network.pulleys[pulley];
            if p.inertia > 0.0 && turning(rope) {
                let c = self.flow_gradient(rope, position, heights);
                let factor = p.inertia / (p.radius * p.radius);
                for i in 0..count {
                    for j in 0..count {
                        matrix.add(i, j, factor * c[i] * c[j]);
                    }
                }
            }
        }
        matrix
    }

    /// Gravity on each body, N.
    pub(super) fn forces(&self) -> Vec<f64> {
        self.network
            .bodies
            .iter()
            .map(|b| -b.mass * GRAVITY)
            .collect()
    }

    /// Every unilateral constraint at `(y, v)`: ropes first (one per rope, in order), then floor
    /// contacts, then segment stops.
    pub(super) fn constraints(&self, heights: &[f64], velocities: &[f64]) -> Vec<Constraint> {
        let count = heights.len();
        let mut constraints = Vec::new();
        for index in 0..self.network.ropes.len() {
            let length = |heights: &[f64]| self.rope_length(index, heights);
            constraints.push(Constraint {
                gap: length(heights) - self.rest_lengths[index],
                gradient: numeric_gradient(length, heights, &self.rope_bodies[index]),
                curvature: numeric_curvature(length, heights, velocities),
            });
        }
        if let Some(floor) = self.network.floor {
            for (i, body) in self.network.bodies.iter().enumerate() {
                if let Some(clearance) = body.floor_clearance {
                    let mut gradient = vec![0.0; count];
                    gradient[i] = -1.0;
                    constraints.push(Constraint {
                        gap: floor + clearance - heights[i],
                        gradient,
                        curvature: 0.0,
                    });
                }
            }
        }
        for (index, rope) in self.network.ropes.iter().enumerate() {
            for (segment, w) in rope.path.windows(2).enumerate() {
                let length = |heights: &[f64]| self.segment_length(index, segment, heights);
                let gradient = numeric_gradient(length, heights, &self.rope_bodies[index]);
                if gradient.iter().any(|g| g.abs() > 1e-12) {
                    let minimum = self.clearance(w[0]) + self.clearance(w[1]);
                    constraints.push(Constraint {
                        gap: minimum - length(heights),
                        gradient: gradient.iter().map(|g| -g).collect(),
                        curvature: -numeric_curvature(length, heights, velocities),
                    });
                }
            }
        }
        constraints
    }

    /// `M⁻¹ · x`.
    pub(super) fn inverse_mass_times(
        m: &Matrix,
        x: &[f64],
        context: &str,
    ) -> Result<Vec<f64>, SimulationError> {
        solve(m, x).ok_or_else(|| SimulationError::Singular {
            context: context.to_string(),
        })
    }

    /// The constraint-space system of the rows with these gradients: `A = J M⁻¹ Jᵀ` and the
    /// columns `M⁻¹ Jᵀ`.
    pub(super) fn constraint_system(
        m: &Matrix,
        gradients: &[&[f64]],
    ) -> Result<(Matrix, Vec<Vec<f64>>), SimulationError> {
        let columns: Vec<Vec<f64>> = gradients
            .iter()
            .map(|gradient| Self::inverse_mass_times(m, gradient, "mass matrix"))
            .collect::<Result<_, _>>()?;
        let k = gradients.len();
        let mut a = Matrix::zeros(k);
        for (i, gradient) in gradients.iter().enumerate() {
            for (j, column) in columns.iter().enumerate() {
                a.add(i, j, dot(gradient, column));
            }
        }
        Ok((a, columns))
    }

    /// The bearing-friction rows at heights `y`: one per pass of a rope over a pulley with a
    /// bearing torque. Ideal pulleys add none (no cost), nor does a straight pass (the rope
    /// does not touch the pulley, which does not turn), nor a pass whose flow no body moves (the
    /// rope up to the pulley comes from a fixed or driven point, so the bearing resists only the
    /// hand that drives it, and the bodies' motion does not depend on it).
    pub(super) fn friction_rows(&self, heights: &[f64]) -> Vec<FrictionRow> {
        self.passes
            .iter()
            .enumerate()
            .filter_map(|(pass, &(rope, position, pulley, sign))| {
                let p = &self.network.pulleys[pulley];
                if p.friction_torque <= 0.0 || sign == 0.0 {
                    return None;
                }
                let gradient = self.flow_gradient(rope, position, heights);
                gradient
                    .iter()
                    .any(|g| g.abs() > 1e-12)
                    .then(|| FrictionRow {
                        pass,
                        gradient,
                        bound: p.friction_torque / p.radius,
                    })
            })
            .collect()
    }

    /// For each friction row, the rate (m/s) at which driven points lengthen the rope up to its
    /// pulley at time `time` with the bodies held at `heights` (so the forward flow over the
    /// pulley is `−(gradient · v + this)`); zeros when nothing is driven.
    pub(super) fn drive_flow(&self, rows: &[FrictionRow], heights: &[f64], time: f64) -> Vec<f64> {
        if self.network.drives.is_empty() {
            return vec![0.0; rows.len()];
        }
        let length_at = |rope: usize, position: usize, at: f64| {
            self.now.set(at);
            self.length_to(rope, position, heights)
        };
        let rates = rows
            .iter()
            .map(|row| {
                let (rope, position, _, _) = self.passes[row.pass];
                // Forward in time: what the drive does next, also at its start.
                (length_at(rope, position, time + DRIVE_PROBE) - length_at(rope, position, time))
                    / DRIVE_PROBE
            })
            .collect();
        self.now.set(time);
        rates
    }

    /// Adds each friction row's impulse (or force), turned into a bearing torque on its pulley
    /// (counter-clockwise positive), to `torques`; `per` is the step (1 for forces).
    pub(super) fn add_friction_torques(
        &self,
        rows: &[FrictionRow],
        impulses: &[f64],
        per: f64,
        torques: &mut [f64],
    ) {
        for (row, lambda) in rows.iter().zip(impulses) {
            let (_, _, pulley, sign) = self.passes[row.pass];
            // A positive impulse pushes the rope forward, which turns the pulley by `sign`.
            torques[pulley] += sign * self.network.pulleys[pulley].radius * lambda / per;
        }
    }
}

/// Step of the differences, m. The five-point stencil's truncation error is O(h⁴) (1e-12 of
/// the fifth derivative) and its rounding error about `eps · L / h` (1e-11 for ropes of tens
/// of metres); for vertical segments the length is linear and the result exact to rounding.
const DIFFERENCE_STEP: f64 = 1e-3;

/// `∂f/∂yᵢ` by five-point central differences, for the `involved` heights (the others are 0).
pub(super) fn numeric_gradient(
    f: impl Fn(&[f64]) -> f64,
    y: &[f64],
    involved: &[usize],
) -> Vec<f64> {
    let mut probe = y.to_vec();
    let mut gradient = vec![0.0; y.len()];
    let h = DIFFERENCE_STEP;
    for &i in involved {
        let mut at = |offset: f64| {
            probe[i] = y[i] + offset;
            let value = f(&probe);
            probe[i] = y[i];
            value
        };
        gradient[i] = (8.0 * (at(h) - at(-h)) - (at(2.0 * h) - at(-2.0 * h))) / (12.0 * h);
    }
    gradient
}

/// `vᵀ (∂²f/∂y²) v`, the velocity term of `f̈`, by a central second difference along `v`.
pub(super) fn numeric_curvature(f: impl Fn(&[f64]) -> f64, y: &[f64], v: &[f64]) -> f64 {
    let speed = v.iter().fold(0.0_f64, |acc, x| acc.max(x.abs()));
    if speed == 0.0 {
        return 0.0;
    }
    let step = 1e-4 / speed;
    let along =
        |sign: f64| -> Vec<f64> { y.iter().zip(v).map(|(a, b)| a + sign * step * b).collect() };
    (f(&along(1.0)) - 2.0 * f(y) + f(&along(-1.0))) / (step * step)
}

/// `a · b`.
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Fails with [`SimulationError::NonFinite`] unless every value of `what` is finite.
pub(super) fn check_finite(time: f64, what: &str, values: &[f64]) -> Result<(), SimulationError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(SimulationError::NonFinite {
            time,
            what: what.to_string(),
        })
    }
}
