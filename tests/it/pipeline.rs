//! End-to-end runs on the real rope video: builtin programs with oracle backends must score 100%
//! on every family; runs are deterministic, resumable, cacheable and re-scorable.

use std::path::Path;

use serde_json::Value;

use crate::support::{contphy, predictions_without_timings, root, stderr, stdout, temp_data_root};

fn run_all_questions(out: &Path, extra: &[&str]) -> std::process::Output {
    // Relative paths, as a user types them (the report quotes them).
    let mut args = vec![
        "run",
        "--data",
        "eval/demo",
        "--questions",
        "eval/demo/pulley_group/0.json",
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    contphy(&root(), &args)
}

fn results(run: &Path) -> Value {
    serde_json::from_slice(&fs_err::read(run.join("results.json")).unwrap()).unwrap()
}

/// Asserts that every family of a run is answered perfectly.
fn assert_perfect(run: &Path) {
    let results = results(run);
    let families = results["scores"]["families"].as_array().unwrap();
    // Seven or eight families: tension questions exist only for some engine seeds.
    assert!(
        families.len() >= 7,
        "expected the rope families, got {}",
        families.len()
    );
    for family in families {
        let model = &family["model"];
        assert_eq!(
            model["questions_correct"], model["questions"],
            "family {}: {model}",
            family["family"]
        );
        assert_eq!(
            model["options_correct"], model["options"],
            "family {}: {model}",
            family["family"]
        );
    }
    assert_eq!(results["scores"]["failures"], serde_json::json!({}));
    assert_eq!(results["scores"]["missing_units"], 0);
}

#[test]
fn demo_run_scores_100_percent_on_every_family_and_property_questions_never_simulate() {
    let out = tempfile::tempdir().unwrap();
    let run = out.path().join("demo");
    let output = run_all_questions(&run, &[]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_perfect(&run);
    let predictions = predictions_without_timings(&run);
    assert_eq!(predictions.len(), 384, "units of the demo questions");
    for prediction in &predictions {
        assert_eq!(prediction["work"]["sim_runs"], 0, "{prediction}");
        assert_eq!(prediction["work"]["frames_decoded"], 0, "{prediction}");
    }
    let loads: u64 = predictions
        .iter()
        .map(|p| p["work"]["annotation_loads"].as_u64().unwrap())
        .sum();
    assert_eq!(loads, 1, "one worker loads the one video once");
    let report = fs_err::read_to_string(run.join("report.md")).unwrap();
    insta::assert_snapshot!("demo_report", report);
    assert!(
        stdout(&output).starts_with("# contphy-eval report: demo"),
        "the report goes to stdout"
    );
}

#[test]
fn two_runs_give_identical_predictions_and_results() {
    let out = tempfile::tempdir().unwrap();
    let (first, second) = (out.path().join("first"), out.path().join("second"));
    assert!(run_all_questions(&first, &["--jobs", "2"]).status.success());
    assert!(
        run_all_questions(&second, &["--jobs", "1"])
            .status
            .success()
    );
    assert_eq!(
        predictions_without_timings(&first),
        predictions_without_timings(&second)
    );
    assert_eq!(
        fs_err::read(first.join("results.json")).unwrap(),
        fs_err::read(second.join("results.json")).unwrap()
    );
    let strip = |run: &Path| -> String {
        fs_err::read_to_string(run.join("predictions.jsonl"))
            .unwrap()
            .lines()
            .map(|line| {
                // Byte-level check: only the `_ms` fields may differ.
                let mut value: serde_json::Map<String, Value> = serde_json::from_str(line).unwrap();
                for (key, field) in &mut value {
                    if key.ends_with("_ms") {
                        *field = Value::Null;
                    }
                }
                serde_json::to_string(&value).unwrap()
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(strip(&first), strip(&second));
}

#[test]
fn resume_keeps_finished_units_and_runs_only_the_rest() {
    let out = tempfile::tempdir().unwrap();
    let run = out.path().join("run");
    assert!(run_all_questions(&run, &[]).status.success());
    let complete = predictions_without_timings(&run);
    // Simulate a crash: keep 250 lines, mark them, and leave a torn half line at the end.
    let text = fs_err::read_to_string(run.join("predictions.jsonl")).unwrap();
    let mut kept: Vec<String> = text
        .lines()
        .take(250)
        .map(|line| {
            let mut value: serde_json::Map<String, Value> = serde_json::from_str(line).unwrap();
            value.insert("wall_ms".into(), Value::from(999_999));
            serde_json::to_string(&value).unwrap()
        })
        .collect();
    kept.push("{\"unit\":\"0/color/3\",\"question_".to_string());
    fs_err::write(run.join("predictions.jsonl"), kept.join("\n")).unwrap();

    let refused = run_all_questions(&run, &[]);
    assert_eq!(refused.status.code(), Some(1));
    assert!(
        stderr(&refused).contains("already holds a run; pass --resume"),
        "{}",
        stderr(&refused)
    );
    let changed = run_all_questions(&run, &["--resume", "--program-timeout", "9"]);
    assert_eq!(changed.status.code(), Some(1));
    assert!(
        stderr(&changed).contains("holds a run with different settings"),
        "{}",
        stderr(&changed)
    );

    let resumed = run_all_questions(&run, &["--resume"]);
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    assert!(
        stderr(&resumed).contains("resuming: 250 of 384 units already done"),
        "{}",
        stderr(&resumed)
    );
    // Work counters show the work each run did: the resumed run loads the video once more.
    let without_work = |predictions: Vec<Value>| -> Vec<Value> {
        predictions
            .into_iter()
            .map(|mut p| {
                p.as_object_mut().unwrap().remove("work");
                p
            })
            .collect()
    };
    let resumed_predictions = without_work(predictions_without_timings(&run));
    let complete = without_work(complete);
    assert_eq!(resumed_predictions.len(), complete.len());
    let differing = resumed_predictions
        .iter()
        .zip(&complete)
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(
        differing, 0,
        "the resumed run completes the same predictions"
    );
    let marked = fs_err::read_to_string(run.join("predictions.jsonl"))
        .unwrap()
        .lines()
        .filter(|line| line.contains("\"wall_ms\":999999"))
        .count();
    assert_eq!(marked, 250, "finished units are kept, not redone");
    assert_perfect(&run);
}

#[test]
fn cache_records_programs_and_offline_replays_them() {
    let out = tempfile::tempdir().unwrap();
    let cache = out.path().join("cache");
    let (recorded, replayed, missed) = (
        out.path().join("recorded"),
        out.path().join("replayed"),
        out.path().join("missed"),
    );
    assert!(
        run_all_questions(&recorded, &["--cache", cache.to_str().unwrap()])
            .status
            .success()
    );
    let listing = contphy(
        &root(),
        &["cache", "ls", "--cache", cache.to_str().unwrap()],
    );
    assert!(listing.status.success());
    let listed = stdout(&listing);
    assert!(listed.trim_end().ends_with("384 programs"), "{listed}");
    assert!(listed.contains("| builtin | 0/mass/0 |"), "{listed}");

    let output = run_all_questions(
        &replayed,
        &["--cache", cache.to_str().unwrap(), "--offline"],
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let without_origin = |run: &Path| -> Vec<Value> {
        predictions_without_timings(run)
            .into_iter()
            .map(|mut p| {
                assert!(p["program_origin"].is_string());
                p.as_object_mut().unwrap().remove("program_origin");
                p
            })
            .collect()
    };
    assert_eq!(without_origin(&recorded), without_origin(&replayed));
    assert!(
        predictions_without_timings(&replayed)
            .iter()
            .all(|p| p["program_origin"] == "cache")
    );

    // Another user: export the run's programs, import them into a fresh cache, replay offline.
    let exported = out.path().join("programs.jsonl");
    let export = contphy(
        &root(),
        &[
            "cache",
            "export",
            "--cache",
            cache.to_str().unwrap(),
            "--run",
            recorded.to_str().unwrap(),
            "--out",
            exported.to_str().unwrap(),
        ],
    );
    assert!(export.status.success(), "{}", stderr(&export));
    assert_eq!(
        fs_err::read_to_string(&exported).unwrap().lines().count(),
        384
    );
    let fresh = out.path().join("fresh-cache");
    let import = contphy(
        &root(),
        &[
            "cache",
            "import",
            "--cache",
            fresh.to_str().unwrap(),
            exported.to_str().unwrap(),
        ],
    );
    assert!(import.status.success(), "{}", stderr(&import));
    let elsewhere = out.path().join("elsewhere");
    assert!(
        run_all_questions(
            &elsewhere,
            &["--cache", fresh.to_str().unwrap(), "--offline"]
        )
        .status
        .success()
    );
    assert_eq!(without_origin(&recorded), without_origin(&elsewhere));

    let empty = out.path().join("empty-cache");
    fs_err::create_dir_all(&empty).unwrap();
    let output = run_all_questions(&missed, &["--cache", empty.to_str().unwrap(), "--offline"]);
    assert!(
        output.status.success(),
        "a cache miss fails units, not the run: {}",
        stderr(&output)
    );
    let failures = &results(&missed)["scores"]["failures"];
    assert_eq!(failures["program"]["cache_miss"], 384, "{failures}");
}

#[test]
fn score_prints_one_leaderboard_over_saved_runs() {
    let out = tempfile::tempdir().unwrap();
    let (full, empty_cache) = (out.path().join("builtin"), out.path().join("offline-miss"));
    assert!(run_all_questions(&full, &[]).status.success());
    let cache = out.path().join("none");
    fs_err::create_dir_all(&cache).unwrap();
    assert!(
        run_all_questions(
            &empty_cache,
            &["--cache", cache.to_str().unwrap(), "--offline"]
        )
        .status
        .success()
    );
    let output = contphy(out.path(), &["score", "builtin", "offline-miss"]);
    assert!(output.status.success(), "{}", stderr(&output));
    insta::assert_snapshot!("leaderboard", stdout(&output));
}

#[test]
fn questions_from_many_engine_seeds_are_all_answered_correctly() {
    // Every seed draws different mass/tension statements and counterfactual option sets; the
    // builtin programs must get all of them right, or the engine, writer or API has a bug.
    let data = temp_data_root();
    for seed in 1..=6 {
        let seed = seed.to_string();
        let questions_output = contphy(data.path(), &["questions", "--data", ".", "--seed", &seed]);
        assert!(
            questions_output.status.success(),
            "{}",
            stderr(&questions_output)
        );
        let run = data.path().join(format!("run-{seed}"));
        let output = contphy(
            data.path(),
            &[
                "--data",
                ".",
                "--questions",
                "pulley_group/0.json",
                "--out",
                run.to_str().unwrap(),
                "--quiet",
            ],
        );
        assert!(output.status.success(), "seed {seed}: {}", stderr(&output));
        assert_perfect(&run);
    }
}

#[test]
fn default_run_evaluates_the_sampled_test_split() {
    let data = temp_data_root();
    assert!(
        contphy(data.path(), &["questions", "--data", "."])
            .status
            .success()
    );
    let output = contphy(
        data.path(),
        &["--data", ".", "--out", "runs/test-split", "--quiet"],
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let questions: Value = serde_json::from_slice(
        &fs_err::read(data.path().join("runs/test-split/questions.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(
        questions["questions"].as_array().unwrap().len(),
        4,
        "2 property + 2 dynamics questions of the one (test) video"
    );
}

#[test]
fn per_question_programs_answer_every_option_and_score_the_same() {
    let out = tempfile::tempdir().unwrap();
    let run = out.path().join("per-question");
    let output = run_all_questions(&run, &["--per-question"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert_perfect(&run);
    let predictions = predictions_without_timings(&run);
    assert_eq!(predictions.len(), 384);
    // One program per choice question: every option of a question shares it, and its work is
    // recorded once, on the first option.
    let options: Vec<&Value> = predictions
        .iter()
        .filter(|p| {
            p["unit"]
                .as_str()
                .unwrap()
                .starts_with("0/rope_goaldriven/0:")
        })
        .collect();
    assert!(options.len() >= 3);
    assert!(
        options
            .iter()
            .all(|p| p["program_hash"] == options[0]["program_hash"])
    );
    assert!(options[0]["work"]["api_calls"].as_u64().unwrap() > 0);
    assert!(options[1..].iter().all(|p| p["work"]["api_calls"] == 0));
}

/// Builtin runs write each prediction as its program finishes, as LLM runs do: with one program
/// that runs on (a cached stand-in that loops), the other units' predictions are on disk while
/// it runs, so a crash then loses only the unit in flight.
#[test]
fn builtin_runs_write_each_prediction_as_it_completes() {
    use std::process::{Command, Stdio};
    use std::time::{Duration, Instant};

    let out = tempfile::tempdir().unwrap();
    let first = out.path().join("first");
    let cache = out.path().join("cache");
    let limit = ["--limit", "12"];
    let made = run_all_questions(
        &first,
        &[&["--cache", cache.to_str().unwrap()][..], &limit].concat(),
    );
    assert!(made.status.success(), "{}", stderr(&made));
    let exported = out.path().join("programs.jsonl");
    let export = contphy(
        &root(),
        &[
            "cache",
            "export",
            "--cache",
            cache.to_str().unwrap(),
            "--run",
            first.to_str().unwrap(),
            "--out",
            exported.to_str().unwrap(),
        ],
    );
    assert!(export.status.success(), "{}", stderr(&export));
    // The last unit's program becomes one that never returns (a video's units run on one
    // worker, in order, so the others run before it).
    let text = fs_err::read_to_string(&exported).unwrap();
    let mut lines: Vec<Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let last = lines.len() - 1;
    lines[last]["program"] =
        Value::from("def execute_command(video):\n    while True:\n        pass\n");
    let edited: Vec<String> = lines.iter().map(ToString::to_string).collect();
    fs_err::write(&exported, edited.join("\n") + "\n").unwrap();
    let looping_cache = out.path().join("looping");
    let import = contphy(
        &root(),
        &[
            "cache",
            "import",
            "--cache",
            looping_cache.to_str().unwrap(),
            exported.to_str().unwrap(),
        ],
    );
    assert!(import.status.success(), "{}", stderr(&import));

    let run = out.path().join("second");
    let mut child = Command::new(env!("CARGO_BIN_EXE_contphy-eval"))
        .args([
            "run",
            "--data",
            "eval/demo",
            "--questions",
            "eval/demo/pulley_group/0.json",
            "--cache",
            looping_cache.to_str().unwrap(),
            "--program-timeout",
            "120",
            "--quiet",
            "--out",
            run.to_str().unwrap(),
        ])
        .args(limit)
        .current_dir(root())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let units = predictions_without_timings(&first).len();
    let started = Instant::now();
    let mut written = 0;
    while started.elapsed() < Duration::from_secs(90) {
        written = fs_err::read_to_string(run.join("predictions.jsonl"))
            .map_or(0, |text| text.lines().count());
        if written == units - 1 {
            break;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    // The looping program is still running (its budget is 120 s): kill the run as a crash.
    let still_running = child.try_wait().unwrap().is_none();
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(still_running, "the run ended before it was killed");
    assert_eq!(
        written,
        units - 1,
        "every unit but the one in flight was written before the crash"
    );
}
