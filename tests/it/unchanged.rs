//! Rope outputs byte for byte as they were before the scenario seam (issue 11): the questions
//! the engine writes for several seeds, the files `generate --frames none` writes, and the demo
//! run's `results.json` and `predictions.jsonl` (timings removed) under every pair of backends.
//!
//! The hashes were taken from the build before the refactor that moved rope into per-scenario
//! folders (`CONTPHY_UNCHANGED_BINARY=<that binary> cargo test unchanged` prints a build's
//! hashes in the failure message); a refactor that changes any rope output fails here. A
//! deliberate change of rope behaviour updates them, with the reason in the commit.

use std::path::Path;

use std::process::{Command, Output};

use crate::support::{predictions_without_timings, root, stderr};

/// Runs the binary under test: this build's, or the one `CONTPHY_UNCHANGED_BINARY` names (to
/// take the hashes of another build, e.g. the release before a refactor).
fn contphy(dir: &Path, args: &[&str]) -> Output {
    let binary = std::env::var_os("CONTPHY_UNCHANGED_BINARY").map_or_else(
        || env!("CARGO_BIN_EXE_contphy-eval").into(),
        std::path::PathBuf::from,
    );
    Command::new(binary)
        .args(args)
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .output()
        .expect("the binary runs")
}

/// blake3 over every file under `dir` (sorted by relative path): path, length, bytes.
fn tree_hash(dir: &Path, skip: &[&str]) -> String {
    fn walk(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
        for entry in fs_err::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else {
                out.push(path);
            }
        }
    }
    let mut files = Vec::new();
    walk(dir, &mut files);
    files.sort();
    let mut hasher = blake3::Hasher::new();
    for file in files {
        let relative = file
            .strip_prefix(dir)
            .unwrap()
            .to_string_lossy()
            .into_owned();
        if skip.iter().any(|s| relative == *s) {
            continue;
        }
        let bytes = fs_err::read(&file).unwrap();
        hasher.update(relative.as_bytes());
        hasher.update(&(bytes.len() as u64).to_le_bytes());
        hasher.update(&bytes);
    }
    hasher.finalize().to_hex().to_string()
}

/// blake3 of `results.json` and of the predictions without their `*_ms` fields.
fn run_hash(run: &Path) -> String {
    let mut hasher = blake3::Hasher::new();
    hasher.update(&fs_err::read(run.join("results.json")).unwrap());
    for prediction in predictions_without_timings(run) {
        hasher.update(serde_json::to_string(&prediction).unwrap().as_bytes());
        hasher.update(b"\n");
    }
    hasher.finalize().to_hex().to_string()
}

fn check(what: &str, actual: &str, expected: &str, mismatches: &mut Vec<String>) {
    if actual != expected {
        mismatches.push(format!("{what}: {actual} (expected {expected})"));
    }
}

#[test]
fn engine_questions_for_several_seeds_are_unchanged() {
    const EXPECTED: [(&str, &str); 4] = [
        (
            "0",
            "f90fbe4ebe114996396dff8451ab4bb6c1347543accf4f48223f693efaac2c18",
        ),
        (
            "1",
            "120bfdab218af85db1fd5610361214478328fc45cbbaa2ab0c00f0ccc79c13b4",
        ),
        (
            "7",
            "e8dce2f410f7abb7a1f8156c9f8ed9d1ddb4e8cb23cff94e6e70f137068c52d9",
        ),
        (
            "2024",
            "ff33a41d14dc9af75befa64e2a93726d974d3c6c4e343f285cf9358656e38649",
        ),
    ];
    let out = tempfile::tempdir().unwrap();
    let mut mismatches = Vec::new();
    for (seed, expected) in EXPECTED {
        let dir = out.path().join(seed);
        let output = contphy(
            &root(),
            &[
                "questions",
                "--data",
                "eval/demo",
                "--seed",
                seed,
                "--out",
                dir.to_str().unwrap(),
            ],
        );
        assert!(output.status.success(), "{}", stderr(&output));
        // The rope files only: the demo also holds generated fluid, cloth and ball videos,
        // whose questions are their own engines' (with their own tests).
        check(
            &format!("questions --seed {seed}"),
            &tree_hash(
                &dir,
                &[
                    "fluid_slides/0.json",
                    "fluid_slides/1.json",
                    "fluid_slides_train.json",
                    "fluid_slides_val.json",
                    "fluid_slides_test.json",
                    "cloth_collision/0.json",
                    "cloth_collision/1.json",
                    "cloth_collision_train.json",
                    "cloth_collision_val.json",
                    "cloth_collision_test.json",
                    "soft_body/0.json",
                    "soft_body/1.json",
                    "soft_body_train.json",
                    "soft_body_val.json",
                    "soft_body_test.json",
                ],
            ),
            expected,
            &mut mismatches,
        );
    }
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
}

#[test]
fn generated_videos_questions_and_their_runs_are_unchanged() {
    // Changed with the release-like hollow pulley (a holed web: other masks, boxes and 4-D
    // faces, its inward hole walls wound like the ring's inner wall); the questions and both runs
    // below kept their hashes. The runs' hashes changed once more when RND's answer space of a
    // yes/no family became {yes, no} even where every evaluated answer is the same: in
    // results.json two families' RND expectations fell (6 → 5 and 2 → 1 questions), nothing else.
    const GENERATED: &str = "bec2969e49551da158af948a7d69e088587873add7e2366b154403b303c8a43d";
    const RUNS: [(&str, &str); 2] = [
        (
            "annotation",
            "fa6465f2fb54c351686d16ec00306ec6ad8e7832469aba336d8f47c4c627b5b9",
        ),
        (
            "simulate",
            "64262c3d96e824619780f3a14f9f2409229ff9bb1b639ee7a82e9281bb0e99c2",
        ),
    ];
    let out = tempfile::tempdir().unwrap();
    let data = out.path().join("data");
    let output = contphy(
        &root(),
        &[
            "generate",
            "--scenario",
            "rope",
            "--videos",
            "3",
            "--seed",
            "11",
            "--frames",
            "none",
            "--jobs",
            "2",
            "--quiet",
            "--out",
            data.to_str().unwrap(),
        ],
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let mut mismatches = Vec::new();
    // `generate.json` records wall times; everything else is content.
    check(
        "generate --videos 3 --seed 11 --frames none",
        &tree_hash(&data, &["generate.json"]),
        GENERATED,
        &mut mismatches,
    );
    for (dynamics, expected) in RUNS {
        let run = out.path().join(dynamics);
        let output = contphy(
            &root(),
            &[
                "--data",
                data.to_str().unwrap(),
                "--split",
                "all",
                "--dynamics",
                dynamics,
                // Generous budgets: on a loaded machine a program may overrun the default 5 s,
                // and a timed-out unit would change the results (not what this test is about).
                "--program-timeout",
                "600",
                "--api-timeout",
                "3600",
                "--quiet",
                "--out",
                run.to_str().unwrap(),
            ],
        );
        assert!(output.status.success(), "{}", stderr(&output));
        check(
            &format!("generated data, --dynamics {dynamics}"),
            &run_hash(&run),
            expected,
            &mut mismatches,
        );
    }
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
}

#[test]
fn demo_results_under_every_backend_pair_are_unchanged() {
    const EXPECTED: [(&str, &str, &str); 4] = [
        (
            "annotation",
            "annotation",
            "b616785f3175a00919b38b45b4e20acdff20517eb8be342b897e61da5615b2b2",
        ),
        (
            "annotation",
            "simulate",
            "90f242b1420f29831bf792b4f37374651ae4a4a57365923e6de597d5e5043fd1",
        ),
        (
            "maskrcnn",
            "annotation",
            "424263f1ba81db5e3ba3a3309a676bdc4b1e6f42cbff6f692dade69934acb4a0",
        ),
        (
            "maskrcnn",
            "simulate",
            "5750bd4fc9fabeab9d2005f2d720e606f296afb1dd5de07aad09149b2a784b9a",
        ),
    ];
    let out = tempfile::tempdir().unwrap();
    let mut mismatches = Vec::new();
    for (perception, dynamics, expected) in EXPECTED {
        let run = out.path().join(format!("{perception}-{dynamics}"));
        let output = contphy(
            &root(),
            &[
                "--data",
                "eval/demo",
                "--questions",
                "eval/demo/pulley_group/0.json",
                "--perception",
                perception,
                "--dynamics",
                dynamics,
                // Generous budgets: on a loaded machine a program may overrun the default 5 s,
                // and a timed-out unit would change the results (not what this test is about).
                "--program-timeout",
                "600",
                "--api-timeout",
                "3600",
                "--quiet",
                "--out",
                run.to_str().unwrap(),
            ],
        );
        assert!(output.status.success(), "{}", stderr(&output));
        check(
            &format!("demo, --perception {perception} --dynamics {dynamics}"),
            &run_hash(&run),
            expected,
            &mut mismatches,
        );
    }
    assert!(mismatches.is_empty(), "{}", mismatches.join("\n"));
}
