//! A cloth scene read from pixels (`--perception maskrcnn`): the pillars and plates the detector
//! finds before the cloths spawn, placed in the world through the camera calibration and named
//! by colour and shape as the questions name them (`Green Plate`), so the simulate backend runs
//! on them as on an annotation's boxes.
//!
//! Input: the first pass of a [`Perceiver`] (tracks over frames 0–60 with their colours) and the
//! video's camera record. Output: [`PerceivedCloth`], a release-format [`ClothAnnotation`] of the
//! boxes (sizes, start poses; no outcomes, no masses, placeholder cloth properties) and the name
//! each first-pass track stands for. What the cloths do is read by `pixels`.
//!
//! **Boxes.** A box stands on the table (`y = 0`), turned about `y` only: a pillar is a square
//! column (side, height; the release does not turn pillars), a plate a slab (width, height,
//! thickness, yaw). Its mask is its silhouette, the convex hull of its eight corners seen through
//! the camera. The box is the one whose silhouette covers the masks of its track in the frames
//! before the cloth spawns (frames 0, 10 and 20) best (mean pixel IoU; a pattern search from the
//! mask's bottom edge lifted onto the table, a plate from three yaws), where pixels of another
//! box's mask whose bottom is lower in the image (a nearer box) are hidden and count for
//! neither. A box is named by its track's colour and its class; two tracks of one name keep the
//! one seen more often; its half is the side of `x = 0` it stands on.

use std::collections::BTreeMap;

use crate::dataset::Camera;
use crate::dataset::cloth::names::{Shape, Side, box_name};
use crate::dataset::cloth::outcome::Pose;
use crate::dataset::cloth::{
    BoxRecord, ClothAnnotation, ClothProperties, Friction, HalfObjects, RegionForces, VALUES,
};
use crate::dataset::palette::palette_name;
use crate::perception::camera::CameraModel;
use crate::perception::classes::ClassTable;
use crate::perception::detection::{Detection, InstanceMask};
use crate::perception::silhouette::{convex_hull, pattern_search, polygon_iou};
use crate::perception::tracking::Track;
use crate::physics::vector3 as v3;
use crate::scene_api::ApiError;
use crate::scene_api::perceiver::{Perceiver, camera_model};
use crate::synth::cloth::layout::HALF_CENTRES;
use crate::synth::cloth::simulate::{CAPTURE_EVERY, SPAWN_UPDATE};

use super::simulate::unity_rotation;

/// The first video frame the cloths are in (update 60, two updates a frame).
pub(crate) const SPAWN_FRAME: usize = SPAWN_UPDATE / CAPTURE_EVERY;
/// Yaws a plate's fit starts from, radians (the release turns plates by −30° to 30°).
const PLATE_START_YAWS: [f64; 3] = [-0.2, 0.05, 0.3];
/// Where a pillar's parameters may go: side, height, units. The release's ranges (cubes of
/// 0.45–0.6 stacked to at most 2.2: heights 1.65–2.2) and a pixel's slack: a front view barely
/// tells a box's depth from its width, and the layout's rule does.
const PILLAR_BOUNDS: [[f64; 2]; 2] = [[0.44, 0.61], [1.6, 2.25]];
/// Where a plate's parameters may go: width, height, thickness (units), yaw (radians). The
/// release's ranges (0.9–1.4, 1.4–2.1, 0.35–0.45, ±30°) and a pixel's slack.
const PLATE_BOUNDS: [[f64; 2]; 4] = [[0.88, 1.42], [1.38, 2.12], [0.35, 0.45], [-0.53, 0.53]];

/// A cloth scene's boxes as the video shows them.
#[derive(Debug, Clone)]
pub(crate) struct PerceivedCloth {
    /// The boxes in the release's format (no outcomes; masses 0 and the cloths' properties are
    /// placeholders: the dynamics read the cloths from their masks).
    pub annotation: ClothAnnotation,
    /// Per first-pass track, the box it was read as (`None`: none).
    pub names: Vec<Option<String>>,
    /// What the video could not tell, one line per object.
    pub unknown: Vec<String>,
}

/// A box placed in the world: centre of its footprint, full extents, yaw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PlacedBox {
    /// Footprint centre `(x, z)`, units.
    pub footprint: [f64; 2],
    /// Full extents along its local x, y, z, units.
    pub size: [f64; 3],
    /// Turn about `y`, radians (Unity's sense: the release's `startRot[1]`).
    pub yaw: f64,
    /// Mean IoU of its silhouette with the masks it was fitted to.
    pub iou: f64,
}

impl PlacedBox {
    /// The box of an annotation's record where it starts.
    pub(crate) fn from_record(record: &BoxRecord) -> PlacedBox {
        PlacedBox {
            footprint: [record.start_position[0], record.start_position[2]],
            size: record.scale,
            yaw: record.start_rotation[1].to_radians(),
            iou: 1.0,
        }
    }

    /// Its eight corners, units.
    pub(crate) fn corners(&self) -> Vec<[f64; 3]> {
        let rotation = v3::rotation_matrix(unity_rotation([0.0, self.yaw.to_degrees(), 0.0]));
        let [w, h, d] = self.size;
        let mut corners = Vec::with_capacity(8);
        for y in [0.0, h] {
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let local = v3::apply(&rotation, [a * w / 2.0, 0.0, b * d / 2.0]);
                corners.push([
                    self.footprint[0] + local[0],
                    y,
                    self.footprint[1] + local[2],
                ]);
            }
        }
        corners
    }

    /// Its silhouette through `model`: the hull of `corners` (all eight, or the top four for
    /// its top face); `None` when a corner is behind the camera.
    pub(crate) fn polygon(&self, model: &CameraModel, top_only: bool) -> Option<Vec<[f64; 2]>> {
        let corners = self.corners();
        let chosen = if top_only {
            &corners[4..]
        } else {
            &corners[..]
        };
        let projected: Option<Vec<[f64; 2]>> = chosen
            .iter()
            .map(|corner| model.project(*corner).map(|p| [p.x, p.y]))
            .collect();
        Some(convex_hull(projected?))
    }
}

/// Reads the boxes of the video `perceiver` opened, seen through `camera`.
pub(crate) fn perceive_scene(
    perceiver: &mut Perceiver,
    camera: &Camera,
) -> Result<PerceivedCloth, ApiError> {
    perceiver.first_pass()?;
    let (width, height, frame_count) = perceiver.frames();
    let model = camera_model(camera, (width, height));
    let Some(classes) = perceiver.classes() else {
        return Ok(PerceivedCloth {
            annotation: annotation(&[], camera),
            names: vec![None; perceiver.first_tracks().len()],
            unknown: vec!["the video has no frames".to_string()],
        });
    };
    let mut perceived = read_boxes(
        perceiver.first_tracks(),
        perceiver.first_detections(),
        classes,
        &model,
        camera,
    );
    perceived.annotation.frame_count = frame_count;
    Ok(perceived)
}

/// The boxes of the first pass's `tracks` (their detections per frame in `detections`).
pub(crate) fn read_boxes(
    tracks: &[Track],
    detections: &BTreeMap<usize, Vec<Detection>>,
    classes: &ClassTable,
    model: &CameraModel,
    camera: &Camera,
) -> PerceivedCloth {
    let mut names = vec![None; tracks.len()];
    let mut unknown = Vec::new();
    // (track index, name, shape, placed box, observations)
    let mut read: Vec<(usize, String, Shape, PlacedBox, usize)> = Vec::new();
    for (index, track) in tracks.iter().enumerate() {
        let shape = match classes.kind(track.class) {
            "pillar" => Shape::Pillar,
            "plate" => Shape::Plate,
            _ => continue,
        };
        let Some(color) = track.color.and_then(|color| palette_name(i64::from(color))) else {
            unknown.push(format!(
                "a {} of no palette colour (track {})",
                shape.word(),
                track.id
            ));
            continue;
        };
        let name = box_name(color, shape);
        let Some(placed) = place_track(track, detections, model, shape) else {
            unknown.push(format!("{name}: no silhouette fits its masks"));
            continue;
        };
        let seen = track.observations.len();
        if let Some(other) = read.iter_mut().find(|entry| entry.1 == name) {
            unknown.push(format!("{name}: read twice, the one seen more often kept"));
            if other.4 < seen {
                *other = (index, name, shape, placed, seen);
            }
            continue;
        }
        read.push((index, name, shape, placed, seen));
    }
    let mut records: Vec<(Side, BoxRecord)> = Vec::new();
    for (index, name, shape, placed, _) in read {
        let side = if placed.footprint[0] < 0.0 {
            Side::Left
        } else {
            Side::Right
        };
        if let Some(slot) = names.get_mut(index) {
            *slot = Some(name.clone());
        }
        records.push((side, box_record(name, shape, side, &placed)));
    }
    // Pillars, then plates, each left to right: the release's order within a half.
    records.sort_by(|a, b| {
        (a.1.shape != Shape::Pillar)
            .cmp(&(b.1.shape != Shape::Pillar))
            .then(a.1.start_position[0].total_cmp(&b.1.start_position[0]))
    });
    PerceivedCloth {
        annotation: annotation(&records, camera),
        names,
        unknown,
    }
}

/// The box `track` shows in its frames before the cloths spawn (all its frames if none).
fn place_track(
    track: &Track,
    detections: &BTreeMap<usize, Vec<Detection>>,
    model: &CameraModel,
    shape: Shape,
) -> Option<PlacedBox> {
    let early: Vec<_> = track
        .observations
        .iter()
        .filter(|point| point.frame < SPAWN_FRAME)
        .collect();
    let points = if early.is_empty() {
        track.observations.iter().collect()
    } else {
        early
    };
    let views: Vec<View<'_>> = points
        .iter()
        .filter_map(|point| {
            let frame = detections.get(&point.frame)?;
            let own = frame.get(point.detection)?;
            let bottom = own.mask.bounds()?[3];
            let nearer = frame
                .iter()
                .enumerate()
                .filter(|(index, other)| {
                    *index != point.detection && other.mask.bounds().is_some_and(|b| b[3] > bottom)
                })
                .map(|(_, other)| &other.mask)
                .collect();
            Some(View {
                mask: &own.mask,
                nearer,
            })
        })
        .collect();
    fit_box(model, shape, &views)
}

/// One mask of a box and the masks of the boxes in front of it.
pub(crate) struct View<'a> {
    /// The box's mask.
    pub mask: &'a InstanceMask,
    /// Masks of nearer boxes (their pixels may hide the box).
    pub nearer: Vec<&'a InstanceMask>,
}

/// The box of `shape` whose silhouette covers `views` best; `None` without a usable mask.
pub(crate) fn fit_box(model: &CameraModel, shape: Shape, views: &[View<'_>]) -> Option<PlacedBox> {
    let first = views.iter().max_by_key(|view| view.mask.area())?;
    let [x0, _, x1, y1] = first.mask.bounds()?;
    let bottom = model.lift_to_height(
        f64::midpoint(f64::from(x0), f64::from(x1) + 1.0),
        f64::from(y1) + 1.0,
        0.0,
    )?;
    let cost = |placed: &PlacedBox| {
        let Some(polygon) = placed.polygon(model, false) else {
            return 1.0;
        };
        let total: f64 = views
            .iter()
            .map(|view| {
                let hidden = |x: u32, y: u32| view.nearer.iter().any(|mask| mask.contains(x, y));
                polygon_iou(&polygon, view.mask, (model.width, model.height), &hidden)
            })
            .sum();
        1.0 - total / views.len() as f64
    };
    let within = |value: f64, [low, high]: [f64; 2]| (low..=high).contains(&value);
    let placed = match shape {
        Shape::Pillar => {
            let side = 0.52;
            let box_of = |p: &[f64; 4]| PlacedBox {
                footprint: [p[0], p[1]],
                size: [p[2], p[3], p[2]],
                yaw: 0.0,
                iou: 0.0,
            };
            let (best, cost) = pattern_search(
                [bottom[0], bottom[1] + side / 2.0, side, 1.9],
                [0.1, 0.1, 0.05, 0.1],
                0.002,
                &|p| within(p[2], PILLAR_BOUNDS[0]) && within(p[3], PILLAR_BOUNDS[1]),
                &|p| cost(&box_of(p)),
            );
            PlacedBox {
                iou: 1.0 - cost,
                ..box_of(&best)
            }
        }
        Shape::Plate | Shape::Cube => {
            let thickness = 0.4;
            let box_of = |p: &[f64; 6]| PlacedBox {
                footprint: [p[0], p[1]],
                size: [p[2], p[3], p[4]],
                yaw: p[5],
                iou: 0.0,
            };
            let valid = |p: &[f64; 6]| {
                within(p[2], PLATE_BOUNDS[0])
                    && within(p[3], PLATE_BOUNDS[1])
                    && within(p[4], PLATE_BOUNDS[2])
                    && within(p[5], PLATE_BOUNDS[3])
            };
            PLATE_START_YAWS
                .iter()
                .map(|yaw| {
                    let (best, cost) = pattern_search(
                        [
                            bottom[0],
                            bottom[1] + thickness / 2.0,
                            1.15,
                            1.75,
                            thickness,
                            *yaw,
                        ],
                        [0.1, 0.1, 0.05, 0.1, 0.03, 0.08],
                        0.002,
                        &valid,
                        &|p| cost(&box_of(p)),
                    );
                    PlacedBox {
                        iou: 1.0 - cost,
                        ..box_of(&best)
                    }
                })
                .max_by(|a, b| a.iou.total_cmp(&b.iou))?
        }
    };
    (placed.iou > 0.0
        && placed
            .footprint
            .iter()
            .chain(&placed.size)
            .all(|v| v.is_finite()))
    .then_some(placed)
}

/// The release-format record of a box read as `placed` in `side`'s half.
fn box_record(name: String, shape: Shape, side: Side, placed: &PlacedBox) -> BoxRecord {
    let centre_x = match side {
        Side::Left => HALF_CENTRES[0],
        Side::Right => HALF_CENTRES[1],
    };
    let color = name
        .rsplit_once(' ')
        .map_or_else(String::new, |(color, _)| color.to_string());
    let yaw = placed.yaw.to_degrees();
    let start = [
        placed.footprint[0],
        placed.size[1] / 2.0,
        placed.footprint[1],
    ];
    BoxRecord {
        name,
        color,
        color_rgba: [0.0, 0.0, 0.0, 1.0],
        shape,
        scale: placed.size,
        sampled_position_local: [placed.footprint[0] - centre_x, 0.0, placed.footprint[1]],
        sampled_rotation: [0.0, yaw, 0.0],
        start_position: start,
        start_rotation: [0.0, yaw, 0.0],
        end_position: start,
        end_rotation: [0.0, yaw, 0.0],
        end_pose: Pose::Upright,
        mass: 0.0,
        collision_events: Vec::new(),
        start_moving_update: None,
        touchers: Vec::new(),
    }
}

/// A release-format annotation of `records` (each with its half) seen through `camera`.
fn annotation(records: &[(Side, BoxRecord)], camera: &Camera) -> ClothAnnotation {
    let placeholder = ClothProperties {
        stretching_compliance: f64::midpoint(
            VALUES.stretch_compliance[0],
            VALUES.stretch_compliance[1],
        ),
        bending_compliance: f64::midpoint(VALUES.max_bending[0], VALUES.max_bending[1]),
        friction: Friction::Low,
        region_forces: RegionForces {
            red: 0.0,
            blue: 0.0,
            yellow: 0.0,
            green: 0.0,
        },
    };
    let half = |side: Side| HalfObjects {
        towers: Vec::new(),
        isolated: records
            .iter()
            .filter(|(of, _)| *of == side)
            .map(|(_, record)| record.clone())
            .collect(),
    };
    ClothAnnotation {
        left_cloth: placeholder,
        right_cloth: placeholder,
        left_objects: half(Side::Left),
        right_objects: half(Side::Right),
        camera: Some(camera.clone()),
        id_to_object_name: Vec::new(),
        frame_count: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::cloth::PERCEPTION;
    use crate::perception::tracking::{TrackerConfig, track};
    use crate::scene_api::perceiver::truth_detections;
    use std::path::Path;

    /// The worst errors of `read` against `truth` over their common boxes: footprint distance,
    /// size, yaw (degrees); and the names of `truth` not read.
    pub(crate) fn placement_errors(
        read: &ClothAnnotation,
        truth: &ClothAnnotation,
    ) -> ([f64; 3], Vec<String>) {
        let mut worst = [0.0_f64; 3];
        let mut missing = Vec::new();
        for (side, record) in truth.boxes() {
            let Some((read_side, other)) = read.find_box(&record.name) else {
                missing.push(record.name.clone());
                continue;
            };
            assert_eq!(read_side, side, "{}", record.name);
            let (a, b) = (record.start_position, other.start_position);
            worst[0] = worst[0].max((a[0] - b[0]).hypot(a[2] - b[2]));
            for axis in 0..3 {
                let error = (record.scale[axis] - other.scale[axis]).abs();
                worst[1] = worst[1].max(error);
            }
            let turn = (record.start_rotation[1] - other.start_rotation[1] + 540.0) % 360.0 - 180.0;
            worst[2] = worst[2].max(turn.abs());
        }
        (worst, missing)
    }

    /// Read from the segmentation truth of the generated demo videos (320 × 180 mp4s, a pixel
    /// about 0.04 units there), every pillar and plate is named as annotated, in its half, its
    /// footprint within 0.12 units, its extents within 0.2 (a plate whose side edge a pillar
    /// hides trades width for yaw: 0.18 on video 0) and its yaw within 12° (11.7° on video 1).
    #[test]
    fn a_perfect_detector_places_the_annotated_boxes() {
        for folder in ["eval/demo/cloth_collision/0", "eval/demo/cloth_collision/1"] {
            let video = Path::new(env!("CARGO_MANIFEST_DIR")).join(folder);
            let truth = ClothAnnotation::load(&video.join("outputs.json")).unwrap();
            let camera = truth.camera.clone().unwrap();
            let wanted: Vec<usize> = (0..=60).step_by(10).collect();
            let (per_frame, classes) = truth_detections(&video, PERCEPTION.classes, &wanted);
            let tracks = track(&per_frame, &TrackerConfig::default()).unwrap();
            let detections: BTreeMap<usize, Vec<Detection>> = per_frame.into_iter().collect();
            let model = camera_model(&camera, (320, 180));
            let read = read_boxes(&tracks, &detections, &classes, &model, &camera);
            assert!(read.unknown.is_empty(), "{folder}: {:?}", read.unknown);
            let (worst, missing) = placement_errors(&read.annotation, &truth);
            assert!(missing.is_empty(), "{folder}: {missing:?}");
            assert_eq!(read.annotation.boxes().count(), truth.boxes().count());
            assert!(
                worst[0] < 0.12 && worst[1] < 0.2 && worst[2] < 12.0,
                "{folder}: footprint {:.3}, size {:.3}, yaw {:.1}°",
                worst[0],
                worst[1],
                worst[2]
            );
        }
    }
}
