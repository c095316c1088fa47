//! Rope outcomes by simulation: the mechanism of a rope video is rebuilt from its annotations
//! and simulated with `physics::rope`, so motion and rotation answers come from physics instead
//! of the recorded results (the first piece of `--dynamics simulate`).
//!
//! Input: a [`RopeAnnotation`] (element names and layout positions, rope paths from
//! `relatedGroupsInRope`, the camera's mirroring), optionally the video's [`FourDData`] (the
//! tracked rope particles tell on which side a rope passes each pulley), and the load masses of
//! the run to simulate. Output: per element, the benchmark's motion sign (+1 up past 1.2 units)
//! and per pulley its rotation sign (+1 clockwise as seen in the video, past 35°).
//!
//! Assumptions, each from the one released video: every pulley's rope radius is 1.48 units (a
//! load hangs 1.48 beside its pulley's centre); a counterfactual run is simulated for the 300
//! updates (6 s) after its change; movable pulleys weigh [`MOVABLE_PULLEY_KG`] (no released
//! video has one). A pulled static pulley or fixed point moves at 2 units/s for 3.5 units (7
//! for fixed points), as the generator's hand does (FORMAT.md §2.3).

use indexmap::IndexMap;

use crate::dataset::{FourDData, RopeAnnotation};
use crate::physics::rope::{
    Body, Drive, DrivenPoint, Mechanism, Mount, Network, Point, Pulley, Rope, SimulationError, Turn,
};

/// Rope radius of every pulley, m (Unity units).
pub const PULLEY_RADIUS: f64 = 1.48;
/// Assumed mass of a movable pulley's frame, kg.
pub const MOVABLE_PULLEY_KG: f64 = 0.1;
/// Vertical travel that counts as motion (`ResultMotion`), units.
pub const MOTION_THRESHOLD: f64 = 1.2;
/// Turn that counts as rotation (`ResultRotation`), degrees.
pub const ROTATION_THRESHOLD_DEG: f64 = 35.0;
/// Simulated time after the change, s (300 updates at 50 Hz).
pub const SIMULATED_SECONDS: f64 = 6.0;
/// Integration step, s (see `bench physics`).
pub const STEP_SECONDS: f64 = 1e-3;
/// Speed of a pulled element, units/s.
pub const PULL_SPEED: f64 = 2.0;
/// How far a pulled static pulley moves, units.
pub const PULL_PULLEY_DISTANCE: f64 = 3.5;
/// How far a pulled fixed point moves, units.
pub const PULL_ANCHOR_DISTANCE: f64 = 7.0;

/// An element moved by hand during the run: its name and `up` (`true`) or down.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Pull {
    /// The static pulley or fixed point.
    pub agent: String,
    /// Upwards.
    pub up: bool,
}

/// Why a rope video cannot be simulated.
#[derive(Debug, thiserror::Error)]
pub enum RopeSimulationError {
    /// An element has no layout position.
    #[error("element `{0}` has no layout position (metaSamplingData.name2position)")]
    MissingPosition(String),
    /// A pulled element is not a static pulley or fixed point of the video.
    #[error("`{0}` cannot be pulled: it is not a static pulley or fixed point of this video")]
    NotPullable(String),
    /// An element's name does not say what it is.
    #[error("element `{0}`: not a pulley, fixed point, cube or sphere")]
    UnknownElement(String),
    /// A load has no mass.
    #[error("load `{0}` has no mass")]
    MissingMass(String),
    /// The physics refused.
    #[error(transparent)]
    Simulation(#[from] SimulationError),
}

/// What one simulated run shows.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RopeOutcome {
    /// Loads, pulleys and fixed points → +1 up, −1 down, 0.
    pub motion: IndexMap<String, i8>,
    /// Pulleys → +1 clockwise as seen in the video, −1 anti-clockwise, 0.
    pub rotation: IndexMap<String, i8>,
    /// Integration steps taken.
    pub steps: u64,
}

/// What an element is, from its scene name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    StaticPulley,
    MovablePulley,
    Anchor,
    Load,
}

fn kind_of(name: &str) -> Option<Kind> {
    if name.contains("Static Pulley") {
        Some(Kind::StaticPulley)
    } else if name.contains("Dynamic Pulley") {
        Some(Kind::MovablePulley)
    } else if name.contains("Fixed Point") {
        Some(Kind::Anchor)
    } else if name.ends_with("Cube") || name.ends_with("Sphere") {
        Some(Kind::Load)
    } else {
        None
    }
}

/// The mechanism of a rope video and where each element ended up in it.
struct Built {
    network: Network,
    bodies: IndexMap<String, usize>,
    pulleys: IndexMap<String, usize>,
    anchors: Vec<String>,
}

fn build(
    annotation: &RopeAnnotation,
    four_d: Option<&FourDData>,
    masses: &IndexMap<String, f64>,
) -> Result<Built, RopeSimulationError> {
    let position = |name: &str| {
        annotation
            .element_positions
            .get(name)
            .copied()
            .ok_or_else(|| RopeSimulationError::MissingPosition(name.to_string()))
    };
    let mut built = Built {
        network: Network::default(),
        bodies: IndexMap::new(),
        pulleys: IndexMap::new(),
        anchors: Vec::new(),
    };
    for group in &annotation.related_groups_in_rope {
        for (rope_name, elements) in group {
            let path_names: Vec<&String> = elements.iter().filter(|e| *e != rope_name).collect();
            let mut path = Vec::with_capacity(path_names.len());
            for name in &path_names {
                let name = name.as_str();
                let kind = kind_of(name)
                    .ok_or_else(|| RopeSimulationError::UnknownElement(name.into()))?;
                let point = match kind {
                    Kind::Anchor => {
                        if !built.anchors.iter().any(|a| a == name) {
                            built.anchors.push(name.to_string());
                        }
                        Point::Fixed(position(name)?)
                    }
                    Kind::Load => {
                        let index = body_index(&mut built, name, position(name)?, || {
                            masses
                                .get(name)
                                .copied()
                                .ok_or_else(|| RopeSimulationError::MissingMass(name.into()))
                        })?;
                        Point::Body(index)
                    }
                    Kind::StaticPulley | Kind::MovablePulley => {
                        let index = if let Some(index) = built.pulleys.get(name) {
                            *index
                        } else {
                            let at = position(name)?;
                            let mount = if kind == Kind::MovablePulley {
                                let body =
                                    body_index(&mut built, name, at, || Ok(MOVABLE_PULLEY_KG))?;
                                Mount::Body(body)
                            } else {
                                Mount::Fixed(at)
                            };
                            built.network.pulleys.push(Pulley {
                                name: name.to_string(),
                                radius: PULLEY_RADIUS,
                                inertia: 0.0,
                                friction_torque: 0.0,
                                mount,
                            });
                            built
                                .pulleys
                                .insert(name.to_string(), built.network.pulleys.len() - 1);
                            built.network.pulleys.len() - 1
                        };
                        Point::Pulley(index)
                    }
                };
                path.push(point);
            }
            let rope_index = built.network.ropes.len();
            if let Some(four_d) = four_d {
                for (position, turn) in observed_turns(&built.network, &path, four_d, rope_name) {
                    built.network.turns.push((rope_index, position, turn));
                }
            }
            built.network.ropes.push(Rope {
                name: rope_name.clone(),
                path,
            });
        }
    }
    Ok(built)
}

fn body_index(
    built: &mut Built,
    name: &str,
    at: [f64; 2],
    mass: impl FnOnce() -> Result<f64, RopeSimulationError>,
) -> Result<usize, RopeSimulationError> {
    if let Some(index) = built.bodies.get(name) {
        return Ok(*index);
    }
    built.network.bodies.push(Body {
        name: name.to_string(),
        mass: mass()?,
        position: at,
        floor_clearance: None,
    });
    let index = built.network.bodies.len() - 1;
    built.bodies.insert(name.to_string(), index);
    Ok(index)
}

/// The side each pulley of `path` is passed on, from the rope's tracked particles at the first
/// frame: the pulley is on the path's left (a counter-clockwise turn) when it lies left of the
/// particles' direction of travel nearest to it.
fn observed_turns(
    network: &Network,
    path: &[Point],
    four_d: &FourDData,
    rope: &str,
) -> Vec<(usize, Turn)> {
    let Some(particles) = four_d
        .soft_bodies
        .get(rope)
        .and_then(|track| track.particles.first())
    else {
        return Vec::new();
    };
    if particles.len() < 3 {
        return Vec::new();
    }
    let centre_of = |point: &Point| match *point {
        Point::Fixed(p) => Some(p),
        Point::Body(index) => network.bodies.get(index).map(|b| b.position),
        Point::Pulley(index) => network.pulleys.get(index).map(|p| match p.mount {
            Mount::Fixed(at) => at,
            Mount::Body(body) => network.bodies[body].position,
        }),
    };
    let distance = |a: [f64; 3], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    // Particles may run from either end of the rope.
    let (Some(first), Some(last)) = (
        path.first().and_then(centre_of),
        path.last().and_then(centre_of),
    ) else {
        return Vec::new();
    };
    let forward = distance(particles[0], first) <= distance(particles[0], last);
    let mut turns = Vec::new();
    for (position, point) in path.iter().enumerate().take(path.len() - 1).skip(1) {
        let Some(centre) = centre_of(point) else {
            continue;
        };
        let nearest = (1..particles.len() - 1)
            .min_by(|&i, &j| {
                distance(particles[i], centre).total_cmp(&distance(particles[j], centre))
            })
            .unwrap_or(1);
        let before = particles[nearest - 1];
        let after = particles[nearest + 1];
        let mut travel = [after[0] - before[0], after[1] - before[1]];
        if !forward {
            travel = [-travel[0], -travel[1]];
        }
        let to_centre = [
            centre[0] - particles[nearest][0],
            centre[1] - particles[nearest][1],
        ];
        let cross = travel[0] * to_centre[1] - travel[1] * to_centre[0];
        if cross.abs() > 1e-9 {
            let turn = if cross > 0.0 {
                Turn::CounterClockwise
            } else {
                Turn::Clockwise
            };
            turns.push((position, turn));
        }
    }
    turns
}

impl RopeOutcome {
    /// Every sign negated: how the generator writes a counterfactual record's second entry
    /// (`"1"`, the opposite change), which it never simulates (FORMAT.md §2.3). A pull the
    /// other way can be unphysical (a ceiling anchor pulled down past its pulley), so pull
    /// mirrors are answered this way; mass mirrors (a heavier load) are simulated.
    #[must_use]
    pub fn negated(&self) -> RopeOutcome {
        RopeOutcome {
            motion: self.motion.iter().map(|(k, v)| (k.clone(), -v)).collect(),
            rotation: self.rotation.iter().map(|(k, v)| (k.clone(), -v)).collect(),
            steps: self.steps,
        }
    }
}

/// Simulates the rope video with the load masses `masses` (kg) and reads off the benchmark's
/// motion and rotation signs.
pub fn simulate_rope(
    annotation: &RopeAnnotation,
    four_d: Option<&FourDData>,
    masses: &IndexMap<String, f64>,
    pull: Option<&Pull>,
) -> Result<RopeOutcome, RopeSimulationError> {
    let mut built = build(annotation, four_d, masses)?;
    let mut moved: Option<(String, f64)> = None;
    if let Some(pull) = pull {
        let agent = pull.agent.as_str();
        let (point, distance) = match (kind_of(agent), built.pulleys.get(agent)) {
            (Some(Kind::StaticPulley), Some(&index)) => {
                (DrivenPoint::Pulley(index), PULL_PULLEY_DISTANCE)
            }
            (Some(Kind::Anchor), _) if built.anchors.iter().any(|a| a == agent) => {
                let at = annotation
                    .element_positions
                    .get(agent)
                    .copied()
                    .ok_or_else(|| RopeSimulationError::MissingPosition(agent.into()))?;
                (DrivenPoint::Fixed(at), PULL_ANCHOR_DISTANCE)
            }
            _ => return Err(RopeSimulationError::NotPullable(agent.into())),
        };
        let velocity = if pull.up { PULL_SPEED } else { -PULL_SPEED };
        let drive = Drive {
            point,
            velocity,
            start: 0.0,
            distance,
        };
        moved = Some((agent.to_string(), drive.displacement(SIMULATED_SECONDS)));
        built.network.drives.push(drive);
    }
    let mechanism = Mechanism::new(built.network)?;
    let start = mechanism.initial_state();
    let mut state = start.clone();
    mechanism.run(&mut state, SIMULATED_SECONDS, STEP_SECONDS)?;
    let sign = |delta: f64, threshold: f64| -> i8 {
        if delta > threshold {
            1
        } else if delta < -threshold {
            -1
        } else {
            0
        }
    };
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a small positive step count"
    )]
    let steps = (SIMULATED_SECONDS / STEP_SECONDS).round() as u64;
    let mut outcome = RopeOutcome {
        steps,
        ..RopeOutcome::default()
    };
    for (name, &index) in &built.bodies {
        outcome.motion.insert(
            name.clone(),
            sign(state.y[index] - start.y[index], MOTION_THRESHOLD),
        );
    }
    for name in built.pulleys.keys().chain(built.anchors.iter()) {
        let lift = moved
            .as_ref()
            .filter(|(agent, _)| agent == name)
            .map_or(0.0, |(_, lift)| *lift);
        outcome
            .motion
            .entry(name.clone())
            .or_insert(sign(lift, MOTION_THRESHOLD));
    }
    // Counter-clockwise is positive in the simulation; the video shows the scene from −z when
    // the camera is mirrored, so its clockwise is the simulation's clockwise then, and the
    // opposite otherwise.
    let mirrored = annotation.camera.as_ref().is_none_or(|c| c.mirrored);
    let threshold = ROTATION_THRESHOLD_DEG.to_radians();
    for (name, &index) in &built.pulleys {
        let turned = state.angles[index];
        let clockwise_as_seen = if mirrored { -turned } else { turned };
        outcome
            .rotation
            .insert(name.clone(), sign(clockwise_as_seen, threshold));
    }
    Ok(outcome)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::RopeChange;

    fn sample() -> (RopeAnnotation, FourDData) {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/pulley_group/0");
        (
            RopeAnnotation::load(&dir.join("outputs.json")).unwrap(),
            FourDData::load(&dir.join("outputs4D.json")).unwrap(),
        )
    }

    fn assert_matches(
        outcome: &RopeOutcome,
        motion: &IndexMap<String, i8>,
        rotation: &IndexMap<String, i8>,
        what: &str,
    ) {
        for (name, expected) in motion {
            assert_eq!(
                outcome.motion.get(name),
                Some(expected),
                "{what}: motion of {name}: {outcome:?}"
            );
        }
        for (name, expected) in rotation {
            assert_eq!(
                outcome.rotation.get(name),
                Some(expected),
                "{what}: rotation of {name}: {outcome:?}"
            );
        }
    }

    #[test]
    fn the_real_video_is_simulated_as_annotated() {
        let (annotation, four_d) = sample();
        // The factual run, with the video's masses.
        let outcome =
            simulate_rope(&annotation, Some(&four_d), &annotation.output_mass_kg, None).unwrap();
        assert_matches(
            &outcome,
            &annotation.result_motion,
            &annotation.result_rotation,
            "factual",
        );
        // Every counterfactual entry (mass changes and pulls), the simulated one and its mirror.
        // Mass mirrors are simulated (a heavier load); pull mirrors are the negated pull, as
        // the generator writes them.
        let mut checked = 0;
        for pair in &annotation.counterfactuals {
            let mut simulated_pull: Option<RopeOutcome> = None;
            for entry in [&pair.simulated, &pair.mirrored] {
                if let (RopeChange::Pull { .. }, Some(first)) = (&entry.change, &simulated_pull) {
                    assert_matches(
                        &first.negated(),
                        &entry.motion,
                        &entry.rotation,
                        &format!("{} mirror {:?}", pair.key, entry.change),
                    );
                    checked += 1;
                    continue;
                }
                let mut masses = pair.baseline_mass_kg.clone();
                let pull = match &entry.change {
                    RopeChange::Mass {
                        target, after_kg, ..
                    } => {
                        masses.insert(target.clone(), *after_kg);
                        None
                    }
                    RopeChange::Pull { agent, direction } => Some(Pull {
                        agent: agent.clone(),
                        up: direction == "up",
                    }),
                    RopeChange::Other { mode } => panic!("unexpected mode {mode}"),
                };
                let outcome =
                    simulate_rope(&annotation, Some(&four_d), &masses, pull.as_ref()).unwrap();
                assert_matches(
                    &outcome,
                    &entry.motion,
                    &entry.rotation,
                    &format!("{} {:?}", pair.key, entry.change),
                );
                if pull.is_some() {
                    simulated_pull = Some(outcome);
                }
                checked += 1;
            }
        }
        assert_eq!(checked, 10, "five records, two entries each");
    }
}
