//! The per-unit part of `run`: sandbox execution of prepared units (grouped by video, so one
//! worker keeps one video's memoised scene) and the turn of each result into a [`Prediction`].

use serde_json::Value;

use super::error::{AppError, Classify as _};
use super::run::origin_name;
use super::settings::Budgets;
use crate::answer::{interpret, is_correct};
use crate::dataset::{ChoiceOption, Question};
use crate::program::Program;
use crate::sandbox::{self, Pool, PoolConfig, Unit, WorkerCommand, scene_host_spec};
use crate::scene_api::{VideoSpec, WorkCounters};
use crate::score::{Prediction, Stage, UnitError};

/// A unit ready for the sandbox.
#[derive(Debug, Clone)]
pub(crate) struct PreparedUnit {
    /// `<question>` or `<question>:<letter>`.
    pub(crate) unit: String,
    /// Index of its question in the run's question list.
    pub(crate) question_index: usize,
    /// The option, for choice questions.
    pub(crate) option: Option<ChoiceOption>,
    /// The video to bind as the scene.
    pub(crate) video: VideoSpec,
    /// The program.
    pub(crate) program: Program,
}

/// What the sandbox returned for a unit.
#[derive(Debug, Clone)]
pub(crate) struct ExecutedUnit {
    /// The unit id.
    pub(crate) unit: String,
    /// The program's value as JSON, or why it has none.
    pub(crate) result: Result<Value, UnitError>,
    /// Scene work done for the unit.
    pub(crate) work: WorkCounters,
    /// Own time, ms.
    pub(crate) own_ms: u64,
    /// Scene-API time, ms.
    pub(crate) api_ms: u64,
    /// Wall time, ms.
    pub(crate) wall_ms: u64,
}

/// The prediction of an executed unit: its answer judged against the gold.
pub(crate) fn finish_unit(
    question: &Question,
    option: Option<&ChoiceOption>,
    program: &Program,
    executed: ExecutedUnit,
) -> Prediction {
    let (value, answer, correct, error) = match executed.result {
        Ok(value) => match interpret(&value, option) {
            Ok(answer) => {
                let correct = is_correct(&answer, &question.answer, option);
                (Some(value), Some(answer), correct, None)
            }
            Err(error) => (
                Some(value),
                None,
                false,
                Some(UnitError {
                    stage: Stage::Answer,
                    kind: error.kind().to_string(),
                    message: error.to_string(),
                }),
            ),
        },
        Err(error) => (None, None, false, Some(error)),
    };
    Prediction {
        unit: executed.unit,
        question_id: question.id.0.clone(),
        option: option.map(|o| o.letter),
        scenario: question.scenario,
        family: question.family.0.clone(),
        video_id: question.video_id.0.clone(),
        program_hash: Some(program.hash()),
        program_key: program.key.clone(),
        program_origin: Some(origin_name(program.origin).to_string()),
        value,
        answer,
        correct,
        error,
        work: executed.work,
        own_ms: executed.own_ms,
        api_ms: executed.api_ms,
        wall_ms: executed.wall_ms,
    }
}

/// The sandbox's budgets for the run's settings.
pub(crate) fn sandbox_budgets(budgets: Budgets) -> sandbox::Budgets {
    let own_time_ms = seconds_to_ms(budgets.program_seconds);
    let api_time_ms = seconds_to_ms(budgets.api_seconds);
    sandbox::Budgets {
        own_time_ms,
        api_time_ms,
        // CPU may be spent by the program and by the API (simulation); allow both plus slack.
        cpu_time_ms: own_time_ms
            .saturating_add(api_time_ms)
            .saturating_add(10_000),
        ..sandbox::Budgets::default()
    }
}

/// A budget in seconds as whole milliseconds, at least 1 (a zero or invalid budget would stop
/// every program at once).
fn seconds_to_ms(seconds: f64) -> u64 {
    whole_ms(seconds * 1000.0).max(1)
}

/// Starts a pool of `jobs` workers (this binary) with the run's memory limit.
pub(crate) fn start_pool(jobs: usize, budgets: Budgets) -> Result<Pool, AppError> {
    let worker = WorkerCommand::current_exe().internal()?;
    let mut config = PoolConfig::new(worker, jobs.max(1));
    config.limits.address_space_bytes = budgets.memory_mib.saturating_mul(1024 * 1024);
    Pool::start(config).internal()
}

/// The pipeline's view of one sandbox result.
pub(crate) fn executed_from(unit: String, result: &sandbox::UnitResult) -> ExecutedUnit {
    let report = &result.report;
    let outcome = match &report.outcome {
        Ok(value) => Ok(value.to_plain_json()),
        Err(error) => Err(unit_error(error)),
    };
    let work =
        serde_json::from_value::<WorkCounters>(report.work_counters.clone()).unwrap_or_default();
    ExecutedUnit {
        unit,
        result: outcome,
        work,
        own_ms: whole_ms(report.own_ms),
        api_ms: whole_ms(report.api_ms),
        wall_ms: whole_ms(result.wall_ms),
    }
}

/// Milliseconds rounded to whole ones; NaN and negative times become 0.
fn whole_ms(ms: f64) -> u64 {
    if ms.is_finite() && ms > 0.0 {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "positive, finite, rounded, clamped to the u64 range"
        )]
        let rounded = ms.round().min(u64::MAX as f64) as u64;
        rounded
    } else {
        0
    }
}

/// The stage and kind of a sandbox failure: scene exceptions and API time are the scene API's;
/// everything else is the sandbox's.
pub(crate) fn unit_error(error: &sandbox::Error) -> UnitError {
    match error {
        sandbox::Error::ApiException { class_name, .. } => UnitError {
            stage: Stage::SceneApi,
            kind: sandbox::scene_error_kind(class_name)
                .unwrap_or("api_exception")
                .to_string(),
            message: error.to_string(),
        },
        sandbox::Error::ApiTimeout { .. } => UnitError {
            stage: Stage::SceneApi,
            kind: error.kind().to_string(),
            message: error.to_string(),
        },
        other => {
            let kind = match other {
                sandbox::Error::PythonException { class_name, .. } => class_name.clone(),
                _ => other.kind().to_string(),
            };
            UnitError {
                stage: Stage::Sandbox,
                kind,
                message: other.to_string(),
            }
        }
    }
}

/// Runs `units` through a pool of `jobs` workers, calling `on_result` as each finishes. Units of
/// one video go to one worker, in order, so its memoised scene is loaded once.
pub(crate) fn execute_units(
    units: Vec<PreparedUnit>,
    jobs: usize,
    budgets: Budgets,
    mut on_result: impl FnMut(ExecutedUnit),
) -> Result<(), AppError> {
    if units.is_empty() {
        return Ok(());
    }
    let pool = start_pool(jobs.min(units.len()), budgets)?;
    let sandbox_budgets = sandbox_budgets(budgets);
    let mut names = Vec::with_capacity(units.len());
    for (index, unit) in units.into_iter().enumerate() {
        pool.submit(Unit {
            id: index as u64,
            key: format!("{}/{}", unit.video.scenario, unit.video.video_id),
            host: scene_host_spec(&unit.video),
            source: unit.program.source,
            budgets: sandbox_budgets.clone(),
        })
        .internal()?;
        names.push(unit.unit);
    }
    for result in pool.results() {
        let Some(name) = usize::try_from(result.unit_id)
            .ok()
            .and_then(|i| names.get(i))
        else {
            continue;
        };
        on_result(executed_from(name.clone(), &result));
    }
    Ok(())
}
