//! Scene API errors. `Misuse`, `Unavailable` and `NotSeen` become a Python `SceneApiError` (or
//! one of its subclasses) that the program may catch; `Data` means the video's files are broken and fails the unit at stage `scene_api`.

use crate::dataset::DatasetError;

/// Why a scene API call failed.
#[derive(Debug, Clone, thiserror::Error)]
pub enum ApiError {
    /// The program called the API wrongly; the message says what is allowed.
    #[error("{0}")]
    Misuse(String),
    /// The call is well formed but this video cannot answer it (no such counterfactual run...).
    #[error("{0}")]
    Unavailable(String),
    /// A well-formed description names no object perception read from the video's pixels: the
    /// detector missed the object or read it in another colour. (Under annotation perception
    /// every object is known, so naming an absent one is `Misuse`.)
    #[error("{0}")]
    NotSeen(String),
    /// The video's files could not be read or are malformed (the message carries the cause
    /// chain, so the error can be memoised and replayed to every later call).
    #[error("cannot load the scene: {0}")]
    Data(String),
}

impl From<DatasetError> for ApiError {
    fn from(error: DatasetError) -> Self {
        let mut message = error.to_string();
        let mut source = std::error::Error::source(&error);
        while let Some(cause) = source {
            message.push_str(": ");
            message.push_str(&cause.to_string());
            source = cause.source();
        }
        ApiError::Data(message)
    }
}

impl ApiError {
    /// A short stable name for reports: `misuse`, `unavailable`, `not_seen` or `data`.
    pub fn kind(&self) -> &'static str {
        match self {
            ApiError::Misuse(_) => "misuse",
            ApiError::Unavailable(_) => "unavailable",
            ApiError::NotSeen(_) => "not_seen",
            ApiError::Data(_) => "data",
        }
    }
}

/// The error for a call given no object where it needs one, or a well-formed name no object
/// carries (`message` says which): under perception from pixels the detector may have missed
/// the object or read it in another colour (`NotSeen`, a perception miss); under annotation
/// perception every object is known, so it is the program's `Misuse`.
pub(crate) fn named_nothing(message: String, from_pixels: bool) -> ApiError {
    if from_pixels {
        ApiError::NotSeen(format!(
            "{message}; perception from pixels may have missed the object or read it in another colour"
        ))
    } else {
        ApiError::Misuse(message)
    }
}

pub(crate) fn misuse(message: impl Into<String>) -> ApiError {
    ApiError::Misuse(message.into())
}

/// Every action word `happen` knows, in any scenario (the paper's API).
const ALL_ACTIONS: &str =
    "entering, passing, motion, rotation, collision, falling, touching, droping";

/// `happen` was given an action no scenario knows: the message lists every action, then the
/// ones `scenario` answers (`own`).
pub(crate) fn unknown_action(action: &str, scenario: &str, own: &str) -> ApiError {
    misuse(format!(
        "happen: unknown action `{action}`; actions are {ALL_ACTIONS} ({scenario}: {own})"
    ))
}
