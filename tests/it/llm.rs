//! The LLM client against the loopback mock server: success, every error class, retries and
//! their bounds, size caps, credentials, concurrency and rate limits. Nothing leaves 127.0.0.1.
//! Timings are only checked as generous bounds that prove a wait happened or a cap held.

use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use contphy_eval::llm::mock::{MockReply, MockServer};
use contphy_eval::llm::{
    ChatMessage, ChatRequest, Client, ClientConfig, LlmError, SamplingParams, TokenUsage,
};

const KEY: &str = "sk-test-0123456789";

/// Fast retries, a short timeout, three attempts; `Retry-After` up to 2 s is honoured.
fn config(base_url: String) -> ClientConfig {
    ClientConfig {
        api_key: Some(KEY.to_owned()),
        request_timeout: Duration::from_secs(5),
        connect_timeout: Duration::from_secs(2),
        max_attempts: 3,
        backoff_base: Duration::from_millis(10),
        backoff_cap: Duration::from_secs(2),
        total_retry_budget: Duration::from_secs(30),
        ..ClientConfig::new(base_url)
    }
}

fn client(server: &MockServer) -> Client {
    Client::new(config(server.base_url())).unwrap()
}

fn request(text: &str) -> ChatRequest {
    ChatRequest {
        sampling: SamplingParams {
            temperature: Some(0.0),
            max_tokens: Some(64),
            seed: Some(3),
            ..SamplingParams::default()
        },
        ..ChatRequest::new(
            "gpt-4o",
            vec![
                ChatMessage::system("Write Python."),
                ChatMessage::user(text),
            ],
        )
    }
}

async fn one_error(script: Vec<MockReply>) -> (LlmError, MockServer) {
    let server = MockServer::scripted(script).await.unwrap();
    let error = client(&server).complete(&request("q")).await.unwrap_err();
    (error, server)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn success_parses_content_usage_and_model_and_sends_the_set_parameters() {
    let usage = TokenUsage {
        prompt_tokens: 12,
        completion_tokens: 5,
        total_tokens: 17,
    };
    let server = MockServer::scripted([MockReply::Ok {
        content: "answer = 1".into(),
        usage: Some(usage),
        model: Some("gpt-4o-2024-08-06".into()),
    }])
    .await
    .unwrap();
    let client = client(&server);
    let completion = client.complete(&request("how heavy?")).await.unwrap();
    assert_eq!(completion.content, "answer = 1");
    assert_eq!(completion.usage, Some(usage));
    assert_eq!(completion.model.as_deref(), Some("gpt-4o-2024-08-06"));
    assert_eq!(completion.finish_reason.as_deref(), Some("stop"));
    assert_eq!(completion.attempts, 1);
    assert_eq!(completion.raw["id"], "chatcmpl-mock-0");

    let requests = server.requests();
    assert_eq!(requests.len(), 1);
    let sent = &requests[0];
    assert_eq!(
        (sent.method.as_str(), sent.path.as_str()),
        ("POST", "/v1/chat/completions")
    );
    assert_eq!(sent.header("content-type"), Some("application/json"));
    assert_eq!(sent.last_user_text(), Some("how heavy?"));
    let body = sent.json.as_ref().unwrap();
    assert_eq!(body["model"], "gpt-4o");
    assert_eq!(body["temperature"], 0.0);
    assert_eq!(body["max_tokens"], 64);
    assert_eq!(body["seed"], 3);
    assert!(
        body.get("top_p").is_none() && body.get("stop").is_none(),
        "{body}"
    );
    assert_eq!(client.stats().completions, 1);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn rate_limited_with_retry_after_waits_then_succeeds() {
    let server = MockServer::scripted([MockReply::rate_limited("1"), MockReply::ok("done")])
        .await
        .unwrap();
    let client = client(&server);
    let notices = Arc::new(Mutex::new(Vec::new()));
    let seen = Arc::clone(&notices);
    let started = Instant::now();
    let completion = client
        .complete_observed(&request("q"), &move |notice| {
            seen.lock()
                .unwrap()
                .push((notice.error.kind(), notice.delay, notice.failed_attempt));
        })
        .await
        .unwrap();
    assert!(started.elapsed() >= Duration::from_millis(990));
    assert_eq!(
        (completion.content.as_str(), completion.attempts),
        ("done", 2)
    );
    let requests = server.requests();
    assert!(requests[1].received_at - requests[0].received_at >= Duration::from_millis(990));
    assert_eq!(
        *notices.lock().unwrap(),
        vec![("rate_limited", Duration::from_secs(1), 1)]
    );
    let stats = client.stats();
    assert_eq!(
        (stats.requests_sent, stats.retries, stats.rate_limited),
        (2, 1, 1)
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_429_pause_holds_back_the_other_workers_too() {
    let server = MockServer::scripted([MockReply::rate_limited("1")])
        .await
        .unwrap();
    let client = client(&server);
    let first = tokio::spawn({
        let client = client.clone();
        async move { client.complete(&request("first")).await }
    });
    // The second worker starts after the 429 arrived, and must wait out the same pause.
    tokio::time::sleep(Duration::from_millis(200)).await;
    let second = client.complete(&request("second")).await.unwrap();
    assert_eq!(second.attempts, 1);
    assert_eq!(first.await.unwrap().unwrap().attempts, 2);
    let requests = server.requests();
    let second_sent = requests
        .iter()
        .find(|r| r.last_user_text() == Some("second"))
        .unwrap();
    assert!(
        second_sent.received_at - requests[0].received_at >= Duration::from_millis(950),
        "the second worker did not wait for the pause"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn server_error_then_success_is_retried() {
    let server = MockServer::scripted([
        MockReply::error(500, "internal", None),
        MockReply::error(503, "overloaded", None),
        MockReply::ok("third time"),
    ])
    .await
    .unwrap();
    let completion = client(&server).complete(&request("q")).await.unwrap();
    assert_eq!(
        (completion.content.as_str(), completion.attempts),
        ("third time", 3)
    );
    assert_eq!(server.request_count(), 3);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn hanging_response_times_out_on_every_attempt_then_gives_up() {
    let server = MockServer::builder()
        .responder(|_| MockReply::Hang)
        .start()
        .await
        .unwrap();
    let config = ClientConfig {
        request_timeout: Duration::from_millis(200),
        ..config(server.base_url())
    };
    let started = Instant::now();
    let error = Client::new(config)
        .unwrap()
        .complete(&request("q"))
        .await
        .unwrap_err();
    let LlmError::RetriesExhausted { attempts, last } = &error else {
        panic!("{error:?}");
    };
    assert_eq!(*attempts, 3);
    assert_eq!(last.kind(), "timeout");
    assert!(error.to_string().contains("within 200 ms"), "{error}");
    assert_eq!(server.request_count(), 3);
    assert!(started.elapsed() < Duration::from_secs(5));
    assert!(!error.is_fatal_for_run());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn unusable_bodies_fail_without_retrying() {
    // (reply, kind)
    let cases = [
        (MockReply::Malformed, "malformed"),
        (MockReply::NoChoices, "no_choices"),
        (MockReply::NullContent, "empty_completion"),
        (MockReply::ok(""), "empty_completion"),
    ];
    for (reply, kind) in cases {
        let (error, server) = one_error(vec![reply]).await;
        assert_eq!(error.kind(), kind, "{error}");
        assert_eq!(server.request_count(), 1, "{error}");
        assert!(error.to_string().contains(&server.base_url()), "{error}");
    }
    let (error, _server) = one_error(vec![MockReply::Malformed]).await;
    let LlmError::Malformed { body_prefix, .. } = &error else {
        panic!("{error:?}");
    };
    assert!(body_prefix.starts_with("{\"choices\""), "{body_prefix}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn huge_body_is_refused_without_reading_it_all() {
    const TWENTY_MB: u64 = 20_000_000;
    let server = MockServer::scripted([MockReply::Huge {
        bytes: TWENTY_MB,
        declare_length: false,
    }])
    .await
    .unwrap();
    let config = ClientConfig {
        max_body_bytes: 1024 * 1024,
        ..config(server.base_url())
    };
    let error = Client::new(config)
        .unwrap()
        .complete(&request("q"))
        .await
        .unwrap_err();
    assert_eq!(
        (error.kind(), error.status()),
        ("too_large", Some(200)),
        "{error}"
    );
    assert!(error.to_string().contains("1048576 bytes"), "{error}");
    // The client hung up after 1 MiB; the server got to push at most socket buffers' worth more.
    tokio::time::sleep(Duration::from_millis(100)).await;
    let sent = server.body_bytes_sent();
    assert!(
        sent < TWENTY_MB,
        "the whole body was streamed ({sent} bytes)"
    );

    // With the default 8 MiB cap, and with the size announced up front.
    for declare_length in [false, true] {
        let (error, _server) = one_error(vec![MockReply::Huge {
            bytes: TWENTY_MB,
            declare_length,
        }])
        .await;
        assert_eq!(error.kind(), "too_large", "{error}");
        assert!(error.to_string().contains("8388608 bytes"), "{error}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn unauthorized_is_fatal_after_exactly_one_request() {
    for status in [401, 403] {
        let (error, server) = one_error(vec![MockReply::error(
            status,
            "Incorrect API key provided",
            None,
        )])
        .await;
        assert_eq!(error.kind(), "unauthorized");
        assert!(error.is_fatal_for_run());
        assert_eq!(server.request_count(), 1);
        let message = error.to_string();
        assert!(
            message.contains(&format!("{}/chat/completions", server.base_url())),
            "{message}"
        );
        assert!(message.contains(&status.to_string()), "{message}");
        assert!(message.contains("Incorrect API key provided"), "{message}");
        assert!(!message.contains(KEY), "{message}");
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn unknown_model_is_fatal_whether_404_or_model_not_found() {
    let replies = [
        MockReply::error(
            404,
            "The model `gpt-9` does not exist",
            Some("model_not_found"),
        ),
        MockReply::error(400, "no such model", Some("model_not_found")),
    ];
    for reply in replies {
        let (error, server) = one_error(vec![reply]).await;
        assert_eq!(error.kind(), "unknown_model", "{error}");
        assert!(error.is_fatal_for_run());
        assert!(error.to_string().contains("model `gpt-4o`"), "{error}");
        assert_eq!(server.request_count(), 1);
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn context_length_and_other_bad_requests_are_not_retried() {
    let (error, server) = one_error(vec![MockReply::error(
        400,
        "This model's maximum context length is 8192 tokens. However, you requested 9000 tokens.",
        Some("context_length_exceeded"),
    )])
    .await;
    assert_eq!(error.kind(), "context_length");
    assert!(!error.is_fatal_for_run());
    assert_eq!(server.request_count(), 1);

    let (error, server) = one_error(vec![MockReply::error(
        400,
        "temperature must be <= 2",
        Some("invalid_value"),
    )])
    .await;
    assert_eq!(
        error,
        LlmError::BadRequest {
            url: format!("{}/chat/completions", server.base_url()),
            status: 400,
            message: "temperature must be <= 2".into(),
        }
    );
    assert_eq!(server.request_count(), 1);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_final_bad_request_after_retries_keeps_the_attempt_count() {
    let (error, server) = one_error(vec![
        MockReply::error(502, "bad gateway", None),
        MockReply::error(400, "bad", None),
    ])
    .await;
    assert_eq!(error.kind(), "after_retries");
    assert_eq!(error.root().kind(), "bad_request");
    assert_eq!((error.attempts(), server.request_count()), (2, 2));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn connection_refused_names_the_address_and_is_retried_up_to_the_cap() {
    // A port that was just free: nothing listens on it.
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let address = listener.local_addr().unwrap();
    drop(listener);
    let started = Instant::now();
    let client = Client::new(config(format!("http://{address}/v1"))).unwrap();
    let error = client.complete(&request("q")).await.unwrap_err();
    let LlmError::RetriesExhausted { attempts, last } = &error else {
        panic!("{error:?}");
    };
    assert_eq!(*attempts, 3);
    assert_eq!(last.kind(), "connection");
    let message = error.to_string();
    assert!(message.contains(&format!("`{address}`")), "{message}");
    assert!(message.to_lowercase().contains("refused"), "{message}");
    assert_eq!(client.stats().requests_sent, 3);
    assert!(started.elapsed() < Duration::from_secs(5));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_closed_connection_is_retried() {
    let server = MockServer::scripted([MockReply::Close, MockReply::ok("after close")])
        .await
        .unwrap();
    let first_error = Arc::new(Mutex::new(None));
    let seen = Arc::clone(&first_error);
    let completion = client(&server)
        .complete_observed(&request("q"), &move |notice| {
            *seen.lock().unwrap() = Some(notice.error.clone());
        })
        .await
        .unwrap();
    assert_eq!(
        (completion.content.as_str(), completion.attempts),
        ("after close", 2)
    );
    let first_error = first_error.lock().unwrap().clone().unwrap();
    assert_eq!(first_error.kind(), "connection", "{first_error}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn retry_after_beyond_the_budget_gives_up_at_once() {
    let server = MockServer::scripted([MockReply::rate_limited("2")])
        .await
        .unwrap();
    let config = ClientConfig {
        total_retry_budget: Duration::from_millis(500),
        ..config(server.base_url())
    };
    let started = Instant::now();
    let error = Client::new(config)
        .unwrap()
        .complete(&request("q"))
        .await
        .unwrap_err();
    assert_eq!((error.kind(), error.attempts()), ("retries_exhausted", 1));
    assert_eq!(error.root().retry_after(), Some(Duration::from_secs(2)));
    assert!(started.elapsed() < Duration::from_secs(1));
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_key_goes_in_the_authorization_header_and_nowhere_else() {
    let server = MockServer::scripted([]).await.unwrap();
    let config = config(server.base_url());
    assert!(!format!("{config:?}").contains(KEY));
    let client = Client::new(config).unwrap();
    assert!(!format!("{client:?}").contains(KEY));
    client.complete(&request("q")).await.unwrap();

    let keyless = Client::new(ClientConfig {
        api_key: None,
        ..self::config(server.base_url())
    })
    .unwrap();
    keyless.complete(&request("q")).await.unwrap();

    let requests = server.requests();
    assert!(requests[0].authorization_is(&format!("Bearer {KEY}")));
    assert!(
        requests[0]
            .headers
            .iter()
            .all(|(_, value)| !value.contains(KEY))
    );
    assert!(!requests[1].has_authorization());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 4)]
async fn concurrent_completes_reach_the_server_concurrently() {
    const JOBS: usize = 32;
    let server = MockServer::builder()
        .latency(Duration::from_millis(200))
        .answering(|text| format!("answer to {text}"))
        .start()
        .await
        .unwrap();
    let client = client(&server);
    let permits = Arc::new(tokio::sync::Semaphore::new(JOBS));
    let started = Instant::now();
    let mut tasks = tokio::task::JoinSet::new();
    for index in 0..64 {
        let (client, permits) = (client.clone(), Arc::clone(&permits));
        tasks.spawn(async move {
            let _permit = permits.acquire_owned().await.unwrap();
            let completion = client
                .complete(&request(&format!("q{index}")))
                .await
                .unwrap();
            assert_eq!(completion.content, format!("answer to q{index}"));
        });
    }
    while let Some(joined) = tasks.join_next().await {
        joined.unwrap();
    }
    assert_eq!(server.max_in_flight(), JOBS);
    // Two rounds of 200 ms; serial would take 12.8 s.
    assert!(
        started.elapsed() < Duration::from_secs(4),
        "{:?}",
        started.elapsed()
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn rpm_limit_spaces_concurrent_requests() {
    let server = MockServer::scripted([]).await.unwrap();
    let client = Client::new(ClientConfig {
        rpm: Some(600),
        ..config(server.base_url())
    })
    .unwrap();
    let mut tasks = tokio::task::JoinSet::new();
    for index in 0..10 {
        let client = client.clone();
        tasks.spawn(async move { client.complete(&request(&format!("q{index}"))).await });
    }
    while let Some(joined) = tasks.join_next().await {
        joined.unwrap().unwrap();
    }
    let mut arrivals: Vec<Instant> = server.requests().iter().map(|r| r.received_at).collect();
    arrivals.sort();
    // 600 rpm = 100 ms apart: ten requests span 0.9 s at least.
    let span = arrivals[9] - arrivals[0];
    assert!(span >= Duration::from_millis(880), "{span:?}");
    assert!(span < Duration::from_secs(5), "{span:?}");
    for pair in arrivals.windows(2) {
        assert!(
            pair[1] - pair[0] >= Duration::from_millis(80),
            "{arrivals:?}"
        );
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn mock_answers_unknown_routes_with_404_and_maps_prompts() {
    let server = MockServer::builder()
        .answering(str::to_uppercase)
        .start()
        .await
        .unwrap();
    let completion = client(&server).complete(&request("abc")).await.unwrap();
    assert_eq!(completion.content, "ABC");
    // A base URL with a wrong path gets the 404 a real endpoint would send.
    let wrong = Client::new(config(format!("http://{}/api", server.address()))).unwrap();
    let error = wrong.complete(&request("abc")).await.unwrap_err();
    assert_eq!(error.kind(), "unknown_model", "{error}");
}
