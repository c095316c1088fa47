//! Turning generated questions into [`QuestionRecord`]s in the public engine's exact form
//! (`docs/data/questions.md`, record fields): field order `question, answer, question_family,
//! positive, negative, program, answer_type`; options appended as `\nA. …`; answers as sorted
//! letters joined by one space.

use std::collections::BTreeSet;

use indexmap::IndexMap;
use serde_json::{Value, json};

use crate::dataset::QuestionRecord;

/// `answer_type` of open questions (the property families).
const OPEN_ENDED: &str = "open_ended";
/// `answer_type` of choice questions with any number of correct options (the dynamics
/// families, even those whose questions have exactly one correct option).
const MULTIPLE_CHOICE: &str = "multiple_choice";

/// One option of a choice question before it gets its letter.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct DraftOption {
    /// The option text without the `"A. "` prefix.
    pub(crate) text: String,
    /// The option's program triple (`["blue pulley", "rotation", "clockwise"]`).
    pub(crate) program: [String; 3],
    /// Whether the option is true.
    pub(crate) correct: bool,
}

/// Pops a false option with probability |F|/(|F|+|T|), else a true one; `None` when both are
/// empty.
pub(crate) fn draw_weighted(
    true_options: &mut Vec<DraftOption>,
    false_options: &mut Vec<DraftOption>,
    rng: &mut impl rand::Rng,
) -> Option<DraftOption> {
    let total = true_options.len() + false_options.len();
    if total == 0 {
        return None;
    }
    let false_probability = false_options.len() as f64 / total as f64;
    if rng.random::<f64>() < false_probability {
        false_options.pop()
    } else {
        true_options.pop()
    }
}

/// An open-ended record: `positive` is `[answer]`, `negative` is empty.
pub(crate) fn open_ended_record(
    family: &str,
    question: String,
    answer: &str,
    program: &[&str],
) -> QuestionRecord {
    QuestionRecord {
        question,
        answer: answer.to_string(),
        question_family: family.to_string(),
        positive: vec![answer.to_string()],
        negative: Vec::new(),
        program: Some(json!(program)),
        answer_type: OPEN_ENDED.to_string(),
        qtype: None,
        video_id: None,
        question_id: None,
        split: None,
        extra: IndexMap::new(),
    }
}

/// A multiple-choice record with options lettered in the given order. `positive` and `negative`
/// list option texts in letter order; the public engine built `negative` from a Python `set`, so
/// its order was arbitrary (`docs/data/rope.md`, quirks of the public engine), fixed here.
///
/// `None` (the question is dropped) when two options share a text, when no option is true, or
/// when there are more options than letters. The public engine stopped in `breakpoint()` on a
/// repeated option text.
pub(crate) fn choice_record(
    family: &str,
    title: &str,
    question_program: [&str; 3],
    options: &[DraftOption],
) -> Option<QuestionRecord> {
    let mut texts = BTreeSet::new();
    if options.len() > 26
        || !options
            .iter()
            .all(|option| texts.insert(option.text.as_str()))
    {
        return None;
    }
    let mut question = title.to_string();
    let mut letters = Vec::new();
    let mut positive = Vec::new();
    let mut negative = Vec::new();
    let mut choices = serde_json::Map::new();
    for (letter, option) in ('A'..='Z').zip(options) {
        question.push('\n');
        question.push(letter);
        question.push_str(". ");
        question.push_str(&option.text);
        choices.insert(letter.to_string(), json!(option.program));
        if option.correct {
            letters.push(letter.to_string());
            positive.push(option.text.clone());
        } else {
            negative.push(option.text.clone());
        }
    }
    if letters.is_empty() {
        return None;
    }
    Some(QuestionRecord {
        question,
        answer: letters.join(" "),
        question_family: family.to_string(),
        positive,
        negative,
        program: Some(json!({ "question": question_program, "choices": Value::Object(choices) })),
        answer_type: MULTIPLE_CHOICE.to_string(),
        qtype: None,
        video_id: None,
        question_id: None,
        split: None,
        extra: IndexMap::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn option(text: &str, correct: bool) -> DraftOption {
        DraftOption {
            text: text.to_string(),
            program: [text.to_string(), "motion".into(), "up".into()],
            correct,
        }
    }

    #[test]
    fn choice_records_letter_options_and_serialise_in_engine_field_order() {
        let record = choice_record(
            "rope_goaldriven",
            "If we want the purple cube to move up, what can we do?",
            ["purple cube", "motion", "up"],
            &[option("x", false), option("y", true), option("z", true)],
        )
        .unwrap();
        assert_eq!(
            record.question,
            "If we want the purple cube to move up, what can we do?\nA. x\nB. y\nC. z"
        );
        assert_eq!(record.answer, "B C");
        assert_eq!(record.positive, ["y", "z"]);
        assert_eq!(record.negative, ["x"]);
        let text = serde_json::to_string(&record).unwrap();
        assert_eq!(
            text,
            r#"{"question":"If we want the purple cube to move up, what can we do?\nA. x\nB. y\nC. z","answer":"B C","question_family":"rope_goaldriven","positive":["y","z"],"negative":["x"],"program":{"question":["purple cube","motion","up"],"choices":{"A":["x","motion","up"],"B":["y","motion","up"],"C":["z","motion","up"]}},"answer_type":"multiple_choice"}"#
        );
    }

    #[test]
    fn unsound_choice_questions_are_dropped() {
        let cases = [
            vec![option("x", true), option("x", false), option("y", false)],
            vec![option("x", false), option("y", false), option("z", false)],
        ];
        for options in cases {
            assert!(
                choice_record("f", "t", ["a", "b", "c"], &options).is_none(),
                "{options:?}"
            );
        }
    }

    #[test]
    fn open_ended_records_carry_their_answer_as_positive() {
        let record = open_ended_record(
            "color",
            "How many red objects are there in the video?".into(),
            "0",
            &["red"],
        );
        let text = serde_json::to_string(&record).unwrap();
        assert_eq!(
            text,
            r#"{"question":"How many red objects are there in the video?","answer":"0","question_family":"color","positive":["0"],"negative":[],"program":["red"],"answer_type":"open_ended"}"#
        );
    }
}
