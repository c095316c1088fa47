//! The integrator: one semi-implicit Euler step with every constraint and bearing solved as one
//! boxed complementarity problem ([`Mechanism::step`]), runs of many steps, and the energy the
//! tests check.

use super::super::linalg::solve_boxed_lcp;
use super::GRAVITY;
use super::dynamics::{check_finite, dot};
use super::mechanism::{Mechanism, State};
use super::network::SimulationError;

impl Mechanism {
    /// Advances `state` by `dt` seconds (semi-implicit Euler with one LCP per step).
    pub fn step(&self, state: &mut State, dt: f64) -> Result<(), SimulationError> {
        // Driven points are placed where they will be at the end of the step, so the rope
        // constraints ask the bodies to follow them within the step.
        let driven = !self.network.drives.is_empty();
        let flow_before: Vec<f64> = if driven {
            self.now.set(state.time);
            self.passes
                .iter()
                .map(|&(rope, position, _, _)| self.length_to(rope, position, &state.y))
                .collect()
        } else {
            Vec::new()
        };
        self.now.set(state.time + dt);
        let m = self.mass_matrix(&state.y);
        let force = self.forces();
        let free = Self::inverse_mass_times(&m, &force, "mass matrix")?;
        let predicted: Vec<f64> = state.v.iter().zip(&free).map(|(v, a)| v + dt * a).collect();
        let constraints = self.constraints(&state.y, &state.v);
        // Per pass, the rope a moving anchor or pulley pulls over the pulley in this step, as a
        // rate (m/s) of lengthening of the rope up to it; empty when nothing is driven.
        let drive_flow: Vec<f64> = self
            .passes
            .iter()
            .zip(&flow_before)
            .map(|(&(rope, position, _, _), before)| {
                (self.length_to(rope, position, &state.y) - before) / dt
            })
            .collect();
        let frictions = self.friction_rows(&state.y);
        let gradients: Vec<&[f64]> = constraints
            .iter()
            .map(|c| c.gradient.as_slice())
            .chain(frictions.iter().map(|row| row.gradient.as_slice()))
            .collect();
        let (a, columns) = Self::constraint_system(&m, &gradients)?;
        // Target: g(y + dt·v⁺) ≤ 0 to first order, i.e. J·v⁺ ≤ −g/dt.
        let mut q: Vec<f64> = constraints
            .iter()
            .map(|c| -(dot(&c.gradient, &predicted) + c.gap / dt))
            .collect();
        let mut lower = vec![0.0; q.len()];
        let mut upper = vec![f64::INFINITY; q.len()];
        // Bearing friction: u is the forward flow after the step, −(c·v⁺ + drive), and the
        // impulse stays within ±(τ/R)·dt: the pulley holds (u = 0) until holding it would take
        // more, then the rope slides over the bearing against exactly that impulse.
        for row in &frictions {
            let drive = drive_flow.get(row.pass).copied().unwrap_or(0.0);
            q.push(-(dot(&row.gradient, &predicted) + drive));
            lower.push(-row.bound * dt);
            upper.push(row.bound * dt);
        }
        let mut impulses = vec![0.0; q.len()];
        for (slot, tension) in impulses.iter_mut().zip(&state.tensions) {
            *slot = tension * dt;
        }
        solve_boxed_lcp(&a, &q, &lower, &upper, &mut impulses);
        check_finite(state.time, "rope impulse", &impulses)?;
        let mut velocity = predicted;
        for (column, lambda) in columns.iter().zip(&impulses) {
            for (vi, ci) in velocity.iter_mut().zip(column) {
                *vi -= ci * lambda;
            }
        }
        check_finite(state.time, "velocity", &velocity)?;
        let friction_impulses = impulses.get(constraints.len()..).unwrap_or(&[]);
        // A bearing whose impulse is strictly inside its bound holds: the complementarity
        // conditions make its flow zero, so its pulley does not turn (rather than turning by the
        // rounding residue of that zero).
        let mut holding = vec![false; self.passes.len()];
        for (row, lambda) in frictions.iter().zip(friction_impulses) {
            holding[row.pass] = lambda.abs() < row.bound * dt;
        }
        let mut friction_torques = vec![0.0; self.network.pulleys.len()];
        self.add_friction_torques(&frictions, friction_impulses, dt, &mut friction_torques);
        check_finite(state.time, "friction torque", &friction_torques)?;
        // Pulley angles turn with the rope flowing over them. The rope length from the rope's
        // start to the pulley grows when material flows back towards the start, so the forward
        // flow (start → end, the direction `sign` is taken in) is its rate of shrinking.
        for (pass, &(rope, position, pulley, sign)) in self.passes.iter().enumerate() {
            if holding[pass] {
                continue;
            }
            let mut forward = -dot(&self.flow_gradient(rope, position, &state.y), &velocity);
            if let Some(drive) = drive_flow.get(pass) {
                // The rope a moving anchor or pulley pulls over the pulley.
                forward -= drive;
            }
            let radius = self.network.pulleys[pulley].radius;
            state.angles[pulley] += dt * sign * forward / radius;
        }
        for (y, v) in state.y.iter_mut().zip(&velocity) {
            *y += dt * v;
        }
        check_finite(state.time, "position", &state.y)?;
        state.v = velocity;
        for (tension, lambda) in state.tensions.iter_mut().zip(&impulses) {
            *tension = lambda / dt;
        }
        state.friction_torques = friction_torques;
        state.time += dt;
        Ok(())
    }

    /// Kinetic plus potential energy, J (potential zero at `y = 0`).
    pub fn energy(&self, state: &State) -> f64 {
        let m = self.mass_matrix(&state.y);
        let kinetic = 0.5 * dot(&state.v, &m.mul_vec(&state.v));
        let potential: f64 = self
            .network
            .bodies
            .iter()
            .zip(&state.y)
            .map(|(b, y)| b.mass * GRAVITY * y)
            .sum();
        kinetic + potential
    }

    /// Simulates `duration` seconds at step `dt` from `state`.
    pub fn run(&self, state: &mut State, duration: f64, dt: f64) -> Result<(), SimulationError> {
        if !(dt.is_finite() && dt > 0.0 && duration.is_finite() && duration >= 0.0) {
            return Err(SimulationError::InvalidParameter {
                object: "simulation".to_string(),
                problem: format!("dt {dt} s and duration {duration} s must be positive"),
            });
        }
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a positive step count, checked finite above"
        )]
        let steps = (duration / dt).round() as u64;
        for _ in 0..steps {
            self.step(state, dt)?;
        }
        Ok(())
    }
}
