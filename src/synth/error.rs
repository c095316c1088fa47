//! Errors of synthetic-video generation.

use std::path::PathBuf;

/// Why a video could not be generated.
#[derive(Debug, thiserror::Error)]
pub enum SynthError {
    /// Reading or writing a file failed.
    #[error("cannot write `{path}`")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// An image or video could not be encoded.
    #[error("cannot encode `{path}`: {detail}")]
    Encode {
        /// The file.
        path: PathBuf,
        /// The encoder's message.
        detail: String,
    },
    /// mp4 output was asked for but ffmpeg is not installed.
    #[error(
        "mp4 output needs `ffmpeg`, which is not installed (Debian: `apt-get install ffmpeg`); use `--frames png` or `--frames none`"
    )]
    FfmpegMissing,
    /// No valid scene was found within the attempt budget.
    #[error("video seed {seed}: no valid scene after {attempts} trials (last: {last})")]
    NoValidScene {
        /// The video's seed.
        seed: u64,
        /// Trials made.
        attempts: u32,
        /// Why the last one was rejected.
        last: String,
    },
    /// The scenario has no generator yet.
    #[error("the {scenario} scenario has no generator yet; `generate` supports: {supported}")]
    Unsupported {
        /// The scenario asked for.
        scenario: String,
        /// The scenarios with a generator, comma separated.
        supported: String,
    },
}

impl From<crate::util::FsError> for SynthError {
    fn from(error: crate::util::FsError) -> SynthError {
        match error {
            crate::util::FsError::Write { path, source } => SynthError::Io { path, source },
        }
    }
}
