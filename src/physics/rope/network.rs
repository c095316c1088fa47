//! The described network: movable bodies, pulleys and where their axles are, ropes as paths of
//! points, the hands that drive static pulleys and fixed points, the way ropes turn round
//! pulleys, and why a network cannot be simulated ([`SimulationError`]). Plain data; the checks
//! are [`super::Mechanism::new`]'s.

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
