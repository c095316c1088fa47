//! Command-line arguments. Doc comments are the `--help` text.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::app::{
    BenchLlmSettings, BenchMpm88Settings, BenchPerceptionSettings, BenchPhysicsSettings,
    BenchSettings, BenchViewSettings, Budgets, CacheExportSettings, CacheImportSettings,
    CacheSettings, ExecSettings, FitColorsSettings, FrameSelection, FramesSelection,
    GenerateSettings, LlmSettings, ModelOverrides, QuestionsSettings, RenderSettings, Request,
    RunSettings, SplitSelection,
};
use crate::dataset::Scenario;
use crate::scene_api::{DynamicsBackend, PerceptionBackend};
use crate::synth::appearance::Appearance;
use crate::synth::video::FrameOutput;

use super::bench_args::{BenchCommand, PhysicsArgs};
use super::report_args::{ScoreArgs, ViewArgs};

/// Evaluate physical reasoning on ContPhy videos: each question becomes a Python program that
/// runs in a sandbox against the scene API, and answers are scored per option and per question.
///
/// With no subcommand, `contphy-eval --data DIR …` runs the evaluation (`run`).
#[derive(Debug, Parser)]
#[command(
    name = "contphy-eval",
    version,
    args_conflicts_with_subcommands = true,
    subcommand_negates_reqs = true
)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    run: RunArgs,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Evaluate questions on videos and write a run directory (the default command).
    Run(Box<RunArgs>),
    /// Run one program on one video and print one JSON object.
    Exec(ExecArgs),
    /// Print the exact prompt a question (or one of its options) sends to the model.
    Render(RenderArgs),
    /// Generate questions from video annotations (rope: the public engine re-implemented;
    /// fluid, ball: the paper's templates).
    Questions(QuestionsArgs),
    /// Generate synthetic videos in the release format (annotations, 4-D data, frames), then
    /// their questions.
    Generate(GenerateArgs),
    /// Re-score saved runs and print one leaderboard table.
    Score(ScoreArgs),
    /// Write a static site of runs: the leaderboard, and every unit with its program and answer.
    View(ViewArgs),
    /// Inspect the program cache.
    #[command(subcommand)]
    Cache(CacheCommand),
    /// Benchmarks, printed as JSON.
    #[command(subcommand)]
    Bench(BenchCommand),
    /// Perception models: fitting the colour model.
    #[command(subcommand)]
    Perception(PerceptionCommand),
}

/// Which frames perception commands use.
#[derive(Debug, Args, Clone)]
pub struct FrameSelectionArgs {
    /// Use every N-th frame (0-based frame index divisible by N).
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub every: usize,
    /// Only frames in START..END (0-based, END excluded).
    #[arg(long, value_name = "START..END", value_parser = parse_frame_range)]
    pub frame_range: Option<(usize, usize)>,
    /// At most N videos, in folder order.
    #[arg(long, value_name = "N")]
    pub max_videos: Option<usize>,
}

fn parse_frame_range(text: &str) -> Result<(usize, usize), String> {
    let (start, end) = text
        .split_once("..")
        .ok_or_else(|| format!("`{text}` is not START..END"))?;
    let start: usize = start
        .trim()
        .parse()
        .map_err(|_| format!("`{start}` is not a frame index"))?;
    let end: usize = end
        .trim()
        .parse()
        .map_err(|_| format!("`{end}` is not a frame index"))?;
    if end <= start {
        return Err(format!("`{text}` is empty: END must be above START"));
    }
    Ok((start, end))
}

impl FrameSelectionArgs {
    fn selection(&self) -> FrameSelection {
        FrameSelection {
            every: self.every.max(1),
            range: self.frame_range,
            max_videos: self.max_videos,
        }
    }
}

/// `perception` subcommands.
#[derive(Debug, Subcommand)]
pub enum PerceptionCommand {
    /// Fit the colour model (one Gaussian per palette colour over wall-relative features) on the
    /// segmentation truth of videos, and write it as JSON.
    FitColors {
        /// Data roots holding `<scenario folder>/<video_id>/` (repeatable).
        #[arg(long, value_name = "DIR", required = true)]
        data: Vec<PathBuf>,
        /// The scenario whose videos are used (default: the one scenario with perception the
        /// data roots hold).
        #[arg(long, value_name = "SCENARIO")]
        scenario: Option<Scenario>,
        #[command(flatten)]
        frames: FrameSelectionArgs,
        /// Where the model is written.
        #[arg(long, value_name = "FILE")]
        out: PathBuf,
    },
}

/// Backend and budget flags shared by `run` and `exec`.
#[derive(Debug, Args, Clone)]
struct EngineArgs {
    /// Where objects and properties come from.
    #[arg(long, value_enum, default_value_t = PerceptionArg::Annotation)]
    perception: PerceptionArg,
    /// Where dynamics answers come from.
    #[arg(long, value_enum, default_value_t = DynamicsArg::Annotation)]
    dynamics: DynamicsArg,
    /// The Mask R-CNN ONNX model of `--perception maskrcnn` (default: each scenario's committed
    /// model under models/).
    #[arg(long, value_name = "FILE")]
    detector_model: Option<PathBuf>,
    /// The colour model of `--perception maskrcnn`, from `perception fit-colors` (default: each
    /// scenario's committed model under models/).
    #[arg(long, value_name = "FILE")]
    color_model: Option<PathBuf>,
    /// A program's own time budget, seconds (time inside scene-API calls is budgeted apart).
    #[arg(long, value_name = "SECONDS", default_value_t = 5.0)]
    program_timeout: f64,
    /// Time budget for scene-API calls (simulation, perception) per program, seconds.
    #[arg(long, value_name = "SECONDS", default_value_t = 300.0)]
    api_timeout: f64,
    /// Address-space limit of each sandbox worker process, MiB.
    #[arg(long, value_name = "MIB", default_value_t = 2048)]
    memory_limit: u64,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum PerceptionArg {
    /// Objects, masks and tracks from the annotations (the paper's oracle perception).
    Annotation,
    /// The Mask R-CNN ONNX model run on the frames (needs ONNX Runtime:
    /// scripts/setup-onnxruntime.sh).
    Maskrcnn,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum DynamicsArg {
    /// Counterfactual and factual outcomes from the annotations (the paper's offline mode).
    Annotation,
    /// Outcomes simulated from the mechanism rebuilt from the video, masses inferred from its
    /// tracked motion (rope scenes).
    Simulate,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum SplitArg {
    Train,
    Val,
    Test,
    All,
}

/// `run` arguments.
#[derive(Debug, Args, Clone)]
pub struct RunArgs {
    /// Data root: holds `pulley_group/<video_id>/` (and fluid_slides, cloth_collision, soft_body)
    /// and the question files `<scenario folder>_<split>.json`.
    #[arg(long, value_name = "DIR", required = true)]
    data: Option<PathBuf>,
    /// Question files to evaluate (either engine form); default: the sampled files of the split.
    #[arg(long = "questions", value_name = "FILE")]
    questions: Vec<PathBuf>,
    /// Scenarios to evaluate (default: every scenario folder in the data root).
    #[arg(long = "scenario", value_name = "SCENARIO")]
    scenarios: Vec<Scenario>,
    /// Which sampled split to evaluate when no --questions is given.
    #[arg(long, value_enum, default_value_t = SplitArg::Test)]
    split: SplitArg,
    /// The run directory (default: runs/DATE-TIME).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Continue the run in --out: finished units are kept, the rest are run.
    #[arg(long)]
    resume: bool,
    /// Program cache: every program used is recorded there.
    #[arg(long, value_name = "DIR")]
    cache: Option<PathBuf>,
    /// Replay programs from --cache only; a unit whose program is not cached fails.
    #[arg(long, requires = "cache")]
    offline: bool,
    /// Work in parallel: LLM requests in flight, and sandbox worker processes up to the number of
    /// cores (default: the number of cores; 8 requests with --model).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=1024))]
    jobs: Option<u64>,
    /// Evaluate at most N questions (after sharding).
    #[arg(long, value_name = "N")]
    limit: Option<usize>,
    /// Evaluate shard I of N (questions whose index modulo N is I), e.g. 0/4.
    #[arg(long, value_name = "I/N", value_parser = parse_shard)]
    shard: Option<(usize, usize)>,
    /// Ask for one program per choice question, returning the letters of the options that
    /// hold, instead of one yes/no program per option (the paper's way).
    #[arg(long)]
    per_question: bool,
    /// Programs drawn per task; the majority answer is taken (self-consistency).
    #[arg(long, value_name = "K", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=64))]
    samples: u32,
    /// Repair turns per program: a program that fails with a syntax error or a scene-API misuse
    /// is shown to the model with the error (LLM sources only).
    #[arg(long, value_name = "K", default_value_t = 1, value_parser = clap::value_parser!(u32).range(0..=8))]
    repair: u32,
    /// Hide the progress bar.
    #[arg(long, short)]
    quiet: bool,
    #[command(flatten)]
    engine: EngineArgs,
    #[command(flatten)]
    model: ModelArgs,
}

/// Flags of the LLM program source.
#[derive(Debug, Args, Clone)]
#[command(next_help_heading = "Model (programs written by an LLM)")]
struct ModelArgs {
    /// The model that writes the programs, at an OpenAI-compatible endpoint; the API key comes
    /// from OPENAI_API_KEY. Without --model, the builtin program writer is used.
    #[arg(long, value_name = "NAME")]
    model: Option<String>,
    /// The endpoint's base URL (a local vLLM or llama.cpp server: http://127.0.0.1:8000/v1).
    #[arg(long, value_name = "URL", default_value = crate::llm::DEFAULT_BASE_URL, requires = "model")]
    base_url: String,
    /// Sampling temperature (recorded in the manifest and the cache keys).
    #[arg(long, value_name = "T", requires = "model")]
    temperature: Option<f64>,
    /// Nucleus sampling probability mass.
    #[arg(long, value_name = "P", requires = "model")]
    top_p: Option<f64>,
    /// Most tokens per completion.
    #[arg(long, value_name = "N", requires = "model")]
    max_tokens: Option<u32>,
    /// Sampling seed, for servers that honour it.
    #[arg(long, value_name = "S", requires = "model")]
    seed: Option<u64>,
    /// A stop sequence (repeatable).
    #[arg(long, value_name = "TEXT", requires = "model")]
    stop: Vec<String>,
    /// Requests per minute at most.
    #[arg(long, value_name = "N", requires = "model", value_parser = clap::value_parser!(u32).range(1..))]
    rpm: Option<u32>,
    /// Tokens per minute at most (prompt estimate plus completion cap).
    #[arg(long, value_name = "N", requires = "model", value_parser = clap::value_parser!(u32).range(1..))]
    tpm: Option<u32>,
    /// Time allowed for one request attempt, seconds.
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = 120.0,
        requires = "model"
    )]
    request_timeout: f64,
    /// Requests per completion at most: the first and its retries (429, 5xx, timeouts,
    /// connection errors).
    #[arg(long, value_name = "N", default_value_t = 6, requires = "model", value_parser = clap::value_parser!(u32).range(1..=20))]
    max_attempts: u32,
    /// A TOML price table (USD per million tokens) overriding eval/prices.toml.
    #[arg(long, value_name = "FILE", requires = "model")]
    prices: Option<PathBuf>,
    /// Stop sending requests once this run's new completions cost this much (US dollars, from
    /// the price table); finished work is kept, and --resume with a higher cap goes on.
    #[arg(long, value_name = "USD", requires = "model")]
    max_cost: Option<f64>,
}

impl ModelArgs {
    fn into_settings(self) -> Option<LlmSettings> {
        let model = self.model?;
        Some(LlmSettings {
            model,
            base_url: self.base_url,
            temperature: self.temperature,
            top_p: self.top_p,
            max_tokens: self.max_tokens,
            seed: self.seed,
            stop: self.stop,
            rpm: self.rpm,
            tpm: self.tpm,
            request_timeout_seconds: self.request_timeout,
            max_attempts: self.max_attempts,
            prices: self.prices,
            max_cost_usd: self.max_cost,
        })
    }
}

/// `render` arguments.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Data root holding the question files.
    #[arg(long, value_name = "DIR")]
    data: PathBuf,
    /// The question's id (`question_id` of a sampled file, or `<video>_<index>` of a per-video
    /// file).
    #[arg(long, value_name = "ID")]
    question_id: String,
    /// The option letter: render that option's yes/no prompt (choice questions, per option).
    #[arg(long, value_name = "LETTER", conflicts_with = "per_question")]
    option: Option<char>,
    /// Question files to search (default: every question file under the data root).
    #[arg(long = "questions", value_name = "FILE")]
    questions: Vec<PathBuf>,
    /// Render the per-question prompt (one program returning the letters of the options that
    /// hold).
    #[arg(long)]
    per_question: bool,
    /// Print the request as JSON (the chat messages, template hash, api_spec version).
    #[arg(long)]
    json: bool,
}

fn default_jobs() -> usize {
    std::thread::available_parallelism().map_or(2, std::num::NonZero::get)
}

fn parse_shard(text: &str) -> Result<(usize, usize), String> {
    let (index, count) = text.split_once('/').ok_or("expected I/N, e.g. 0/4")?;
    let index: usize = index
        .trim()
        .parse()
        .map_err(|_| format!("`{index}` is not a number"))?;
    let count: usize = count
        .trim()
        .parse()
        .map_err(|_| format!("`{count}` is not a number"))?;
    if count == 0 || index >= count {
        return Err(format!(
            "shard {index}/{count}: I must be smaller than N and N at least 1"
        ));
    }
    Ok((index, count))
}

/// `exec` arguments.
#[derive(Debug, Args)]
pub struct ExecArgs {
    /// The video folder (e.g. DATA/pulley_group/0).
    #[arg(long, value_name = "DIR")]
    video: PathBuf,
    /// The Python program.
    #[arg(long, value_name = "FILE")]
    program: PathBuf,
    /// The scenario (default: from the video's parent folder name).
    #[arg(long, value_name = "SCENARIO")]
    scenario: Option<Scenario>,
    /// Score the value against this question (needs --questions).
    #[arg(long, value_name = "ID", requires = "questions")]
    question_id: Option<String>,
    /// The question file holding --question-id.
    #[arg(long, value_name = "FILE")]
    questions: Option<PathBuf>,
    /// The option letter, for a choice question.
    #[arg(long, value_name = "LETTER", requires = "question_id")]
    option: Option<char>,
    #[command(flatten)]
    engine: EngineArgs,
}

/// `questions` arguments.
#[derive(Debug, Args)]
pub struct QuestionsArgs {
    /// Data root holding `<scenario folder>/<video_id>/`.
    #[arg(long, value_name = "DIR")]
    data: PathBuf,
    /// Where to write `<scenario folder>/<video_id>.json` and
    /// `<scenario folder>_{train,val,test}.json` (default: the data root).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Seed of the question engine and sampler.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Property questions sampled per video [default: the paper's, rope 2, fluid and ball 1].
    #[arg(long, value_name = "N")]
    fact_per_video: Option<usize>,
    /// Dynamics questions sampled per video [default: 2].
    #[arg(long, value_name = "N")]
    dynamics_per_video: Option<usize>,
}

/// `generate` arguments.
#[derive(Debug, Args)]
pub struct GenerateArgs {
    /// The scenario to generate: rope, fluid, cloth or ball.
    #[arg(long, value_name = "SCENARIO")]
    scenario: Option<Scenario>,
    /// Number of videos (folders 0 … N−1).
    #[arg(long, value_name = "N")]
    videos: usize,
    /// Base seed: video i depends only on (seed, i); also seeds the question engine.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Data root to write (`OUT/<scenario folder>/<i>/`, questions beside it). Existing video
    /// folders are kept, so an interrupted generation resumes; a data root `generate` did not
    /// make is refused.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Videos generated at once (default: the number of cores).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..))]
    jobs: Option<u16>,
    /// Frame files: mp4 (needs ffmpeg), png folders, both, or none (annotations only).
    #[arg(long, value_enum, default_value_t = FramesArg::Auto)]
    frames: FramesArg,
    /// Image size, WIDTHxHEIGHT (the release's is 1920x1080).
    #[arg(long, value_name = "WxH", default_value = "1920x1080", value_parser = parse_resolution)]
    resolution: (u32, u32),
    /// How the frames look: the release's, or randomised per video (light, wall, colours within
    /// their names, sensor noise and blur) to train perception on generated frames only.
    /// Annotations and questions are the same either way.
    #[arg(long, value_enum, default_value_t = AppearanceArg::Release)]
    appearance: AppearanceArg,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum AppearanceArg {
    /// The release's look.
    Release,
    /// Domain randomisation, for training perception models.
    Randomized,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum FramesArg {
    /// mp4 when ffmpeg is installed, PNG folders otherwise.
    Auto,
    /// `output_Full.mp4` and `output_Full_seg.mp4`.
    Mp4,
    /// `frames/output_Full_ori/` and `frames/output_Full_seg/` PNG folders.
    Png,
    /// Both.
    Both,
    /// No frame files.
    None,
}

fn parse_resolution(text: &str) -> Result<(u32, u32), String> {
    let parsed = text
        .split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)));
    parsed.ok_or_else(|| format!("`{text}` is not WIDTHxHEIGHT, e.g. 1920x1080"))
}

/// `cache` subcommands.
#[derive(Debug, Subcommand)]
pub enum CacheCommand {
    /// List cached programs.
    Ls {
        /// The cache folder.
        #[arg(long, value_name = "DIR")]
        cache: PathBuf,
    },
    /// Write the programs a run used, with their completions, as one JSONL file that another
    /// user can import and replay with --offline.
    Export {
        /// The cache folder the run recorded into.
        #[arg(long, value_name = "DIR")]
        cache: PathBuf,
        /// The run directory.
        #[arg(long, value_name = "RUN")]
        run: PathBuf,
        /// The JSONL file to write (default: stdout).
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// Add the entries of exported JSONL files to a cache (keys are checked; existing entries
    /// are kept).
    Import {
        /// The cache folder.
        #[arg(long, value_name = "DIR")]
        cache: PathBuf,
        /// Exported JSONL files.
        #[arg(value_name = "FILE", required = true)]
        files: Vec<PathBuf>,
    },
}

impl EngineArgs {
    fn budgets(&self) -> Budgets {
        Budgets {
            program_seconds: self.program_timeout,
            api_seconds: self.api_timeout,
            memory_mib: self.memory_limit,
        }
    }

    fn perception(&self) -> PerceptionBackend {
        match self.perception {
            PerceptionArg::Annotation => PerceptionBackend::Annotation,
            PerceptionArg::Maskrcnn => PerceptionBackend::MaskRcnn,
        }
    }

    fn models(&self) -> ModelOverrides {
        ModelOverrides {
            detector: self.detector_model.clone(),
            colors: self.color_model.clone(),
        }
    }

    fn dynamics(&self) -> DynamicsBackend {
        match self.dynamics {
            DynamicsArg::Annotation => DynamicsBackend::Annotation,
            DynamicsArg::Simulate => DynamicsBackend::Simulate,
        }
    }
}

impl RunArgs {
    fn into_settings(self) -> RunSettings {
        RunSettings {
            data: self.data.unwrap_or_default(),
            questions: self.questions,
            scenarios: self.scenarios,
            split: match self.split {
                SplitArg::Train => SplitSelection::One(crate::dataset::Split::Train),
                SplitArg::Val => SplitSelection::One(crate::dataset::Split::Val),
                SplitArg::Test => SplitSelection::One(crate::dataset::Split::Test),
                SplitArg::All => SplitSelection::All,
            },
            out: self.out,
            resume: self.resume,
            cache: self.cache,
            offline: self.offline,
            jobs: self.jobs.and_then(|jobs| usize::try_from(jobs).ok()),
            llm: self.model.into_settings(),
            limit: self.limit,
            shard: self.shard,
            quiet: self.quiet,
            per_question: self.per_question,
            samples: self.samples,
            repair: self.repair,
            perception: self.engine.perception(),
            models: self.engine.models(),
            dynamics: self.engine.dynamics(),
            budgets: self.engine.budgets(),
        }
    }
}

impl Cli {
    /// The request this command line asks for.
    pub fn into_request(self) -> Request {
        match self.command {
            None => Request::Run(Box::new(self.run.into_settings())),
            Some(Command::Run(args)) => Request::Run(Box::new(args.into_settings())),
            Some(Command::Exec(args)) => Request::Exec(ExecSettings {
                perception: args.engine.perception(),
                models: args.engine.models(),
                dynamics: args.engine.dynamics(),
                budgets: args.engine.budgets(),
                video: args.video,
                program: args.program,
                scenario: args.scenario,
                question_id: args.question_id,
                questions: args.questions,
                option: args.option,
            }),
            Some(Command::Questions(args)) => Request::Questions(QuestionsSettings {
                out: args.out.unwrap_or_else(|| args.data.clone()),
                data: args.data,
                seed: args.seed,
                fact_per_video: args.fact_per_video,
                dynamics_per_video: args.dynamics_per_video,
            }),
            Some(Command::Generate(args)) => Request::Generate(GenerateSettings {
                scenario: args.scenario,
                videos: args.videos,
                seed: args.seed,
                out: args.out,
                jobs: args.jobs.map(usize::from),
                frames: match args.frames {
                    FramesArg::Auto => FramesSelection::Auto,
                    FramesArg::Mp4 => FramesSelection::Exactly(FrameOutput::Mp4),
                    FramesArg::Png => FramesSelection::Exactly(FrameOutput::Png),
                    FramesArg::Both => FramesSelection::Exactly(FrameOutput::Both),
                    FramesArg::None => FramesSelection::Exactly(FrameOutput::None),
                },
                resolution: args.resolution,
                appearance: match args.appearance {
                    AppearanceArg::Release => Appearance::Release,
                    AppearanceArg::Randomized => Appearance::Randomized,
                },
                quiet: args.quiet,
            }),
            Some(Command::Score(args)) => Request::Score(args.into_settings()),
            Some(Command::View(args)) => Request::View(args.into_settings()),
            Some(Command::Cache(CacheCommand::Export { cache, run, out })) => {
                Request::CacheExport(CacheExportSettings { cache, run, out })
            }
            Some(Command::Cache(CacheCommand::Import { cache, files })) => {
                Request::CacheImport(CacheImportSettings { cache, files })
            }
            Some(Command::Cache(CacheCommand::Ls { cache })) => {
                Request::CacheList(CacheSettings { cache })
            }
            Some(Command::Render(args)) => Request::Render(RenderSettings {
                data: args.data,
                questions: args.questions,
                question_id: args.question_id,
                option: args.option,
                per_question: args.per_question,
                json: args.json,
            }),
            Some(Command::Bench(BenchCommand::Physics(args))) => {
                Request::BenchPhysics(bench_physics_settings(args))
            }
            Some(Command::Perception(PerceptionCommand::FitColors {
                data,
                scenario,
                frames,
                out,
            })) => Request::FitColors(FitColorsSettings {
                data,
                scenario,
                frames: frames.selection(),
                out,
            }),
            Some(Command::Bench(BenchCommand::Perception {
                data,
                frames,
                scenario,
                model,
                colors,
                threads,
            })) => Request::BenchPerception(BenchPerceptionSettings {
                data,
                frames: frames.selection(),
                scenario,
                models: ModelOverrides {
                    detector: model,
                    colors,
                },
                threads: threads.max(1),
            }),
            Some(Command::Bench(BenchCommand::Mpm88 {
                init,
                steps,
                threads,
                material,
            })) => Request::BenchMpm88(BenchMpm88Settings {
                init,
                steps,
                threads,
                material,
            }),
            Some(Command::Bench(BenchCommand::Inference { data, noise })) => {
                Request::BenchInference(data, noise)
            }
            Some(Command::Bench(BenchCommand::Llm {
                latency_ms,
                jobs,
                rpm,
                rpm_seconds,
            })) => Request::BenchLlm(BenchLlmSettings {
                latency_ms,
                jobs,
                rpm,
                rpm_seconds,
            }),
            Some(Command::Bench(BenchCommand::View {
                units,
                out,
                browser,
            })) => Request::BenchView(BenchViewSettings {
                units,
                out,
                browser,
            }),
            Some(Command::Bench(BenchCommand::Sandbox { units, jobs, video })) => {
                Request::BenchSandbox(BenchSettings {
                    units,
                    jobs: jobs.unwrap_or_else(default_jobs).max(1),
                    video,
                })
            }
        }
    }
}

/// The `bench physics` settings from its arguments.
fn bench_physics_settings(args: PhysicsArgs) -> BenchPhysicsSettings {
    let PhysicsArgs {
        scenario,
        svg,
        steps,
        grid_spacing,
        particles_per_cell,
        emitter_shift,
        cfl,
        start_shift,
        sheet_resolution,
        substeps,
        iterations,
        ensemble_runs,
        radius_per_spacing,
        videos,
        reference_cache,
        confirm,
    } = args;
    BenchPhysicsSettings {
        scenario,
        svg,
        sweep: physics_sweep(
            steps,
            grid_spacing,
            [
                particles_per_cell,
                sheet_resolution,
                substeps,
                iterations,
                ensemble_runs.map(|runs| vec![runs]),
            ],
            [emitter_shift, cfl, start_shift, radius_per_spacing],
        ),
        videos,
        reference_cache,
        confirm,
    }
}

/// The `bench physics` sweep options that were given, with their flags (`counts`:
/// `--particles-per-cell`, `--sheet-resolution`, `--substeps`, `--iterations`,
/// `--ensemble-runs`; `reals`: `--emitter-shift`, `--cfl`, `--start-shift`,
/// `--radius-per-spacing`).
fn physics_sweep(
    steps: Option<Vec<f64>>,
    grid_spacing: Option<Vec<f64>>,
    counts: [Option<Vec<u32>>; 5],
    reals: [Option<Vec<f64>>; 4],
) -> Vec<(&'static str, Vec<f64>)> {
    let [emitter_shift, cfl, start_shift, radius_per_spacing] = reals;
    let [
        per_cell,
        sheet_resolution,
        substeps,
        iterations,
        ensemble_runs,
    ] = counts.map(|counts| counts.map(|counts| counts.into_iter().map(f64::from).collect()));
    [
        ("--dt", steps),
        ("--grid-spacing", grid_spacing),
        ("--particles-per-cell", per_cell),
        ("--emitter-shift", emitter_shift),
        ("--cfl", cfl),
        ("--start-shift", start_shift),
        ("--sheet-resolution", sheet_resolution),
        ("--substeps", substeps),
        ("--iterations", iterations),
        ("--ensemble-runs", ensemble_runs),
        ("--radius-per-spacing", radius_per_spacing),
    ]
    .into_iter()
    .filter_map(|(flag, values)| values.map(|values| (flag, values)))
    .collect()
}
