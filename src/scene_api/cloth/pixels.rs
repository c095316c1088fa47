//! What the cloths do, read from the detector's masks (`--perception maskrcnn --dynamics
//! simulate`): where each cloth spawns, which cloth stretches and which bends, and a friction
//! guess. Of the annotation only the camera calibration is read.
//!
//! Input: the detections of frames [`CLOTH_FRAMES`] (per frame and half, the cloth is the
//! largest cloth detection on that side of `x = 0`), the camera. Output:
//! [`SeenCloths`]. Frames are video frames: frame `j` is update `2j`; the cloth spawns at frame
//! 30, flat, its far edge (the gripped row, at `z` = [`CLOTH_START_Z`]) dragged along +z at 3
//! units/s. Measured against the generator's truth on 16 videos of seed 3410 (chosen there) and
//! the 8 held-out videos of seed 3403 (`docs/data/cloth.md`, *Perception*).
//!
//! * **Spawn.** The release spawns each cloth as a flat 3 × 3 grid centred on its half, its
//!   gripped edge at `z = −3.4`, at a height of 2.4 + U(0, 0.3) (`synth::cloth::layout`). The
//!   height is the one unknown: the gripped row is the top of the cloth's mask while it is
//!   dragged, so the height is the median, over frames [`HEIGHT_FRAMES`], of the mask's top point
//!   lifted onto the plane `z` where the handle is at that frame, less the particles' radius
//!   (0.04; the top edge read is their top). Mean error 0.020 units (the release's mean: 0.067).
//! * **Pull.** The release's mean, 5 units (4.8 + U(−0.1, 0.5)): the handle's travel read from
//!   the top of the held cloth (frames 85–94) was worse (mean error 0.40 units against 0.13),
//!   since a cloth piled up on the boxes rises above its handle.
//! * **Stretch.** While the cloths fall from the handle (frames [`STRETCH_FRAMES`]) the cloth
//!   that stretches shows the smaller mask: it has swung further down, towards the camera's
//!   line of sight. Told when the two masks' median areas differ by [`STRETCH_MARGIN`] of their
//!   sum.
//! * **Bending.** Just after the handle lets go (frames [`BEND_FRAMES`]), the cloth that bends
//!   easily falls as a compact heap, its mask more solid (mask area over its convex hull's
//!   area) than the stiffer cloth's, which keeps folds standing out. Told when the median
//!   solidities differ by [`BEND_MARGIN`] of their sum.
//! * **Friction.** The cloth of high friction stays lower in the image while dragged over the
//!   boxes (frames [`FRICTION_FRAMES`]): the larger median centroid row is the high-friction
//!   guess, told when the rows differ by [`FRICTION_MARGIN`] of their sum.
//! * **Draped boxes** (measured, not used). A box carries the cloth when, over frames 95–114
//!   (after the handle lets go), the cloth's mask covers most of its top face's silhouette at
//!   its start pose (of the upright boxes of seeds 3410 and 3403 flagged, 8 of 9 carried the
//!   cloth; of 16 that carried it, 8 were flagged). Taken as "immovable" for the boxes' masses
//!   it scored P-Opt. 54.6 / P-Ques. 31.2 on the 16 tuning videos of seed 3410, against 75.3 /
//!   62.5 with every box movable. The boxes' own masks tell it better (`motion`).

use crate::dataset::cloth::names::Side;
use crate::perception::camera::CameraModel;
use crate::perception::detection::InstanceMask;
#[cfg(test)]
use crate::perception::silhouette::inside;
use crate::perception::silhouette::{convex_hull, polygon_area};
use crate::physics::vector3::Vector;
use crate::scene_api::ApiError;
use crate::scene_api::perceiver::Perceiver;
use crate::synth::cloth::layout::{CLOTH_RESOLUTION, CLOTH_SIDE, CLOTH_START_Z, HALF_CENTRES};
use crate::synth::cloth::simulate::{CAPTURE_EVERY, PULL_SPEED, RADIUS_PER_SPACING};

use super::infer::ClothVerdict;
use super::motion::{MOTION_FRAMES, Motion, StartRegion};
#[cfg(test)]
use super::perceived::PlacedBox;
use super::perceived::SPAWN_FRAME;

/// The frames the cloths are read from (the union of the ranges below).
pub(crate) const CLOTH_FRAMES: std::ops::RangeInclusive<usize> = 31..=114;
/// The frames one pass of the detector reads for the cloths and the boxes' motion: the union
/// of [`CLOTH_FRAMES`] and `motion`'s frames, in order.
pub(crate) fn pass_frames() -> Vec<usize> {
    (*CLOTH_FRAMES.start().min(MOTION_FRAMES.start())
        ..=*CLOTH_FRAMES.end().max(MOTION_FRAMES.end()))
        .collect()
}
/// Frames the spawn height is read over (the cloth is dragged, its gripped row on top).
const HEIGHT_FRAMES: std::ops::RangeInclusive<usize> = 31..=40;
/// Frames the stretch is read over (the cloths fall from their handles).
const STRETCH_FRAMES: std::ops::RangeInclusive<usize> = 40..=49;
/// Frames the bending is read over (the handle has let go at frame 95).
const BEND_FRAMES: std::ops::RangeInclusive<usize> = 95..=104;
/// Frames the friction guess is read over (the cloths are dragged over the boxes).
const FRICTION_FRAMES: std::ops::RangeInclusive<usize> = 40..=94;
/// Frames the cloth is looked for on the boxes' tops in.
#[cfg(test)]
pub(crate) const DRAPED_FRAMES: std::ops::RangeInclusive<usize> = 95..=114;
/// Relative difference of the median mask areas under which stretch is not told (seed 3410:
/// the three closest of 16 pairs, two of them wrong).
pub(crate) const STRETCH_MARGIN: f64 = 0.015;
/// Relative difference of the median solidities under which bending is not told (seed 3410:
/// the five closest of 16 pairs, the three wrong ones among them).
pub(crate) const BEND_MARGIN: f64 = 0.012;
/// Relative difference of the median centroid rows under which friction is not told.
pub(crate) const FRICTION_MARGIN: f64 = 0.02;
/// Share of a box's top face the cloth must cover to lie on it.
#[cfg(test)]
const COVERED: f64 = 0.5;
/// Spawn height when no mask tells it: the middle of the release's 2.4–2.7, units.
const MEAN_HEIGHT: f64 = 2.55;
/// The handle's travel: the middle of the release's 4.7–5.3, units.
pub(crate) const MEAN_PULL: f64 = 5.0;

/// The masks of one cloth, by frame.
pub(crate) type ClothMasks = Vec<(usize, InstanceMask)>;

/// The cloths' masks, by frame, and what the boxes' masks showed of their motion.
#[derive(Debug, Clone, Default)]
pub(crate) struct SeenMasks {
    /// Left, right: each cloth's masks.
    pub cloths: [ClothMasks; 2],
    /// Per watched box (the `regions` given to [`seen_masks`]), its motion.
    pub motions: Vec<Motion>,
}

/// What the video shows of the cloths.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct SeenCloths {
    /// Left, right: the particles at the spawn (31 × 31, flat), units.
    pub spawns: [Vec<Vector>; 2],
    /// The properties' verdicts.
    pub verdict: ClothVerdict,
    /// What the masks could not tell (a default was taken), one line each.
    pub unknown: Vec<String>,
}

/// The masks of `frames`: per frame and half, the largest cloth detection whose centroid lies
/// on that half's side of `x = 0`; and each box of `regions` watched through the pillar and plate
/// masks of its colour (`motion`).
pub(crate) fn seen_masks(
    perceiver: &mut Perceiver,
    model: &CameraModel,
    frames: &[usize],
    regions: &[StartRegion],
) -> Result<SeenMasks, ApiError> {
    perceiver.first_pass()?;
    let Some(classes) = perceiver.classes().cloned() else {
        return Ok(SeenMasks::default());
    };
    let divide = model
        .project([0.0, 1.0, 0.0])
        .map_or(f64::from(model.width) / 2.0, |p| p.x);
    let mut seen = SeenMasks {
        motions: vec![Motion::default(); regions.len()],
        ..SeenMasks::default()
    };
    perceiver.visit_detections(frames, &mut |frame, detections| {
        for (region, motion) in regions.iter().zip(&mut seen.motions) {
            let masks: Vec<&InstanceMask> = detections
                .iter()
                .filter(|detection| {
                    detection.color == Some(region.color)
                        && matches!(classes.kind(detection.class), "pillar" | "plate")
                })
                .map(|detection| &detection.mask)
                .collect();
            motion.watch(region, frame.index, &masks);
        }
        let mut best: [Option<&InstanceMask>; 2] = [None, None];
        for detection in detections {
            if classes.kind(detection.class) != "cloth" {
                continue;
            }
            let Some(centroid) = detection.mask.centroid() else {
                continue;
            };
            let slot = if centroid[0] < divide {
                &mut best[0]
            } else {
                &mut best[1]
            };
            if slot.is_none_or(|kept| kept.area() < detection.mask.area()) {
                *slot = Some(&detection.mask);
            }
        }
        for (mask, list) in best.into_iter().zip(seen.cloths.iter_mut()) {
            if let Some(mask) = mask {
                list.push((frame.index, mask.clone()));
            }
        }
    })?;
    Ok(seen)
}

/// The top point of `mask`: the mean column of its top row, at that row's upper edge.
fn top_point(mask: &InstanceMask) -> Option<[f64; 2]> {
    let [x0, y0, x1, _] = mask.bounds()?;
    let columns: Vec<f64> = (x0..=x1)
        .filter(|x| mask.contains(*x, y0))
        .map(|x| f64::from(x) + 0.5)
        .collect();
    if columns.is_empty() {
        return None;
    }
    Some([
        columns.iter().sum::<f64>() / columns.len() as f64,
        f64::from(y0),
    ])
}

/// A mask's solidity: its area over the area of the convex hull of its pixels' corners.
fn solidity(mask: &InstanceMask) -> Option<f64> {
    let mut corners = Vec::new();
    for (x, y) in mask.pixels() {
        let inner = x > 0
            && y > 0
            && mask.contains(x - 1, y)
            && mask.contains(x + 1, y)
            && mask.contains(x, y - 1)
            && mask.contains(x, y + 1);
        if !inner {
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                corners.push([f64::from(x + dx), f64::from(y + dy)]);
            }
        }
    }
    let hull_area = polygon_area(&convex_hull(corners));
    (hull_area > 0.0).then(|| mask.area() as f64 / hull_area)
}

/// The median of `values` (non-finite ones left out); `None` when none is left.
fn median(mut values: Vec<f64>) -> Option<f64> {
    values.retain(|v| v.is_finite());
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n == 0 {
        return None;
    }
    let high = values.get(n / 2).copied();
    if n % 2 == 1 {
        high
    } else {
        Some(f64::midpoint(values.get(n / 2 - 1).copied()?, high?))
    }
}

/// The median of `measure` over the masks of `frames`.
fn median_over(
    masks: &ClothMasks,
    frames: &std::ops::RangeInclusive<usize>,
    measure: fn(&InstanceMask) -> Option<f64>,
) -> Option<f64> {
    median(
        masks
            .iter()
            .filter(|(frame, _)| frames.contains(frame))
            .filter_map(|(_, mask)| measure(mask))
            .collect(),
    )
}

/// The gripped row's `z` at video frame `frame` while the handle moves, units.
fn handle_z(frame: usize) -> f64 {
    let updates = (frame * CAPTURE_EVERY).saturating_sub(SPAWN_FRAME * CAPTURE_EVERY);
    CLOTH_START_Z + PULL_SPEED * updates as f64 / 60.0
}

/// The spawn height read from `masks`, units.
pub(crate) fn spawn_height(masks: &ClothMasks, model: &CameraModel) -> Option<f64> {
    let radius = RADIUS_PER_SPACING * CLOTH_SIDE / (CLOTH_RESOLUTION - 1) as f64;
    median(
        masks
            .iter()
            .filter(|(frame, _)| HEIGHT_FRAMES.contains(frame))
            .filter_map(|(frame, mask)| {
                let [x, y] = top_point(mask)?;
                Some(model.lift_to_plane(x, y, handle_z(*frame))?[1] - radius)
            })
            .collect(),
    )
}

/// The cloth of `side` as the release spawns it at `height`: 31 × 31 particles, rows along x,
/// the last row the gripped edge.
pub(crate) fn spawn_grid(side: Side, height: f64) -> Vec<Vector> {
    let centre = match side {
        Side::Left => HALF_CENTRES[0],
        Side::Right => HALF_CENTRES[1],
    };
    let spacing = CLOTH_SIDE / (CLOTH_RESOLUTION - 1) as f64;
    (0..CLOTH_RESOLUTION)
        .flat_map(|row| {
            (0..CLOTH_RESOLUTION).map(move |column| {
                [
                    centre - CLOTH_SIDE / 2.0 + column as f64 * spacing,
                    height,
                    CLOTH_START_Z - CLOTH_SIDE + row as f64 * spacing,
                ]
            })
        })
        .collect()
}

/// The share of the pixels whose centres lie inside the convex `polygon` that `covered` says
/// are covered; `None` when the polygon holds no pixel centre.
#[cfg(test)]
fn share_covered(
    polygon: &[[f64; 2]],
    model: &CameraModel,
    covered: &dyn Fn(u32, u32) -> bool,
) -> Option<f64> {
    let low = |axis: usize| {
        polygon
            .iter()
            .map(|p| p[axis])
            .fold(f64::INFINITY, f64::min)
    };
    let high = |axis: usize| {
        polygon
            .iter()
            .map(|p| p[axis])
            .fold(f64::NEG_INFINITY, f64::max)
    };
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "clamped to the image"
    )]
    let (x0, x1, y0, y1) = (
        low(0).floor().clamp(0.0, f64::from(model.width)) as u32,
        high(0).ceil().clamp(0.0, f64::from(model.width)) as u32,
        low(1).floor().clamp(0.0, f64::from(model.height)) as u32,
        high(1).ceil().clamp(0.0, f64::from(model.height)) as u32,
    );
    let (mut inside_count, mut covered_count) = (0_u32, 0_u32);
    for y in y0..y1 {
        for x in x0..x1 {
            if inside(polygon, [f64::from(x) + 0.5, f64::from(y) + 0.5]) {
                inside_count += 1;
                covered_count += u32::from(covered(x, y));
            }
        }
    }
    (inside_count > 0).then(|| f64::from(covered_count) / f64::from(inside_count))
}

/// Per box of `boxes`, whether the cloth's `masks` cover most of its top face's silhouette at
/// its start pose (the median share over [`DRAPED_FRAMES`]; a frame without the cloth's mask
/// covers nothing). Measured only: as a box's mass class it lost to every box movable (module
/// doc).
#[cfg(test)]
pub(crate) fn draped(boxes: &[PlacedBox], masks: &ClothMasks, model: &CameraModel) -> Vec<bool> {
    boxes
        .iter()
        .map(|placed| {
            let Some(top) = placed.polygon(model, true) else {
                return false;
            };
            let shares = DRAPED_FRAMES
                .filter_map(|frame| match masks.iter().find(|(at, _)| *at == frame) {
                    Some((_, mask)) => share_covered(&top, model, &|x, y| mask.contains(x, y)),
                    None => Some(0.0),
                })
                .collect();
            median(shares).is_some_and(|share| share > COVERED)
        })
        .collect()
}

/// Reads the cloths from their masks (left, right).
pub(crate) fn read_cloths(masks: &SeenMasks, model: &CameraModel) -> SeenCloths {
    let mut unknown = Vec::new();
    let mut read = |side: Side, index: usize| {
        let cloth = &masks.cloths[index];
        let height = spawn_height(cloth, model).unwrap_or_else(|| {
            unknown.push(format!(
                "the {} cloth's spawn height (no mask in frames 31-40): {MEAN_HEIGHT} taken",
                side.word()
            ));
            MEAN_HEIGHT
        });
        spawn_grid(side, height)
    };
    let left_spawn = read(Side::Left, 0);
    let right_spawn = read(Side::Right, 1);
    SeenCloths {
        spawns: [left_spawn, right_spawn],
        verdict: verdict(&masks.cloths),
        unknown,
    }
}

/// The side a pairwise measure (left, right) points to, told and leaning: with
/// `larger_is_more` the cloth of the larger value has more of the property, else the smaller;
/// told when the difference reaches `margin` of the values' sum; `None` when a cloth has no
/// value (or, leaning, when they are equal).
fn pick(
    values: [Option<f64>; 2],
    larger_is_more: bool,
    margin: f64,
) -> (Option<Side>, Option<Side>) {
    let [Some(left), Some(right)] = values else {
        return (None, None);
    };
    let total = left.abs() + right.abs();
    if total <= 0.0 {
        return (None, None);
    }
    let difference = (left - right) / total;
    let leaning = if difference == 0.0 {
        None
    } else if (difference > 0.0) == larger_is_more {
        Some(Side::Left)
    } else {
        Some(Side::Right)
    };
    (leaning.filter(|_| difference.abs() >= margin), leaning)
}

/// The properties' verdicts from the two cloths' masks (left, right).
pub(crate) fn verdict(masks: &[ClothMasks; 2]) -> ClothVerdict {
    #[expect(
        clippy::unnecessary_wraps,
        reason = "one signature for every per-mask measure"
    )]
    fn area(mask: &InstanceMask) -> Option<f64> {
        Some(mask.area() as f64)
    }
    fn row(mask: &InstanceMask) -> Option<f64> {
        mask.centroid().map(|c| c[1])
    }
    let over = |frames: &std::ops::RangeInclusive<usize>,
                measure: fn(&InstanceMask) -> Option<f64>| {
        [0, 1].map(|i| median_over(&masks[i], frames, measure))
    };
    let (stretches, _) = pick(over(&STRETCH_FRAMES, area), false, STRETCH_MARGIN);
    let (bends, _) = pick(over(&BEND_FRAMES, solidity), true, BEND_MARGIN);
    let (friction, friction_guess) = pick(over(&FRICTION_FRAMES, row), true, FRICTION_MARGIN);
    ClothVerdict {
        stretches,
        bends,
        friction,
        friction_guess,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::cloth::{ClothAnnotation, VOCABULARY};
    use crate::perception::cloth::PERCEPTION;
    use crate::scene_api::PerceptionModels;
    use crate::scene_api::cloth::perceived::perceive_scene;
    use crate::scene_api::perceiver::camera_model;
    use std::path::{Path, PathBuf};

    fn repository(path: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
    }

    /// Area, bounding box, boundary pixels, convex hull area, centroid, top point and the
    /// bottom row's height on the handle's plane of a mask.
    fn features(mask: &InstanceMask, model: &CameraModel, frame: usize) -> serde_json::Value {
        let Some([x0, y0, x1, y1]) = mask.bounds() else {
            return serde_json::Value::Null;
        };
        let mut boundary = 0_u64;
        let mut corners = Vec::new();
        for (x, y) in mask.pixels() {
            let edge = x == 0
                || y == 0
                || !mask.contains(x - 1, y)
                || !mask.contains(x + 1, y)
                || !mask.contains(x, y - 1)
                || !mask.contains(x, y + 1);
            if edge {
                boundary += 1;
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    corners.push([f64::from(x + dx), f64::from(y + dy)]);
                }
            }
        }
        let hull_area = polygon_area(&convex_hull(corners));
        let bottom: Vec<f64> = (x0..=x1)
            .filter(|x| mask.contains(*x, y1))
            .map(|x| f64::from(x) + 0.5)
            .collect();
        let bottom_x = bottom.iter().sum::<f64>() / bottom.len().max(1) as f64;
        let bottom_y = model
            .lift_to_plane(bottom_x, f64::from(y1) + 1.0, handle_z(frame.min(83)))
            .map(|p| p[1]);
        serde_json::json!({
            "area": mask.area(), "bbox": [x0, y0, x1, y1], "boundary": boundary,
            "hull": hull_area, "top": top_point(mask), "centroid": mask.centroid(),
            "bottom_y": bottom_y,
        })
    }

    /// The mask of the convex hull of `corners` seen through `model`.
    fn drawn(model: &CameraModel, corners: &[[f64; 3]]) -> InstanceMask {
        let polygon = convex_hull(
            corners
                .iter()
                .map(|c| model.project(*c).map(|p| [p.x, p.y]).unwrap())
                .collect(),
        );
        InstanceMask::from_predicate(model.width, model.height, |x, y| {
            inside(&polygon, [f64::from(x) + 0.5, f64::from(y) + 0.5])
        })
    }

    fn demo_camera() -> CameraModel {
        let video = repository("eval/demo/cloth_collision/0");
        let truth = ClothAnnotation::load(&video.join("outputs.json")).unwrap();
        camera_model(&truth.camera.unwrap(), (480, 270))
    }

    /// A flat cloth dragged at 2.61: the spawn height is read back within a pixel's worth
    /// (0.03 units) and the grid spawned there.
    #[test]
    fn the_spawn_height_is_read_from_the_mask_s_top() {
        let model = demo_camera();
        let (height, x) = (2.61, HALF_CENTRES[0]);
        let mut masks: ClothMasks = Vec::new();
        for frame in HEIGHT_FRAMES {
            let far = handle_z(frame);
            let corners: Vec<[f64; 3]> = [
                (-1.5, far - CLOTH_SIDE),
                (1.5, far - CLOTH_SIDE),
                (1.5, far),
                (-1.5, far),
            ]
            .iter()
            .map(|(dx, z)| [x + dx, height, *z])
            .collect();
            masks.push((frame, drawn(&model, &corners)));
        }
        let read = spawn_height(&masks, &model).unwrap();
        // The mask drawn here has no particles' thickness: it reads one radius (0.04) low.
        assert!((read + 0.04 - height).abs() < 0.03, "{read}");
        let grid = spawn_grid(Side::Left, read);
        assert_eq!(grid.len(), CLOTH_RESOLUTION * CLOTH_RESOLUTION);
        assert!(grid.iter().all(|p| (p[1] - read).abs() < 1e-12));
        let gripped: Vec<_> = grid
            .iter()
            .filter(|p| (p[2] - CLOTH_START_Z).abs() < 1e-9)
            .collect();
        assert_eq!(gripped.len(), CLOTH_RESOLUTION);
    }

    /// Without masks, the cloths take the release's mean spawn height, say so, lie on no box
    /// and tell no property.
    #[test]
    fn without_masks_the_means_are_taken_and_nothing_is_told() {
        let model = demo_camera();
        let placed = PlacedBox {
            footprint: [-2.4, -1.0],
            size: [0.5, 2.0, 0.5],
            yaw: 0.0,
            iou: 1.0,
        };
        let seen = read_cloths(&SeenMasks::default(), &model);
        assert!(
            seen.spawns
                .iter()
                .flatten()
                .all(|p| (p[1] - MEAN_HEIGHT).abs() < 1e-12)
        );
        assert_eq!(draped(&[placed], &Vec::new(), &model), vec![false]);
        assert_eq!(seen.verdict.stretches, None);
        assert_eq!(seen.verdict.bends, None);
        insta::assert_snapshot!(seen.unknown.join("\n"));
    }

    /// Prints, per video of `CLOTH_VIDEOS` (folders, separated by commas), what the detector
    /// reads of the boxes and the cloths' masks per frame, as one JSON line (a measuring aid).
    #[test]
    #[ignore = "needs ONNX Runtime and videos: CLOTH_VIDEOS=<folder>,<folder>"]
    fn print_the_cloth_measures() {
        let models = PerceptionModels {
            detector: repository(PERCEPTION.detector),
            colors: repository(PERCEPTION.colors),
        };
        let list = std::env::var("CLOTH_VIDEOS").unwrap();
        for video in list.split(',').map(PathBuf::from) {
            let truth = ClothAnnotation::load(&video.join("outputs.json")).unwrap();
            let camera = truth.camera.clone().unwrap();
            let mut perceiver =
                Perceiver::open(&video, &models, PERCEPTION.classes, &VOCABULARY).unwrap();
            let perceived = perceive_scene(&mut perceiver, &camera).unwrap();
            let (width, height, _) = perceiver.frames();
            let model = camera_model(&camera, (width, height));
            let frames: Vec<usize> = CLOTH_FRAMES.collect();
            let seen_masks = seen_masks(&mut perceiver, &model, &frames, &[]).unwrap();
            let masks = &seen_masks.cloths;
            let boxes: Vec<serde_json::Value> = perceived
                .annotation
                .boxes()
                .map(|(side, record)| {
                    serde_json::json!({
                        "side": side.word(), "name": record.name, "scale": record.scale,
                        "start": record.start_position, "yaw": record.start_rotation[1],
                    })
                })
                .collect();
            let placed: [Vec<PlacedBox>; 2] = Side::BOTH.map(|side| {
                perceived
                    .annotation
                    .objects(side)
                    .boxes()
                    .map(PlacedBox::from_record)
                    .collect()
            });
            let shares: Vec<Vec<Vec<f64>>> = (0..2)
                .map(|side| {
                    placed[side]
                        .iter()
                        .map(|placed| {
                            DRAPED_FRAMES
                                .map(|frame| {
                                    masks[side]
                                        .iter()
                                        .find(|(at, _)| *at == frame)
                                        .and_then(|(_, mask)| {
                                            let top = placed.polygon(&model, true)?;
                                            share_covered(&top, &model, &|x, y| mask.contains(x, y))
                                        })
                                        .unwrap_or(-1.0)
                                })
                                .collect()
                        })
                        .collect()
                })
                .collect();
            let seen = read_cloths(&seen_masks, &model);
            let on_top: Vec<Vec<bool>> = (0..2)
                .map(|side| draped(&placed[side], &masks[side], &model))
                .collect();
            let frames: Vec<Vec<(usize, serde_json::Value)>> = masks
                .iter()
                .map(|list| {
                    list.iter()
                        .map(|(f, m)| (*f, features(m, &model, *f)))
                        .collect()
                })
                .collect();
            println!(
                "{}",
                serde_json::json!({
                    "video": video, "unknown": perceived.unknown, "boxes": boxes,
                    "heights": [seen.spawns[0][0][1], seen.spawns[1][0][1]],
                    "draped": on_top, "shares": shares, "verdict": format!("{:?}", seen.verdict),
                    "frames": frames, "cloth_unknown": seen.unknown,
                })
            );
        }
    }
}
