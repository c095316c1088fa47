//! Mass identification: which candidate load masses explain a rope–pulley network's observed
//! motion (perception → parameters, as ContPRO infers physical parameters from video).
//!
//! Input: a [`Network`] (geometry as at the first observed frame, pulley inertias, and the
//! masses of the bodies that are known), an [`Observation`] (frame times in s, tracked body
//! heights in m), and per unknown body its candidate masses ([`Unknown`], kg). Output
//! ([`Identification`]): per mechanically coupled group of bodies its fits and the candidate
//! assignments ranked by how well they explain the observed accelerations; per pair of unknown
//! bodies a [`PairVerdict`] (their [`RatioClass`], or why the motion cannot tell); per unknown
//! body a [`BodyVerdict`]. Nothing here knows about scenes or questions.
//!
//! **Method: acceleration matching over the candidate grid.** Each tracked height is fitted
//! with a parabola over the longest early window it follows (the window ends before the first
//! contact, stop or impact, found from the fit: a frame the parabola of the frames before it
//! misses, or a parabola that stops fitting its own frames), giving the velocity and the
//! acceleration at the window start and the acceleration's standard error. For every candidate
//! assignment, [`Mechanism::observed_accelerations`] gives the model's exact accelerations at
//! the observed state (fitted heights and velocities), and the score is
//! `Σ ((a_model − a_observed) / σ)²` over the tracked bodies of the group, with `σ` the fit's
//! error plus a model error (10 % of the observed acceleration and 0.01 m/s²: the real video's
//! loads follow the model to 3 %, not to their fits' 0.1 %). Candidates within
//! [`NEAR_BEST`] of the best score are *near-best*.
//!
//! Why this and not a non-negative least-squares solve of the force balance for the tensions:
//! the candidates are a small discrete set (3 per load, at most a few hundred assignments per
//! group), and the forward model already encodes everything a force balance would have to
//! restate — pulley inertia seen at the wrap radius, diagonal segments, movable pulleys, ropes
//! that only pull, and stops that only push — exactly, through one complementarity solve per
//! candidate. A least-squares inversion would need the rope flows' derivatives and the active
//! contact set as extra unknowns, and would still have to be rounded to a candidate.
//!
//! **Verdicts.** A pair of unknown bodies is decided when every near-best assignment puts their
//! masses in the same [`RatioClass`] (equal, twice, half, within [`RATIO_TOLERANCE`]); the
//! answer is the best assignment's masses. Otherwise, or when the question cannot even be
//! asked of the motion, the verdict says why ([`Undecidable`]): the bodies are in different
//! groups; a group has no track or no clean window; no candidate explains the motion; a body
//! rests against a stop or falls freely, so its mass does not show; the mass of a body changes
//! nothing observable; the motion is too small to measure; or the near-best assignments
//! simply disagree.
//!
//! Deterministic: assignments are enumerated in a fixed order and ranked by a stable sort.

use std::cmp::Ordering;
use std::fmt;

use super::{GRAVITY, Instant, Mechanism, Mount, Network, Point, SimulationError, State};
use crate::physics::linalg::{Matrix, solve};

/// Fewest frames a window must hold for its parabola to mean anything.
pub const MIN_FRAMES: usize = 8;
/// Largest RMS misfit (m) of a window's parabola, or [`RESIDUAL_NOISE_FACTOR`] times the
/// track's noise when that is larger: the real video's tracked loads follow one parabola over
/// all 150 frames to 0.009 m, a load that hits a stop does not.
pub const RESIDUAL_TOLERANCE: f64 = 0.02;
/// See [`RESIDUAL_TOLERANCE`].
pub const RESIDUAL_NOISE_FACTOR: f64 = 2.0;
/// Smallest miss (m) of the next frame by the parabola through the frames before it that ends
/// a window; the threshold is at least [`PREDICTION_NOISE_FACTOR`] times the fit's RMS misfit
/// and [`PREDICTION_TRACK_NOISE_FACTOR`] times the track's noise (the real purple cube's track
/// wobbles by up to 0.025 m a frame).
pub const PREDICTION_TOLERANCE: f64 = 0.02;
/// See [`PREDICTION_TOLERANCE`].
pub const PREDICTION_NOISE_FACTOR: f64 = 5.0;
/// See [`PREDICTION_TOLERANCE`]: a parabola through [`MIN_FRAMES`] noisy frames predicts the
/// next to about twice the noise, so six times it is a change of motion, not noise.
pub const PREDICTION_TRACK_NOISE_FACTOR: f64 = 6.0;
/// Frames the noise of a track is estimated over (its second differences; the motion's own
/// curvature adds `a·dt²`, under a millimetre here).
pub const NOISE_FRAMES: usize = 40;
/// Track noise (m) below which a track counts as exact and its window may grow from three
/// frames; a noisier one starts from [`MIN_FRAMES`], since a parabola through three noisy
/// frames predicts the fourth no better than four times the noise.
pub const EXACT_TRACK_NOISE: f64 = 1e-4;
/// Relative model error of an observed acceleration.
pub const RELATIVE_MODEL_ERROR: f64 = 0.1;
/// Absolute model error of an observed acceleration, m/s².
pub const ABSOLUTE_MODEL_ERROR: f64 = 0.01;
/// Score margin over the best within which an assignment is near-best (2 σ for one body).
pub const NEAR_BEST: f64 = 4.0;
/// Largest mean squared normalised misfit per tracked body for the best assignment to count
/// as explaining the motion (3 σ).
pub const MAX_MEAN_SCORE: f64 = 9.0;
/// Distance (m) within which an observed rope counts as taut and a stop as touching.
pub const CONTACT_TOLERANCE: f64 = 0.05;
/// Relative difference within which two masses (or one and twice or half the other) count as
/// equal: a load of 1.975 × 0.2 kg is twice 0.2 kg.
pub const RATIO_TOLERANCE: f64 = 0.02;
/// Travel (m) below which an ambiguous motion counts as too small to measure.
pub const MOTION_RESOLUTION: f64 = 0.05;
/// Most assignments one group may have (each is one model solve; the release's largest groups
/// have a few loads of 3 candidates each, 3⁶ = 729).
pub const MAX_ASSIGNMENTS: usize = 100_000;

/// One tracked body.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// Index into [`Network::bodies`].
    pub body: usize,
    /// Height of the body's position point per frame, m (one per [`Observation::times`]).
    pub heights: Vec<f64>,
}

/// What was seen: frame times and tracked heights. Untracked bodies are taken at their
/// positions in the network, at rest.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Observation {
    /// Frame times, s, increasing; the first is the time of the network's positions.
    pub times: Vec<f64>,
    /// Tracked bodies.
    pub tracks: Vec<Track>,
}

/// A body whose mass is unknown, and the masses it may have, kg.
#[derive(Debug, Clone, PartialEq)]
pub struct Unknown {
    /// Index into [`Network::bodies`].
    pub body: usize,
    /// Candidate masses, kg.
    pub candidates: Vec<f64>,
}

/// The parabola fitted to one tracked body over its group's window.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// Index into [`Network::bodies`].
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
    fn sigma(&self) -> f64 {
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
        /// Index into [`Network::bodies`].
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
    /// Bodies of the group, indices into [`Network::bodies`].
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

/// The result of [`identify`].
#[derive(Debug, Clone, PartialEq)]
pub struct Identification {
    /// Groups with at least one unknown body, in order of their first body.
    pub groups: Vec<Group>,
    /// Per unknown (the `unknowns` argument's order): its verdict.
    pub bodies: Vec<BodyVerdict>,
    /// Per unknown: its mass in its group's best assignment, kg (`None` without a ranking).
    pub best: Vec<Option<f64>>,
    /// Verdicts of every pair of unknowns `(i, j)` with `i < j`, in order.
    pairs: Vec<((usize, usize), PairVerdict)>,
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

/// One scored assignment with the model's instantaneous solve (for the verdicts' reasons).
struct Trial {
    /// Per unknown of the group, the index of its candidate.
    choice: Vec<usize>,
    masses: Vec<f64>,
    score: f64,
    instant: Instant,
}

/// A group with its scored trials, best first.
struct Judged {
    group: Group,
    trials: Vec<Trial>,
}

/// Ranks the candidate masses of `unknowns` by how well they explain `observation` and judges
/// every pair; see the module documentation.
pub fn identify(
    network: &Network,
    observation: &Observation,
    unknowns: &[Unknown],
) -> Result<Identification, IdentifyError> {
    check(network, observation, unknowns)?;
    let (groups, ropes_of) = coupled_groups(network);
    let mut group_of_unknown = vec![0; unknowns.len()];
    let mut judged = Vec::new();
    for bodies in groups {
        let members: Vec<usize> = (0..unknowns.len())
            .filter(|&u| bodies.contains(&unknowns[u].body))
            .collect();
        if members.is_empty() {
            continue;
        }
        for &u in &members {
            group_of_unknown[u] = judged.len();
        }
        judged.push(judge(network, observation, unknowns, bodies, members)?);
    }
    let name = |body: usize| network.bodies[body].name.clone();
    let mut pairs = Vec::new();
    for i in 0..unknowns.len() {
        for j in i + 1..unknowns.len() {
            let verdict = if group_of_unknown[i] == group_of_unknown[j] {
                pair_verdict(
                    &judged[group_of_unknown[i]],
                    unknowns,
                    &ropes_of,
                    (i, j),
                    &name,
                )
            } else {
                PairVerdict::Undecidable(Undecidable::DifferentMechanisms)
            };
            pairs.push(((i, j), verdict));
        }
    }
    let mut best = vec![None; unknowns.len()];
    let mut verdicts = Vec::with_capacity(unknowns.len());
    for (u, slot) in best.iter_mut().enumerate() {
        let group = &judged[group_of_unknown[u]];
        let position = group.group.unknowns.iter().position(|&m| m == u);
        *slot = group
            .trials
            .first()
            .zip(position)
            .map(|(trial, at)| trial.masses[at]);
        verdicts.push(body_verdict(group, unknowns, &ropes_of, u, &pairs, &name));
    }
    Ok(Identification {
        groups: judged.into_iter().map(|j| j.group).collect(),
        bodies: verdicts,
        best,
        pairs,
    })
}

fn check(
    network: &Network,
    observation: &Observation,
    unknowns: &[Unknown],
) -> Result<(), IdentifyError> {
    let times = &observation.times;
    if times.iter().any(|t| !t.is_finite()) {
        return Err(IdentifyError::Times("a frame time is not finite".into()));
    }
    if let Some(at) = times.windows(2).position(|w| w[1] <= w[0]) {
        return Err(IdentifyError::Times(format!(
            "frame times must increase; frame {} is at {} s after {} s",
            at + 1,
            times[at + 1],
            times[at]
        )));
    }
    let body_name = |index: usize| {
        network
            .bodies
            .get(index)
            .map(|b| b.name.clone())
            .ok_or(IdentifyError::NoSuchBody(index))
    };
    for (position, track) in observation.tracks.iter().enumerate() {
        let body = body_name(track.body)?;
        if track.heights.len() != times.len() {
            return Err(IdentifyError::Body {
                body,
                problem: format!(
                    "{} tracked heights for {} frame times",
                    track.heights.len(),
                    times.len()
                ),
            });
        }
        if let Some(frame) = track.heights.iter().position(|h| !h.is_finite()) {
            return Err(IdentifyError::Body {
                body,
                problem: format!("tracked height at frame {frame} is not finite"),
            });
        }
        if observation.tracks[..position]
            .iter()
            .any(|t| t.body == track.body)
        {
            return Err(IdentifyError::Body {
                body,
                problem: "tracked twice".into(),
            });
        }
    }
    for (position, unknown) in unknowns.iter().enumerate() {
        let body = body_name(unknown.body)?;
        if unknown.candidates.is_empty() {
            return Err(IdentifyError::Body {
                body,
                problem: "no candidate masses".into(),
            });
        }
        if let Some(bad) = unknown
            .candidates
            .iter()
            .find(|m| !(m.is_finite() && **m > 0.0))
        {
            return Err(IdentifyError::Body {
                body,
                problem: format!("candidate mass {bad} kg must be positive"),
            });
        }
        if unknowns[..position].iter().any(|u| u.body == unknown.body) {
            return Err(IdentifyError::Body {
                body,
                problem: "listed twice as unknown".into(),
            });
        }
    }
    Ok(())
}

/// The groups of bodies coupled by ropes (a rope couples the bodies tied to it and the bodies
/// carrying the pulleys it passes), each sorted, in order of their first body; and per body the
/// ropes it is on.
fn coupled_groups(network: &Network) -> (Vec<Vec<usize>>, Vec<Vec<usize>>) {
    let count = network.bodies.len();
    let mut parent: Vec<usize> = (0..count).collect();
    let mut ropes_of = vec![Vec::new(); count];
    for (rope_index, rope) in network.ropes.iter().enumerate() {
        let bodies: Vec<usize> = rope
            .path
            .iter()
            .filter_map(|point| match *point {
                Point::Body(body) => Some(body),
                Point::Pulley(pulley) => match network.pulleys.get(pulley)?.mount {
                    Mount::Body(body) => Some(body),
                    Mount::Fixed(_) => None,
                },
                Point::Fixed(_) => None,
            })
            .filter(|&body| body < count)
            .collect();
        for &body in &bodies {
            if !ropes_of[body].contains(&rope_index) {
                ropes_of[body].push(rope_index);
            }
        }
        for pair in bodies.windows(2) {
            let (a, b) = (root(&mut parent, pair[0]), root(&mut parent, pair[1]));
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut group_of_root: Vec<Option<usize>> = vec![None; count];
    for body in 0..count {
        let r = root(&mut parent, body);
        if let Some(index) = group_of_root[r] {
            groups[index].push(body);
        } else {
            group_of_root[r] = Some(groups.len());
            groups.push(vec![body]);
        }
    }
    (groups, ropes_of)
}

/// The representative of `at`'s set in a union–find forest (halving the path on the way).
fn root(parent: &mut [usize], mut at: usize) -> usize {
    while parent[at] != at {
        parent[at] = parent[parent[at]];
        at = parent[at];
    }
    at
}

/// Measures a group's window and fits, then scores every assignment of its unknowns.
fn judge(
    network: &Network,
    observation: &Observation,
    unknowns: &[Unknown],
    bodies: Vec<usize>,
    members: Vec<usize>,
) -> Result<Judged, IdentifyError> {
    let tracks: Vec<&Track> = observation
        .tracks
        .iter()
        .filter(|t| bodies.contains(&t.body))
        .collect();
    let mut window = Window::Untracked;
    for track in &tracks {
        let frames = clean_frames(&observation.times, &track.heights);
        window = match (window, frames >= MIN_FRAMES) {
            (Window::TooShort { .. }, _) => window,
            (_, false) => Window::TooShort {
                body: track.body,
                frames,
            },
            (Window::Untracked, true) => Window::Clean { frames },
            (Window::Clean { frames: shortest }, true) => Window::Clean {
                frames: shortest.min(frames),
            },
        };
    }
    let mut group = Group {
        bodies,
        unknowns: members,
        window,
        fits: Vec::new(),
        ranking: Vec::new(),
    };
    let Window::Clean { frames } = window else {
        return Ok(Judged {
            group,
            trials: Vec::new(),
        });
    };
    let times = &observation.times[..frames];
    for track in &tracks {
        let heights = &track.heights[..frames];
        let Some(parabola) = fit_parabola(times, heights) else {
            return Err(IdentifyError::Body {
                body: network.bodies[track.body].name.clone(),
                problem: "its heights do not determine a parabola".into(),
            });
        };
        let travel = heights
            .iter()
            .map(|h| (h - heights[0]).abs())
            .fold(0.0, f64::max);
        group.fits.push(Fit {
            body: track.body,
            height: parabola.height,
            velocity: parabola.velocity,
            acceleration: parabola.acceleration,
            acceleration_error: parabola.acceleration_error,
            residual: parabola.residual,
            travel,
        });
    }
    let mut state = State {
        time: observation.times.first().copied().unwrap_or(0.0),
        y: network.bodies.iter().map(|b| b.position[1]).collect(),
        v: vec![0.0; network.bodies.len()],
        angles: vec![0.0; network.pulleys.len()],
        tensions: vec![0.0; network.ropes.len()],
        friction_torques: vec![0.0; network.pulleys.len()],
    };
    for fit in &group.fits {
        state.y[fit.body] = fit.height;
        state.v[fit.body] = fit.velocity;
    }
    let count = group.unknowns.iter().fold(1_usize, |product, &u| {
        product.saturating_mul(unknowns[u].candidates.len())
    });
    if count > MAX_ASSIGNMENTS {
        return Err(IdentifyError::TooManyAssignments {
            body: network.bodies[group.bodies[0]].name.clone(),
            count,
        });
    }
    let mut trials = Vec::with_capacity(count);
    let mut choice = vec![0_usize; group.unknowns.len()];
    let mut trial_network = network.clone();
    loop {
        let masses: Vec<f64> = group
            .unknowns
            .iter()
            .zip(&choice)
            .map(|(&u, &c)| unknowns[u].candidates[c])
            .collect();
        for (&u, &mass) in group.unknowns.iter().zip(&masses) {
            trial_network.bodies[unknowns[u].body].mass = mass;
        }
        let mechanism = Mechanism::new(trial_network.clone())?;
        let instant = mechanism.observed_accelerations(&state, CONTACT_TOLERANCE)?;
        let score: f64 = group
            .fits
            .iter()
            .map(|fit| ((instant.accelerations[fit.body] - fit.acceleration) / fit.sigma()).powi(2))
            .sum();
        if !score.is_finite() {
            return Err(SimulationError::NonFinite {
                time: state.time,
                what: "identification score".into(),
            }
            .into());
        }
        trials.push(Trial {
            choice: choice.clone(),
            masses,
            score,
            instant,
        });
        // The next assignment, the last unknown's candidate turning fastest.
        let mut position = choice.len();
        loop {
            if position == 0 {
                trials.sort_by(|a, b| a.score.total_cmp(&b.score));
                group.ranking = trials
                    .iter()
                    .map(|t| Assignment {
                        masses: t.masses.clone(),
                        score: t.score,
                    })
                    .collect();
                return Ok(Judged { group, trials });
            }
            position -= 1;
            choice[position] += 1;
            if choice[position] < unknowns[group.unknowns[position]].candidates.len() {
                break;
            }
            choice[position] = 0;
        }
    }
}

/// Why a group cannot be judged at all: no track, no clean window, or no candidate fits.
fn unjudgeable(judged: &Judged, name: &dyn Fn(usize) -> String) -> Option<Undecidable> {
    let group = &judged.group;
    match group.window {
        Window::Untracked => {
            return Some(Undecidable::Untracked {
                body: name(group.bodies[0]),
            });
        }
        Window::TooShort { body, frames } => {
            return Some(Undecidable::NoCleanWindow {
                body: name(body),
                frames,
            });
        }
        Window::Clean { .. } => {}
    }
    let best = judged.trials.first()?;
    let mean_score = best.score / group.fits.len().max(1) as f64;
    (mean_score > MAX_MEAN_SCORE).then_some(Undecidable::Unexplained { mean_score })
}

/// The near-best trials of a judged group.
fn near_best(judged: &Judged) -> impl Iterator<Item = &Trial> {
    let best = judged.trials.first().map_or(f64::INFINITY, |t| t.score);
    judged
        .trials
        .iter()
        .take_while(move |t| t.score <= best + NEAR_BEST)
}

fn pair_verdict(
    judged: &Judged,
    unknowns: &[Unknown],
    ropes_of: &[Vec<usize>],
    (first, second): (usize, usize),
    name: &dyn Fn(usize) -> String,
) -> PairVerdict {
    if let Some(reason) = unjudgeable(judged, name) {
        return PairVerdict::Undecidable(reason);
    }
    let at = |u: usize| judged.group.unknowns.iter().position(|&m| m == u);
    let (Some(a), Some(b), Some(best)) = (at(first), at(second), judged.trials.first()) else {
        return PairVerdict::Undecidable(Undecidable::DifferentMechanisms);
    };
    let mut classes: Vec<RatioClass> = near_best(judged)
        .map(|t| RatioClass::of(t.masses[a], t.masses[b]))
        .collect();
    classes.sort_unstable();
    classes.dedup();
    if let [class] = classes.as_slice() {
        return PairVerdict::Decided {
            masses: [best.masses[a], best.masses[b]],
            class: *class,
        };
    }
    PairVerdict::Undecidable(reason(
        judged,
        unknowns,
        ropes_of,
        &[(first, a), (second, b)],
        classes.len(),
        name,
    ))
}

/// Why the near-best assignments disagree about `blamed` (unknown index, position in the
/// group): a stop holds one, one falls freely, one's mass changes nothing, the motion is too
/// small, or none of these.
fn reason(
    judged: &Judged,
    unknowns: &[Unknown],
    ropes_of: &[Vec<usize>],
    blamed: &[(usize, usize)],
    classes: usize,
    name: &dyn Fn(usize) -> String,
) -> Undecidable {
    let body_of = |u: usize| unknowns[u].body;
    for &(u, _) in blamed {
        if near_best(judged).any(|t| t.instant.stopped[body_of(u)]) {
            return Undecidable::RestsAgainstStop {
                body: name(body_of(u)),
            };
        }
    }
    if let Some(best) = judged.trials.first() {
        for &(u, _) in blamed {
            let body = body_of(u);
            let slack = ropes_of[body].iter().all(|&rope| !best.instant.taut[rope]);
            if slack && (best.instant.accelerations[body] + GRAVITY).abs() <= 1e-6 * GRAVITY {
                return Undecidable::FreeFall { body: name(body) };
            }
        }
        for &(u, at) in blamed {
            // Hidden: every candidate of this body, the others as in the best, is near-best.
            let hidden = judged
                .trials
                .iter()
                .filter(|t| {
                    t.choice
                        .iter()
                        .zip(&best.choice)
                        .enumerate()
                        .all(|(i, (c, b))| i == at || c == b)
                })
                .all(|t| t.score <= best.score + NEAR_BEST);
            if hidden {
                return Undecidable::MassHidden {
                    body: name(body_of(u)),
                };
            }
        }
    }
    let travel = judged
        .group
        .fits
        .iter()
        .map(|f| f.travel)
        .fold(0.0, f64::max);
    if travel < MOTION_RESOLUTION {
        return Undecidable::MotionTooSmall { travel };
    }
    Undecidable::Ambiguous { classes }
}

fn body_verdict(
    judged: &Judged,
    unknowns: &[Unknown],
    ropes_of: &[Vec<usize>],
    u: usize,
    pairs: &[((usize, usize), PairVerdict)],
    name: &dyn Fn(usize) -> String,
) -> BodyVerdict {
    if let Some(reason) = unjudgeable(judged, name) {
        return BodyVerdict::Undetermined(reason);
    }
    let group = &judged.group;
    let (Some(at), Some(best)) = (
        group.unknowns.iter().position(|&m| m == u),
        judged.trials.first(),
    ) else {
        return BodyVerdict::Undetermined(Undecidable::Untracked {
            body: name(unknowns[u].body),
        });
    };
    if group.unknowns.len() > 1 {
        // Pinned against every other unknown of the group.
        for ((i, j), verdict) in pairs {
            if (*i == u || *j == u)
                && let PairVerdict::Undecidable(reason) = verdict
                && group.unknowns.contains(i)
                && group.unknowns.contains(j)
            {
                return BodyVerdict::Undetermined(reason.clone());
            }
        }
        return BodyVerdict::Determined {
            mass: best.masses[at],
        };
    }
    let mut masses: Vec<f64> = near_best(judged).map(|t| t.masses[at]).collect();
    masses.sort_by(f64::total_cmp);
    masses.dedup();
    if masses.len() == 1 {
        BodyVerdict::Determined {
            mass: best.masses[at],
        }
    } else {
        BodyVerdict::Undetermined(reason(
            judged,
            unknowns,
            ropes_of,
            &[(u, at)],
            masses.len(),
            name,
        ))
    }
}

/// How many of the first frames follow one parabola: the window grows frame by frame while
/// the parabola through the frames so far predicts the next one and still fits them all when
/// it is added, to within tolerances that grow with the track's noise ([`track_noise`]). An
/// exact track grows from three frames; a noisy one from [`MIN_FRAMES`] (or from three when
/// even those do not fit one parabola, so a motion that changes early reads as such). Below
/// [`MIN_FRAMES`] it is too short to measure.
fn clean_frames(times: &[f64], heights: &[f64]) -> usize {
    let count = times.len().min(heights.len());
    if count < 3 {
        return 0;
    }
    let noise = track_noise(&heights[..count]);
    let residual_tolerance = RESIDUAL_TOLERANCE.max(RESIDUAL_NOISE_FACTOR * noise);
    let start = if noise > EXACT_TRACK_NOISE && count >= MIN_FRAMES {
        fit_parabola(&times[..MIN_FRAMES], &heights[..MIN_FRAMES])
            .filter(|fit| fit.residual <= residual_tolerance)
            .map_or(3, |_| MIN_FRAMES)
    } else {
        3
    };
    let mut frames = start;
    let Some(mut fit) = fit_parabola(&times[..frames], &heights[..frames]) else {
        return 0;
    };
    while frames < count {
        let tolerance = PREDICTION_TOLERANCE
            .max(PREDICTION_NOISE_FACTOR * fit.residual)
            .max(PREDICTION_TRACK_NOISE_FACTOR * noise);
        if (fit.at(times[frames]) - heights[frames]).abs() > tolerance {
            break;
        }
        match fit_parabola(&times[..=frames], &heights[..=frames]) {
            Some(next) if next.residual <= residual_tolerance => {
                fit = next;
                frames += 1;
            }
            _ => break,
        }
    }
    frames
}

/// The RMS noise of a track (m), from its second differences over the first
/// [`NOISE_FRAMES`] frames: white noise of σ gives differences of σ·√6; the median absolute
/// deviation keeps a contact or two from inflating it.
fn track_noise(heights: &[f64]) -> f64 {
    let end = heights.len().min(NOISE_FRAMES);
    let mut differences: Vec<f64> = heights[..end]
        .windows(3)
        .map(|w| w[2] - 2.0 * w[1] + w[0])
        .collect();
    if differences.is_empty() {
        return 0.0;
    }
    let median = |values: &mut Vec<f64>| {
        values.sort_by(f64::total_cmp);
        values[values.len() / 2]
    };
    let centre = median(&mut differences);
    let mut deviations: Vec<f64> = differences.iter().map(|d| (d - centre).abs()).collect();
    1.4826 * median(&mut deviations) / 6.0_f64.sqrt()
}

/// A least-squares parabola `h(t) = h₀ + v₀ τ + ½ a τ²`, `τ = t − t₀`.
struct Parabola {
    start: f64,
    height: f64,
    velocity: f64,
    acceleration: f64,
    acceleration_error: f64,
    residual: f64,
}

impl Parabola {
    fn at(&self, time: f64) -> f64 {
        let tau = time - self.start;
        self.height + self.velocity * tau + 0.5 * self.acceleration * tau * tau
    }
}

/// Fits a parabola to at least three samples over a positive time span (normal equations in
/// time scaled to [0, 1], heights taken from the first, so the 3×3 system stays well
/// conditioned); `None` otherwise or when the system is singular.
fn fit_parabola(times: &[f64], heights: &[f64]) -> Option<Parabola> {
    let count = times.len().min(heights.len());
    if count < 3 {
        return None;
    }
    let start = times[0];
    let span = times[count - 1] - start;
    let base = heights[0];
    if !span.is_finite() || span <= 0.0 {
        return None;
    }
    let mut normal = Matrix::zeros(3);
    let mut rhs = [0.0; 3];
    for (t, h) in times.iter().zip(heights).take(count) {
        let s = (t - start) / span;
        let powers = [1.0, s, s * s];
        for row in 0..3 {
            for column in 0..3 {
                normal.add(row, column, powers[row] * powers[column]);
            }
            rhs[row] += powers[row] * (h - base);
        }
    }
    let coefficients = solve(&normal, &rhs)?;
    let squares: f64 = times
        .iter()
        .zip(heights)
        .take(count)
        .map(|(t, h)| {
            let s = (t - start) / span;
            let model = coefficients[0] + coefficients[1] * s + coefficients[2] * s * s;
            (h - base - model).powi(2)
        })
        .sum();
    let residual = (squares / count as f64).sqrt();
    // The acceleration's variance: σ² (XᵀX)⁻¹₂₂ with σ² = SSR / (n − 3), through a = 2 c₂ / T².
    let variance = if count > 3 {
        squares / (count - 3) as f64
    } else {
        0.0
    };
    let inverse_column = solve(&normal, &[0.0, 0.0, 1.0])?;
    let acceleration_error = 2.0 * (variance * inverse_column[2].max(0.0)).sqrt() / (span * span);
    let parabola = Parabola {
        start,
        height: base + coefficients[0],
        velocity: coefficients[1] / span,
        acceleration: 2.0 * coefficients[2] / (span * span),
        acceleration_error,
        residual,
    };
    [
        parabola.height,
        parabola.velocity,
        parabola.acceleration,
        parabola.acceleration_error,
        parabola.residual,
    ]
    .iter()
    .all(|v| v.is_finite())
    .then_some(parabola)
}

#[cfg(test)]
mod tests;
