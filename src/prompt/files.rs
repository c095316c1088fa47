//! The files of a prompt set: the ones compiled into the binary, and an optional directory that
//! overrides them.
//!
//! A prompt set is `prompts/**/*.jinja` plus `api_spec/scene_api.pyi`, `api_spec/VERSION` and
//! `api_spec/examples/**/*.py`, keyed by their path relative to the repository root. The
//! embedded copy makes the binary work anywhere; a test checks that [`EMBEDDED`] lists exactly
//! the files on disk, so a new example or partial cannot be forgotten here.

use std::collections::BTreeMap;
use std::path::Path;

use super::error::PromptError;

/// The prompt set compiled into the binary: `(path, text)`.
pub(crate) const EMBEDDED: &[(&str, &str)] = &[
    ("api_spec/VERSION", include_str!("../../api_spec/VERSION")),
    (
        "api_spec/examples/ball/ball_counterfactual.py",
        include_str!("../../api_spec/examples/ball/ball_counterfactual.py"),
    ),
    (
        "api_spec/examples/cloth/cloth_predictive.py",
        include_str!("../../api_spec/examples/cloth/cloth_predictive.py"),
    ),
    (
        "api_spec/examples/fluid/fluid_goaldriven.py",
        include_str!("../../api_spec/examples/fluid/fluid_goaldriven.py"),
    ),
    (
        "api_spec/examples/rope/color.py",
        include_str!("../../api_spec/examples/rope/color.py"),
    ),
    (
        "api_spec/examples/rope/existence.py",
        include_str!("../../api_spec/examples/rope/existence.py"),
    ),
    (
        "api_spec/examples/rope/mass.py",
        include_str!("../../api_spec/examples/rope/mass.py"),
    ),
    (
        "api_spec/examples/rope/mass_can_not_answer.py",
        include_str!("../../api_spec/examples/rope/mass_can_not_answer.py"),
    ),
    (
        "api_spec/examples/rope/rope_counterfactual.per_question.py",
        include_str!("../../api_spec/examples/rope/rope_counterfactual.per_question.py"),
    ),
    (
        "api_spec/examples/rope/rope_counterfactual.py",
        include_str!("../../api_spec/examples/rope/rope_counterfactual.py"),
    ),
    (
        "api_spec/examples/rope/rope_counterfactual2.per_question.py",
        include_str!("../../api_spec/examples/rope/rope_counterfactual2.per_question.py"),
    ),
    (
        "api_spec/examples/rope/rope_counterfactual2.py",
        include_str!("../../api_spec/examples/rope/rope_counterfactual2.py"),
    ),
    (
        "api_spec/examples/rope/rope_counterfactual_not_move.py",
        include_str!("../../api_spec/examples/rope/rope_counterfactual_not_move.py"),
    ),
    (
        "api_spec/examples/rope/rope_goaldriven.per_question.py",
        include_str!("../../api_spec/examples/rope/rope_goaldriven.per_question.py"),
    ),
    (
        "api_spec/examples/rope/rope_goaldriven.py",
        include_str!("../../api_spec/examples/rope/rope_goaldriven.py"),
    ),
    (
        "api_spec/examples/rope/shape.py",
        include_str!("../../api_spec/examples/rope/shape.py"),
    ),
    (
        "api_spec/examples/rope/tension.py",
        include_str!("../../api_spec/examples/rope/tension.py"),
    ),
    (
        "api_spec/scene_api.pyi",
        include_str!("../../api_spec/scene_api.pyi"),
    ),
    (
        "prompts/base.jinja",
        include_str!("../../prompts/base.jinja"),
    ),
    (
        "prompts/partials/answer_format.jinja",
        include_str!("../../prompts/partials/answer_format.jinja"),
    ),
    (
        "prompts/partials/examples.jinja",
        include_str!("../../prompts/partials/examples.jinja"),
    ),
    (
        "prompts/partials/guidelines.jinja",
        include_str!("../../prompts/partials/guidelines.jinja"),
    ),
    (
        "prompts/partials/query.jinja",
        include_str!("../../prompts/partials/query.jinja"),
    ),
    (
        "prompts/partials/sandbox.jinja",
        include_str!("../../prompts/partials/sandbox.jinja"),
    ),
    (
        "prompts/partials/scenarios/ball.jinja",
        include_str!("../../prompts/partials/scenarios/ball.jinja"),
    ),
    (
        "prompts/partials/scenarios/cloth.jinja",
        include_str!("../../prompts/partials/scenarios/cloth.jinja"),
    ),
    (
        "prompts/partials/scenarios/fluid.jinja",
        include_str!("../../prompts/partials/scenarios/fluid.jinja"),
    ),
    (
        "prompts/partials/scenarios/rope.jinja",
        include_str!("../../prompts/partials/scenarios/rope.jinja"),
    ),
    (
        "prompts/system.jinja",
        include_str!("../../prompts/system.jinja"),
    ),
];

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
