//! What a command's backends need before its first unit: the perception models of each
//! scenario (found, loadable, with their ONNX Runtime), and a decoder for the videos' frames.
//!
//! A missing prerequisite stops the command with one line and exit 1 before any work, instead of
//! failing every unit with the same error. Input: the perception backend, the model files the
//! command line names (or none: each scenario's committed models, from the scenario table), the
//! scenarios and videos of the run. Output: each scenario's absolute model files (sandbox workers
//! open them), or the user error.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::error::{AppError, Classify as _, user_error};
use crate::dataset::{Scenario, VideoFolder};
use crate::perception::ScenarioPerception;
use crate::perception::color::ColorModel;
use crate::perception::detector::{Detector, DetectorConfig};
use crate::perception::frames::{FrameSource, FramesError, Stream, ffmpeg_available};
use crate::scenarios;
use crate::scene_api::{PerceptionBackend, PerceptionModels};

/// Model files named on the command line; `None` means each scenario's own.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ModelOverrides {
    /// `--detector-model`.
    pub detector: Option<PathBuf>,
    /// `--color-model`.
    pub colors: Option<PathBuf>,
}

/// Each scenario's perception models, absolute; empty unless the backend is `maskrcnn`.
pub(crate) type ScenarioModels = BTreeMap<Scenario, PerceptionModels>;

/// With `--perception maskrcnn`: every scenario's model files (the command line's, else the
/// scenario table's), made absolute, after loading each once with the scenario's classes so a
/// missing runtime, a broken model or a scenario without models stops the command before any
/// question (exit 1).
pub(super) fn resolve_models(
    backend: PerceptionBackend,
    scenarios_in_run: impl IntoIterator<Item = Scenario>,
    overrides: &ModelOverrides,
) -> Result<ScenarioModels, AppError> {
    let mut resolved = ScenarioModels::new();
    if backend != PerceptionBackend::MaskRcnn {
        return Ok(resolved);
    }
    for scenario in scenarios_in_run {
        if resolved.contains_key(&scenario) {
            continue;
        }
        let (perception, models) = model_files(scenario, overrides)?;
        ColorModel::read(&models.colors).user()?;
        Detector::load(
            DetectorConfig::new(models.detector.clone(), 1),
            perception.classes,
        )
        .user()?;
        resolved.insert(scenario, models);
    }
    Ok(resolved)
}

/// `scenario`'s perception and its model files (the command line's, else the scenario table's),
/// made absolute, without loading them; an error when the scenario has no perception.
pub(super) fn model_files(
    scenario: Scenario,
    overrides: &ModelOverrides,
) -> Result<(&'static ScenarioPerception, PerceptionModels), AppError> {
    let Some(perception) = scenarios::parts(scenario).perception else {
        return Err(user_error(format!(
            "--perception maskrcnn: there is no perception for {scenario} scenes yet (scenarios with perception: {})",
            scenarios::names_with(|row| row.perception.is_some())
        )));
    };
    let absolute = |given: Option<&Path>, default: &str| {
        let path = given.unwrap_or(Path::new(default));
        std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
    };
    let models = PerceptionModels {
        detector: absolute(overrides.detector.as_deref(), perception.detector),
        colors: absolute(overrides.colors.as_deref(), perception.colors),
    };
    Ok((perception, models))
}

/// The content hashes of each scenario's detector and colour models (part of a run's
/// identity); `None` without models.
pub(super) fn model_hashes(
    models: &ScenarioModels,
) -> Result<Option<BTreeMap<Scenario, [String; 2]>>, AppError> {
    if models.is_empty() {
        return Ok(None);
    }
    let hash = |path: &Path| -> Result<String, AppError> {
        Ok(crate::util::content_hash(&fs_err::read(path).user()?))
    };
    let mut hashes = BTreeMap::new();
    for (scenario, files) in models {
        hashes.insert(*scenario, [hash(&files.detector)?, hash(&files.colors)?]);
    }
    Ok(Some(hashes))
}

/// With `--perception maskrcnn`: every video has frames to read (a PNG folder, or an mp4 and
/// ffmpeg to decode it).
pub(super) fn check_frames<'a>(
    backend: PerceptionBackend,
    videos: impl IntoIterator<Item = &'a VideoFolder>,
) -> Result<(), AppError> {
    if backend != PerceptionBackend::MaskRcnn {
        return Ok(());
    }
    let mut decoder: Option<bool> = None;
    for video in videos {
        if let FrameSource::Video(path) = FrameSource::of_video(&video.dir, Stream::Rgb).user()?
            && !*decoder.get_or_insert_with(ffmpeg_available)
        {
            return Err(FramesError::FfmpegMissing {
                program: "ffmpeg".to_string(),
                path,
            })
            .user();
        }
    }
    Ok(())
}
