//! Judging one group: its clean window, the parabola of each tracked body over it, and the
//! score of every assignment of its unknowns' candidate masses.

use super::super::{Mechanism, Network, SimulationError, State};
use super::parabola::{clean_frames, fit_parabola};
use super::{
    Assignment, CONTACT_TOLERANCE, Fit, Group, IdentifyError, Judged, MAX_ASSIGNMENTS, MIN_FRAMES,
    Observation, Track, Trial, Unknown, Window,
};

/// Measures a group's window and fits, then scores every assignment of its unknowns.
pub(super) fn judge(
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
