//! `Client`: sends chat-completions requests, classifies every outcome, retries what may succeed.
//!
//! Input: a [`ChatRequest`]. Output: a [`Completion`] (with the number of attempts it took) or
//! an [`LlmError`]. One `Client` is shared (it is a cheap `Clone`) by all concurrent requests of
//! a run: they share its connection pool, its rate limiters and its 429 pause.
//!
//! One attempt: wait for the pause gate and the limiters, `POST {base_url}/chat/completions`,
//! read the body in chunks up to the size cap (a larger body is dropped unread), classify. The
//! whole attempt runs under the request timeout, so no await can hang. Retries follow
//! [`LlmError::is_retryable`] with the schedule of `retry.rs`, and stop at `max_attempts` or
//! when the next delay would pass the total retry budget.

use std::fmt;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, SystemTime};

use bytes::Bytes;
use rand_chacha::ChaCha8Rng;
use reqwest::header::{AUTHORIZATION, CONTENT_TYPE, HeaderValue};
use reqwest::{StatusCode, Url};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use tokio::time::Instant;

use super::config::{ClientConfig, duration_ms};
use super::error::LlmError;
use super::limiter::{Pacer, PauseGate};
use super::retry::{backoff_delay, retry_after};
use super::types::{
    ChatRequest, Completion, body_prefix, error_code_of, error_message_of, parse_completion,
};
use crate::util::seeded_rng;

/// Bytes of an error response read for its message; the rest is not needed.
const ERROR_BODY_BYTES: u64 = 64 * 1024;

/// What a caller sees when the client is about to retry (for "retrying (429, 12 s)" progress).
#[derive(Debug, Clone, Copy)]
pub struct RetryNotice<'error> {
    /// The attempt that failed (1-based).
    pub failed_attempt: u32,
    /// The configured maximum.
    pub max_attempts: u32,
    /// The wait before the next attempt.
    pub delay: Duration,
    /// Why the attempt failed.
    pub error: &'error LlmError,
}

/// Counters over the client's lifetime, shared by all its requests.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct ClientStats {
    /// HTTP requests sent (attempts, retries included).
    pub requests_sent: u64,
    /// Attempts that were followed by a retry.
    pub retries: u64,
    /// 429 responses received.
    pub rate_limited: u64,
    /// Completions returned.
    pub completions: u64,
}

#[derive(Default)]
struct Counters {
    requests_sent: AtomicU64,
    retries: AtomicU64,
    rate_limited: AtomicU64,
    completions: AtomicU64,
}

/// An OpenAI-compatible chat-completions client.
#[derive(Clone)]
pub struct Client {
    inner: Arc<Inner>,
}

struct Inner {
    http: reqwest::Client,
    config: ClientConfig,
    endpoint: Url,
    /// `<base>/models`, for [`Client::list_models`].
    models_endpoint: Url,
    /// The endpoint without user info or query, for messages.
    display_url: String,
    /// `host:port` of the endpoint, for connection errors.
    address: String,
    authorization: Option<HeaderValue>,
    requests_per_minute: Option<Pacer>,
    tokens_per_minute: Option<Pacer>,
    pause: PauseGate,
    jitter: Mutex<ChaCha8Rng>,
    counters: Counters,
}

impl fmt::Debug for Client {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        formatter
            .debug_struct("Client")
            .field("endpoint", &self.inner.display_url)
            .field("config", &self.inner.config)
            .finish_non_exhaustive()
    }
}

impl Client {
    /// A client for `config`; fails on a configuration that cannot work.
    pub fn new(config: ClientConfig) -> Result<Client, LlmError> {
        let invalid = |message: String| LlmError::InvalidConfig { message };
        let base = Url::parse(config.base_url.trim()).map_err(|error| {
            invalid(format!(
                "base url `{}` is not a URL: {error}",
                redacted_url(&config.base_url)
            ))
        })?;
        if !matches!(base.scheme(), "http" | "https") {
            return Err(invalid(format!(
                "base url `{}` must start with http:// or https:// (e.g. http://localhost:8000/v1)",
                redacted_url(&config.base_url)
            )));
        }
        // The path is extended, not the string: a query (Azure's `api-version`) stays a query.
        let mut endpoint = base.clone();
        endpoint.set_path(&format!(
            "{}/chat/completions",
            base.path().trim_end_matches('/')
        ));
        let mut models_endpoint = base.clone();
        models_endpoint.set_path(&format!("{}/models", base.path().trim_end_matches('/')));
        if config.max_attempts == 0 {
            return Err(invalid("max_attempts must be at least 1".to_owned()));
        }
        if config.rpm == Some(0) || config.tpm == Some(0) {
            return Err(invalid("rpm and tpm limits must be at least 1".to_owned()));
        }
        if config.max_body_bytes == 0 {
            return Err(invalid("max_body_bytes must be at least 1".to_owned()));
        }
        let authorization = config
            .api_key
            .as_deref()
            .map(|key| {
                let mut value = HeaderValue::from_str(&format!("Bearer {}", key.trim()))
                    .map_err(|_| invalid("the API key is not a valid header value".to_owned()))?;
                value.set_sensitive(true);
                Ok::<_, LlmError>(value)
            })
            .transpose()?;
        let host = endpoint.host_str().unwrap_or_default().to_owned();
        let port = endpoint.port_or_known_default().unwrap_or_default();
        let address = if host.contains(':') {
            format!("[{host}]:{port}")
        } else {
            format!("{host}:{port}")
        };

        // reqwest is built without a crypto provider of its own (aws-lc-rs needs cmake); ring is
        // installed as the process default. Failing means one is installed already, which is fine.
        let _ = rustls::crypto::ring::default_provider().install_default();
        let mut builder = reqwest::Client::builder()
            .connect_timeout(config.connect_timeout)
            // A redirect would resend the body, possibly to another host; an API never needs it.
            .redirect(reqwest::redirect::Policy::none())
            .user_agent(concat!("contphy-eval/", env!("CARGO_PKG_VERSION")));
        if is_loopback(&endpoint) {
            // A local server (a mock, a local model) must not be sent through a proxy taken
            // from the environment.
            builder = builder.no_proxy();
        }
        let http = builder
            .build()
            .map_err(|error| invalid(format!("cannot build the HTTP client: {error}")))?;

        Ok(Client {
            inner: Arc::new(Inner {
                http,
                display_url: redacted_url(endpoint.as_str()),
                endpoint,
                models_endpoint,
                address,
                authorization,
                requests_per_minute: config.rpm.map(Pacer::per_minute),
                tokens_per_minute: config.tpm.map(Pacer::per_minute),
                pause: PauseGate::default(),
                jitter: Mutex::new(seeded_rng(config.jitter_seed)),
                counters: Counters::default(),
                config,
            }),
        })
    }

    /// The configuration this client was made with.
    pub fn config(&self) -> &ClientConfig {
        &self.inner.config
    }

    /// The base URL as configured, without credentials, for messages.
    pub fn base_url(&self) -> String {
        redacted_url(&self.inner.config.base_url)
    }

    /// The endpoint requests go to, without credentials.
    pub fn endpoint(&self) -> &str {
        &self.inner.display_url
    }

    /// Counters over all requests so far.
    pub fn stats(&self) -> ClientStats {
        let counters = &self.inner.counters;
        ClientStats {
            requests_sent: counters.requests_sent.load(Ordering::Relaxed),
            retries: counters.retries.load(Ordering::Relaxed),
            rate_limited: counters.rate_limited.load(Ordering::Relaxed),
            completions: counters.completions.load(Ordering::Relaxed),
        }
    }

    /// One chat completion, retried as the configuration allows.
    pub async fn complete(&self, request: &ChatRequest) -> Result<Completion, LlmError> {
        self.complete_observed(request, &|_| {}).await
    }

    /// [`Client::complete`], calling `observer` before each retry's wait.
    pub async fn complete_observed(
        &self,
        request: &ChatRequest,
        observer: &(dyn Fn(&RetryNotice<'_>) + Send + Sync),
    ) -> Result<Completion, LlmError> {
        let inner = &*self.inner;
        let config = &inner.config;
        let body = Bytes::from(request.to_json().to_string());
        let estimated_tokens = request.estimated_tokens();
        let started = Instant::now();
        let mut attempt: u32 = 0;
        loop {
            attempt += 1;
            if let Some(pacer) = &inner.requests_per_minute {
                pacer.acquire(1).await;
            }
            if let Some(pacer) = &inner.tokens_per_minute {
                pacer.acquire(estimated_tokens).await;
            }
            // After the limiters: a 429 seen by another worker meanwhile holds this one too.
            inner.pause.wait().await;
            inner.counters.requests_sent.fetch_add(1, Ordering::Relaxed);
            let error = match self.attempt_once(body.clone(), &request.model).await {
                Ok(mut completion) => {
                    completion.attempts = attempt;
                    if let (Some(pacer), Some(usage)) = (&inner.tokens_per_minute, completion.usage)
                    {
                        let reported = i64::try_from(usage.total_tokens).unwrap_or(i64::MAX);
                        let estimated = i64::try_from(estimated_tokens).unwrap_or(i64::MAX);
                        pacer.adjust(reported.saturating_sub(estimated));
                    }
                    inner.counters.completions.fetch_add(1, Ordering::Relaxed);
                    return Ok(completion);
                }
                Err(error) => error,
            };
            if matches!(error, LlmError::RateLimited { .. }) {
                inner.counters.rate_limited.fetch_add(1, Ordering::Relaxed);
            }
            if !error.is_retryable() {
                return Err(if attempt == 1 {
                    error
                } else {
                    LlmError::AfterRetries {
                        attempts: attempt,
                        last: Box::new(error),
                    }
                });
            }
            let exhausted = |error: LlmError| LlmError::RetriesExhausted {
                attempts: attempt,
                last: Box::new(error),
            };
            if attempt >= config.max_attempts {
                return Err(exhausted(error));
            }
            let delay = if let Some(asked) = error.retry_after() {
                asked.min(config.backoff_cap)
            } else {
                let mut rng = inner.jitter.lock().unwrap_or_else(PoisonError::into_inner);
                backoff_delay(attempt, config.backoff_base, config.backoff_cap, &mut *rng)
            };
            if started.elapsed().saturating_add(delay) > config.total_retry_budget {
                return Err(exhausted(error));
            }
            if matches!(error, LlmError::RateLimited { .. }) && error.retry_after().is_some() {
                inner.pause.pause_until(Instant::now() + delay);
            }
            inner.counters.retries.fetch_add(1, Ordering::Relaxed);
            observer(&RetryNotice {
                failed_attempt: attempt,
                max_attempts: config.max_attempts,
                delay,
                error: &error,
            });
            tokio::time::sleep(delay).await;
        }
    }

    /// The model ids the server lists (`GET <base>/models`), once, without retries: the
    /// preflight check that the server is reachable, accepts the key and serves the model.
    ///
    /// `Ok(None)` when the server has no such route (404, 405): some compatible servers do not
    /// list models, and that is no reason to refuse them.
    pub async fn list_models(&self) -> Result<Option<Vec<String>>, LlmError> {
        let inner = &*self.inner;
        let url = redacted_url(inner.models_endpoint.as_str());
        let mut builder = inner.http.get(inner.models_endpoint.clone());
        if let Some(authorization) = &inner.authorization {
            builder = builder.header(AUTHORIZATION, authorization.clone());
        }
        let exchange = async {
            let response = builder
                .send()
                .await
                .map_err(|error| self.transport_error(&error))?;
            let status = response.status();
            if matches!(status.as_u16(), 404 | 405) {
                return Ok(None);
            }
            let limit = usize::try_from(inner.config.max_body_bytes).unwrap_or(usize::MAX);
            let body = read_capped(response, limit)
                .await
                .map_err(|error| self.transport_error(&error))?;
            if !status.is_success() {
                return Err(classify_status(&StatusContext {
                    url: &url,
                    status,
                    model: "",
                    body: &body,
                    retry_after: None,
                }));
            }
            let json: Value =
                serde_json::from_slice(&body).map_err(|error| LlmError::Malformed {
                    url: url.clone(),
                    status: status.as_u16(),
                    message: format!("the model list is not JSON: {error}"),
                    body_prefix: body_prefix(&body),
                })?;
            let ids = json.get("data").and_then(Value::as_array).map(|models| {
                models
                    .iter()
                    .filter_map(|model| model.get("id").and_then(Value::as_str))
                    .map(str::to_owned)
                    .collect::<Vec<_>>()
            });
            Ok(ids)
        };
        match tokio::time::timeout(inner.config.request_timeout, exchange).await {
            Ok(result) => result,
            Err(_elapsed) => Err(LlmError::Timeout {
                url,
                timeout_ms: duration_ms(inner.config.request_timeout),
            }),
        }
    }

    /// One HTTP exchange under the request timeout.
    async fn attempt_once(&self, body: Bytes, model: &str) -> Result<Completion, LlmError> {
        let inner = &*self.inner;
        let mut builder = inner
            .http
            .post(inner.endpoint.clone())
            .header(CONTENT_TYPE, "application/json")
            .body(body);
        if let Some(authorization) = &inner.authorization {
            builder = builder.header(AUTHORIZATION, authorization.clone());
        }
        let exchange = async {
            let response = builder
                .send()
                .await
                .map_err(|error| self.transport_error(&error))?;
            self.read_response(response, model).await
        };
        match tokio::time::timeout(inner.config.request_timeout, exchange).await {
            Ok(result) => result,
            Err(_elapsed) => Err(LlmError::Timeout {
                url: inner.display_url.clone(),
                timeout_ms: duration_ms(inner.config.request_timeout),
            }),
        }
    }

    /// Reads the body (capped) and turns the response into a completion or an error.
    async fn read_response(
        &self,
        mut response: reqwest::Response,
        model: &str,
    ) -> Result<Completion, LlmError> {
        let inner = &*self.inner;
        let url = inner.display_url.as_str();
        let status = response.status();
        let waited = retry_after(response.headers(), SystemTime::now());
        if status.is_success() {
            let limit = inner.config.max_body_bytes;
            let too_large = || LlmError::TooLarge {
                url: url.to_owned(),
                status: status.as_u16(),
                limit_bytes: limit,
            };
            if response
                .content_length()
                .is_some_and(|length| length > limit)
            {
                return Err(too_large());
            }
            let mut body = Vec::new();
            while let Some(chunk) = response
                .chunk()
                .await
                .map_err(|error| self.transport_error(&error))?
            {
                if u64::try_from(body.len() + chunk.len()).unwrap_or(u64::MAX) > limit {
                    // Dropping the response closes the connection; the rest is never read.
                    return Err(too_large());
                }
                body.extend_from_slice(&chunk);
            }
            return parse_completion(&body, url, status.as_u16());
        }

        // An error status: only the start of the body is needed, for the server's message.
        let mut body = Vec::new();
        let limit = usize::try_from(ERROR_BODY_BYTES.min(inner.config.max_body_bytes))
            .unwrap_or(usize::MAX);
        while body.len() < limit {
            match response.chunk().await {
                Ok(Some(chunk)) => body.extend_from_slice(&chunk),
                // A broken error body still has a status worth classifying.
                Ok(None) | Err(_) => break,
            }
        }
        body.truncate(limit);
        Err(classify_status(&StatusContext {
            url,
            status,
            model,
            body: &body,
            retry_after: waited,
        }))
    }

    fn transport_error(&self, error: &reqwest::Error) -> LlmError {
        let inner = &*self.inner;
        if error.is_timeout() && !error.is_connect() {
            return LlmError::Timeout {
                url: inner.display_url.clone(),
                timeout_ms: duration_ms(inner.config.request_timeout),
            };
        }
        let mut detail = innermost_message(error);
        if error.is_connect() && error.is_timeout() {
            detail = format!(
                "connect timed out after {} ms",
                duration_ms(inner.config.connect_timeout)
            );
        }
        LlmError::Connection {
            url: inner.display_url.clone(),
            address: inner.address.clone(),
            detail,
        }
    }
}

/// What classifying an error response needs.
struct StatusContext<'a> {
    url: &'a str,
    status: StatusCode,
    model: &'a str,
    body: &'a [u8],
    retry_after: Option<Duration>,
}

/// The error for a non-2xx response.
fn classify_status(context: &StatusContext<'_>) -> LlmError {
    let url = context.url.to_owned();
    let status = context.status.as_u16();
    let json: Option<Value> = serde_json::from_slice(context.body).ok();
    let code = json.as_ref().and_then(error_code_of).unwrap_or_default();
    let message = json
        .as_ref()
        .and_then(error_message_of)
        .or_else(|| {
            let text = body_prefix(context.body);
            (!text.trim().is_empty()).then(|| text.trim().to_owned())
        })
        .unwrap_or_else(|| {
            context
                .status
                .canonical_reason()
                .unwrap_or("no message")
                .to_owned()
        });
    let retry_after_ms = context.retry_after.map(duration_ms);
    match status {
        401 | 403 => LlmError::Unauthorized {
            url,
            status,
            message,
        },
        404 => LlmError::UnknownModel {
            url,
            status,
            model: context.model.to_owned(),
            message,
        },
        429 if code == "insufficient_quota" => LlmError::QuotaExceeded {
            url,
            status,
            message,
        },
        429 => LlmError::RateLimited {
            url,
            status,
            message,
            retry_after_ms,
        },
        408 | 500..=599 => LlmError::ServerError {
            url,
            status,
            message,
            retry_after_ms,
        },
        _ if code == "model_not_found" => LlmError::UnknownModel {
            url,
            status,
            model: context.model.to_owned(),
            message,
        },
        400..=499 if is_context_length(&code, &message) => LlmError::ContextLength {
            url,
            status,
            message,
        },
        _ => LlmError::BadRequest {
            url,
            status,
            message,
        },
    }
}

/// Whether an error says the prompt does not fit: OpenAI's code, or the phrases vLLM, llama.cpp
/// and other compatible servers use.
fn is_context_length(code: &str, message: &str) -> bool {
    const PHRASES: &[&str] = &[
        "context_length_exceeded",
        "context length",
        "maximum context",
        "context window",
        "prompt is too long",
        "too many tokens",
    ];
    if code == "context_length_exceeded" {
        return true;
    }
    let message = message.to_lowercase();
    PHRASES.iter().any(|phrase| message.contains(phrase))
}

/// At most `limit` bytes of a response body; the rest is never read.
async fn read_capped(
    mut response: reqwest::Response,
    limit: usize,
) -> Result<Vec<u8>, reqwest::Error> {
    let mut body = Vec::new();
    while body.len() < limit {
        match response.chunk().await? {
            Some(chunk) => body.extend_from_slice(&chunk),
            None => break,
        }
    }
    body.truncate(limit);
    Ok(body)
}

/// The deepest cause in an error chain (`Connection refused (os error 111)` rather than
/// reqwest's "error sending request").
fn innermost_message(error: &(dyn std::error::Error + 'static)) -> String {
    let mut current = error;
    while let Some(source) = current.source() {
        current = source;
    }
    current.to_string()
}

fn is_loopback(url: &Url) -> bool {
    let host = url.host_str().unwrap_or_default().trim_matches(['[', ']']);
    host.parse::<std::net::IpAddr>()
        .map_or(host.eq_ignore_ascii_case("localhost"), |address| {
            address.is_loopback()
        })
}

/// `url` without user info and query (where keys sometimes travel), for messages and manifests.
pub(crate) fn redacted_url(url: &str) -> String {
    match Url::parse(url.trim()) {
        Ok(mut parsed) => {
            let _ = parsed.set_username("");
            let _ = parsed.set_password(None);
            parsed.set_query(None);
            parsed.to_string()
        }
        // Not a URL: keep only what precedes any `@` or `?`, which cannot hold a secret.
        Err(_) => url
            .rsplit('@')
            .next()
            .unwrap_or_default()
            .split('?')
            .next()
            .unwrap_or_default()
            .to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn classify(status: u16, body: &Value) -> LlmError {
        classify_status(&StatusContext {
            url: "http://127.0.0.1:9/v1/chat/completions",
            status: StatusCode::from_u16(status).unwrap(),
            model: "gpt-4o",
            body: body.to_string().as_bytes(),
            retry_after: None,
        })
    }

    #[test]
    fn status_classification_table() {
        let error =
            |message: &str, code: &str| json!({"error": {"message": message, "code": code}});
        // (status, body, kind, retryable, fatal)
        let cases = [
            (
                400,
                error("bad temperature", "invalid_value"),
                "bad_request",
                false,
                false,
            ),
            (
                400,
                error("This model's maximum context length is 8192 tokens", ""),
                "context_length",
                false,
                false,
            ),
            (
                400,
                error("too long", "context_length_exceeded"),
                "context_length",
                false,
                false,
            ),
            (
                401,
                error("bad key", "invalid_api_key"),
                "unauthorized",
                false,
                true,
            ),
            (403, error("no access", ""), "unauthorized", false, true),
            (
                404,
                error("The model `x` does not exist", "model_not_found"),
                "unknown_model",
                false,
                true,
            ),
            (
                400,
                error("no such model", "model_not_found"),
                "unknown_model",
                false,
                true,
            ),
            (408, json!({}), "server_error", true, false),
            (409, error("conflict", ""), "bad_request", false, false),
            (
                422,
                json!({"detail": "unprocessable"}),
                "bad_request",
                false,
                false,
            ),
            (
                429,
                error("slow down", "rate_limit_exceeded"),
                "rate_limited",
                true,
                false,
            ),
            (
                429,
                json!({"error": {"message": "quota", "type": "insufficient_quota"}}),
                "quota_exceeded",
                false,
                true,
            ),
            (500, json!("oops"), "server_error", true, false),
            (
                503,
                json!({"message": "overloaded"}),
                "server_error",
                true,
                false,
            ),
            (302, json!({}), "bad_request", false, false),
        ];
        for (status, body, kind, retryable, fatal) in cases {
            let classified = classify(status, &body);
            assert_eq!(classified.kind(), kind, "{status} {body}");
            assert_eq!(classified.is_retryable(), retryable, "{status} {body}");
            assert_eq!(classified.is_fatal_for_run(), fatal, "{status} {body}");
            assert_eq!(classified.status(), Some(status));
        }
    }

    #[test]
    fn error_message_falls_back_to_body_text_then_reason() {
        let from_text = classify_status(&StatusContext {
            url: "u",
            status: StatusCode::BAD_GATEWAY,
            model: "m",
            body: b"<html>bad gateway</html>",
            retry_after: Some(Duration::from_secs(2)),
        });
        assert_eq!(
            from_text.to_string(),
            "`u` answered 502 (server error, retry after 2000 ms): <html>bad gateway</html>"
        );
        let from_reason = classify_status(&StatusContext {
            url: "u",
            status: StatusCode::SERVICE_UNAVAILABLE,
            model: "m",
            body: b"",
            retry_after: None,
        });
        assert!(from_reason.to_string().ends_with(": Service Unavailable"));
    }

    #[test]
    fn redacted_urls_lose_user_info_and_query() {
        let cases = [
            (
                "http://user:pw@127.0.0.1:8/v1?api-key=k",
                "http://127.0.0.1:8/v1",
            ),
            ("http://127.0.0.1:8/v1/", "http://127.0.0.1:8/v1/"),
            ("not a url user:pw@host?key=k", "host"),
        ];
        for (url, expected) in cases {
            assert_eq!(redacted_url(url), expected);
        }
    }

    /// A change to a valid configuration, and the message it must produce.
    type ConfigCase = (fn(&mut ClientConfig), &'static str);

    #[test]
    fn invalid_configurations_are_refused() {
        let cases: [ConfigCase; 5] = [
            (|c| c.base_url = "not a url".into(), "is not a URL"),
            (
                |c| c.base_url = "ftp://127.0.0.1/".into(),
                "must start with http:// or https://",
            ),
            (|c| c.max_attempts = 0, "max_attempts"),
            (|c| c.rpm = Some(0), "rpm and tpm"),
            (
                |c| c.api_key = Some("bad\nkey".into()),
                "not a valid header value",
            ),
        ];
        for (change, expected) in cases {
            let mut config = ClientConfig::new("http://127.0.0.1:9/v1");
            change(&mut config);
            let error = Client::new(config).unwrap_err();
            assert!(error.is_fatal_for_run());
            assert!(error.to_string().contains(expected), "{error}");
            assert!(!error.to_string().contains("bad\nkey"));
        }
    }

    #[test]
    fn endpoint_joins_base_url_with_or_without_a_slash() {
        for base in ["http://127.0.0.1:9/v1", "http://127.0.0.1:9/v1/"] {
            let client = Client::new(ClientConfig::new(base)).unwrap();
            assert_eq!(client.endpoint(), "http://127.0.0.1:9/v1/chat/completions");
            assert_eq!(client.inner.address, "127.0.0.1:9");
        }
        let azure =
            Client::new(ClientConfig::new("http://127.0.0.1:9/openai?api-version=1")).unwrap();
        assert_eq!(
            azure.endpoint(),
            "http://127.0.0.1:9/openai/chat/completions"
        );
        assert_eq!(azure.inner.endpoint.query(), Some("api-version=1"));
        let debug = format!(
            "{:?}",
            Client::new(ClientConfig {
                api_key: Some("sk-hidden".into()),
                ..ClientConfig::new("http://127.0.0.1:9")
            })
            .unwrap()
        );
        assert!(!debug.contains("sk-hidden"), "{debug}");
    }
}
