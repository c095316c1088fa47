//! Rope outcomes and masses by physics: the mechanism of a rope video is rebuilt from its
//! annotations and simulated with `physics::rope`, so motion and rotation answers come from
//! physics instead of the recorded results, and load masses from the tracked motion instead of
//! `outputMass` (`--dynamics simulate`).
//!
//! Input: a [`RopeAnnotation`] (element names and layout positions, rope paths from
//! `relatedGroupsInRope`, the camera's mirroring), optionally the video's [`FourDData`] (the
//! loads' first-frame centroids; the tracked rope particles, which tell on which side a rope
//! passes each pulley; the tracked heights that masses are inferred from), and the load masses
//! of the run to simulate. Output: per element, the benchmark's motion sign (+1 up past 1.2
//! units) and per pulley its rotation sign (+1 clockwise as seen in the video, past 35°), each
//! latched at its first crossing as the generator does; or ([`infer_rope_masses`]) per load and
//! pair of loads what the motion says about their masses.
//!
//! The world follows the release (`dataset::rope::world`): static pulleys are 1 kg discs that turn
//! with the rope, the rope wraps solid and hollow pulleys at their own radii, movable pulleys
//! weigh 5 g; a factual run lasts the 500 updates after the masses change, a counterfactual run
//! the 300 after its change. A pulled static pulley or fixed point moves at 2 units/s for 3.5
//! units (7 for fixed points), as the generator's hand does (`docs/data/rope.md`, timeline and
//! outcome labels). Loads and movable pulleys start at their first 4-D centroid when the video has
//! one: the layout puts end loads 1.48 beside their pulley's centre, but they hang under its rim,
//! 2.16 beside it.

use indexmap::IndexMap;

use crate::dataset::FourDData;
use crate::dataset::rope::outcome::{OutcomeLatch, pulled_motion, seen_rotation};
use crate::dataset::rope::{RopeAnnotation, RopeObjectKind, parse_rope_object_name, world};
use crate::physics::rope::identify::{
    BodyVerdict, Identification, IdentifyError, Observation, PairVerdict, Track, Unknown, identify,
};
use crate::physics::rope::{
    Body, Drive, DrivenPoint, Mechanism, Mount, Network, Point, Pulley, Rope, SimulationError, Turn,
};

/// Integration steps per release update (1/60 s): steps of 0.98 ms, just under the 1 ms whose
/// error `bench physics` shows (under 5 mm a second on its mechanisms).
pub const SUBSTEPS_PER_UPDATE: u32 = 17;

/// Which of the generator's runs is simulated: it sets how long the run lasts after its change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Run {
    /// The video's run: [`world::FACTUAL_UPDATES_AFTER_CHANGE`] updates after the masses change.
    Factual,
    /// A counterfactual run: [`world::COUNTERFACTUAL_UPDATES_AFTER_CHANGE`] updates after its
    /// change.
    Counterfactual,
}

impl Run {
    /// Updates simulated after the change.
    pub fn updates(self) -> u32 {
        match self {
            Run::Factual => world::FACTUAL_UPDATES_AFTER_CHANGE,
            Run::Counterfactual => world::COUNTERFACTUAL_UPDATES_AFTER_CHANGE,
        }
    }
}

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
    /// A pulley's name says neither solid nor hollow.
    #[error("pulley `{0}`: its name says neither Solid nor Hollow, so its size is unknown")]
    UnknownPulleySize(String),
    /// The video has no tracked motion to infer masses from.
    #[error("no load of this video is tracked in outputs4D.json, so its motion cannot be measured")]
    NoTracks,
    /// The physics refused.
    #[error(transparent)]
    Simulation(#[from] SimulationError),
    /// The identification refused.
    #[error(transparent)]
    Identification(#[from] IdentifyError),
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
    // The name grammar, so a grid id after any kind (`Red Cube (1 4)`, perception's name for a
    // second red cube) reads the same.
    let parsed = parse_rope_object_name(name)?;
    match parsed.kind {
        RopeObjectKind::Pulley if parsed.dynamics == "static" => Some(Kind::StaticPulley),
        RopeObjectKind::Pulley => Some(Kind::MovablePulley),
        RopeObjectKind::FixedPoint => Some(Kind::Anchor),
        RopeObjectKind::Cube | RopeObjectKind::Sphere => Some(Kind::Load),
        RopeObjectKind::Rope => None,
    }
}

/// Whether a pulley is solid (little) or hollow (big), from its name.
fn is_solid(name: &str) -> Result<bool, RopeSimulationError> {
    match parse_rope_object_name(name)
        .and_then(|parsed| parsed.pulley_shape)
        .as_deref()
    {
        Some("solid") => Ok(true),
        Some("hollow") => Ok(false),
        _ => Err(RopeSimulationError::UnknownPulleySize(name.to_string())),
    }
}

/// The mass multiplier of a load: [`world::MOVABLE_PULLEY_LOAD_MULTIPLIER`] when it hangs from a
/// movable pulley (next to a `Dynamic Pulley` on a rope's path), else 1.
pub(crate) fn load_multiplier(annotation: &RopeAnnotation, load: &str) -> f64 {
    let under_movable = annotation
        .related_groups_in_rope
        .iter()
        .flat_map(|group| group.iter())
        .any(|(rope, elements)| {
            let path: Vec<&String> = elements.iter().filter(|e| *e != rope).collect();
            path.windows(2).any(|pair| {
                (pair[0] == load && pair[1].contains("Dynamic Pulley"))
                    || (pair[1] == load && pair[0].contains("Dynamic Pulley"))
            })
        });
    if under_movable {
        world::MOVABLE_PULLEY_LOAD_MULTIPLIER
    } else {
        1.0
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
    // A moving body starts where the 4-D data first sees it, when it does.
    let start = |name: &str| match four_d
        .and_then(|data| data.rigid_bodies.get(name))
        .and_then(|track| track.poses.first())
    {
        Some((centroid, _)) if centroid[0].is_finite() && centroid[1].is_finite() => {
            Ok([centroid[0], centroid[1]])
        }
        _ => position(name),
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
                        let index = body_index(&mut built, name, start(name)?, || {
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
                            let solid = is_solid(name)?;
                            let (mount, inertia) = if kind == Kind::MovablePulley {
                                let body = body_index(&mut built, name, start(name)?, || {
                                    Ok(world::MOVABLE_PULLEY_KG)
                                })?;
                                // The same disc as a static pulley's, at the movable one's mass.
                                let disc = if solid {
                                    world::SOLID_PULLEY_RADIUS
                                } else {
                                    world::HOLLOW_PULLEY_RADIUS
                                };
                                (
                                    Mount::Body(body),
                                    0.5 * world::MOVABLE_PULLEY_KG * disc * disc,
                                )
                            } else {
                                (
                                    Mount::Fixed(position(name)?),
                                    world::static_pulley_inertia(solid),
                                )
                            };
                            built.network.pulleys.push(Pulley {
                                name: name.to_string(),
                                radius: world::wrap_radius(solid),
                                inertia,
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
        let radius = match *point {
            Point::Pulley(index) => network.pulleys.get(index).map(|p| p.radius),
            _ => None,
        };
        if let Some(turn) = radius.and_then(|r| winding(particles, centre, r, forward)) {
            turns.push((position, turn));
            continue;
        }
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

/// Half-width of the band round a pulley's wrap radius in which tracked particles count as
/// lying on its rim, units (the rope's radius is 0.2; particles sit on its centre line).
const RIM_BAND: f64 = 0.45;

/// The turn round a pulley from the tracked particles that lie on its rim: the longest run of
/// consecutive particles in the rim band, and the sign of the angle it sweeps round the centre in
/// the path's direction. A rope wrapped almost all the way round, or crossing itself near the
/// pulley, still sweeps its wrap in one run; `None` when no run of two particles lies on the rim
/// (a grazing pass), for the nearest-particle test to decide.
fn winding(particles: &[[f64; 3]], centre: [f64; 2], radius: f64, forward: bool) -> Option<Turn> {
    let on_rim =
        |p: &[f64; 3]| ((p[0] - centre[0]).hypot(p[1] - centre[1]) - radius).abs() < RIM_BAND;
    let angle = |p: &[f64; 3]| (p[1] - centre[1]).atan2(p[0] - centre[0]);
    let mut best = 0.0_f64;
    let mut run: f64 = 0.0;
    for pair in particles.windows(2) {
        if on_rim(&pair[0]) && on_rim(&pair[1]) {
            let mut step = angle(&pair[1]) - angle(&pair[0]);
            // The short way round: consecutive particles are 0.5 apart on a rim of radius ≥ 1.6.
            if step > std::f64::consts::PI {
                step -= std::f64::consts::TAU;
            } else if step < -std::f64::consts::PI {
                step += std::f64::consts::TAU;
            }
            run += step;
            if run.abs() > best.abs() {
                best = run;
            }
        } else {
            run = 0.0;
        }
    }
    if best.abs() < 0.05 {
        return None;
    }
    let counter_clockwise = (best > 0.0) == forward;
    Some(if counter_clockwise {
        Turn::CounterClockwise
    } else {
        Turn::Clockwise
    })
}

impl RopeOutcome {
    /// Every sign negated: how the generator writes a counterfactual record's second entry
    /// (`"1"`, the opposite change), which it never simulates (`docs/data/rope.md`, counterfactual
    /// records). A pull the other way can be unphysical (a ceiling anchor pulled down past its
    /// pulley), so pull mirrors are answered this way; mass mirrors (a heavier load) are simulated.
    #[must_use]
    pub fn negated(&self) -> RopeOutcome {
        RopeOutcome {
            motion: self.motion.iter().map(|(k, v)| (k.clone(), -v)).collect(),
            rotation: self.rotation.iter().map(|(k, v)| (k.clone(), -v)).collect(),
            steps: self.steps,
        }
    }
}

/// The counterfactual baseline of every load on a rope: 0.2 kg times its multiplier (kg); the
/// masses a build needs when the masses do not matter.
fn baseline_masses(annotation: &RopeAnnotation) -> IndexMap<String, f64> {
    annotation
        .related_groups_in_rope
        .iter()
        .flat_map(|group| group.values().flatten())
        .filter(|name| kind_of(name) == Some(Kind::Load))
        .map(|name| {
            (
                name.clone(),
                world::BASELINE_MASS_KG * load_multiplier(annotation, name),
            )
        })
        .collect()
}

/// A rope's name, the names of the elements it runs through, and its turn at each.
pub(crate) type RopeLayoutPath = (String, Vec<String>, Vec<Option<Turn>>);

/// Each rope's path as the simulator builds it: element names in order, and the turn at each
/// (`None` at ends and where the particles do not tell).
pub(crate) fn rope_paths(
    annotation: &RopeAnnotation,
    four_d: Option<&FourDData>,
) -> Result<Vec<RopeLayoutPath>, RopeSimulationError> {
    let built = build(annotation, four_d, &baseline_masses(annotation))?;
    let network = &built.network;
    Ok(network
        .ropes
        .iter()
        .enumerate()
        .map(|(index, rope)| {
            let names = rope
                .path
                .iter()
                .map(|point| match *point {
                    Point::Body(body) => network.bodies.get(body).map(|b| b.name.clone()),
                    Point::Pulley(pulley) => network.pulleys.get(pulley).map(|p| p.name.clone()),
                    Point::Fixed(at) => built
                        .anchors
                        .iter()
                        .find(|name| annotation.element_positions.get(*name) == Some(&at))
                        .cloned(),
                })
                .map(Option::unwrap_or_default)
                .collect();
            let mut turns = vec![None; rope.path.len()];
            for (rope_index, position, turn) in &network.turns {
                if *rope_index == index
                    && let Some(slot) = turns.get_mut(*position)
                {
                    *slot = Some(*turn);
                }
            }
            (rope.name.clone(), names, turns)
        })
        .collect())
}

/// Simulates the rope video's `run` with the load masses `masses` (kg) and reads off the
/// benchmark's motion and rotation signs with the generator's own labelling
/// (`dataset::rope::outcome`: each latched at the first update it crosses its threshold).
pub fn simulate_rope(
    annotation: &RopeAnnotation,
    four_d: Option<&FourDData>,
    masses: &IndexMap<String, f64>,
    pull: Option<&Pull>,
    run: Run,
) -> Result<RopeOutcome, RopeSimulationError> {
    let mut built = build(annotation, four_d, masses)?;
    let mut pulled: Option<(String, Drive)> = None;
    if let Some(pull) = pull {
        let agent = pull.agent.as_str();
        let (point, distance) = match (kind_of(agent), built.pulleys.get(agent)) {
            (Some(Kind::StaticPulley), Some(&index)) => {
                (DrivenPoint::Pulley(index), world::PULL_PULLEY_DISTANCE)
            }
            (Some(Kind::Anchor), _) if built.anchors.iter().any(|a| a == agent) => {
                let at = annotation
                    .element_positions
                    .get(agent)
                    .copied()
                    .ok_or_else(|| RopeSimulationError::MissingPosition(agent.into()))?;
                (DrivenPoint::Fixed(at), world::PULL_ANCHOR_DISTANCE)
            }
            _ => return Err(RopeSimulationError::NotPullable(agent.into())),
        };
        let velocity = if pull.up {
            world::PULL_SPEED
        } else {
            -world::PULL_SPEED
        };
        let drive = Drive {
            point,
            velocity,
            start: 0.0,
            distance,
        };
        pulled = Some((agent.to_string(), drive));
        built.network.drives.push(drive);
    }
    let mechanism = Mechanism::new(built.network)?;
    let mut state = mechanism.initial_state();
    // The video shows the scene from −z when the camera is mirrored (`seen_rotation`).
    let mirrored = annotation.camera.as_ref().is_none_or(|c| c.mirrored);
    let dt = world::UPDATE_SECONDS / f64::from(SUBSTEPS_PER_UPDATE);
    // The generator's labelling: thresholds checked once per update, the first crossing kept.
    let mut labels = OutcomeLatch::new(&state.y, &state.angles);
    for _ in 0..run.updates() {
        for _ in 0..SUBSTEPS_PER_UPDATE {
            mechanism.step(&mut state, dt)?;
        }
        labels.observe(&state.y, &state.angles);
    }
    let mut outcome = RopeOutcome {
        steps: u64::from(run.updates()) * u64::from(SUBSTEPS_PER_UPDATE),
        ..RopeOutcome::default()
    };
    for (name, &index) in &built.bodies {
        outcome.motion.insert(name.clone(), labels.motion(index));
    }
    for name in built.pulleys.keys().chain(built.anchors.iter()) {
        let moved = match &pulled {
            Some((agent, drive)) if agent == name => pulled_motion(drive.velocity),
            _ => 0,
        };
        outcome.motion.entry(name.clone()).or_insert(moved);
    }
    for (name, &index) in &built.pulleys {
        outcome.rotation.insert(
            name.clone(),
            seen_rotation(labels.rotation(index), mirrored),
        );
    }
    Ok(outcome)
}

/// What a rope video's tracked motion says about its load masses: the identification of
/// `physics::rope::identify`, by load name. Masses are as simulated (kg, loads under a movable
/// pulley with their multiplier).
#[derive(Debug, Clone)]
pub struct RopeMassInference {
    /// The unknown loads, in the network's order, with their index in the identification.
    loads: IndexMap<String, usize>,
    identification: Identification,
}

impl RopeMassInference {
    /// The verdict on one load; `None` for a name that is not a load of the mechanism.
    pub fn load(&self, name: &str) -> Option<&BodyVerdict> {
        self.loads
            .get(name)
            .and_then(|&index| self.identification.bodies.get(index))
    }

    /// The verdict on two loads, in that order; `None` for a name that is not a load of the
    /// mechanism, or a load with itself.
    pub fn pair(&self, first: &str, second: &str) -> Option<PairVerdict> {
        let (&a, &b) = (self.loads.get(first)?, self.loads.get(second)?);
        self.identification.pair(a, b)
    }

    /// The whole identification (fits, rankings), with loads in [`RopeMassInference::loads`]
    /// order.
    pub fn identification(&self) -> &Identification {
        &self.identification
    }

    /// The loads, in the identification's order.
    pub fn loads(&self) -> impl Iterator<Item = &str> {
        self.loads.keys().map(String::as_str)
    }
}

/// Infers the load masses of a rope video from its tracked motion (ContPRO's perception →
/// parameters): the mechanism as at the first 4-D frame, the tracked centroid heights of its
/// loads and movable pulleys (one frame every [`world::UPDATES_PER_FRAME`] updates), and per load
/// the release's masses ([`world::LOAD_MASSES_KG`]) times its multiplier. `outputMass` is not
/// read.
pub fn infer_rope_masses(
    annotation: &RopeAnnotation,
    four_d: &FourDData,
) -> Result<RopeMassInference, RopeSimulationError> {
    // Placeholder masses for the build; identification tries every candidate.
    let built = build(annotation, Some(four_d), &baseline_masses(annotation))?;
    // Tracked heights of the mechanism's bodies (loads, movable pulleys), per body.
    let tracked: Vec<(usize, Vec<f64>)> = built
        .bodies
        .iter()
        .filter_map(|(name, &body)| {
            let poses = &four_d.rigid_bodies.get(name)?.poses;
            (!poses.is_empty()).then(|| (body, poses.iter().map(|(at, _)| at[1]).collect()))
        })
        .collect();
    let frames = tracked
        .iter()
        .map(|(_, heights)| heights.len())
        .min()
        .ok_or(RopeSimulationError::NoTracks)?;
    let frame_seconds = world::UPDATE_SECONDS * f64::from(world::UPDATES_PER_FRAME);
    let observation = Observation {
        times: (0..frames)
            .map(|frame| frame as f64 * frame_seconds)
            .collect(),
        tracks: tracked
            .into_iter()
            .map(|(body, mut heights)| {
                heights.truncate(frames);
                Track { body, heights }
            })
            .collect(),
    };
    let mut loads = IndexMap::new();
    let mut unknowns = Vec::new();
    for (name, &body) in &built.bodies {
        if kind_of(name) == Some(Kind::Load) {
            let multiplier = load_multiplier(annotation, name);
            let mut candidates: Vec<f64> = world::LOAD_MASSES_KG
                .iter()
                .map(|mass| mass * multiplier)
                .collect();
            candidates.sort_by(f64::total_cmp);
            loads.insert(name.clone(), unknowns.len());
            unknowns.push(Unknown { body, candidates });
        }
    }
    let identification = identify(&built.network, &observation, &unknowns)?;
    Ok(RopeMassInference {
        loads,
        identification,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::dataset::rope::RopeChange;

    /// The real video's annotations and 4-D record.
    pub(crate) fn sample() -> (RopeAnnotation, FourDData) {
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
        let outcome = simulate_rope(
            &annotation,
            Some(&four_d),
            &annotation.output_mass_kg,
            None,
            Run::Factual,
        )
        .unwrap();
        assert_eq!(outcome.steps, 500 * u64::from(SUBSTEPS_PER_UPDATE));
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
                let outcome = simulate_rope(
                    &annotation,
                    Some(&four_d),
                    &masses,
                    pull.as_ref(),
                    Run::Counterfactual,
                )
                .unwrap();
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

    /// The tracked height change of `name` from the first to the last 4-D frame.
    fn tracked_rise(four_d: &FourDData, name: &str) -> f64 {
        let poses = &four_d.rigid_bodies[name].poses;
        poses[poses.len() - 1].0[1] - poses[0].0[1]
    }

    #[test]
    fn the_factual_masses_move_the_cubes_as_tracked() {
        // From rest with the video's masses (0.2 kg purple against 0.25 kg green over two solid
        // and one hollow 1 kg disc pulley), the cubes move as the 4-D data tracks them over the
        // video's 149 frame intervals (298 updates, 4.97 s): purple up 3.467, green down 3.459.
        // Ideal massless pulleys would move them about 13.6.
        let (annotation, four_d) = sample();
        let built = build(&annotation, Some(&four_d), &annotation.output_mass_kg).unwrap();
        let purple = built.bodies["Purple Cube"];
        let green = built.bodies["Green Cube"];
        let mechanism = Mechanism::new(built.network).unwrap();
        let mut state = mechanism.initial_state();
        let dt = world::UPDATE_SECONDS / f64::from(SUBSTEPS_PER_UPDATE);
        for _ in 0..149 * world::UPDATES_PER_FRAME * SUBSTEPS_PER_UPDATE {
            mechanism.step(&mut state, dt).unwrap();
        }
        let start = mechanism.initial_state();
        for (name, body) in [("Purple Cube", purple), ("Green Cube", green)] {
            let simulated = state.y[body] - start.y[body];
            let tracked = tracked_rise(&four_d, name);
            assert!(
                (simulated - tracked).abs() < 0.05 * tracked.abs(),
                "{name}: simulated {simulated:.3}, tracked {tracked:.3}"
            );
        }
        // Atwood with I/R² per pulley: a = g·0.05/(0.45 + 2·I_s/R_s² + I_h/R_h²).
        let extra = 2.0 * world::static_pulley_inertia(true) / world::SOLID_WRAP_RADIUS.powi(2)
            + world::static_pulley_inertia(false) / world::HOLLOW_WRAP_RADIUS.powi(2);
        let t = 298.0 * world::UPDATE_SECONDS;
        let closed_form = 0.5 * 9.81 * 0.05 / (0.45 + extra) * t * t;
        let simulated = state.y[purple] - start.y[purple];
        assert!(
            (simulated - closed_form).abs() < 0.02 * closed_form,
            "simulated {simulated:.3}, closed form {closed_form:.3}"
        );
    }

    #[test]
    fn the_real_videos_masses_are_inferred_from_the_tracked_motion() {
        use crate::physics::rope::identify::{RatioClass, Undecidable, Window};
        use std::cmp::Ordering;
        let (mut annotation, four_d) = sample();
        // The inference must not read the recorded masses.
        annotation.output_mass_kg.clear();
        let inference = infer_rope_masses(&annotation, &four_d).unwrap();
        assert_eq!(
            inference.loads().collect::<Vec<_>>(),
            ["Purple Cube", "Green Cube", "Pink Sphere"]
        );
        let identification = inference.identification();
        // The cubes follow one parabola each over all 150 frames.
        let group = &identification.groups[0];
        assert_eq!(group.window, Window::Clean { frames: 150 });
        for fit in &group.fits {
            assert!(
                (fit.acceleration.abs() - 0.27).abs() < 0.01,
                "tracked acceleration {fit:?}"
            );
        }
        // Purple 0.2 kg against green 0.25 kg: "less than", at the recorded masses.
        match inference.pair("Purple Cube", "Green Cube") {
            Some(PairVerdict::Decided { masses, class }) => {
                assert!(
                    (masses[0] - 0.2).abs() < 1e-12 && (masses[1] - 0.25).abs() < 1e-12,
                    "{masses:?}"
                );
                assert_eq!(class, RatioClass::of(0.2, 0.25));
                assert_eq!(class.to_other, Ordering::Less);
            }
            other => panic!("{other:?}: {identification:#?}"),
        }
        assert_eq!(group.ranking[0].masses, vec![0.2, 0.25]);
        // The pink sphere hangs alone from a ceiling point: no rope couples it to the cubes,
        // and its mass changes nothing it does.
        for cube in ["Purple Cube", "Green Cube"] {
            assert_eq!(
                inference.pair(cube, "Pink Sphere"),
                Some(PairVerdict::Undecidable(Undecidable::DifferentMechanisms))
            );
        }
        assert_eq!(
            inference.load("Pink Sphere"),
            Some(&BodyVerdict::Undetermined(Undecidable::MassHidden {
                body: "Pink Sphere".into()
            }))
        );
        assert_eq!(
            inference.load("Purple Cube"),
            Some(&BodyVerdict::Determined { mass: 0.2 })
        );
    }
}
