//! `exec`: one program on one video, through the same sandbox worker as `run`; prints one JSON
//! object. Exit 0 when the program produced a value, 1 when it failed (or the input is bad).

use std::io::Write as _;
use std::process::ExitCode;

use serde_json::json;

use super::error::{AppError, Classify as _, user_error};
use super::pipeline::{outcome_from, sandbox_budgets, start_pool};
use super::prerequisites::{check_frames, resolve_models};
use super::settings::ExecSettings;
use crate::answer::{interpret, is_correct};
use crate::dataset::{VideoFolder, load_question_file, read_validity};
use crate::sandbox::{Unit, scene_host_spec};
use crate::scenarios;
use crate::scene_api::VideoSpec;
use crate::score::{Stage, UnitError};

pub(crate) fn exec(settings: &ExecSettings) -> Result<ExitCode, AppError> {
    let video = VideoFolder::open(&settings.video, settings.scenario).user()?;
    if !read_validity(&video.outputs_json()).user()? {
        return Err(user_error(format!(
            "`{}` is an invalid trial (`validity: false`); it has no annotations to answer from",
            video.dir.display()
        )));
    }
    let source = fs_err::read_to_string(&settings.program).user()?;
    let question = match (&settings.question_id, &settings.questions) {
        (Some(id), Some(path)) => {
            let loaded =
                load_question_file(path, Some(video.scenario), scenarios::families()).user()?;
            let question = loaded
                .questions
                .into_iter()
                .find(|q| q.id.0 == *id)
                .ok_or_else(|| {
                    user_error(format!("question `{id}` is not in `{}`", path.display()))
                })?;
            Some(question)
        }
        _ => None,
    };
    let option = match (&question, settings.option) {
        (Some(question), Some(letter)) => {
            Some(question.option(letter).cloned().ok_or_else(|| {
                user_error(format!(
                    "question `{}` has no option `{letter}`",
                    question.id
                ))
            })?)
        }
        (Some(question), None) if question.answer_type.is_choice() => {
            return Err(user_error(format!(
                "question `{}` is a choice question; pass --option with one of its letters",
                question.id
            )));
        }
        _ => None,
    };

    check_frames(settings.perception, [&video])?;
    let models = resolve_models(settings.perception, [video.scenario], &settings.models)?;
    let spec = VideoSpec::new(&video, settings.perception, settings.dynamics)
        .with_models(models.get(&video.scenario).cloned());
    let pool = start_pool(1, settings.budgets)?;
    pool.submit(Unit {
        id: 0,
        key: spec.video_id.clone(),
        host: scene_host_spec(&spec),
        source,
        budgets: sandbox_budgets(settings.budgets),
    })
    .internal()?;
    let result = pool.recv().ok_or_else(|| AppError {
        class: super::ErrorClass::Internal,
        error: anyhow::anyhow!("the sandbox pool returned no result"),
    })?;
    let executed = outcome_from(&result);
    let (value, answer, correct, error) = match &executed.result {
        Ok(value) => match (interpret(value, option.as_ref()), &question) {
            (Ok(answer), Some(question)) => {
                let correct = is_correct(&answer, &question.answer, option.as_ref());
                (Some(value.clone()), Some(answer), Some(correct), None)
            }
            (Ok(answer), None) => (Some(value.clone()), Some(answer), None, None),
            (Err(error), Some(_)) => (
                Some(value.clone()),
                None,
                Some(false),
                Some(UnitError {
                    stage: Stage::Answer,
                    kind: error.kind().to_string(),
                    message: error.to_string(),
                }),
            ),
            // Without a question there is nothing to answer; the value alone is the result.
            (Err(_), None) => (Some(value.clone()), None, None, None),
        },
        Err(error) => (
            None,
            None,
            question.as_ref().map(|_| false),
            Some(error.clone()),
        ),
    };
    let produced = value.is_some();
    let mut output = json!({
        "value": value,
        "answer": answer,
        "error": error,
        "work": executed.work,
        "printed": result.report.printed,
        "own_ms": executed.own_ms,
        "api_ms": executed.api_ms,
        "wall_ms": executed.wall_ms,
    });
    if let Some(question) = &question {
        output["question_id"] = json!(question.id.0);
        output["option"] = json!(option.as_ref().map(|o| o.letter.to_string()));
        output["gold"] = json!(match &option {
            Some(option) => if option.correct { "yes" } else { "no" }.to_string(),
            None => question.answer.clone(),
        });
        output["correct"] = json!(correct);
    }
    let mut stdout = std::io::stdout().lock();
    let _ = writeln!(
        stdout,
        "{}",
        serde_json::to_string_pretty(&output).unwrap_or_default()
    );
    Ok(if produced {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
