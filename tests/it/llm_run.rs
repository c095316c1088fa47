//! Whole runs with `--model` against the loopback mock server (127.0.0.1 only): the mock answers
//! each rendered prompt of the demo questions with the builtin writer's program for it, so a
//! correct pipeline scores 100%. Then the faults a real endpoint has on a bad day, a run killed
//! with SIGKILL and resumed, an offline replay, and the errors a new user meets.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::Arc;

use contphy_eval::dataset::{Question, load_question_file};
use contphy_eval::llm::mock::{MOCK_MODEL, MockReply, MockRequest, MockServer, MockServerBuilder};
use contphy_eval::program::builtin::{write_program, write_question_program};
use contphy_eval::prompt::{PromptMode, render};
use serde_json::Value;

use crate::support::{root, stderr, stdout};

const QUESTIONS: &str = "eval/demo/pulley_group/0.json";
/// A key the tests set, to check that it never reaches a file.
const SECRET_KEY: &str = "sk-contphy-test-0123456789-secret";

/// A mock server with the runtime it runs on (the server is dropped first).
struct Mock {
    server: MockServer,
    _runtime: tokio::runtime::Runtime,
}

impl Mock {
    fn start(builder: MockServerBuilder) -> Mock {
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .enable_all()
            .build()
            .unwrap();
        let server = runtime.block_on(builder.start()).unwrap();
        Mock {
            server,
            _runtime: runtime,
        }
    }

    fn url(&self) -> String {
        self.server.base_url()
    }
}

fn demo_questions() -> Vec<Question> {
    load_question_file(&root().join(QUESTIONS), None)
        .unwrap()
        .questions
}

/// The first user message of every prompt the demo run sends, in both modes, mapped to a
/// completion holding the builtin program for that unit: what a perfect model would write.
fn perfect_answers() -> Arc<BTreeMap<String, String>> {
    let mut answers = BTreeMap::new();
    for question in demo_questions() {
        let mut units: Vec<(PromptMode, Option<usize>)> = Vec::new();
        if question.answer_type.is_choice() {
            units.extend((0..question.options.len()).map(|i| (PromptMode::PerOption, Some(i))));
            units.push((PromptMode::PerQuestion, None));
        } else {
            units.push((PromptMode::PerOption, None));
        }
        for (mode, option) in units {
            let option = option.map(|i| &question.options[i]);
            let prompt = render(&question, option, mode).unwrap();
            let program = if mode == PromptMode::PerQuestion {
                write_question_program(&question).unwrap()
            } else {
                write_program(&question, option).unwrap()
            };
            let completion = format!("Here is the program.\n\n```python\n{program}\n```\n");
            answers.insert(prompt.user, completion);
        }
    }
    Arc::new(answers)
}

/// The first user message of a chat request (the rendered prompt; later ones are repair turns).
fn first_user_text(request: &MockRequest) -> Option<String> {
    request
        .json
        .as_ref()?
        .get("messages")?
        .as_array()?
        .iter()
        .find(|m| m.get("role").and_then(Value::as_str) == Some("user"))?
        .get("content")?
        .as_str()
        .map(str::to_owned)
}

/// A responder answering every known prompt perfectly (and anything else with a refusal).
fn perfect(answers: Arc<BTreeMap<String, String>>) -> impl Fn(&MockRequest) -> MockReply {
    move |request| match first_user_text(request).and_then(|text| answers.get(&text).cloned()) {
        Some(completion) => MockReply::ok(completion),
        None => MockReply::ok("I cannot help with that."),
    }
}

/// `contphy-eval` with `args`, no key unless `key`, and nothing from the caller's environment
/// that could reach a real endpoint.
fn command(args: &[&str], key: Option<&str>) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_contphy-eval"));
    command
        .args(args)
        .current_dir(root())
        .env("NO_COLOR", "1")
        .env_remove("OPENAI_API_KEY")
        .env_remove("HTTPS_PROXY")
        .env_remove("HTTP_PROXY")
        .env_remove("ALL_PROXY");
    if let Some(key) = key {
        command.env("OPENAI_API_KEY", key);
    }
    command
}

fn run(args: &[&str], key: Option<&str>) -> Output {
    command(args, key).output().unwrap()
}

/// `run` arguments for the demo questions against `url`.
fn run_args<'a>(url: &'a str, out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "run",
        "--data",
        "eval/demo",
        "--questions",
        QUESTIONS,
        "--out",
        out,
        "--quiet",
        "--model",
        MOCK_MODEL,
        "--base-url",
        url,
    ];
    args.extend_from_slice(extra);
    args
}

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&fs_err::read_to_string(path).unwrap()).unwrap()
}

fn predictions(run: &Path) -> Vec<Value> {
    fs_err::read_to_string(run.join("predictions.jsonl"))
        .unwrap()
        .lines()
        .map(|line| serde_json::from_str(line).unwrap())
        .collect()
}

/// The unit ids of the demo run, in order.
fn demo_units() -> Vec<String> {
    demo_questions()
        .iter()
        .flat_map(|q| q.units().into_iter().map(|(unit, _)| unit))
        .collect()
}

/// Asserts every demo unit has exactly one prediction.
fn assert_each_unit_once(run: &Path) {
    let units: Vec<String> = predictions(run)
        .iter()
        .map(|p| p["unit"].as_str().unwrap().to_owned())
        .collect();
    let distinct: BTreeSet<&String> = units.iter().collect();
    assert_eq!(distinct.len(), units.len(), "a unit was recorded twice");
    assert_eq!(units, demo_units(), "units lost or out of order");
}

/// Every file under `dir`, recursively.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in fs_err::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                files.push(path);
            }
        }
    }
    files
}

/// Whether every question and option of every category is answered correctly.
fn all_correct(results: &Value) -> bool {
    let scores = &results["scores"];
    scores["units"] == scores["units_answered"]
        && scores["failures"]
            .as_object()
            .is_some_and(serde_json::Map::is_empty)
        && scores["categories"].as_array().unwrap().iter().all(|c| {
            let model = &c["model"];
            model["questions"] == model["questions_correct"]
                && model["options"] == model["options_correct"]
        })
}

#[test]
fn a_perfect_model_scores_every_unit_and_the_offline_replay_is_byte_identical() {
    let mock = Mock::start(MockServer::builder().responder(perfect(perfect_answers())));
    let dir = tempfile::tempdir().unwrap();
    let live = dir.path().join("live");
    let output = run(
        &run_args(&mock.url(), live.to_str().unwrap(), &["--jobs", "4"]),
        Some(SECRET_KEY),
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let results = read_json(&live.join("results.json"));
    assert_each_unit_once(&live);
    let failures: Vec<Value> = predictions(&live)
        .into_iter()
        .filter(|p| !p["error"].is_null())
        .collect();
    assert!(failures.is_empty(), "failed units: {failures:?}");
    assert!(all_correct(&results), "{results}");
    assert!(stdout(&output).contains("100.0"), "{}", stdout(&output));

    // Against the builtin writer on the same questions: the same scores, byte for byte.
    let builtin = dir.path().join("builtin");
    let output = run(
        &[
            "run",
            "--data",
            "eval/demo",
            "--questions",
            QUESTIONS,
            "--out",
            builtin.to_str().unwrap(),
            "--quiet",
        ],
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        fs_err::read(live.join("results.json")).unwrap(),
        fs_err::read(builtin.join("results.json")).unwrap()
    );

    // One request per distinct prompt (identical prompts share a completion), each sent once.
    let requests = mock.server.requests();
    let chat: Vec<&MockRequest> = requests
        .iter()
        .filter(|r| r.path.ends_with("/chat/completions"))
        .collect();
    let distinct: BTreeSet<String> = chat.iter().filter_map(|r| first_user_text(r)).collect();
    assert_eq!(distinct.len(), chat.len(), "a prompt was sent twice");
    assert!(
        requests.iter().any(|r| r.path.ends_with("/models")),
        "no preflight"
    );

    // The manifest: model, sampling, prompt identity, usage totals; the key nowhere on disk.
    let manifest = read_json(&live.join("manifest.json"));
    assert_eq!(manifest["source"]["model"], MOCK_MODEL);
    assert_eq!(manifest["source"]["endpoint"]["api_key_set"], true);
    assert!(manifest["source"]["prompt_set_hash"].is_string());
    assert_eq!(
        manifest["usage"]["requests"].as_u64().unwrap(),
        chat.len() as u64
    );
    assert!(manifest["usage"]["prompt_tokens"].as_u64().unwrap() > 0);
    for file in files_under(dir.path()) {
        let bytes = fs_err::read(&file).unwrap();
        assert!(
            !String::from_utf8_lossy(&bytes).contains(SECRET_KEY),
            "the API key is in {}",
            file.display()
        );
    }

    // Offline replay from the run's cache: no request, identical results.
    drop(mock);
    let replay = dir.path().join("replay");
    let cache = live.join("cache");
    let output = run(
        &run_args(
            "http://127.0.0.1:9/v1",
            replay.to_str().unwrap(),
            &["--offline", "--cache", cache.to_str().unwrap()],
        ),
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        fs_err::read(live.join("results.json")).unwrap(),
        fs_err::read(replay.join("results.json")).unwrap()
    );
    let replay_manifest = read_json(&replay.join("manifest.json"));
    assert_eq!(replay_manifest["usage"]["requests"], 0);
    assert_eq!(
        replay_manifest["usage"]["prompt_tokens"],
        manifest["usage"]["prompt_tokens"]
    );
}

#[test]
fn per_question_mode_asks_once_per_choice_question_and_scores_like_per_option() {
    let mock = Mock::start(MockServer::builder().responder(perfect(perfect_answers())));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("per-question");
    let output = run(
        &run_args(&mock.url(), out.to_str().unwrap(), &["--per-question"]),
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    assert_each_unit_once(&out);
    let questions = demo_questions();
    let chat = mock
        .server
        .requests()
        .iter()
        .filter(|r| r.path.ends_with("/chat/completions"))
        .count();
    let distinct_prompts: BTreeSet<String> = questions
        .iter()
        .map(|q| render(q, None, PromptMode::PerQuestion).unwrap().user)
        .collect();
    assert_eq!(chat, distinct_prompts.len());
    let results = read_json(&out.join("results.json"));
    assert!(all_correct(&results), "{results}");
}
