//! `bench perception --scenario cloth`: the scene read from pixels against the annotated one
//! (the cloth scenario's reading check), as `--perception maskrcnn --dynamics simulate` reads
//! it: the pillars and plates (named by colour and shape, placed by their silhouettes), and the
//! cloths' properties from their masks.
//!
//! Input: cloth video folders (`outputs.json` with the camera, the frames) and the perception
//! models. Output: JSON: per shape the annotated boxes, those read right (the right name in the
//! right half, the footprint's centre within [`MATCH_RADIUS`]) and those read that are not in
//! the scene or misplaced; the footprint and yaw errors of the boxes named right (median and
//! 90th percentile); per property (stretch, bending, friction, and the friction guess the
//! simulation takes) the verdicts right, wrong and not told; the boxes read still (`motion`)
//! among the immovable ones, the light ones that fell and the light ones that stayed upright.
//! Per video and in total.

use std::path::Path;

use serde::Serialize;
use serde_json::json;

use super::infer::percentile;
use super::inference_bench::IMMOVABLE;
use super::inference_bench::scored;
use super::motion::start_regions;
use super::perceived::perceive_scene;
use super::pixels::{pass_frames, read_cloths, seen_masks};
use crate::dataset::VideoFolder;
use crate::dataset::cloth::names::{Shape, Side};
use crate::dataset::cloth::outcome::Pose;
use crate::dataset::cloth::{ClothAnnotation, VOCABULARY};
use crate::perception::cloth::PERCEPTION;
use crate::scene_api::perceiver::{
    KindCheck, Perceiver, Tally, VideoReading, calibration, camera_model, check_videos,
};
use crate::scene_api::{ApiError, PerceptionModels};

/// A box whose footprint's centre lies within this of the annotated one (units) is in the right
/// place: under the narrowest side of any box (a pillar's 0.45).
pub(crate) const MATCH_RADIUS: f64 = 0.3;

/// The properties the cloth questions ask about (the factual families).
const ASKED: [&str; 2] = ["elasticity", "bending"];

/// The boxes named right that the masks show standing still (`motion`: the simulation gives
/// them their pool's immovable mass), per what they truly were: each `[read still, read]`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
struct StillCheck {
    /// Immovable boxes (a 99999-class mass).
    immovable: [usize; 2],
    /// Light boxes that fell over.
    light_fell: [usize; 2],
    /// Light boxes that stayed upright.
    light_upright: [usize; 2],
}

impl StillCheck {
    fn add(&mut self, other: StillCheck) {
        for (own, theirs) in [
            (&mut self.immovable, other.immovable),
            (&mut self.light_fell, other.light_fell),
            (&mut self.light_upright, other.light_upright),
        ] {
            own[0] += theirs[0];
            own[1] += theirs[1];
        }
    }

    /// Counts `truth`'s box `name` (if it has one), read still or not.
    fn count(&mut self, truth: &ClothAnnotation, name: &str, still: bool) {
        let Some((_, record)) = truth.find_box(name) else {
            return;
        };
        let slot = if record.mass >= IMMOVABLE {
            &mut self.immovable
        } else if record.end_pose == Pose::Upright {
            &mut self.light_upright
        } else {
            &mut self.light_fell
        };
        slot[0] += usize::from(still);
        slot[1] += 1;
    }
}

/// One video's reading.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
struct SceneCheck {
    /// Pillars.
    pillars: KindCheck,
    /// Plates.
    plates: KindCheck,
    /// Footprint centre errors of the boxes named right, units.
    #[serde(skip)]
    footprint_errors: Vec<f64>,
    /// Yaw errors of the boxes named right, degrees (a box turned half round is the same box).
    #[serde(skip)]
    yaw_errors: Vec<f64>,
    /// Per property, in [`scored`]'s order: its name and its verdict's tally.
    properties: Vec<(&'static str, Tally)>,
    /// The boxes read still (`motion`), against what they were.
    still: StillCheck,
    /// What the video could not tell.
    unknown: Vec<String>,
    /// Each box read wrong, and how.
    misread: Vec<String>,
}

impl VideoReading for SceneCheck {
    /// Whether every box was read right, nothing else was read, and the properties questions ask
    /// about (elasticity and bending; friction only feeds the simulation) were told right.
    fn entire(&self) -> bool {
        [self.pillars, self.plates]
            .iter()
            .all(|kind| kind.right == kind.annotated && kind.wrong == 0)
            && ASKED.iter().all(|asked| {
                self.properties.iter().any(|(name, tally)| {
                    name == asked && tally.right > 0 && tally.wrong == 0 && tally.undecided == 0
                })
            })
    }

    fn add(&mut self, other: &SceneCheck) {
        self.pillars.add(other.pillars);
        self.plates.add(other.plates);
        self.still.add(other.still);
        self.footprint_errors.extend(&other.footprint_errors);
        self.yaw_errors.extend(&other.yaw_errors);
        for (name, tally) in &other.properties {
            match self.properties.iter_mut().find(|(own, _)| own == name) {
                Some((_, own)) => own.add(*tally),
                None => self.properties.push((name, *tally)),
            }
        }
    }
}

/// The reading check of `videos` (the scenario table's reading check for cloth).
pub fn scene_report(
    videos: &[VideoFolder],
    models: &PerceptionModels,
) -> Result<serde_json::Value, ApiError> {
    let (total, per_video, entire) =
        check_videos(videos, |video_dir| check_scene(video_dir, models))?;
    Ok(json!({
        "match_radius_units": MATCH_RADIUS,
        "pillars": total.pillars,
        "plates": total.plates,
        "footprint_error_units": spread(&total.footprint_errors),
        "yaw_error_degrees": spread(&total.yaw_errors),
        "properties": total.properties,
        "still": total.still,
        "videos_read_entirely": entire,
        "per_video": per_video,
    }))
}

/// The median and 90th percentile of `values` (`infer::percentile`'s nearest rank; non-finite
/// values left out), `null` when there are none.
fn spread(values: &[f64]) -> serde_json::Value {
    let mut finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        return serde_json::Value::Null;
    }
    json!({
        "median": percentile(&mut finite, 0.5),
        "p90": percentile(&mut finite, 0.9),
        "count": finite.len(),
    })
}

/// Reads the scene of the video in `video_dir` from its pixels, as `--perception maskrcnn
/// --dynamics simulate` does, and compares it with the annotated one.
fn check_scene(video_dir: &Path, models: &PerceptionModels) -> Result<SceneCheck, ApiError> {
    let truth = ClothAnnotation::load(&video_dir.join("outputs.json"))?;
    let camera = calibration(truth.camera.as_ref())?.clone();
    let mut perceiver = Perceiver::open(video_dir, models, PERCEPTION.classes, &VOCABULARY)?;
    let perceived = perceive_scene(&mut perceiver, &camera)?;
    perceiver.set_names(perceived.names.clone());
    let mut check = SceneCheck {
        unknown: perceived.unknown.clone(),
        ..SceneCheck::default()
    };
    compare_boxes(&truth, &perceived.annotation, &mut check);
    let (width, height, _) = perceiver.frames();
    let model = camera_model(&camera, (width, height));
    let regions = start_regions(&perceiver, &perceived.annotation, &model);
    let masks = seen_masks(&mut perceiver, &model, &pass_frames(), &regions)?;
    for (region, motion) in regions.iter().zip(&masks.motions) {
        check
            .still
            .count(&truth, &region.name, motion.still(region));
    }
    let seen = read_cloths(&masks, &model);
    check.unknown.extend(seen.unknown);
    for property in scored(&truth, seen.verdict) {
        let mut tally = Tally::default();
        tally.count(property.told, property.truth);
        check.properties.push((property.name, tally));
    }
    Ok(check)
}

/// Counts the boxes of `seen_scene` read right against `truth`'s, by name and half and within
/// [`MATCH_RADIUS`], into `check`, with the errors of those read right and a line for each
/// misread.
fn compare_boxes(truth: &ClothAnnotation, seen_scene: &ClothAnnotation, check: &mut SceneCheck) {
    for (_, record) in truth.boxes() {
        match record.shape {
            Shape::Pillar => check.pillars.annotated += 1,
            Shape::Plate => check.plates.annotated += 1,
            Shape::Cube => {}
        }
    }
    for side in Side::BOTH {
        for seen in seen_scene.objects(side).boxes() {
            let kind = match seen.shape {
                Shape::Pillar => &mut check.pillars,
                Shape::Plate => &mut check.plates,
                Shape::Cube => continue,
            };
            let Some(annotated) = truth.objects(side).boxes().find(|b| b.name == seen.name) else {
                kind.wrong += 1;
                check.misread.push(format!(
                    "`{}` ({} half): not in that half",
                    seen.name,
                    side.word()
                ));
                continue;
            };
            let [x, _, z] = seen.start_position;
            let [true_x, _, true_z] = annotated.start_position;
            let error = (x - true_x).hypot(z - true_z);
            if error <= MATCH_RADIUS {
                kind.right += 1;
                check.footprint_errors.push(error);
                let turn = (seen.start_rotation[1] - annotated.start_rotation[1]).rem_euclid(180.0);
                check.yaw_errors.push(turn.min(180.0 - turn));
            } else {
                kind.wrong += 1;
                check.misread.push(format!(
                    "`{}` ({} half): footprint {error:.2} units off",
                    seen.name,
                    side.word()
                ));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hand-written video's annotation (`tests/data/cloth_collision/0`): left the green
    /// plate, gray pillar and blue plate; right the yellow pillar, orange plate and green pillar.
    fn fixture() -> ClothAnnotation {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/cloth_collision/0/outputs.json");
        ClothAnnotation::load(&path).unwrap()
    }

    fn boxes_mut(
        half: &mut crate::dataset::cloth::HalfObjects,
    ) -> Vec<&mut crate::dataset::cloth::BoxRecord> {
        half.towers
            .iter_mut()
            .flat_map(|tower| tower.layers.iter_mut())
            .chain(half.isolated.iter_mut())
            .collect()
    }

    #[test]
    fn boxes_count_right_by_name_half_and_place_and_misreads_say_how() {
        let truth = fixture();
        let mut check = SceneCheck::default();
        compare_boxes(&truth, &truth, &mut check);
        assert_eq!(
            (check.pillars, check.plates),
            (
                KindCheck {
                    annotated: 3,
                    right: 3,
                    wrong: 0
                },
                KindCheck {
                    annotated: 3,
                    right: 3,
                    wrong: 0
                }
            )
        );
        assert!(check.footprint_errors.iter().all(|e| *e == 0.0));
        assert!(check.misread.is_empty());
        // Every box right; the video is read entirely once both asked properties are told
        // right, whatever the friction.
        let told = |right, undecided| Tally {
            right,
            wrong: 0,
            undecided,
        };
        check.properties = vec![("elasticity", told(1, 0)), ("friction", told(0, 1))];
        assert!(!check.entire());
        check.properties.push(("bending", told(1, 0)));
        assert!(check.entire());
        check.properties[0].1 = told(0, 1);
        assert!(!check.entire());

        // Left: one box 0.5 units off, one turned half round less a degree (the same box, 1°
        // off). Right: one box read in another colour.
        let mut seen = truth.clone();
        let mut left = boxes_mut(&mut seen.left_objects);
        left[0].start_position[0] += 0.5;
        left[1].start_rotation[1] += 179.0;
        let moved = left[0].name.clone();
        let mut right = boxes_mut(&mut seen.right_objects);
        let renamed = right[0].name.clone();
        right[0].name = format!("Purple {}", right[0].name.rsplit_once(' ').unwrap().1);
        let purple = right[0].name.clone();
        let mut check = SceneCheck::default();
        compare_boxes(&truth, &seen, &mut check);
        assert_eq!(check.pillars.annotated + check.plates.annotated, 6);
        assert_eq!(check.pillars.right + check.plates.right, 4);
        assert_eq!(check.pillars.wrong + check.plates.wrong, 2);
        assert_eq!(
            check.misread,
            [
                format!("`{moved}` (left half): footprint 0.50 units off"),
                format!("`{purple}` (right half): not in that half"),
            ]
        );
        assert_ne!(renamed, purple);
        let mut yaws = check.yaw_errors.clone();
        yaws.sort_by(f64::total_cmp);
        assert!((yaws[3] - 1.0).abs() < 1e-9, "{yaws:?}");
        assert!(!check.entire());
    }

    #[test]
    fn the_spread_is_the_nearest_rank_median_and_90th_percentile() {
        // Ranks round((n − 1) × share): 4.5 → 5 and 8.1 → 8 of 0..=9.
        let values: Vec<f64> = (1..=10).map(f64::from).collect();
        assert_eq!(
            spread(&values),
            json!({"median": 6.0, "p90": 9.0, "count": 10})
        );
        let odd: Vec<f64> = (1..=11).map(f64::from).collect();
        assert_eq!(
            spread(&odd),
            json!({"median": 6.0, "p90": 10.0, "count": 11})
        );
        assert_eq!(spread(&[f64::NAN]), serde_json::Value::Null);
        assert_eq!(
            spread(&[2.0]),
            json!({"median": 2.0, "p90": 2.0, "count": 1})
        );
    }
}
