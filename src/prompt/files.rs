//! The files of a prompt set: the ones compiled into the binary, and an optional directory that
//! overrides them.
//!
//! A prompt set is `prompts/**/*.jinja` plus `api_spec/scene_api.pyi`, `api_spec/VERSION` and
//! `api_spec/examples/**/*.py`, keyed by their path relative to the repository root. The
//! embedded copy makes the binary work anywhere; `build.rs` lists the files, and a test checks
//! that [`EMBEDDED`] holds exactly the files on disk.

use std::collections::BTreeMap;
use std::path::Path;

use super::error::PromptError;

/// The prompt set compiled into the binary: `(path, text)`, sorted by path; `build.rs` lists
/// every file of `prompts/` and `api_spec/`.
pub(crate) const EMBEDDED: &[(&str, &str)] =
    include!(concat!(env!("OUT_DIR"), "/embedded_prompt_files.rs"));

/// Whether `path` (relative to the set's root, `/`-separated) belongs to a prompt set.
pub(crate) fn is_prompt_file(path: &str) -> bool {
    (path.starts_with("prompts/") && has_extension(path, "jinja"))
        || path == "api_spec/scene_api.pyi"
        || path == "api_spec/VERSION"
        || (path.starts_with("api_spec/examples/") && has_extension(path, "py"))
}

/// Whether `path` ends in `.extension`, in any case (`Rope.PY` is an example too).
fn has_extension(path: &str, extension: &str) -> bool {
    Path::new(path)
        .extension()
        .is_some_and(|found| found.eq_ignore_ascii_case(extension))
}

/// The embedded files.
pub(crate) fn embedded_files() -> BTreeMap<String, String> {
    EMBEDDED
        .iter()
        .map(|(path, text)| ((*path).to_string(), (*text).to_string()))
        .collect()
}

/// The prompt-set files under `dir` (which mirrors the repository: `dir/prompts/...`,
/// `dir/api_spec/...`); other files are ignored.
pub(crate) fn read_dir_files(dir: &Path) -> Result<BTreeMap<String, String>, PromptError> {
    let has_prompts = dir.join("prompts").is_dir();
    let has_spec = dir.join("api_spec").is_dir();
    if !has_prompts && !has_spec {
        return Err(PromptError::EmptyOverride {
            path: dir.to_path_buf(),
        });
    }
    let mut files = BTreeMap::new();
    for (top, present) in [("prompts", has_prompts), ("api_spec", has_spec)] {
        if present {
            walk(dir, &dir.join(top), &mut files)?;
        }
    }
    Ok(files)
}

fn walk(root: &Path, dir: &Path, files: &mut BTreeMap<String, String>) -> Result<(), PromptError> {
    let read_error = |path: &Path| {
        let path = path.to_path_buf();
        move |source| PromptError::Read { path, source }
    };
    let entries = fs_err::read_dir(dir).map_err(read_error(dir))?;
    for entry in entries {
        let path = entry.map_err(read_error(dir))?.path();
        if path.is_dir() {
            walk(root, &path, files)?;
            continue;
        }
        let Ok(relative) = path.strip_prefix(root) else {
            continue;
        };
        let key = relative
            .components()
            .map(|c| c.as_os_str().to_string_lossy())
            .collect::<Vec<_>>()
            .join("/");
        if is_prompt_file(&key) {
            let text = fs_err::read_to_string(&path).map_err(read_error(&path))?;
            files.insert(key, text);
        }
    }
    Ok(())
}
