//! The ground truth of a generated rope video: the layout's mechanism built with the release's
//! prefab physics (static pulleys are 1 kg discs turning with the rope, movable pulleys 5 g,
//! ropes wrapping at the pulleys' wrap radii on the sides the release's orientation rule gives)
//! and simulated through the release's timeline (`docs/data/rope.md`, timeline and outcome labels):
//! 100 updates with every load at the baseline mass, the change at update 100 (the factual random
//! masses, a counterfactual mass change, or a pulled pulley or anchor), then 500 (factual) or 300
//! (counterfactual) updates, with motion and rotation latched at their first threshold crossing.
//!
//! Input: a [`Layout`]. Output: [`RunResult`]s (signs, tensions at the change, recorded frames)
//! and the validity checks of the release (movable pulleys that drift more than 0.9 units or
//! bodies faster than 1.8 units/s before the change, pulleys faster than 20 rad/s).
//! Units: world units (nominally metres), kilograms, seconds, radians.

use indexmap::IndexMap;

use super::layout::{ElementKind, Layout, LayoutRope};
use crate::dataset::rope::outcome::{OutcomeLatch, pulled_motion, seen_rotation};
use crate::dataset::rope::world;
use crate::physics::rope::{
    Body, Drive, DrivenPoint, Mechanism, Mount, Network, Point, Pulley, Rope, SimulationError,
    State, Turn,
};

/// Integration steps per release update (the truth runs at 1/1200 s, half the inference step).
pub const SUBSTEPS_PER_UPDATE: u32 = 20;
/// Bearing friction of every static pulley, N·m: none, because the real video's cubes move as
/// frictionless 1 kg disc pulleys predict (within 1%); the simulator supports it.
pub const BEARING_FRICTION_NM: f64 = 0.0;
/// Before the change, a movable pulley drifting further than this makes the trial invalid, units.
const STABILITY_DRIFT: f64 = 0.9;
/// Before the change, a body faster than this makes the trial invalid, units/s.
const STABILITY_SPEED: f64 = 1.8;
/// A pulley faster than this makes the trial invalid, rad/s.
const MAX_ANGULAR_SPEED: f64 = 20.0;
/// Arc sampling of rope polylines, units.
const ARC_STEP: f64 = 0.25;

/// What a body of the mechanism is.
#[derive(Debug, Clone, PartialEq)]
pub enum BodyRole {
    /// A load (its index in `Layout::loads`).
    Load(usize),
    /// A movable pulley's frame.
    MovablePulley,
}

/// The layout's mechanism and where each named object sits in it.
#[derive(Debug, Clone)]
pub struct TruthModel {
    /// The network, with every load at its baseline mass.
    pub network: Network,
    /// Body index per name (loads and movable pulleys).
    pub bodies: IndexMap<String, usize>,
    /// What each body is.
    pub roles: Vec<BodyRole>,
    /// Pulley index per name.
    pub pulleys: IndexMap<String, usize>,
    /// Whether each pulley is solid (little) rather than hollow.
    pub solid: Vec<bool>,
    /// Fixed points: name, centre, whether on the ceiling.
    pub anchors: Vec<(String, [f64; 2], bool)>,
    /// Rope names, in network order (main cables, load connections, pulley–pulley cables).
    pub ropes: Vec<String>,
    /// For each rope, the path's element names (empty for an end tied to a pulley's axle).
    pub rope_elements: Vec<Vec<String>>,
    /// Per load (`Layout::loads` order): its body index.
    pub load_bodies: Vec<usize>,
    /// The baseline masses (kg) of the loads, `Layout::loads` order.
    pub baseline_kg: Vec<f64>,
}

/// The change a run makes at update 100.
#[derive(Debug, Clone, PartialEq)]
pub enum Change {
    /// Loads take these masses (kg, `Layout::loads` order).
    Masses(Vec<f64>),
    /// A static pulley or fixed point is moved.
    Pull {
        /// Its name.
        agent: String,
        /// Upwards.
        up: bool,
    },
}

/// One body and pulley configuration of a recorded frame.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameState {
    /// The mechanism's state.
    pub state: State,
    /// Rope centre lines (network rope order).
    pub ropes: Vec<Vec<[f64; 2]>>,
    /// Fixed-point centres (after any pull).
    pub anchors: Vec<[f64; 2]>,
    /// Static pulley centres (after any pull).
    pub pulley_centres: Vec<[f64; 2]>,
}

/// The outcome of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunResult {
    /// Names of pulleys, loads and fixed points → +1 up, −1 down, 0 (latched).
    pub motion: IndexMap<String, i8>,
    /// Pulleys → +1 clockwise as seen in the video, −1 anti-clockwise, 0 (latched).
    pub rotation: IndexMap<String, i8>,
    /// Rope tensions at the change, N (network rope order).
    pub tensions_at_change: Vec<f64>,
    /// Frames at updates 100, 102, … when recording.
    pub frames: Vec<FrameState>,
    /// Why the trial is invalid, if it is.
    pub invalid: Option<String>,
    /// Integration steps taken.
    pub steps: u64,
}

/// Builds the mechanism of `layout`.
pub fn build_truth(layout: &Layout) -> Result<TruthModel, SimulationError> {
    let mut model = TruthModel {
        network: Network::default(),
        bodies: IndexMap::new(),
        roles: Vec::new(),
        pulleys: IndexMap::new(),
        solid: Vec::new(),
        anchors: Vec::new(),
        ropes: Vec::new(),
        rope_elements: Vec::new(),
        load_bodies: vec![usize::MAX; layout.loads.len()],
        baseline_kg: layout
            .loads
            .iter()
            .map(|(_, multiplier)| world::BASELINE_MASS_KG * multiplier)
            .collect(),
    };
    // Pulleys first, so ends tied to any pulley can find it.
    add_pulleys(&mut model, layout);
    for rope in &layout.ropes {
        add_rope(&mut model, layout, rope)?;
        add_hanging_loads(&mut model, layout, rope)?;
    }
    add_cables(&mut model, layout)?;
    if model.load_bodies.contains(&usize::MAX) {
        return Err(missing("a load"));
    }
    for (load, &body) in model.load_bodies.iter().enumerate() {
        model.network.bodies[body].mass = model.baseline_kg[load];
    }
    Ok(model)
}

/// The index of load `name` in `Layout::loads`.
fn load_index(layout: &Layout, name: &str) -> Option<usize> {
    layout.loads.iter().position(|(n, _)| n == name)
}

/// Adds every pulley of the layout: static ones at their positions, movable ones on a body of
/// their own, with the release's radii, inertias and bearing friction.
fn add_pulleys(model: &mut TruthModel, layout: &Layout) {
    for rope in &layout.ropes {
        for element in rope.path.iter().filter(|e| e.is_pulley()) {
            let radius = world::wrap_radius(element.solid);
            let mount = if element.kind == ElementKind::MovablePulley {
                let body = add_body(
                    model,
                    &element.name,
                    world::MOVABLE_PULLEY_KG,
                    element.position,
                    None,
                    BodyRole::MovablePulley,
                );
                Mount::Body(body)
            } else {
                Mount::Fixed(element.position)
            };
            let (inertia, friction_torque) = if element.kind == ElementKind::StaticPulley {
                (
                    world::static_pulley_inertia(element.solid),
                    BEARING_FRICTION_NM,
                )
            } else {
                let disc = if element.solid {
                    world::SOLID_PULLEY_RADIUS
                } else {
                    world::HOLLOW_PULLEY_RADIUS
                };
                (0.5 * world::MOVABLE_PULLEY_KG * disc * disc, 0.0)
            };
            model.network.pulleys.push(Pulley {
                name: element.name.clone(),
                radius,
                inertia,
                friction_torque,
                mount,
            });
            model
                .pulleys
                .insert(element.name.clone(), model.network.pulleys.len() - 1);
            model.solid.push(element.solid);
        }
    }
}

/// Adds a main cable: its path's points (creating the end loads' bodies and the fixed points)
/// and how it turns round its pulleys.
fn add_rope(
    model: &mut TruthModel,
    layout: &Layout,
    rope: &LayoutRope,
) -> Result<(), SimulationError> {
    let last = rope.path.len() - 1;
    let mut path = Vec::with_capacity(rope.path.len());
    let mut names = Vec::with_capacity(rope.path.len());
    let mut turns = Vec::new();
    for (index, element) in rope.path.iter().enumerate() {
        let point = rope_point(model, layout, rope, index)?;
        if element.is_pulley() && index > 0 && index < last {
            turns.push((index, orientation(rope, index)));
        }
        path.push(point);
        names.push(element.name.clone());
    }
    let rope_index = model.network.ropes.len();
    for (position, turn) in turns {
        model.network.turns.push((rope_index, position, turn));
    }
    model.network.ropes.push(Rope {
        name: rope.name.clone(),
        path,
    });
    model.ropes.push(rope.name.clone());
    model.rope_elements.push(names);
    Ok(())
}

/// The network point of element `index` of `rope`, adding the body of an end load and the
/// anchor of a fixed point to `model`.
fn rope_point(
    model: &mut TruthModel,
    layout: &Layout,
    rope: &LayoutRope,
    index: usize,
) -> Result<Point, SimulationError> {
    let element = &rope.path[index];
    let last = rope.path.len() - 1;
    Ok(match element.kind {
        ElementKind::StaticPulley | ElementKind::MovablePulley => {
            let pulley = model.pulleys[&element.name];
            Point::Pulley(pulley)
        }
        ElementKind::FixedPoint(ceiling) => {
            model
                .anchors
                .push((element.name.clone(), element.position, ceiling));
            Point::Fixed(anchor_attachment(element.position))
        }
        ElementKind::Load => {
            // The load hangs straight under the rim of its pulley, on the side the layout
            // puts it.
            let neighbour = if index == 0 {
                &rope.path[1]
            } else {
                &rope.path[last - 1]
            };
            let side = (element.position[0] - neighbour.position[0]).signum();
            let x = neighbour.position[0] + side * world::wrap_radius(neighbour.solid);
            let load = load_index(layout, &element.name).ok_or_else(|| missing(&element.name))?;
            let body = add_body(
                model,
                &element.name,
                world::BASELINE_MASS_KG,
                [x, element.position[1]],
                Some(world::LOAD_HALF_HEIGHT),
                BodyRole::Load(load),
            );
            model.load_bodies[load] = body;
            Point::Body(body)
        }
        ElementKind::TiedToPulley => {
            let target = layout
                .ropes
                .iter()
                .flat_map(|r| r.path.iter())
                .find(|e| {
                    e.is_pulley() && element.target.is_some_and(|(x, y)| e.grid == Some((y, x)))
                })
                .ok_or_else(|| missing("the pulley a rope end is tied to"))?;
            Point::Pulley(model.pulleys[&target.name])
        }
    })
}

/// The load hanging under each movable pulley of `rope`, on its own rope from the pulley's
/// axle.
fn add_hanging_loads(
    model: &mut TruthModel,
    layout: &Layout,
    rope: &LayoutRope,
) -> Result<(), SimulationError> {
    for element in &rope.path {
        if let Some((load_name, connection)) = &element.hanging {
            let load = load_index(layout, load_name).ok_or_else(|| missing(load_name))?;
            let below = [
                element.position[0],
                element.position[1] - world::CONNECTION_DROP,
            ];
            let body = add_body(
                model,
                load_name,
                world::BASELINE_MASS_KG,
                below,
                Some(world::LOAD_HALF_HEIGHT),
                BodyRole::Load(load),
            );
            model.load_bodies[load] = body;
            model.network.ropes.push(Rope {
                name: connection.clone(),
                path: vec![
                    Point::Pulley(model.pulleys[&element.name]),
                    Point::Body(body),
                ],
            });
            model.ropes.push(connection.clone());
            model
                .rope_elements
                .push(vec![element.name.clone(), load_name.clone()]);
        }
    }
    Ok(())
}

/// Adds the pulley–pulley cables, each from the upper pulley's axle to the lower one's.
fn add_cables(model: &mut TruthModel, layout: &Layout) -> Result<(), SimulationError> {
    for cable in &layout.cables {
        let (Some(&upper), Some(&lower)) = (
            model.pulleys.get(&cable.upper),
            model.pulleys.get(&cable.lower),
        ) else {
            return Err(missing(&cable.name));
        };
        model.network.ropes.push(Rope {
            name: cable.name.clone(),
            path: vec![Point::Pulley(upper), Point::Pulley(lower)],
        });
        model.ropes.push(cable.name.clone());
        model
            .rope_elements
            .push(vec![cable.upper.clone(), cable.lower.clone()]);
    }
    Ok(())
}

fn missing(what: &str) -> SimulationError {
    SimulationError::InvalidParameter {
        object: what.to_string(),
        problem: "is not part of the layout's mechanism".to_string(),
    }
}

fn add_body(
    model: &mut TruthModel,
    name: &str,
    mass: f64,
    position: [f64; 2],
    floor_clearance: Option<f64>,
    role: BodyRole,
) -> usize {
    model.network.bodies.push(Body {
        name: name.to_string(),
        mass,
        position,
        floor_clearance,
    });
    model.roles.push(role);
    model
        .bodies
        .insert(name.to_string(), model.network.bodies.len() - 1);
    model.network.bodies.len() - 1
}

/// Where a fixed point holds its rope: 0.28 units above its centre.
pub fn anchor_attachment(centre: [f64; 2]) -> [f64; 2] {
    [centre[0], centre[1] + world::ANCHOR_ATTACH_HEIGHT]
}

/// The release's wrap rule (`FixOrientation`): counter-clockwise when layer parity and row
/// parity differ, flipped for a lower first or last pulley next to a load or a tied end.
fn orientation(rope: &LayoutRope, index: usize) -> Turn {
    let element = &rope.path[index];
    let layer = element.grid.map_or(0, |(layer, _)| layer);
    let layer_sign = if layer.rem_euclid(2) == 0 { 1 } else { -1 };
    let row_sign = if element.row % 2 == 0 { 1 } else { -1 };
    let mut counter_clockwise = layer_sign * row_sign == -1;
    let last = rope.path.len() - 1;
    if (index == last - 1 || index == 1) && element.row % 2 == 1 {
        let end = if index == last - 1 { last } else { 0 };
        if matches!(
            rope.path[end].kind,
            ElementKind::Load | ElementKind::TiedToPulley
        ) {
            counter_clockwise = !counter_clockwise;
        }
    }
    if counter_clockwise {
        Turn::CounterClockwise
    } else {
        Turn::Clockwise
    }
}

/// Simulates one run: baseline masses for 100 updates, `change`, then `updates_after` updates.
/// `record` keeps the frames at updates 100, 102, … (150 of them for the video);
/// `check_validity` applies the release's stability checks.
pub fn run(
    model: &TruthModel,
    change: &Change,
    updates_after: u32,
    record: usize,
    check_validity: bool,
    mirrored: bool,
) -> Result<RunResult, SimulationError> {
    let dt = world::UPDATE_SECONDS / f64::from(SUBSTEPS_PER_UPDATE);
    let before = Mechanism::new(model.network.clone())?;
    let mut state = before.initial_state();
    let start = state.clone();
    let mut steps = 0_u64;
    let mut invalid: Option<String> = None;
    for _ in 0..world::CHANGE_UPDATE {
        for _ in 0..SUBSTEPS_PER_UPDATE {
            before.step(&mut state, dt)?;
            steps += 1;
        }
    }
    if check_validity {
        invalid = unstable(model, &state, &start);
    }
    if invalid.is_some() {
        // The release discards the trial; nothing after the change matters.
        return Ok(RunResult {
            motion: IndexMap::new(),
            rotation: IndexMap::new(),
            tensions_at_change: state.tensions.clone(),
            frames: Vec::new(),
            invalid,
            steps,
        });
    }
    let tensions_at_change = state.tensions.clone();
    let (network, moved) = changed_network(model, change, state.time)?;
    let after = Mechanism::new(network)?;
    let mut latches = Latches::new(&state, invalid);
    let mut frames = Vec::with_capacity(record);
    for update in 0..=updates_after {
        if update > 0 {
            for _ in 0..SUBSTEPS_PER_UPDATE {
                after.step(&mut state, dt)?;
                steps += 1;
            }
            latches.observe(model, &state, check_validity);
            if latches.invalid.is_some() {
                break;
            }
        }
        if update % 2 == 0 && frames.len() < record {
            frames.push(frame_state(model, &after, &state));
        }
    }
    let mut result = RunResult {
        motion: IndexMap::new(),
        rotation: IndexMap::new(),
        tensions_at_change,
        frames,
        invalid: latches.invalid.take(),
        steps,
    };
    latches.report(&mut result, model, moved.as_ref(), mirrored);
    Ok(result)
}

/// The release's stability check before the change: the last movable pulley that drifted too
/// far or body that moved too fast, if any.
fn unstable(model: &TruthModel, state: &State, start: &State) -> Option<String> {
    let mut invalid = None;
    for (index, role) in model.roles.iter().enumerate() {
        let drift = (state.y[index] - start.y[index]).abs();
        if *role == BodyRole::MovablePulley && drift > STABILITY_DRIFT {
            invalid = Some(format!(
                "movable pulley `{}` drifted {drift:.2} units before the change",
                model.network.bodies[index].name
            ));
        }
        if state.v[index].abs() > STABILITY_SPEED {
            invalid = Some(format!(
                "`{}` moved at {:.2} units/s before the change",
                model.network.bodies[index].name,
                state.v[index].abs()
            ));
        }
    }
    invalid
}

/// The network after the change at `time` (s): loads with their new masses, or a static pulley
/// or fixed point driven up or down; with the pulled agent and its velocity.
fn changed_network(
    model: &TruthModel,
    change: &Change,
    time: f64,
) -> Result<(Network, Option<(String, f64)>), SimulationError> {
    let mut network = model.network.clone();
    let mut moved: Option<(String, f64)> = None;
    match change {
        Change::Masses(masses) => {
            for (load, &body) in model.load_bodies.iter().enumerate() {
                if let Some(mass) = masses.get(load) {
                    network.bodies[body].mass = *mass;
                }
            }
        }
        Change::Pull { agent, up } => {
            let (point, distance) = if let Some(&pulley) = model.pulleys.get(agent) {
                (DrivenPoint::Pulley(pulley), world::PULL_PULLEY_DISTANCE)
            } else if let Some((_, centre, _)) = model.anchors.iter().find(|(n, _, _)| n == agent) {
                (
                    DrivenPoint::Fixed(anchor_attachment(*centre)),
                    world::PULL_ANCHOR_DISTANCE,
                )
            } else {
                return Err(missing(agent));
            };
            let velocity = if *up {
                world::PULL_SPEED
            } else {
                -world::PULL_SPEED
            };
            network.drives.push(Drive {
                point,
                velocity,
                start: time,
                distance,
            });
            moved = Some((agent.clone(), velocity));
        }
    }
    Ok((network, moved))
}

/// What a run latches after the change: each body's and pulley's sign at its first threshold
/// crossing, and the first pulley too fast for a valid trial.
struct Latches {
    /// The release's outcome labels, latched from the change (shared with `--dynamics
    /// simulate`).
    labels: OutcomeLatch,
    /// Pulley angles at the previous update.
    previous_angles: Vec<f64>,
    /// Why the trial is invalid, if it is.
    invalid: Option<String>,
}

impl Latches {
    /// Nothing latched yet, from the state at the change.
    fn new(state: &State, invalid: Option<String>) -> Latches {
        Latches {
            labels: OutcomeLatch::new(&state.y, &state.angles),
            previous_angles: state.angles.clone(),
            invalid,
        }
    }

    /// Latches the motion and rotation of `state` (against the state at the change), and with
    /// `check_validity` notes a pulley turning faster than a valid trial allows.
    fn observe(&mut self, model: &TruthModel, state: &State, check_validity: bool) {
        self.labels.observe(&state.y, &state.angles);
        for (index, angle) in state.angles.iter().enumerate() {
            let speed = (angle - self.previous_angles[index]).abs() / world::UPDATE_SECONDS;
            if check_validity && speed > MAX_ANGULAR_SPEED && self.invalid.is_none() {
                self.invalid = Some(format!(
                    "pulley `{}` turned at {speed:.1} rad/s",
                    model.network.pulleys[index].name
                ));
            }
        }
        self.previous_angles.clone_from(&state.angles);
    }

    /// Writes the latched signs into `result` by name: pulleys (rope order; a static pulley
    /// moves only when `moved` pulls it, and `mirrored` cameras see rotations reversed), then
    /// the other bodies and fixed points.
    fn report(
        &self,
        result: &mut RunResult,
        model: &TruthModel,
        moved: Option<&(String, f64)>,
        mirrored: bool,
    ) {
        // The release lists pulleys (rope order), then the other bodies and fixed points.
        let moved_sign = |name: &str| -> i8 {
            moved
                .filter(|(agent, _)| agent == name)
                .map_or(0, |(_, velocity)| pulled_motion(*velocity))
        };
        for (name, &pulley) in &model.pulleys {
            let motion = match model.network.pulleys[pulley].mount {
                Mount::Body(body) => self.labels.motion(body),
                Mount::Fixed(_) => moved_sign(name),
            };
            result.motion.insert(name.clone(), motion);
            let turned = self.labels.rotation(pulley);
            result
                .rotation
                .insert(name.clone(), seen_rotation(turned, mirrored));
        }
        for (name, &body) in &model.bodies {
            if model.roles[body] != BodyRole::MovablePulley {
                result.motion.insert(name.clone(), self.labels.motion(body));
            }
        }
        for (name, _, _) in &model.anchors {
            result.motion.insert(name.clone(), moved_sign(name));
        }
    }
}

fn frame_state(model: &TruthModel, mechanism: &Mechanism, state: &State) -> FrameState {
    let network = mechanism.network();
    FrameState {
        state: state.clone(),
        ropes: (0..network.ropes.len())
            .map(|rope| mechanism.rope_polyline(rope, state, ARC_STEP))
            .collect(),
        anchors: model
            .anchors
            .iter()
            .map(|(_, centre, _)| {
                let attach = mechanism.position_of(Point::Fixed(anchor_attachment(*centre)), state);
                [attach[0], attach[1] - world::ANCHOR_ATTACH_HEIGHT]
            })
            .collect(),
        pulley_centres: (0..network.pulleys.len())
            .map(|pulley| mechanism.position_of(Point::Pulley(pulley), state))
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::super::layout::sample_layout;
    use super::*;
    use crate::util::seeded_rng;

    #[test]
    fn generated_mechanisms_simulate_and_report_every_object() {
        let mut rng = seeded_rng(3);
        let mut checked = 0;
        for _ in 0..10 {
            let (layout, _) = sample_layout(&mut rng).unwrap();
            let model = build_truth(&layout).unwrap();
            let masses: Vec<f64> = layout.masses_kg.clone();
            let result = run(&model, &Change::Masses(masses), 60, 3, true, true);
            let Ok(result) = result else {
                continue;
            };
            if result.invalid.is_some() {
                assert!(result.frames.is_empty(), "an invalid trial stops early");
                continue;
            }
            checked += 1;
            assert_eq!(result.frames.len(), 3);
            for (name, _) in &layout.loads {
                assert!(result.motion.contains_key(name), "{name}");
            }
            for name in model.pulleys.keys() {
                assert!(result.rotation.contains_key(name), "{name}");
            }
            for frame in &result.frames {
                assert!(frame.state.y.iter().all(|y| y.is_finite()));
                assert_eq!(frame.ropes.len(), model.ropes.len());
            }
        }
        assert!(checked >= 5, "most layouts simulate validly: {checked}/10");
    }
}
