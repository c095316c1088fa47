//! Rope–pulley scenes (`pulley_group`, `docs/data/rope.md`): layouts sampled as the release samples
//! them ([`layout`]), simulated with `physics::rope` through the release's timeline
//! ([`simulate`]), described for rendering and as 4-D data ([`scene`]), and assembled into the
//! release's `outputs.json` here.
//!
//! A trial the release would reject (a drifting movable pulley, a body or pulley too fast, a
//! mechanism the simulator refuses) is discarded and a new layout is sampled from the same RNG
//! stream, so a video's content depends only on its seed.

pub mod layout;
pub mod scene;
pub mod simulate;

use indexmap::IndexMap;
use rand_chacha::ChaCha8Rng;
use serde_json::{Map, Value, json};

use self::layout::{ElementKind, Layout, sample_layout};
use self::scene::{FIELD_PADDING, RopeScene, sample_camera};
use self::simulate::{Change, RunResult, TruthModel, build_truth, run};
use super::background::Wall;
use super::camera::frame_camera;
use super::raster::Light;
use super::shadow::RELEASE_SHADOW;
use super::{ScenarioSynth, SynthError, SynthesizedVideo};
use crate::dataset::Scenario;
use crate::dataset::rope::world;
use crate::perception::camera::CameraModel;
use crate::util::seeded_rng;

/// Frames of a rope video (updates 100–398, every second update).
pub const FRAMES: usize = 150;
/// Trials before giving up on a seed.
const MAX_TRIALS: u32 = 200;

/// The rope scenario's generator.
#[derive(Debug, Clone, Copy, Default)]
pub struct RopeSynth;

impl ScenarioSynth for RopeSynth {
    fn scenario(&self) -> Scenario {
        Scenario::Rope
    }

    fn synthesize(
        &self,
        seed: u64,
        width: u32,
        height: u32,
    ) -> Result<SynthesizedVideo, SynthError> {
        let mut rng = seeded_rng(seed);
        let mut rejected = 0_u32;
        let mut last = String::new();
        while rejected < MAX_TRIALS {
            match trial(&mut rng, width, height) {
                Ok(Trial::Valid(mut video)) => {
                    video.rejected_trials += rejected;
                    return Ok(*video);
                }
                Ok(Trial::Invalid { reason, layouts }) => {
                    rejected += 1 + layouts;
                    last = reason;
                }
                Err(reason) => {
                    rejected += 1;
                    last = reason;
                }
            }
        }
        Err(SynthError::NoValidScene {
            seed,
            attempts: rejected,
            last,
        })
    }
}

enum Trial {
    Valid(Box<SynthesizedVideo>),
    Invalid { reason: String, layouts: u32 },
}

fn trial(rng: &mut ChaCha8Rng, width: u32, height: u32) -> Result<Trial, String> {
    let (layout, layouts_rejected) =
        sample_layout(rng).ok_or_else(|| "no layout passed the release's checks".to_string())?;
    let camera_sample = sample_camera(rng);
    let model = build_truth(&layout).map_err(|e| e.to_string())?;
    let factual = run(
        &model,
        &Change::Masses(layout.masses_kg.clone()),
        world::FACTUAL_UPDATES_AFTER_CHANGE,
        FRAMES,
        true,
        camera_sample.mirrored,
    )
    .map_err(|e| e.to_string())?;
    if let Some(reason) = factual.invalid.clone() {
        return Ok(Trial::Invalid {
            reason,
            layouts: layouts_rejected,
        });
    }
    let scene = RopeScene::new(&model);
    let Some(first) = factual.frames.first() else {
        return Err("the factual run recorded no frames".into());
    };
    let camera = frame_camera(
        &camera_sample,
        scene.bounds(&model, first),
        FIELD_PADDING,
        width,
        height,
    );
    let mut steps = factual.steps;
    let counterfactuals =
        counterfactuals(&layout, &model, &camera, camera_sample.mirrored, &mut steps)
            .map_err(|e| e.to_string())?;
    let annotations = annotations(&layout, &model, &factual, &camera, camera_sample.mirrored);
    let mut trailing = Map::new();
    trailing.insert("CounterFactualAnnotations".into(), counterfactuals);
    let frames = factual
        .frames
        .iter()
        .map(|frame| scene.items(&model, frame))
        .collect();
    // The wall behind the scene (the release's room plane at z = ±1 on the far side).
    let wall_depth = if camera_sample.mirrored { 1.0 } else { -1.0 };
    let room: u64 = rand::Rng::random_range(rng, 0..2);
    let light_direction = {
        let toward_camera = if camera_sample.mirrored { -1.0 } else { 1.0 };
        let v: [f64; 3] = [-0.25, 0.4, toward_camera];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|c| c / n)
    };
    Ok(Trial::Valid(Box::new(SynthesizedVideo {
        four_d: scene.four_d(&model, &factual.frames),
        annotations,
        trailing,
        camera,
        light: Light {
            direction: light_direction,
            ambient: 0.45,
            diffuse: 0.7,
            specular: 0.25,
            shininess: 24.0,
        },
        wall: Wall {
            depth: wall_depth,
            color: if room == 0 {
                [0.80, 0.79, 0.76]
            } else {
                [0.76, 0.72, 0.66]
            },
            variant: room,
            frequency: 1.3,
            contrast: 0.3,
            grain: [3.0, 0.6],
        },
        shadow: RELEASE_SHADOW,
        labels: scene.labels(),
        id_to_name: scene.id_to_name(),
        first_step: 1,
        frames,
        rejected_trials: layouts_rejected,
        simulation_steps: steps,
    })))
}

fn round6(value: f64) -> f64 {
    (value * 1e6).round() / 1e6
}

fn camera_json(camera: &CameraModel, mirrored: bool) -> Value {
    json!({"Main Camera": {
        "position": camera.position.map(round6),
        "rotation": camera.euler_deg().map(round6),
        "fov": [round6(camera.vertical_fov_deg)],
        "mirrored": i32::from(mirrored),
    }})
}

fn signs(map: &IndexMap<String, i8>) -> Value {
    Value::Object(map.iter().map(|(k, v)| (k.clone(), json!(v))).collect())
}

fn negated(map: &IndexMap<String, i8>) -> Value {
    Value::Object(map.iter().map(|(k, v)| (k.clone(), json!(-v))).collect())
}

/// The factual keys of `outputs.json`, in the release's order.
fn annotations(
    layout: &Layout,
    model: &TruthModel,
    factual: &RunResult,
    camera: &CameraModel,
    mirrored: bool,
) -> Map<String, Value> {
    let mut out = Map::new();
    out.insert("validity".into(), json!(true));
    out.insert("mode".into(), json!("FACTUAL_PREDICTIVE_set_random_mass"));
    out.insert("FrameIndexToSetRandomMass".into(), json!(48));
    out.insert("relatedGroups".into(), json!(layout.related_groups));
    out.insert(
        "relatedGroupsInRope".into(),
        json!(layout.related_groups_in_rope),
    );
    out.insert("ResultRotation".into(), signs(&factual.rotation));
    out.insert("ResultMotion".into(), signs(&factual.motion));
    let mut tension = Map::new();
    let mut average = Map::new();
    for (rope, (name, elements)) in model.ropes.iter().zip(&model.rope_elements).enumerate() {
        // Joint impulse over dt, negative, one per consecutive pair of bodies on the rope.
        let value = -round6(factual.tensions_at_change.get(rope).copied().unwrap_or(0.0));
        let named: Vec<&String> = elements.iter().filter(|e| !e.is_empty()).collect();
        let pairs: Map<String, Value> = named
            .windows(2)
            .map(|w| (format!("({}, {})", w[0], w[1]), json!(value)))
            .collect();
        tension.insert(name.clone(), Value::Object(pairs));
        average.insert(name.clone(), json!(value));
    }
    out.insert("ResultTension".into(), Value::Object(tension));
    out.insert("ResultTensionAvg".into(), Value::Object(average));
    // Ropes keep their contacts (the simulator has fixed paths), so no rope attaches to or
    // detaches from a pulley after the video.
    let none: Map<String, Value> = model
        .ropes
        .iter()
        .map(|r| (r.clone(), json!("None")))
        .collect();
    out.insert("PredictiveEventType".into(), Value::Object(none.clone()));
    out.insert("PredictiveEventPulleyName".into(), Value::Object(none));
    out.insert("metaSamplingData".into(), layout.meta.clone());
    out.insert("outputMass".into(), mass_json(layout, &layout.masses_kg));
    out.insert("outputCamera".into(), camera_json(camera, mirrored));
    out
}

fn mass_json(layout: &Layout, masses: &[f64]) -> Value {
    Value::Object(
        layout
            .loads
            .iter()
            .zip(masses)
            .map(|((name, _), m)| (name.clone(), json!(round6(*m))))
            .collect(),
    )
}

/// The counterfactual records: a pull of every static pulley and fixed point of a group with
/// exactly one load, then a lighter run for every load; each with its mirror (the opposite
/// change, every sign negated, never simulated, `docs/data/rope.md`, timeline and outcome labels).
fn counterfactuals(
    layout: &Layout,
    model: &TruthModel,
    camera: &CameraModel,
    mirrored: bool,
    steps: &mut u64,
) -> Result<Value, crate::physics::rope::SimulationError> {
    let mut records = Map::new();
    let camera_value = camera_json(camera, mirrored);
    let baseline = mass_json(layout, &model.baseline_kg);
    let elements: Vec<&layout::Element> = layout.ropes.iter().flat_map(|r| r.path.iter()).collect();
    let mut pulled: Vec<String> = Vec::new();
    for group in &layout.related_groups {
        let loads = group
            .iter()
            .filter(|n| layout.loads.iter().any(|(l, _)| l == *n))
            .count();
        if loads != 1 {
            continue;
        }
        for name in group {
            if pulled.contains(name) {
                continue;
            }
            let Some(element) = elements.iter().find(|e| e.name == *name) else {
                continue;
            };
            let up = match element.kind {
                ElementKind::FixedPoint(ceiling) => ceiling,
                // An upper static pulley is pulled down, a lower one up.
                ElementKind::StaticPulley => element.row % 2 == 1,
                _ => continue,
            };
            pulled.push(name.clone());
            let result = run(
                model,
                &Change::Pull {
                    agent: name.clone(),
                    up,
                },
                world::COUNTERFACTUAL_UPDATES_AFTER_CHANGE,
                0,
                false,
                mirrored,
            )?;
            *steps += result.steps;
            let entry = |direction: &str, flip: bool| {
                json!({
                    "mode": "COUNTERFACTUAL_pull_object_up_or_down",
                    "TargetMovingAgent": {"name": name, "direction": direction, "onAllStaticRope": "False"},
                    "ResultRotation": if flip { negated(&result.rotation) } else { signs(&result.rotation) },
                    "ResultMotion": if flip { negated(&result.motion) } else { signs(&result.motion) },
                })
            };
            let (direction, opposite) = if up { ("up", "down") } else { ("down", "up") };
            records.insert(
                records.len().to_string(),
                json!({
                    "0": entry(direction, false),
                    "1": entry(opposite, true),
                    "outputMass": baseline.clone(),
                    "outputCamera": camera_value.clone(),
                }),
            );
        }
    }
    for (load, (name, multiplier)) in layout.loads.iter().enumerate() {
        let before = model.baseline_kg[load];
        let after = before - world::COUNTERFACTUAL_MASS_STEP_KG * multiplier;
        let mut masses = model.baseline_kg.clone();
        masses[load] = after;
        let result = run(
            model,
            &Change::Masses(masses),
            world::COUNTERFACTUAL_UPDATES_AFTER_CHANGE,
            0,
            false,
            mirrored,
        )?;
        *steps += result.steps;
        let entry = |to: f64, flip: bool| {
            json!({
                "mode": "COUNTERFACTUAL_change_one_object_mass",
                "TargetObj_Name": name,
                "TargetObj_Mass_Before_After": {"Item1": round6(before), "Item2": round6(to)},
                "ResultRotation": if flip { negated(&result.rotation) } else { signs(&result.rotation) },
                "ResultMotion": if flip { negated(&result.motion) } else { signs(&result.motion) },
            })
        };
        records.insert(
            records.len().to_string(),
            json!({
                "0": entry(after, false),
                "1": entry(2.0 * before - after, true),
                "outputMass": baseline.clone(),
                "outputCamera": camera_value.clone(),
            }),
        );
    }
    Ok(Value::Object(records))
}
