//! Answers: turns a program's value into the answer of its unit and judges it against the gold.
//!
//! Input: the program's value in its JSON form (the sandbox converts Python values: `None` →
//! null, `bool`, `int`, `float`, `str`, lists; other objects as `{"type": …, "repr": …}`), and
//! the unit (question, option). Output: a normalised answer text, or an [`AnswerError`] (the unit
//! then fails at stage `answer`).
//!
//! * An option unit asks "is this option right?": `True`/`"yes"` → `yes`, `False`/`"no"` → `no`.
//! * An open-ended unit's answer is compared as text after normalisation: booleans → yes/no,
//!   integral numbers → digits (`3.0` → `3`), strings lower-cased with spaces collapsed and a
//!   final period dropped, `cannot answer` → `can not answer`.

use serde_json::Value;

use crate::dataset::ChoiceOption;

/// Why a value is not an answer.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AnswerError {
    /// An option unit's value is not a yes/no.
    #[error("an option's program must return yes/no (or True/False), got {0}")]
    NotYesNo(String),
    /// The program returned `None`.
    #[error("the program returned None")]
    NoneValue,
    /// A per-question program for a choice question did not return option letters.
    #[error(
        "a choice question's program must return the letters of the correct options (e.g. \"A C\"), got {0}"
    )]
    NotLetters(String),
    /// A value that cannot be an answer (a list, an object...).
    #[error("the program returned {0}, which is not an answer (expected text, a number or yes/no)")]
    NotAnAnswer(String),
}

impl AnswerError {
    /// A short stable kind for reports.
    pub fn kind(&self) -> &'static str {
        match self {
            AnswerError::NotYesNo(_) => "not_yes_no",
            AnswerError::NotLetters(_) => "not_letters",
            AnswerError::NoneValue => "none",
            AnswerError::NotAnAnswer(_) => "not_an_answer",
        }
    }
}

/// A short description of a value for error messages (truncated).
fn describe(value: &Value) -> String {
    let text = value.to_string();
    if text.chars().count() > 80 {
        let cut: String = text.chars().take(77).collect();
        format!("{cut}...")
    } else {
        text
    }
}

/// Normalises open-ended answer text: lower case, single spaces, no final period.
pub fn normalize_text(text: &str) -> String {
    let collapsed = text
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_lowercase();
    let trimmed = collapsed.trim_end_matches('.').trim().to_string();
    match trimmed.as_str() {
        "true" => "yes".to_string(),
        "false" => "no".to_string(),
        "cannot answer" | "can't answer" | "can not be answered" | "cannot be answered" => {
            "can not answer".to_string()
        }
        _ => trimmed,
    }
}

/// The answer text of a unit: `yes`/`no` for an option unit, the normalised answer otherwise.
pub fn interpret(value: &Value, option: Option<&ChoiceOption>) -> Result<String, AnswerError> {
    if option.is_some() {
        let text = match value {
            Value::Bool(true) => "yes".to_string(),
            Value::Bool(false) => "no".to_string(),
            Value::String(text) => normalize_text(text),
            Value::Null => return Err(AnswerError::NoneValue),
            other => return Err(AnswerError::NotYesNo(describe(other))),
        };
        return match text.as_str() {
            "yes" | "no" => Ok(text),
            _ => Err(AnswerError::NotYesNo(describe(value))),
        };
    }
    match value {
        Value::Null => Err(AnswerError::NoneValue),
        Value::Bool(flag) => Ok(if *flag { "yes" } else { "no" }.to_string()),
        Value::Number(number) => Ok(number_text(number)),
        Value::String(text) => Ok(normalize_text(text)),
        other => Err(AnswerError::NotAnAnswer(describe(other))),
    }
}

fn number_text(number: &serde_json::Number) -> String {
    if let Some(integer) = number.as_i64() {
        return integer.to_string();
    }
    match number.as_f64() {
        Some(float) if float.fract() == 0.0 && float.abs() < 1e15 => format!("{float:.0}"),
        Some(float) => float.to_string(),
        None => number.to_string(),
    }
}

/// The option letters a per-question program chose: `"A C"`, `"A, C"`, `"AC"`, `["A", "C"]` or
/// `"none"` (no option). Letters must name existing options.
pub fn interpret_letters(value: &Value, letters: &[char]) -> Result<Vec<char>, AnswerError> {
    let bad = || AnswerError::NotLetters(describe(value));
    let mut chosen = Vec::new();
    let mut push = |text: &str| -> Result<(), AnswerError> {
        for token in text
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|t| !t.is_empty())
        {
            let token = token.trim_end_matches(['.', ')']);
            if token.eq_ignore_ascii_case("none") {
                continue;
            }
            // "AC" is two letters; any other character makes the value not a letter list.
            for c in token.chars() {
                let upper = c.to_ascii_uppercase();
                if !letters.contains(&upper) {
                    return Err(bad());
                }
                if !chosen.contains(&upper) {
                    chosen.push(upper);
                }
            }
        }
        Ok(())
    };
    match value {
        Value::String(text) => push(text)?,
        Value::Array(items) => {
            for item in items {
                match item {
                    Value::String(text) => push(text)?,
                    _ => return Err(bad()),
                }
            }
        }
        Value::Null => return Err(AnswerError::NoneValue),
        _ => return Err(bad()),
    }
    chosen.sort_unstable();
    Ok(chosen)
}

/// Whether a unit's answer is right: for an option, its yes/no matches the option's gold truth;
/// otherwise the text equals the gold answer.
pub fn is_correct(answer: &str, gold_answer: &str, option: Option<&ChoiceOption>) -> bool {
    match option {
        Some(option) => (answer == "yes") == option.correct,
        None => answer == gold_answer,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn open_ended_values_normalise() {
        let cases = [
            (json!(true), "yes"),
            (json!(false), "no"),
            (json!(3), "3"),
            (json!(3.0), "3"),
            (json!(0.5), "0.5"),
            (json!(" Can not  answer. "), "can not answer"),
            (json!("Cannot answer"), "can not answer"),
            (json!("YES"), "yes"),
            (json!("True"), "yes"),
        ];
        for (value, expected) in cases {
            assert_eq!(interpret(&value, None).unwrap(), expected, "{value}");
        }
        assert_eq!(
            interpret(&json!(null), None).unwrap_err(),
            AnswerError::NoneValue
        );
        assert_eq!(
            interpret(&json!([1, 2]), None).unwrap_err().kind(),
            "not_an_answer"
        );
    }

    #[test]
    fn per_question_letters_parse() {
        let letters = ['A', 'B', 'C', 'D'];
        let cases = [
            (json!("A C"), vec!['A', 'C']),
            (json!("c, a"), vec!['A', 'C']),
            (json!("BD"), vec!['B', 'D']),
            (json!(["D", "A"]), vec!['A', 'D']),
            (json!("none"), vec![]),
            (json!("A."), vec!['A']),
        ];
        for (value, expected) in cases {
            assert_eq!(
                interpret_letters(&value, &letters).unwrap(),
                expected,
                "{value}"
            );
        }
        for bad in [json!("E"), json!("yes"), json!(3), json!(["A", 1])] {
            assert_eq!(
                interpret_letters(&bad, &letters).unwrap_err().kind(),
                "not_letters",
                "{bad}"
            );
        }
    }

    #[test]
    fn option_values_must_be_yes_or_no() {
        let option = ChoiceOption {
            letter: 'A',
            text: "Up".into(),
            correct: true,
        };
        assert_eq!(interpret(&json!(true), Some(&option)).unwrap(), "yes");
        assert_eq!(interpret(&json!("no"), Some(&option)).unwrap(), "no");
        assert_eq!(
            interpret(&json!("maybe"), Some(&option))
                .unwrap_err()
                .kind(),
            "not_yes_no"
        );
        assert_eq!(
            interpret(&json!(1), Some(&option)).unwrap_err().kind(),
            "not_yes_no"
        );
        assert!(is_correct("yes", "", Some(&option)));
        assert!(!is_correct("no", "", Some(&option)));
        assert!(is_correct("3", "3", None));
        assert!(!is_correct("4", "3", None));
    }
}
