//! Whole runs with `--model` against the loopback mock server (127.0.0.1 only): the mock answers
//! each rendered prompt of the demo questions with the builtin writer's program for it, so a
//! correct pipeline scores 100%. Then the faults a real endpoint has on a bad day, a run killed
//! with SIGKILL and resumed, an offline replay, and the errors a new user meets.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::Arc;
use std::time::Duration;

use contphy_eval::dataset::{Question, load_question_file};
use contphy_eval::llm::mock::{MOCK_MODEL, MockReply, MockRequest, MockServer, MockServerBuilder};
use contphy_eval::program::builtin::{write_program, write_question_program};
use contphy_eval::prompt::PromptMode;
use contphy_eval::scenarios;
use contphy_eval::scenarios::render_prompt as render;
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
    load_question_file(&root().join(QUESTIONS), None, scenarios::families())
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
            let writer = scenarios::parts(question.scenario).writer.unwrap();
            let program = if mode == PromptMode::PerQuestion {
                write_question_program(&question, writer).unwrap()
            } else {
                write_program(&question, option, writer).unwrap()
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
    let report = fs_err::read_to_string(live.join("report.md")).unwrap();
    assert!(
        report.contains(&format!("- LLM: {} requests in this run;", chat.len())),
        "{report}"
    );
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

/// The units of the first `limit` demo questions, in order.
fn first_units(limit: usize) -> Vec<String> {
    demo_questions()
        .iter()
        .take(limit)
        .flat_map(|q| q.units().into_iter().map(|(unit, _)| unit))
        .collect()
}

/// Failed units by `stage/kind`.
fn failures_by_kind(run: &Path) -> BTreeMap<String, usize> {
    let mut failures = BTreeMap::new();
    for prediction in predictions(run) {
        let error = &prediction["error"];
        if !error.is_null() {
            let kind = format!(
                "{}/{}",
                error["stage"].as_str().unwrap(),
                error["kind"].as_str().unwrap()
            );
            *failures.entry(kind).or_insert(0) += 1;
        }
    }
    failures
}

#[test]
fn each_endpoint_fault_fails_or_delays_only_its_own_unit() {
    // With one request in flight, the n-th chat request meets the n-th behaviour below; after
    // the list, the model is perfect. Retries take the next behaviour.
    let answers = perfect_answers();
    let counter = std::sync::atomic::AtomicUsize::new(0);
    let responder = perfect(Arc::clone(&answers));
    let faults: Vec<Option<MockReply>> = vec![
        Some(MockReply::rate_limited("1")),
        None, // the 429's retry, after Retry-After: succeeds
        Some(MockReply::error(500, "upstream overloaded", None)),
        None, // the 500's retry: succeeds
        Some(MockReply::Malformed),
        Some(MockReply::NoChoices),
        Some(MockReply::ok("")),
        Some(MockReply::ok("I am sorry, I cannot write that program.")),
        Some(MockReply::error(
            400,
            "This model's maximum context length is 8192 tokens.",
            Some("context_length_exceeded"),
        )),
        Some(MockReply::Huge {
            bytes: 20 * 1024 * 1024,
            declare_length: false,
        }),
        Some(MockReply::Hang),
        Some(MockReply::Hang), // the hang's retry hangs too: the unit times out
    ];
    let server = MockServer::builder().responder(move |request| {
        let index = counter.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        match faults.get(index).cloned().flatten() {
            Some(fault) => fault,
            None => responder(request),
        }
    });
    let mock = Mock::start(server);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("faults");
    let output = run(
        &run_args(
            &mock.url(),
            out.to_str().unwrap(),
            &[
                "--limit",
                "40",
                "--jobs",
                "1",
                "--repair",
                "0",
                "--request-timeout",
                "1",
                "--max-attempts",
                "2",
            ],
        ),
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));

    // No unit lost or counted twice, and exactly the faulty ones failed, each with its cause.
    let units: Vec<String> = predictions(&out)
        .iter()
        .map(|p| p["unit"].as_str().unwrap().to_owned())
        .collect();
    assert_eq!(units, first_units(40));
    let expected: BTreeMap<String, usize> = [
        ("llm/malformed", 1),
        ("llm/no_choices", 1),
        ("llm/empty_completion", 1),
        ("extract/no_code", 1),
        ("llm/context_length", 1),
        ("llm/too_large", 1),
        ("llm/timeout", 1),
    ]
    .into_iter()
    .map(|(kind, count)| (kind.to_owned(), count))
    .collect();
    assert_eq!(failures_by_kind(&out), expected);

    // The retried units succeeded after two requests each; nothing else was retried.
    let retried: Vec<u64> = predictions(&out)
        .iter()
        .filter_map(|p| p["usage"]["requests"].as_u64())
        .filter(|&requests| requests > 1)
        .collect();
    assert_eq!(retried, vec![2, 2]);
    let chat = mock
        .server
        .requests()
        .iter()
        .filter(|r| r.path.ends_with("/chat/completions"))
        .count();
    let distinct: BTreeSet<String> = mock
        .server
        .requests()
        .iter()
        .filter_map(first_user_text)
        .collect();
    assert_eq!(chat, distinct.len() + 3, "two retries and the hang's retry");
    let results = read_json(&out.join("results.json"));
    assert_eq!(results["scores"]["units_answered"].as_u64().unwrap() + 7, {
        results["scores"]["units"].as_u64().unwrap()
    });
}

#[test]
fn a_broken_program_gets_one_repair_turn_that_shows_the_error() {
    // The first completion of every prompt has a syntax error; the repair turn gets the program.
    let answers = perfect_answers();
    let server = MockServer::builder().responder(move |request| {
        let messages = request
            .json
            .as_ref()
            .and_then(|j| j["messages"].as_array().cloned())
            .unwrap_or_default();
        let first = first_user_text(request).unwrap_or_default();
        if messages.len() <= 2 {
            MockReply::ok("```python\ndef execute_command(video)\n    return 'yes'\n```")
        } else {
            let feedback = messages.last().unwrap()["content"].as_str().unwrap();
            assert!(feedback.contains("syntax"), "{feedback}");
            MockReply::ok(answers.get(&first).cloned().unwrap_or_default())
        }
    });
    let mock = Mock::start(server);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("repair");
    let output = run(
        &run_args(&mock.url(), out.to_str().unwrap(), &["--limit", "10"]),
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let predictions = predictions(&out);
    assert_eq!(predictions.len(), first_units(10).len());
    for prediction in &predictions {
        assert!(prediction["error"].is_null(), "{prediction}");
        assert!(prediction["correct"].as_bool().unwrap(), "{prediction}");
        let attempts = prediction["attempts"].as_array().unwrap();
        assert_eq!(attempts.len(), 2, "{prediction}");
    }
    // The viewer shows both turns of a unit, each with its completion (from the run's own
    // cache), the first with its error.
    let site = dir.path().join("site");
    let output = run(
        &[
            "view",
            out.to_str().unwrap(),
            "--out",
            site.to_str().unwrap(),
        ],
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let chunk = fs_err::read_to_string(site.join("runs/1/units/0.js")).unwrap();
    let start = chunk.find('[').unwrap();
    let details: Value = serde_json::from_str(&chunk[start..=chunk.rfind(']').unwrap()]).unwrap();
    let first = &details[0];
    assert_eq!(first["attempts"].as_array().unwrap().len(), 2, "{first}");
    let broken = &first["attempts"][0];
    assert_eq!(broken["error"]["stage"], "sandbox", "{broken}");
    assert_eq!(broken["error"]["kind"], "syntax", "{broken}");
    assert!(
        broken["program"]["text"]
            .as_str()
            .unwrap()
            .contains("def execute_command(video)\n    return 'yes'"),
        "{broken}"
    );
    assert!(
        broken["program"]["completion"]
            .as_str()
            .unwrap()
            .starts_with("```python"),
        "{broken}"
    );
    let repaired = &first["attempts"][1];
    assert!(repaired["error"].is_null(), "{repaired}");
    assert_eq!(
        first["program"], repaired["program"],
        "the unit's program is the repair"
    );
    // Without repair turns every unit fails at the sandbox stage.
    let out = dir.path().join("no-repair");
    let output = run(
        &run_args(
            &mock.url(),
            out.to_str().unwrap(),
            &["--limit", "10", "--repair", "0"],
        ),
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        failures_by_kind(&out),
        BTreeMap::from([("sandbox/syntax".to_owned(), first_units(10).len())])
    );
}

/// The exit code and stderr of a run, with the mock's port and temporary paths made stable.
fn transcript_entry(title: &str, output: &Output, temp: &Path) -> String {
    let text = stderr(output).replace(temp.to_str().unwrap(), "[TMP]");
    let port = regex_free_port_filter(&text);
    format!(
        "## {title}\nexit {}\n{port}\n",
        output.status.code().unwrap_or(-1)
    )
}

/// `127.0.0.1:<port>` → `127.0.0.1:PORT` (ports differ per run).
fn regex_free_port_filter(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find("127.0.0.1:") {
        let (before, after) = rest.split_at(at + "127.0.0.1:".len());
        out.push_str(before);
        let digits = after.chars().take_while(char::is_ascii_digit).count();
        out.push_str(if digits > 0 { "PORT" } else { "" });
        rest = &after[digits..];
    }
    out.push_str(rest);
    out
}

#[test]
fn new_user_mistakes_get_one_clear_line_and_exit_1() {
    let mock = Mock::start(MockServer::builder());
    let dir = tempfile::tempdir().unwrap();
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_owned();
    let mut transcript = String::new();
    let cases: Vec<(&str, Vec<String>, Option<&str>)> = vec![
        (
            "no key for the default endpoint",
            vec!["--model".into(), "gpt-4".into()],
            None,
        ),
        (
            "base url that is not a URL",
            vec![
                "--model".into(),
                MOCK_MODEL.into(),
                "--base-url".into(),
                "localhost:8000".into(),
            ],
            None,
        ),
        (
            "unreachable host",
            vec![
                "--model".into(),
                MOCK_MODEL.into(),
                "--base-url".into(),
                "http://127.0.0.1:9/v1".into(),
            ],
            None,
        ),
        (
            "unknown model",
            vec![
                "--model".into(),
                "gpt-9".into(),
                "--base-url".into(),
                mock.url(),
            ],
            Some(SECRET_KEY),
        ),
        (
            "offline without a cache entry needs no key and fails per unit, not per run",
            vec![
                "--model".into(),
                "gpt-4".into(),
                "--offline".into(),
                "--cache".into(),
                out("empty-cache"),
                "--limit".into(),
                "1".into(),
            ],
            None,
        ),
    ];
    for (index, (title, extra, key)) in cases.into_iter().enumerate() {
        let run_dir = out(&format!("run{index}"));
        let mut args = vec![
            "run",
            "--data",
            "eval/demo",
            "--questions",
            QUESTIONS,
            "--out",
            &run_dir,
            "--quiet",
        ];
        args.extend(extra.iter().map(String::as_str));
        let output = run(&args, key);
        let entry = transcript_entry(title, &output, dir.path());
        if index < 4 {
            assert_eq!(output.status.code(), Some(1), "{entry}");
            assert_eq!(stderr(&output).lines().count(), 1, "{entry}");
        } else {
            assert_eq!(output.status.code(), Some(0), "{entry}");
        }
        transcript.push_str(&entry);
    }
    // Only the unknown-model case reached the server, and only its model list.
    let paths: Vec<String> = mock
        .server
        .requests()
        .iter()
        .map(|r| r.path.clone())
        .collect();
    assert_eq!(paths, vec!["/v1/models".to_owned()]);
    insta::assert_snapshot!("llm_new_user_errors", transcript);
}

#[test]
fn a_rejected_key_or_unknown_model_mid_run_stops_at_the_first_unit_with_exit_1() {
    for (reply, expected) in [
        (
            MockReply::error(
                401,
                "Incorrect API key provided: sk-...cret.",
                Some("invalid_api_key"),
            ),
            "refused the credentials (401)",
        ),
        (
            MockReply::error(
                404,
                "The model `mock-model` does not exist",
                Some("model_not_found"),
            ),
            "does not serve model `mock-model`",
        ),
    ] {
        let mock = Mock::start(MockServer::builder().responder(move |_| reply.clone()));
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("run");
        let output = run(
            &run_args(&mock.url(), out.to_str().unwrap(), &["--jobs", "1"]),
            Some(SECRET_KEY),
        );
        assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
        assert!(stderr(&output).contains(expected), "{}", stderr(&output));
        assert!(!stderr(&output).contains(SECRET_KEY));
        let chat = mock
            .server
            .requests()
            .iter()
            .filter(|r| r.path.ends_with("/chat/completions"))
            .count();
        assert_eq!(chat, 1, "the run went on after a fatal answer");
        // Nothing was recorded as a unit failure: the run stopped before any unit finished.
        assert!(predictions(&out).is_empty());
    }
}

#[test]
fn runs_killed_at_random_points_and_resumed_end_equal_to_an_uninterrupted_run() {
    // Latency stretches the run over a few seconds, so the kills land in the completion phase,
    // in the sandbox phase, or while predictions are written.
    // (About 380 completions at 2 in flight: 2 s uninterrupted.)
    let mock = Mock::start(
        MockServer::builder()
            .latency(Duration::from_millis(10))
            .responder(perfect(perfect_answers())),
    );
    let dir = tempfile::tempdir().unwrap();
    // The uninterrupted run: the builtin writer's, which a perfect model equals byte for byte
    // (the first test of this file).
    let whole = dir.path().join("whole");
    let output = run(
        &[
            "run",
            "--data",
            "eval/demo",
            "--questions",
            QUESTIONS,
            "--out",
            whole.to_str().unwrap(),
            "--quiet",
        ],
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let needed: BTreeSet<String> = demo_questions()
        .iter()
        .flat_map(|q| {
            q.units()
                .into_iter()
                .map(|(_, option)| render(q, option, PromptMode::PerOption).unwrap().user)
                .collect::<Vec<_>>()
        })
        .collect();

    let killed = dir.path().join("killed");
    // Kill delays from a fixed-seed generator (xorshift), 150..1150 ms.
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut kills = 0;
    // Up to 16 rounds: the early ones die while completions arrive, the later ones (everything
    // cached) while programs run and predictions are written.
    for _ in 0..16 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let delay = Duration::from_millis(150 + state % 1000);
        let mut child = command(
            &run_args(
                &mock.url(),
                killed.to_str().unwrap(),
                &["--jobs", "2", "--resume"],
            ),
            None,
        )
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
        std::thread::sleep(delay);
        if child.try_wait().unwrap().is_some() {
            break;
        }
        child.kill().unwrap(); // SIGKILL
        child.wait().unwrap();
        kills += 1;
        let saved = fs_err::read_to_string(killed.join("predictions.jsonl"))
            .map_or(0, |text| text.lines().count());
        let cached = if killed.join("cache").is_dir() {
            files_under(&killed.join("cache")).len()
        } else {
            0
        };
        eprintln!("kill {kills} after {delay:?}: {saved} predictions, {cached} cache entries");
    }
    assert!(kills >= 3, "only {kills} runs were still going when killed");
    let output = run(
        &run_args(
            &mock.url(),
            killed.to_str().unwrap(),
            &["--jobs", "2", "--resume"],
        ),
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    assert_each_unit_once(&killed);
    assert_eq!(
        fs_err::read(whole.join("results.json")).unwrap(),
        fs_err::read(killed.join("results.json")).unwrap()
    );
    // Completions cached before a kill are not bought again: at most the requests in flight at
    // each kill (2) are repeated.
    let chat = mock
        .server
        .requests()
        .iter()
        .filter(|r| r.path.ends_with("/chat/completions"))
        .count();

    // Everything is cached now: offline replays die while programs run and predictions are
    // written, and the resumed replay still ends equal.
    let replayed = dir.path().join("replayed");
    let cache = killed.join("cache");
    // Kill points are fractions of how long one whole replay takes on this machine.
    let started = std::time::Instant::now();
    let reference = dir.path().join("reference-replay");
    let output = run(
        &run_args(
            "http://127.0.0.1:9/v1",
            reference.to_str().unwrap(),
            &["--offline", "--cache", cache.to_str().unwrap()],
        ),
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let mut replay_time = started.elapsed();
    let mut replay_kills = 0;
    for _ in 0..16 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        #[expect(clippy::cast_precision_loss, reason = "a number below 1000")]
        let fraction = 0.2 + 0.75 * ((state % 1000) as f64 / 1000.0);
        let delay = replay_time.mul_f64(fraction);
        let mut child = command(
            &run_args(
                "http://127.0.0.1:9/v1",
                replayed.to_str().unwrap(),
                &["--offline", "--cache", cache.to_str().unwrap(), "--resume"],
            ),
            None,
        )
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
        std::thread::sleep(delay);
        if child.try_wait().unwrap().is_some() {
            if replay_kills > 0 {
                break;
            }
            // Finished before its kill (this replay ran faster than the reference): start the
            // replay over and kill it sooner.
            fs_err::remove_dir_all(&replayed).unwrap();
            replay_time /= 2;
            continue;
        }
        child.kill().unwrap();
        child.wait().unwrap();
        replay_kills += 1;
        let saved = fs_err::read_to_string(replayed.join("predictions.jsonl"))
            .map_or(0, |text| text.lines().count());
        eprintln!("replay kill {replay_kills} after {delay:?}: {saved} predictions");
    }
    let output = run(
        &run_args(
            "http://127.0.0.1:9/v1",
            replayed.to_str().unwrap(),
            &["--offline", "--cache", cache.to_str().unwrap(), "--resume"],
        ),
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    assert_each_unit_once(&replayed);
    assert_eq!(
        fs_err::read(whole.join("results.json")).unwrap(),
        fs_err::read(replayed.join("results.json")).unwrap()
    );
    assert!(replay_kills >= 1, "no replay was still going when killed");

    eprintln!(
        "{kills} kills; {chat} completions for {} distinct prompts",
        needed.len()
    );
    assert!(
        chat <= needed.len() + kills * 2,
        "{chat} completions for a run that needs {}",
        needed.len()
    );
}

#[test]
fn render_prints_exactly_the_messages_a_run_sends() {
    let questions = load_question_file(
        &root().join("eval/demo/pulley_group_test.json"),
        None,
        scenarios::families(),
    )
    .unwrap()
    .questions;
    let choice = questions
        .iter()
        .find(|q| q.answer_type.is_choice())
        .unwrap();
    let option = &choice.options[1];
    let expected = render(choice, Some(option), PromptMode::PerOption).unwrap();
    let output = run(
        &[
            "render",
            "--data",
            "eval/demo",
            "--question-id",
            &choice.id.0,
            "--option",
            &option.letter.to_string(),
            "--json",
        ],
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let printed: Value = serde_json::from_str(&stdout(&output)).unwrap();
    let messages = printed["messages"].as_array().unwrap();
    assert_eq!(messages.last().unwrap()["content"], expected.user);
    assert_eq!(printed["template_hash"], expected.template_hash);

    // As text: role headers and the same user message.
    let output = run(
        &[
            "render",
            "--data",
            "eval/demo",
            "--question-id",
            &choice.id.0,
            "--per-question",
        ],
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let whole = render(choice, None, PromptMode::PerQuestion).unwrap();
    assert!(stdout(&output).contains(&format!("===== user =====\n{}\n", whole.user)));

    // Mistakes: one line each, exit 1.
    let mut transcript = String::new();
    for (title, args) in [
        ("unknown id", vec!["--question-id", "99999"]),
        (
            "choice question without an option",
            vec!["--question-id", &choice.id.0],
        ),
        (
            "option letter it does not have",
            vec!["--question-id", &choice.id.0, "--option", "Z"],
        ),
        (
            "option on an open question",
            vec!["--question-id", "00000", "--option", "A"],
        ),
    ] {
        let mut full = vec!["render", "--data", "eval/demo"];
        full.extend(args);
        let output = run(&full, None);
        assert_eq!(
            output.status.code(),
            Some(1),
            "{title}: {}",
            stderr(&output)
        );
        assert_eq!(stderr(&output).lines().count(), 1, "{title}");
        write!(transcript, "## {title}\n{}\n", stderr(&output)).unwrap();
    }
    insta::assert_snapshot!("render_errors", transcript);
}

#[test]
fn samples_are_cached_apart_and_the_majority_answer_wins_and_an_export_replays_elsewhere() {
    // The first completion for each prompt answers wrongly (the opposite yes/no); later ones
    // are right. With three samples, the majority is right whichever sample met the bad one.
    let answers = perfect_answers();
    let seen = std::sync::Mutex::new(BTreeMap::<String, usize>::new());
    let server = MockServer::builder().responder(move |request| {
        let prompt = first_user_text(request).unwrap_or_default();
        let mut seen = seen.lock().unwrap();
        let count = seen.entry(prompt.clone()).or_insert(0);
        *count += 1;
        if *count == 1 {
            MockReply::ok("```python\ndef execute_command(video):\n    return 'wrong answer'\n```")
        } else {
            MockReply::ok(answers.get(&prompt).cloned().unwrap_or_default())
        }
    });
    let mock = Mock::start(server);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("samples");
    let output = run(
        &run_args(
            &mock.url(),
            out.to_str().unwrap(),
            &["--limit", "12", "--samples", "3", "--repair", "0"],
        ),
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let predictions = predictions(&out);
    assert_eq!(predictions.len(), first_units(12).len());
    for prediction in &predictions {
        assert!(prediction["correct"].as_bool().unwrap(), "{prediction}");
        assert_eq!(
            prediction["attempts"].as_array().unwrap().len(),
            3,
            "{prediction}"
        );
    }
    let prompts: BTreeSet<String> = mock
        .server
        .requests()
        .iter()
        .filter_map(first_user_text)
        .collect();
    let chat = mock
        .server
        .requests()
        .iter()
        .filter(|r| r.path.ends_with("/chat/completions"))
        .count();
    assert_eq!(
        chat,
        3 * prompts.len(),
        "one completion per sample and prompt"
    );

    // Export the run's programs, import them into another cache, replay offline: same results.
    let exported = dir.path().join("run.jsonl");
    let cache = out.join("cache");
    let output = run(
        &[
            "cache",
            "export",
            "--cache",
            cache.to_str().unwrap(),
            "--run",
            out.to_str().unwrap(),
            "--out",
            exported.to_str().unwrap(),
        ],
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let lines = fs_err::read_to_string(&exported).unwrap().lines().count();
    assert_eq!(lines, 3 * prompts.len());
    let elsewhere = dir.path().join("elsewhere-cache");
    let output = run(
        &[
            "cache",
            "import",
            "--cache",
            elsewhere.to_str().unwrap(),
            exported.to_str().unwrap(),
        ],
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    drop(mock);
    let replay = dir.path().join("replay");
    let output = run(
        &run_args(
            "http://127.0.0.1:9/v1",
            replay.to_str().unwrap(),
            &[
                "--limit",
                "12",
                "--samples",
                "3",
                "--repair",
                "0",
                "--offline",
                "--cache",
                elsewhere.to_str().unwrap(),
            ],
        ),
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    assert_eq!(
        fs_err::read(out.join("results.json")).unwrap(),
        fs_err::read(replay.join("results.json")).unwrap()
    );
}

#[test]
fn bench_llm_prints_json_with_the_client_and_its_peer() {
    let output = run(
        &[
            "bench",
            "llm",
            "--latency-ms",
            "2",
            "--jobs",
            "1,4",
            "--rpm",
            "6000",
            "--rpm-seconds",
            "0.3",
        ],
        None,
    );
    assert!(output.status.success(), "{}", stderr(&output));
    let report: Value = serde_json::from_str(&stdout(&output)).unwrap();
    let points = report["client"]["throughput"].as_array().unwrap();
    let jobs: Vec<u64> = points.iter().map(|p| p["jobs"].as_u64().unwrap()).collect();
    assert_eq!(jobs, vec![1, 4]);
    for point in points {
        assert_eq!(point["failures"], 0, "{point}");
        assert!(point["max_in_flight"].as_u64().unwrap() <= point["jobs"].as_u64().unwrap());
    }
    let limits = report["client"]["rate_limits"].as_array().unwrap();
    assert_eq!(limits.len(), 1);
    assert_eq!(limits[0]["rpm_limit"], 6000);
    // The peer needs python3; without it the report says why instead of failing.
    let peer = &report["peer_cpython_http_client"];
    assert!(
        peer["throughput"].is_array() || peer["error"].is_string(),
        "{peer}"
    );
}

#[test]
fn a_spending_cap_stops_the_run_and_resume_with_a_higher_cap_buys_nothing_twice() {
    let mock = Mock::start(MockServer::builder().responder(perfect(perfect_answers())));
    let dir = tempfile::tempdir().unwrap();
    let prices = dir.path().join("prices.toml");
    fs_err::write(
        &prices,
        format!(
            "snapshot = \"test\"\n\n[models.\"{MOCK_MODEL}\"]\ninput_per_million = 10.0\noutput_per_million = 10.0\n"
        ),
    )
    .unwrap();
    let out = dir.path().join("capped");
    let capped = |cap: &str, resume: bool| {
        let mut extra = vec![
            "--limit",
            "10",
            "--jobs",
            "1",
            "--prices",
            prices.to_str().unwrap(),
            "--max-cost",
            cap,
        ];
        if resume {
            extra.push("--resume");
        }
        run(&run_args(&mock.url(), out.to_str().unwrap(), &extra), None)
    };
    let output = capped("0.05", false);
    assert_eq!(output.status.code(), Some(1), "{}", stderr(&output));
    assert!(
        stderr(&output).contains("stopped at the spending cap"),
        "{}",
        stderr(&output)
    );
    let chat = |mock: &Mock| {
        mock.server
            .requests()
            .iter()
            .filter(|r| r.path.ends_with("/chat/completions"))
            .count()
    };
    let before = chat(&mock);
    assert!(
        before >= 1 && before < first_units(10).len(),
        "{before} requests"
    );

    let output = capped("100", true);
    assert!(output.status.success(), "{}", stderr(&output));
    let predictions = predictions(&out);
    assert_eq!(predictions.len(), first_units(10).len());
    assert!(
        predictions
            .iter()
            .all(|p| p["correct"].as_bool() == Some(true))
    );
    let distinct: BTreeSet<String> = mock
        .server
        .requests()
        .iter()
        .filter_map(first_user_text)
        .collect();
    assert_eq!(chat(&mock), distinct.len(), "a completion was bought twice");

    // A cap without a price for the model is refused before any request.
    let output = run(
        &run_args(
            &mock.url(),
            dir.path().join("unpriced").to_str().unwrap(),
            &["--max-cost", "1"],
        ),
        None,
    );
    assert_eq!(output.status.code(), Some(1));
    assert!(
        stderr(&output).contains("--max-cost needs a price"),
        "{}",
        stderr(&output)
    );
}
