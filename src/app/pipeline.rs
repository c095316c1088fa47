//! The per-unit part of `run`: sandbox execution of prepared units (grouped by video, so one
//! worker keeps one video's memoised scene) and the turn of each result into a [`Prediction`].

use serde_json::Value;

use super::error::{AppError, Classify as _};
use super::run::origin_name;
use super::settings::Budgets;
use crate::answer::{interpret, is_correct};
use crate::dataset::{ChoiceOption, Question};
use crate::program::Program;
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
                Some(UnitError { stage: Stage::Answer, kind: error.kind().to_string(), message: error.to_string() }),
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
