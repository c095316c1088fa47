//! Cloth scenes (`cloth_collision`, `FORMAT.md` §4, `docs/data/cloth.md`): layouts drawn as
//! the release draws them ([`layout`]), each half simulated through the release's timeline on
//! the XPBD cloth-and-boxes solver ([`simulate`]), described for rendering and as 4-D data
//! ([`scene`]), and assembled into the release's `outputs.json` here through the cloth
//! annotation's own writer, so what is written is what the reader reads.
//!
//! Frames: the release captured 145 images, one every second update from 0 to 288; here each of
//! them is a video frame and `perFrameAnnotations` keys run from 1, so video frame `j`,
//! annotation step `j + 1` and update `2j` are the same instant. The 4-D data starts at update
//! 60, when the cloth spawns (115 frames), as the release's does.

pub mod layout;
pub mod scene;
pub mod simulate;

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde_json::{Map, json};

use self::layout::{HalfLayout, Layout, sample_layout};
use self::scene::ClothView;
use self::simulate::{BoxOutcome, HalfRun, box_body, run_half};
use super::annotate::names_by_id;
use super::background::Wall;
use super::camera::{CameraSample, frame_camera, truncated_normal};
use super::shadow::RELEASE_SHADOW;
use super::unity::{camera_json, light_from_euler, sample_light, unity_euler_degrees};
use super::{ScenarioSynth, SynthError, SynthesizedVideo, first_valid_trial};
use crate::dataset::Scenario;
use crate::dataset::cloth::outcome::Pose;
use crate::dataset::cloth::{
    BoxRecord, ClothAnnotation, ClothProperties, CollisionEvent, HalfObjects, RegionForces,
};
use crate::perception::camera::CameraModel;
use crate::physics::vector3::{apply, rotation_matrix};

/// Trials before giving up on a seed (a trial fails when placement or the solver does).
const MAX_TRIALS: u32 = 20;
/// The release's validity check: no box may start more than this far from its sampled height.
const START_HEIGHT_TOLERANCE: f64 = 0.4;

/// The cloth scenario's generator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ClothSynth;

/// The generator, as the scenario table lists it.
pub static CLOTH_SYNTH: ClothSynth = ClothSynth;

impl ScenarioSynth for ClothSynth {
    fn scenario(&self) -> Scenario {
        Scenario::Cloth
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

/// The release's camera (`CameraRandomizer` with the cloth settings): azimuth −90°, elevation
/// 30°, distance N(11, 1) within [10, 12], vertical field of view U(30°, 40°), then re-framed on
/// all the objects with no padding.
fn sample_camera(rng: &mut ChaCha8Rng, layout: &Layout, width: u32, height: u32) -> CameraModel {
    let distance = truncated_normal(rng, 11.0, 1.0, 10.0, 12.0);
    let fov = rng.random_range(30.0..40.0);
    let elevation = 30.0_f64.to_radians();
    let position = [0.0, distance * elevation.sin(), -distance * elevation.cos()];
    let mut low = [f64::INFINITY; 3];
    let mut high = [f64::NEG_INFINITY; 3];
    for half in &layout.halves {
        for index in 0..half.boxes.len() {
            let Some(body) = box_body(half, index) else {
                continue;
            };
            for corner in body.corners() {
                for axis in 0..3 {
                    low[axis] = low[axis].min(corner[axis]);
                    high[axis] = high[axis].max(corner[axis]);
                }
            }
        }
    }
    let sample = CameraSample {
        position,
        vertical_fov_deg: fov,
        mirrored: true,
    };
    frame_camera(&sample, (low, high), 0.0, width, height)
}

/// A cloth's random texture colour: a soft, light tint.
fn cloth_color(rng: &mut ChaCha8Rng) -> [f64; 3] {
    let hue: f64 = rng.random_range(0.0..6.0);
    let (saturation, value) = (0.35, 0.9);
    let chroma = saturation * value;
    let x = chroma * (1.0 - (hue % 2.0 - 1.0).abs());
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "the hue is in [0, 6)"
    )]
    let [r, g, b] = match hue as u32 {
        0 => [chroma, x, 0.0],
        1 => [x, chroma, 0.0],
        2 => [0.0, chroma, x],
        3 => [0.0, x, chroma],
        4 => [x, 0.0, chroma],
        _ => [chroma, 0.0, x],
    };
    let base = value - chroma;
    [r + base, g + base, b + base]
}

fn trial(rng: &mut ChaCha8Rng, width: u32, height: u32) -> Result<SynthesizedVideo, String> {
    let layout = sample_layout(rng).ok_or("the objects could not be placed")?;
    let light_euler = sample_light(rng);
    let camera = sample_camera(rng, &layout, width, height);
    let colors = [cloth_color(rng), cloth_color(rng)];
    let [left, right] = &layout.halves;
    let runs = [
        run_half(left).map_err(|e| format!("left half: {e}"))?,
        run_half(right).map_err(|e| format!("right half: {e}"))?,
    ];
    check_start_heights(&layout, &runs)?;
    let annotation = annotation(&layout, &runs);
    let mut annotations = annotation.scenario_keys();
    annotations.insert("outputCamera".into(), camera_json(&camera));
    let mut trailing = Map::new();
    trailing.insert("CounterFactualAnnotations".into(), json!({}));
    let view = ClothView::new(&layout, colors);
    let frames = (0..runs[0].frames.len())
        .map(|frame| view.items(&runs, frame))
        .collect();
    let labels = view.labels();
    let id_to_name = names_by_id(&labels);
    Ok(SynthesizedVideo {
        four_d: view.four_d(&layout, &runs),
        annotations,
        trailing,
        camera,
        light: light_from_euler(light_euler),
        wall: Wall {
            depth: 6.0,
            color: [0.8, 0.8, 0.78],
            variant: 0,
            frequency: 0.8,
            contrast: 0.15,
            grain: [1.0, 1.0],
        },
        // The table, not a wall, lies behind the objects: no drop shadow on the wall.
        shadow: super::shadow::Shadow {
            strength: 0.0,
            ..RELEASE_SHADOW
        },
        labels,
        id_to_name,
        first_step: 1,
        frames,
        rejected_trials: 0,
        simulation_steps: runs.iter().map(|run| run.updates as u64).sum(),
    })
}

/// The release's validity check: every box starts within 0.4 of its sampled height.
fn check_start_heights(layout: &Layout, runs: &[HalfRun; 2]) -> Result<(), String> {
    for (half, run) in layout.halves.iter().zip(runs) {
        let Some(start) = run
            .frames
            .get(simulate::SPAWN_UPDATE / simulate::CAPTURE_EVERY)
        else {
            continue;
        };
        for (entry, (position, _)) in half.boxes.iter().zip(&start.boxes) {
            if (position[1] - entry.size[1] / 2.0).abs() > START_HEIGHT_TOLERANCE {
                return Err(format!("{} did not stand at its start height", entry.name));
            }
        }
    }
    Ok(())
}

/// The scene's annotation, as the release records it.
fn annotation(layout: &Layout, runs: &[HalfRun; 2]) -> ClothAnnotation {
    let [left, right] = &layout.halves;
    let [left_run, right_run] = runs;
    ClothAnnotation {
        left_cloth: cloth_properties(left, left_run),
        right_cloth: cloth_properties(right, right_run),
        left_objects: half_objects(left, left_run),
        right_objects: half_objects(right, right_run),
        camera: None,
        id_to_object_name: Vec::new(),
        frame_count: 0,
    }
}

/// `clothLeft` / `clothRight`: the properties as the release writes them (its
/// `bendingCompliance` holds the max bending) and the quadrants' forces, quadrant 1 to 4 as
/// Red, Blue, Yellow, Green.
fn cloth_properties(half: &HalfLayout, run: &HalfRun) -> ClothProperties {
    let [red, blue, yellow, green] = run.region_forces;
    ClothProperties {
        stretching_compliance: half.cloth.stretch_compliance,
        bending_compliance: half.cloth.max_bending,
        friction: half.cloth.friction,
        region_forces: RegionForces {
            red,
            blue,
            yellow,
            green,
        },
    }
}

/// A half's boxes as isolated objects (a single-object tower is moved there by the release).
fn half_objects(half: &HalfLayout, run: &HalfRun) -> HalfObjects {
    let isolated = half
        .boxes
        .iter()
        .zip(&run.outcomes)
        .enumerate()
        .map(|(index, (entry, outcome))| box_record(half, index, entry, outcome))
        .collect();
    HalfObjects {
        towers: Vec::new(),
        isolated,
    }
}

fn box_record(
    half: &HalfLayout,
    index: usize,
    entry: &layout::BoxLayout,
    outcome: &BoxOutcome,
) -> BoxRecord {
    let start = box_body(half, index);
    let (start_position, start_rotation) = start.as_ref().map_or(([0.0; 3], [0.0; 3]), |body| {
        (body.position, unity_euler_degrees(body.rotation()))
    });
    let end_rotation = rotation_matrix(outcome.end_orientation);
    let up = apply(&end_rotation, [0.0, 1.0, 0.0]);
    let rgb = scene::color_of(entry.color);
    BoxRecord {
        name: entry.name.clone(),
        color: entry.color.to_string(),
        color_rgba: [rgb[0], rgb[1], rgb[2], 1.0],
        shape: entry.shape,
        scale: entry.size,
        sampled_position_local: [entry.footprint[0], 0.0, entry.footprint[1]],
        sampled_rotation: [0.0, entry.yaw_degrees.rem_euclid(360.0), 0.0],
        start_position,
        start_rotation,
        end_position: outcome.end_position,
        end_rotation: unity_euler_degrees(&end_rotation),
        end_pose: Pose::from_up_axis(up),
        mass: entry.mass,
        collision_events: outcome
            .collisions
            .iter()
            .map(|(update, other)| CollisionEvent {
                update: *update,
                other: other.clone(),
            })
            .collect(),
        start_moving_update: outcome.start_moving,
        touchers: outcome.touchers.clone(),
    }
}

#[cfg(test)]
mod tests;
