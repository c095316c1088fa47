//! `bench perception --scenario ball`: the scene read from pixels against the annotated one
//! (the ball scenario's reading check).
//!
//! Input: ball video folders and the perception models. Output: JSON: per kind (ramps, floor
//! pieces, floating walls, balls) the annotated objects, those read right (the right name, and
//! for a slab both ends within [`MATCH_RADIUS`]) and those read that are not in the scene; the
//! mean error of the slabs' ends; the balls' materials as `--perception maskrcnn --dynamics
//! simulate` reads them (the rigid ball from its first rebound, the others by the simulation
//! fit), right, wrong or undecided per annotated material; and the drops the video shows,
//! against the annotation's observed pits. Per video and in total.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;
use serde_json::json;

use super::perceived::{camera_model, perceive_scene, seen_balls};
use super::runs::fit_materials;
use super::simulate::{BallModel, Stadium};
use crate::dataset::VideoFolder;
use crate::dataset::ball::outcome::PitResult;
use crate::dataset::ball::{BallAnnotation, ElasticityType, SlabRecord, VOCABULARY};
use crate::perception::ball::PERCEPTION;
use crate::scene_api::perceiver::Perceiver;
use crate::scene_api::{ApiError, PerceptionModels};

/// A slab's ends within this of the annotated ones (units) is in the right place: the thinnest
/// slab is 0.2 thick, and a ball 1 across.
pub(crate) const MATCH_RADIUS: f64 = 0.2;

pub(crate) use crate::scene_api::perceiver::{KindCheck, Tally};
use crate::scene_api::perceiver::{VideoReading, check_videos};

/// One video's reading.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub(crate) struct SceneCheck {
    /// Ramps.
    pub ramps: KindCheck,
    /// Floor pieces.
    pub floor_pieces: KindCheck,
    /// Floating walls.
    pub floating_walls: KindCheck,
    /// Balls (by name: their colour).
    pub balls: KindCheck,
    /// Sum of the slabs' end errors over the slabs read right, units.
    #[serde(skip)]
    pub end_error_sum: f64,
    /// Slabs read right (the end errors' count).
    #[serde(skip)]
    pub slabs_right: usize,
    /// The balls' materials, by annotated material (`Elastic`, `Rigid`, `Plastic`).
    pub materials: BTreeMap<String, Tally>,
    /// The rigid ball read from the first rebounds alone, before the fit.
    pub rigid_by_rebound: Tally,
    /// Balls the video shows dropping into a pit (annotated `… Observed`), and the others, read
    /// as the video shows them.
    pub drops: Tally,
    /// What the video could not tell.
    pub unknown: Vec<String>,
    /// Each object read wrong, and how.
    pub misread: Vec<String>,
}

impl VideoReading for SceneCheck {
    /// Whether every object was read right and nothing else was read.
    fn entire(&self) -> bool {
        [
            self.ramps,
            self.floor_pieces,
            self.floating_walls,
            self.balls,
        ]
        .iter()
        .all(|kind| kind.right == kind.annotated && kind.wrong == 0)
    }

    fn add(&mut self, other: &SceneCheck) {
        self.ramps.add(other.ramps);
        self.floor_pieces.add(other.floor_pieces);
        self.floating_walls.add(other.floating_walls);
        self.balls.add(other.balls);
        self.end_error_sum += other.end_error_sum;
        self.slabs_right += other.slabs_right;
        for (material, tally) in &other.materials {
            self.materials
                .entry(material.clone())
                .or_default()
                .add(*tally);
        }
        self.rigid_by_rebound.add(other.rigid_by_rebound);
        self.drops.add(other.drops);
    }
}

/// The reading check of `videos` (the scenario table's reading check for ball).
pub fn scene_report(
    videos: &[VideoFolder],
    models: &PerceptionModels,
) -> Result<serde_json::Value, ApiError> {
    let (total, per_video, entire) =
        check_videos(videos, |video_dir| check_scene(video_dir, models))?;
    Ok(json!({
        "match_radius_units": MATCH_RADIUS,
        "ramps": total.ramps,
        "floor_pieces": total.floor_pieces,
        "floating_walls": total.floating_walls,
        "balls": total.balls,
        "mean_slab_end_error_units": total.end_error_sum / total.slabs_right.max(1) as f64,
        "materials": total.materials,
        "rigid_by_rebound": total.rigid_by_rebound,
        "drops": total.drops,
        "videos_read_entirely": entire,
        "per_video": per_video,
    }))
}

/// Reads the scene of the video in `video_dir` from its pixels, as `--perception maskrcnn
/// --dynamics simulate` does, and compares it with the annotated one.
fn check_scene(video_dir: &Path, models: &PerceptionModels) -> Result<SceneCheck, ApiError> {
    let truth = BallAnnotation::load(&video_dir.join("outputs.json"))?;
    let camera = truth.camera.clone().ok_or_else(|| {
        ApiError::Unavailable("the video has no camera calibration (outputCamera)".to_string())
    })?;
    let mut perceiver = Perceiver::open(video_dir, models, PERCEPTION.classes, &VOCABULARY)?;
    let perceived = perceive_scene(&mut perceiver, &camera)?;
    let layout = &perceived.annotation.layout;
    let mut check = SceneCheck {
        unknown: perceived.unknown.clone(),
        ..SceneCheck::default()
    };
    for (kind, seen, annotated) in [
        ("ramp", &layout.ramps, &truth.layout.ramps),
        (
            "floor piece",
            &layout.floor_pieces,
            &truth.layout.floor_pieces,
        ),
        (
            "floating wall",
            &layout.floating_walls,
            &truth.layout.floating_walls,
        ),
    ] {
        let tally = compare_slabs(kind, seen, annotated, &mut check);
        match kind {
            "ramp" => check.ramps = tally,
            "floor piece" => check.floor_pieces = tally,
            _ => check.floating_walls = tally,
        }
    }
    check.balls.annotated = truth.layout.balls.len();
    for ball in &layout.balls {
        if truth.layout.ball(&ball.name).is_some() {
            check.balls.right += 1;
        } else {
            check.balls.wrong += 1;
            check
                .misread
                .push(format!("ball `{}`: not in the scene", ball.name));
        }
    }
    let (width, height, _) = perceiver.frames();
    let model = camera_model(&camera, (width, height));
    let mut balls = seen_balls(&mut perceiver, layout, &model)?;
    for ball in &balls {
        if let Some(annotated) = truth.layout.ball(&ball.name) {
            let rigid = annotated.elasticity == ElasticityType::Rigid;
            let read = ball.material.map(|m| m == ElasticityType::Rigid);
            if rigid || read == Some(true) {
                check.rigid_by_rebound.count(read, true);
            }
        }
    }
    fit_materials(
        &Stadium::from_layout(layout),
        &mut balls,
        &BallModel::default(),
    )?;
    for ball in &balls {
        let Some(annotated) = truth.layout.ball(&ball.name) else {
            continue;
        };
        check
            .materials
            .entry(format!("{:?}", annotated.elasticity))
            .or_default()
            .count(ball.material, annotated.elasticity);
        if let Some(record) = truth.tracking.get(&ball.name) {
            let shown = match record.result {
                PitResult::Observed(pit) => Some(pit),
                PitResult::ToPredict(_) | PitResult::NoPit => None,
            };
            check.drops.count(Some(ball.dropped), shown);
        }
    }
    Ok(check)
}

/// Compares the slabs of one kind read with the annotated ones, by name; adds the misreadings
/// and end errors to `check`.
fn compare_slabs(
    kind: &str,
    seen: &[SlabRecord],
    annotated: &[SlabRecord],
    check: &mut SceneCheck,
) -> KindCheck {
    let distance = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let mut tally = KindCheck {
        annotated: annotated.len(),
        ..KindCheck::default()
    };
    for slab in seen {
        let Some(truth) = annotated.iter().find(|other| other.name == slab.name) else {
            tally.wrong += 1;
            check
                .misread
                .push(format!("{kind} `{}`: not in the scene", slab.name));
            continue;
        };
        let error = (distance(slab.start, truth.start).max(distance(slab.end, truth.end)))
            .min(distance(slab.start, truth.end).max(distance(slab.end, truth.start)));
        let same_color = kind != "ramp" || slab.color == truth.color;
        if error <= MATCH_RADIUS && same_color {
            tally.right += 1;
            check.end_error_sum += error;
            check.slabs_right += 1;
        } else {
            tally.wrong += 1;
            check.misread.push(format!(
                "{kind} `{}`: ends {error:.2} units off{}",
                slab.name,
                if same_color { "" } else { ", another colour" }
            ));
        }
    }
    tally
}
