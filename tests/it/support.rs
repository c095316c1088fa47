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

/// A temporary data root holding `copies` copies (videos `0`, `1`, …) of the hand-made video
/// `tests/data/<folder>/0` (its annotations): more than one gives the sampler a video for every
/// split.
pub(crate) fn fixture_data_root(folder: &str, copies: usize) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for id in 0..copies {
        let video = dir.path().join(folder).join(id.to_string());
        fs_err::create_dir_all(&video).unwrap();
        fs_err::copy(
            root()
                .join("tests/data")
                .join(folder)
                .join("0/outputs.json"),
            video.join("outputs.json"),
        )
        .unwrap();
    }
    dir
}

/// Per family of a run: (questions right, questions, options right, options); asserts that no
/// unit failed or is missing.
pub(crate) fn family_scores(run: &Path) -> std::collections::BTreeMap<String, [u64; 4]> {
    let results: serde_json::Value =
        serde_json::from_slice(&fs_err::read(run.join("results.json")).unwrap()).unwrap();
    assert_eq!(results["scores"]["failures"], serde_json::json!({}));
    assert_eq!(results["scores"]["missing_units"], 0);
    results["scores"]["families"]
        .as_array()
        .unwrap()
        .iter()
        .map(|family| {
            let model = &family["model"];
            let count = |key: &str| model[key].as_u64().unwrap();
            (
                family["family"].as_str().unwrap().to_string(),
                [
                    count("questions_correct"),
                    count("questions"),
                    count("options_correct"),
                    count("options"),
                ],
            )
        })
        .collect()
}

/// Asserts that every unit of `run` is answered right, with no simulation and no frames, and
/// that every family is one of `families`; returns the per-family scores.
pub(crate) fn assert_perfect(
    run: &Path,
    families: &[&str],
) -> std::collections::BTreeMap<String, [u64; 4]> {
    let scores = family_scores(run);
    for (family, [questions_right, questions, options_right, options]) in &scores {
        assert!(
            families.contains(&family.as_str()),
            "not one of {families:?}: {family}"
        );
        assert_eq!(questions_right, questions, "{family}: {scores:?}");
        assert_eq!(options_right, options, "{family}: {scores:?}");
    }
    for prediction in predictions_without_timings(run) {
        assert_eq!(prediction["work"]["sim_runs"], 0, "{prediction}");
        assert_eq!(prediction["work"]["frames_decoded"], 0, "{prediction}");
    }
    scores
}

/// The frames a run kept for the viewer of one video (`RUN/frames/<scenario>/<video>/`), as its
/// `detections.json` lists them: the listing and its frame numbers in order.
pub(crate) fn kept_frames(frames: &Path) -> (serde_json::Value, Vec<u64>) {
    let listing: serde_json::Value =
        serde_json::from_slice(&fs_err::read(frames.join("detections.json")).unwrap()).unwrap();
    let numbers = listing["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|frame| frame["frame"].as_u64().unwrap())
        .collect();
    (listing, numbers)
}
