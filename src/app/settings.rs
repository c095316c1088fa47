//! Typed settings of each command, built by `cli` from the command line.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

pub use super::prerequisites::ModelOverrides;
use crate::dataset::{Scenario, Split};
use crate::scene_api::{DynamicsBackend, PerceptionBackend};
use crate::synth::appearance::Appearance;

/// A command to run.
#[derive(Debug)]
pub enum Request {
    /// `run`.
    Run(Box<RunSettings>),
    /// `view`.
    View(ViewSettings),
    /// `bench view`.
    BenchView(super::BenchViewSettings),
    /// `exec`.
    Exec(ExecSettings),
    /// `questions`.
    Questions(QuestionsSettings),
    /// `score`.
    Score(ScoreSettings),
    /// `cache ls`.
    CacheList(CacheSettings),
    /// `cache export`.
    CacheExport(CacheExportSettings),
    /// `cache import`.
    CacheImport(CacheImportSettings),
    /// `bench sandbox`.
    BenchSandbox(BenchSettings),
    /// `bench llm`.
    BenchLlm(BenchLlmSettings),
    /// `bench physics`.
    BenchPhysics(BenchPhysicsSettings),
    /// `render`.
    Render(RenderSettings),
    /// `generate`.
    Generate(GenerateSettings),
    /// `bench inference` over a data root, at these track-noise levels (units).
    BenchInference(PathBuf, Vec<f64>),
    /// `perception fit-colors`.
    FitColors(super::perception::FitColorsSettings),
    /// `bench perception`.
    BenchPerception(super::perception::BenchPerceptionSettings),
    /// `bench mpm88`.
    BenchMpm88(super::bench_mpm::BenchMpm88Settings),
}

/// Which sampled split(s) a run evaluates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SplitSelection {
    /// One split.
    One(Split),
    /// Train, val and test.
    All,
}

/// Sandbox budgets per program.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Budgets {
    /// The program's own time (interpreter time outside the scene API), seconds.
    pub program_seconds: f64,
    /// Time inside scene-API calls, seconds.
    pub api_seconds: f64,
    /// Address-space limit per worker process, MiB.
    pub memory_mib: u64,
}

/// `run` settings.
#[derive(Debug, Clone)]
pub struct RunSettings {
    /// Data root.
    pub data: PathBuf,
    /// Explicit question files.
    pub questions: Vec<PathBuf>,
    /// Scenarios to evaluate (empty: all present).
    pub scenarios: Vec<Scenario>,
    /// Split(s) when no question files are given.
    pub split: SplitSelection,
    /// Run directory.
    pub out: Option<PathBuf>,
    /// Continue an existing run.
    pub resume: bool,
    /// Program cache.
    pub cache: Option<PathBuf>,
    /// Replay from the cache only.
    pub offline: bool,
    /// `--jobs`: LLM requests in flight; sandbox workers are this, capped at the core count.
    /// `None`: the core count for both, and [`DEFAULT_LLM_JOBS`] requests for a model.
    pub jobs: Option<usize>,
    /// The model that writes programs (`None`: the builtin writer).
    pub llm: Option<LlmSettings>,
    /// At most this many questions.
    pub limit: Option<usize>,
    /// Shard `(index, count)`.
    pub shard: Option<(usize, usize)>,
    /// No progress bar.
    pub quiet: bool,
    /// One program per choice question.
    pub per_question: bool,
    /// Programs drawn per task.
    pub samples: u32,
    /// Repair turns per program.
    pub repair: u32,
    /// Perception backend.
    pub perception: PerceptionBackend,
    /// The model files of `--perception maskrcnn` named on the command line.
    pub models: ModelOverrides,
    /// Dynamics backend.
    pub dynamics: DynamicsBackend,
    /// Sandbox budgets.
    pub budgets: Budgets,
}

/// Requests in flight to a model when `--jobs` is not given: a hosted API answers in seconds,
/// so the run waits on the network, not on the cores.
pub const DEFAULT_LLM_JOBS: usize = 8;

/// How a model writes the programs of a run (`--model` and its flags). The API key is not
/// here: it is read from `OPENAI_API_KEY` when the client is made, so that no settings dump can
/// show it.
#[derive(Debug, Clone, PartialEq)]
pub struct LlmSettings {
    /// The model id.
    pub model: String,
    /// The OpenAI-compatible base URL (`.../v1`).
    pub base_url: String,
    /// Sampling temperature.
    pub temperature: Option<f64>,
    /// Nucleus sampling.
    pub top_p: Option<f64>,
    /// Completion token cap.
    pub max_tokens: Option<u32>,
    /// Sampling seed, for servers that honour it.
    pub seed: Option<u64>,
    /// Stop sequences.
    pub stop: Vec<String>,
    /// Requests per minute.
    pub rpm: Option<u32>,
    /// Tokens per minute.
    pub tpm: Option<u32>,
    /// Per-attempt request timeout, seconds.
    pub request_timeout_seconds: f64,
    /// Requests per completion at most (first try and retries).
    pub max_attempts: u32,
    /// A price table overriding the built-in one.
    pub prices: Option<PathBuf>,
    /// Spending cap for this run's new completions, USD.
    pub max_cost_usd: Option<f64>,
}

/// `render` settings.
#[derive(Debug, Clone)]
pub struct RenderSettings {
    /// Data root.
    pub data: PathBuf,
    /// Question files to search (default: every sampled and per-video file of the root).
    pub questions: Vec<PathBuf>,
    /// The question.
    pub question_id: String,
    /// The option letter (per-option mode).
    pub option: Option<char>,
    /// Render the per-question prompt.
    pub per_question: bool,
    /// Print the request as JSON (messages and key material) instead of text.
    pub json: bool,
}

/// Which frame files `generate` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FramesSelection {
    /// mp4 when ffmpeg is installed, PNG folders otherwise.
    Auto,
    /// Exactly this.
    Exactly(crate::synth::video::FrameOutput),
}

/// `generate` settings.
#[derive(Debug, Clone)]
pub struct GenerateSettings {
    /// The scenario; `None`: the one scenario with a generator.
    pub scenario: Option<Scenario>,
    /// Number of videos.
    pub videos: usize,
    /// Base seed (videos, and the question engine and sampler).
    pub seed: u64,
    /// The data root to write.
    pub out: PathBuf,
    /// Worker threads (`None`: the number of cores).
    pub jobs: Option<usize>,
    /// Frame files.
    pub frames: FramesSelection,
    /// Image width and height, pixels.
    pub resolution: (u32, u32),
    /// How the frames look.
    pub appearance: Appearance,
    /// No progress bar.
    pub quiet: bool,
}

/// `bench physics` settings.
#[derive(Debug, Clone)]
pub struct BenchPhysicsSettings {
    /// The scenario whose simulator is measured; `None`: the one scenario with a benchmark.
    pub scenario: Option<Scenario>,
    /// Where to write the SVG plot.
    pub svg: Option<PathBuf>,
    /// Values to sweep, by the option that gave them (`--dt`, `--grid-spacing`); empty: the
    /// simulator's own sweep.
    pub sweep: Vec<(&'static str, Vec<f64>)>,
    /// Videos the cases are built from, for simulators that need scenes (empty: the
    /// scenario's demo video).
    pub videos: Vec<PathBuf>,
    /// Where reference runs are stored and reused (`--reference-cache`).
    pub reference_cache: Option<PathBuf>,
    /// Whether decided labels count only when the simulator's confirmation point repeats
    /// them (`--confirm`).
    pub confirm: bool,
}

/// `bench llm` settings.
#[derive(Debug, Clone)]
pub struct BenchLlmSettings {
    /// Simulated server latency, ms.
    pub latency_ms: u64,
    /// Concurrency levels.
    pub jobs: Vec<usize>,
    /// Requests-per-minute limits to check.
    pub rpm: Vec<u32>,
    /// Seconds each rate limit is measured over.
    pub rpm_seconds: f64,
}

/// `exec` settings.
#[derive(Debug, Clone)]
pub struct ExecSettings {
    /// The video folder.
    pub video: PathBuf,
    /// The program file.
    pub program: PathBuf,
    /// The scenario, if given.
    pub scenario: Option<Scenario>,
    /// A question to score the value against.
    pub question_id: Option<String>,
    /// The file holding that question.
    pub questions: Option<PathBuf>,
    /// The option letter.
    pub option: Option<char>,
    /// Perception backend.
    pub perception: PerceptionBackend,
    /// The model files of `--perception maskrcnn` named on the command line.
    pub models: ModelOverrides,
    /// Dynamics backend.
    pub dynamics: DynamicsBackend,
    /// Sandbox budgets.
    pub budgets: Budgets,
}

/// `questions` settings.
#[derive(Debug, Clone)]
pub struct QuestionsSettings {
    /// Data root.
    pub data: PathBuf,
    /// Output folder.
    pub out: PathBuf,
    /// Engine and sampler seed.
    pub seed: u64,
    /// Property questions per video (`None`: the engine's, [`QuestionEngine::per_video`]).
    ///
    /// [`QuestionEngine::per_video`]: crate::dataset::engine::QuestionEngine::per_video
    pub fact_per_video: Option<usize>,
    /// Dynamics questions per video (`None`: the engine's).
    pub dynamics_per_video: Option<usize>,
}

/// `score` settings.
#[derive(Debug, Clone)]
pub struct ScoreSettings {
    /// Run directories.
    pub runs: Vec<PathBuf>,
    /// JSON instead of a table.
    pub json: bool,
}

/// `view` settings.
#[derive(Debug, Clone)]
pub struct ViewSettings {
    /// Run directories.
    pub runs: Vec<PathBuf>,
    /// The site's folder.
    pub out: PathBuf,
    /// The program cache the runs used, for the programs' texts.
    pub cache: Option<PathBuf>,
}

/// `cache ls` settings.
#[derive(Debug, Clone)]
pub struct CacheSettings {
    /// The cache folder.
    pub cache: PathBuf,
}

/// `cache export` settings.
#[derive(Debug, Clone)]
pub struct CacheExportSettings {
    /// The cache folder.
    pub cache: PathBuf,
    /// The run whose programs are exported.
    pub run: PathBuf,
    /// Output file (stdout when `None`).
    pub out: Option<PathBuf>,
}

/// `cache import` settings.
#[derive(Debug, Clone)]
pub struct CacheImportSettings {
    /// The cache folder.
    pub cache: PathBuf,
    /// Exported JSONL files.
    pub files: Vec<PathBuf>,
}

/// `bench sandbox` settings.
#[derive(Debug, Clone)]
pub struct BenchSettings {
    /// Units through the pool.
    pub units: usize,
    /// Worker processes.
    pub jobs: usize,
    /// The video whose builtin programs are timed; `None`: the repository's demo video.
    pub video: Option<PathBuf>,
}
