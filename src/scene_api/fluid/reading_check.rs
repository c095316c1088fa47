//! `bench perception --scenario fluid`: the scene read from pixels against the annotated one,
//! object by object (the fluid scenario's reading check).
//!
//! Input: fluid video folders and the perception models. Output: JSON: per kind the annotated
//! objects, those read right (the right name, so the right colour and, for an emitter, first
//! or later, at the right place) and those read that are not in the scene, per video and in
//! total, with the videos read entirely and the mean error of the sticks' ends; and the fluids'
//! density order and viscosity classes inferred from the detector's masks, scored against the
//! annotation as `bench inference` scores them from the tracked particles.

use std::path::Path;

use serde::Serialize;
use serde_json::json;

use super::infer::masks::frames_needed;
use super::infer::{FluidInference, InferenceScore, PerceivedFluidScene, infer_from_masks};
use super::perceived::{camera_model, perceive_scene};
use super::seen::{fluid_colors, seen_flow};
use super::{attach_other_colors, scene_objects};
use crate::dataset::VideoFolder;
use crate::dataset::fluid::{
    FluidAnnotation, FluidLayout, LATER_EMITTED_PREFIX, ReservoirRecord, StickRecord, VOCABULARY,
};
use crate::perception::fluid::PERCEPTION;
use crate::scene_api::find::NameQuery;
use crate::scene_api::perceiver::Perceiver;
use crate::scene_api::{ApiError, PerceptionModels};

/// A stick's ends, an emitter's centre or a cup's corners within this of the annotated ones
/// (units) is in the right place: a stick is 0.15 thick and two sticks at least 0.7 apart.
pub(crate) const MATCH_RADIUS: f64 = 0.2;

pub(crate) use crate::scene_api::perceiver::KindCheck;

/// One video's reading.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub(crate) struct SceneCheck {
    /// Regular sticks.
    pub sticks: KindCheck,
    /// Containers.
    pub containers: KindCheck,
    /// Emitters, first and later.
    pub emitters: KindCheck,
    /// Fluids (one per first emitter).
    pub fluids: KindCheck,
    /// Sum of the sticks' end errors over the sticks read right, units.
    #[serde(skip)]
    pub end_error_sum: f64,
    /// What the video could not tell.
    pub unknown: Vec<String>,
    /// Each object read wrong, and how ("stick `Red Stick`: ends 0.31 units off").
    pub misread: Vec<String>,
    /// Sticks read in a wrong colour: how many, and how many of them `find` still names by
    /// their true colour, the colour model's likeliest second choice for them.
    pub recoloured_sticks: SecondChoices,
    /// Containers read in place in a wrong colour, and those `find` still names.
    pub recoloured_containers: SecondChoices,
}

/// How far a stick read in a wrong colour may be from the annotated one it stands in for (its
/// ends, either way round), units: a stick's length.
const STAND_IN_RADIUS: f64 = 1.5;

/// Objects of one kind read in a wrong colour, and those their second choice names right.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub(crate) struct SecondChoices {
    /// Annotated objects read in place but in another colour.
    pub recoloured: usize,
    /// Of them, those `find` still returns for their true name: of the objects of the kind
    /// with the true colour as a second choice, this one is where it ranks highest.
    pub found_by_second_choice: usize,
}

impl SecondChoices {
    fn add(&mut self, other: SecondChoices) {
        self.recoloured += other.recoloured;
        self.found_by_second_choice += other.found_by_second_choice;
    }
}

impl SceneCheck {
    /// Whether every object was read right and nothing else was read.
    pub(crate) fn entire(&self) -> bool {
        [self.sticks, self.containers, self.emitters, self.fluids]
            .iter()
            .all(|kind| kind.right == kind.annotated && kind.wrong == 0)
    }
}

/// The reading check of `videos` (the scenario table's reading check for fluid).
pub fn scene_report(
    videos: &[VideoFolder],
    models: &PerceptionModels,
) -> Result<serde_json::Value, ApiError> {
    let mut total = SceneCheck::default();
    let mut per_video = Vec::new();
    let mut entire = 0;
    let mut properties = InferenceScore::default();
    let mut failed = Vec::new();
    for video in videos {
        let (check, inference, truth) = check_scene(&video.dir, models)
            .map_err(|error| ApiError::Data(format!("video {}: {error}", video.dir.display())))?;
        let mut viscosity_evidence = json!(null);
        match inference {
            Ok(inference) => {
                properties.add(&video.id.0, &truth, &inference);
                viscosity_evidence = json!(inference.mask_viscosity);
            }
            Err(error) => failed.push(json!({"video": video.id.0, "error": error.to_string()})),
        }
        total.sticks.add(check.sticks);
        total.containers.add(check.containers);
        total.emitters.add(check.emitters);
        total.fluids.add(check.fluids);
        total.end_error_sum += check.end_error_sum;
        total.recoloured_sticks.add(check.recoloured_sticks);
        total.recoloured_containers.add(check.recoloured_containers);
        entire += usize::from(check.entire());
        per_video.push(json!({
            "video": video.id.0,
            "check": check,
            "viscosity_from_masks": viscosity_evidence,
        }));
    }
    let mean_end_error = total.end_error_sum / total.sticks.right.max(1) as f64;
    Ok(json!({
        "match_radius_units": MATCH_RADIUS,
        "sticks": total.sticks,
        "containers": total.containers,
        "emitters": total.emitters,
        "fluids": total.fluids,
        "mean_stick_end_error_units": mean_end_error,
        "recoloured_sticks": total.recoloured_sticks,
        "recoloured_containers": total.recoloured_containers,
        "videos_read_entirely": entire,
        "per_video": per_video,
        "properties_from_masks": properties.json(),
        "properties_failed": failed,
    }))
}

/// What the check of one video gives: the scene's reading, the properties inferred from the
/// detector's masks (or why not), and the annotation.
type VideoCheck = (
    SceneCheck,
    Result<FluidInference, ApiError>,
    FluidAnnotation,
);

/// Reads the scene of the video in `video_dir` from its pixels and compares it with the
/// annotated one; infers the fluids' properties from the masks, as `--dynamics simulate`
/// does.
pub(crate) fn check_scene(
    video_dir: &Path,
    models: &PerceptionModels,
) -> Result<VideoCheck, ApiError> {
    let truth = FluidAnnotation::load(&video_dir.join("outputs.json"))?;
    let camera = truth.camera.clone().ok_or_else(|| {
        ApiError::Unavailable(format!(
            "{}: no camera calibration (outputCamera)",
            video_dir.display()
        ))
    })?;
    let mut perceiver = Perceiver::open(video_dir, models, PERCEPTION.classes, &VOCABULARY)?;
    let seen = perceive_scene(&mut perceiver, &camera)?;
    let mut check = compare(&truth.layout, &seen.annotation.layout);
    (check.recoloured_sticks, check.recoloured_containers) = second_choices(
        &truth.layout,
        &seen.annotation.layout,
        &seen.other_colors,
        &mut check.misread,
    );
    check.unknown = seen.unknown;
    let (width, height, frame_count) = perceiver.frames();
    let model = camera_model(&camera, (width, height));
    let fluids = fluid_colors(&seen.annotation.layout);
    let scene = PerceivedFluidScene::from_layout(&seen.annotation.layout);
    let inference = seen_flow(&mut perceiver, &model, &fluids, &frames_needed(frame_count))
        .and_then(|flow| {
            infer_from_masks(&video_dir.display().to_string(), &scene, &flow)
                .map_err(ApiError::from)
        });
    Ok((check, inference, truth))
}

/// The annotated sticks and containers read in place but in another colour, and whether `find`
/// names each by its true colour through the seen objects' second choices (`other_colors`);
/// says which in `misread`.
fn second_choices(
    truth: &FluidLayout,
    seen: &FluidLayout,
    other_colors: &std::collections::BTreeMap<String, Vec<String>>,
    misread: &mut Vec<String>,
) -> (SecondChoices, SecondChoices) {
    let (mut objects, _) = scene_objects(seen);
    attach_other_colors(&mut objects, other_colors);
    let sticks = stand_ins(
        &truth
            .sticks
            .iter()
            .map(|s| s.name.clone())
            .collect::<Vec<_>>(),
        &seen
            .sticks
            .iter()
            .map(|s| s.name.clone())
            .collect::<Vec<_>>(),
        |t, s| stick_error(&truth.sticks[t], &seen.sticks[s]),
        STAND_IN_RADIUS,
    );
    let containers = stand_ins(
        &truth
            .reservoirs
            .iter()
            .map(|c| c.name.clone())
            .collect::<Vec<_>>(),
        &seen
            .reservoirs
            .iter()
            .map(|c| c.name.clone())
            .collect::<Vec<_>>(),
        |t, s| cup_error(&truth.reservoirs[t], &seen.reservoirs[s]),
        MATCH_RADIUS,
    );
    let mut tally = |kind: &str, pairs: Vec<(String, String)>| {
        let mut tally = SecondChoices::default();
        for (annotated, stand_in) in pairs {
            let Some(true_color) = crate::dataset::fluid::parse_fluid_object_name(&annotated)
                .and_then(|parsed| parsed.color)
                .map(str::to_lowercase)
            else {
                continue;
            };
            tally.recoloured += 1;
            // What `find` does when no object of the kind was read in the true colour.
            let query = NameQuery {
                color: Some(true_color),
                kind: Some(kind.to_string()),
                ..NameQuery::default()
            };
            let found = query
                .second_choice_object(&objects, &VOCABULARY)
                .and_then(|id| objects.iter().find(|object| object.id == id))
                .is_some_and(|object| object.name == stand_in);
            tally.found_by_second_choice += usize::from(found);
            misread.push(format!(
                "{kind} `{annotated}` read as `{stand_in}`: {}",
                if found {
                    "found by its second choice".to_string()
                } else {
                    format!(
                        "second choices {}",
                        other_colors
                            .get(&stand_in)
                            .map_or_else(|| "none".to_string(), |c| c.join(", "))
                    )
                }
            ));
        }
        tally
    };
    (tally("stick", sticks), tally("container", containers))
}

/// Per annotated object no seen object is named as (`truth`, `seen`: names), the nearest seen
/// object within `radius` (by `error` of their indices) that no annotated object is named as:
/// the object read in another colour, `(annotated, seen)`.
fn stand_ins(
    truth: &[String],
    seen: &[String],
    error: impl Fn(usize, usize) -> f64,
    radius: f64,
) -> Vec<(String, String)> {
    truth
        .iter()
        .enumerate()
        .filter(|(_, annotated)| !seen.contains(annotated))
        .filter_map(|(t, annotated)| {
            seen.iter()
                .enumerate()
                .filter(|(_, name)| !truth.contains(name))
                .map(|(s, name)| (name, error(t, s)))
                .filter(|(_, distance)| *distance <= radius)
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(name, _)| (annotated.clone(), name.clone()))
        })
        .collect()
}

/// How far apart two containers' cups are: the farther of their corresponding corners, units.
fn cup_error(a: &ReservoirRecord, b: &ReservoirRecord) -> f64 {
    let origin = [0.0, 0.0];
    let (a, b) = (a.cup_box(origin), b.cup_box(origin));
    distance(a.min, b.min).max(distance(a.max, b.max))
}

/// How far apart two sticks' ends are, either way round, units.
fn stick_error(a: &StickRecord, b: &StickRecord) -> f64 {
    let straight = distance(a.start, b.start).max(distance(a.end, b.end));
    let crossed = distance(a.start, b.end).max(distance(a.end, b.start));
    straight.min(crossed)
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// `seen` against `truth` (both relative to the tank origin).
pub(crate) fn compare(truth: &FluidLayout, seen: &FluidLayout) -> SceneCheck {
    let mut check = SceneCheck::default();
    // Sticks: both ends in place, either way round.
    check.sticks.annotated = truth.sticks.len();
    for stick in &seen.sticks {
        match truth.sticks.iter().find(|t| t.name == stick.name) {
            Some(annotated) if stick_error(annotated, stick) <= MATCH_RADIUS => {
                check.sticks.right += 1;
                check.end_error_sum += stick_error(annotated, stick);
            }
            Some(annotated) => {
                check.sticks.wrong += 1;
                check.misread.push(format!(
                    "stick `{}`: ends {:.2} units off (seen {:.2} long, annotated {:.2})",
                    stick.name,
                    stick_error(annotated, stick),
                    distance(stick.start, stick.end),
                    distance(annotated.start, annotated.end)
                ));
            }
            None => {
                check.sticks.wrong += 1;
                check.misread.push(format!(
                    "stick `{}`: no annotated stick of that name",
                    stick.name
                ));
            }
        }
    }
    // Containers: the cup in place.
    check.containers.annotated = truth.reservoirs.len();
    for container in &seen.reservoirs {
        let in_place = truth
            .reservoirs
            .iter()
            .find(|t| t.name == container.name)
            .is_some_and(|t| cup_error(t, container) <= MATCH_RADIUS);
        if in_place {
            check.containers.right += 1;
        } else {
            check.containers.wrong += 1;
            check.misread.push(format!(
                "container `{}`: not annotated there",
                container.name
            ));
        }
    }
    // Emitters and fluids: by key, the emitter in place.
    let emitters = |layout: &FluidLayout| -> Vec<(String, [f64; 2])> {
        let mut all = Vec::new();
        for fluid in &layout.fluids {
            let p = fluid.emitter_position;
            all.push((fluid.name.clone(), [p[0], p[1]]));
            if fluid.has_predictive_emitter {
                let q = fluid.predictive_emitter_position;
                all.push((
                    format!("{LATER_EMITTED_PREFIX}{}", fluid.name),
                    [q[0], q[1]],
                ));
            }
        }
        all
    };
    let (annotated, read) = (emitters(truth), emitters(seen));
    check.emitters.annotated = annotated.len();
    for (key, at) in &read {
        if annotated
            .iter()
            .any(|(k, p)| k == key && distance(*p, *at) <= MATCH_RADIUS)
        {
            check.emitters.right += 1;
        } else {
            check.emitters.wrong += 1;
            check
                .misread
                .push(format!("emitter `{key}`: not annotated there"));
        }
    }
    check.fluids.annotated = truth.fluids.len();
    for fluid in &seen.fluids {
        if truth.fluids.iter().any(|t| t.name == fluid.name) {
            check.fluids.right += 1;
        } else {
            check.fluids.wrong += 1;
            check
                .misread
                .push(format!("fluid `{}`: not in the scene", fluid.name));
        }
    }
    check
}
