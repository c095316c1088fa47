//! `--perception maskrcnn`: the objects of a video as the detector sees them.
//!
//! The Mask R-CNN runs on a few frames of the video's first two seconds (every
//! [`FRAME_STEP`]-th frame up to [`LAST_FRAME`], the stretch in which the release's questions
//! describe the scene), its detections are named by colour (`perception::color`) and tracked
//! (`perception::tracking`), and each track names one object: its colour and class words are
//! what `find` matches. Objects the detector misses are not findable, and a misread colour or
//! class makes `find` return the wrong object or none, as in ContPRO.
//!
//! Shared by every scenario with perception: [`Perceiver::scene`] binds the first pass's tracks
//! to the annotated objects by box overlap (the oracle dynamics, whose recorded results are keyed
//! by the release's names); [`Perceiver::full_pass`] runs the detector on every frame (reusing
//! the first pass's frames) and gives each track the name of the first-pass track it shares
//! detections with. A scenario that reads its scene from pixels (rope's mechanism,
//! `scene_api::rope`) names the first-pass tracks itself ([`Perceiver::set_names`]) from what
//! [`Perceiver::first_pass`] hands it. Input: a video folder, the model files, the scenario's
//! detector classes and vocabulary. Output: per annotated object its perceived words, or the
//! tracks, and the work done.
//!
//! The models are loaded once per process and shared by every scene in it (one ONNX Runtime
//! session per sandbox worker, not one per video).

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::{Mutex, PoisonError};

use super::error::ApiError;
use super::overlays::write_overlays;
use super::scene::PerceptionModels;
use crate::dataset::{SegmentationRecords, Vocabulary};
use crate::perception::assignment::assign;
use crate::perception::camera::CameraModel;
use crate::perception::classes::{Class, ClassTable, ClassWords, ScenarioClasses};
use crate::perception::closer::look_closer;
use crate::perception::color::{ColorModel, features, name_colors, wall_color};
use crate::perception::detection::{Detection, InstanceMask, box_iou};
use crate::perception::detector::{Detector, DetectorConfig};
use crate::perception::distinct::separate_class_colors;
use crate::perception::frames::{FrameSource, RgbFrame, Stream, VideoInfo};
use crate::perception::palette::palette_color;
use crate::perception::tracking::{Track, TrackerConfig, track};

/// Every how many frames the detector runs.
pub const FRAME_STEP: usize = 10;
/// The last frame it runs on (0-based; 2 s at the release's 30 fps).
pub const LAST_FRAME: usize = 60;
/// The first-pass frames whose objects of a class with rivals are looked at again on windows
/// at twice the scale (`perception::closer`): three frames spread over the pass, as measured.
const CLOSER_LOOK_FRAMES: [usize; 3] = [0, 30, 60];
/// Least box IoU for a track to name an annotated object.
const MIN_BINDING_IOU: f64 = 0.3;

/// What perception says about one annotated object.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PerceivedWords {
    /// Colour words (`light blue`); empty when the colour was not recognised.
    pub color: String,
    /// The detector's class name (`solid static pulley`).
    pub class: &'static str,
    /// The class's kind word (`pulley`).
    pub kind: &'static str,
    /// The class's attribute values (`shape` = `solid`).
    pub attributes: &'static [(&'static str, &'static str)],
}

/// The objects perception found in one video.
#[derive(Debug, Clone, Default)]
pub struct PerceivedScene {
    /// Annotated object name → its perceived words (objects not listed were not seen).
    pub objects: Vec<(String, PerceivedWords)>,
    /// Tracks that matched no annotated object (false positives).
    pub unbound_tracks: usize,
}

/// Detections per frame, in frame order.
pub type FrameDetections = Vec<(usize, Vec<Detection>)>;

fn unavailable(error: impl std::fmt::Display) -> ApiError {
    ApiError::Unavailable(format!("perception (maskrcnn): {error}"))
}

/// The loaded models, shared by every scene of the process, with the scenario classes they
/// were loaded for (its class list identifies it); replaced when a scene asks for other files
/// or another scenario.
static LOADED: Mutex<Option<Loaded>> = Mutex::new(None);

/// Models loaded for one scenario.
struct Loaded {
    files: PerceptionModels,
    /// The scenario's class list (its identity: one static list per scenario).
    classes: &'static [ClassWords],
    detector: Detector,
    colors: ColorModel,
}

/// Runs `work` with the detector and colour model of `models`, loading them on first use.
fn with_models<T>(
    models: &PerceptionModels,
    classes: ScenarioClasses,
    work: impl FnOnce(&mut Detector, &ColorModel) -> Result<T, ApiError>,
) -> Result<T, ApiError> {
    let mut loaded = LOADED.lock().unwrap_or_else(PoisonError::into_inner);
    if loaded.as_ref().is_none_or(|current| {
        current.files != *models || !std::ptr::eq(current.classes, classes.classes)
    }) {
        let colors = ColorModel::read(&models.colors).map_err(unavailable)?;
        let detector = Detector::load(DetectorConfig::new(models.detector.clone(), 1), classes)
            .map_err(unavailable)?;
        *loaded = Some(Loaded {
            files: models.clone(),
            classes: classes.classes,
            detector,
            colors,
        });
    }
    match loaded.as_mut() {
        Some(current) => work(&mut current.detector, &current.colors),
        None => Err(unavailable("the models could not be kept loaded")),
    }
}

/// One video as the detector sees it: its frames, read once per scene, the first pass's
/// detections and tracks, and the name each of those tracks stands for.
pub struct Perceiver {
    models: PerceptionModels,
    classes: ScenarioClasses,
    vocabulary: &'static Vocabulary,
    /// The model's classes as the scenario reads them (known once the detector ran).
    table: Option<ClassTable>,
    video_dir: std::path::PathBuf,
    source: FrameSource,
    info: VideoInfo,
    /// Detections of the first pass (frames 0, 10, …, 60), reused by [`Perceiver::full_pass`].
    kept: BTreeMap<usize, Vec<Detection>>,
    /// The first pass's tracks (empty until it ran).
    first: Vec<Track>,
    /// Per first-pass track, the object it stands for.
    names: Vec<Option<String>>,
    /// Frames decoded and run through the detector so far.
    work: (u64, u64),
    /// Where the first pass's frames are written with its detections drawn on them, for the
    /// run viewer (`RUN/frames/<scenario>/<video>/`); `None`: nowhere.
    overlays: Option<std::path::PathBuf>,
}

impl Perceiver {
    /// Opens the video's frames; runs nothing yet. `classes` and `vocabulary` are the
    /// scenario's.
    pub fn open(
        video_dir: &Path,
        models: &PerceptionModels,
        classes: ScenarioClasses,
        vocabulary: &'static Vocabulary,
    ) -> Result<Self, ApiError> {
        let source = FrameSource::of_video(video_dir, Stream::Rgb)
            .map_err(|e| ApiError::Data(e.to_string()))?;
        let info = source.info().map_err(|e| ApiError::Data(e.to_string()))?;
        Ok(Perceiver {
            models: models.clone(),
            classes,
            vocabulary,
            table: None,
            video_dir: video_dir.to_path_buf(),
            source,
            info,
            kept: BTreeMap::new(),
            first: Vec::new(),
            names: Vec::new(),
            work: (0, 0),
            overlays: None,
        })
    }

    /// Opens the video of `spec` as [`Perceiver::open`] does, writing the first pass's frames
    /// with their detections where the spec asks (`VideoSpec::overlays`).
    pub fn open_for(
        spec: &super::scene::VideoSpec,
        classes: ScenarioClasses,
        vocabulary: &'static Vocabulary,
    ) -> Result<Self, ApiError> {
        let mut perceiver = Perceiver::open(
            &spec.video_dir,
            spec.perception_models()?,
            classes,
            vocabulary,
        )?;
        perceiver.overlays.clone_from(&spec.overlays);
        Ok(perceiver)
    }

    /// Frames decoded and frames run through the detector so far.
    pub fn work(&self) -> (u64, u64) {
        self.work
    }

    /// The model's classes as the scenario reads them, once the detector has run.
    pub fn classes(&self) -> Option<&ClassTable> {
        self.table.as_ref()
    }

    /// The words of `class` (colour aside), when the detector has run and knows it.
    pub fn words(&self, class: Class, color: Option<u8>) -> Option<PerceivedWords> {
        let words = self.table.as_ref()?.words(class)?;
        Some(PerceivedWords {
            color: color
                .and_then(palette_color)
                .map(|c| c.word.to_string())
                .unwrap_or_default(),
            class: words.name,
            kind: words.kind,
            attributes: words.attributes,
        })
    }

    /// The video's frame size (width, height) and frame count.
    pub fn frames(&self) -> (u32, u32, usize) {
        (self.info.width, self.info.height, self.info.frame_count)
    }

    /// The first pass's tracks (empty until it ran).
    pub fn first_tracks(&self) -> &[Track] {
        &self.first
    }

    /// The first pass's detections, by frame.
    pub fn first_detections(&self) -> &BTreeMap<usize, Vec<Detection>> {
        &self.kept
    }

    /// Per first-pass track, the object it stands for (empty until named).
    pub fn names(&self) -> &[Option<String>] {
        &self.names
    }

    /// Names the first pass's tracks (one entry per track; `None`: stands for no object), for
    /// [`Perceiver::full_pass`].
    pub fn set_names(&mut self, names: Vec<Option<String>>) {
        self.names = names;
    }

    /// Frames `indices`, decoded (counted as work), in order; frames the video lacks are left
    /// out.
    pub fn read_frames(&mut self, indices: &[usize]) -> Result<Vec<RgbFrame>, ApiError> {
        let frames = self
            .source
            .read(indices)
            .map_err(|e| ApiError::Data(e.to_string()))?;
        self.work.0 += frames.len() as u64;
        Ok(frames)
    }

    /// Frames of the first pass: 0, 10, …, 60 (those the video has).
    pub fn first_frames(&self) -> Vec<usize> {
        (0..=LAST_FRAME.min(self.info.frame_count.saturating_sub(1)))
            .step_by(FRAME_STEP)
            .collect()
    }

    /// Runs the first pass once: the detector on frames 0, 10, …, 60, and the tracks. Returns
    /// the pass's frames when this call ran it (the caller may want their pixels; the scene
    /// does not keep frames, since a worker keeps one scene per video it has seen), else none.
    pub fn first_pass(&mut self) -> Result<Vec<RgbFrame>, ApiError> {
        if !self.kept.is_empty() || self.info.frame_count == 0 {
            return Ok(Vec::new());
        }
        let wanted = self.first_frames();
        let (per_frame, frames) = self.detect(&wanted, true)?;
        let mut first = track(&per_frame, &TrackerConfig::default()).map_err(unavailable)?;
        let vocabulary = self.vocabulary;
        let windows = with_models(&self.models, self.classes, |detector, colors| {
            let table = detector.classes().clone();
            let rivals = |a: Class, b: Class| rival_classes(&table, vocabulary, a, b);
            let windows = look_closer(
                &mut first,
                &per_frame,
                &frames,
                &CLOSER_LOOK_FRAMES,
                detector,
                &rivals,
            )
            .map_err(unavailable)?;
            separate_class_colors(&mut first, &per_frame, &frames, colors, detector.classes());
            Ok(windows)
        })?;
        self.work.1 += windows;
        self.first = first;
        self.kept = per_frame.into_iter().collect();
        if let Some(dir) = &self.overlays {
            // For the viewer only: a frame that cannot be written leaves the answers as they
            // are, and the viewer shows the unit without it.
            let drawn: Vec<(&RgbFrame, &[Detection])> = frames
                .iter()
                .map(|frame| {
                    let detections = self.kept.get(&frame.index).map_or(&[][..], Vec::as_slice);
                    (frame, detections)
                })
                .collect();
            let _ = write_overlays(dir, self.table.as_ref(), &drawn);
        }
        Ok(frames)
    }

    /// The objects of the video under the oracle dynamics (`--dynamics annotation`), whose
    /// recorded results are keyed by the release's names: the first pass's tracks bound to the
    /// annotated objects by box overlap.
    pub fn scene(&mut self) -> Result<PerceivedScene, ApiError> {
        self.first_pass()?;
        let records = SegmentationRecords::read(&self.video_dir.join("outputs.json"))?;
        self.names = match &self.table {
            Some(table) => bind_to_annotation(
                &self.first,
                &self.first_frames(),
                &records,
                table,
                self.vocabulary,
            ),
            None => Vec::new(),
        };
        let mut scene = PerceivedScene::default();
        for (track, name) in self.first.iter().zip(&self.names) {
            match (name, self.words(track.class, track.color)) {
                (Some(name), Some(words)) => scene.objects.push((name.clone(), words)),
                _ => scene.unbound_tracks += 1,
            }
        }
        scene.objects.sort_by(|a, b| a.0.cmp(&b.0));
        Ok(scene)
    }

    /// The colours `class` can have, likeliest first for the pixels of `mask` in `frame` (the
    /// wall read round `masks`, the frame's detections) by the colour model's Gaussians. Empty
    /// when the class is unknown or too few pixels are read.
    pub fn color_ranking(
        &self,
        frame: &RgbFrame,
        mask: &InstanceMask,
        masks: &[&InstanceMask],
        class: Class,
    ) -> Result<Vec<u8>, ApiError> {
        let Some(table) = self.table.as_ref() else {
            return Ok(Vec::new());
        };
        let Some(wall) = wall_color(frame, masks) else {
            return Ok(Vec::new());
        };
        let Some(features) = features(frame, mask, wall) else {
            return Ok(Vec::new());
        };
        with_models(&self.models, self.classes, |_, colors| {
            Ok(colors.ranked(&features, table.colors(class)))
        })
    }

    /// The colour model's Gaussians (without its fitting samples): for reading colours pixel by
    /// pixel ([`ColorModel::likeliest`]).
    pub fn color_prototypes(&self) -> Result<ColorModel, ApiError> {
        with_models(&self.models, self.classes, |_, colors| {
            Ok(ColorModel {
                fitted_on: colors.fitted_on.clone(),
                prototypes: colors.prototypes.clone(),
                samples: Vec::new(),
                training_videos: Vec::new(),
            })
        })
    }

    /// Hands `visit` each of `frames` (in order; those the video lacks are left out) with its
    /// detections (with colours), untracked: the first pass runs first and its detections are
    /// reused; frames are decoded in batches, so a whole video is never held at once.
    pub fn visit_detections(
        &mut self,
        frames: &[usize],
        visit: &mut dyn FnMut(&RgbFrame, &[Detection]),
    ) -> Result<(), ApiError> {
        self.first_pass()?;
        let wanted: Vec<usize> = frames
            .iter()
            .copied()
            .filter(|f| *f < self.info.frame_count)
            .collect();
        for batch in wanted.chunks(16) {
            let decoded = self.read_frames(batch)?;
            let missing: Vec<&RgbFrame> = decoded
                .iter()
                .filter(|frame| !self.kept.contains_key(&frame.index))
                .collect();
            let mut found: BTreeMap<usize, Vec<Detection>> = BTreeMap::new();
            if !missing.is_empty() {
                with_models(&self.models, self.classes, |detector, colors| {
                    for frame in &missing {
                        let mut detections = detector.detect(frame).map_err(unavailable)?;
                        name_colors(frame, &mut detections, colors, detector.classes());
                        found.insert(frame.index, detections);
                    }
                    Ok(())
                })?;
                self.work.1 += missing.len() as u64;
            }
            for frame in &decoded {
                let detections = found
                    .get(&frame.index)
                    .or_else(|| self.kept.get(&frame.index))
                    .map_or(&[][..], Vec::as_slice);
                visit(frame, detections);
            }
        }
        Ok(())
    }

    /// The tracks of every frame of the video, each with the name of the first-pass track it
    /// shares most detections with (the first pass's detections are reused, so they coincide);
    /// tracks that stand for no named object are left out.
    pub fn full_pass(&mut self) -> Result<Vec<(String, Track)>, ApiError> {
        self.first_pass()?;
        let wanted: Vec<usize> = (0..self.info.frame_count).collect();
        let (per_frame, _) = self.detect(&wanted, false)?;
        let tracks = track(&per_frame, &TrackerConfig::default()).map_err(unavailable)?;
        let firsts = assign_to_first(&tracks, &self.first);
        Ok(tracks
            .into_iter()
            .zip(firsts)
            .filter_map(|(track, first)| {
                let name = first.and_then(|f| self.names.get(f).cloned().flatten())?;
                Some((name, track))
            })
            .collect())
    }

    /// Detections with colours for `wanted`, in order; frames [`Perceiver::scene`] ran are
    /// reused, the rest decoded in batches so a whole video is never held in memory at once.
    /// With `keep` (a few frames only), also hands back the frames decoded here.
    fn detect(
        &mut self,
        wanted: &[usize],
        keep: bool,
    ) -> Result<(FrameDetections, Vec<RgbFrame>), ApiError> {
        let missing: Vec<usize> = wanted
            .iter()
            .copied()
            .filter(|f| !self.kept.contains_key(f))
            .collect();
        let mut found: BTreeMap<usize, Vec<Detection>> = BTreeMap::new();
        let mut kept_frames = Vec::new();
        for batch in missing.chunks(16) {
            let frames = self
                .source
                .read(batch)
                .map_err(|e| ApiError::Data(e.to_string()))?;
            self.work.0 += frames.len() as u64;
            let known = self.table.is_some();
            let mut table = None;
            with_models(&self.models, self.classes, |detector, colors| {
                if !known {
                    table = Some(detector.classes().clone());
                }
                for frame in &frames {
                    let mut detections = detector.detect(frame).map_err(unavailable)?;
                    name_colors(frame, &mut detections, colors, detector.classes());
                    found.insert(frame.index, detections);
                }
                Ok(())
            })?;
            self.work.1 += frames.len() as u64;
            if table.is_some() {
                self.table = table;
            }
            if let (Some(dir), false) = (&self.overlays, keep) {
                // A full pass keeps every FRAME_STEP-th frame it read for the viewer (the
                // first pass's are written already); a failed write changes no answer.
                let drawn: Vec<(&RgbFrame, &[Detection])> = frames
                    .iter()
                    .filter(|frame| frame.index % FRAME_STEP == 0)
                    .filter_map(|frame| Some((frame, found.get(&frame.index)?.as_slice())))
                    .collect();
                if !drawn.is_empty() {
                    let _ = write_overlays(dir, self.table.as_ref(), &drawn);
                }
            }
            if keep {
                kept_frames.extend(frames);
            }
        }
        let per_frame = wanted
            .iter()
            .filter_map(|f| {
                let detections = found.remove(f).or_else(|| self.kept.get(f).cloned())?;
                Some((*f, detections))
            })
            .collect();
        Ok((per_frame, kept_frames))
    }
}

/// The frames decoded and run through the detector by the perceiver a backend keeps for its
/// later questions (`None`: it keeps none), for the scene's work counters.
pub(crate) fn kept_work(perceiver: Option<&Mutex<Perceiver>>) -> (u64, u64) {
    perceiver.map_or((0, 0), |perceiver| {
        perceiver
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .work()
    })
}

/// The annotated object each track stands for, by box overlap with the annotated boxes of the
/// track's first frame (kind against kind, or two kinds of one group word such as rope's
/// loads; one track per object).
fn bind_to_annotation(
    tracks: &[Track],
    wanted: &[usize],
    records: &SegmentationRecords,
    table: &ClassTable,
    vocabulary: &Vocabulary,
) -> Vec<Option<String>> {
    let candidates: Vec<(String, Class, usize, [f64; 4])> = records
        .boxes
        .iter()
        .filter(|(frame, _)| wanted.binary_search(frame).is_ok())
        .flat_map(|(frame, boxes)| {
            boxes.iter().filter_map(|(id, bbox)| {
                let name = records.names.get(id)?;
                let class = table.of_object(name)?;
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
        let track_class = tracks[t].class;
        if *class != track_class && !rival_classes(table, vocabulary, *class, track_class) {
            return None;
        }
        let overlap = box_iou(seen, *annotated);
        (overlap >= MIN_BINDING_IOU).then_some(1.0 - overlap)
    })
    .into_iter()
    .map(|bound| bound.map(|n| names[n].clone()))
    .collect()
}

/// Whether classes `a` and `b` are alternatives for one object: two classes of one kind (a
/// solid and a hollow pulley), or of two kinds one group word of the vocabulary names (rope's
/// loads: a cube or a sphere).
fn rival_classes(table: &ClassTable, vocabulary: &Vocabulary, a: Class, b: Class) -> bool {
    if a == b {
        return false;
    }
    a.same_kind(b)
        || vocabulary.kind_groups.iter().any(|group| {
            group.kinds.contains(&table.kind(a)) && group.kinds.contains(&table.kind(b))
        })
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

/// The video's camera record, which reading a scene from pixels needs (the one part of the
/// annotation `--perception maskrcnn` reads), or the error saying it is missing.
pub(crate) fn calibration(
    camera: Option<&crate::dataset::Camera>,
) -> Result<&crate::dataset::Camera, ApiError> {
    camera.ok_or_else(|| {
        ApiError::Unavailable(
            "perception needs the camera calibration (outputCamera), which this video lacks"
                .to_string(),
        )
    })
}

/// The projection of the release's camera record onto frames of `size` (width, height).
pub(crate) fn camera_model(camera: &crate::dataset::Camera, size: (u32, u32)) -> CameraModel {
    CameraModel::from_unity_euler(
        camera.position,
        camera.rotation_deg,
        camera.vertical_fov_deg,
        size.0,
        size.1,
    )
}

/// Annotated objects of one kind, those a scene reading read right, and those read that are
/// not there (the scenarios' reading checks, `bench perception`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub(crate) struct KindCheck {
    /// Annotated objects.
    pub annotated: usize,
    /// Read with the right name at the right place.
    pub right: usize,
    /// Read objects with no annotated object of their name, or at the wrong place.
    pub wrong: usize,
}

impl KindCheck {
    /// Adds `other`'s counts.
    pub(crate) fn add(&mut self, other: KindCheck) {
        self.annotated += other.annotated;
        self.right += other.right;
        self.wrong += other.wrong;
    }
}

/// One video's scene read from pixels against its annotation, summable over videos (the
/// scenarios' reading checks, `bench perception`).
pub(crate) trait VideoReading: Default + serde::Serialize {
    /// Adds `other`'s counts and errors.
    fn add(&mut self, other: &Self);
    /// Whether the video was read entirely right.
    fn entire(&self) -> bool;
}

/// The readings of `videos`, each by `check` on its folder: their sum, each video's reading as
/// JSON (`{"video", "check"}`), and how many were read entirely. A video that cannot be read
/// fails the whole check, named.
pub(crate) fn check_videos<R: VideoReading>(
    videos: &[crate::dataset::VideoFolder],
    check: impl Fn(&Path) -> Result<R, ApiError>,
) -> Result<(R, Vec<serde_json::Value>, usize), ApiError> {
    let mut total = R::default();
    let mut per_video = Vec::with_capacity(videos.len());
    let mut entire = 0;
    for video in videos {
        let reading = check(&video.dir)
            .map_err(|error| ApiError::Data(format!("video {}: {error}", video.dir.display())))?;
        total.add(&reading);
        entire += usize::from(reading.entire());
        per_video.push(serde_json::json!({"video": video.id.0, "check": reading}));
    }
    Ok((total, per_video, entire))
}

/// Readings of one kind of answer: right, wrong, and "cannot tell" (the scenarios' reading
/// checks, `bench perception`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub(crate) struct Tally {
    /// Read as annotated.
    pub right: usize,
    /// Read otherwise.
    pub wrong: usize,
    /// Not read.
    pub undecided: usize,
}

impl Tally {
    /// Counts one reading `read` of a thing annotated `annotated`.
    pub(crate) fn count<T: PartialEq + Copy>(&mut self, read: Option<T>, annotated: T) {
        match read {
            Some(read) if read == annotated => self.right += 1,
            Some(_) => self.wrong += 1,
            None => self.undecided += 1,
        }
    }

    /// Adds `other`'s counts.
    pub(crate) fn add(&mut self, other: Tally) {
        self.right += other.right;
        self.wrong += other.wrong;
        self.undecided += other.undecided;
    }
}

/// What a perfect detector finds: a video's segmentation truth on `frames` as detections, each
/// coloured by its name (for the scene readers' tests).
#[cfg(test)]
pub(crate) fn truth_detections(
    video: &Path,
    classes: ScenarioClasses,
    frames: &[usize],
) -> (Vec<(usize, Vec<Detection>)>, ClassTable) {
    use crate::perception::truth::{MP4_TOLERANCE, Painted, truth_instances};
    let classes = ClassTable::of_scenario(classes);
    let records = SegmentationRecords::read(&video.join("outputs.json")).unwrap();
    let source = FrameSource::of_video(video, Stream::Segmentation).unwrap();
    let mut per_frame = Vec::new();
    for frame in source.read(frames).unwrap() {
        let boxes = &records.boxes[&frame.index];
        let painted: Vec<Painted<'_>> = records.frames[&frame.index]
            .iter()
            .map(|p| Painted {
                id: p.instance_id,
                color: p.color,
                name: records.names[&p.instance_id].as_str(),
                bbox: boxes
                    .iter()
                    .find(|(id, _)| *id == p.instance_id)
                    .map(|b| b.1),
            })
            .collect();
        let detections = truth_instances(&frame, &painted, &classes, MP4_TOLERANCE)
            .into_iter()
            .filter_map(|truth| {
                let [x0, y0, x1, y1] = truth.mask.bounds()?;
                #[expect(clippy::cast_precision_loss, reason = "pixel coordinates")]
                let bbox = [x0 as f32, y0 as f32, x1 as f32, y1 as f32];
                Some(Detection {
                    frame: frame.index,
                    class: truth.class,
                    score: 1.0,
                    bbox,
                    mask: truth.mask,
                    color: truth.color,
                })
            })
            .collect();
        per_frame.push((frame.index, detections));
    }
    (per_frame, classes)
}
