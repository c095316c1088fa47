//! Fluid scenes (`fluid_slides`, `FORMAT.md` §3, `docs/data/fluid.md`): layouts sampled as the
//! release samples them ([`layout`]), simulated through the release's timeline with position-based
//! fluids ([`simulate`]), counted into its tracking statistics ([`tracking`]), described for
//! rendering and as 4-D data ([`scene`]), and assembled into the release's `outputs.json` here,
//! with one counterfactual run per stick the release would remove.
//!
//! Frames: the release encoded its video from image step 2 (248 frames of 250 captures); here
//! every one of the 250 captures is a video frame and `perFrameAnnotations` keys run from 1, so
//! video frame `j`, annotation step `j + 1` and 4-D index `j` are the same instant (update
//! `2j + 2`), as in the rope scenario.

pub mod layout;
pub mod scene;
pub mod simulate;
pub mod tracking;

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde_json::{Map, Value, json};

use self::layout::{
    Layout, ORIGIN, ROOM_ABOVE, ROOM_BELOW, SIDE_CLEARANCE, STICK_SCALE, Stick, TANK,
    WALL_THICKNESS, sample_layout,
};
use self::scene::FluidView;
use self::simulate::{FluidScene, RunKind, Timeline, run};
use self::tracking::track;
use super::annotate::names_by_id;
use super::background::Wall;
use super::camera::{CameraSample, frame_camera, truncated_normal};
use super::raster::Light;
use super::shadow::RELEASE_SHADOW;
use super::unity::{camera_json, round, vector3};
use super::{ScenarioSynth, SynthError, SynthesizedVideo, first_valid_trial};
use crate::dataset::Scenario;
use crate::util::derive_seed;

/// Trials before giving up on a seed (a trial fails only when the solver does).
const MAX_TRIALS: u32 = 20;
/// Padding round the scene when the camera is framed, units (`field_paddings`).
const FIELD_PADDING: f64 = 1.0;

/// The fluid scenario's generator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FluidSynth {
    /// The timeline its trials run through.
    pub timeline: Timeline,
}

/// The generator with the release's timeline, as the scenario table lists it.
pub static FLUID_SYNTH: FluidSynth = FluidSynth {
    timeline: Timeline::RELEASE,
};

impl ScenarioSynth for FluidSynth {
    fn scenario(&self) -> Scenario {
        Scenario::Fluid
    }

    fn synthesize(
        &self,
        seed: u64,
        width: u32,
        height: u32,
    ) -> Result<SynthesizedVideo, SynthError> {
        first_valid_trial(seed, MAX_TRIALS, |rng| {
            trial(rng, seed, &self.timeline, width, height)
        })
    }
}

/// The release's light: Euler x in U(−20, 10)°, y in U(−50, 50)°.
fn sample_light(rng: &mut ChaCha8Rng) -> [f64; 3] {
    [
        rng.random_range(-20.0..10.0),
        rng.random_range(-50.0..50.0),
        0.0,
    ]
}

/// The release's camera draw (`CameraRandomizer` with the fluid settings): azimuth U(−1.65,
/// −1.50) rad, elevation N(0, π/30) within ±π/30, distance 10, vertical field of view
/// U(50°, 60°), round the background's centre; the camera sits at −z.
fn sample_camera(rng: &mut ChaCha8Rng) -> CameraSample {
    let look_at = [0.0, -0.575, 0.5];
    let azimuth: f64 = rng.random_range(-1.65..-1.50);
    let limit = std::f64::consts::PI / 30.0;
    let elevation = truncated_normal(rng, 0.0, limit, -limit, limit);
    let distance = 10.0;
    CameraSample {
        position: [
            look_at[0] + distance * elevation.cos() * azimuth.cos(),
            look_at[1] + distance * elevation.sin(),
            look_at[2] + distance * elevation.cos() * azimuth.sin(),
        ],
        vertical_fov_deg: rng.random_range(50.0..60.0),
        mirrored: true,
    }
}

fn trial(
    rng: &mut ChaCha8Rng,
    seed: u64,
    timeline: &Timeline,
    width: u32,
    height: u32,
) -> Result<SynthesizedVideo, String> {
    let layout = sample_layout(rng);
    let light_euler = sample_light(rng);
    let camera_sample = sample_camera(rng);
    let scene = FluidScene::new(&layout);
    // One emitter stream per video: every run draws the same emission velocities, so a
    // counterfactual run differs from the factual one only by what it removes.
    let emission_seed = derive_seed(seed, "synth/fluid/emission");
    let factual = run(&layout, &scene, RunKind::Factual, timeline, emission_seed)
        .map_err(|e| e.to_string())?;
    let tracking = track(&layout, &scene, &factual, None);
    let view = FluidView::new(&layout, &scene);
    let camera = frame_camera(&camera_sample, view.bounds(), FIELD_PADDING, width, height);
    let mut steps = factual.updates as u64;
    let mut counterfactuals = Map::new();
    for (index, stick) in tracking.sticks_to_remove(rng).iter().enumerate() {
        let without = run(
            &layout,
            &scene,
            RunKind::Without(stick),
            timeline,
            emission_seed,
        )
        .map_err(|e| format!("without {stick}: {e}"))?;
        steps += without.updates as u64;
        let changed = track(&layout, &scene, &without, Some(stick));
        counterfactuals.insert(
            index.to_string(),
            json!({
                "mode": "COUNTERFACTUAL_",
                "trackingData": changed.to_json(),
                "removedStickName": stick,
                "outputLight": light_json(light_euler),
                "outputCamera": camera_json(&camera),
            }),
        );
    }
    let mut annotations = Map::new();
    annotations.insert("validity".into(), json!(true));
    annotations.insert("mode".into(), json!("FACTUAL_PREDICTIVE"));
    annotations.insert("trackingData".into(), tracking.to_json());
    annotations.insert("metaSamplingData".into(), meta_json(&layout, timeline));
    annotations.insert("allObjectTransforms".into(), transforms_json(&scene));
    annotations.insert("outputLight".into(), light_json(light_euler));
    annotations.insert("outputCamera".into(), camera_json(&camera));
    let mut trailing = Map::new();
    trailing.insert(
        "CounterFactualAnnotations".into(),
        Value::Object(counterfactuals),
    );
    let frames = factual
        .frames
        .iter()
        .map(|positions| view.items(&factual, positions))
        .collect();
    let labels = view.labels();
    let id_to_name = names_by_id(&labels);
    Ok(SynthesizedVideo {
        four_d: view.four_d(&factual),
        annotations,
        trailing,
        camera,
        light: light_from_euler(light_euler),
        wall: Wall {
            depth: 0.5,
            color: [0.86, 0.86, 0.84],
            variant: 0,
            frequency: 1.3,
            contrast: 0.2,
            grain: [3.0, 0.6],
        },
        shadow: RELEASE_SHADOW,
        labels,
        id_to_name,
        first_step: 1,
        frames,
        rejected_trials: 0,
        simulation_steps: steps,
    })
}

/// The renderer's light for the release's light Euler angles: y turns it sideways, and it always
/// comes from above and from the camera's side (−z). The release's directional light pointed
/// into the scene with x between −20° and 10°; the `|sin x| + 0.3` lift keeps the light above the
/// horizon for every draw, so no sampled light leaves the sticks' tops unlit (a choice of this
/// renderer, which has no sky light).
fn light_from_euler(euler_deg: [f64; 3]) -> Light {
    let (x, y) = (euler_deg[0].to_radians(), euler_deg[1].to_radians());
    let direction = [
        -(y.sin() * x.cos()),
        x.sin().abs() + 0.3,
        -(y.cos() * x.cos()),
    ];
    let length = direction.iter().map(|c| c * c).sum::<f64>().sqrt();
    Light {
        direction: direction.map(|c| c / length),
        ambient: 0.5,
        diffuse: 0.6,
        specular: 0.2,
        shininess: 24.0,
    }
}

fn light_json(euler_deg: [f64; 3]) -> Value {
    json!({"Prefabs/Fluid Slides/Directional Light": {"rotation": euler_deg.map(|c| round(c, 4))}})
}

/// A stick's `GetAll()` (local coordinates).
fn stick_json(stick: &Stick) -> Value {
    let centre = [
        f64::midpoint(stick.start[0], stick.end[0]),
        f64::midpoint(stick.start[1], stick.end[1]),
        0.0,
    ];
    let slope_deg = ((stick.start[1] - stick.end[1]) / (stick.start[0] - stick.end[0]))
        .atan()
        .to_degrees();
    json!({
        "name": stick.name,
        "color": stick.color,
        "temperature": "Normal",
        "isRotatable": stick.rotatable,
        "position": vector3(centre),
        "rotation": vector3([0.0, 0.0, slope_deg]),
        "scale": vector3([stick.length(), STICK_SCALE[0], STICK_SCALE[1]]),
        "startP": {"Item1": round(stick.start[0], 6), "Item2": round(stick.start[1], 6)},
        "endP": {"Item1": round(stick.end[0], 6), "Item2": round(stick.end[1], 6)},
        "length": round(stick.length(), 6),
        "angleRad": round(stick.angle(), 6),
    })
}

/// `metaSamplingData`: the tank, sticks, containers and fluids as the release's sampler lists
/// them.
fn meta_json(layout: &Layout, timeline: &Timeline) -> Value {
    let lower = -TANK[1] / 2.0;
    let pos_y_vert = lower / 2.0 + ROOM_ABOVE / 2.0 - ROOM_BELOW / 2.0;
    let container = json!({
        "size": [TANK[0], TANK[1], 1.0],
        "centre_location": [0.0, 0.0, 0.0],
        "lowerLimitY": lower,
        "wall_thickness": WALL_THICKNESS,
        "O_x": ORIGIN[0],
        "O_y": ORIGIN[1],
        "pos_x_vert1": -TANK[0] / 2.0 - WALL_THICKNESS / 2.0 - SIDE_CLEARANCE,
        "pos_x_vert2": TANK[0] / 2.0 + WALL_THICKNESS / 2.0 + SIDE_CLEARANCE,
        "pos_y_vert1": round(pos_y_vert, 6),
        "pos_y_vert2": round(pos_y_vert, 6),
        "pos_x_hori1": 0.0,
        "pos_x_hori2": 0.0,
        "pos_y_hori1": -TANK[1] / 2.0 + lower - WALL_THICKNESS / 2.0 - ROOM_BELOW,
        "pos_y_hori2": TANK[1] / 2.0 + WALL_THICKNESS / 2.0 + ROOM_ABOVE,
        "pos_z": 0.0,
        "scl_x_vert": WALL_THICKNESS,
        "scl_y_vert": 2.0 * WALL_THICKNESS + ROOM_BELOW + ROOM_ABOVE - lower + TANK[1],
        "scl_x_hori": TANK[0] + 2.0 * SIDE_CLEARANCE,
        "scl_y_hori": WALL_THICKNESS,
        "scl_z": STICK_SCALE[1],
    });
    let reservoirs: Vec<Value> = layout
        .containers
        .iter()
        .map(|c| {
            json!({
                "name": c.name,
                "color": c.color,
                "cupPosition": vector3([c.position[0], c.position[1], 0.0]),
                "cupScale": vector3([c.scale[0], c.scale[1], STICK_SCALE[1]]),
                "stickLeft": stick_json(&c.left),
                "stickRight": stick_json(&c.right),
            })
        })
        .collect();
    let fluids: Vec<Value> = layout
        .fluids
        .iter()
        .map(|f| {
            let later = f.later_emitter.unwrap_or([0.0, 0.0]);
            json!({
                "name": f.name,
                "color": f.color,
                "density": f.density,
                "viscosity": f.viscosity_word(),
                "viscositiesUnderTemperature": f.viscosity(),
                "surfaceTension": f.surface_tension,
                "amount": timeline.capacity,
                "emitter_pos": vector3([f.emitter[0], f.emitter[1], 0.0]),
                "hasPredEmitter": f.later_emitter.is_some(),
                "pred_emitter_pos": vector3([later[0], later[1], 0.0]),
                "pred_emitter_color": if f.later_emitter.is_some() {
                    i64::try_from(f.color).unwrap_or(-1)
                } else {
                    -1
                },
            })
        })
        .collect();
    json!({
        "container": container,
        "sticks": layout.sticks.iter().map(stick_json).collect::<Vec<_>>(),
        "reservoirs": reservoirs,
        "fluids": fluids,
    })
}

/// `allObjectTransforms`: every collider's pose (centre, Euler z in [0, 360), scale).
fn transforms_json(scene: &FluidScene) -> Value {
    let mut out = Map::new();
    for named in &scene.colliders {
        let c = &named.collider;
        let centre = [
            f64::midpoint(c.start[0], c.end[0]),
            f64::midpoint(c.start[1], c.end[1]),
            0.0,
        ];
        let angle = (c.end[1] - c.start[1])
            .atan2(c.end[0] - c.start[0])
            .to_degrees()
            .rem_euclid(180.0);
        let length = (c.end[0] - c.start[0]).hypot(c.end[1] - c.start[1]);
        out.insert(
            named.name.clone(),
            json!({
                "position": centre.map(|v| round(v, 5)),
                "rotation": [0.0, 0.0, round(angle, 4)],
                "scale": [round(length, 5), round(2.0 * c.half_thickness, 5), STICK_SCALE[1]],
            }),
        );
    }
    Value::Object(out)
}
