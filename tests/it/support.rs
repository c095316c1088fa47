//! Helpers shared by the integration tests: the binary, the demo data, temporary copies.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root.
pub(crate) fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The demo data root (`eval/demo`).
pub(crate) fn demo() -> PathBuf {
    root().join("eval/demo")
}

/// Runs `contphy-eval` with `args` in `dir`.
pub(crate) fn contphy(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_contphy-eval"))
        .args(args)
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .output()
        .expect("the binary runs")
}

pub(crate) fn stdout(output: &Output) -> String {
    String::from_utf8_lossy(&output.stdout).into_owned()
}

pub(crate) fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A temporary data root holding the real rope video (annotations only, no mp4s).
pub(crate) fn temp_data_root() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let video = dir.path().join("pulley_group/0");
    fs_err::create_dir_all(&video).unwrap();
    for file in ["outputs.json", "outputs4D.json"] {
        fs_err::copy(demo().join("pulley_group/0").join(file), video.join(file)).unwrap();
    }
    dir
}

/// `predictions.jsonl` with every `*_ms` field removed (the only fields allowed to differ).
pub(crate) fn predictions_without_timings(run: &Path) -> Vec<serde_json::Value> {
    fs_err::read_to_string(run.join("predictions.jsonl"))
        .unwrap()
        .lines()
        .map(|line| {
            let mut value: serde_json::Value = serde_json::from_str(line).unwrap();
            value
                .as_object_mut()
                .unwrap()
                .retain(|key, _| !key.ends_with("_ms"));
            value
        })
        .collect()
}
