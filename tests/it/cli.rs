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
    fs_err::write(
        path.join("pulley_group_extra.json"),
        r#"[{"question": "Is there any red cube in the video?", "answer": "no", "question_family": "existence",
             "answer_type": "open_ended", "qtype": "existence", "video_id": "7", "question_id": "00001", "split": "test"}]"#,
    )
    .unwrap();
    fs_err::write(path.join("truncated.json"), r#"[{"question": "Is there"#).unwrap();
    fs_err::copy(
        path.join("pulley_group_extra.json"),
        path.join("questions.json"),
    )
    .unwrap();
    fs_err::write(path.join("program.py"), "answer = 1\n").unwrap();
    let cases: [(&str, Vec<&str>); 10] = [
        ("wrong_path", vec!["--data", "no/such/dir"]),
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
