//! The sandbox side of the pipeline: budgets from settings, the worker pool, and the translation
//! of a sandbox result into the pipeline's outcome (value, or a failure with its stage).

use serde_json::Value;

use super::error::{AppError, Classify as _};
use super::settings::Budgets;
use crate::sandbox::{self, Pool, PoolConfig, WorkerCommand};
use crate::scene_api::WorkCounters;
use crate::score::{Stage, UnitError};

/// What the sandbox returned for one program.
#[derive(Debug, Clone)]
pub(crate) struct SandboxOutcome {
    /// The program's value as JSON, or why it has none.
    pub(crate) result: Result<Value, UnitError>,
    /// Scene work done for it.
    pub(crate) work: WorkCounters,
    /// Own time, ms.
    pub(crate) own_ms: u64,
    /// Scene-API time, ms.
    pub(crate) api_ms: u64,
    /// Wall time, ms.
    pub(crate) wall_ms: u64,
}

impl SandboxOutcome {
    /// A program whose result never came back (the pool lost it).
    pub(crate) fn lost() -> SandboxOutcome {
        SandboxOutcome {
            result: Err(UnitError {
                stage: Stage::Sandbox,
                kind: "internal".to_string(),
                message: "the sandbox pool returned no result for this program".to_string(),
            }),
            work: WorkCounters::default(),
            own_ms: 0,
            api_ms: 0,
            wall_ms: 0,
        }
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
    let mut worker = WorkerCommand::current_exe().internal()?;
    // The workers host the scene API, and with it perception: they must find ONNX Runtime
    // where the user said it is.
    let variable = crate::perception::runtime::DYLIB_VARIABLE;
    if let Some(value) = std::env::var_os(variable) {
        worker.environment.push((variable.into(), value));
    }
    let mut config = PoolConfig::new(worker, jobs.max(1));
    config.limits.address_space_bytes = budgets.memory_mib.saturating_mul(1024 * 1024);
    Pool::start(config).internal()
}

/// The pipeline's view of one sandbox result.
pub(crate) fn outcome_from(result: &sandbox::UnitResult) -> SandboxOutcome {
    let report = &result.report;
    let outcome = match &report.outcome {
        Ok(value) => Ok(value.to_plain_json()),
        Err(error) => Err(unit_error(error)),
    };
    let work =
        serde_json::from_value::<WorkCounters>(report.work_counters.clone()).unwrap_or_default();
    SandboxOutcome {
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
