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
//! assignment, [`Mechanism::observed_accelerations`](super::Mechanism::observed_accelerations)
//! gives the model's exact accelerations at the observed state (fitted heights and
//! velocities), and the score is
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
//!
//! **Layout.** The inputs and their checks (`input`), the results and verdicts (`outcome`), the
//! rope-coupled groups (`groups`), the parabola fits and clean windows (`parabola`), the scoring
//! of a group's assignments (`judge`) and the verdicts' reasons (`verdict`); [`identify`] here
//! ties them together.

mod groups;
mod input;
mod judge;
mod outcome;
mod parabola;
mod verdict;

pub use input::{Observation, Track, Unknown};
pub use outcome::{
    Assignment, BodyVerdict, Fit, Group, Identification, IdentifyError, PairVerdict, RatioClass,
    Undecidable, Window,
};

use self::groups::coupled_groups;
use self::input::check;
use self::judge::judge;
use self::verdict::{body_verdict, pair_verdict};
use super::{Instant, Network};
// The tests reach the model and the fitting helpers through `super::*`, as they did when this
// module was one file.
#[cfg(test)]
use {
    self::parabola::{clean_frames, fit_parabola},
    super::{GRAVITY, Mechanism, Mount, Point, State},
    std::cmp::Ordering,
};

/// Fewest frames a window must hold for its parabola to mean anything.
pub const MIN_FRAMES: usize = 8;
/// Frames a noisy track's window starts from when one parabola fits them (else from
/// [`MIN_FRAMES`]): the curvature of a parabola through eight noisy frames is mostly noise, and
/// a track read from masks drifts for several frames at a time (a mask edge gains or loses a
/// pixel row), so eight-frame extrapolations miss the next frame by more than the noise says.
pub const NOISY_START_FRAMES: usize = 12;
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

#[cfg(test)]
mod tests;
