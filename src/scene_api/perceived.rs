//! `--perception maskrcnn` for rope scenes: the objects as the detector sees them.
//!
//! The Mask R-CNN runs on a few frames of the video's first two seconds (every
//! [`FRAME_STEP`]-th frame up to [`LAST_FRAME`], the stretch in which the release's questions
//! describe the scene), its detections are named by colour (`perception::color`) and tracked
//! (`perception::tracking`), and each track names one object: its colour and class words are
//! what `find` matches. Objects the detector misses are not findable, and a misread colour or
//! class makes `find` return the wrong object or none, as in ContPRO.
//!
//! For mass and tension questions under `--dynamics simulate`, [`perceive_positions`] runs the
//! detector on every frame and lifts each track's mask centroid onto the scene plane through the
//! camera; mass inference then matches those tracks instead of the annotated 4-D ones.
//!
//! Binding a track to the mechanism the dynamics backends simulate still uses the release's 2-D
//! boxes of the track's first frame (one assignment by box overlap, kind against kind): the rope
//! topology (which rope runs over which pulley) is not yet read from pixels. Input: a video
//! folder, the model files, the camera record. Output: per annotated object, its perceived words
//! (objects not seen are absent) or its perceived positions, and the work done.

use std::path::Path;

use super::error::ApiError;
use super::scene::PerceptionModels;
use crate::dataset::{Camera, SegmentationRecords};
use crate::perception::assignment::assign;
use crate::perception::camera::CameraModel;
use crate::perception::color::{ColorModel, name_colors};
use crate::perception::detection::{Detection, ObjectClass};
use crate::perception::detector::{Detector, DetectorConfig};
use crate::perception::frames::FrameSource;
use crate::perception::palette::palette_color;
use crate::perception::tracking::{Track, TrackerConfig, track};

/// Every how many frames the detector runs.
pub(crate) const FRAME_STEP: usize = 10;
/// The last frame it runs on (0-based; 2 s at the release's 30 fps).
pub(crate) const LAST_FRAME: usize = 60;
/// Least box IoU for a track to name an annotated object.
const MIN_BINDING_IOU: f64 = 0.3;

/// What perception says about one annotated object.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct PerceivedWords {
    /// Colour words (`light blue`); empty when the colour was not recognised.
    pub color: String,
    /// The detector's class.
    pub class: ObjectClass,
}

/// The outcome of perceiving one video.
#[derive(Debug, Clone, Default)]
pub(crate) struct PerceivedScene {
    /// Annotated object name → its perceived words (objects not listed were not seen).
    pub objects: Vec<(String, PerceivedWords)>,
    /// Tracks that matched no annotated object (false positives).
    pub unbound_tracks: usize,
    /// Frames decoded.
    pub frames_decoded: u64,
    /// Frames run through the detector.
    pub detections: u64,
}

fn unavailable(error: impl std::fmt::Display) -> ApiError {
    ApiError::Unavailable(format!("perception (maskrcnn): {error}"))
}

/// Runs the detector on frames 0, 10, …, 60 and binds its tracks to the annotated objects.
pub(crate) fn perceive_rope(
    video_dir: &Path,
    models: &PerceptionModels,
) -> Result<PerceivedScene, ApiError> {
    perceive(video_dir, models, |count| {
        (0..=LAST_FRAME.min(count.saturating_sub(1)))
            .step_by(FRAME_STEP)
            .collect()
    })
    .map(|(scene, _)| scene)
}

/// The world positions of the bound objects in every frame of the video: the detector runs on
/// all frames, and each track's mask centroid is lifted onto the scene plane (`z = 0`, where the
/// release lays out every rope scene) along the camera's viewing ray. Frames where a track was
/// not seen are `None`. Also returns the work done.
pub(crate) fn perceive_positions(
    video_dir: &Path,
    models: &PerceptionModels,
    camera: &Camera,
) -> Result<PerceivedPositions, ApiError> {
    let (scene, bound) = perceive(video_dir, models, |count| (0..count).collect())?;
    let mut positions = Vec::new();
    for (name, track, size) in bound {
        let model = CameraModel::from_unity_euler(
            camera.position,
            camera.rotation_deg,
            camera.vertical_fov_deg,
            size.0,
            size.1,
        );
        let last = track.last_frame().unwrap_or(0);
        let mut per_frame = vec![None; last + 1];
        for point in &track.observations {
            let direction = model.ray(point.centroid[0], point.centroid[1]);
            if direction[2].abs() < 1e-9 {
                continue;
            }
            let distance = -camera.position[2] / direction[2];
            let world = [
                camera.position[0] + distance * direction[0],
                camera.position[1] + distance * direction[1],
                0.0,
            ];
            if distance > 0.0
                && world.iter().all(|v| v.is_finite())
                && let Some(slot) = per_frame.get_mut(point.frame)
            {
                *slot = Some(world);
            }
        }
        positions.push((name, per_frame));
    }
    Ok(PerceivedPositions {
        positions,
        frames_decoded: scene.frames_decoded,
        detections: scene.detections,
    })
}

/// Per bound object, its world position (units, on the `z = 0` plane) in each frame.
#[derive(Debug, Clone, Default)]
pub(crate) struct PerceivedPositions {
    /// Annotated object name → position per frame (`None`: not seen in that frame).
    pub positions: Vec<(String, Vec<Option<[f64; 3]>>)>,
    /// Frames decoded.
    pub frames_decoded: u64,
    /// Frames run through the detector.
    pub detections: u64,
}

/// A track bound to an annotated object: the object's name, the track, and the frame size.
type BoundTrack = (String, Track, (u32, u32));

/// Detects, names colours, tracks over the frames `choose(frame_count)` picks, and binds the
/// tracks to annotated objects; returns the scene and the bound tracks with the frame size.
fn perceive(
    video_dir: &Path,
    models: &PerceptionModels,
    choose: impl FnOnce(usize) -> Vec<usize>,
) -> Result<(PerceivedScene, Vec<BoundTrack>), ApiError> {
    let colors = ColorModel::read(&models.colors).map_err(unavailable)?;
    let mut detector =
        Detector::load(DetectorConfig::new(models.detector.clone(), 1)).map_err(unavailable)?;
    let png = video_dir.join("frames/output_Full_ori");
    let source = if png.is_dir() {
        FrameSource::PngFolder(png)
    } else {
        FrameSource::open(&video_dir.join("output_Full.mp4"))
            .map_err(|e| ApiError::Data(e.to_string()))?
    };
    let info = source.info().map_err(|e| ApiError::Data(e.to_string()))?;
    let wanted = choose(info.frame_count);
    let mut scene = PerceivedScene::default();
    let mut per_frame: Vec<(usize, Vec<Detection>)> = Vec::with_capacity(wanted.len());
    // Decode in batches so a whole video is never held in memory at once.
    for batch in wanted.chunks(16) {
        let frames = source
            .read(batch)
            .map_err(|e| ApiError::Data(e.to_string()))?;
        scene.frames_decoded += frames.len() as u64;
        for frame in &frames {
            let mut detections = detector.detect(frame).map_err(unavailable)?;
            scene.detections += 1;
            name_colors(frame, &mut detections, &colors);
            per_frame.push((frame.index, detections));
        }
    }
    let tracks = track(&per_frame, &TrackerConfig::default()).map_err(unavailable)?;
    let records = SegmentationRecords::read(&video_dir.join("outputs.json"))?;
    // Each track's first observation, against the annotated boxes of that frame.
    let candidates: Vec<(String, ObjectClass, usize, [f64; 4])> = records
        .boxes
        .iter()
        .filter(|(frame, _)| wanted.contains(frame))
        .flat_map(|(frame, boxes)| {
            boxes.iter().filter_map(|(id, bbox)| {
                let name = records.names.get(id)?;
                let class = ObjectClass::from_object_name(name)?;
                Some((name.clone(), class, *frame, *bbox))
            })
        })
        .collect();
    let mut names: Vec<String> = candidates.iter().map(|c| c.0.clone()).collect();
    names.sort();
    names.dedup();
    let firsts: Vec<Option<(usize, [f64; 4])>> = tracks
        .iter()
        .map(|t| {
            t.observations
                .first()
                .map(|p| (p.frame, p.bbox.map(f64::from)))
        })
        .collect();
    let binding = assign(tracks.len(), names.len(), |t, n| {
        let (frame, seen) = firsts[t]?;
        let (_, class, _, annotated) = candidates
            .iter()
            .find(|c| c.0 == names[n] && c.2 == frame)?;
        if class.kind() != tracks[t].class.kind() && !(is_load(*class) && is_load(tracks[t].class))
        {
            return None;
        }
        let overlap = box_iou(seen, *annotated);
        (overlap >= MIN_BINDING_IOU).then_some(1.0 - overlap)
    });
    let mut bound_tracks = Vec::new();
    for (t, bound) in binding.iter().enumerate() {
        match bound {
            Some(n) => {
                bound_tracks.push((
                    names[*n].clone(),
                    tracks[t].clone(),
                    (info.width, info.height),
                ));
                scene.objects.push((
                    names[*n].clone(),
                    PerceivedWords {
                        color: tracks[t]
                            .color
                            .and_then(palette_color)
                            .map(|c| c.name.to_lowercase())
                            .unwrap_or_default(),
                        class: tracks[t].class,
                    },
                ));
            }
            None => scene.unbound_tracks += 1,
        }
    }
    scene.objects.sort_by(|a, b| a.0.cmp(&b.0));
    Ok((scene, bound_tracks))
}

fn is_load(class: ObjectClass) -> bool {
    matches!(class, ObjectClass::Cube | ObjectClass::Sphere)
}

fn box_iou(a: [f64; 4], b: [f64; 4]) -> f64 {
    let width = (a[2].min(b[2]) - a[0].max(b[0])).max(0.0);
    let height = (a[3].min(b[3]) - a[1].max(b[1])).max(0.0);
    let intersection = width * height;
    let area = |r: [f64; 4]| (r[2] - r[0]).max(0.0) * (r[3] - r[1]).max(0.0);
    let union = area(a) + area(b) - intersection;
    if union > 0.0 {
        intersection / union
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_overlap_is_intersection_over_union() {
        assert!((box_iou([0.0, 0.0, 2.0, 2.0], [1.0, 0.0, 3.0, 2.0]) - 1.0 / 3.0).abs() < 1e-12);
        assert!(box_iou([0.0, 0.0, 1.0, 1.0], [2.0, 2.0, 3.0, 3.0]).abs() < 1e-12);
    }
}
