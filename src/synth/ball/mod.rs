//! Ball scenes (`soft_body`, `FORMAT.md` §5, `docs/data/ball.md`): layouts sampled as the
//! release samples them ([`layout`]), simulated with shape-matching soft bodies through the
//! release's timeline ([`simulate`]), described for rendering and as 4-D data ([`scene`]), and
//! assembled into the release's `outputs.json` here, with the six counterfactual runs (each
//! floating wall removed, each ball alone).
//!
//! Frames: the release captured updates 0 to 240 (120 sensor frames) and encoded its video from
//! image step 2; here every one of the 120 captures is a video frame and `perFrameAnnotations`
//! keys run from 1, so video frame `j`, annotation step `j + 1` and 4-D index `j` are the same
//! instant (update `2j + 2`), as in the other generated scenarios.

pub mod layout;
pub mod scene;
pub mod simulate;

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde_json::{Map, Value, json};

use self::layout::{Layout, SlabLayout, sample_layout};
use self::scene::BallView;
use self::simulate::{BallRun, RunKind, run};
use super::annotate::names_by_id;
use super::background::Wall;
use super::camera::truncated_normal;
use super::shadow::RELEASE_SHADOW;
use super::unity::{camera_json, light_from_euler, round, sample_light, vector3};
use super::{ScenarioSynth, SynthError, SynthesizedVideo, first_valid_trial};
use crate::dataset::Scenario;
use crate::dataset::ball::outcome::PitRecord;
use crate::perception::camera::CameraModel;

/// Trials before giving up on a seed (a trial fails only when the solver does).
const MAX_TRIALS: u32 = 20;
/// The point the camera looks at, units: the middle of the stadium between the floor and the balls' release heights.
const LOOK_AT: [f64; 3] = [0.0, 3.4, 0.0];
/// The camera's distance, units.
const CAMERA_DISTANCE: f64 = 16.0;
/// The light's object name in `outputLight`.
const LIGHT_NAME: &str = "Prefabs/Soft Body/Directional Light";

/// The ball scenario's generator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BallSynth;

/// The generator, as the scenario table lists it.
pub static BALL_SYNTH: BallSynth = BallSynth;

impl ScenarioSynth for BallSynth {
    fn scenario(&self) -> Scenario {
        Scenario::Ball
    }

    fn synthesize(
        &self,
        seed: u64,
        width: u32,
        height: u32,
    ) -> Result<SynthesizedVideo, SynthError> {
        first_valid_trial(seed, MAX_TRIALS, |rng| trial(rng, width, height))
    }
}

/// The release's camera draw (`CameraRandomizer` with the ball settings): azimuth
/// U(−π/2 ± 0.04) rad, elevation N(0, π/6) truncated to [π/10, π/6], distance 16, vertical field
/// of view U(30°, 35°); not re-framed. The camera sits at −z looking at [`LOOK_AT`].
fn sample_camera(rng: &mut ChaCha8Rng, width: u32, height: u32) -> CameraModel {
    let half_pi = std::f64::consts::FRAC_PI_2;
    let azimuth: f64 = rng.random_range(-half_pi - 0.04..-half_pi + 0.04);
    let pi = std::f64::consts::PI;
    let elevation = truncated_normal(rng, 0.0, pi / 6.0, pi / 10.0, pi / 6.0);
    let fov = rng.random_range(30.0..35.0);
    let position = [
        LOOK_AT[0] + CAMERA_DISTANCE * elevation.cos() * azimuth.cos(),
        LOOK_AT[1] + CAMERA_DISTANCE * elevation.sin(),
        LOOK_AT[2] + CAMERA_DISTANCE * elevation.cos() * azimuth.sin(),
    ];
    CameraModel::looking_at(position, LOOK_AT, fov, width, height)
}

fn trial(rng: &mut ChaCha8Rng, width: u32, height: u32) -> Result<SynthesizedVideo, String> {
    let layout = sample_layout(rng).ok_or("no floating-wall layout fitted")?;
    let light_euler = sample_light(rng);
    let camera = sample_camera(rng, width, height);
    let factual = run(&layout, RunKind::Factual).map_err(|e| e.to_string())?;
    let mut steps = factual.updates as u64;
    let mut counterfactuals = Map::new();
    let mut key = 0;
    for wall in 0..layout.floating_walls.len() {
        for ball in 0..layout.balls.len() {
            let alone = run(&layout, RunKind::Counterfactual { wall, ball })
                .map_err(|e| format!("without wall {wall}, ball {ball} alone: {e}"))?;
            steps += alone.updates as u64;
            let record = alone
                .records
                .first()
                .copied()
                .ok_or("a run without its ball")?;
            counterfactuals.insert(
                key.to_string(),
                json!({
                    "mode": "COUNTERFACTUAL_",
                    "trackingData": {"onlyThatBall": pit_json(record)},
                    "removedWall": layout.floating_walls[wall].name,
                    "ball": layout.balls[ball].name,
                    "outputLight": light_json(light_euler),
                    "outputCamera": camera_json(&camera),
                }),
            );
            key += 1;
        }
    }
    let view = BallView::new(&layout);
    let mut annotations = Map::new();
    annotations.insert("validity".into(), json!(true));
    annotations.insert("mode".into(), json!("FACTUAL_PREDICTIVE"));
    annotations.insert("trackingData".into(), tracking_json(&layout, &factual));
    annotations.insert("metaSamplingData".into(), meta_json(&layout));
    annotations.insert("allObjectTransforms".into(), transforms_json(&layout));
    annotations.insert("outputLight".into(), light_json(light_euler));
    annotations.insert("outputCamera".into(), camera_json(&camera));
    let mut trailing = Map::new();
    trailing.insert(
        "CounterFactualAnnotations".into(),
        Value::Object(counterfactuals),
    );
    let frames = (0..factual.frames.len())
        .map(|frame| view.items(&factual, frame))
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
            depth: 1.5,
            color: [0.82, 0.83, 0.85],
            variant: 0,
            frequency: 0.8,
            contrast: 0.15,
            grain: [1.0, 1.0],
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

fn pit_json(record: PitRecord) -> Value {
    json!({"pitResult": record.result.as_str(), "pitFrame": record.frame})
}

fn tracking_json(layout: &Layout, factual: &BallRun) -> Value {
    let mut out = Map::new();
    for (&index, record) in factual.balls.iter().zip(&factual.records) {
        if let Some(ball) = layout.balls.get(index) {
            out.insert(ball.name.clone(), pit_json(*record));
        }
    }
    Value::Object(out)
}

fn light_json(euler_deg: [f64; 3]) -> Value {
    json!({LIGHT_NAME: {"rotation": euler_deg.map(|c| round(c, 4))}})
}

/// A slab's `GetAll()`, in world coordinates.
fn slab_json(slab: &SlabLayout) -> Value {
    let centre = [
        f64::midpoint(slab.start[0], slab.end[0]),
        f64::midpoint(slab.start[1], slab.end[1]),
        0.0,
    ];
    json!({
        "name": slab.name,
        "color": slab.color,
        "position": vector3(centre),
        "rotation": vector3([0.0, 0.0, slab.angle().to_degrees().rem_euclid(360.0)]),
        "scale": vector3([slab.length(), slab.thickness, layout::SLAB_DEPTH]),
        "startP": {"Item1": round(slab.start[0], 6), "Item2": round(slab.start[1], 6)},
        "endP": {"Item1": round(slab.end[0], 6), "Item2": round(slab.end[1], 6)},
        "length": round(slab.length(), 6),
        "angleRad": round(slab.angle(), 6),
    })
}

/// `metaSamplingData`.
fn meta_json(layout: &Layout) -> Value {
    let balls: Vec<Value> = layout
        .balls
        .iter()
        .map(|ball| {
            json!({
                "name": ball.name,
                "color": ball.color,
                "elasticityType": ball.elasticity.as_str(),
                "releasePos": ball.release.map(|c| round(c, 6)),
            })
        })
        .collect();
    json!({
        "ramps": layout.ramps.iter().map(slab_json).collect::<Vec<_>>(),
        "floorPieces": layout.floor_pieces.iter().map(slab_json).collect::<Vec<_>>(),
        "balls": balls,
        "floatingWalls": layout.floating_walls.iter().map(slab_json).collect::<Vec<_>>(),
        "holesCenterXValue": layout.pits.map(|x| round(x, 6)),
    })
}

/// `allObjectTransforms`: every slab's pose (centre, Euler z in [0, 360), scale).
fn transforms_json(layout: &Layout) -> Value {
    let mut out = Map::new();
    for slab in layout.slabs() {
        let centre = [
            f64::midpoint(slab.start[0], slab.end[0]),
            f64::midpoint(slab.start[1], slab.end[1]),
            0.0,
        ];
        out.insert(
            slab.name.clone(),
            json!({
                "position": centre.map(|v| round(v, 5)),
                "rotation": [0.0, 0.0, round(slab.angle().to_degrees().rem_euclid(360.0), 4)],
                "scale": [round(slab.length(), 5), round(slab.thickness, 5), layout::SLAB_DEPTH],
            }),
        );
    }
    Value::Object(out)
}

#[cfg(test)]
mod tests;
