//! `generate`: synthetic videos in the release format, then their questions.
//!
//! Videos are written by `synth` (one folder each, atomically; an interrupted generation resumes
//! where it stopped), a manifest `generate.json` records the settings and what every video cost,
//! and the question engine then runs over the new data root through the same loader as the real
//! data, writing the per-video and sampled question files.

use std::io::Write as _;
use std::process::ExitCode;

use serde_json::json;

use super::error::{AppError, Classify as _, user_error};
use super::progress::Progress;
use super::questions::questions;
use super::settings::{FramesSelection, GenerateSettings, QuestionsSettings};
use crate::dataset::Scenario;
use crate::perception::frames::ffmpeg_available;
use crate::scenarios;
use crate::synth::appearance::Appearance;
use crate::synth::video::FrameOutput;
use crate::synth::{GenerateOptions, SynthError, generate as generate_videos};
use crate::util::write_atomic;

pub(crate) fn generate(settings: &GenerateSettings) -> Result<ExitCode, AppError> {
    if settings.videos == 0 {
        return Err(user_error("--videos must be at least 1"));
    }
    let (width, height) = settings.resolution;
    if width < 16 || height < 16 || width > 7680 || height > 4320 {
        return Err(user_error(format!(
            "--resolution {width}x{height} is outside 16x16 to 7680x4320"
        )));
    }
    let scenario = settings
        .scenario
        .or_else(|| scenarios::only_with(|row| row.synth.is_some()))
        .ok_or_else(|| {
            user_error(format!(
                "pass --scenario: generators exist for {}",
                scenarios::names_with(|row| row.synth.is_some())
            ))
        })?;
    let Some(synth) = scenarios::parts(scenario).synth else {
        return Err(SynthError::Unsupported {
            scenario: scenario.name().to_string(),
            supported: scenarios::names_with(|row| row.synth.is_some()),
        })
        .user();
    };
    let frames = match settings.frames {
        FramesSelection::Exactly(output) => {
            if output.mp4() && !ffmpeg_available() {
                return Err(SynthError::FfmpegMissing).user();
            }
            output
        }
        FramesSelection::Auto if ffmpeg_available() => FrameOutput::Mp4,
        FramesSelection::Auto => {
            let _ = writeln!(
                std::io::stderr().lock(),
                "note: ffmpeg is not installed; writing PNG frame folders instead of mp4"
            );
            FrameOutput::Png
        }
    };
    let jobs = settings
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from))
        .max(1);
    let options = GenerateOptions {
        scenario,
        videos: settings.videos,
        seed: settings.seed,
        out: settings.out.clone(),
        jobs,
        frames,
        width,
        height,
        appearance: settings.appearance,
    };
    // The settings that decide a video's content: a data root holds videos of one setting only,
    // so a resumed generation never mixes two.
    let mut identity = json!({
        "scenario": scenario.name(),
        "seed": settings.seed,
        "frames": format!("{frames:?}").to_lowercase(),
        "resolution": [width, height],
    });
    // Only a randomised appearance is recorded, so data roots written before the option existed
    // (all of the release's look) still resume.
    if settings.appearance == Appearance::Randomized {
        identity["appearance"] = json!("randomized");
    }
    let manifest_path = claim_data_root(settings, &identity)?;
    let progress = Progress::labelled(
        u64::try_from(settings.videos).unwrap_or(u64::MAX),
        "videos",
        settings.quiet,
    );
    let report = generate_videos(synth, &options, &|_| progress.advance(0)).internal_or_user()?;
    progress.finish();
    let bytes: u64 = report.videos.iter().map(|v| v.bytes).sum();
    let rejected: u64 = report
        .videos
        .iter()
        .map(|v| u64::from(v.rejected_trials))
        .sum();
    let reused = report.videos.iter().filter(|v| v.reused).count();
    let manifest = json!({
        "settings": identity,
        "complete": true,
        "tool": format!("contphy-eval {}", env!("CARGO_PKG_VERSION")),
        "videos": settings.videos,
        "jobs": jobs,
        "wall_ms": report.wall_ms,
        "bytes": bytes,
        "rejected_trials": rejected,
        "per_video": report.videos,
    });
    let text = serde_json::to_vec_pretty(&manifest).internal()?;
    write_atomic(&manifest_path, &text).internal()?;
    let mut stdout = std::io::stdout().lock();
    #[expect(clippy::cast_precision_loss, reason = "a byte count shown in MB")]
    let megabytes = bytes as f64 / 1e6;
    let _ = writeln!(
        stdout,
        "generated {} {} videos ({} kept from an earlier run) in {:.1} s with {jobs} jobs: {megabytes:.1} MB, {rejected} trials rejected by the validity checks -> {}",
        settings.videos,
        scenario.name(),
        reused,
        report.wall_ms as f64 / 1000.0,
        settings.out.join(scenario.folder_name()).display(),
    );
    drop(stdout);
    questions(&QuestionsSettings {
        data: settings.out.clone(),
        out: settings.out.clone(),
        seed: settings.seed,
        fact_per_video: None,
        dynamics_per_video: None,
    })
}

/// Checks that `settings.out` may take these videos and returns its manifest's path: a data root
/// `generate` made with the same settings (`identity`) resumes; one made with others, or a data
/// root `generate` did not make (its question files would be replaced), is refused; a new one
/// gets a manifest marked incomplete.
fn claim_data_root(
    settings: &GenerateSettings,
    identity: &serde_json::Value,
) -> Result<std::path::PathBuf, AppError> {
    let manifest_path = settings.out.join("generate.json");
    if manifest_path.is_file() {
        let previous: serde_json::Value =
            serde_json::from_slice(&fs_err::read(&manifest_path).user()?).map_err(|error| {
                user_error(format!(
                    "`{}` is not a generate manifest ({error}); remove it or choose another --out",
                    manifest_path.display()
                ))
            })?;
        if previous.get("settings") != Some(identity) {
            return Err(user_error(format!(
                "`{}` holds videos generated with {}; generate there with the same --scenario, --seed, --frames and --resolution, or choose another --out",
                settings.out.display(),
                previous.get("settings").unwrap_or(&serde_json::Value::Null)
            )));
        }
    } else {
        // A data root `generate` did not make (a release download, the demo) is never written
        // into: its question files would be replaced by the generated ones.
        if let Some(existing) = Scenario::ALL
            .iter()
            .map(|s| s.folder_name())
            .find(|folder| settings.out.join(folder).exists())
        {
            return Err(user_error(format!(
                "`{}` already holds `{existing}/`, which `generate` did not write; generate into an empty folder or one `generate` made",
                settings.out.display()
            )));
        }
        let text = serde_json::to_vec_pretty(&json!({"settings": identity, "complete": false}))
            .internal()?;
        write_atomic(&manifest_path, &text).user()?;
    }
    Ok(manifest_path)
}

/// Generation errors are the environment's or the user's (paths, ffmpeg), except a scene that
/// cannot be made valid, which is a defect of the generator.
trait GenerateClass<T> {
    fn internal_or_user(self) -> Result<T, AppError>;
}

impl<T> GenerateClass<T> for Result<T, SynthError> {
    fn internal_or_user(self) -> Result<T, AppError> {
        match self {
            Err(error @ SynthError::NoValidScene { .. }) => Err(error).internal(),
            other => other.user(),
        }
    }
}
