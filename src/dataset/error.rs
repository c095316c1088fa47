//! The dataset error type: every variant names the file, and the field or question involved.

use std::path::PathBuf;

use super::{QuestionError, Scenario};

/// A problem with dataset files: missing, unreadable, malformed, truncated or inconsistent.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    /// A file or folder could not be read.
    #[error("cannot read `{path}`")]
    Read {
        /// The path that failed.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A file is not valid JSON (serde's message gives line and column; truncation shows as EOF).
    #[error("`{path}` is not valid JSON")]
    Json {
        /// The file.
        path: PathBuf,
        /// The parse error, with line and column.
        #[source]
        source: serde_json::Error,
    },
    /// A JSON file parsed, but a field is missing or has the wrong type or value.
    #[error("`{path}`: field `{field}` {problem}")]
    Field {
        /// The file.
        path: PathBuf,
        /// The field, as a dotted path from the document root.
        field: String,
        /// What is wrong with it.
        problem: String,
    },
    /// The data root does not exist or is not a folder.
    #[error("data root `{path}` does not exist or is not a folder")]
    MissingRoot {
        /// The path given.
        path: PathBuf,
    },
    /// A video folder lacks its annotation file.
    #[error("video folder `{path}` has no `outputs.json`")]
    MissingAnnotation {
        /// The video folder.
        path: PathBuf,
    },
    /// A question names a video that has no folder under the data root.
    #[error(
        "question `{question_id}` in `{path}` names video `{video_id}`, but `{expected}` does not exist"
    )]
    MissingVideo {
        /// The question file.
        path: PathBuf,
        /// The question.
        question_id: String,
        /// The video it names.
        video_id: String,
        /// The folder that was looked for.
        expected: PathBuf,
    },
    /// A question record is inconsistent (answer letters without options, unknown answer type...).
    #[error("`{path}`: question `{question_id}`: {problem}")]
    Question {
        /// The question file.
        path: PathBuf,
        /// The question.
        question_id: String,
        /// What is wrong (shown in the message, so it is not also a source).
        problem: QuestionError,
    },
    /// The scenario of a question file cannot be told from its name, folder or families.
    #[error(
        "cannot tell the scenario of `{path}`: name it `<scenario folder>_<split>.json` (scenario folders: {folders}), put it in a scenario folder, or pass --scenario",
        folders = Scenario::folder_names()
    )]
    UnknownScenario {
        /// The question file.
        path: PathBuf,
    },
    /// A video folder given directly is not inside a scenario folder, and no scenario was given.
    #[error(
        "cannot tell the scenario of video folder `{path}`: its parent folder is none of {folders}; pass --scenario",
        folders = Scenario::folder_names()
    )]
    UnknownVideoScenario {
        /// The video folder.
        path: PathBuf,
    },
}

impl DatasetError {
    pub(crate) fn read(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Read {
            path: path.into(),
            source,
        }
    }
}
