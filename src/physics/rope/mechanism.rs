//! The checked mechanism ([`Mechanism`]) and what it computes: a state ([`State`]), the
//! instantaneous solutions ([`Instantaneous`], [`Instant`]). [`Mechanism::new`] checks the
//! description and fixes, from the start geometry, how every rope turns round its pulleys, the
//! start wraps and the rest lengths.

use super::geometry::inferred_turn;
use super::network::{Mount, Network, Point, Rope, SimulationError};

/// At the start, a pass wrapped more than a full turn less this (rad) is read as the rope
/// leaving the pulley (bent slightly the other way), not as wrapped nearly all the way round.
const LEAVING_ANGLE: f64 = 0.5;

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

/// A checked network, ready to simulate.
#[derive(Debug, Clone)]
pub struct Mechanism {
    /// The described network.
    pub(super) network: Network,
    /// Rest lengths of the ropes, m (their lengths at the start).
    pub(super) rest_lengths: Vec<f64>,
    /// Per pulley pass: (rope, index in path, pulley, wrap sign: +1 counter-clockwise).
    pub(super) passes: Vec<(usize, usize, usize, f64)>,
    /// Per rope, per path point: how the path turns round it (+1 counter-clockwise, −1
    /// clockwise, 0 for ends and straight vertical passes).
    pub(super) turns: Vec<Vec<f64>>,
    /// Per rope, per path point: the wrap angle at the start (rad, 0 for ends), the branch every
    /// later wrap angle is read on (see [`Mechanism::wrap_angle`]).
    pub(super) wraps: Vec<Vec<f64>>,
    /// Per rope, the bodies that move it.
    pub(super) rope_bodies: Vec<Vec<usize>>,
    /// The time driven points are placed at, s.
    pub(super) now: std::cell::Cell<f64>,
}

impl Mechanism {
    /// Checks `network` and takes the ropes' start lengths as their lengths.
    pub fn new(network: Network) -> Result<Mechanism, SimulationError> {
        check_parameters(&network)?;
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
            mechanism.check_path(rope)?;
            let turns = mechanism.path_turns(rope_index, rope, &start, &mut passes);
            mechanism.turns.push(turns);
            let bodies = mechanism.bodies_of(rope_index);
            mechanism.rope_bodies.push(bodies);
            mechanism.check_tangents(rope_index, &start)?;
            let wraps = mechanism.start_wraps(rope_index, rope, &start)?;
            mechanism.wraps.push(wraps);
        }
        for rope_index in 0..mechanism.network.ropes.len() {
            rest_lengths.push(mechanism.rope_length(rope_index, &start));
        }
        mechanism.rest_lengths = rest_lengths;
        mechanism.passes = passes;
        Ok(mechanism)
    }

    /// Fails unless `rope` has two ends, its points name bodies and pulleys that exist, its fixed
    /// points are finite, and every point inside its path is a pulley.
    fn check_path(&self, rope: &Rope) -> Result<(), SimulationError> {
        if rope.path.len() < 2 {
            return Err(invalid(&rope.name, "a rope needs two ends".to_string()));
        }
        for (position, point) in rope.path.iter().enumerate() {
            let inside = position > 0 && position + 1 < rope.path.len();
            match point {
                Point::Body(index) if *index >= self.network.bodies.len() => {
                    return Err(invalid(&rope.name, format!("body {index} does not exist")));
                }
                Point::Pulley(index) if *index >= self.network.pulleys.len() => {
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
        Ok(())
    }

    /// How rope `rope_index` turns round each point of its path (+1 counter-clockwise, −1
    /// clockwise, 0 for ends and straight passes): as the network gives it, else as the start
    /// heights `start` show it. Appends each pulley pass to `passes`.
    fn path_turns(
        &self,
        rope_index: usize,
        rope: &Rope,
        start: &[f64],
        passes: &mut Vec<(usize, usize, usize, f64)>,
    ) -> Vec<f64> {
        let mut turns = vec![0.0; rope.path.len()];
        for (position, turn) in turns
            .iter_mut()
            .enumerate()
            .take(rope.path.len() - 1)
            .skip(1)
        {
            if let Point::Pulley(pulley) = rope.path[position] {
                let given = self
                    .network
                    .turns
                    .iter()
                    .find(|(r, p, _)| *r == rope_index && *p == position)
                    .map(|(_, _, turn)| turn.sign());
                let sign = given.unwrap_or_else(|| {
                    let before = self.point_position(rope.path[position - 1], start);
                    let at = self.point_position(rope.path[position], start);
                    let after = self.point_position(rope.path[position + 1], start);
                    inferred_turn(before, at, after)
                });
                *turn = sign;
                passes.push((rope_index, position, pulley, sign));
            }
        }
        turns
    }

    /// The wrap angles of rope `rope_index` at the start heights `start`, one per path point;
    /// fails when a segment has no length.
    fn start_wraps(
        &self,
        rope_index: usize,
        rope: &Rope,
        start: &[f64],
    ) -> Result<Vec<f64>, SimulationError> {
        let contacts = self.contacts(rope_index, start);
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
                let raw = self.raw_wrap(rope_index, position, &contacts, start);
                if raw > std::f64::consts::TAU - LEAVING_ANGLE {
                    0.0
                } else {
                    raw
                }
            })
            .collect();
        Ok(wraps)
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
}

/// A parameter error of `object`.
fn invalid(object: &str, problem: String) -> SimulationError {
    SimulationError::InvalidParameter {
        object: object.to_string(),
        problem,
    }
}

/// Fails unless every body has a positive finite mass and a finite position, and every pulley a
/// positive finite radius, non-negative finite inertia and bearing torque, and a mount that
/// exists.
fn check_parameters(network: &Network) -> Result<(), SimulationError> {
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
    Ok(())
}
