//! Questions: the on-disk record of the question engine and its typed, validated form.
//!
//! A record (`docs/data/questions.md`) keeps choice options inside the question text
//! (`"title\nA. …\nB. …"`) and the answer as sorted letters (`"A C"`). [`Question`] splits that
//! into a title and [`ChoiceOption`]s with their gold truth, which is what per-option scoring
//! needs.

use std::fmt;

use indexmap::IndexMap;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::Scenario;

/// A question id: the sampler's global 5-digit id, or `<video>/<family>/<index>` for questions
/// read from a per-video engine file.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct QuestionId(pub String);

/// A video id: the name of the video's folder under `DATA/<scenario folder>/`.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct VideoId(pub String);

impl fmt::Display for QuestionId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl fmt::Display for VideoId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl VideoId {
    /// Sort key that orders numeric ids numerically (`2` before `10`), as the public split does.
    pub fn sort_key(&self) -> (u8, u64, &str) {
        match self.0.parse::<u64>() {
            Ok(number) => (0, number, ""),
            Err(_) => (1, 0, self.0.as_str()),
        }
    }
}

/// A question family key (`mass`, `rope_counterfactual`, ...), as written by the engine.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Family(pub String);

impl Family {
    /// The Table-2 category of this family, by the public sampler's rule: keys containing
    /// `counterfact`, `goal` or `predict` are dynamics questions, everything else is a property.
    pub fn category(&self) -> Category {
        if self.0.contains("counterfact") {
            Category::Counterfactual
        } else if self.0.contains("goal") {
            Category::GoalDriven
        } else if self.0.contains("predict") {
            Category::Predictive
        } else {
            Category::Property
        }
    }
}

impl fmt::Display for Family {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// The question types of the paper's Table 2.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Category {
    /// Physical-property questions (classification over all answers; reported as "Prop.").
    Property,
    /// Counterfactual dynamics ("C-Opt." / "C-Ques.").
    Counterfactual,
    /// Goal-driven dynamics ("G-Opt." / "G-Ques.").
    GoalDriven,
    /// Predictive dynamics ("P-Opt." / "P-Ques.").
    Predictive,
}

impl Category {
    /// All categories in Table-2 row order.
    pub const ALL: [Category; 4] = [
        Category::Property,
        Category::Counterfactual,
        Category::GoalDriven,
        Category::Predictive,
    ];

    /// The one-letter prefix used in Table 2 (`C` for counterfactual).
    pub fn letter(self) -> &'static str {
        match self {
            Category::Property => "Prop",
            Category::Counterfactual => "C",
            Category::GoalDriven => "G",
            Category::Predictive => "P",
        }
    }

    /// The snake-case name used in JSON output.
    pub fn name(self) -> &'static str {
        match self {
            Category::Property => "property",
            Category::Counterfactual => "counterfactual",
            Category::GoalDriven => "goal_driven",
            Category::Predictive => "predictive",
        }
    }
}

/// How a question is answered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AnswerType {
    /// A free answer: yes/no/can not answer, or a count.
    OpenEnded,
    /// Options, exactly one correct.
    SingleChoice,
    /// Options, any subset correct.
    MultipleChoice,
}

impl AnswerType {
    /// Whether the question carries lettered options.
    pub fn is_choice(self) -> bool {
        !matches!(self, AnswerType::OpenEnded)
    }

    fn parse(text: &str) -> Option<AnswerType> {
        match text {
            "open_ended" => Some(AnswerType::OpenEnded),
            "single_choice" => Some(AnswerType::SingleChoice),
            "multiple_choice" => Some(AnswerType::MultipleChoice),
            _ => None,
        }
    }

    /// The record spelling (`open_ended`).
    pub fn as_str(self) -> &'static str {
        match self {
            AnswerType::OpenEnded => "open_ended",
            AnswerType::SingleChoice => "single_choice",
            AnswerType::MultipleChoice => "multiple_choice",
        }
    }
}

/// A dataset split, assigned per video.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Split {
    /// The first half of the videos.
    Train,
    /// The next 20%.
    Val,
    /// The last 30%.
    Test,
}

impl Split {
    /// All splits in file order.
    pub const ALL: [Split; 3] = [Split::Train, Split::Val, Split::Test];

    /// The record spelling (`test`).
    pub fn as_str(self) -> &'static str {
        match self {
            Split::Train => "train",
            Split::Val => "val",
            Split::Test => "test",
        }
    }

    /// Parses the record spelling.
    pub fn parse(text: &str) -> Option<Split> {
        Split::ALL.into_iter().find(|s| s.as_str() == text)
    }
}

/// One question record as the engine writes it (`docs/data/questions.md`, record fields), with the
/// sampler's fields (`docs/data/questions.md`, sampler and split) when present. Unknown fields are
/// kept, so a file round-trips unchanged.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct QuestionRecord {
    /// The question text; choice options follow as `\nA. …` lines.
    pub question: String,
    /// Open-ended: the answer text; choice: sorted letters joined by single spaces.
    pub answer: String,
    /// The family key.
    pub question_family: String,
    /// Open-ended: `[answer]`; choice: the texts of the correct options.
    #[serde(default)]
    pub positive: Vec<String>,
    /// Choice: the texts of the wrong options.
    #[serde(default)]
    pub negative: Vec<String>,
    /// The engine's symbolic program ("feature") for the question.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program: Option<Value>,
    /// `open_ended`, `single_choice` or `multiple_choice`.
    pub answer_type: String,
    /// Sampler: the family key again.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub qtype: Option<String>,
    /// Sampler: the video folder name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub video_id: Option<String>,
    /// Sampler: the global 5-digit id.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub question_id: Option<String>,
    /// Sampler: `train`, `val` or `test`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<String>,
    /// Any other fields, kept in file order.
    #[serde(flatten)]
    pub extra: IndexMap<String, Value>,
}

impl QuestionRecord {
    /// A record with the four required fields and nothing else.
    pub fn new(question: &str, answer: &str, family: &str, answer_type: &str) -> QuestionRecord {
        QuestionRecord {
            question: question.to_string(),
            answer: answer.to_string(),
            question_family: family.to_string(),
            positive: Vec::new(),
            negative: Vec::new(),
            program: None,
            answer_type: answer_type.to_string(),
            qtype: None,
            video_id: None,
            question_id: None,
            split: None,
            extra: IndexMap::new(),
        }
    }
}

/// Why a question record is not a valid question; the caller adds the file and question id.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum QuestionError {
    /// `answer_type` is none of the three.
    #[error("unknown answer_type `{0}` (expected open_ended, single_choice or multiple_choice)")]
    AnswerType(String),
    /// `split` is none of the three.
    #[error("unknown split `{0}` (expected train, val or test)")]
    Split(String),
    /// The text before the option lines is empty.
    #[error("the question text is empty")]
    EmptyQuestion,
    /// An open question without an answer.
    #[error("the answer is empty")]
    EmptyAnswer,
    /// A single-choice answer names no option or several.
    #[error("single_choice answer `{0}` must name exactly one option")]
    NotSingle(String),
    /// An option line is not `A. text`.
    #[error("option line `{0}` does not start with a letter and `. `")]
    OptionLine(String),
    /// Option letters are not `A`, `B`, … in order.
    #[error("option `{found}` is out of order (expected `{expected}`)")]
    OptionOrder {
        /// The letter found.
        found: char,
        /// The letter expected there.
        expected: char,
    },
    /// A choice question without options.
    #[error("a choice question has no `A. …` option lines")]
    NoOptions,
    /// The answer is not letters separated by spaces.
    #[error("answer `{0}` must be option letters separated by spaces")]
    AnswerLetters(String),
    /// The answer names a letter no option has.
    #[error("answer `{answer}` names option `{letter}`, which does not exist")]
    UnknownLetter {
        /// The answer.
        answer: String,
        /// The letter.
        letter: char,
    },
    /// Two questions of one file share an id.
    #[error("the id appears more than once")]
    DuplicateId,
    /// The answer names a letter twice.
    #[error("answer `{answer}` repeats option `{letter}`")]
    RepeatedLetter {
        /// The answer.
        answer: String,
        /// The letter.
        letter: char,
    },
}

/// One lettered option of a choice question.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ChoiceOption {
    /// `A`, `B`, ...
    pub letter: char,
    /// The option text without the `"A. "` prefix.
    pub text: String,
    /// Whether the gold answer marks this option correct.
    pub correct: bool,
}

/// A validated question, ready to be turned into units of work.
#[derive(Debug, Clone, PartialEq)]
pub struct Question {
    /// Unique within a run.
    pub id: QuestionId,
    /// The video it is about.
    pub video_id: VideoId,
    /// The scenario of that video.
    pub scenario: Scenario,
    /// The family key.
    pub family: Family,
    /// Open-ended or choice.
    pub answer_type: AnswerType,
    /// The question text without the option lines.
    pub title: String,
    /// The options (empty for open-ended questions).
    pub options: Vec<ChoiceOption>,
    /// The gold answer: normalised text for open-ended questions, sorted letters for choices.
    pub answer: String,
    /// The split, when the record carries one.
    pub split: Option<Split>,
    /// The record as read.
    pub record: QuestionRecord,
}

impl Question {
    /// Validates a record and splits it into title, options and gold truth.
    ///
    pub fn from_record(
        id: QuestionId,
        video_id: VideoId,
        scenario: Scenario,
        record: QuestionRecord,
    ) -> Result<Question, QuestionError> {
        let answer_type = AnswerType::parse(&record.answer_type)
            .ok_or_else(|| QuestionError::AnswerType(record.answer_type.clone()))?;
        let split = match record.split.as_deref() {
            None => None,
            Some(text) => {
                Some(Split::parse(text).ok_or_else(|| QuestionError::Split(text.to_string()))?)
            }
        };
        let mut lines = record.question.split('\n');
        let title = lines.next().unwrap_or_default().trim().to_string();
        if title.is_empty() {
            return Err(QuestionError::EmptyQuestion);
        }
        let (options, answer) = if answer_type.is_choice() {
            let options = parse_options(lines)?;
            let letters = parse_answer_letters(&record.answer, &options)?;
            let options: Vec<ChoiceOption> = options
                .into_iter()
                .map(|(letter, text)| ChoiceOption {
                    letter,
                    text,
                    correct: letters.contains(&letter),
                })
                .collect();
            if answer_type == AnswerType::SingleChoice && letters.len() != 1 {
                return Err(QuestionError::NotSingle(record.answer.clone()));
            }
            let answer = letters
                .iter()
                .map(char::to_string)
                .collect::<Vec<_>>()
                .join(" ");
            (options, answer)
        } else {
            let answer = normalize_open_answer(&record.answer);
            if answer.is_empty() {
                return Err(QuestionError::EmptyAnswer);
            }
            (Vec::new(), answer)
        };
        Ok(Question {
            id,
            video_id,
            scenario,
            family: Family(record.question_family.clone()),
            answer_type,
            title,
            options,
            answer,
            split,
            record,
        })
    }

    /// The Table-2 category of the question's family.
    pub fn category(&self) -> Category {
        self.family.category()
    }

    /// The units of work of this question: one for an open-ended question, one per option for a
    /// choice question (the paper's "question | option" pairs). Ids are `<question>` and
    /// `<question>:<letter>`.
    pub fn units(&self) -> Vec<(String, Option<&ChoiceOption>)> {
        if self.options.is_empty() {
            vec![(self.id.0.clone(), None)]
        } else {
            self.options
                .iter()
                .map(|o| (format!("{}:{}", self.id.0, o.letter), Some(o)))
                .collect()
        }
    }

    /// The option with `letter`, if any.
    pub fn option(&self, letter: char) -> Option<&ChoiceOption> {
        self.options.iter().find(|o| o.letter == letter)
    }
}

/// Open-ended answers compare case- and space-insensitively (`"Yes "` = `"yes"`).
pub(crate) fn normalize_open_answer(text: &str) -> String {
    text.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_lowercase()
}

fn parse_options<'a>(
    lines: impl Iterator<Item = &'a str>,
) -> Result<Vec<(char, String)>, QuestionError> {
    let mut options = Vec::new();
    for line in lines {
        let line = line.trim_end();
        if line.trim().is_empty() {
            continue;
        }
        let mut chars = line.chars();
        let (Some(letter), Some('.'), Some(' ')) = (chars.next(), chars.next(), chars.next())
        else {
            return Err(QuestionError::OptionLine(line.to_string()));
        };
        let expected = char::from(b'A' + u8::try_from(options.len()).unwrap_or(u8::MAX).min(25));
        if letter != expected {
            return Err(QuestionError::OptionOrder {
                found: letter,
                expected,
            });
        }
        options.push((letter, chars.as_str().trim().to_string()));
    }
    if options.is_empty() {
        return Err(QuestionError::NoOptions);
    }
    Ok(options)
}

fn parse_answer_letters(
    answer: &str,
    options: &[(char, String)],
) -> Result<Vec<char>, QuestionError> {
    let mut letters = Vec::new();
    for token in answer.split_whitespace() {
        let mut chars = token.chars();
        let (Some(letter), None) = (chars.next(), chars.next()) else {
            return Err(QuestionError::AnswerLetters(answer.to_string()));
        };
        if !options.iter().any(|(l, _)| *l == letter) {
            return Err(QuestionError::UnknownLetter {
                answer: answer.to_string(),
                letter,
            });
        }
        if letters.contains(&letter) {
            return Err(QuestionError::RepeatedLetter {
                answer: answer.to_string(),
                letter,
            });
        }
        letters.push(letter);
    }
    letters.sort_unstable();
    Ok(letters)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(question: &str, answer: &str, family: &str, answer_type: &str) -> QuestionRecord {
        QuestionRecord::new(question, answer, family, answer_type)
    }

    fn parse(record: QuestionRecord) -> Result<Question, QuestionError> {
        Question::from_record(
            QuestionId("q".into()),
            VideoId("0".into()),
            Scenario::Rope,
            record,
        )
    }

    #[test]
    fn choice_question_splits_options_and_marks_gold() {
        let q = parse(record(
            "If we want the purple cube to move down, what can we do?\nA. Decrease the mass of the green cube\nB. Increase the mass of the purple cube\nC. Decrease the mass of the purple cube",
            "B A",
            "rope_goaldriven",
            "multiple_choice",
        ))
        .unwrap();
        assert_eq!(
            q.title,
            "If we want the purple cube to move down, what can we do?"
        );
        assert_eq!(q.answer, "A B");
        let truth: Vec<(char, bool)> = q.options.iter().map(|o| (o.letter, o.correct)).collect();
        assert_eq!(truth, vec![('A', true), ('B', true), ('C', false)]);
        assert_eq!(q.options[2].text, "Decrease the mass of the purple cube");
        assert_eq!(q.category(), Category::GoalDriven);
    }

    #[test]
    fn malformed_records_are_rejected_with_reasons() {
        let cases = [
            (
                record(
                    "Q?\nA. x\nB. y",
                    "C",
                    "rope_counterfactual",
                    "multiple_choice",
                ),
                "names option `C`",
            ),
            (
                record(
                    "Q?\nA. x\nC. y",
                    "A",
                    "rope_counterfactual",
                    "multiple_choice",
                ),
                "out of order",
            ),
            (
                record("Q?", "A", "rope_counterfactual", "multiple_choice"),
                "no `A. …` option",
            ),
            (
                record("Q?\nA. x", "AB", "rope_counterfactual", "multiple_choice"),
                "option letters",
            ),
            (record("Q?", "", "mass", "open_ended"), "answer is empty"),
            (
                record("Q?", "yes", "mass", "free_text"),
                "unknown answer_type",
            ),
            (
                record("\nA. x", "A", "x", "multiple_choice"),
                "question text is empty",
            ),
        ];
        for (record, expected) in cases {
            let error = parse(record).unwrap_err().to_string();
            assert!(
                error.contains(expected),
                "`{error}` does not contain `{expected}`"
            );
        }
    }

    #[test]
    fn categories_follow_the_public_sampler_rule() {
        let cases = [
            ("mass", Category::Property),
            ("existence", Category::Property),
            ("rope_counterfactual2", Category::Counterfactual),
            ("rope_goaldriven", Category::GoalDriven),
            ("fluid_predictive_container", Category::Predictive),
        ];
        for (family, category) in cases {
            assert_eq!(Family(family.to_string()).category(), category, "{family}");
        }
    }

    #[test]
    fn open_answers_are_normalised() {
        let q = parse(record("Is it?", " Can  not Answer ", "mass", "open_ended")).unwrap();
        assert_eq!(q.answer, "can not answer");
        assert!(q.options.is_empty());
    }
}
