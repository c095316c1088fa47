//! What identification gives: per group its window, fits and ranked assignments, and the
//! verdicts on pairs and single bodies with the reasons the motion cannot tell.

use std::cmp::Ordering;
use std::fmt;

use super::super::SimulationError;
use super::{
    ABSOLUTE_MODEL_ERROR, MAX_ASSIGNMENTS, MIN_FRAMES, MOTION_RESOLUTION, RATIO_TOLERANCE,
    RELATIVE_MODEL_ERROR,
};

/// The parabola fitted to one tracked body over its group's window.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// Index into [`Network::bodies`](super::super::Network::bodies).
    pub body: usize,
    /// Height at the window start, m.
    pub height: f64,
    /// Velocity at the window start, m/s.
    pub velocity: f64,
    /// Acceleration, m/s².
    pub acceleration: f64,
    /// Standard error of the acceleration from the fit's misfit, m/s².
    pub acceleration_error: f64,
    /// RMS misfit, m.
    pub residual: f64,
    /// Largest height change within the window, m.
    pub travel: f64,
}

impl Fit {
    /// The acceleration's uncertainty for scoring: the fit's error and the model error.
    pub(super) fn sigma(&self) -> f64 {
        let relative = RELATIVE_MODEL_ERROR * self.acceleration.abs();
        (self.acceleration_error.powi(2) + relative.powi(2) + ABSOLUTE_MODEL_ERROR.powi(2)).sqrt()
    }
}

/// The frames a group's accelerations are measured over.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Window {
    /// The first `frames` frames follow one parabola for every tracked body of the group.
    Clean {
        /// Frames in the window.
        frames: usize,
    },
    /// No body of the group is tracked.
    Untracked,
    /// A tracked body's motion changes before [`MIN_FRAMES`] frames (or fewer were seen).
    TooShort {
        /// Index into [`Network::bodies`](super::super::Network::bodies).
        body: usize,
        /// Frames it follows one parabola for (0 when it follows none).
        frames: usize,
    },
}

/// A candidate assignment: one mass per unknown body of a group, in the group's order.
#[derive(Debug, Clone, PartialEq)]
pub struct Assignment {
    /// Masses, kg, per entry of [`Group::unknowns`].
    pub masses: Vec<f64>,
    /// `Σ z²` of the tracked bodies' acceleration misfits (lower is better).
    pub score: f64,
}

/// A mechanically coupled group of bodies (joined by ropes) with unknown masses.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// Bodies of the group, indices into [`Network::bodies`](super::super::Network::bodies).
    pub bodies: Vec<usize>,
    /// Unknown bodies of the group, indices into the `unknowns` argument.
    pub unknowns: Vec<usize>,
    /// The window measured over.
    pub window: Window,
    /// The tracked bodies' parabolas (empty unless the window is clean).
    pub fits: Vec<Fit>,
    /// Every assignment, best first (empty unless the window is clean).
    pub ranking: Vec<Assignment>,
}

/// How one mass compares with another, as rope questions ask: against it, against twice it,
/// and against half of it, with [`RATIO_TOLERANCE`] for "equal".
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct RatioClass {
    /// `m₁` against `m₂`.
    pub to_other: Ordering,
    /// `m₁` against `2·m₂`.
    pub to_twice: Ordering,
    /// `m₁` against `m₂ / 2`.
    pub to_half: Ordering,
}

impl RatioClass {
    /// The class of `first` against `second`, kg.
    pub fn of(first: f64, second: f64) -> RatioClass {
        RatioClass {
            to_other: compare(first, second),
            to_twice: compare(first, 2.0 * second),
            to_half: compare(first, 0.5 * second),
        }
    }

    /// The class of the second mass against the first.
    #[must_use]
    pub fn reversed(self) -> RatioClass {
        RatioClass {
            to_other: self.to_other.reverse(),
            to_twice: self.to_half.reverse(),
            to_half: self.to_twice.reverse(),
        }
    }
}

fn compare(a: f64, b: f64) -> Ordering {
    if (a - b).abs() <= RATIO_TOLERANCE * a.abs().max(b.abs()) {
        Ordering::Equal
    } else {
        a.total_cmp(&b)
    }
}

/// Why the observed motion cannot tell how two masses (or one mass) compare.
#[derive(Debug, Clone, PartialEq)]
pub enum Undecidable {
    /// The bodies are in different groups: no rope couples them, so their motions are
    /// independent.
    DifferentMechanisms,
    /// No body of the group is tracked.
    Untracked {
        /// A body of the group.
        body: String,
    },
    /// A tracked body's motion changes (contact, stop, impact) before a window long enough to
    /// measure.
    NoCleanWindow {
        /// The body.
        body: String,
        /// Frames it follows one parabola for.
        frames: usize,
    },
    /// Even the best assignment misses the observed accelerations.
    Unexplained {
        /// The best assignment's mean squared normalised misfit per tracked body.
        mean_score: f64,
    },
    /// A stop or the floor holds the body, so its weight goes into the stop, not the motion.
    RestsAgainstStop {
        /// The body.
        body: String,
    },
    /// The body's ropes are slack: it falls freely, whatever its mass.
    FreeFall {
        /// The body.
        body: String,
    },
    /// No candidate mass of the body changes the motion measurably (it hangs from fixed
    /// points, for example).
    MassHidden {
        /// The body.
        body: String,
    },
    /// The near-best assignments disagree and the group barely moved.
    MotionTooSmall {
        /// The largest travel of a tracked body in the window, m.
        travel: f64,
    },
    /// The near-best assignments disagree.
    Ambiguous {
        /// How many classes (or masses, for one body) the near-best assignments give.
        classes: usize,
    },
}

impl fmt::Display for Undecidable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Undecidable::DifferentMechanisms => {
                write!(f, "different mechanisms: no rope couples the bodies")
            }
            Undecidable::Untracked { body } => {
                write!(f, "no body of `{body}`'s mechanism is tracked")
            }
            Undecidable::NoCleanWindow { body, frames } => write!(
                f,
                "`{body}` follows one parabola for {frames} frames, fewer than {MIN_FRAMES}: \
                 its motion changes too early to measure"
            ),
            Undecidable::Unexplained { mean_score } => write!(
                f,
                "no candidate explains the motion (mean squared misfit {mean_score:.1} σ²)"
            ),
            Undecidable::RestsAgainstStop { body } => write!(
                f,
                "`{body}` rests against a stop, so its weight does not show in the motion"
            ),
            Undecidable::FreeFall { body } => write!(
                f,
                "`{body}` falls freely on a slack rope, so its mass does not show"
            ),
            Undecidable::MassHidden { body } => {
                write!(f, "the mass of `{body}` does not change the motion")
            }
            Undecidable::MotionTooSmall { travel } => write!(
                f,
                "the motion is too small to measure ({travel:.3} m, under {MOTION_RESOLUTION} m)"
            ),
            Undecidable::Ambiguous { classes } => write!(
                f,
                "{classes} different answers explain the motion about equally well"
            ),
        }
    }
}

/// The verdict on a pair of unknown bodies.
#[derive(Debug, Clone, PartialEq)]
pub enum PairVerdict {
    /// Every near-best assignment agrees on the class.
    Decided {
        /// The best assignment's masses of the two bodies, kg.
        masses: [f64; 2],
        /// How the first compares with the second.
        class: RatioClass,
    },
    /// The motion cannot tell.
    Undecidable(Undecidable),
}

/// The verdict on one unknown body.
#[derive(Debug, Clone, PartialEq)]
pub enum BodyVerdict {
    /// Its mass is pinned against every other unknown of its group (or, alone, to one
    /// candidate); the best assignment's mass, kg.
    Determined {
        /// Mass, kg.
        mass: f64,
    },
    /// The motion cannot tell.
    Undetermined(Undecidable),
}

/// The result of [`identify`](super::identify()).
#[derive(Debug, Clone, PartialEq)]
pub struct Identification {
    /// Groups with at least one unknown body, in order of their first body.
    pub groups: Vec<Group>,
    /// Per unknown (the `unknowns` argument's order): its verdict.
    pub bodies: Vec<BodyVerdict>,
    /// Per unknown: its mass in its group's best assignment, kg (`None` without a ranking).
    pub best: Vec<Option<f64>>,
    /// Verdicts of every pair of unknowns `(i, j)` with `i < j`, in order.
    pub(super) pairs: Vec<((usize, usize), PairVerdict)>,
}

impl Identification {
    /// The verdict on unknowns `first` and `second` (indices into the `unknowns` argument), with
    /// masses and class in that order; `None` for an index out of range or a body with itself.
    pub fn pair(&self, first: usize, second: usize) -> Option<PairVerdict> {
        let key = (first.min(second), first.max(second));
        let verdict = self
            .pairs
            .iter()
            .find(|(pair, _)| *pair == key)
            .map(|(_, verdict)| verdict.clone())?;
        if first < second {
            return Some(verdict);
        }
        Some(match verdict {
            PairVerdict::Decided { masses, class } => PairVerdict::Decided {
                masses: [masses[1], masses[0]],
                class: class.reversed(),
            },
            undecidable @ PairVerdict::Undecidable(_) => undecidable,
        })
    }
}

/// Why identification could not run.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum IdentifyError {
    /// The frame times are unusable.
    #[error("observation: {0}")]
    Times(String),
    /// A body's track or candidates are unusable.
    #[error("body `{body}`: {problem}")]
    Body {
        /// The body's name.
        body: String,
        /// What is wrong.
        problem: String,
    },
    /// A track or unknown names a body the network does not have.
    #[error("body index {0} is not in the network")]
    NoSuchBody(usize),
    /// A group has more candidate assignments than [`MAX_ASSIGNMENTS`].
    #[error("the group of `{body}` has {count} candidate assignments, more than {MAX_ASSIGNMENTS}")]
    TooManyAssignments {
        /// A body of the group.
        body: String,
        /// Assignments (the product of its unknowns' candidate counts, saturating).
        count: usize,
    },
    /// The model refused.
    #[error(transparent)]
    Simulation(#[from] SimulationError),
}
