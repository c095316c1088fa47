//! The question engine's error type: a video whose annotations cannot be read, or cannot be
//! turned into the scenario engine's view of the scene.

use crate::dataset::DatasetError;

/// Why questions could not be generated for a video.
#[derive(Debug, thiserror::Error)]
pub enum EngineError {
    /// The video's annotations could not be read.
    #[error(transparent)]
    Annotation(#[from] DatasetError),
    /// The annotations were read, but the scenario's engine cannot build its view of the scene
    /// from them (the error names the video and the object).
    #[error(transparent)]
    Scene(Box<dyn std::error::Error + Send + Sync>),
}
