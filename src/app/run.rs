//! `run`: questions → programs → sandbox → answers → predictions → scores → report.

use std::collections::{BTreeMap, BTreeSet};
use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use serde_json::json;

use super::error::{AppError, Classify as _, user_error};
use super::evaluate::{EvaluationSettings, Task, evaluate};
use super::llm_source::{LlmSource, LlmSourceSettings};
use super::prerequisites::{ScenarioModels, check_frames, model_hashes, resolve_models};
use super::progress::Progress;
use super::run_dir::{Manifest, RunDir, RunIdentity, unix_ms};
use super::settings::DEFAULT_LLM_JOBS;
use super::settings::{RunSettings, SplitSelection};
use super::source::{BuiltinSource, CacheAccess, ProgramSource};
use crate::dataset::{
    ChoiceOption, DataRoot, Question, QuestionSource, Scenario, Split, VideoFolder,
    load_question_file, read_validity, sampled_file_path,
};
use crate::llm::{ClientConfig, Prices, SamplingParams};
use crate::program::ProgramCache;
use crate::report::{ReportMeta, render_run_report, run_plots};
use crate::scenarios;
use crate::scene_api::{DynamicsBackend, PerceptionBackend, VideoSpec};
use crate::score::{EvalQuestion, Prediction, Priors, RunQuestions, Usage, score};
use crate::util::content_hash;

pub(crate) fn run(settings: &RunSettings) -> Result<ExitCode, AppError> {
    let root = DataRoot::open(&settings.data).user()?;
    let Selection {
        questions,
        videos,
        question_files,
        skipped_invalid,
    } = select_questions(&root, settings)?;
    // The backends' prerequisites, before the first unit: a missing one is one line, not a
    // report of failed units.
    check_frames(settings.perception, videos.values().flatten())?;
    let models = resolve_models(
        settings.perception,
        questions.iter().map(|q| q.scenario),
        &settings.models,
    )?;

    let priors = load_priors(&root, &questions)?;
    let out = settings.out.clone().unwrap_or_else(default_run_dir);
    let source = program_source(settings, &out)?;
    let identity = RunIdentity {
        program_source: source.name(),
        source_identity: source_identity(&source.describe()),
        offline: settings.offline,
        perception: settings.perception,
        perception_models: model_hashes(&models)?,
        dynamics: settings.dynamics,
        budgets: settings.budgets,
        split: settings.split,
        question_files: question_files.clone(),
        data_hash: data_hash(videos.values().flatten())?,
        limit: settings.limit,
        shard: settings.shard,
        per_question: settings.per_question,
        samples: settings.samples,
        repair: settings.repair,
    };
    let run_dir = RunDir::new(&out);
    let done = resumed_predictions(&run_dir, settings, &identity)?;
    fs_err::create_dir_all(&out).user()?;

    let eval_questions: Vec<EvalQuestion> =
        questions.iter().map(EvalQuestion::from_question).collect();
    let unit_order: Vec<String> = eval_questions
        .iter()
        .flat_map(EvalQuestion::unit_ids)
        .collect();
    let mut manifest = Manifest {
        tool: "contphy-eval".to_string(),
        tool_version: env!("CARGO_PKG_VERSION").to_string(),
        git_revision: option_env!("CONTPHY_GIT_REVISION").map(str::to_string),
        source: source.describe(),
        identity,
        data_root: settings.data.display().to_string(),
        questions: questions.len(),
        units: unit_order.len(),
        skipped_invalid_video_questions: skipped_invalid,
        started_unix_ms: unix_ms(),
        finished_unix_ms: 0,
        usage: None,
    };
    run_dir.write_manifest(&manifest)?;
    run_dir.write_questions(&RunQuestions {
        questions: eval_questions.clone(),
        priors: priors.clone(),
    })?;

    let finished: BTreeSet<&str> = done.iter().map(|p| p.unit.as_str()).collect();
    if settings.resume && !finished.is_empty() {
        let kept = unit_order
            .iter()
            .filter(|unit| finished.contains(unit.as_str()))
            .count();
        let mut stderr = std::io::stderr().lock();
        let _ = writeln!(
            stderr,
            "resuming: {kept} of {} units already done",
            unit_order.len()
        );
    }
    // With perception, the frames it reads are kept with its detections drawn, for `view`.
    let frames_dir =
        (settings.perception == PerceptionBackend::MaskRcnn).then(|| run_dir.dir().join("frames"));
    let tasks = plan_tasks(
        &questions,
        &videos,
        &finished,
        &models,
        settings,
        frames_dir.as_deref(),
    );
    let new_predictions = run_tasks(
        &tasks,
        &questions,
        &finished,
        source.as_ref(),
        &run_dir,
        settings,
    )?;

    let mut all = done;
    all.extend(new_predictions);
    run_dir.rewrite_predictions(&all, &unit_order)?;
    let predictions = run_dir.read_predictions()?;
    let scores = score(&eval_questions, &predictions, &priors);
    run_dir.write_json("results.json", &json!({ "scores": scores }))?;
    let usage = run_usage(&predictions);
    let plots = run_plots(&source.name(), &scores, &eval_questions, &predictions).internal()?;
    for plot in &plots {
        run_dir.write_text(&format!("plots/{}", plot.file_name), &plot.svg)?;
    }
    let meta = ReportMeta {
        usage,
        plots: plots
            .iter()
            .map(|plot| (plot.file_name.clone(), plot.caption.clone()))
            .collect(),
        run_name: out.file_name().map_or_else(
            || out.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        ),
        program_source: source.name(),
        backends: backends_line(settings.perception, settings.dynamics),
        questions: question_files
            .iter()
            .map(|(path, _)| path.as_str())
            .collect::<Vec<_>>()
            .join(", "),
    };
    let report = render_run_report(&meta, &scores);
    run_dir.write_text("report.md", &report)?;
    manifest.finished_unix_ms = unix_ms();
    manifest.usage = usage;
    run_dir.write_manifest(&manifest)?;

    let mut stdout = std::io::stdout().lock();
    let _ = write!(stdout, "{report}");
    let _ = writeln!(stdout, "\nrun directory: {}", run_dir.dir().display());
    Ok(ExitCode::SUCCESS)
}

/// The questions a run evaluates, with their video folders.
struct Selection {
    /// In file order, then sharded and limited; questions of invalid trials left out.
    questions: Vec<Question>,
    /// Every video a question names: its folder, or `None` for an invalid trial.
    videos: BTreeMap<(Scenario, String), Option<VideoFolder>>,
    /// The question files read (path and content hash).
    question_files: Vec<(String, String)>,
    /// Questions left out because their video is an invalid trial.
    skipped_invalid: usize,
}

/// Loads the run's question files and selects its questions: every question must name a video
/// folder; questions of invalid trials are skipped with a count; then `--shard` and `--limit`.
fn select_questions(root: &DataRoot, settings: &RunSettings) -> Result<Selection, AppError> {
    let (sources, question_files) = load_questions(root, settings)?;
    let mut questions: Vec<Question> = Vec::new();
    let mut videos: BTreeMap<(Scenario, String), Option<VideoFolder>> = BTreeMap::new();
    for source in sources {
        for question in source.questions {
            let key = (question.scenario, question.video_id.0.clone());
            if let std::collections::btree_map::Entry::Vacant(slot) = videos.entry(key) {
                let folder = root.video(question.scenario, &question.video_id);
                if !folder.outputs_json().is_file() {
                    return Err(AppError {
                        class: super::ErrorClass::User,
                        error: crate::dataset::DatasetError::MissingVideo {
                            path: source.path.clone(),
                            question_id: question.id.0.clone(),
                            video_id: question.video_id.0.clone(),
                            expected: folder.dir.clone(),
                        }
                        .into(),
                    });
                }
                let valid = read_validity(&folder.outputs_json()).user()?;
                slot.insert(valid.then_some(folder));
            }
            questions.push(question);
        }
    }
    let before = questions.len();
    questions.retain(|q| {
        videos
            .get(&(q.scenario, q.video_id.0.clone()))
            .is_some_and(Option::is_some)
    });
    let skipped_invalid = before - questions.len();
    if let Some((index, count)) = settings.shard {
        questions = questions
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % count == index)
            .map(|(_, q)| q)
            .collect();
    }
    if let Some(limit) = settings.limit {
        questions.truncate(limit);
    }
    if questions.is_empty() {
        return Err(user_error(
            "no questions to evaluate (check --questions, --split, --scenario, --shard and --limit)",
        ));
    }
    Ok(Selection {
        questions,
        videos,
        question_files,
        skipped_invalid,
    })
}

/// The predictions a run directory already holds, when `--resume` continues the same run
/// (`identity`); none for a new directory. A directory holding a run without `--resume`, or
/// another run, is refused.
fn resumed_predictions(
    run_dir: &RunDir,
    settings: &RunSettings,
    identity: &RunIdentity,
) -> Result<Vec<Prediction>, AppError> {
    if !run_dir.holds_run() {
        return Ok(Vec::new());
    }
    if !settings.resume {
        return Err(user_error(format!(
            "`{}` already holds a run; pass --resume to continue it or choose another --out",
            run_dir.dir().display()
        )));
    }
    let manifest = run_dir.read_manifest()?;
    if manifest.identity != *identity {
        return Err(user_error(format!(
            "`{}` holds a run with different settings or data; --resume continues only the same run (use another --out)",
            run_dir.dir().display()
        )));
    }
    run_dir.read_predictions()
}

/// Runs the tasks, appending each prediction to the run directory as its task finishes (with a
/// progress bar); returns the new predictions.
fn run_tasks(
    tasks: &[Task],
    questions: &[Question],
    finished: &BTreeSet<&str>,
    source: &dyn ProgramSource,
    run_dir: &RunDir,
    settings: &RunSettings,
) -> Result<Vec<Prediction>, AppError> {
    let total_units: usize = tasks.iter().map(|t| t.units.len()).sum();
    let progress = Progress::new(total_units as u64, settings.quiet);
    let mut writer = run_dir.prediction_writer()?;
    let mut failed = 0_u64;
    let mut new_predictions = Vec::with_capacity(total_units);
    let evaluation = EvaluationSettings {
        workers: sandbox_workers(settings.jobs),
        budgets: settings.budgets,
        samples: settings.samples,
        repair: settings.repair,
    };
    evaluate(tasks, questions, source, evaluation, |predictions| {
        for prediction in predictions {
            // A resumed per-question task may re-answer units that were already saved.
            if finished.contains(prediction.unit.as_str()) {
                continue;
            }
            if prediction.error.is_some() {
                failed += 1;
            }
            writer.append(&prediction)?;
            progress.advance(failed);
            new_predictions.push(prediction);
        }
        Ok(())
    })?;
    progress.finish();
    Ok(new_predictions)
}

/// `perception=…, dynamics=…` for the report.
/// `perception=…, dynamics=…`, as the report and the viewer name a run's backends.
pub(crate) fn backends_line(perception: PerceptionBackend, dynamics: DynamicsBackend) -> String {
    let name = |value: serde_json::Result<serde_json::Value>| {
        value
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_default()
    };
    format!(
        "perception={}, dynamics={}",
        name(serde_json::to_value(perception)),
        name(serde_json::to_value(dynamics)),
    )
}

/// The core count: sandbox workers never exceed it (`--jobs` above it is LLM concurrency).
fn cores() -> usize {
    std::thread::available_parallelism().map_or(2, std::num::NonZero::get)
}

/// Sandbox worker processes for `--jobs`.
fn sandbox_workers(jobs: Option<usize>) -> usize {
    jobs.unwrap_or_else(cores).clamp(1, cores())
}

/// The run's program source: the builtin writer, or the model of `--model` (after a preflight
/// check of the endpoint, unless the run is offline).
fn program_source(
    settings: &RunSettings,
    out: &std::path::Path,
) -> Result<Box<dyn ProgramSource>, AppError> {
    let Some(llm) = &settings.llm else {
        let cache = CacheAccess {
            cache: settings.cache.as_deref().map(ProgramCache::new),
            offline: settings.offline,
        };
        return Ok(Box::new(BuiltinSource { cache }));
    };
    // Completions cost money: without --cache they are kept in the run directory, so a resumed
    // run never pays for one twice.
    let cache_dir = settings.cache.clone().unwrap_or_else(|| out.join("cache"));
    let cache = CacheAccess {
        cache: Some(ProgramCache::new(&cache_dir)),
        offline: settings.offline,
    };
    let api_key = std::env::var("OPENAI_API_KEY")
        .ok()
        .filter(|key| !key.trim().is_empty());
    if api_key.is_none()
        && !settings.offline
        && llm.base_url.trim_end_matches('/') == crate::llm::DEFAULT_BASE_URL
    {
        return Err(user_error(format!(
            "OPENAI_API_KEY is not set; export it to use `{}` at {}, or pass --base-url for a server that needs no key",
            llm.model,
            crate::llm::DEFAULT_BASE_URL
        )));
    }
    if !(llm.request_timeout_seconds.is_finite() && llm.request_timeout_seconds > 0.0) {
        return Err(user_error(
            "--request-timeout must be a positive number of seconds",
        ));
    }
    let mut client = ClientConfig::new(llm.base_url.clone());
    client.api_key = api_key;
    client.rpm = llm.rpm;
    client.tpm = llm.tpm;
    client.max_attempts = llm.max_attempts;
    client.request_timeout = std::time::Duration::from_secs_f64(llm.request_timeout_seconds);
    let sampling = SamplingParams {
        temperature: llm.temperature,
        top_p: llm.top_p,
        max_tokens: llm.max_tokens,
        seed: llm.seed,
        stop: llm.stop.clone(),
    };
    let prices = Prices::resolve(llm.prices.as_deref()).user()?;
    if settings.samples > 1 && llm.temperature == Some(0.0) {
        let _ = writeln!(
            std::io::stderr().lock(),
            "warning: --samples {} at --temperature 0 draws near-identical programs; self-consistency needs a temperature above 0",
            settings.samples
        );
    }
    let source = LlmSource::new(
        LlmSourceSettings {
            client,
            model: llm.model.clone(),
            sampling,
            jobs: settings.jobs.unwrap_or(DEFAULT_LLM_JOBS),
            prices,
            quiet: settings.quiet,
            max_cost_usd: llm.max_cost_usd,
        },
        cache,
    )?;
    if !settings.offline {
        source.preflight()?;
    }
    Ok(Box::new(source))
}

/// What of a source's description determines results: everything but the endpoint's transport
/// settings (URL, timeouts, rate limits), which a resumed run may change.
fn source_identity(described: &serde_json::Value) -> serde_json::Value {
    let mut identity = described.clone();
    if let Some(object) = identity.as_object_mut() {
        object.remove("endpoint");
        object.remove("prices");
    }
    identity
}

/// Token, cost and request totals over the run's predictions (`None` without an LLM).
fn run_usage(predictions: &[Prediction]) -> Option<Usage> {
    let mut total = Usage::default();
    let mut any = false;
    for usage in predictions.iter().filter_map(|p| p.usage.as_ref()) {
        total.add(usage);
        any = true;
    }
    any.then_some(total)
}

/// The tasks of the run: one per unit (per-option mode), skipping finished units.
fn plan_tasks(
    questions: &[Question],
    videos: &BTreeMap<(Scenario, String), Option<VideoFolder>>,
    finished: &BTreeSet<&str>,
    models: &ScenarioModels,
    settings: &RunSettings,
    frames_dir: Option<&std::path::Path>,
) -> Vec<Task> {
    let mut tasks = Vec::new();
    for (question_index, question) in questions.iter().enumerate() {
        let Some(Some(video)) = videos.get(&(question.scenario, question.video_id.0.clone()))
        else {
            continue;
        };
        let spec = VideoSpec::new(video, settings.perception, settings.dynamics)
            .with_models(models.get(&question.scenario).cloned())
            .with_overlays(frames_dir.map(|dir| {
                dir.join(question.scenario.name())
                    .join(&question.video_id.0)
            }));
        if settings.per_question && question.answer_type.is_choice() {
            let units: Vec<(String, Option<ChoiceOption>)> = question
                .units()
                .into_iter()
                .map(|(unit, option)| (unit, option.cloned()))
                .collect();
            if units
                .iter()
                .all(|(unit, _)| finished.contains(unit.as_str()))
            {
                continue;
            }
            tasks.push(Task {
                question_index,
                option: None,
                whole_question: true,
                units,
                video: spec,
            });
            continue;
        }
        for (unit, option) in question.units() {
            if finished.contains(unit.as_str()) {
                continue;
            }
            tasks.push(Task {
                question_index,
                option: option.cloned(),
                whole_question: false,
                units: vec![(unit, option.cloned())],
                video: spec.clone(),
            });
        }
    }
    tasks
}

fn default_run_dir() -> PathBuf {
    let seconds = unix_ms() / 1000;
    let (days, rest) = (seconds / 86_400, seconds % 86_400);
    let (year, month, day) = civil_from_days(i64::try_from(days).unwrap_or(0));
    PathBuf::from("runs").join(format!(
        "{year:04}{month:02}{day:02}-{:02}{:02}{:02}",
        rest / 3600,
        (rest % 3600) / 60,
        rest % 60
    ))
}

/// Gregorian date of a day count since 1970-01-01 (Howard Hinnant's algorithm).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = u32::try_from(doy - (153 * mp + 2) / 5 + 1).unwrap_or(1);
    let month = u32::try_from(if mp < 10 { mp + 3 } else { mp - 9 }).unwrap_or(1);
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// Question files with their content hashes (`(path, blake3)`), as the manifest records them.
type HashedFiles = Vec<(String, String)>;

/// The question files of the run: `--questions`, or the sampled files of the split(s).
fn load_questions(
    root: &DataRoot,
    settings: &RunSettings,
) -> Result<(Vec<QuestionSource>, HashedFiles), AppError> {
    let paths: Vec<(PathBuf, Option<Scenario>)> = if settings.questions.is_empty() {
        let scenarios = if settings.scenarios.is_empty() {
            root.scenarios()
        } else {
            settings.scenarios.clone()
        };
        if scenarios.is_empty() {
            return Err(user_error(format!(
                "data root `{}` has no scenario folder ({})",
                root.dir().display(),
                Scenario::folder_names()
            )));
        }
        let splits: Vec<Split> = match settings.split {
            SplitSelection::One(split) => vec![split],
            SplitSelection::All => Split::ALL.to_vec(),
        };
        let mut paths = Vec::new();
        for scenario in scenarios {
            // A --scenario the data root has no videos of: say so, not "make its questions".
            if !root.scenario_dir(scenario).is_dir() {
                let present = root.scenarios();
                return Err(user_error(format!(
                    "data root `{}` has no `{}/` folder (no {} videos; it holds {})",
                    root.dir().display(),
                    scenario.folder_name(),
                    scenario.name(),
                    if present.is_empty() {
                        "no scenario folder".to_string()
                    } else {
                        present
                            .iter()
                            .map(|s| format!("`{}/`", s.folder_name()))
                            .collect::<Vec<_>>()
                            .join(", ")
                    }
                )));
            }
            for split in &splits {
                let path = sampled_file_path(root, scenario, *split);
                if !path.is_file() {
                    return Err(user_error(format!(
                        "no question file `{}`; generate questions with `contphy-eval questions --data {}` or pass --questions FILE",
                        path.display(),
                        root.dir().display()
                    )));
                }
                paths.push((path, Some(scenario)));
            }
        }
        paths
    } else {
        // One --scenario names the scenario of files whose names do not tell it.
        let hint = match settings.scenarios.as_slice() {
            [one] => Some(*one),
            _ => None,
        };
        settings
            .questions
            .iter()
            .map(|p| (p.clone(), hint))
            .collect()
    };
    let mut sources = Vec::new();
    let mut files = Vec::new();
    for (path, scenario) in paths {
        let source = load_question_file(&path, scenario, scenarios::families()).user()?;
        if !settings.scenarios.is_empty() && !settings.scenarios.contains(&source.scenario) {
            continue;
        }
        let hash = content_hash(&fs_err::read(&path).user()?);
        files.push((path.display().to_string(), hash));
        sources.push(source);
    }
    Ok((sources, files))
}

/// Priors of the FRQ/RND baselines from the train split files of the evaluated scenarios.
fn load_priors(root: &DataRoot, questions: &[Question]) -> Result<Priors, AppError> {
    let scenarios: BTreeSet<Scenario> = questions.iter().map(|q| q.scenario).collect();
    let mut train = Vec::new();
    for scenario in scenarios {
        let path = sampled_file_path(root, scenario, Split::Train);
        if path.is_file() {
            train.extend(
                load_question_file(&path, Some(scenario), scenarios::families())
                    .user()?
                    .questions,
            );
        }
    }
    Ok(Priors::from_train(&train))
}

/// Content hash over the evaluated videos' annotation files.
fn data_hash<'a>(videos: impl Iterator<Item = &'a VideoFolder>) -> Result<String, AppError> {
    let mut hasher = blake3::Hasher::new();
    for video in videos {
        let bytes = fs_err::read(video.outputs_json()).user()?;
        hasher.update(video.id.0.as_bytes());
        hasher.update(blake3::hash(&bytes).as_bytes());
    }
    Ok(hasher.finalize().to_hex().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn civil_dates_are_right() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(20_779), (2026, 11, 22));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
    }

    #[test]
    fn default_run_dir_is_under_runs() {
        assert!(default_run_dir().starts_with(std::path::Path::new("runs")));
    }
}
