//! Sharding: `--shard I/N` splits the questions deterministically, `score` merges the shard run
//! directories into exactly the unsharded result, and the scheduler recipes in `eval/scale-out/`
//! (a Slurm array job, a Kubernetes Indexed Job) map their task indices onto every shard once.

use std::collections::BTreeSet;
use std::process::Command;

use serde_json::Value;

use crate::support::{contphy, root, stderr, stdout};

fn run(out: &std::path::Path, shard: Option<&str>) {
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
    if let Some(shard) = shard {
        args.extend(["--shard", shard]);
    }
    let output = contphy(&root(), &args);
    assert!(output.status.success(), "{}", stderr(&output));
}

fn scores_json(runs: &[&std::path::Path]) -> Value {
    let mut args = vec!["score", "--json"];
    args.extend(runs.iter().map(|r| r.to_str().unwrap()));
    let output = contphy(&root(), &args);
    assert!(output.status.success(), "{}", stderr(&output));
    serde_json::from_str(&stdout(&output)).unwrap()
}

#[test]
fn merged_shards_score_exactly_like_the_unsharded_run() {
    let dir = tempfile::tempdir().unwrap();
    let whole = dir.path().join("whole");
    run(&whole, None);
    let shards: Vec<_> = (0..3)
        .map(|i| dir.path().join("sharded").join(format!("shard-{i}")))
        .collect();
    for (index, shard) in shards.iter().enumerate() {
        run(shard, Some(&format!("{index}/3")));
    }
    // Every question is in exactly one shard.
    let mut seen = BTreeSet::new();
    for shard in &shards {
        let questions: Value =
            serde_json::from_slice(&fs_err::read(shard.join("questions.json")).unwrap()).unwrap();
        for question in questions["questions"].as_array().unwrap() {
            assert!(
                seen.insert(question["id"].as_str().unwrap().to_string()),
                "a question in two shards"
            );
        }
    }
    assert_eq!(seen.len(), 185);

    let unsharded = scores_json(&[&whole]);
    let merged = scores_json(
        &shards
            .iter()
            .map(std::path::PathBuf::as_path)
            .rev()
            .collect::<Vec<_>>(),
    );
    assert_eq!(
        merged["runs"].as_array().unwrap().len(),
        1,
        "three shards, one column"
    );
    assert_eq!(merged["runs"][0]["name"], "sharded (3 shards)");
    assert_eq!(merged["runs"][0]["scores"], unsharded["runs"][0]["scores"]);

    let partial = contphy(
        &root(),
        &[
            "score",
            shards[0].to_str().unwrap(),
            shards[2].to_str().unwrap(),
        ],
    );
    assert!(
        stderr(&partial).contains("shards 0, 2 of a 3-shard run are not a complete set"),
        "{}",
        stderr(&partial)
    );
}

/// Runs `script` under bash with `contphy-eval` replaced by a function printing its arguments,
/// and returns the value given to `--shard`.
fn shard_argument(script: &str, environment: &[(&str, String)]) -> String {
    let output = Command::new("bash")
        .arg("-c")
        .arg(format!(
            "contphy-eval() {{ printf '%s\\n' \"$@\"; }}\n{script}"
        ))
        .envs(environment.iter().map(|(k, v)| (*k, v.as_str())))
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let printed = String::from_utf8_lossy(&output.stdout).into_owned();
    let lines: Vec<&str> = printed.lines().collect();
    let at = lines
        .iter()
        .position(|line| *line == "--shard")
        .expect("the recipe passes --shard");
    lines[at + 1].to_string()
}

#[test]
fn slurm_array_and_kubernetes_indexed_job_cover_every_shard_once() {
    let slurm = fs_err::read_to_string(root().join("eval/scale-out/slurm-array.sbatch")).unwrap();
    let slurm_body: String = slurm
        .lines()
        .filter(|l| !l.starts_with("#SBATCH"))
        .collect::<Vec<_>>()
        .join("\n");
    // `--array=0-3` and `--array=1-4` must both map onto shards 0/4 .. 3/4.
    for first in [0, 1] {
        let shards: Vec<String> = (first..first + 4)
            .map(|task| {
                shard_argument(
                    &slurm_body,
                    &[
                        ("SLURM_ARRAY_TASK_ID", task.to_string()),
                        ("SLURM_ARRAY_TASK_MIN", first.to_string()),
                        ("SLURM_ARRAY_TASK_COUNT", "4".to_string()),
                    ],
                )
            })
            .collect();
        assert_eq!(
            shards,
            ["0/4", "1/4", "2/4", "3/4"],
            "slurm --array starting at {first}"
        );
    }

    let job = fs_err::read_to_string(root().join("eval/scale-out/k8s-indexed-job.yaml")).unwrap();
    let completions: usize = job
        .lines()
        .find_map(|l| l.trim().strip_prefix("completions:"))
        .unwrap()
        .trim()
        .parse()
        .unwrap();
    let shard_count = job
        .lines()
        .skip_while(|l| !l.contains("name: SHARD_COUNT"))
        .nth(1)
        .unwrap();
    assert!(
        shard_count.contains(&format!("\"{completions}\"")),
        "SHARD_COUNT must equal completions"
    );
    // The container command: the folded block after `args:`.
    let command: String = job
        .lines()
        .skip_while(|l| !l.trim_start().starts_with("- >-"))
        .skip(1)
        .take_while(|l| !l.trim_start().starts_with("volumeMounts:"))
        .map(str::trim)
        .collect::<Vec<_>>()
        .join(" ");
    let shards: Vec<String> = (0..completions)
        .map(|index| {
            shard_argument(
                &command,
                &[
                    ("JOB_COMPLETION_INDEX", index.to_string()),
                    ("SHARD_COUNT", completions.to_string()),
                ],
            )
        })
        .collect();
    let expected: Vec<String> = (0..completions)
        .map(|i| format!("{i}/{completions}"))
        .collect();
    assert_eq!(shards, expected);
}
