//! `--perception maskrcnn` for rope scenes: the objects as the detector sees them.
//!
//! The Mask R-CNN runs on a few frames of the video's first two seconds (every
//! [`FRAME_STEP`]-th frame up to [`LAST_FRAME`], the stretch in which the release's questions
//! describe the scene), its detections are named by colour (`perception::color`) and tracked
//! (`perception::tracking`), and each track names one object: its colour and class words are
//! what `find` matches. Objects the detector misses are not findable, and a misread colour or
//! class makes `find` return the wrong object or none, as in ContPRO.
//!
//! For mass and tension questions under `--dynamics simulate`, [`Perceiver::positions`] runs
//! the detector on every frame (reusing the frames the object list was read from) and lifts each track's mask centroid onto the scene plane through the
//! camera; mass inference then matches those tracks instead of the annotated 4-D ones.
//!
//! Binding a track to the mechanism the dynamics backends simulate still uses the release's 2-D
//! boxes of the track's first frame (one assignment by box overlap, kind against kind): the rope
//! topology (which rope runs over which pulley) is not yet read from pixels. Input: a video
//! folder, the model files, the camera record. Output: per annotated object, its perceived words
//! (objects not seen are absent) or its perceived positions, and the work done.
//!
//! The models are loaded once per process and shared by every scene in it (one ONNX Runtime
//! session per sandbox worker, not one per video).

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Mutex, PoisonError};

use super::error::ApiError;
use super::scene::PerceptionModels;
use crate::dataset::{Camera, SegmentationRecords};
use crate::perception::assignment::assign;
use crate::perception::camera::CameraModel;
use crate::perception::color::{ColorModel, name_colors};
use crate::perception::detection::{Detection, ObjectClass};
use crate::perception::detector::{Detector, DetectorConfig};
use crate::perception::frames::{FrameSource, Stream, VideoInfo};
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

/// The objects perception found in one video.
#[derive(Debug, Clone, Default)]
pub(crate) struct PerceivedScene {
    /// Annotated object name → its perceived words (objects not listed were not seen).
    pub objects: Vec<(String, PerceivedWords)>,
    /// Tracks that matched no annotated object (false positives).
    pub unbound_tracks: usize,
}

/// Per bound object, its world position (units, on the `z = 0` plane) in each frame (`None`:
/// not seen in that frame).
pub(crate) type PerceivedPositions = Vec<(String, Vec<Option<[f64; 3]>>)>;

fn unavailable(error: impl std::fmt::Display) -> ApiError {
    ApiError::Unavailable(format!("perception (maskrcnn): {error}"))
}

/// The loaded models, shared by every scene of the process; replaced when a scene asks for
/// other files.
static LOADED: Mutex<Option<(PerceptionModels, Detector, ColorModel)>> = Mutex::new(None);

/// Runs `work` with the detector and colour model of `models`, loading them on first use.
fn with_models<T>(
    models: &PerceptionModels,
    work: impl FnOnce(&mut Detector, &ColorModel) -> Result<T, ApiError>,
) -> Result<T, ApiError> {
    let mut loaded = LOADED.lock().unwrap_or_else(PoisonError::into_inner);
    if loaded.as_ref().is_none_or(|(files, _, _)| files != models) {
        let colors = ColorModel::read(&models.colors).map_err(unavailable)?;
        let detector =
            Detector::load(DetectorConfig::new(models.detector.clone(), 1)).map_err(unavailable)?;
        *loaded = Some((models.clone(), detector, colors));
    }
    match loaded.as_mut() {
        Some((_, detector, colors)) => work(detector, colors),
        None => Err(unavailable("the models could not be kept loaded")),
    }
}

/// One video as the detector sees it: its frames and annotated boxes, read once per scene, and
/// the detections the object list was read from.
pub(crate) struct Perceiver {
    models: PerceptionModels,
    source: FrameSource,
    info: VideoInfo,
    records: SegmentationRecords,
    /// Detections of the frames [`Perceiver::scene`] ran, reused by [`Perceiver::positions`].
    kept: BTreeMap<usize, Vec<Detection>>,
    /// Frames decoded and run through the detector so far.
    work: (u64, u64),
}

impl Perceiver {
    /// Opens the video's frames and its annotated boxes; runs nothing yet.
    pub(crate) fn open(video_dir: &Path, models: &PerceptionModels) -> Result<Self, ApiError> {
        let source = FrameSource::of_video(video_dir, Stream::Rgb)
            .map_err(|e| ApiError::Data(e.to_string()))?;
        let info = source.info().map_err(|e| ApiError::Data(e.to_string()))?;
        let records = SegmentationRecords::read(&video_dir.join("outputs.json"))?;
        Ok(Perceiver {
            models: models.clone(),
            source,
            info,
            records,
            kept: BTreeMap::new(),
            work: (0, 0),
        })
    }

    /// Frames decoded and frames run through the detector so far.
    pub(crate) fn work(&self) -> (u64, u64) {
        self.work
    }

    /// The objects of the video: the detector on frames 0, 10, …, 60, tracks bound to the
    /// annotated objects.
    pub(crate) fn scene(&mut self) -> Result<PerceivedScene, ApiError> {
        let wanted: Vec<usize> = (0..=LAST_FRAME.min(self.info.frame_count.saturating_sub(1)))
            .step_by(FRAME_STEP)
            .collect();
        let per_frame = self.detect(&wanted)?;
        self.kept = per_frame.iter().cloned().collect();
        let tracks = track(&per_frame, &TrackerConfig::default()).map_err(unavailable)?;
        let mut scene = PerceivedScene::default();
        for (track, name) in tracks.iter().zip(self.bind(&tracks, &wanted)) {
            match name {
                Some(name) => scene.objects.push((
                    name,
                    PerceivedWords {
                        color: track
                            .color
                            .and_then(palette_color)
                            .map(|c| c.name.to_lowercase())
                            .unwrap_or_default(),
                        class: track.class,
                    },
                )),
                None => scene.unbound_tracks += 1,
            }
        }
        scene.objects.sort_by(|a, b| a.0.cmp(&b.0));
        Ok(scene)
    }

    /// The world positions of the bound objects in every frame of the video: the detector runs
    /// on all frames, and each track's mask centroid is lifted onto the scene plane (`z = 0`,
    /// where the release lays out every rope scene) along the camera's viewing ray.
    pub(crate) fn positions(&mut self, camera: &Camera) -> Result<PerceivedPositions, ApiError> {
        let wanted: Vec<usize> = (0..self.info.frame_count).collect();
        let per_frame = self.detect(&wanted)?;
        let tracks = track(&per_frame, &TrackerConfig::default()).map_err(unavailable)?;
        let model = CameraModel::from_unity_euler(
            camera.position,
            camera.rotation_deg,
            camera.vertical_fov_deg,
            self.info.width,
            self.info.height,
        );
        let mut positions = Vec::new();
        for (track, name) in tracks.iter().zip(self.bind(&tracks, &wanted)) {
            let Some(name) = name else {
                continue;
            };
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
        Ok(positions)
    }

    /// Detections with colours for `wanted`, in order; frames [`Perceiver::scene`] ran are
    /// reused, the rest decoded in batches so a whole video is never held in memory at once.
    fn detect(&mut self, wanted: &[usize]) -> Result<Vec<(usize, Vec<Detection>)>, ApiError> {
        let missing: Vec<usize> = wanted
            .iter()
            .copied()
            .filter(|f| !self.kept.contains_key(f))
            .collect();
        let mut found: BTreeMap<usize, Vec<Detection>> = BTreeMap::new();
        for batch in missing.chunks(16) {
            let frames = self
                .source
                .read(batch)
                .map_err(|e| ApiError::Data(e.to_string()))?;
            self.work.0 += frames.len() as u64;
            with_models(&self.models, |detector, colors| {
                for frame in &frames {
                    let mut detections = detector.detect(frame).map_err(unavailable)?;
                    name_colors(frame, &mut detections, colors);
                    found.insert(frame.index, detections);
                }
                Ok(())
            })?;
            self.work.1 += frames.len() as u64;
        }
        Ok(wanted
            .iter()
            .filter_map(|f| {
                let detections = found.remove(f).or_else(|| self.kept.get(f).cloned())?;
                Some((*f, detections))
            })
            .collect())
    }

    /// The annotated object each track stands for, by box overlap with the annotated boxes of
    /// the track's first frame (kind against kind; one track per object).
    fn bind(&self, tracks: &[Track], wanted: &[usize]) -> Vec<Option<String>> {
        let records = &self.records;
        let candidates: Vec<(String, ObjectClass, usize, [f64; 4])> = records
            .boxes
            .iter()
            .filter(|(frame, _)| wanted.binary_search(frame).is_ok())
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
        assign(tracks.len(), names.len(), |t, n| {
            let (frame, seen) = firsts[t]?;
            let (_, class, _, annotated) = candidates
                .iter()
                .find(|c| c.0 == names[n] && c.2 == frame)?;
            if class.kind() != tracks[t].class.kind()
                && !(is_load(*class) && is_load(tracks[t].class))
            {
                return None;
            }
            let overlap = box_iou(seen, *annotated);
            (overlap >= MIN_BINDING_IOU).then_some(1.0 - overlap)
        })
        .into_iter()
        .map(|bound| bound.map(|n| names[n].clone()))
        .collect()
    }
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
