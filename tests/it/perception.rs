//! The Mask R-CNN session code driven with a tiny committed ONNX model that has the real export's
//! contract (`scripts/perception/make_tiny_model.py`): the runtime loads, the contract is
//! checked, frames are scaled to the model input, scores above the threshold are kept, boxes are
//! scaled back to the frame and masks are pasted there. A corrupt or missing model is one clear
//! error. These tests need ONNX Runtime (`scripts/setup-onnxruntime.sh`); `.ci/run` installs it,
//! and under CI a missing runtime is a failure, not a skip.

use std::path::{Path, PathBuf};

use contphy_eval::perception::detector::{Detector, DetectorConfig, DetectorError};
use contphy_eval::perception::frames::RgbFrame;
use contphy_eval::perception::rope::PERCEPTION;
use contphy_eval::perception::runtime::library_available;

#[expect(clippy::print_stderr, reason = "a skipped test says why")]
pub(crate) fn need_runtime() -> bool {
    if library_available() {
        return true;
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "ONNX Runtime is not installed; .ci/run runs scripts/setup-onnxruntime.sh"
    );
    eprintln!("skipping: ONNX Runtime is not installed (scripts/setup-onnxruntime.sh)");
    false
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/perception")
        .join(name)
}

fn uniform_frame(width: u32, height: u32, value: u8) -> RgbFrame {
    RgbFrame {
        index: 7,
        width,
        height,
        rgb: vec![value; width as usize * height as usize * 3],
    }
}

#[test]
fn the_tiny_model_runs_through_the_session_and_its_outputs_are_read_whole() {
    if !need_runtime() {
        return;
    }
    let mut detector = Detector::load(
        DetectorConfig::new(data("tiny-maskrcnn.onnx"), 1),
        PERCEPTION.classes,
    )
    .unwrap();
    let image = ndarray::Array3::<f32>::ones((3, 270, 480));
    let raw = detector.run_raw(&image.view(), 0).unwrap();
    assert_eq!(raw.labels, vec![1, 3]);
    assert_eq!(
        raw.boxes,
        vec![[10.0, 20.0, 38.0, 48.0], [100.0, 50.0, 200.0, 60.0]]
    );
    // sigmoid(4·1 − 2) on a white image.
    let expected = 1.0 / (1.0 + (-2.0f64).exp());
    assert!(
        (f64::from(raw.scores[0]) - expected).abs() < 1e-6,
        "{:?}",
        raw.scores
    );
    assert!((raw.scores[1] - 0.3).abs() < 1e-7);
    assert_eq!(raw.masks.len(), 2);
    assert_eq!(
        raw.masks[1]
            .iter()
            .filter(|v| (**v - 1.0).abs() < 1e-9)
            .count(),
        28 * 28
    );
}

#[test]
fn detections_are_thresholded_scaled_to_the_frame_and_their_masks_pasted_there() {
    if !need_runtime() {
        return;
    }
    let mut detector = Detector::load(
        DetectorConfig::new(data("tiny-maskrcnn.onnx"), 1),
        PERCEPTION.classes,
    )
    .unwrap();
    // A white 960×540 frame: the model sees 480×270, the cube scores 0.88 and the rope 0.3
    // (below the 0.5 threshold), and the cube's box doubles to [20, 40, 76, 96].
    let detections = detector.detect(&uniform_frame(960, 540, 255)).unwrap();
    assert_eq!(detections.len(), 1, "{detections:?}");
    let cube = &detections[0];
    assert_eq!(cube.frame, 7);
    assert_eq!(detector.classes().name(cube.class), "cube");
    let expected_box = [20.0f32, 40.0, 76.0, 96.0];
    assert!(
        cube.bbox
            .iter()
            .zip(expected_box)
            .all(|(a, b)| (a - b).abs() < 1e-4),
        "{:?}",
        cube.bbox
    );
    // The disc has radius 10 of 28 mask pixels, so about 20 frame pixels: π·20² ≈ 1257.
    let area = cube.mask.area();
    assert!((1100..1400).contains(&area), "disc area {area}");
    let [cx, cy] = cube.mask.centroid().unwrap();
    assert!(
        (cx - 48.0).abs() < 1.5 && (cy - 68.0).abs() < 1.5,
        "{cx} {cy}"
    );
    // A black frame scores the cube sigmoid(−2) = 0.12: nothing is kept.
    assert!(
        detector
            .detect(&uniform_frame(480, 270, 0))
            .unwrap()
            .is_empty()
    );
}

#[test]
fn a_corrupt_or_missing_model_is_one_clear_error() {
    if !need_runtime() {
        return;
    }
    let corrupt = data("corrupt.onnx");
    let error =
        Detector::load(DetectorConfig::new(corrupt.clone(), 1), PERCEPTION.classes).unwrap_err();
    assert!(matches!(error, DetectorError::Model { .. }), "{error:?}");
    let message = error.to_string();
    assert!(
        message.starts_with(&format!("cannot load model {}", corrupt.display())),
        "{message}"
    );
    assert!(!message.contains('\n'), "{message}");
    let missing = data("no-such-model.onnx");
    let error = Detector::load(DetectorConfig::new(missing, 1), PERCEPTION.classes).unwrap_err();
    assert!(
        matches!(error, DetectorError::MissingModel { .. }),
        "{error:?}"
    );
    // A model without its class description, or one whose classes are another scenario's.
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("model.onnx");
    fs_err::copy(data("tiny-maskrcnn.onnx"), &model).unwrap();
    let error = Detector::load(DetectorConfig::new(model.clone(), 1), PERCEPTION.classes)
        .unwrap_err()
        .to_string();
    assert!(
        error.starts_with("cannot read the model description"),
        "{error}"
    );
    fs_err::write(
        dir.path().join("model.json"),
        r#"{"classes": {"1": "fluid", "2": "container"}}"#,
    )
    .unwrap();
    let error = Detector::load(DetectorConfig::new(model, 1), PERCEPTION.classes)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("names none of the classes this scenario's objects fall into"),
        "{error}"
    );
}

#[test]
fn bench_perception_fails_with_one_clear_line_for_each_bad_input() {
    use std::fmt::Write as _;
    use std::process::Command;

    if !need_runtime() || !crate::frames::need_ffmpeg() {
        return;
    }
    let root = crate::support::root();
    let scratch = tempfile::tempdir().unwrap();
    // A data root whose "mp4" is a text file.
    let broken = scratch.path().join("broken/pulley_group/0");
    fs_err::create_dir_all(&broken).unwrap();
    fs_err::copy(
        root.join("eval/demo/pulley_group/0/outputs.json"),
        broken.join("outputs.json"),
    )
    .unwrap();
    fs_err::write(broken.join("output_Full.mp4"), "not a video\n").unwrap();
    fs_err::write(broken.join("output_Full_seg.mp4"), "not a video\n").unwrap();
    let colors = scratch.path().join("colors.json");
    fs_err::write(
        &colors,
        r#"{"fitted_on": "test", "prototypes": [{"palette_id": 0, "name": "Red", "mean": [0.9, 0.05, 0.0], "variance": [0.01, 0.01, 0.1], "samples": 1}]}"#,
    )
    .unwrap();
    let tiny = data("tiny-maskrcnn.onnx");
    let tiny = tiny.to_str().unwrap();
    let colors = colors.to_str().unwrap();
    let demo = root.join("eval/demo");
    let demo = demo.to_str().unwrap();
    let broken_root = scratch.path().join("broken");
    let broken_root = broken_root.to_str().unwrap();
    let missing_library = scratch.path().join("no-such-libonnxruntime.so");
    let not_a_library = data("corrupt.onnx");
    let corrupt_model = data("corrupt.onnx");
    let cases: Vec<(&str, Vec<&str>, Option<&Path>, i32)> = vec![
        (
            "runtime_missing",
            vec!["--data", demo, "--scenario", "rope", "--model", tiny],
            Some(&missing_library),
            1,
        ),
        (
            "runtime_not_a_library",
            vec!["--data", demo, "--scenario", "rope", "--model", tiny],
            Some(&not_a_library),
            1,
        ),
        (
            "model_corrupt",
            vec![
                "--data",
                demo,
                "--scenario",
                "rope",
                "--model",
                corrupt_model.to_str().unwrap(),
            ],
            None,
            1,
        ),
        (
            "mp4_not_a_video",
            vec!["--data", broken_root, "--model", tiny],
            None,
            1,
        ),
        (
            "colour_model_missing",
            vec![
                "--data",
                demo,
                "--scenario",
                "rope",
                "--model",
                tiny,
                "--colors",
                "no-such-colors.json",
            ],
            None,
            1,
        ),
        (
            // The demo holds rope and fluid videos, and both have perception.
            "scenario_ambiguous",
            vec!["--data", demo, "--model", tiny],
            None,
            1,
        ),
        (
            "frame_range_empty",
            vec!["--data", demo, "--frame-range", "9..3"],
            None,
            2,
        ),
    ];
    let mut transcript = String::new();
    for (name, args, library, code) in cases {
        let mut command = Command::new(env!("CARGO_BIN_EXE_contphy-eval"));
        command
            .args(["bench", "perception", "--every", "50"])
            .args(&args)
            .current_dir(&root)
            .env("NO_COLOR", "1");
        if !args.contains(&"--colors") {
            command.args(["--colors", colors]);
        }
        match library {
            Some(path) => command.env("ORT_DYLIB_PATH", path),
            None => command.env_remove("ORT_DYLIB_PATH"),
        };
        let output = command.output().unwrap();
        let message = crate::support::stderr(&output)
            .replace(scratch.path().to_str().unwrap(), "[TMP]")
            .replace(root.to_str().unwrap(), "[ROOT]");
        assert_eq!(output.status.code(), Some(code), "{name}: {message}");
        assert!(!message.contains("panicked"), "{name}: {message}");
        if code == 1 {
            assert_eq!(message.lines().count(), 1, "{name}: {message}");
        }
        let _ = writeln!(transcript, "## {name}\n{message}");
    }
    insta::assert_snapshot!("bench_perception_errors", transcript);
}

#[test]
fn with_maskrcnn_perception_find_sees_only_what_the_detector_found() {
    if !need_runtime() || !crate::frames::need_ffmpeg() {
        return;
    }
    // The tiny model finds one "cube" in the top-left corner of every frame, where the real
    // video has no object: nothing binds to the scene, so no object is findable, and the
    // detector ran on the 7 frames 0, 10, ..., 60 only.
    let root = crate::support::root();
    let video = root.join("eval/demo/pulley_group/0");
    let program = root.join("tests/fixtures/programs/color.py");
    let colors = tempfile::NamedTempFile::new().unwrap();
    fs_err::write(
        colors.path(),
        r#"{"fitted_on": "test", "prototypes": [{"palette_id": 6, "name": "Purple", "mean": [0.4, 0.2, 0.0], "variance": [0.01, 0.01, 0.1], "samples": 1}]}"#,
    )
    .unwrap();
    let run = |perception: &str| {
        let output = crate::support::contphy(
            &root,
            &[
                "exec",
                "--video",
                video.to_str().unwrap(),
                "--program",
                program.to_str().unwrap(),
                "--perception",
                perception,
                "--detector-model",
                data("tiny-maskrcnn.onnx").to_str().unwrap(),
                "--color-model",
                colors.path().to_str().unwrap(),
            ],
        );
        assert_eq!(
            output.status.code(),
            Some(0),
            "{}",
            crate::support::stderr(&output)
        );
        serde_json::from_str::<serde_json::Value>(&crate::support::stdout(&output)).unwrap()
    };
    let annotation = run("annotation");
    assert_eq!(annotation["value"], 3, "{annotation}");
    assert_eq!(annotation["work"]["detections"], 0);
    let perceived = run("maskrcnn");
    assert_eq!(perceived["value"], 0, "{perceived}");
    assert_eq!(perceived["work"]["frames_decoded"], 7, "{perceived}");
    // The 7 first-pass frames, and one window at twice the scale on each of frames 0, 30 and
    // 60 for the closer look at the tracks whose class has rivals.
    assert_eq!(perceived["work"]["detections"], 10, "{perceived}");
    assert_eq!(perceived["work"]["sim_runs"], 0);
}

#[derive(serde::Deserialize)]
struct Reference {
    boxes: Vec<[f32; 4]>,
    labels: Vec<i64>,
    scores: Vec<f32>,
    masks: Vec<Vec<f32>>,
    /// Per detection: `[y, x_start, x_end)` runs of torchvision's pasted mask at 480×270.
    pasted_masks: Vec<Vec<[u32; 3]>>,
}

#[test]
fn the_real_model_matches_python_onnxruntime_on_a_real_frame() {
    use contphy_eval::perception::detector::{model_input, paste_mask, resize_rgb};
    use contphy_eval::perception::frames::FrameSource;

    if !need_runtime() || !crate::frames::need_ffmpeg() {
        return;
    }
    let root = crate::support::root();
    // Preprocessing: the real video's frame 59 (annotation key 60), box-averaged 4× in Rust,
    // is byte for byte the PNG the Python reference was computed on.
    let png = image::open(data("real-frame-060-480x270.png"))
        .unwrap()
        .to_rgb8();
    let decoded = FrameSource::open(&root.join("eval/demo/pulley_group/0/output_Full.mp4"))
        .unwrap()
        .read(&[59])
        .unwrap()
        .remove(0);
    assert_eq!(resize_rgb(&decoded, 480, 270), png.as_raw().clone());
    let frame = RgbFrame {
        index: 59,
        width: 480,
        height: 270,
        rgb: png.into_raw(),
    };
    let reference: Reference =
        serde_json::from_str(&fs_err::read_to_string(data("reference-outputs.json")).unwrap())
            .unwrap();
    let mut detector = Detector::load(
        DetectorConfig::new(root.join("models/maskrcnn-rope.onnx"), 1),
        PERCEPTION.classes,
    )
    .unwrap();
    let raw = detector
        .run_raw(&model_input(&frame, 480, 270).view(), 59)
        .unwrap();
    assert!(
        !reference.labels.is_empty(),
        "the reference frame has detections"
    );
    assert_eq!(raw.labels, reference.labels);
    let close = |a: &[f32], b: &[f32]| a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-5);
    assert!(close(&raw.scores, &reference.scores), "{:?}", raw.scores);
    for (found, expected) in raw.boxes.iter().zip(&reference.boxes) {
        assert!(close(found, expected), "{found:?} vs {expected:?}");
    }
    for (found, expected) in raw.masks.iter().zip(&reference.masks) {
        assert_eq!(found.len(), expected.len());
        assert!(close(found, expected));
    }
    // Pasting: Rust's paste equals torchvision's, pixel for pixel.
    for (i, runs) in reference.pasted_masks.iter().enumerate() {
        let mask = paste_mask(&raw.masks[i], raw.boxes[i], 480, 270, 0.5);
        let expected: u64 = runs.iter().map(|[_, a, b]| u64::from(b - a)).sum();
        assert_eq!(mask.area(), expected, "detection {i}");
        for [y, start, end] in runs {
            for x in *start..*end {
                assert!(mask.contains(x, *y), "detection {i} pixel ({x}, {y})");
            }
        }
    }
}

#[test]
fn a_resume_with_other_perception_models_is_refused() {
    if !need_runtime() || !crate::frames::need_ffmpeg() {
        return;
    }
    let root = crate::support::root();
    let scratch = tempfile::tempdir().unwrap();
    let out = scratch.path().join("run");
    let write_colors = |name: &str, palette_id: u8| {
        let path = scratch.path().join(name);
        fs_err::write(
            &path,
            format!(
                r#"{{"fitted_on": "test", "prototypes": [{{"palette_id": {palette_id}, "name": "x", "mean": [0.4, 0.2, 0.0], "variance": [0.01, 0.01, 0.1], "samples": 1}}]}}"#
            ),
        )
        .unwrap();
        path
    };
    let first = write_colors("first.json", 6);
    let second = write_colors("second.json", 0);
    let run = |colors: &Path, resume: bool| {
        let mut args = vec![
            "--data",
            "eval/demo",
            "--questions",
            "eval/demo/pulley_group/0.json",
            "--limit",
            "2",
            "--quiet",
            "--perception",
            "maskrcnn",
            "--detector-model",
            "tests/data/perception/tiny-maskrcnn.onnx",
            "--color-model",
            colors.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        if resume {
            args.push("--resume");
        }
        crate::support::contphy(&root, &args)
    };
    let output = run(&first, false);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        crate::support::stderr(&output)
    );
    let output = run(&first, true);
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        crate::support::stderr(&output)
    );
    let output = run(&second, true);
    assert_eq!(
        output.status.code(),
        Some(1),
        "{}",
        crate::support::stderr(&output)
    );
    assert!(crate::support::stderr(&output).contains("different settings or data"));
}

#[test]
fn the_real_videos_mechanism_is_read_from_its_pixels() {
    if !need_runtime() || !crate::frames::need_ffmpeg() {
        return;
    }
    // The real video is held out from every model (see no_real_frame_is_in_any_training_set).
    // Hand-checked against the annotation: 8 elements on 2 ropes; the purple rope runs from
    // the purple cube over the blue, gray and pink pulleys to the green cube, the green rope
    // from the pink sphere over the purple pulley to the brown fixed point.
    let root = crate::support::root();
    let models = contphy_eval::scene_api::PerceptionModels {
        detector: root.join("models/maskrcnn-rope.onnx"),
        colors: root.join("models/color-model.json"),
    };
    let check = contphy_eval::scene_api::rope::check_rope_mechanism(
        &root.join("eval/demo/pulley_group/0"),
        &models,
    )
    .unwrap();
    assert_eq!(check.elements, 8, "{check:?}");
    assert_eq!(check.elements_found, 8, "{check:?}");
    assert!(check.mean_position_error < 0.5, "{check:?}");
    assert_eq!(check.ropes, 2, "{check:?}");
    assert_eq!(check.ropes_read_with_turns, 2, "{check:?}");
    assert_eq!(check.extra_ropes, 0, "{check:?}");
}

#[test]
fn every_question_of_the_real_video_is_answered_right_from_its_pixels() {
    if !need_runtime() || !crate::frames::need_ffmpeg() {
        return;
    }
    // ContPRO's pipeline on the held-out real video: objects, colours, tracks and the mechanism
    // from the detector, masses from the tracked motion, dynamics from the simulator; nothing
    // from the annotation but the camera. All 185 questions right, every option. The track-window
    // start of mass inference was set after reading this video's tracks (its unit test says
    // so), so its 3 mass questions are in-sample for that constant.
    let root = crate::support::root();
    let out = tempfile::tempdir().unwrap();
    let run_dir = out.path().join("run");
    let output = crate::support::contphy(
        &root,
        &[
            "run",
            "--data",
            "eval/demo",
            "--questions",
            "eval/demo/pulley_group/0.json",
            "--perception",
            "maskrcnn",
            "--dynamics",
            "simulate",
            "--out",
            run_dir.to_str().unwrap(),
        ],
    );
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        crate::support::stderr(&output)
    );
    let results: serde_json::Value =
        serde_json::from_str(&fs_err::read_to_string(run_dir.join("results.json")).unwrap())
            .unwrap();
    let categories = results["scores"]["categories"].as_array().unwrap();
    let count = |field: &str| -> u64 {
        categories
            .iter()
            .map(|c| c["model"][field].as_u64().unwrap())
            .sum()
    };
    assert_eq!(count("questions"), 185, "{results}");
    assert_eq!(count("questions_correct"), 185, "{results}");
    assert_eq!(count("options_correct"), count("options"), "{results}");
    for category in categories {
        assert_eq!(
            category["failed_units"],
            serde_json::json!({}),
            "{category}"
        );
    }
    // The mass and tension questions' full pass read every frame; every tenth is kept for the
    // viewer with its detections drawn (the first pass's 0–60 and the full pass's 70–140).
    let (_, kept) = crate::support::kept_frames(&run_dir.join("frames/rope/0"));
    assert_eq!(kept, (0..=140).step_by(10).collect::<Vec<u64>>());
    assert!(run_dir.join("frames/rope/0/0140.jpg").is_file());
}

/// SHA-256 of a file, lowercase hex.
fn sha256_hex(path: &Path) -> String {
    use sha2::Digest as _;
    let bytes = fs_err::read(path).unwrap();
    sha2::Sha256::digest(&bytes)
        .iter()
        .fold(String::new(), |mut hex, byte| {
            use std::fmt::Write as _;
            let _ = write!(hex, "{byte:02x}");
            hex
        })
}

#[test]
fn no_real_frame_is_in_any_training_set() {
    // The real video is held out: the detector's and the colour model's descriptions list every
    // video they learnt from, by the SHA-256 of its outputs.json, and the real video is not
    // among them (its copy in eval/demo, and the release sample beside the repository when
    // present).
    let root = crate::support::root();
    let mut real = vec![sha256_hex(
        &root.join("eval/demo/pulley_group/0/outputs.json"),
    )];
    let sample = root.join("../shared/contphy-sample/rope/0/outputs.json");
    if sample.is_file() {
        real.push(sha256_hex(&sample));
    }
    let detector = model_json("maskrcnn-rope.json");
    let colors = model_json("color-model.json");
    for (model, listed) in [
        ("maskrcnn-rope.json", &detector["data"]["training_videos"]),
        ("color-model.json", &colors["training_videos"]),
    ] {
        let listed = listed
            .as_array()
            .unwrap_or_else(|| panic!("{model}: no list"));
        assert!(
            listed.len() >= 20,
            "{model}: {} training videos",
            listed.len()
        );
        for video in listed {
            let hash = video["outputs_sha256"].as_str().unwrap();
            assert_eq!(hash.len(), 64, "{model}: {video}");
            assert!(
                !real.iter().any(|r| r == hash),
                "{model} trained on the real video: {video}"
            );
        }
    }
    // Nothing else in the descriptions names real frames as training data: the real video is
    // named only as the held-out test.
    let data = detector["data"].as_object().unwrap();
    assert!(
        data.keys()
            .all(|key| !key.contains("real") && key != "train_keys"),
        "{data:?}"
    );
    assert!(
        data["held_out"].as_str().is_some_and(
            |text| text.contains("real video") && text.contains("never a training input")
        ),
        "{data:?}"
    );
}

/// Checks a model's list of training videos: each from a folder starting with one of
/// `folders`, with an `outputs.json` SHA-256 not among `excluded`; returns how many it lists.
fn assert_training_videos(
    model: &str,
    listed: &serde_json::Value,
    folders: &[&str],
    excluded: &[String],
) -> usize {
    let listed = listed
        .as_array()
        .unwrap_or_else(|| panic!("{model}: no list"));
    for video in listed {
        let folder = video["video"].as_str().unwrap();
        assert!(
            folders.iter().any(|prefix| folder.starts_with(prefix)),
            "{model}: {folder}"
        );
        let hash = video["outputs_sha256"].as_str().unwrap();
        assert_eq!(hash.len(), 64, "{model}: {video}");
        assert!(
            !excluded.iter().any(|other| other == hash),
            "{model} learnt from a held-out video: {video}"
        );
    }
    listed.len()
}

/// A committed model description (`models/<file>`).
fn model_json(file: &str) -> serde_json::Value {
    let path = crate::support::root().join("models").join(file);
    serde_json::from_slice(&fs_err::read(path).unwrap()).unwrap()
}

/// A detector description's class names, in label order.
fn class_names(detector: &serde_json::Value) -> Vec<&str> {
    detector["classes"]
        .as_object()
        .unwrap()
        .values()
        .filter_map(|name| name.as_str())
        .collect()
}

/// The SHA-256 of the `outputs.json` of each video folder (relative to the repository).
fn outputs_hashes(dirs: &[&str]) -> Vec<String> {
    let root = crate::support::root();
    dirs.iter()
        .map(|dir| sha256_hex(&root.join(dir).join("outputs.json")))
        .collect()
}

#[test]
fn the_fluid_models_learnt_from_their_training_seeds_only() {
    // The fluid detector and colour model list the generated videos they learnt from; every
    // one is from the two training seeds' folders (3201 randomised, 3202 the release's look),
    // never from the tuning seed's (fluid-tune11, the held-out figures) or the test seed's
    // (fluid100), and none is a demo video (eval/demo/fluid_slides, by its outputs.json hash).
    let demo = outputs_hashes(&["eval/demo/fluid_slides/0", "eval/demo/fluid_slides/1"]);
    let detector = model_json("maskrcnn-fluid.json");
    let colors = model_json("color-model-fluid.json");
    for (model, listed, least) in [
        (
            "maskrcnn-fluid.json",
            &detector["data"]["training_videos"],
            19,
        ),
        ("color-model-fluid.json", &colors["training_videos"], 36),
    ] {
        let count = assert_training_videos(
            model,
            listed,
            &[
                "fluid-train-rand/fluid_slides/",
                "fluid-train-rel/fluid_slides/",
            ],
            &demo,
        );
        assert!(count >= least, "{model}: {count} training videos");
    }
    assert_eq!(
        class_names(&detector),
        ["stick", "container", "emitter", "fluid"]
    );
}

#[test]
fn the_ball_detector_learnt_from_its_training_seeds_only() {
    // The ball detector lists the generated videos it learnt from: every one from the two
    // training seeds' folders (3301 randomised, 3302 the release's look), never the held-out
    // seed's (3303), the tuning seed's (11) or the test seed's (2026), and none is a demo video
    // or the hand-written fixture (by their outputs.json hashes).
    let excluded = outputs_hashes(&[
        "eval/demo/soft_body/0",
        "eval/demo/soft_body/1",
        "tests/data/soft_body/0",
    ]);
    let detector = model_json("maskrcnn-ball.json");
    let count = assert_training_videos(
        "maskrcnn-ball.json",
        &detector["data"]["training_videos"],
        &["ball-train-rand/soft_body/", "ball-train-rel/soft_body/"],
        &excluded,
    );
    assert_eq!(count, 36);
    assert_eq!(
        class_names(&detector),
        ["ball", "floating wall", "ramp", "floor piece"]
    );
}

#[test]
fn the_cloth_models_learnt_from_their_training_seeds_only() {
    // The cloth detector and colour model list the generated videos they learnt from: every one
    // from the two training seeds' folders (3401 randomised, 3402 the release's look), never the
    // held-out seed's (3403) or the test seeds' (2026, 7070), and none is a demo video or the
    // test fixture (by their outputs.json hashes).
    let excluded = outputs_hashes(&[
        "eval/demo/cloth_collision/0",
        "eval/demo/cloth_collision/1",
        "tests/data/cloth_collision/0",
    ]);
    let detector = model_json("maskrcnn-cloth.json");
    let colors = model_json("color-model-cloth.json");
    for (model, listed) in [
        ("maskrcnn-cloth.json", &detector["data"]["training_videos"]),
        ("color-model-cloth.json", &colors["training_videos"]),
    ] {
        let count = assert_training_videos(
            model,
            listed,
            &[
                "cloth-train-rand/cloth_collision/",
                "cloth-train-rel/cloth_collision/",
            ],
            &excluded,
        );
        assert_eq!(count, 36, "{model}");
    }
    assert_eq!(class_names(&detector), ["cloth", "pillar", "plate"]);
}

#[test]
fn the_demo_cloth_boxes_that_stand_still_are_read_still_from_their_masks() {
    if !need_runtime() || !crate::frames::need_ffmpeg() {
        return;
    }
    // The two generated demo videos, which no cloth model learnt from. Their annotations
    // (hand-checked): three boxes of the immovable 99999-class masses, all upright at the end
    // (video 0's brown pillar and yellow plate, video 1's cyan plate), and seven light boxes,
    // all fallen (supine). From the masks alone, the three immovable boxes are read still and
    // none of the seven: these get their pool's immovable mass under `--perception maskrcnn
    // --dynamics simulate`.
    let output = crate::support::contphy(
        &crate::support::root(),
        &[
            "bench",
            "perception",
            "--scenario",
            "cloth",
            "--data",
            "eval/demo",
            "--every",
            "50",
        ],
    );
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        crate::support::stderr(&output)
    );
    let report: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(
        report["mechanism"]["still"],
        serde_json::json!({"immovable": [3, 3], "light_fell": [0, 7], "light_upright": [0, 0]}),
        "{}",
        report["mechanism"]
    );
}

#[test]
fn from_pixels_the_demo_cloth_s_immovable_pillar_does_not_fall_and_the_work_is_counted() {
    if !need_runtime() || !crate::frames::need_ffmpeg() {
        return;
    }
    // The fall questions of demo video 0 under ContPRO's pipeline (nothing from the annotation
    // but the camera). Hand-checked against its annotation: the brown pillar and the yellow
    // plate are immovable (99999 and 99998 kg) and stay upright; the orange pillar and the pink
    // plate are light and fall. Read still from their masks, the immovable two are simulated
    // immovable (with every box movable, the brown pillar fell in the simulation).
    let root = crate::support::root();
    let scratch = tempfile::tempdir().unwrap();
    let all: serde_json::Value = serde_json::from_str(
        &fs_err::read_to_string(root.join("eval/demo/cloth_collision/0.json")).unwrap(),
    )
    .unwrap();
    let falls = serde_json::json!({
        "video_id": all["video_id"],
        "question_dict": {"cloth_predictive_fall": all["question_dict"]["cloth_predictive_fall"]},
    });
    let questions = scratch.path().join("falls.json");
    fs_err::write(&questions, falls.to_string()).unwrap();
    let run_dir = scratch.path().join("run");
    let output = crate::support::contphy(
        &root,
        &[
            "run",
            "--data",
            "eval/demo",
            "--questions",
            questions.to_str().unwrap(),
            "--perception",
            "maskrcnn",
            "--dynamics",
            "simulate",
            "--quiet",
            "--out",
            run_dir.to_str().unwrap(),
        ],
    );
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        crate::support::stderr(&output)
    );
    let units: Vec<serde_json::Value> = fs_err::read_to_string(run_dir.join("predictions.jsonl"))
        .unwrap()
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect();
    let answers: Vec<(String, String, bool)> = units
        .iter()
        .map(|unit| {
            (
                unit["question_id"].as_str().unwrap().to_string(),
                unit["value"].as_str().unwrap_or("").to_string(),
                unit["correct"].as_bool().unwrap(),
            )
        })
        .collect();
    assert_eq!(units.len(), 8, "{answers:?}");
    assert!(
        answers.iter().all(|(_, _, correct)| *correct),
        "{answers:?}"
    );
    // The first unit loaded the scene: the first pass (7 frames: 0, 10, …, 60) and one pass over
    // the 115 frames 30–144 for the cloths and the boxes' motion, which decodes frames 30, 40,
    // 50 and 60 again but reuses their detections: 122 frames decoded, 118 detected.
    let frames: u64 = units
        .iter()
        .map(|unit| unit["work"]["frames_decoded"].as_u64().unwrap())
        .sum();
    let detections: u64 = units
        .iter()
        .map(|unit| unit["work"]["detections"].as_u64().unwrap())
        .sum();
    assert_eq!((frames, detections), (122, 118), "{units:?}");
}
