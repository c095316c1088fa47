//! What identification is given: frame times and tracked heights ([`Observation`]), and the
//! candidate masses of the unknown bodies ([`Unknown`]); [`check`] refuses unusable ones.

use super::super::Network;
use super::IdentifyError;

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

/// Fails on frame times that are not finite or do not increase, tracks or unknowns that name a
/// body the network lacks, tracks of the wrong length or with a height that is not finite, a
/// body tracked twice or listed twice as unknown, and unknowns without positive candidates.
pub(super) fn check(
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
