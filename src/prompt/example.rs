//! Worked examples (`api_spec/examples/<scenario>/<name>.py`): parsing their header and the text
//! a prompt shows.
//!
//! An example starts with a comment header, as the paper's listings do:
//!
//! ```text
//! # <question>[ | <option>]            the query the program answers
//! # expected: <answer>                 what it returns on the demo video, or
//! # runnable: no (<why>)               for examples of scenarios without a backend
//! # A. <option text>                   per-question examples: the options, one a line
//!
//! def execute_command(video):
//!     ...
//! ```
//!
//! The prompt shows the file without its `expected:`/`runnable:` line: the examples are about
//! another video, so their answers would only mislead.

use serde::Serialize;

use super::error::PromptError;
use crate::dataset::Scenario;

/// What running an example must give.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ExampleCheck {
    /// The answer on the demo rope video (`eval/demo/pulley_group/0`).
    Expected(String),
    /// Not runnable in this version; the reason.
    NotRunnable(String),
}

/// One worked example program.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Example {
    /// Its name: the path under `api_spec/examples/` without `.py` (`rope/mass`).
    pub name: String,
    /// Its path in the prompt set (`api_spec/examples/rope/mass.py`).
    pub path: String,
    /// The scenario it is written for (its folder).
    pub scenario: Scenario,
    /// The question, without the option.
    pub question: String,
    /// The option of an option unit (`question | option`).
    pub option: Option<String>,
    /// The lettered options of a per-question example, `(letter, text)`.
    pub options: Vec<(char, String)>,
    /// What running it must give.
    pub check: ExampleCheck,
    /// The whole file, as the sandbox runs it.
    pub source: String,
    /// The text a prompt shows.
    pub prompt_text: String,
}

impl Example {
    /// Parses the example at `path` (`api_spec/examples/<scenario>/<name>.py`).
    pub(crate) fn parse(path: &str, source: &str) -> Result<Example, PromptError> {
        let problem = |problem: String| PromptError::Spec {
            path: path.to_string(),
            problem,
        };
        let name = path
            .strip_prefix("api_spec/examples/")
            .and_then(|rest| rest.strip_suffix(".py"))
            .ok_or_else(|| {
                problem("an example is `api_spec/examples/<scenario>/<name>.py`".into())
            })?
            .to_string();
        let scenario = name
            .split_once('/')
            .and_then(|(folder, _)| folder.parse::<Scenario>().ok())
            .ok_or_else(|| {
                problem(format!(
                    "examples live in a scenario folder: {}",
                    Scenario::ALL.map(|s| format!("{}/", s.name())).join(", ")
                ))
            })?;
        let header: Vec<&str> = source
            .lines()
            .take_while(|line| line.starts_with('#'))
            .collect();
        let query = header
            .first()
            .map(|line| line.trim_start_matches('#').trim())
            .filter(|query| !query.is_empty())
            .ok_or_else(|| {
                problem("the first line must be a comment holding the question".into())
            })?;
        let (question, option) = match query.split_once(" | ") {
            Some((question, option)) => (question.trim(), Some(option.trim().to_string())),
            None => (query, None),
        };
        let mut check = None;
        let mut check_line = None;
        let mut options = Vec::new();
        for (index, line) in header.iter().enumerate().skip(1) {
            let text = line.trim_start_matches('#').trim();
            if let Some(answer) = text.strip_prefix("expected:") {
                check = Some(ExampleCheck::Expected(answer.trim().to_string()));
                check_line = Some(index);
            } else if let Some(reason) = text.strip_prefix("runnable: no") {
                check = Some(ExampleCheck::NotRunnable(
                    reason
                        .trim()
                        .trim_start_matches('(')
                        .trim_end_matches(')')
                        .to_string(),
                ));
                check_line = Some(index);
            } else if let Some((letter, option_text)) = option_line(text) {
                options.push((letter, option_text.to_string()));
            }
        }
        let (Some(check), Some(check_line)) = (check, check_line) else {
            return Err(problem(
                "the header needs a `# expected: <answer>` or `# runnable: no (<why>)` line".into(),
            ));
        };
        if option.is_some() && !options.is_empty() {
            return Err(problem(
                "an example answers one option (`question | option`) or lists the options, not both"
                    .into(),
            ));
        }
        let prompt_text = source
            .lines()
            .enumerate()
            .filter(|(index, _)| *index != check_line)
            .map(|(_, line)| line)
            .collect::<Vec<_>>()
            .join("\n")
            .trim()
            .to_string();
        if !prompt_text.contains("def execute_command(video)") {
            return Err(problem(
                "an example defines `def execute_command(video):`".into(),
            ));
        }
        Ok(Example {
            name,
            path: path.to_string(),
            scenario,
            question: question.to_string(),
            option,
            options,
            check,
            source: source.to_string(),
            prompt_text,
        })
    }
}

/// `A. text` → `('A', "text")`.
fn option_line(text: &str) -> Option<(char, &str)> {
    let mut chars = text.chars();
    let letter = chars.next().filter(char::is_ascii_uppercase)?;
    let rest = chars.as_str().strip_prefix(". ")?;
    Some((letter, rest.trim()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_parse_into_query_check_and_options() {
        let example = Example::parse(
            "api_spec/examples/rope/x.py",
            "# Q? | Up\n# expected: yes\n\ndef execute_command(video):\n    return 'yes'\n",
        )
        .unwrap();
        assert_eq!(example.name, "rope/x");
        assert_eq!(example.scenario, Scenario::Rope);
        assert_eq!(example.question, "Q?");
        assert_eq!(example.option.as_deref(), Some("Up"));
        assert_eq!(example.check, ExampleCheck::Expected("yes".into()));
        assert_eq!(
            example.prompt_text,
            "# Q? | Up\n\ndef execute_command(video):\n    return 'yes'"
        );
        let example = Example::parse(
            "api_spec/examples/ball/y.py",
            "# Which?\n# runnable: no (no ball backend)\n# A. Left\n# B. Right\n\ndef execute_command(video):\n    pass\n",
        )
        .unwrap();
        assert_eq!(
            example.check,
            ExampleCheck::NotRunnable("no ball backend".into())
        );
        assert_eq!(
            example.options,
            vec![('A', "Left".to_string()), ('B', "Right".to_string())]
        );
        assert!(example.prompt_text.starts_with("# Which?\n# A. Left\n"));
    }

    #[test]
    fn malformed_examples_are_rejected_with_reasons() {
        let cases = [
            (
                "api_spec/examples/x.py",
                "# Q?\n# expected: 1\ndef execute_command(video): pass",
                "scenario folder",
            ),
            (
                "api_spec/examples/rope/x.py",
                "def execute_command(video): pass",
                "first line must be a comment",
            ),
            (
                "api_spec/examples/rope/x.py",
                "# Q?\n\ndef execute_command(video): pass",
                "`# expected: <answer>`",
            ),
            (
                "api_spec/examples/rope/x.py",
                "# Q? | A\n# expected: yes\n# A. a\ndef execute_command(video): pass",
                "not both",
            ),
            (
                "api_spec/examples/rope/x.py",
                "# Q?\n# expected: yes\nanswer = 1",
                "defines `def execute_command",
            ),
        ];
        for (path, source, expected) in cases {
            let error = Example::parse(path, source).unwrap_err().to_string();
            assert!(error.contains(expected), "`{error}` lacks `{expected}`");
        }
    }
}
