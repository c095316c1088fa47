//! The built-in program writer: turns each question (and each option of a choice question,
//! "question | option") into a Python program against the scene API.
//!
//! It stands in for the LLM of ContPRO when no model is given, so runs are deterministic and
//! offline. Each scenario brings a [`Writer`] (`builtin/<scenario>.rs`) that parses its question
//! templates and writes the kind of program the paper's listings show (`eg1`): find the objects,
//! query or simulate, compare. This module assembles the programs: a header comment, the
//! `execute_command(video)` function opening the scene, and in per-question mode one function per
//! option. The programs are real Python that goes through the sandbox; nothing is answered here.

pub mod ball;
pub mod cloth;
pub mod fluid;
pub mod rope;

use std::fmt::Write as _;

use crate::dataset::{ChoiceOption, Question, Scenario};

/// Why the writer cannot produce a program for a question.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum WriterError {
    /// The question's text matches none of the templates the writer knows.
    #[error("the builtin writer does not recognise the {what} `{text}`")]
    Unrecognised {
        /// `question`, `option`.
        what: &'static str,
        /// The text.
        text: String,
    },
    /// The scenario has no writer yet.
    #[error("the builtin writer has no programs for {0} questions yet")]
    Scenario(Scenario),
}

/// The error for a question or option text no template matches.
pub(crate) fn unrecognised(what: &'static str, text: &str) -> WriterError {
    WriterError::Unrecognised {
        what,
        text: text.to_string(),
    }
}

/// One scenario's part of the writer: the bodies of its programs. The body runs inside
/// `execute_command(video)` after `<scenario>_scene = SoftScene(video, '<scenario>')` and ends
/// with a `return`.
#[derive(Debug, Clone, Copy)]
pub struct Writer {
    /// Version of the scenario's writer, part of the cache key of its programs; change it when
    /// the programs it writes change.
    pub version: &'static str,
    /// The body for an open question, from its title.
    pub open_body: fn(&str) -> Result<String, WriterError>,
    /// The body for one option of a choice question, from the title and the option's text;
    /// returns `"yes"` when the option holds.
    pub option_body: fn(&str, &str) -> Result<String, WriterError>,
}

/// Writes the program for `question`, or for one of its options, with `writer` (the question's
/// scenario's).
pub fn write_program(
    question: &Question,
    option: Option<&ChoiceOption>,
    writer: &Writer,
) -> Result<String, WriterError> {
    let title = question.title.as_str();
    let body = match option {
        None => (writer.open_body)(title)?,
        Some(option) => (writer.option_body)(title, &option.text)?,
    };
    let mut program = String::new();
    let header = match option {
        None => title.to_string(),
        Some(option) => format!("{title} | {}", option.text),
    };
    // The header is a comment: strip line breaks so data cannot escape it.
    let _ = writeln!(program, "# {}", header.replace(['\n', '\r'], " "));
    program.push_str("\ndef execute_command(video):\n");
    program.push_str(&scene_line(question.scenario));
    program.push_str(&body);
    Ok(program)
}

/// Writes one program for a whole choice question (the `--per-question` mode): it checks every
/// option with that option's program and returns the letters of those that hold (`"A C"`).
/// Open-ended questions get their usual program.
pub fn write_question_program(question: &Question, writer: &Writer) -> Result<String, WriterError> {
    if question.options.is_empty() {
        return write_program(question, None, writer);
    }
    let title = question.title.as_str();
    let mut program = String::new();
    let _ = writeln!(program, "# {}", title.replace(['\n', '\r'], " "));
    for option in &question.options {
        let _ = writeln!(
            program,
            "\n# {}. {}",
            option.letter,
            option.text.replace(['\n', '\r'], " ")
        );
        let _ = writeln!(
            program,
            "def option_{}(video):",
            option.letter.to_ascii_lowercase()
        );
        program.push_str(&scene_line(question.scenario));
        program.push_str(&(writer.option_body)(title, &option.text)?);
    }
    program.push_str("\ndef execute_command(video):\n    chosen = []\n");
    for option in &question.options {
        let _ = writeln!(
            program,
            "    if option_{}(video) == \"yes\":\n        chosen.append(\"{}\")",
            option.letter.to_ascii_lowercase(),
            option.letter
        );
    }
    program.push_str("    return \" \".join(chosen)\n");
    Ok(program)
}

/// The line that opens the scene: `    rope_scene = SoftScene(video, 'rope')`.
fn scene_line(scenario: Scenario) -> String {
    let name = scenario.name();
    format!("    {name}_scene = SoftScene(video, '{name}')\n")
}

/// A Python string literal for `text` (escaped, so question text cannot inject code).
pub(crate) fn literal(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '"' => out.push_str("\\\""),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04x}", u32::from(c));
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Strips a leading "the " from an object phrase.
pub(crate) fn object_phrase(text: &str) -> &str {
    let text = text.trim();
    text.strip_prefix("the ").unwrap_or(text).trim()
}

/// `text` between `prefix` and `suffix`, trimmed; `None` when it does not have them or nothing
/// is between them.
pub(crate) fn between<'a>(text: &'a str, prefix: &str, suffix: &str) -> Option<&'a str> {
    text.strip_prefix(prefix)?
        .strip_suffix(suffix)
        .map(str::trim)
        .filter(|inside| !inside.is_empty())
}

/// An object phrase with its kind word (`pink` → `pink fluid`; `pink fluid` stays).
pub(crate) fn with_kind(phrase: &str, kind: &str) -> String {
    let phrase = object_phrase(phrase);
    if phrase.ends_with(kind) {
        phrase.to_string()
    } else {
        format!("{phrase} {kind}")
    }
}

/// A question of `scenario` as the writers' tests build it: id `q`, video `0`.
#[cfg(test)]
pub(crate) fn test_question(
    scenario: Scenario,
    text: &str,
    answer: &str,
    family: &str,
    answer_type: &str,
) -> Question {
    let record = crate::dataset::QuestionRecord::new(text, answer, family, answer_type);
    Question::from_record(
        crate::dataset::QuestionId("q".into()),
        crate::dataset::VideoId("0".into()),
        scenario,
        record,
    )
    .expect("a test question is well formed")
}
