//! Rope–pulley mechanics: planar networks of fixed points, static pulleys, movable pulleys and
//! loads joined by ideal inextensible ropes (FORMAT.md §2).
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

use super::linalg::{Matrix, solve, solve_boxed_lcp, solve_lcp};

pub mod identify;

/// Gravitational acceleration, m/s².
pub const GRAVITY: f64 = 9.81;

/// At the start, a pass wrapped more than a full turn less this (rad) is read as the rope
/// leaving the pulley (bent slightly the other way), not as wrapped nearly all the way round.
const LEAVING_ANGLE: f64 = 0.5;

/// Rope length (m) by which a rope counts as taut in the instantaneous solve.
const TAUT_TOLERANCE: f64 = 1e-9;

/// Rope speed over a pulley (m/s) below which its bearing counts as holding in the
/// instantaneous solve (static friction, a force anywhere in its bound) rather than sliding (the
/// full bound, against the flow). Far above the rounding of a rope at rest (exactly 0) and far
/// below any speed the scenes reach.
const STICK_TOLERANCE: f64 = 1e-9;

/// Time step (s) of the difference that gives the rope flow a driven point causes in the
/// instantaneous solve. Drives move linearly, so the difference is exact away from a drive's
/// start and end; its rounding is about `eps · L / h`, 1e-10 m/s for ropes of tens of metres.
const DRIVE_PROBE: f64 = 1e-4;

/// A movable body: a load, or a movable pulley's frame (its pulley is a [`Pulley`] mounted on
/// it).
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// The scene name (`Purple Cube`).
    pub name: String,
    /// Mass, kg.
    pub mass: f64,
    /// Start position `(x, y)`, m.
    pub position: [f64; 2],
    /// Distance from the body's centre down to its bottom, m, when it can rest on the floor.
    pub floor_clearance: Option<f64>,
}

/// Where a pulley's axle is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mount {
    /// A static pulley at `(x, y)`, m.
    Fixed([f64; 2]),
    /// A movable pulley: the axle moves with this body.
    Body(usize),
}

/// A pulley.
#[derive(Debug, Clone, PartialEq)]
pub struct Pulley {
    /// The scene name.
    pub name: String,
    /// Radius, m.
    pub radius: f64,
    /// Moment of inertia about the axle, kg·m² (0 for an ideal pulley).
    pub inertia: f64,
    /// Coulomb friction torque of the bearing, N·m (0 for an ideal pulley): the pulley does
    /// not turn while the rope tensions either side differ by less than `friction_torque / R`,
    /// and while it turns the bearing resists with exactly this torque.
    pub friction_torque: f64,
    /// Where the axle is.
    pub mount: Mount,
}

/// A point of a rope's path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Point {
    /// A fixed point at `(x, y)`, m (ceiling or floor anchor).
    Fixed([f64; 2]),
    /// Tied to a body.
    Body(usize),
    /// Over a pulley (inside the path), or tied to its axle (at an end).
    Pulley(usize),
}

/// A rope: a path of at least two points; the points inside are pulleys.
#[derive(Debug, Clone, PartialEq)]
pub struct Rope {
    /// The scene name.
    pub name: String,
    /// End, pulleys, end.
    pub path: Vec<Point>,
}

/// A whole mechanism as described: bodies, pulleys, ropes and an optional floor height (m).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Network {
    /// Movable bodies.
    pub bodies: Vec<Body>,
    /// Pulleys.
    pub pulleys: Vec<Pulley>,
    /// Ropes.
    pub ropes: Vec<Rope>,
    /// Floor height, m.
    pub floor: Option<f64>,
    /// How ropes turn round pulleys, where the start geometry does not tell (a rope coming
    /// down from a pulley straight above and leaving on one side): `(rope, path position,
    /// turn)`. Passes not listed are inferred from the centres.
    pub turns: Vec<(usize, usize, Turn)>,
    /// Static pulleys and fixed points moved by a hand (the pull counterfactuals).
    pub drives: Vec<Drive>,
}

/// A static pulley or fixed point moved vertically at a constant speed for a distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    /// What moves.
    pub point: DrivenPoint,
    /// Vertical speed, m/s (+ up).
    pub velocity: f64,
    /// When it starts, s.
    pub start: f64,
    /// How far it goes, m.
    pub distance: f64,
}

/// The target of a [`Drive`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DrivenPoint {
    /// A static pulley (by index).
    Pulley(usize),
    /// Every fixed rope point at exactly this position.
    Fixed([f64; 2]),
}

impl Drive {
    /// Vertical displacement at time `t`, m.
    pub fn displacement(&self, t: f64) -> f64 {
        let travelled = (self.velocity.abs() * (t - self.start).max(0.0)).min(self.distance);
        travelled * self.velocity.signum()
    }
}

/// Which way a rope's path turns round a pulley; a pulley the path turns counter-clockwise
/// round also turns counter-clockwise when the rope flows forward (start → end).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Turn {
    /// The pulley is on the path's left.
    CounterClockwise,
    /// The pulley is on the path's right.
    Clockwise,
}

impl Turn {
    /// +1 counter-clockwise, −1 clockwise.
    pub fn sign(self) -> f64 {
        match self {
            Turn::CounterClockwise => 1.0,
            Turn::Clockwise => -1.0,
        }
    }

    /// The same wrap travelled the other way along the rope.
    #[must_use]
    pub fn reversed(self) -> Turn {
        match self {
            Turn::CounterClockwise => Turn::Clockwise,
            Turn::Clockwise => Turn::CounterClockwise,
        }
    }
}

/// Why a mechanism cannot be simulated.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum SimulationError {
    /// A parameter is out of range or not finite.
    #[error("{object}: {problem}")]
    InvalidParameter {
        /// The body, pulley or rope.
        object: String,
        /// What is wrong.
        problem: String,
    },
    /// A rope segment has no length, so its direction (and the force it transmits) is undefined.
    #[error("rope `{rope}`: segment {segment} has zero length; its direction is undefined")]
    DegenerateSegment {
        /// The rope.
        rope: String,
        /// Index of the segment along the path.
        segment: usize,
    },
    /// The mass matrix or a constraint system is singular.
    #[error("the mechanism's equations are singular ({context})")]
    Singular {
        /// Where.
        context: String,
    },
    /// A value stopped being finite.
    #[error("the simulation diverged at t = {time} s ({what} is not finite)")]
    NonFinite {
        /// Simulated time, s.
        time: f64,
        /// What.
        what: String,
    },
}

/// The state of a mechanism at one time.
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Time, s.
    pub time: f64,
    /// Body heights, m.
    pub y: Vec<f64>,
    /// Body vertical velocities, m/s.
    pub v: Vec<f64>,
    /// Pulley angles from the start, rad (counter-clockwise positive).
    pub angles: Vec<f64>,
    /// Rope tensions of the last step, N: the tension of each rope's last segment (with pulley
    /// inertia or bearing friction, the segments either side of a pulley differ by
    /// `(I·α + bearing torque)/R`, α its angular acceleration).
    pub tensions: Vec<f64>,
    /// Bearing friction torque on each pulley in the last step, N·m, counter-clockwise positive
    /// (it opposes the pulley's turning; 0 for ideal pulleys).
    pub friction_torques: Vec<f64>,
}

/// The instantaneous solution at one state ([`Mechanism::instantaneous`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Instantaneous {
    /// Body vertical accelerations, m/s².
    pub accelerations: Vec<f64>,
    /// Rope tensions, N: the tension of each rope's last segment, 0 for a slack rope.
    pub tensions: Vec<f64>,
    /// Bearing friction torque on each pulley, N·m, counter-clockwise positive: the full
    /// `friction_torque` against the turning of a pulley that turns, whatever holds a pulley
    /// at rest (at most `friction_torque`) otherwise.
    pub friction_torques: Vec<f64>,
}

/// The instantaneous solve at an observed state ([`Mechanism::observed_accelerations`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Instant {
    /// Body vertical accelerations, m/s².
    pub accelerations: Vec<f64>,
    /// Rope tensions, N (each rope's last segment, as in [`State::tensions`]; 0 when slack).
    pub tensions: Vec<f64>,
    /// Per body: a floor or segment stop pushes on it (it rests against the stop).
    pub stopped: Vec<bool>,
    /// Per rope: taut within the tolerance (a slack rope neither pulls nor turns its pulleys).
    pub taut: Vec<bool>,
}

/// One unilateral constraint `g(y) ≤ 0` with gradient `J`.
#[derive(Clone)]
struct Constraint {
    gap: f64,
    gradient: Vec<f64>,
    /// Velocity-product term of `g̈` (`J̇·v`), for the instantaneous solve.
    curvature: f64,
}

/// One bearing-friction row: a pass of a rope over a pulley whose bearing resists the flow.
struct FrictionRow {
    /// Index into [`Mechanism::passes`].
    pass: usize,
    /// Gradient of the rope length up to the pulley, dimensionless (the rope flows forward over
    /// the pulley at `−gradient · v`, m/s).
    gradient: Vec<f64>,
    /// The largest friction force at the rim, N: `friction_torque / R`.
    bound: f64,
}

/// A checked network, ready to simulate.
#[derive(Debug, Clone)]
pub struct Mechanism {
    network: Network,
    /// Rest lengths of the ropes, m (their lengths at the start).
    rest_lengths: Vec<f64>,
    /// Per pulley pass: (rope, index in path, pulley, wrap sign: +1 counter-clockwise).
    passes: Vec<(usize, usize, usize, f64)>,
    /// Per rope, per path point: how the path turns round it (+1 counter-clockwise, −1
    /// clockwise, 0 for ends and straight vertical passes).
    turns: Vec<Vec<f64>>,
    /// Per rope, per path point: the wrap angle at the start (rad, 0 for ends), the branch every
    /// later wrap angle is read on (see [`Mechanism::wrap_angle`]).
    wraps: Vec<Vec<f64>>,
    /// Per rope, the bodies that move it.
    rope_bodies: Vec<Vec<usize>>,
    /// The time driven points are placed at, s.
    now: std::cell::Cell<f64>,
}

impl Mechanism {
    /// Checks `network` and takes the ropes' start lengths as their lengths.
    pub fn new(network: Network) -> Result<Mechanism, SimulationError> {
        let invalid = |object: &str, problem: String| SimulationError::InvalidParameter {
            object: object.to_string(),
            problem,
        };
        for body in &network.bodies {
            if !(body.mass.is_finite() && body.mass > 0.0) {
                return Err(invalid(
                    &body.name,
                    format!("mass {} kg must be positive", body.mass),
                ));
            }
            if !body.position.iter().all(|c| c.is_finite()) {
                return Err(invalid(&body.name, "position is not finite".to_string()));
            }
        }
        for pulley in &network.pulleys {
            if !(pulley.radius.is_finite() && pulley.radius > 0.0) {
                return Err(invalid(
                    &pulley.name,
                    format!("radius {} m must be positive", pulley.radius),
                ));
            }
            if !(pulley.inertia.is_finite() && pulley.inertia >= 0.0) {
                return Err(invalid(
                    &pulley.name,
                    format!("inertia {} must be non-negative", pulley.inertia),
                ));
            }
            if !(pulley.friction_torque.is_finite() && pulley.friction_torque >= 0.0) {
                return Err(invalid(
                    &pulley.name,
                    format!(
                        "friction torque {} N·m must be non-negative",
                        pulley.friction_torque
                    ),
                ));
            }
            if let Mount::Body(index) = pulley.mount
                && index >= network.bodies.len()
            {
                return Err(invalid(
                    &pulley.name,
                    format!("mounted on body {index}, which does not exist"),
                ));
            }
        }
        let mut passes = Vec::new();
        let mut rest_lengths = Vec::new();
        let start: Vec<f64> = network.bodies.iter().map(|b| b.position[1]).collect();
        let mut mechanism = Mechanism {
            network,
            rest_lengths: Vec::new(),
            passes: Vec::new(),
            turns: Vec::new(),
            wraps: Vec::new(),
            rope_bodies: Vec::new(),
            now: std::cell::Cell::new(0.0),
        };
        let ropes = mechanism.network.ropes.clone();
        for (rope_index, rope) in ropes.iter().enumerate() {
            if rope.path.len() < 2 {
                return Err(invalid(&rope.name, "a rope needs two ends".to_string()));
            }
            for (position, point) in rope.path.iter().enumerate() {
                let inside = position > 0 && position + 1 < rope.path.len();
                match point {
                    Point::Body(index) if *index >= mechanism.network.bodies.len() => {
                        return Err(invalid(&rope.name, format!("body {index} does not exist")));
                    }
                    Point::Pulley(index) if *index >= mechanism.network.pulleys.len() => {
                        return Err(invalid(
                            &rope.name,
                            format!("pulley {index} does not exist"),
                        ));
                    }
                    Point::Fixed(p) if !p.iter().all(|c| c.is_finite()) => {
                        return Err(invalid(
                            &rope.name,
                            "a fixed point is not finite".to_string(),
                        ));
                    }
                    Point::Pulley(_) => {}
                    _ if inside => {
                        return Err(invalid(
                            &rope.name,
                            format!("point {position} is inside the path but not a pulley"),
                        ));
                    }
                    _ => {}
                }
            }
            let mut turns = vec![0.0; rope.path.len()];
            for (position, turn) in turns
                .iter_mut()
                .enumerate()
                .take(rope.path.len() - 1)
                .skip(1)
            {
                if let Point::Pulley(pulley) = rope.path[position] {
                    let given = mechanism
                        .network
                        .turns
                        .iter()
                        .find(|(r, p, _)| *r == rope_index && *p == position)
                        .map(|(_, _, turn)| turn.sign());
                    let sign = given.unwrap_or_else(|| {
                        let before = mechanism.point_position(rope.path[position - 1], &start);
                        let at = mechanism.point_position(rope.path[position], &start);
                        let after = mechanism.point_position(rope.path[position + 1], &start);
                        inferred_turn(before, at, after)
                    });
                    *turn = sign;
                    passes.push((rope_index, position, pulley, sign));
                }
            }
            mechanism.turns.push(turns);
            let bodies = mechanism.bodies_of(rope_index);
            mechanism.rope_bodies.push(bodies);
            mechanism.check_tangents(rope_index, &start)?;
            let contacts = mechanism.contacts(rope_index, &start);
            for (segment, (a, b)) in contacts.iter().enumerate() {
                if (a[0] - b[0]).hypot(a[1] - b[1]) < 1e-9 {
                    return Err(SimulationError::DegenerateSegment {
                        rope: rope.name.clone(),
                        segment,
                    });
                }
            }
            // The start's wrap angles: a pass the path bends slightly the other way round (or
            // that rounding puts just under a full turn) is a rope leaving the pulley, not one
            // wrapped all the way round it.
            let wraps: Vec<f64> = (0..rope.path.len())
                .map(|position| {
                    let raw = mechanism.raw_wrap(rope_index, position, &contacts, &start);
                    if raw > std::f64::consts::TAU - LEAVING_ANGLE {
                        0.0
                    } else {
                        raw
                    }
                })
                .collect();
            mechanism.wraps.push(wraps);
        }
        for rope_index in 0..mechanism.network.ropes.len() {
            rest_lengths.push(mechanism.rope_length(rope_index, &start));
        }
        mechanism.rest_lengths = rest_lengths;
        mechanism.passes = passes;
        Ok(mechanism)
    }

    /// The described network.
    pub fn network(&self) -> &Network {
        &self.network
    }

    /// Rest lengths of the ropes, m.
    pub fn rest_lengths(&self) -> &[f64] {
        &self.rest_lengths
    }

    /// The state at rest at the described positions.
    pub fn initial_state(&self) -> State {
        State {
            time: 0.0,
            y: self.network.bodies.iter().map(|b| b.position[1]).collect(),
            v: vec![0.0; self.network.bodies.len()],
            angles: vec![0.0; self.network.pulleys.len()],
            tensions: vec![0.0; self.network.ropes.len()],
            friction_torques: vec![0.0; self.network.pulleys.len()],
        }
    }

    /// Where a path point is in `state` (m): a pulley's axle, a body's centre, a fixed point
    /// (moved by its drive, if any).
    pub fn position_of(&self, point: Point, state: &State) -> [f64; 2] {
        self.now.set(state.time);
        self.point_position(point, &state.y)
    }

    /// The rope's centre line in `state` as a polyline (m), from its first end to its last: the
    /// straight segments between rim tangent points and the arcs round the pulleys, sampled so
    /// that no arc step is longer than `arc_step` metres. Ends are the path's end points.
    pub fn rope_polyline(&self, rope: usize, state: &State, arc_step: f64) -> Vec<[f64; 2]> {
        self.now.set(state.time);
        let Some(path) = self.network.ropes.get(rope).map(|r| &r.path) else {
            return Vec::new();
        };
        let contacts = self.contacts(rope, &state.y);
        let mut points = Vec::new();
        for (segment, (from, to)) in contacts.iter().enumerate() {
            if segment == 0 {
                points.push(*from);
            } else {
                // The arc round the pulley between the previous segment's end and this start.
                let position = segment;
                let turn = self.turns[rope][position];
                if let (Point::Pulley(index), true) = (path[position], turn != 0.0) {
                    let centre = self.point_position(path[position], &state.y);
                    let radius = self.network.pulleys[index].radius;
                    let arrive = contacts[position - 1].1;
                    let from_angle = (arrive[1] - centre[1]).atan2(arrive[0] - centre[0]);
                    let sweep = self.wrap_angle(rope, position, &contacts, &state.y);
                    let step = arc_step.max(1e-3);
                    #[expect(
                        clippy::cast_possible_truncation,
                        clippy::cast_sign_loss,
                        reason = "a small positive count: an arc of at most 2π·R over a positive step"
                    )]
                    let count = ((sweep * radius / step).ceil() as usize).max(1);
                    for k in 1..count {
                        let angle = from_angle + turn * sweep * k as f64 / count as f64;
                        points.push([
                            centre[0] + radius * angle.cos(),
                            centre[1] + radius * angle.sin(),
                        ]);
                    }
                }
                points.push(*from);
            }
            points.push(*to);
        }
        points.dedup_by(|a, b| (a[0] - b[0]).hypot(a[1] - b[1]) < 1e-12);
        points
    }

    fn point_position(&self, point: Point, y: &[f64]) -> [f64; 2] {
        match point {
            Point::Fixed(p) => self.driven(p, |target| target == DrivenPoint::Fixed(p)),
            Point::Body(index) => [self.network.bodies[index].position[0], y[index]],
            Point::Pulley(index) => match self.network.pulleys[index].mount {
                Mount::Fixed(p) => self.driven(p, |target| target == DrivenPoint::Pulley(index)),
                Mount::Body(body) => [self.network.bodies[body].position[0], y[body]],
            },
        }
    }

    /// `at`, moved by the drive whose target matches, at the current time.
    fn driven(&self, at: [f64; 2], matches: impl Fn(DrivenPoint) -> bool) -> [f64; 2] {
        let now = self.now.get();
        let lift: f64 = self
            .network
            .drives
            .iter()
            .filter(|drive| matches(drive.point))
            .map(|drive| drive.displacement(now))
            .sum();
        [at[0], at[1] + lift]
    }

    /// The contact points of every segment of `rope` at heights `y`.
    fn contacts(&self, rope: usize, y: &[f64]) -> Vec<([f64; 2], [f64; 2])> {
        (0..self.network.ropes[rope].path.len() - 1)
            .map(|segment| self.segment_contacts(rope, segment, y))
            .collect()
    }

    /// Where segment `segment` of `rope` leaves its first end and meets its second: at a
    /// pulley the rope is tangent to the rim, on the side its turn puts it (a counter-clockwise
    /// turn keeps the pulley on the path's left, so the rope runs on its right).
    ///
    /// Closed form: with signed offsets `s = −turn·R` (0 for points) along the line's left
    /// normal `n`, the contacts are `c + s·n`, and `n ⟂ (c_b − c_a + (s_b − s_a) n)` gives
    /// `n = α·D̂ + √(1−α²)·left(D̂)` with `α = (s_a − s_b)/|D|`.
    fn segment_contacts(&self, rope: usize, segment: usize, y: &[f64]) -> ([f64; 2], [f64; 2]) {
        let path = &self.network.ropes[rope].path;
        let turns = &self.turns[rope];
        let offset = |position: usize| match path[position] {
            Point::Pulley(index) => -turns[position] * self.network.pulleys[index].radius,
            _ => 0.0,
        };
        let a = self.point_position(path[segment], y);
        let b = self.point_position(path[segment + 1], y);
        let (sa, sb) = (offset(segment), offset(segment + 1));
        let d = [b[0] - a[0], b[1] - a[1]];
        let distance = d[0].hypot(d[1]);
        if distance <= 0.0 || (sa == 0.0 && sb == 0.0) {
            return (a, b);
        }
        let unit = [d[0] / distance, d[1] / distance];
        let left = [-unit[1], unit[0]];
        let alpha = ((sa - sb) / distance).clamp(-1.0, 1.0);
        let beta = (1.0 - alpha * alpha).sqrt();
        let normal = [
            alpha * unit[0] + beta * left[0],
            alpha * unit[1] + beta * left[1],
        ];
        (
            [a[0] + sa * normal[0], a[1] + sa * normal[1]],
            [b[0] + sb * normal[0], b[1] + sb * normal[1]],
        )
    }

    /// Fails when a segment has no tangent: an end on or inside the pulley it wraps, or two
    /// pulleys too close for the rope to pass between them (opposite turns: the rope crosses
    /// between the rims) or round them (same turn).
    fn check_tangents(&self, rope: usize, y: &[f64]) -> Result<(), SimulationError> {
        let path = &self.network.ropes[rope].path;
        let turns = &self.turns[rope];
        let wrapped = |position: usize| match path[position] {
            Point::Pulley(index) if turns[position] != 0.0 => {
                self.network.pulleys[index].radius * turns[position]
            }
            _ => 0.0,
        };
        for segment in 0..path.len() - 1 {
            let a = self.point_position(path[segment], y);
            let b = self.point_position(path[segment + 1], y);
            let distance = (a[0] - b[0]).hypot(a[1] - b[1]);
            // Signed radii: a tangent exists when the centres are further apart than the
            // difference of the signed radii (their sum for opposite turns).
            let needed = (wrapped(segment) - wrapped(segment + 1)).abs();
            if distance <= needed + 1e-9 {
                return Err(SimulationError::DegenerateSegment {
                    rope: self.network.ropes[rope].name.clone(),
                    segment,
                });
            }
        }
        Ok(())
    }

    /// The angle (rad, in `[0, 2π)`) from where the rope arrives at path point `position` to
    /// where it leaves, in the turn's direction, as the geometry gives it; 0 for ends and
    /// straight passes.
    fn raw_wrap(
        &self,
        rope: usize,
        position: usize,
        contacts: &[([f64; 2], [f64; 2])],
        y: &[f64],
    ) -> f64 {
        let path = &self.network.ropes[rope].path;
        let turn = self.turns[rope][position];
        if !matches!(path[position], Point::Pulley(_))
            || turn == 0.0
            || position == 0
            || position + 1 >= path.len()
        {
            return 0.0;
        }
        let centre = self.point_position(path[position], y);
        let arrive = contacts[position - 1].1;
        let leave = contacts[position].0;
        let from = (arrive[1] - centre[1]).atan2(arrive[0] - centre[0]);
        let to = (leave[1] - centre[1]).atan2(leave[0] - centre[0]);
        (turn * (to - from)).rem_euclid(std::f64::consts::TAU)
    }

    /// The wrap angle round path point `position` (rad): the geometric angle read on the branch
    /// nearest the start's wrap, so it changes continuously as bodies move (a rope wrapped
    /// 300° stays 300°, a straight pass stays near 0 instead of jumping to a full turn), and
    /// never negative: a rope bending the other way at a pass has left the pulley.
    fn wrap_angle(
        &self,
        rope: usize,
        position: usize,
        contacts: &[([f64; 2], [f64; 2])],
        y: &[f64],
    ) -> f64 {
        let raw = self.raw_wrap(rope, position, contacts, y);
        let reference = self
            .wraps
            .get(rope)
            .and_then(|w| w.get(position))
            .copied()
            .unwrap_or(raw);
        let turns = ((reference - raw) / std::f64::consts::TAU).round();
        (raw + std::f64::consts::TAU * turns).max(0.0)
    }

    /// The rope wrapped round path point `position` (m): radius × its wrap angle.
    fn arc(
        &self,
        rope: usize,
        position: usize,
        contacts: &[([f64; 2], [f64; 2])],
        y: &[f64],
    ) -> f64 {
        let Point::Pulley(index) = self.network.ropes[rope].path[position] else {
            return 0.0;
        };
        self.network.pulleys[index].radius * self.wrap_angle(rope, position, contacts, y)
    }

    /// How close the two ends of a segment may come (m): a pulley's radius, a body's clearance.
    fn clearance(&self, point: Point) -> f64 {
        match point {
            Point::Pulley(index) => self.network.pulleys[index].radius,
            Point::Body(index) => self.network.bodies[index].floor_clearance.unwrap_or(0.0),
            Point::Fixed(_) => 0.0,
        }
    }

    /// Length of segment `segment` of `rope` at heights `y`, m.
    fn segment_length(&self, rope: usize, segment: usize, y: &[f64]) -> f64 {
        let (a, b) = self.segment_contacts(rope, segment, y);
        (a[0] - b[0]).hypot(a[1] - b[1])
    }

    /// A rope's current length: straight segments plus the arcs round its pulleys, m.
    pub fn rope_length(&self, rope: usize, y: &[f64]) -> f64 {
        self.length_to(rope, self.network.ropes[rope].path.len() - 1, y)
    }

    /// The rope length from the rope's start to where it arrives at path point `position`, m.
    fn length_to(&self, rope: usize, position: usize, y: &[f64]) -> f64 {
        let contacts = self.contacts(rope, y);
        let straight: f64 = contacts[..position]
            .iter()
            .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
            .sum();
        let arcs: f64 = (1..position).map(|p| self.arc(rope, p, &contacts, y)).sum();
        straight + arcs
    }

    /// The gradient over body heights of the rope length up to path point `position` (the
    /// rope flows back over that pulley at `gradient · v`).
    fn flow_gradient(&self, rope: usize, position: usize, y: &[f64]) -> Vec<f64> {
        numeric_gradient(
            |heights| self.length_to(rope, position, heights),
            y,
            &self.rope_bodies[rope],
        )
    }

    /// The bodies whose heights move a rope's points (loads tied to it, movable pulleys on it).
    fn bodies_of(&self, rope: usize) -> Vec<usize> {
        let mut bodies: Vec<usize> = self.network.ropes[rope]
            .path
            .iter()
            .filter_map(|point| match *point {
                Point::Body(index) => Some(index),
                Point::Pulley(index) => match self.network.pulleys[index].mount {
                    Mount::Body(body) => Some(body),
                    Mount::Fixed(_) => None,
                },
                Point::Fixed(_) => None,
            })
            .collect();
        bodies.sort_unstable();
        bodies.dedup();
        bodies
    }

    /// The mass matrix at `y`: body masses plus the pulleys' rotational inertia.
    fn mass_matrix(&self, heights: &[f64]) -> Matrix {
        self.mass_matrix_turning(heights, |_| true)
    }

    /// The mass matrix at `y` with the inertia of the pulleys that the ropes `turning(rope)`
    /// pass over (a slack rope does not turn its pulleys, so they add nothing to its bodies).
    fn mass_matrix_turning(&self, heights: &[f64], turning: impl Fn(usize) -> bool) -> Matrix {
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
    fn forces(&self) -> Vec<f64> {
        self.network
            .bodies
            .iter()
            .map(|b| -b.mass * GRAVITY)
            .collect()
    }

    /// Every unilateral constraint at `(y, v)`: ropes first (one per rope, in order), then floor
    /// contacts, then segment stops.
    fn constraints(&self, heights: &[f64], velocities: &[f64]) -> Vec<Constraint> {
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
    fn inverse_mass_times(
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
    fn constraint_system(
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
    fn friction_rows(&self, heights: &[f64]) -> Vec<FrictionRow> {
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
    fn drive_flow(&self, rows: &[FrictionRow], heights: &[f64], time: f64) -> Vec<f64> {
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
    fn add_friction_torques(
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

/// How the path turns at `at` coming from `before` and going to `after`: +1 counter-clockwise,
/// −1 clockwise. A straight horizontal pass rests on the top (a rope under gravity), so flow to
/// +x turns it clockwise; a straight vertical pass does not touch the pulley (0).
fn inferred_turn(before: [f64; 2], at: [f64; 2], after: [f64; 2]) -> f64 {
    let incoming = [at[0] - before[0], at[1] - before[1]];
    let outgoing = [after[0] - at[0], after[1] - at[1]];
    let cross = incoming[0] * outgoing[1] - incoming[1] * outgoing[0];
    if cross.abs() > 1e-12 {
        cross.signum()
    } else if (after[0] - before[0]).abs() > 1e-12 {
        -(after[0] - before[0]).signum()
    } else {
        0.0
    }
}

/// Step of the differences, m. The five-point stencil's truncation error is O(h⁴) (1e-12 of
/// the fifth derivative) and its rounding error about `eps · L / h` (1e-11 for ropes of tens
/// of metres); for vertical segments the length is linear and the result exact to rounding.
const DIFFERENCE_STEP: f64 = 1e-3;

/// `∂f/∂yᵢ` by five-point central differences, for the `involved` heights (the others are 0).
fn numeric_gradient(f: impl Fn(&[f64]) -> f64, y: &[f64], involved: &[usize]) -> Vec<f64> {
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
fn numeric_curvature(f: impl Fn(&[f64]) -> f64, y: &[f64], v: &[f64]) -> f64 {
    let speed = v.iter().fold(0.0_f64, |acc, x| acc.max(x.abs()));
    if speed == 0.0 {
        return 0.0;
    }
    let step = 1e-4 / speed;
    let along =
        |sign: f64| -> Vec<f64> { y.iter().zip(v).map(|(a, b)| a + sign * step * b).collect() };
    (f(&along(1.0)) - 2.0 * f(y) + f(&along(-1.0))) / (step * step)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn check_finite(time: f64, what: &str, values: &[f64]) -> Result<(), SimulationError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(SimulationError::NonFinite {
            time,
            what: what.to_string(),
        })
    }
}

#[cfg(test)]
mod tests;
