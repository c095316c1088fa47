//! Finding and loading the ONNX Runtime library, once per process.
//!
//! `ort` is built with `load-dynamic`: nothing is linked at build time, so the crate builds and
//! every non-perception path works without the library. At run time the library is looked up in
//! this order: `ORT_DYLIB_PATH` (a file), then the project-local install that
//! `scripts/setup-onnxruntime.sh` makes (`.contphy/onnxruntime/`), searched from the current
//! directory and from the executable's directory upwards. Input: the environment and the file
//! system. Output: the process's `ort` environment, or a [`RuntimeError`] that says how to
//! install the library.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The ONNX Runtime release the setup script installs (the `onnxruntime` wheel's version).
pub const ONNXRUNTIME_VERSION: &str = "1.31.1";

/// The library file inside the project-local install folder.
pub const LIBRARY_FILE: &str = "libonnxruntime.so.1.31.1";

/// The project-local install folder, relative to the project root.
pub const INSTALL_DIR: &str = ".contphy/onnxruntime";

/// The environment variable that names the library file.
pub const DYLIB_VARIABLE: &str = "ORT_DYLIB_PATH";

/// Why the runtime could not be used.
#[derive(Debug, Clone, thiserror::Error)]
pub enum RuntimeError {
    /// No library file was found.
    #[error(
        "ONNX Runtime is not installed (looked for {ORT_DYLIB_PATH} and {INSTALL_DIR}/{LIBRARY_FILE}); run scripts/setup-onnxruntime.sh or set {DYLIB_VARIABLE} to a libonnxruntime.so {ONNXRUNTIME_VERSION}",
        ORT_DYLIB_PATH = DYLIB_VARIABLE
    )]
    NotInstalled,
    /// `ORT_DYLIB_PATH` names a file that does not exist.
    #[error("{DYLIB_VARIABLE} names {path}, which does not exist")]
    MissingFile {
        /// The named path.
        path: PathBuf,
    },
    /// The file exists but is not a usable ONNX Runtime library.
    #[error("cannot load ONNX Runtime from {path}: {message}")]
    Load {
        /// The library path.
        path: PathBuf,
        /// What the loader said.
        message: String,
    },
}

/// Where the library is, without loading it.
pub fn locate_library() -> Result<PathBuf, RuntimeError> {
    if let Some(value) = std::env::var_os(DYLIB_VARIABLE).filter(|v| !v.is_empty()) {
        let path = PathBuf::from(value);
        return if path.is_file() {
            Ok(path)
        } else {
            Err(RuntimeError::MissingFile { path })
        };
    }
    let mut roots: Vec<PathBuf> = Vec::new();
    if let Ok(current) = std::env::current_dir() {
        roots.push(current);
    }
    if let Ok(executable) = std::env::current_exe()
        && let Some(folder) = executable.parent()
    {
        roots.extend(folder.ancestors().map(Path::to_path_buf));
    }
    roots
        .iter()
        .map(|root| root.join(INSTALL_DIR).join(LIBRARY_FILE))
        .find(|candidate| candidate.is_file())
        .ok_or(RuntimeError::NotInstalled)
}

/// Whether the library can be found (tests use this to decide whether the runtime is required).
pub fn library_available() -> bool {
    locate_library().is_ok()
}

static ENVIRONMENT: OnceLock<Result<ort::environment::Environment, RuntimeError>> = OnceLock::new();

/// The process's ONNX Runtime environment, loading the library on first use. A failure is
/// remembered: the library is not looked up again in the same process.
pub fn environment() -> Result<&'static ort::environment::Environment, RuntimeError> {
    ENVIRONMENT
        .get_or_init(|| {
            let path = locate_library()?;
            let path = path.canonicalize().unwrap_or(path);
            let builder = ort::init_from(&path).map_err(|error| RuntimeError::Load {
                path: path.clone(),
                message: error.to_string(),
            })?;
            builder
                .with_name("contphy-eval")
                .with_telemetry(false)
                .build()
                .map_err(|error| RuntimeError::Load {
                    path,
                    message: error.to_string(),
                })
        })
        .as_ref()
        .map_err(Clone::clone)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_missing_runtime_message_says_how_to_install_it() {
        let message = RuntimeError::NotInstalled.to_string();
        assert!(
            message.contains("scripts/setup-onnxruntime.sh"),
            "{message}"
        );
        assert!(message.contains("ORT_DYLIB_PATH"), "{message}");
        assert!(message.contains(ONNXRUNTIME_VERSION), "{message}");
        assert!(!message.contains('\n'));
    }
}
