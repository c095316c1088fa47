//! The instantaneous solves: exact accelerations, tensions and bearing torques at a state
//! ([`Mechanism::instantaneous`]), and the same at an observed state whose positions carry
//! measurement error ([`Mechanism::observed_accelerations`]).

use super::super::linalg::{solve_boxed_lcp, solve_lcp};
use super::GRAVITY;
use super::dynamics::{Constraint, check_finite, dot, numeric_curvature};
use super::mechanism::{Instant, Instantaneous, Mechanism, State};
use super::network::SimulationError;

/// Rope length (m) by which a rope counts as taut in the instantaneous solve.
const TAUT_TOLERANCE: f64 = 1e-9;

/// Rope speed over a pulley (m/s) below which its bearing counts as holding in the
/// instantaneous solve (static friction, a force anywhere in its bound) rather than sliding (the
/// full bound, against the flow). Far above the rounding of a rope at rest (exactly 0) and far
/// below any speed the scenes reach.
const STICK_TOLERANCE: f64 = 1e-9;

impl Mechanism {
    /// The exact accelerations (m/s²) and rope tensions (N) at `state`: ropes that are taut and
    /// bodies that rest on the floor act; the rest are free. See [`Mechanism::instantaneous`].
    pub fn accelerations(&self, state: &State) -> Result<(Vec<f64>, Vec<f64>), SimulationError> {
        let solution = self.instantaneous(state)?;
        Ok((solution.accelerations, solution.tensions))
    }

    /// The exact instantaneous solution at `state`: ropes that are taut and bodies that rest on
    /// the floor act, the rest are free; a bearing whose rope flows over it resists with its
    /// full torque, one at rest holds with whatever torque up to it keeps it at rest (a boxed
    /// force, solved with the ropes and contacts as one complementarity problem).
    pub fn instantaneous(&self, state: &State) -> Result<Instantaneous, SimulationError> {
        self.now.set(state.time);
        let m = self.mass_matrix(&state.y);
        let force = self.forces();
        let free = Self::inverse_mass_times(&m, &force, "mass matrix")?;
        let all = self.constraints(&state.y, &state.v);
        let active: Vec<(usize, &Constraint)> = all
            .iter()
            .enumerate()
            .filter(|(_, c)| c.gap >= -TAUT_TOLERANCE)
            .collect();
        let frictions = self.friction_rows(&state.y);
        let drive_flow = self.drive_flow(&frictions, &state.y, state.time);
        let gradients: Vec<&[f64]> = active
            .iter()
            .map(|(_, c)| c.gradient.as_slice())
            .chain(frictions.iter().map(|row| row.gradient.as_slice()))
            .collect();
        let (a, columns) = Self::constraint_system(&m, &gradients)?;
        let mut q: Vec<f64> = active
            .iter()
            .map(|(_, c)| -(dot(&c.gradient, &free) + c.curvature))
            .collect();
        let mut lower = vec![0.0; q.len()];
        let mut upper = vec![f64::INFINITY; q.len()];
        for (row, drive) in frictions.iter().zip(&drive_flow) {
            let (rope, position, _, _) = self.passes[row.pass];
            let length = |heights: &[f64]| self.length_to(rope, position, heights);
            // u = the forward flow's acceleration, −(c·a + vᵀ ∇²ℓ v).
            let curvature = numeric_curvature(length, &state.y, &state.v);
            q.push(-(dot(&row.gradient, &free) + curvature));
            let forward = -(dot(&row.gradient, &state.v) + drive);
            if forward.abs() <= STICK_TOLERANCE {
                lower.push(-row.bound);
                upper.push(row.bound);
            } else {
                // Sliding: a known force against the flow (a one-point box).
                let resisting = -row.bound * forward.signum();
                lower.push(resisting);
                upper.push(resisting);
            }
        }
        let mut impulses = vec![0.0; q.len()];
        solve_boxed_lcp(&a, &q, &lower, &upper, &mut impulses);
        let mut acceleration = free;
        for (column, lambda) in columns.iter().zip(&impulses) {
            for (ai, ci) in acceleration.iter_mut().zip(column) {
                *ai -= ci * lambda;
            }
        }
        let mut tensions = vec![0.0; self.network.ropes.len()];
        for ((index, _), lambda) in active.iter().zip(&impulses) {
            if *index < tensions.len() {
                tensions[*index] = *lambda;
            }
        }
        let mut friction_torques = vec![0.0; self.network.pulleys.len()];
        let friction_forces = impulses.get(active.len()..).unwrap_or(&[]);
        self.add_friction_torques(&frictions, friction_forces, 1.0, &mut friction_torques);
        check_finite(state.time, "acceleration", &acceleration)?;
        check_finite(state.time, "tension", &tensions)?;
        check_finite(state.time, "friction torque", &friction_torques)?;
        Ok(Instantaneous {
            accelerations: acceleration,
            tensions,
            friction_torques,
        })
    }

    /// The instantaneous solve at an *observed* state, whose positions carry measurement
    /// error: a rope counts as taut, and a floor or segment stop as touching, within
    /// `tolerance` metres of its limit (the complementarity problem then decides whether it
    /// acts), and a rope slack beyond it leaves its pulleys' inertia out, as a rope that does
    /// not grip a pulley does not turn it. Also tells which bodies a stop pushes on.
    ///
    /// [`Mechanism::accelerations`] is the same solve at the simulator's own tolerance
    /// (1e-9 m) with every pulley's inertia in, as [`Mechanism::step`] integrates it.
    pub fn observed_accelerations(
        &self,
        state: &State,
        tolerance: f64,
    ) -> Result<Instant, SimulationError> {
        if !(tolerance.is_finite() && tolerance >= 0.0) {
            return Err(SimulationError::InvalidParameter {
                object: "observed state".to_string(),
                problem: format!("contact tolerance {tolerance} m must be non-negative"),
            });
        }
        check_finite(state.time, "observed height", &state.y)?;
        check_finite(state.time, "observed velocity", &state.v)?;
        if state.y.len() != self.network.bodies.len() || state.v.len() != state.y.len() {
            return Err(SimulationError::InvalidParameter {
                object: "observed state".to_string(),
                problem: format!(
                    "{} heights and {} velocities for {} bodies",
                    state.y.len(),
                    state.v.len(),
                    self.network.bodies.len()
                ),
            });
        }
        self.now.set(state.time);
        let taut: Vec<bool> = (0..self.network.ropes.len())
            .map(|rope| self.rope_length(rope, &state.y) - self.rest_lengths[rope] >= -tolerance)
            .collect();
        let m = self.mass_matrix_turning(&state.y, |rope| taut[rope]);
        let force = self.forces();
        let free = Self::inverse_mass_times(&m, &force, "mass matrix")?;
        let all = self.constraints(&state.y, &state.v);
        let active: Vec<(usize, Constraint)> = all
            .into_iter()
            .enumerate()
            .filter(|(_, c)| c.gap >= -tolerance)
            .collect();
        let chosen: Vec<Constraint> = active.iter().map(|(_, c)| c.clone()).collect();
        let gradients: Vec<&[f64]> = chosen.iter().map(|c| c.gradient.as_slice()).collect();
        let (a, columns) = Self::constraint_system(&m, &gradients)?;
        let q: Vec<f64> = chosen
            .iter()
            .map(|c| -(dot(&c.gradient, &free) + c.curvature))
            .collect();
        let mut forces = vec![0.0; chosen.len()];
        solve_lcp(&a, &q, &mut forces);
        check_finite(state.time, "constraint force", &forces)?;
        let mut accelerations = free;
        for (column, lambda) in columns.iter().zip(&forces) {
            for (ai, ci) in accelerations.iter_mut().zip(column) {
                *ai -= ci * lambda;
            }
        }
        check_finite(state.time, "acceleration", &accelerations)?;
        // A stop pushes when its force is more than rounding of the weights it holds.
        let weight: f64 = self.network.bodies.iter().map(|b| b.mass * GRAVITY).sum();
        let mut tensions = vec![0.0; self.network.ropes.len()];
        let mut stopped = vec![false; self.network.bodies.len()];
        for ((index, constraint), lambda) in active.iter().zip(&forces) {
            if *index < tensions.len() {
                tensions[*index] = *lambda;
            } else if *lambda > 1e-9 * weight {
                for (flag, gradient) in stopped.iter_mut().zip(&constraint.gradient) {
                    if gradient.abs() > 1e-12 {
                        *flag = true;
                    }
                }
            }
        }
        Ok(Instant {
            accelerations,
            tensions,
            stopped,
            taut,
        })
    }
}
