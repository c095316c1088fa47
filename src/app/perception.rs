//! Perception against ground truth: `perception fit-colors` (the colour model, fitted on the
//! segmentation truth of generated and real videos) and `bench perception` (the Mask R-CNN's
//! masks, colours, classes and tracks scored against the segmentation truth, with the time of
//! each stage and frames per second), both printing JSON.
//!
//! Input: a data root with `<scenario folder>/<id>/` folders (mp4s or PNG frame folders, and
//! `outputs.json` for the segmentation records) of a scenario with perception, a frame
//! selection, a model (the scenario's by default). Output: JSON on stdout (and a model file for
//! `fit-colors`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use serde::Serialize;
use serde_json::json;

use super::bench::print_report;
use super::error::{AppError, Classify as _, user_error};
use super::prerequisites::{ModelOverrides, check_frames, model_files};
use crate::dataset::{DataRoot, Scenario, SegmentationRecords, VideoFolder};
use crate::perception::ScenarioPerception;
use crate::perception::classes::{Class, ClassTable};
use crate::perception::color::{ColorModel, TrainingVideo, features, name_colors, wall_color};
use crate::perception::detection::{Detection, InstanceMask};
use crate::perception::detector::{Detector, DetectorConfig};
use crate::perception::evaluation::{
    MATCH_IOU, TruthInstance, attribute_accuracy, box_average_precision, id_switches,
    mask_average_precision,
};
use crate::perception::frames::{FrameSource, RgbFrame, Stream};
use crate::perception::tracking::{TrackerConfig, track};
use crate::perception::truth::{MP4_TOLERANCE, Painted, truth_instances};
use crate::scenarios;
use crate::scene_api::PerceptionBackend;

/// Which frames of each video are used.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FrameSelection {
    /// Every how many frames.
    pub every: usize,
    /// Only frames in `[start, end)` (0-based), when given.
    pub range: Option<(usize, usize)>,
    /// At most this many videos (in folder order), when given.
    pub max_videos: Option<usize>,
}

/// `perception fit-colors` settings.
#[derive(Debug, Clone)]
pub struct FitColorsSettings {
    /// Data roots to fit on.
    pub data: Vec<PathBuf>,
    /// The scenario whose videos are used; `None`: the one scenario with perception the data
    /// roots hold.
    pub scenario: Option<Scenario>,
    /// Frames used.
    pub frames: FrameSelection,
    /// Where the model is written.
    pub out: PathBuf,
}

/// `bench perception` settings.
#[derive(Debug, Clone)]
pub struct BenchPerceptionSettings {
    /// Data root.
    pub data: PathBuf,
    /// Frames used.
    pub frames: FrameSelection,
    /// The scenario whose videos are scored; `None`: the one scenario with perception the data
    /// root holds.
    pub scenario: Option<Scenario>,
    /// The model files; by default the scenario's.
    pub models: ModelOverrides,
    /// ONNX Runtime threads.
    pub threads: usize,
}

/// A video's frames and segmentation truth.
struct TruthVideo {
    rgb: FrameSource,
    segmentation: FrameSource,
    tolerance: u32,
    records: SegmentationRecords,
}

fn open_truth_video(video: &VideoFolder) -> Result<TruthVideo, AppError> {
    let rgb = FrameSource::of_video(&video.dir, Stream::Rgb).user()?;
    let segmentation = FrameSource::of_video(&video.dir, Stream::Segmentation).user()?;
    // PNG folders are exact; mp4 colours arrive blurred.
    let tolerance = match segmentation {
        FrameSource::PngFolder(_) => 8,
        FrameSource::Video(_) => MP4_TOLERANCE,
    };
    let records = SegmentationRecords::read(&video.outputs_json()).user()?;
    Ok(TruthVideo {
        rgb,
        segmentation,
        tolerance,
        records,
    })
}

fn selected_frames(records: &SegmentationRecords, selection: &FrameSelection) -> Vec<usize> {
    let every = selection.every.max(1);
    records
        .frames
        .keys()
        .copied()
        .filter(|f| selection.range.is_none_or(|(a, b)| (a..b).contains(f)))
        .filter(|f| f % every == 0)
        .collect()
}

/// The truth objects of a segmentation frame ([`truth_instances`]).
fn truth_objects(
    video: &TruthVideo,
    segmentation: &RgbFrame,
    classes: &ClassTable,
) -> Vec<TruthInstance> {
    let boxes = video.records.boxes.get(&segmentation.index);
    let painted: Vec<Painted<'_>> = video
        .records
        .frames
        .get(&segmentation.index)
        .map(|list| {
            list.iter()
                .filter_map(|p| {
                    let name = video.records.names.get(&p.instance_id)?;
                    let bbox = boxes
                        .and_then(|b| b.iter().find(|(id, _)| *id == p.instance_id))
                        .map(|(_, bbox)| *bbox);
                    Some(Painted {
                        id: p.instance_id,
                        color: p.color,
                        name: name.as_str(),
                        bbox,
                    })
                })
                .collect()
        })
        .unwrap_or_default();
    truth_instances(segmentation, &painted, classes, video.tolerance)
}

/// The scenario whose videos are used: the one given, or the one scenario with perception whose
/// folder the data roots hold; with its perception parts.
fn perceived_scenario(
    data: &[PathBuf],
    given: Option<Scenario>,
) -> Result<(Scenario, &'static ScenarioPerception), AppError> {
    let with_perception = || scenarios::names_with(|row| row.perception.is_some());
    let scenario = if let Some(scenario) = given {
        scenario
    } else {
        let mut present: Vec<Scenario> = Vec::new();
        for root in data {
            for scenario in DataRoot::open(root).user()?.scenarios() {
                if scenarios::parts(scenario).perception.is_some() && !present.contains(&scenario) {
                    present.push(scenario);
                }
            }
        }
        match present.as_slice() {
            [one] => *one,
            [] => {
                return Err(user_error(format!(
                    "no folder of a scenario with perception ({}) in {}",
                    with_perception(),
                    data.iter()
                        .map(|d| format!("`{}`", d.display()))
                        .collect::<Vec<_>>()
                        .join(", ")
                )));
            }
            several => {
                return Err(user_error(format!(
                    "the data holds videos of {}; pass --scenario",
                    spoken_list(&several.iter().map(|s| s.name()).collect::<Vec<_>>())
                )));
            }
        }
    };
    let perception = scenarios::parts(scenario).perception.ok_or_else(|| {
        user_error(format!(
            "there is no perception for {scenario} scenes yet (scenarios with perception: {})",
            with_perception()
        ))
    })?;
    Ok((scenario, perception))
}

fn videos(
    data: &Path,
    scenario: Scenario,
    selection: &FrameSelection,
) -> Result<Vec<VideoFolder>, AppError> {
    let root = DataRoot::open(data).user()?;
    let listing = root.list_videos(scenario).user()?;
    let mut videos: Vec<VideoFolder> = listing.valid;
    if let Some(max) = selection.max_videos {
        videos.truncate(max);
    }
    if videos.is_empty() {
        return Err(user_error(format!(
            "{}: no {scenario} videos ({}/<id>/) to use",
            data.display(),
            scenario.folder_name()
        )));
    }
    Ok(videos)
}

/// `perception fit-colors`.
pub(super) fn fit_colors(settings: &FitColorsSettings) -> Result<ExitCode, AppError> {
    let (scenario, perception) = perceived_scenario(&settings.data, settings.scenario)?;
    let classes = ClassTable::of_scenario(perception.classes);
    let mut samples = Vec::new();
    let mut described = Vec::new();
    let mut training_videos = Vec::new();
    for data in &settings.data {
        let videos = videos(data, scenario, &settings.frames)?;
        let mut frames_used = 0usize;
        for video in &videos {
            training_videos.push(training_video(data, video)?);
            let truth = open_truth_video(video)?;
            let frames = selected_frames(&truth.records, &settings.frames);
            let rgb_frames = truth.rgb.read(&frames).user()?;
            let seg_frames = truth.segmentation.read(&frames).user()?;
            for (rgb, segmentation) in rgb_frames.iter().zip(&seg_frames) {
                let objects = truth_objects(&truth, segmentation, &classes);
                let masks: Vec<&InstanceMask> = objects.iter().map(|o| &o.mask).collect();
                let Some(wall) = wall_color(rgb, &masks) else {
                    continue;
                };
                frames_used += 1;
                for object in &objects {
                    if let (Some(color), Some(f)) =
                        (object.color, features(rgb, &object.mask, wall))
                    {
                        samples.push((color, f));
                    }
                }
            }
        }
        described.push(format!(
            "{} videos, {frames_used} frames of {}",
            videos.len(),
            data.file_name().map_or_else(
                || data.display().to_string(),
                |n| n.to_string_lossy().into_owned()
            )
        ));
    }
    let model = ColorModel::fit(
        &samples,
        &format!(
            "{} (every {} frames{})",
            described.join("; "),
            settings.frames.every,
            settings
                .frames
                .range
                .map_or_else(String::new, |(a, b)| format!(", frames {a}..{b}"))
        ),
    )
    .user()?;
    let model = ColorModel {
        training_videos,
        ..model
    };
    let text = serde_json::to_string_pretty(&model).internal()?;
    crate::util::write_atomic(&settings.out, format!("{text}\n").as_bytes()).user()?;
    let summary = json!({
        "out": settings.out.display().to_string(),
        "samples": samples.len(),
        "colors": model.prototypes.iter().map(|p| json!({"name": p.name, "samples": p.samples})).collect::<Vec<_>>(),
    });
    print_report(&summary)
}

/// A fitting video's record: its folder below the data root's parent and the SHA-256 of its
/// `outputs.json`.
fn training_video(data: &Path, video: &VideoFolder) -> Result<TrainingVideo, AppError> {
    use sha2::Digest as _;
    let outputs = video.dir.join("outputs.json");
    let bytes = fs_err::read(&outputs).user()?;
    let digest = sha2::Sha256::digest(&bytes);
    let base = data.parent().unwrap_or(data);
    let folder = video.dir.strip_prefix(base).unwrap_or(&video.dir);
    Ok(TrainingVideo {
        video: folder.to_string_lossy().replace('\\', "/"),
        outputs_sha256: digest.iter().fold(String::new(), |mut hex, byte| {
            use std::fmt::Write as _;
            let _ = write!(hex, "{byte:02x}");
            hex
        }),
    })
}

#[derive(Debug, Default, Serialize)]
struct Timing {
    frames: usize,
    decode_ms: f64,
    preprocess_ms: f64,
    inference_ms: f64,
    postprocess_ms: f64,
    color_ms: f64,
}

/// One video's scored frames: detections and truth per frame index, in the same frame order.
struct ScoredVideo {
    id: String,
    detections: Vec<(usize, Vec<Detection>)>,
    truth: Vec<(usize, Vec<TruthInstance>)>,
}

/// `bench perception`.
pub(super) fn bench_perception(settings: &BenchPerceptionSettings) -> Result<ExitCode, AppError> {
    let (scenario, _) =
        perceived_scenario(std::slice::from_ref(&settings.data), settings.scenario)?;
    // Loaded once, here: a missing runtime or a broken model is its own one-line error.
    let (perception, models) = model_files(scenario, &settings.models)?;
    let colors = ColorModel::read(&models.colors).user()?;
    let mut detector = Detector::load(
        DetectorConfig::new(models.detector.clone(), settings.threads),
        perception.classes,
    )
    .user()?;
    let videos = videos(&settings.data, scenario, &settings.frames)?;
    check_frames(PerceptionBackend::MaskRcnn, &videos)?;
    let mut timing = Timing::default();
    let mut run: Vec<ScoredVideo> = Vec::new();
    let started = Instant::now();
    let mut release_size = None;
    for video in &videos {
        let truth = open_truth_video(video)?;
        let frames = selected_frames(&truth.records, &settings.frames);
        let decode_started = Instant::now();
        let rgb_frames = truth.rgb.read(&frames).user()?;
        timing.decode_ms += decode_started.elapsed().as_secs_f64() * 1e3;
        let seg_frames = truth.segmentation.read(&frames).user()?;
        let mut scored = ScoredVideo {
            id: video.id.0.clone(),
            detections: Vec::new(),
            truth: Vec::new(),
        };
        for (rgb, segmentation) in rgb_frames.iter().zip(&seg_frames) {
            if (rgb.width, rgb.height) != (segmentation.width, segmentation.height) {
                return Err(user_error(format!(
                    "video {}: the RGB frames are {}x{} but the segmentation frames are {}x{}; the truth masks would not line up",
                    video.dir.display(),
                    rgb.width,
                    rgb.height,
                    segmentation.width,
                    segmentation.height
                )));
            }
            release_size.get_or_insert((rgb.width, rgb.height));
            let (mut detections, times) = detector.detect_timed(rgb).user()?;
            let color_started = Instant::now();
            name_colors(rgb, &mut detections, &colors, detector.classes());
            timing.color_ms += color_started.elapsed().as_secs_f64() * 1e3;
            timing.frames += 1;
            timing.preprocess_ms += times.preprocess_ms;
            timing.inference_ms += times.inference_ms;
            timing.postprocess_ms += times.postprocess_ms;
            scored.detections.push((rgb.index, detections));
            scored.truth.push((
                rgb.index,
                truth_objects(&truth, segmentation, detector.classes()),
            ));
        }
        run.push(scored);
    }
    let wall_s = started.elapsed().as_secs_f64();
    let video_count = run.len();
    let metrics = score_run(run, detector.classes())?;
    let reading = match scenarios::parts(scenario).reading_check {
        Some(check) => check(&videos, &models).user()?,
        None => serde_json::Value::Null,
    };
    let per_frame = |ms: f64| ms / timing.frames.max(1) as f64;
    let report = json!({
        "data": settings.data.display().to_string(),
        "videos": video_count,
        "frames": timing.frames,
        "frame_size": release_size.map(|(w, h)| format!("{w}x{h}")),
        "model_input": format!("{}x{}", detector.config().input_width, detector.config().input_height),
        "threads": settings.threads,
        "ms_per_frame": {
            "decode": per_frame(timing.decode_ms),
            "preprocess": per_frame(timing.preprocess_ms),
            "inference": per_frame(timing.inference_ms),
            "postprocess": per_frame(timing.postprocess_ms),
            "color": per_frame(timing.color_ms),
        },
        "frames_per_second": timing.frames as f64 / wall_s.max(1e-9),
        "peak_rss_mib": peak_rss_mib(),
        "metrics": metrics,
        "mechanism": reading,
    });
    print_report(&report)
}

/// AP@0.5 (mask and box), attribute accuracy and tracking identity over a run, per video
/// summed (tracks are per video).
fn score_run(run: Vec<ScoredVideo>, classes: &ClassTable) -> Result<serde_json::Value, AppError> {
    let mut all_detections = Vec::new();
    let mut all_truth = Vec::new();
    let mut identity = Vec::new();
    let mut switches = 0usize;
    let mut truth_instances = 0usize;
    let mut mostly_tracked = 0usize;
    // Frames of different videos are numbered apart so one list can hold them all.
    for (video_index, video) in run.into_iter().enumerate() {
        let offset = video_index * 1_000_000;
        let ScoredVideo {
            id: video_id,
            detections,
            truth,
        } = video;
        // Identity is scored on whole objects: the pieces of a fluid have none across frames.
        let whole = |class: Class| !classes.pieces(class);
        let whole_detections: Vec<(usize, Vec<Detection>)> = detections
            .iter()
            .map(|(f, list)| {
                (
                    *f,
                    list.iter().filter(|d| whole(d.class)).cloned().collect(),
                )
            })
            .collect();
        let whole_truth: Vec<(usize, Vec<TruthInstance>)> = truth
            .iter()
            .map(|(f, list)| {
                (
                    *f,
                    list.iter().filter(|t| whole(t.class)).cloned().collect(),
                )
            })
            .collect();
        let tracks = track(&whole_detections, &TrackerConfig::default()).internal()?;
        let report = id_switches(&tracks, &whole_detections, &whole_truth).internal()?;
        switches += report.switches;
        truth_instances += report.truth_instances;
        mostly_tracked += report.mostly_tracked;
        identity.push(json!({
            "video": video_id,
            "tracks": report.tracks,
            "truth_instances": report.truth_instances,
            "switches": report.switches,
            "mostly_tracked": report.mostly_tracked,
            "mota": report.mota,
        }));
        all_detections.extend(detections.into_iter().map(|(f, d)| (f + offset, d)));
        all_truth.extend(truth.into_iter().map(|(f, t)| (f + offset, t)));
    }
    let mask_ap =
        mask_average_precision(classes, &all_detections, &all_truth, MATCH_IOU).internal()?;
    let box_ap =
        box_average_precision(classes, &all_detections, &all_truth, MATCH_IOU).internal()?;
    let attributes = attribute_accuracy(classes, &all_detections, &all_truth, 0.0).internal()?;
    Ok(json!({
        "mask_ap50": mask_ap,
        "box_ap50": box_ap,
        "attributes": attributes,
        "tracking": {
            "truth_instances": truth_instances,
            "id_switches": switches,
            "mostly_tracked": mostly_tracked,
            "per_video": identity,
        },
    }))
}

/// The process's peak resident memory (`VmHWM`), MiB; `None` where `/proc` does not say.
fn peak_rss_mib() -> Option<f64> {
    let status = fs_err::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// `a`, `a and b`, `a, b and c`: a list as a sentence says it.
fn spoken_list(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [one] => (*one).to_string(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}
