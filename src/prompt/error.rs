//! Prompt errors. Each names what it is about: the file, the template and its line, the variable,
//! or the question.

use std::path::PathBuf;

/// Why a prompt set cannot be loaded or a prompt cannot be rendered.
#[derive(Debug, thiserror::Error)]
pub enum PromptError {
    /// A prompt directory or one of its files cannot be read.
    #[error("cannot read `{path}`")]
    Read {
        /// The file or folder.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// An override directory holds neither `prompts/` nor `api_spec/`.
    #[error(
        "prompt directory `{path}` has neither a `prompts/` nor an `api_spec/` folder; it should \
         mirror the repository's layout (`prompts/base.jinja`, `api_spec/scene_api.pyi`, ...)"
    )]
    EmptyOverride {
        /// The directory given.
        path: PathBuf,
    },
    /// A file of the set is missing or malformed (an example without its header, an empty
    /// `VERSION`, a missing `base.jinja`).
    #[error("`{path}`: {problem}")]
    Spec {
        /// The file, relative to the prompt set's root (`api_spec/examples/rope/mass.py`).
        path: String,
        /// What is wrong.
        problem: String,
    },
    /// A template does not parse.
    #[error("template `{template}` does not parse (line {line})")]
    Syntax {
        /// The template name (`partials/query.jinja`).
        template: String,
        /// The line of the error, 1-based (0 when unknown).
        line: usize,
        /// The parser's error.
        #[source]
        source: minijinja::Error,
    },
    /// A template uses a variable the context does not define (`UndefinedBehavior::Strict`).
    #[error("template `{template}` line {line}: undefined variable `{variable}`")]
    UndefinedVariable {
        /// The template name.
        template: String,
        /// The line, 1-based (0 when unknown).
        line: usize,
        /// The variable (or `a.b` for a missing attribute), as far as it can be told.
        variable: String,
        /// The renderer's error.
        #[source]
        source: minijinja::Error,
    },
    /// Rendering failed for another reason (an unknown example name, a bad filter argument).
    #[error("template `{template}` line {line}: {detail}")]
    Render {
        /// The template name.
        template: String,
        /// The line, 1-based (0 when unknown).
        line: usize,
        /// What went wrong.
        detail: String,
        /// The renderer's error.
        #[source]
        source: minijinja::Error,
    },
    /// The unit asked for does not fit the question and the mode (an option of an open question,
    /// no option for a choice question in per-option mode).
    #[error("question `{question_id}`: {problem}")]
    Unit {
        /// The question.
        question_id: String,
        /// What does not fit.
        problem: String,
    },
    /// The prompt set compiled into the binary does not load (a bug: its tests catch this).
    #[error("the embedded prompt set does not load: {0}")]
    Embedded(String),
}
