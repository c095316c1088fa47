//! The typed context a template sees, and the per-scenario scene vocabulary it shows.
//!
//! Variables of every template (`UndefinedBehavior::Strict`: any other name is an error):
//!
//! | variable | value |
//! |---|---|
//! | `api_spec` | the text of `api_spec/scene_api.pyi` |
//! | `api_spec_version` | the text of `api_spec/VERSION`, trimmed |
//! | `scenario` | the question's scenario: `rope`, `fluid`, `cloth`, `ball` |
//! | `scenarios` | every scenario in the paper's order, each `{name, objects}` (from the scenario table) |
//! | `colors` | the colour words `find` understands (the release's palette) |
//! | `family` | the question family (`mass`, `rope_counterfactual`, ...) |
//! | `category` | `property`, `counterfactual`, `goal_driven` or `predictive` |
//! | `answer_type` | `open_ended`, `single_choice` or `multiple_choice` |
//! | `mode` | `per_option` or `per_question` |
//! | `unit` | what the program answers: `open` (an open question), `option` (one option, yes/no), `question` (a choice question, letters) |
//! | `question` | the question text without its option lines |
//! | `options` | the options, each `{letter, text}` (empty for open questions) |
//! | `option` | the option of an `option` unit, `{letter, text}`; none otherwise |
//!
//! and the function `example(name)`: the example `api_spec/examples/<name>.py` as the prompt
//! shows it (its `# expected:` line removed).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::dataset::{ChoiceOption, Question};
use crate::perception::palette::color_words;

/// How a choice question becomes programs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PromptMode {
    /// The paper's: one program per "question | option" unit, answering yes or no.
    #[default]
    PerOption,
    /// One program per question, returning the letters of the correct options (`"A C"`).
    PerQuestion,
}

impl PromptMode {
    /// Both modes, the paper's first.
    pub const ALL: [PromptMode; 2] = [PromptMode::PerOption, PromptMode::PerQuestion];

    /// The snake-case name (`per_option`), as templates and JSON see it.
    pub fn as_str(self) -> &'static str {
        match self {
            PromptMode::PerOption => "per_option",
            PromptMode::PerQuestion => "per_question",
        }
    }
}

impl fmt::Display for PromptMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A prompt mode name that is neither.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown prompt mode `{0}`: expected per-option or per-question")]
pub struct UnknownPromptMode(pub String);

/// Accepts `per_option`, `per-option`, `option` and likewise for questions.
impl FromStr for PromptMode {
    type Err = UnknownPromptMode;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text.trim().to_ascii_lowercase().replace('-', "_").as_str() {
            "per_option" | "option" => Ok(PromptMode::PerOption),
            "per_question" | "question" => Ok(PromptMode::PerQuestion),
            _ => Err(UnknownPromptMode(text.to_string())),
        }
    }
}

/// One scenario's name and object words, as the guidelines list them (the scenario's
/// vocabulary, given by the caller from the scenario table).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct SceneWords {
    /// The scenario's name (`rope`).
    pub name: &'static str,
    /// Its object kinds, in the prompt's order.
    pub objects: &'static [&'static str],
}

/// An option as templates see it.
#[derive(Debug, Clone, Serialize)]
pub(crate) struct OptionContext<'a> {
    letter: String,
    text: &'a str,
}

impl<'a> From<&'a ChoiceOption> for OptionContext<'a> {
    fn from(option: &'a ChoiceOption) -> Self {
        OptionContext {
            letter: option.letter.to_string(),
            text: &option.text,
        }
    }
}

/// What one program answers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Unit<'a> {
    /// An open question.
    Open,
    /// One option of a choice question (per-option mode).
    Option(&'a ChoiceOption),
    /// A whole choice question (per-question mode).
    Question,
}

impl Unit<'_> {
    fn name(self) -> &'static str {
        match self {
            Unit::Open => "open",
            Unit::Option(_) => "option",
            Unit::Question => "question",
        }
    }
}

/// The context of one render; the field names are the template variables.
#[derive(Debug, Clone, Serialize)]
pub(crate) struct PromptContext<'a> {
    api_spec: &'a str,
    api_spec_version: &'a str,
    scenario: &'static str,
    scenarios: &'a [SceneWords],
    colors: &'static [&'static str],
    family: &'a str,
    category: &'static str,
    answer_type: &'static str,
    mode: &'static str,
    unit: &'static str,
    question: &'a str,
    options: Vec<OptionContext<'a>>,
    option: Option<OptionContext<'a>>,
}

impl<'a> PromptContext<'a> {
    /// The context for `unit` of `question`; `scenes` are every scenario's words.
    pub(crate) fn new(
        question: &'a Question,
        unit: Unit<'a>,
        mode: PromptMode,
        (api_spec, api_spec_version): (&'a str, &'a str),
        scenes: &'a [SceneWords],
    ) -> Self {
        PromptContext {
            api_spec,
            api_spec_version,
            scenario: question.scenario.name(),
            scenarios: scenes,
            colors: color_words(),
            family: &question.family.0,
            category: question.category().name(),
            answer_type: question.answer_type.as_str(),
            mode: mode.as_str(),
            unit: unit.name(),
            question: &question.title,
            options: question.options.iter().map(OptionContext::from).collect(),
            option: match unit {
                Unit::Option(option) => Some(OptionContext::from(option)),
                Unit::Open | Unit::Question => None,
            },
        }
    }
}

/// The unit that `option` and `mode` ask for on `question`, or why they do not fit.
///
/// An open question is one unit in both modes (so its prompt is the same in both); a choice
/// question is one unit per option in per-option mode and one unit in per-question mode.
pub(crate) fn unit_of<'a>(
    question: &'a Question,
    option: Option<&'a ChoiceOption>,
    mode: PromptMode,
) -> Result<Unit<'a>, String> {
    let is_choice = question.answer_type.is_choice();
    match (is_choice, option, mode) {
        (false, None, _) => Ok(Unit::Open),
        (false, Some(option), _) => Err(format!(
            "option `{}` was given, but the question is open-ended",
            option.letter
        )),
        (true, Some(option), PromptMode::PerOption) => {
            if question.options.iter().any(|o| o == option) {
                Ok(Unit::Option(option))
            } else {
                Err(format!(
                    "option `{}. {}` is not one of the question's options",
                    option.letter, option.text
                ))
            }
        }
        (true, None, PromptMode::PerOption) => {
            Err("a choice question in per-option mode needs the option of the unit".to_string())
        }
        (true, None, PromptMode::PerQuestion) => Ok(Unit::Question),
        (true, Some(option), PromptMode::PerQuestion) => Err(format!(
            "option `{}` was given, but per-question mode asks for the whole question",
            option.letter
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_parse_from_their_names() {
        let cases = [
            ("per_option", Ok(PromptMode::PerOption)),
            ("per-option", Ok(PromptMode::PerOption)),
            ("Per-Question", Ok(PromptMode::PerQuestion)),
            ("question", Ok(PromptMode::PerQuestion)),
            ("both", Err(UnknownPromptMode("both".to_string()))),
        ];
        for (text, expected) in cases {
            assert_eq!(text.parse::<PromptMode>(), expected, "{text}");
        }
        for mode in PromptMode::ALL {
            assert_eq!(mode.as_str().parse::<PromptMode>(), Ok(mode));
            assert_eq!(
                serde_json::to_value(mode).unwrap(),
                serde_json::json!(mode.as_str())
            );
        }
    }
}
