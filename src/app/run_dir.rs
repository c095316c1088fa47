//! The run directory (`docs/architecture.md`, run directory): `manifest.json`, `questions.json`
//! (what was evaluated, gold and baseline priors included, so the run re-scores on its own),
//! `predictions.jsonl` (one line per unit, appended durably as units finish and rewritten in
//! question order at the end), `results.json` and `report.md`.

use std::collections::BTreeMap;
use std::io::{BufRead as _, Write as _};
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use serde::{Deserialize, Serialize};

use super::error::{AppError, Classify as _, user_error};
use super::settings::{Budgets, SplitSelection};
use crate::dataset::Scenario;
use crate::scene_api::{DynamicsBackend, PerceptionBackend};
use crate::score::{Prediction, RunQuestions};
use crate::util::{append_line_durable, write_atomic};

/// The settings that determine a run's results; a resumed run must match them exactly.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct RunIdentity {
    /// `builtin`, or the model.
    pub(crate) program_source: String,
    /// The source's settings that determine programs (writer version; model, sampling, prompt
    /// set hash and api_spec version).
    #[serde(default)]
    pub(crate) source_identity: serde_json::Value,
    /// Replay only.
    pub(crate) offline: bool,
    /// Perception backend.
    pub(crate) perception: PerceptionBackend,
    /// Dynamics backend.
    pub(crate) dynamics: DynamicsBackend,
    /// Sandbox budgets.
    pub(crate) budgets: Budgets,
    /// The split selection (when no question files were given).
    pub(crate) split: SplitSelection,
    /// Question files and their content hashes.
    pub(crate) question_files: Vec<(String, String)>,
    /// Content hash of the evaluated videos' annotation files.
    pub(crate) data_hash: String,
    /// `--limit`.
    pub(crate) limit: Option<usize>,
    /// `--shard`.
    pub(crate) shard: Option<(usize, usize)>,
    /// One program per choice question.
    #[serde(default)]
    pub(crate) per_question: bool,
    /// Programs drawn per task.
    #[serde(default = "one")]
    pub(crate) samples: u32,
    /// Repair turns per program.
    #[serde(default)]
    pub(crate) repair: u32,
    /// With `--perception maskrcnn`: the content hashes of the detector and colour models, so a
    /// resume with other models is refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) perception_models: Option<BTreeMap<Scenario, [String; 2]>>,
}

/// `manifest.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(crate) struct Manifest {
    /// `contphy-eval`.
    pub(crate) tool: String,
    /// The crate version.
    pub(crate) tool_version: String,
    /// The git revision the tool was built from, when known.
    pub(crate) git_revision: Option<String>,
    /// The program source: writer version, or model, endpoint (never the key) and sampling.
    #[serde(default)]
    pub(crate) source: serde_json::Value,
    /// The settings that determine results.
    pub(crate) identity: RunIdentity,
    /// The data root as given.
    pub(crate) data_root: String,
    /// Questions evaluated.
    pub(crate) questions: usize,
    /// Units evaluated.
    pub(crate) units: usize,
    /// Questions skipped because their video is an invalid trial.
    pub(crate) skipped_invalid_video_questions: usize,
    /// Start time, ms since the Unix epoch.
    pub(crate) started_unix_ms: u64,
    /// End time, ms since the Unix epoch (0 while running).
    pub(crate) finished_unix_ms: u64,
    /// Token, cost and request totals of an LLM run (set when it finishes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) usage: Option<crate::score::Usage>,
}

fn one() -> u32 {
    1
}

pub(crate) fn unix_ms() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_millis()).unwrap_or(u64::MAX))
}

/// An open run directory.
pub(crate) struct RunDir {
    dir: PathBuf,
}

impl RunDir {
    pub(crate) fn new(dir: &Path) -> RunDir {
        RunDir {
            dir: dir.to_path_buf(),
        }
    }

    pub(crate) fn dir(&self) -> &Path {
        &self.dir
    }

    pub(crate) fn manifest_path(&self) -> PathBuf {
        self.dir.join("manifest.json")
    }

    pub(crate) fn predictions_path(&self) -> PathBuf {
        self.dir.join("predictions.jsonl")
    }

    pub(crate) fn questions_path(&self) -> PathBuf {
        self.dir.join("questions.json")
    }

    /// Whether the folder already holds a run.
    pub(crate) fn holds_run(&self) -> bool {
        self.manifest_path().is_file() || self.predictions_path().is_file()
    }

    pub(crate) fn read_manifest(&self) -> Result<Manifest, AppError> {
        let path = self.manifest_path();
        let bytes = fs_err::read(&path).user()?;
        serde_json::from_slice(&bytes)
            .with_context(|| format!("`{}` is not a contphy-eval manifest", path.display()))
            .user()
    }

    pub(crate) fn write_manifest(&self, manifest: &Manifest) -> Result<(), AppError> {
        write_json(&self.manifest_path(), manifest)
    }

    pub(crate) fn read_questions(&self) -> Result<RunQuestions, AppError> {
        let path = self.questions_path();
        let bytes = fs_err::read(&path).user()?;
        serde_json::from_slice(&bytes)
            .with_context(|| format!("`{}` is not a contphy-eval questions file", path.display()))
            .user()
    }

    pub(crate) fn write_questions(&self, questions: &RunQuestions) -> Result<(), AppError> {
        write_json(&self.questions_path(), questions)
    }

    /// Reads `predictions.jsonl`. A torn last line (a kill mid-write) is cut off the file, so the
    /// unit it belonged to runs again; any other bad line is an error naming its line number.
    pub(crate) fn read_predictions(&self) -> Result<Vec<Prediction>, AppError> {
        let path = self.predictions_path();
        if !path.is_file() {
            return Ok(Vec::new());
        }
        let file = fs_err::File::open(&path).user()?;
        let mut predictions = Vec::new();
        let mut good_bytes = 0_u64;
        let mut lines = std::io::BufReader::new(file)
            .split(b'\n')
            .enumerate()
            .peekable();
        while let Some((index, line)) = lines.next() {
            let line = line
                .with_context(|| format!("cannot read `{}`", path.display()))
                .user()?;
            let is_last = lines.peek().is_none();
            match serde_json::from_slice::<Prediction>(&line) {
                Ok(prediction) => {
                    predictions.push(prediction);
                    good_bytes += line.len() as u64 + 1;
                }
                Err(_) if line.iter().all(u8::is_ascii_whitespace) => {
                    good_bytes += line.len() as u64 + 1;
                }
                Err(_) if is_last => {
                    // A torn tail: truncate to the last complete line.
                    let file = fs_err::OpenOptions::new().write(true).open(&path).user()?;
                    file.set_len(good_bytes).user()?;
                    break;
                }
                Err(error) => {
                    return Err(user_error(format!(
                        "`{}` line {}: not a prediction: {error}",
                        path.display(),
                        index + 1
                    )));
                }
            }
        }
        Ok(predictions)
    }

    /// Opens `predictions.jsonl` for appending.
    pub(crate) fn prediction_writer(&self) -> Result<PredictionWriter, AppError> {
        let path = self.predictions_path();
        let file = fs_err::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .internal()?;
        Ok(PredictionWriter { file, path })
    }

    /// Rewrites `predictions.jsonl` atomically in `order` (unit ids), dropping duplicates.
    pub(crate) fn rewrite_predictions(
        &self,
        predictions: &[Prediction],
        order: &[String],
    ) -> Result<(), AppError> {
        let rank: BTreeMap<&str, usize> = order
            .iter()
            .enumerate()
            .map(|(i, u)| (u.as_str(), i))
            .collect();
        let mut sorted: Vec<&Prediction> = predictions.iter().collect();
        sorted.sort_by_key(|p| {
            (
                rank.get(p.unit.as_str()).copied().unwrap_or(usize::MAX),
                p.unit.clone(),
            )
        });
        sorted.dedup_by(|a, b| a.unit == b.unit);
        let mut bytes = Vec::new();
        for prediction in sorted {
            serde_json::to_writer(&mut bytes, prediction).internal()?;
            bytes.push(b'\n');
        }
        write_atomic(&self.predictions_path(), &bytes).internal()
    }

    pub(crate) fn write_text(&self, name: &str, text: &str) -> Result<(), AppError> {
        write_atomic(&self.dir.join(name), text.as_bytes()).internal()
    }

    pub(crate) fn write_json(&self, name: &str, value: &impl Serialize) -> Result<(), AppError> {
        write_json(&self.dir.join(name), value)
    }
}

fn write_json(path: &Path, value: &impl Serialize) -> Result<(), AppError> {
    let mut bytes = serde_json::to_vec_pretty(value).internal()?;
    bytes.push(b'\n');
    write_atomic(path, &bytes).internal()
}

/// Appends predictions, one durable line each.
pub(crate) struct PredictionWriter {
    file: fs_err::File,
    path: PathBuf,
}

impl PredictionWriter {
    pub(crate) fn append(&mut self, prediction: &Prediction) -> Result<(), AppError> {
        let line = serde_json::to_string(prediction).internal()?;
        append_line_durable(&mut self.file, &self.path, &line).internal()?;
        self.file.flush().internal()
    }
}
