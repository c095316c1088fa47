//! Code extraction: the Python program inside an LLM completion.
//!
//! Input: completion text as the model wrote it. Output: the program text, or an
//! [`ExtractError`] (the unit then fails at stage `extract`). Models answer with a fenced block
//! (```` ```python ````), several blocks, or bare code with some prose around it; the program is
//! the block that defines `execute_command` (else the longest block), or the bare text from its
//! first line of code onwards.

/// Why a completion holds no program.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ExtractError {
    /// The completion is empty or only whitespace.
    #[error("the completion is empty")]
    Empty,
    /// The completion has text but no Python program in it.
    #[error(
        "the completion has no Python program (no code block and no `def execute_command`): {0}"
    )]
    NoCode(String),
}

impl ExtractError {
    /// A short stable kind for reports.
    pub fn kind(&self) -> &'static str {
        match self {
            ExtractError::Empty => "empty_completion",
            ExtractError::NoCode(_) => "no_code",
        }
    }
}

/// The program in `completion`.
pub fn extract_program(completion: &str) -> Result<String, ExtractError> {
    if completion.trim().is_empty() {
        return Err(ExtractError::Empty);
    }
    let blocks = fenced_blocks(completion);
    let chosen = blocks
        .iter()
        .find(|block| block.contains("def execute_command"))
        .or_else(|| blocks.iter().max_by_key(|block| block.len()))
        .map(|block| block.trim_matches('\n').to_string());
    if let Some(program) = chosen.filter(|p| !p.trim().is_empty()) {
        return Ok(ensure_newline(program));
    }
    // Bare code: from the first line that starts a definition, an import or an assignment.
    let lines: Vec<&str> = completion.lines().collect();
    let start = lines.iter().position(|line| looks_like_code_start(line));
    match start {
        Some(start)
            if completion.contains("def execute_command") || completion.contains("answer") =>
        {
            Ok(ensure_newline(
                lines[start..].join("\n").trim_end().to_string(),
            ))
        }
        _ => Err(ExtractError::NoCode(preview(completion))),
    }
}

fn ensure_newline(mut program: String) -> String {
    if !program.ends_with('\n') {
        program.push('\n');
    }
    program
}

/// The contents of ``` fenced blocks (any language tag), in order. An unclosed final fence
/// counts as a block to the end (completions cut at `max_tokens`).
fn fenced_blocks(text: &str) -> Vec<String> {
    let mut blocks = Vec::new();
    let mut current: Option<Vec<&str>> = None;
    for line in text.lines() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("```") {
            match current.take() {
                Some(lines) => blocks.push(lines.join("\n")),
                None => current = Some(Vec::new()),
            }
        } else if let Some(lines) = current.as_mut() {
            lines.push(line);
        }
    }
    if let Some(lines) = current {
        blocks.push(lines.join("\n"));
    }
    blocks
}

fn looks_like_code_start(line: &str) -> bool {
    let trimmed = line.trim_start();
    trimmed.starts_with("def ")
        || trimmed.starts_with("import ")
        || trimmed.starts_with("from ")
        || trimmed.starts_with('#')
        // An assignment to plain names (`answer = ...`, `a, b = ...`), not prose with " = ".
        || trimmed.split_once(" = ").is_some_and(|(target, _)| target.split(',').all(is_identifier))
}

fn is_identifier(text: &str) -> bool {
    let text = text.trim();
    let mut chars = text.chars();
    chars.next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_')
}

fn preview(text: &str) -> String {
    let flat: String = text.split_whitespace().collect::<Vec<_>>().join(" ");
    if flat.chars().count() > 120 {
        format!("{}...", flat.chars().take(117).collect::<String>())
    } else {
        flat
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn programs_are_found_in_the_shapes_models_answer_with() {
        let program = "def execute_command(video):\n    return 'yes'\n";
        let cases = [
            (format!("```python\n{program}```"), program),
            (
                format!("Here is the program:\n\n```\n{program}```\nIt finds the cube."),
                program,
            ),
            (
                format!("```python\nimport math\n```\nand\n```python\n{program}```"),
                program,
            ),
            (format!("Sure.\n{program}"), program),
            (format!("```python\n{program}"), program),
            ("answer = 3".to_string(), "answer = 3\n"),
        ];
        for (completion, expected) in cases {
            assert_eq!(
                extract_program(&completion).unwrap(),
                expected,
                "{completion}"
            );
        }
    }

    #[test]
    fn empty_and_prose_completions_are_errors() {
        assert_eq!(extract_program("  \n ").unwrap_err(), ExtractError::Empty);
        let error = extract_program("I cannot answer questions about videos.").unwrap_err();
        assert_eq!(error.kind(), "no_code");
        assert!(
            error
                .to_string()
                .contains("I cannot answer questions about videos.")
        );
    }
}
