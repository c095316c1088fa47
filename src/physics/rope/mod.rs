//! Rope–pulley mechanics: planar networks of fixed points, static pulleys, movable pulleys and
//! loads joined by ideal inextensible ropes (`docs/data/rope.md`).
//!
//! Units are SI: metres, kilograms, seconds, newtons; `y` points up and [`GRAVITY`] pulls down.
//! Angles are radians, counter-clockwise positive as seen by the camera.
//!
//! **Model.** Every movable body (a load, or a movable pulley with what it carries) keeps its
//! `x` and moves along `y`. A rope is a path from one end (a fixed point, a body, or a pulley's
//! axle) over pulleys to the other end. A segment leaves a pulley at the rim point level with the
//! axle on the side of its other end (chosen once, from the start geometry), so a load hanging
//! under a rim hangs on a vertical segment, and a rope between pulleys of different columns runs
//! diagonally as in the scenes; the arcs round the pulleys are taken as constant (exact for
//! vertical segments, a small error for diagonal ones, whose wrap angle drifts slightly). A
//! rope only pulls: it is a unilateral constraint `L(y) ≤ L₀` whose tension is its impulse. Loads
//! stop on the floor, and a segment cannot shorten below the radii at its ends (a load that
//! reaches its pulley stops there). Pulley inertia enters through the kinetic energy of the
//! rope flowing over the pulley without slipping, `½ (I/R²) ṡ²`.
//!
//! **Bearing friction.** A pulley's bearing has a constant Coulomb torque τ
//! ([`Pulley::friction_torque`]). The rope flows over a pulley at `ṡ = −c·v` (`c` the gradient of
//! the rope length up to it), so the bearing acts on the bodies as a force `f` along `c`, bounded
//! by `|f| ≤ τ/R`: while the pulley is at rest it holds with whatever force up to τ/R keeps it at
//! rest (the tensions either side may differ by that much and nothing turns), and once the rope
//! flows it resists with exactly τ/R against the flow. Each pass of a rope over a pulley with τ > 0
//! adds one such row to the complementarity problem, a *boxed* variable (ropes and contacts are
//! `[0, ∞)`, a bearing `[−τ/R, τ/R]`), so sticking and slipping are found together with the
//! tensions. Ideal pulleys add no row, nor does a pass whose rope up to the pulley no body moves
//! (it comes from a fixed or driven point: only a driving hand would feel that bearing). A pulley
//! whose bearing holds does not turn. Like the inertia, the bearing acts on the rope's flow whether
//! the rope is taut or slack (the model keeps no separate slack on either side of a pulley), and
//! two ropes over one pulley each get the full bound. Energy is lost at `τ·|θ̇|` per pulley.
//!
//! **Integration.** Semi-implicit (symplectic) Euler on velocities with every constraint solved
//! as one linear complementarity problem per step ([`super::linalg::solve_boxed_lcp`]): taut
//! ropes, slack ropes that re-tighten (inelastically), floor contacts and segment stops are all
//! the same kind of constraint, and bearing friction is an impulse within `±(τ/R)·dt` on the
//! flow after the step. Position drift of taut ropes is removed in the next step (the
//! constraint targets `L(y + dt·v) = L₀`). [`Mechanism::instantaneous`] (and
//! [`Mechanism::accelerations`]) is the exact instantaneous solve (accelerations, tensions and
//! bearing torques) that the analytic tests check against closed forms; there a bearing whose
//! rope flows is a known force and one at rest a boxed force.
//!
//! Every step checks that positions, velocities and impulses are finite; a system that cannot
//! be simulated is a typed [`SimulationError`], never a NaN in an answer.
//!
//! **Identification.** [`identify`] runs the model backwards: from tracked heights to the load
//! masses that explain them, through [`Mechanism::observed_accelerations`].
//!
//! **Layout.** The description (`network`: bodies, pulleys, ropes, drives, errors), the checked
//! mechanism and its states (`mechanism`), the rope geometry (`geometry`: tangent contacts,
//! wraps, lengths, polylines), the dynamics' ingredients (`dynamics`: mass matrix, constraints,
//! bearing-friction rows, numeric derivatives), the instantaneous solves (`instantaneous`) and
//! the integrator (`step`).

pub mod bench;
mod dynamics;
mod geometry;
pub mod identify;
mod instantaneous;
mod mechanism;
mod network;
mod step;

pub use mechanism::{Instant, Instantaneous, Mechanism, State};
pub use network::{
    Body, Drive, DrivenPoint, Mount, Network, Point, Pulley, Rope, SimulationError, Turn,
};

/// Gravitational acceleration, m/s².
pub const GRAVITY: f64 = 9.81;

#[cfg(test)]
mod tests;
