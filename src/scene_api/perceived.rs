//! `--perception maskrcnn` for rope scenes: the objects as the detector sees them.
//!
//! The Mask R-CNN runs on a few frames of the video's first two seconds (every
//! [`FRAME_STEP`]-th frame up to [`LAST_FRAME`], the stretch in which the release's questions
//! describe the scene), its detections are named by colour (`perception::color`) and tracked
//! (`perception::tracking`), and each track names one object: its colour and class words are
//! what `find` matches. Objects the detector misses are not findable, and a misread colour or
//! class makes `find` return the wrong object or none, as in ContPRO.
//!
//! Under `--dynamics simulate` (ContPRO) the mechanism itself is read from pixels
//! ([`Perceiver::mechanism`], `perceived_rope`): objects named from their tracks, rope paths from
//! the rope masks and colours, positions lifted through the camera calibration; no other
//! annotation is read. Under `--dynamics annotation` (the oracle dynamics, whose recorded results
//! are keyed by the release's names) the first pass's tracks are bound to the annotated objects
//! by box overlap ([`Perceiver::scene`]).
//!
//! For mass and tension questions, [`Perceiver::positions`] runs the detector on every frame
//! (reusing the first pass's frames), gives each track the name of the first-pass track it shares
//! detections with, and lifts its mask centroids onto the scene plane; mass inference matches
//! those tracks. Input: a video folder, the model files, the camera calibration. Output: the
//! perceived mechanism, or per annotated object its perceived words, or per named object its
//! perceived positions, and the work done.
//!
//! The models are loaded once per process and shared by every scene in it (one ONNX Runtime
//! session per sandbox worker, not one per video).

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Mutex, PoisonError};

use super::error::ApiError;
use super::perceived_rope::{PerceivedRope, lift, perceive_rope};
use super::scene::PerceptionModels;
use crate::dataset::{Camera, SegmentationRecords};
use crate::perception::assignment::assign;
use crate::perception::camera::CameraModel;
use crate::perception::color::{ColorModel, name_colors};
use crate::perception::detection::{Detection, ObjectClass};
use crate::perception::detector::{Detector, DetectorConfig};
use crate::perception::frames::{FrameSource, RgbFrame, Stream, VideoInfo};
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

/// Detections per frame, in frame order.
type FrameDetections = Vec<(usize, Vec<Detection>)>;

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

/// One video as the detector sees it: its frames, read once per scene, the first pass's
/// detections and tracks, and the name each of those tracks stands for.
pub(crate) struct Perceiver {
    models: PerceptionModels,
    video_dir: std::path::PathBuf,
    source: FrameSource,
    info: VideoInfo,
    /// Detections of the first pass (frames 0, 10, …, 60), reused by [`Perceiver::positions`].
    kept: BTreeMap<usize, Vec<Detection>>,
    /// The first pass's tracks (empty until it ran).
    first: Vec<Track>,
    /// Per first-pass track, the object it stands for.
    names: Vec<Option<String>>,
    /// Frames decoded and run through the detector so far.
    work: (u64, u64),
}

impl Perceiver {
    /// Opens the video's frames; runs nothing yet.
    pub(crate) fn open(video_dir: &Path, models: &PerceptionModels) -> Result<Self, ApiError> {
        let source = FrameSource::of_video(video_dir, Stream::Rgb)
            .map_err(|e| ApiError::Data(e.to_string()))?;
        let info = source.info().map_err(|e| ApiError::Data(e.to_string()))?;
        Ok(Perceiver {
            models: models.clone(),
            video_dir: video_dir.to_path_buf(),
            source,
            info,
            kept: BTreeMap::new(),
            first: Vec::new(),
            names: Vec::new(),
            work: (0, 0),
        })
    }

    /// Frames decoded and frames run through the detector so far.
    pub(crate) fn work(&self) -> (u64, u64) {
        self.work
    }

    /// Frames of the first pass: 0, 10, …, 60 (those the video has).
    fn first_frames(&self) -> Vec<usize> {
        (0..=LAST_FRAME.min(self.info.frame_count.saturating_sub(1)))
            .step_by(FRAME_STEP)
            .collect()
    }

    /// Runs the first pass once: the detector on frames 0, 10, …, 60, and the tracks. Returns
    /// the pass's first frame when this call ran it (the caller may want its pixels; the scene
    /// does not keep frames, since a worker keeps one scene per video it has seen).
    fn first_pass(&mut self) -> Result<Option<RgbFrame>, ApiError> {
        if !self.kept.is_empty() || self.info.frame_count == 0 {
            return Ok(None);
        }
        let wanted = self.first_frames();
        let (per_frame, first_frame) = self.detect(&wanted, wanted.first().copied())?;
        self.first = track(&per_frame, &TrackerConfig::default()).map_err(unavailable)?;
        self.kept = per_frame.into_iter().collect();
        Ok(first_frame)
    }

    /// The objects of the video under the oracle dynamics (`--dynamics annotation`), whose
    /// recorded results are keyed by the release's names: the first pass's tracks bound to the
    /// annotated objects by box overlap.
    pub(crate) fn scene(&mut self) -> Result<PerceivedScene, ApiError> {
        self.first_pass()?;
        let records = SegmentationRecords::read(&self.video_dir.join("outputs.json"))?;
        self.names = bind_to_annotation(&self.first, &self.first_frames(), &records);
        let mut scene = PerceivedScene::default();
        for (track, name) in self.first.iter().zip(&self.names) {
            match name {
                Some(name) => scene.objects.push((
                    name.clone(),
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

    /// The mechanism as seen (`--dynamics simulate`): objects named from their tracks, rope
    /// paths read from the rope masks, positions lifted through the camera (`perceived_rope`).
    pub(crate) fn mechanism(&mut self, camera: &Camera) -> Result<PerceivedRope, ApiError> {
        // The ropes' colours are read from the first pass's first frame; it is decoded again
        // only if the pass ran earlier for another purpose.
        let frame = match (self.first_pass()?, self.first_frames().first()) {
            (Some(frame), _) => Some(frame),
            (None, Some(&first)) => {
                let mut frames = self
                    .source
                    .read(&[first])
                    .map_err(|e| ApiError::Data(e.to_string()))?;
                self.work.0 += frames.len() as u64;
                frames.pop()
            }
            (None, None) => None,
        };
        let perceived = perceive_rope(
            &self.first,
            &self.kept,
            (self.info.width, self.info.height),
            frame.as_ref(),
            camera,
            self.info.frame_count,
        );
        self.names.clone_from(&perceived.names);
        Ok(perceived)
    }

    /// The world positions of the named objects in every frame of the video: the detector runs
    /// on all frames, each track takes the name of the first-pass track it shares most
    /// detections with (the first pass's detections are reused, so they coincide), and its mask
    /// centroids are lifted onto the scene plane (`z = 0`, where the release lays out every
    /// rope scene) along the camera's viewing rays.
    pub(crate) fn positions(&mut self, camera: &Camera) -> Result<PerceivedPositions, ApiError> {
        self.first_pass()?;
        let wanted: Vec<usize> = (0..self.info.frame_count).collect();
        let (per_frame, _) = self.detect(&wanted, None)?;
        let tracks = track(&per_frame, &TrackerConfig::default()).map_err(unavailable)?;
        let model = CameraModel::from_unity_euler(
            camera.position,
            camera.rotation_deg,
            camera.vertical_fov_deg,
            self.info.width,
            self.info.height,
        );
        let mut positions = Vec::new();
        for (track, first) in tracks.iter().zip(assign_to_first(&tracks, &self.first)) {
            let Some(name) = first.and_then(|f| self.names.get(f).cloned().flatten()) else {
                continue;
            };
            let last = track.last_frame().unwrap_or(0);
            let mut per_frame = vec![None; last + 1];
            for point in &track.observations {
                if let Some(world) = lift(&model, camera, point.centroid[0], point.centroid[1])
                    && let Some(slot) = per_frame.get_mut(point.frame)
                {
                    *slot = Some([world[0], world[1], 0.0]);
                }
            }
            positions.push((name, per_frame));
        }
        Ok(positions)
    }

    /// Detections with colours for `wanted`, in order; frames [`Perceiver::scene`] ran are
    /// reused, the rest decoded in batches so a whole video is never held in memory at once.
    /// Also hands back frame `keep` when it was decoded here.
    fn detect(
        &mut self,
        wanted: &[usize],
        keep: Option<usize>,
    ) -> Result<(FrameDetections, Option<RgbFrame>), ApiError> {
        let missing: Vec<usize> = wanted
            .iter()
            .copied()
            .filter(|f| !self.kept.contains_key(f))
            .collect();
        let mut found: BTreeMap<usize, Vec<Detection>> = BTreeMap::new();
        let mut kept_frame = None;
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
            if let Some(frame) = frames.into_iter().find(|f| Some(f.index) == keep) {
                kept_frame = Some(frame);
            }
        }
        let per_frame = wanted
            .iter()
            .filter_map(|f| {
                let detections = found.remove(f).or_else(|| self.kept.get(f).cloned())?;
                Some((*f, detections))
            })
            .collect();
        Ok((per_frame, kept_frame))
    }
}

/// The annotated object each track stands for, by box overlap with the annotated boxes of the
/// track's first frame (kind against kind; one track per object).
fn bind_to_annotation(
    tracks: &[Track],
    wanted: &[usize],
    records: &SegmentationRecords,
) -> Vec<Option<String>> {
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
        if class.kind() != tracks[t].class.kind() && !(is_load(*class) && is_load(tracks[t].class))
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

/// Per track of the full pass, the first-pass track it shares most detections with (the first
/// pass's detections are reused, so a track through frames 0–60 contains them); `None` for
/// tracks that share none.
fn assign_to_first(tracks: &[Track], first: &[Track]) -> Vec<Option<usize>> {
    let shared = |a: &Track, b: &Track| {
        a.observations
            .iter()
            .filter(|p| {
                b.at_frame(p.frame)
                    .is_some_and(|q| q.detection == p.detection)
            })
            .count()
    };
    assign(tracks.len(), first.len(), |t, f| {
        let count = shared(&tracks[t], &first[f]);
        (count > 0).then(|| 1.0 / count as f64)
    })
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
