//! `render`: prints the exact prompt one unit of work sends to the model, so a prompt can be read
//! and debugged without a key or a network.
//!
//! Input: a data root (or explicit question files), a question id, and an option letter
//! (per-option mode) or `--per-question`. Output on stdout: the messages as text, or with
//! `--json` the messages plus the template hash and api_spec version that enter cache keys.

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use serde_json::json;

use super::error::{AppError, Classify as _, user_error};
use super::settings::RenderSettings;
use crate::dataset::{DataRoot, Question, Split, load_question_file, sampled_file_path};
use crate::prompt::PromptMode;
use crate::scenarios;

pub(crate) fn render(settings: &RenderSettings) -> Result<ExitCode, AppError> {
    let files = question_files(settings)?;
    let mut seen = 0_usize;
    let mut example_ids = Vec::new();
    let mut found: Option<Question> = None;
    for (path, scenario) in &files {
        let source = load_question_file(path, *scenario, scenarios::families()).user()?;
        seen += source.questions.len();
        for question in source.questions {
            if question.id.0 == settings.question_id {
                found = Some(question);
                break;
            }
            if example_ids.len() < 3 {
                example_ids.push(question.id.0.clone());
            }
        }
        if found.is_some() {
            break;
        }
    }
    let Some(question) = found else {
        return Err(user_error(format!(
            "no question `{}` among the {seen} questions of {} file(s) under `{}`{}",
            settings.question_id,
            files.len(),
            settings.data.display(),
            if example_ids.is_empty() {
                String::new()
            } else {
                format!(" (ids look like: {})", example_ids.join(", "))
            }
        )));
    };

    let choice = question.answer_type.is_choice();
    let option = match (settings.option, choice) {
        (Some(letter), true) => {
            let letter = letter.to_ascii_uppercase();
            let option = question.options.iter().find(|o| o.letter == letter);
            Some(option.ok_or_else(|| {
                let letters = option_letters(&question);
                user_error(format!(
                    "question `{}` has no option {letter} (its options: {letters})",
                    question.id.0
                ))
            })?)
        }
        (Some(_), false) => {
            return Err(user_error(format!(
                "question `{}` is open-ended: it has no options; drop --option",
                question.id.0
            )));
        }
        (None, true) if !settings.per_question => {
            let letters = option_letters(&question);
            return Err(user_error(format!(
                "question `{}` is multiple choice: pick an option with --option (one of {letters}) or pass --per-question",
                question.id.0
            )));
        }
        (None, _) => None,
    };
    let mode = if settings.per_question {
        PromptMode::PerQuestion
    } else {
        PromptMode::PerOption
    };
    let prompts = scenarios::prompts().internal()?;
    let rendered = prompts.render(&question, option, mode).user()?;
    let mut stdout = std::io::stdout().lock();
    if settings.json {
        let value = json!({
            "question_id": question.id.0,
            "option": option.map(|o| o.letter.to_string()),
            "mode": mode.as_str(),
            "messages": rendered.messages(),
            "template_hash": rendered.template_hash,
            "api_spec_version": rendered.api_spec_version,
        });
        let text = serde_json::to_string_pretty(&value).internal()?;
        let _ = writeln!(stdout, "{text}");
    } else {
        for message in rendered.messages() {
            let _ = writeln!(stdout, "===== {} =====", message.role);
            let _ = writeln!(stdout, "{}", message.content);
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// The files to search: `--questions`, or every sampled split file and per-video question file
/// under the data root, in a fixed order.
fn question_files(
    settings: &RenderSettings,
) -> Result<Vec<(PathBuf, Option<crate::dataset::Scenario>)>, AppError> {
    if !settings.questions.is_empty() {
        return Ok(settings
            .questions
            .iter()
            .map(|p| (p.clone(), None))
            .collect());
    }
    let root = DataRoot::open(&settings.data).user()?;
    let mut files = Vec::new();
    for scenario in root.scenarios() {
        for split in Split::ALL {
            let path = sampled_file_path(&root, scenario, split);
            if path.is_file() {
                files.push((path, Some(scenario)));
            }
        }
        let mut per_video: Vec<PathBuf> = fs_err::read_dir(root.scenario_dir(scenario))
            .user()?
            .filter_map(Result::ok)
            .map(|entry| entry.path())
            .filter(|path| path.is_file() && path.extension().is_some_and(|e| e == "json"))
            .collect();
        per_video.sort();
        files.extend(per_video.into_iter().map(|path| (path, Some(scenario))));
    }
    if files.is_empty() {
        return Err(user_error(format!(
            "no question files under `{}`; pass --questions FILE",
            settings.data.display()
        )));
    }
    Ok(files)
}

/// `A, B, C`: the option letters of a choice question.
fn option_letters(question: &Question) -> String {
    question
        .options
        .iter()
        .map(|o| o.letter.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
