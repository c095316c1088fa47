//! The command line as a new user meets it: help text, and clear errors (exit 1) for bad input.

use std::fmt::Write as _;

use crate::support::{contphy, demo, root, stderr, stdout, temp_data_root};

#[test]
fn help_text() {
    let output = contphy(&root(), &["--help"]);
    assert!(output.status.success());
    insta::assert_snapshot!("help", stdout(&output));
    let output = contphy(&root(), &["exec", "--help"]);
    insta::assert_snapshot!("exec_help", stdout(&output));
}

/// Replaces temporary paths so snapshots are stable.
fn normalise(text: &str, temp: &std::path::Path) -> String {
    text.replace(&temp.display().to_string(), "[TEMP]")
        .replace(&root().display().to_string(), "[ROOT]")
}

#[test]
fn bad_input_gives_exit_1_and_names_the_problem() {
    let data = temp_data_root();
    let path = data.path();
    fs_err::create_dir_all(path.join("empty")).unwrap();
    fs_err::create_dir_all(path.join("corrupt/pulley_group/0")).unwrap();
    fs_err::write(
        path.join("corrupt/pulley_group/0/outputs.json"),
        r#"{"validity": true, "relatedGroups": [["Purple Cube""#,
    )
    .unwrap();
    fs_err::write(path.join("corrupt/pulley_group_test.json"), "[]").unwrap();
    // A generated fluid video with its `trackingData` cut out.
    let mut fluid: serde_json::Value = serde_json::from_slice(
        &fs_err::read(root().join("eval/demo/fluid_slides/0/outputs.json")).unwrap(),
    )
    .unwrap();
    fluid.as_object_mut().unwrap().remove("trackingData");
    fs_err::create_dir_all(path.join("fluid_no_tracking/fluid_slides/0")).unwrap();
    fs_err::write(
        path.join("fluid_no_tracking/fluid_slides/0/outputs.json"),
        serde_json::to_vec(&fluid).unwrap(),
    )
    .unwrap();
    fs_err::write(
        path.join("pulley_group_extra.json"),
        r#"[{"question": "Is there any red cube in the video?", "answer": "no", "question_family": "existence",
             "answer_type": "open_ended", "qtype": "existence", "video_id": "7", "question_id": "00001", "split": "test"}]"#,
    )
    .unwrap();
    fs_err::write(path.join("truncated.json"), r#"[{"question": "Is there"#).unwrap();
    // A family no scenario's engine has: the name, the folder and the families all fail to
    // tell the scenario.
    fs_err::write(
        path.join("questions.json"),
        r#"[{"question": "Is the cloth warmer than the blue ball?", "answer": "no", "question_family": "warmth",
             "answer_type": "open_ended", "qtype": "warmth", "video_id": "7", "question_id": "00001", "split": "test"}]"#,
    )
    .unwrap();
    fs_err::write(path.join("program.py"), "answer = 1\n").unwrap();
    let cases: [(&str, Vec<&str>); 12] = [
        ("wrong_path", vec!["--data", "no/such/dir"]),
        (
            "scenario_without_videos_in_the_root",
            vec!["--data", ".", "--scenario", "fluid"],
        ),
        ("empty_folder", vec!["--data", "empty"]),
        ("no_sampled_questions", vec!["--data", "."]),
        (
            "question_names_missing_video",
            vec![
                "--data",
                ".",
                "--questions",
                "pulley_group_extra.json",
                "--out",
                "r1",
            ],
        ),
        (
            "truncated_question_file",
            vec!["--data", ".", "--questions", "truncated.json"],
        ),
        (
            "scenario_unknown_from_file_name",
            vec!["--data", ".", "--questions", "questions.json"],
        ),
        ("corrupt_annotation", vec!["questions", "--data", "corrupt"]),
        (
            "fluid_video_without_tracking_data",
            vec!["questions", "--data", "fluid_no_tracking"],
        ),
        (
            "exec_missing_program",
            vec!["exec", "--video", "pulley_group/0", "--program", "nope.py"],
        ),
        (
            "exec_not_a_video",
            vec!["exec", "--video", "empty", "--program", "program.py"],
        ),
        ("score_not_a_run", vec!["score", "empty"]),
    ];
    let mut transcript = String::new();
    for (name, args) in cases {
        let output = contphy(path, &args);
        assert_eq!(output.status.code(), Some(1), "{name}: {}", stderr(&output));
        assert!(stdout(&output).is_empty(), "{name}: errors go to stderr");
        let message = normalise(&stderr(&output), path);
        assert!(!message.contains("panicked"), "{name}: {message}");
        let _ = writeln!(transcript, "## {name}\n{message}");
    }
    insta::assert_snapshot!("bad_input", transcript);
}

#[test]
fn usage_errors_exit_2() {
    let cases: [&[&str]; 3] = [
        &["--data", "eval/demo", "--scenario", "pulleys"],
        &["--data", "eval/demo", "--shard", "4/4"],
        &["run"],
    ];
    let mut transcript = String::new();
    for args in cases {
        let output = contphy(&root(), args);
        assert_eq!(
            output.status.code(),
            Some(2),
            "{args:?}: {}",
            stderr(&output)
        );
        let _ = writeln!(transcript, "## {}\n{}", args.join(" "), stderr(&output));
    }
    insta::assert_snapshot!("usage_errors", transcript);
}

#[test]
fn invalid_trials_are_skipped_with_a_count() {
    let data = temp_data_root();
    let invalid = data.path().join("pulley_group/1");
    fs_err::create_dir_all(&invalid).unwrap();
    fs_err::write(invalid.join("outputs.json"), r#"{"validity": false}"#).unwrap();
    let output = contphy(data.path(), &["questions", "--data", "."]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(
        stdout(&output).starts_with("1 videos (1 invalid skipped)"),
        "{}",
        stdout(&output)
    );
    let _ = demo();
}

/// `bench physics --scenario rope` with `arguments`: its report and its progress.
fn bench_rope(arguments: &[&str]) -> (serde_json::Value, String) {
    let output = contphy(
        &root(),
        &[&["bench", "physics", "--scenario", "rope"][..], arguments].concat(),
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let report: serde_json::Value = serde_json::from_str(&stdout(&output)).unwrap();
    (report, stderr(&output))
}

#[test]
fn bench_physics_reports_first_order_convergence_and_writes_the_plot() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("rope.svg");
    let (report, _) = bench_rope(&["--dt", "0.02,0.01,0.001", "--svg", svg.to_str().unwrap()]);
    let default_dt = report["default"]["dt_s"].as_f64().unwrap();
    for case in report["cases"].as_array().unwrap() {
        let sweep = case["sweep"].as_array().unwrap();
        let errors: Vec<(f64, f64)> = sweep
            .iter()
            .map(|r| {
                (
                    r["dt_s"].as_f64().unwrap(),
                    r["max_height_error_m"].as_f64().unwrap(),
                )
            })
            .collect();
        if case["reference"] == "closed form" {
            // Semi-implicit Euler under constant acceleration: error = ½·|a|·dt·T exactly.
            let per_dt = errors[0].1 / errors[0].0;
            for (dt, error) in &errors {
                assert!((error / dt / per_dt - 1.0).abs() < 0.01, "{case}");
            }
        }
        let at_default = errors
            .iter()
            .find(|(dt, _)| (dt - default_dt).abs() < 1e-15)
            .unwrap()
            .1;
        assert!(
            at_default < 5e-3,
            "{}: {at_default} m at the default step",
            case["case"]
        );
    }
    let plot = fs_err::read_to_string(&svg).unwrap();
    assert!(plot.starts_with("<svg") && plot.matches("<polyline").count() == 4);
}

#[test]
fn bench_physics_stores_reference_runs_and_compares_with_them_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("references");
    let run = || {
        bench_rope(&[
            "--dt",
            "0.02,0.01",
            "--reference-cache",
            cache.to_str().unwrap(),
        ])
    };
    let (first, first_progress) = run();
    let (second, second_progress) = run();
    let cases = |report: &serde_json::Value| report["cases"].as_array().unwrap().clone();
    let run_references = cases(&first)
        .iter()
        .filter(|case| case["reference"] != "closed form")
        .count();
    assert!(run_references > 0, "{first}");
    assert!(!first_progress.contains("stored ("), "{first_progress}");
    for (before, after) in cases(&first).iter().zip(&cases(&second)) {
        assert_eq!(before["case"], after["case"]);
        let ran = before["reference"] != "closed form";
        assert_eq!(before.get("reference_stored"), None, "{before}");
        assert_eq!(
            after["reference_stored"].as_bool(),
            ran.then_some(true),
            "{after}"
        );
        // The same reference, so the same errors, to the bit (JSON prints the shortest
        // round-trip form).
        let errors = |case: &serde_json::Value| -> Vec<String> {
            case["sweep"]
                .as_array()
                .unwrap()
                .iter()
                .map(|row| row["max_height_error_m"].to_string())
                .collect()
        };
        assert_eq!(errors(before), errors(after), "{}", before["case"]);
        // The run time shares are against the stored run's time.
        assert_eq!(
            before["reference_run_time_ms"], after["reference_run_time_ms"],
            "{}",
            before["case"]
        );
    }
    assert_eq!(
        second_progress.matches("stored (").count(),
        run_references,
        "{second_progress}"
    );
}

#[test]
fn bench_physics_errors_name_the_simulator_and_the_option() {
    let cases: [&[&str]; 9] = [
        &["--scenario", "cloth", "--dt", "0.01"],
        &["--scenario", "rope", "--reference-cache", "Cargo.toml"],
        &["--scenario", "rope", "--confirm"],
        &["--scenario", "fluid", "--ensemble-runs", "15"],
        &["--scenario", "cloth", "--ensemble-runs", "0"],
        &["--scenario", "fluid", "--dt", "0.01"],
        &["--scenario", "rope", "--video", "eval/demo/pulley_group/0"],
        &["--scenario", "fluid", "--grid-spacing", "0"],
        &["--scenario", "fluid", "--video", "no/such/video"],
    ];
    let mut transcript = String::new();
    for arguments in cases {
        let output = contphy(&root(), &[&["bench", "physics"][..], arguments].concat());
        assert_eq!(output.status.code(), Some(1), "{arguments:?}");
        let _ = writeln!(
            transcript,
            "## {}\n{}",
            arguments.join(" "),
            stderr(&output)
        );
    }
    insta::assert_snapshot!("bench_physics_errors", transcript);
}

#[test]
fn bench_mpm88_runs_the_solids_and_names_an_unknown_material() {
    let init = "tests/data/mpm88/init_8192_seed0.npy";
    for material in ["elastic", "plastic"] {
        let arguments = [
            "bench",
            "mpm88",
            "--init",
            init,
            "--steps",
            "20",
            "--material",
            material,
        ];
        let output = contphy(&root(), &arguments);
        assert!(output.status.success(), "{}", stderr(&output));
        let report: serde_json::Value = serde_json::from_str(&stdout(&output)).unwrap();
        assert_eq!(report["material"], material);
        assert_eq!(
            (report["steps"].as_u64(), report["clamped"].as_u64()),
            (Some(20), Some(0))
        );
        for key in [
            "mean_x",
            "mean_y",
            "kinetic_energy",
            "mean_J",
            "particle_steps_per_s",
        ] {
            let value = report[key].as_f64().unwrap_or(f64::NAN);
            assert!(value.is_finite() && value > 0.0, "{key}: {report}");
        }
    }
    let output = contphy(
        &root(),
        &["bench", "mpm88", "--init", init, "--material", "jelly"],
    );
    assert_eq!(output.status.code(), Some(2), "{}", stderr(&output));
    insta::assert_snapshot!("bench_mpm88_unknown_material", stderr(&output));
}

#[test]
fn dynamics_simulate_answers_every_demo_question_like_the_annotations() {
    // Every counterfactual and goal-driven option of the real video, answered by simulating the
    // rebuilt mechanism instead of reading the recorded outcomes.
    let dir = tempfile::tempdir().unwrap();
    let mut results = Vec::new();
    for dynamics in ["annotation", "simulate"] {
        let out = dir.path().join(dynamics);
        let output = contphy(
            &root(),
            &[
                "run",
                "--data",
                "eval/demo",
                "--questions",
                "eval/demo/pulley_group/0.json",
                "--out",
                out.to_str().unwrap(),
                "--dynamics",
                dynamics,
                "--quiet",
            ],
        );
        assert!(output.status.success(), "{}", stderr(&output));
        results.push(fs_err::read(out.join("results.json")).unwrap());
    }
    assert_eq!(results[0], results[1]);
    // Simulation runs are counted where they happen: only the runs the questions ask for (the
    // factual run and a lighter and a heavier run per load: at most 7), once per scene.
    let sim_runs = |run: &str| -> u64 {
        fs_err::read_to_string(dir.path().join(run).join("predictions.jsonl"))
            .unwrap()
            .lines()
            .map(|line| {
                let prediction: serde_json::Value = serde_json::from_str(line).unwrap();
                prediction["work"]["sim_runs"].as_u64().unwrap_or(0)
            })
            .sum()
    };
    assert_eq!(sim_runs("annotation"), 0);
    let simulated = sim_runs("simulate");
    assert!((1..=7).contains(&simulated), "{simulated} simulation runs");
    let scores: serde_json::Value = serde_json::from_slice(&results[1]).unwrap();
    assert_eq!(scores["scores"]["units_answered"], 384);
    assert!(scores["scores"]["failures"].as_object().unwrap().is_empty());
}

/// Without a decoder, every command that would decode a video stops before its first unit with
/// one line naming ffmpeg and how to install it (exit 1), instead of failing each unit.
#[test]
fn a_missing_decoder_stops_commands_before_their_first_unit() {
    let empty = tempfile::tempdir().unwrap();
    let out = tempfile::tempdir().unwrap();
    let run = out.path().join("run");
    let generated = out.path().join("generated");
    let cases: [(&str, Vec<&str>); 3] = [
        (
            "run",
            vec![
                "--data",
                "eval/demo",
                "--perception",
                "maskrcnn",
                "--dynamics",
                "simulate",
                "--out",
                run.to_str().unwrap(),
            ],
        ),
        (
            "exec",
            vec![
                "exec",
                "--video",
                "eval/demo/pulley_group/0",
                "--program",
                "tests/fixtures/programs/color.py",
                "--perception",
                "maskrcnn",
            ],
        ),
        (
            "generate",
            vec![
                "generate",
                "--scenario",
                "rope",
                "--videos",
                "1",
                "--frames",
                "mp4",
                "--out",
                generated.to_str().unwrap(),
            ],
        ),
    ];
    let mut transcript = String::new();
    for (name, args) in cases {
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_contphy-eval"))
            .args(&args)
            .current_dir(root())
            .env("NO_COLOR", "1")
            .env("CONTPHY_FFMPEG_DIR", empty.path())
            .output()
            .unwrap();
        let message = stderr(&output)
            .replace(&out.path().display().to_string(), "[TEMP]")
            .replace(&root().display().to_string(), "[ROOT]");
        assert_eq!(output.status.code(), Some(1), "{name}: {message}");
        assert_eq!(message.lines().count(), 1, "{name}: one line: {message}");
        assert!(message.contains("ffmpeg"), "{name}: {message}");
        let _ = writeln!(transcript, "## {name}\n{message}");
    }
    assert!(!run.join("predictions.jsonl").exists(), "no unit ran");
    insta::assert_snapshot!("missing_decoder", transcript);
}
