//! `LlmError`: every way one chat completion can fail, classified for the retry loop and the run.
//!
//! Inputs are transport failures (connect, timeout, a connection closed mid-response), HTTP
//! statuses with the server's error body, and responses that are not a usable completion. The
//! output is one serde-serialisable enum: [`LlmError::kind`] is its stable tag for records,
//! [`LlmError::is_retryable`] drives the retry loop, and [`LlmError::is_fatal_for_run`] tells the
//! caller to stop the whole run (bad key, unknown model) instead of failing every question the
//! same way. Every message names the endpoint URL (never the key) and, where there is one, the
//! HTTP status. Causes are kept as text because the enum is stored in per-question records.

use std::time::Duration;

use serde::{Deserialize, Serialize};

/// Why one chat completion failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum LlmError {
    /// The TCP/TLS connection could not be made, or broke before a full response arrived.
    /// Retried.
    #[error("connection to `{address}` failed for `{url}`: {detail}")]
    Connection {
        /// The endpoint, without credentials.
        url: String,
        /// `host:port` the client tried to reach.
        address: String,
        /// The innermost cause, e.g. `Connection refused (os error 111)`.
        detail: String,
    },
    /// No complete response arrived within the request timeout. Retried.
    #[error("no complete response from `{url}` within {timeout_ms} ms")]
    Timeout {
        /// The endpoint, without credentials.
        url: String,
        /// The request timeout that ran out.
        timeout_ms: u64,
    },
    /// HTTP 429. Retried, after `Retry-After` when the server sent one.
    #[error("`{url}` answered {status} (rate limited{}): {message}", retry_after_text(*.retry_after_ms))]
    RateLimited {
        /// The endpoint, without credentials.
        url: String,
        /// Always 429.
        status: u16,
        /// The server's error message.
        message: String,
        /// The server's `Retry-After`, if any.
        retry_after_ms: Option<u64>,
    },
    /// HTTP 408 or 5xx. Retried.
    #[error("`{url}` answered {status} (server error{}): {message}", retry_after_text(*.retry_after_ms))]
    ServerError {
        /// The endpoint, without credentials.
        url: String,
        /// 408 or 5xx.
        status: u16,
        /// The server's error message, or the start of its body.
        message: String,
        /// The server's `Retry-After`, if any.
        retry_after_ms: Option<u64>,
    },
    /// A 4xx the request itself caused (other than the specific ones below). Never retried:
    /// the same request would fail the same way.
    #[error("`{url}` rejected the request ({status}): {message}")]
    BadRequest {
        /// The endpoint, without credentials.
        url: String,
        /// The HTTP status.
        status: u16,
        /// The server's error message.
        message: String,
    },
    /// The prompt plus `max_tokens` does not fit the model's context window. Never retried
    /// (ViperGPT retried it forever: cvlab-columbia/viper #18).
    #[error("`{url}` rejected the request ({status}): context length exceeded: {message}")]
    ContextLength {
        /// The endpoint, without credentials.
        url: String,
        /// The HTTP status (400 in practice).
        status: u16,
        /// The server's error message.
        message: String,
    },
    /// HTTP 401 or 403: the key is missing, wrong or lacks access. Fatal for the run.
    #[error("`{url}` refused the credentials ({status}): {message}; check OPENAI_API_KEY")]
    Unauthorized {
        /// The endpoint, without credentials.
        url: String,
        /// 401 or 403.
        status: u16,
        /// The server's error message.
        message: String,
    },
    /// HTTP 404 or error code `model_not_found`: the model (or the endpoint) does not exist.
    /// Fatal for the run.
    #[error(
        "`{url}` does not serve model `{model}` ({status}): {message}; check --model and --base-url"
    )]
    UnknownModel {
        /// The endpoint, without credentials.
        url: String,
        /// The HTTP status.
        status: u16,
        /// The model that was asked for.
        model: String,
        /// The server's error message.
        message: String,
    },
    /// HTTP 429 with error code `insufficient_quota`: the account has no credit left. Waiting
    /// does not help, so this is not retried, and it is fatal for the run.
    #[error("`{url}` answered {status}: the account's quota is used up: {message}")]
    QuotaExceeded {
        /// The endpoint, without credentials.
        url: String,
        /// Always 429.
        status: u16,
        /// The server's error message.
        message: String,
    },
    /// The response's first choice has no content (null, missing or empty).
    #[error(
        "`{url}` answered {status} with an empty completion (finish reason: {})",
        finish_reason.as_deref().unwrap_or("none")
    )]
    EmptyCompletion {
        /// The endpoint, without credentials.
        url: String,
        /// The HTTP status (2xx).
        status: u16,
        /// The choice's `finish_reason`, e.g. `content_filter` or `length`.
        finish_reason: Option<String>,
    },
    /// The response has no `choices`, or an empty list.
    #[error("`{url}` answered {status} with no choices{}", detail.as_deref().map(|d| format!(": {d}")).unwrap_or_default())]
    NoChoices {
        /// The endpoint, without credentials.
        url: String,
        /// The HTTP status (2xx).
        status: u16,
        /// The server's error message, when the body carried one instead of choices.
        detail: Option<String>,
    },
    /// The response body is not JSON, or not a JSON object.
    #[error(
        "`{url}` answered {status} with a body that is not a JSON object ({message}); it starts with {body_prefix:?}"
    )]
    Malformed {
        /// The endpoint, without credentials.
        url: String,
        /// The HTTP status.
        status: u16,
        /// The parser's message.
        message: String,
        /// The first 200 bytes of the body (lossy UTF-8).
        body_prefix: String,
    },
    /// The response body is larger than the configured cap; the rest was not read.
    #[error("`{url}` answered {status} with a body over the limit of {limit_bytes} bytes")]
    TooLarge {
        /// The endpoint, without credentials.
        url: String,
        /// The HTTP status.
        status: u16,
        /// The cap (`ClientConfig::max_body_bytes`).
        limit_bytes: u64,
    },
    /// Every allowed attempt failed with a retryable error, or the retry budget ran out.
    #[error("gave up after {attempts} attempts: {last}")]
    RetriesExhausted {
        /// Requests sent.
        attempts: u32,
        /// The error of the last attempt.
        last: Box<LlmError>,
    },
    /// An error that cannot be retried, after earlier attempts failed with retryable ones.
    #[error("{last} (attempt {attempts})")]
    AfterRetries {
        /// Requests sent, the failing one included.
        attempts: u32,
        /// The final, non-retryable error.
        last: Box<LlmError>,
    },
    /// The client configuration cannot work (bad base URL, an API key that is not a valid
    /// header value, a zero limit). Fatal for the run.
    #[error("invalid llm client configuration: {message}")]
    InvalidConfig {
        /// What is wrong.
        message: String,
    },
}

fn retry_after_text(retry_after_ms: Option<u64>) -> String {
    retry_after_ms
        .map(|milliseconds| format!(", retry after {milliseconds} ms"))
        .unwrap_or_default()
}

impl LlmError {
    /// The stable tag of this error (its serde `kind`), for records and reports.
    pub fn kind(&self) -> &'static str {
        match self {
            LlmError::Connection { .. } => "connection",
            LlmError::Timeout { .. } => "timeout",
            LlmError::RateLimited { .. } => "rate_limited",
            LlmError::ServerError { .. } => "server_error",
            LlmError::BadRequest { .. } => "bad_request",
            LlmError::ContextLength { .. } => "context_length",
            LlmError::Unauthorized { .. } => "unauthorized",
            LlmError::UnknownModel { .. } => "unknown_model",
            LlmError::QuotaExceeded { .. } => "quota_exceeded",
            LlmError::EmptyCompletion { .. } => "empty_completion",
            LlmError::NoChoices { .. } => "no_choices",
            LlmError::Malformed { .. } => "malformed",
            LlmError::TooLarge { .. } => "too_large",
            LlmError::RetriesExhausted { .. } => "retries_exhausted",
            LlmError::AfterRetries { .. } => "after_retries",
            LlmError::InvalidConfig { .. } => "invalid_config",
        }
    }

    /// The error of the last attempt, looking through [`LlmError::RetriesExhausted`] and
    /// [`LlmError::AfterRetries`].
    pub fn root(&self) -> &LlmError {
        match self {
            LlmError::RetriesExhausted { last, .. } | LlmError::AfterRetries { last, .. } => {
                last.root()
            }
            other => other,
        }
    }

    /// Whether another attempt of the same request may succeed: connection errors, timeouts,
    /// 408, 429 (but not an exhausted quota) and 5xx.
    pub fn is_retryable(&self) -> bool {
        matches!(
            self,
            LlmError::Connection { .. }
                | LlmError::Timeout { .. }
                | LlmError::RateLimited { .. }
                | LlmError::ServerError { .. }
        )
    }

    /// Whether every further request of the run would fail the same way, so the caller should
    /// stop the run (exit 1) rather than record the same failure for every question.
    pub fn is_fatal_for_run(&self) -> bool {
        matches!(
            self.root(),
            LlmError::Unauthorized { .. }
                | LlmError::UnknownModel { .. }
                | LlmError::QuotaExceeded { .. }
                | LlmError::InvalidConfig { .. }
        )
    }

    /// Requests sent before the client gave up (1 for an error of the first attempt, 0 for a
    /// configuration error).
    pub fn attempts(&self) -> u32 {
        match self {
            LlmError::RetriesExhausted { attempts, .. }
            | LlmError::AfterRetries { attempts, .. } => *attempts,
            LlmError::InvalidConfig { .. } => 0,
            _ => 1,
        }
    }

    /// The server's `Retry-After`, when this error carries one.
    pub fn retry_after(&self) -> Option<Duration> {
        match self {
            LlmError::RateLimited { retry_after_ms, .. }
            | LlmError::ServerError { retry_after_ms, .. } => {
                retry_after_ms.map(Duration::from_millis)
            }
            _ => None,
        }
    }

    /// The HTTP status behind this error, if a response arrived.
    pub fn status(&self) -> Option<u16> {
        match self.root() {
            LlmError::RateLimited { status, .. }
            | LlmError::ServerError { status, .. }
            | LlmError::BadRequest { status, .. }
            | LlmError::ContextLength { status, .. }
            | LlmError::Unauthorized { status, .. }
            | LlmError::UnknownModel { status, .. }
            | LlmError::QuotaExceeded { status, .. }
            | LlmError::EmptyCompletion { status, .. }
            | LlmError::NoChoices { status, .. }
            | LlmError::Malformed { status, .. }
            | LlmError::TooLarge { status, .. } => Some(*status),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn url() -> String {
        "http://127.0.0.1:9/v1/chat/completions".to_owned()
    }

    #[test]
    fn kind_matches_the_serde_tag_for_every_variant() {
        let errors = vec![
            LlmError::Connection {
                url: url(),
                address: "127.0.0.1:9".into(),
                detail: "refused".into(),
            },
            LlmError::Timeout {
                url: url(),
                timeout_ms: 5,
            },
            LlmError::RateLimited {
                url: url(),
                status: 429,
                message: "slow down".into(),
                retry_after_ms: Some(1000),
            },
            LlmError::ServerError {
                url: url(),
                status: 503,
                message: "busy".into(),
                retry_after_ms: None,
            },
            LlmError::BadRequest {
                url: url(),
                status: 422,
                message: "bad".into(),
            },
            LlmError::ContextLength {
                url: url(),
                status: 400,
                message: "too long".into(),
            },
            LlmError::Unauthorized {
                url: url(),
                status: 401,
                message: "no".into(),
            },
            LlmError::UnknownModel {
                url: url(),
                status: 404,
                model: "m".into(),
                message: "no".into(),
            },
            LlmError::QuotaExceeded {
                url: url(),
                status: 429,
                message: "pay".into(),
            },
            LlmError::EmptyCompletion {
                url: url(),
                status: 200,
                finish_reason: None,
            },
            LlmError::NoChoices {
                url: url(),
                status: 200,
                detail: None,
            },
            LlmError::Malformed {
                url: url(),
                status: 200,
                message: "eof".into(),
                body_prefix: "{".into(),
            },
            LlmError::TooLarge {
                url: url(),
                status: 200,
                limit_bytes: 8,
            },
            LlmError::RetriesExhausted {
                attempts: 6,
                last: Box::new(LlmError::Timeout {
                    url: url(),
                    timeout_ms: 5,
                }),
            },
            LlmError::AfterRetries {
                attempts: 2,
                last: Box::new(LlmError::BadRequest {
                    url: url(),
                    status: 400,
                    message: "bad".into(),
                }),
            },
            LlmError::InvalidConfig {
                message: "x".into(),
            },
        ];
        for error in errors {
            let json = serde_json::to_value(&error).unwrap();
            assert_eq!(json["kind"], error.kind(), "{error}");
            let back: LlmError = serde_json::from_value(json).unwrap();
            assert_eq!(back, error);
        }
    }

    #[test]
    fn classification_table() {
        // (error, retryable, fatal for the run)
        let unauthorized = LlmError::Unauthorized {
            url: url(),
            status: 401,
            message: "no".into(),
        };
        let server = LlmError::ServerError {
            url: url(),
            status: 500,
            message: "oops".into(),
            retry_after_ms: None,
        };
        let cases = [
            (server.clone(), true, false),
            (unauthorized.clone(), false, true),
            (
                LlmError::RetriesExhausted {
                    attempts: 3,
                    last: Box::new(server),
                },
                false,
                false,
            ),
            (
                LlmError::AfterRetries {
                    attempts: 2,
                    last: Box::new(unauthorized),
                },
                false,
                true,
            ),
        ];
        for (error, retryable, fatal) in cases {
            assert_eq!(error.is_retryable(), retryable, "{error}");
            assert_eq!(error.is_fatal_for_run(), fatal, "{error}");
        }
    }

    #[test]
    fn messages_name_the_url_and_status() {
        let error = LlmError::RateLimited {
            url: url(),
            status: 429,
            message: "slow down".into(),
            retry_after_ms: Some(1500),
        };
        assert_eq!(
            error.to_string(),
            "`http://127.0.0.1:9/v1/chat/completions` answered 429 (rate limited, retry after \
             1500 ms): slow down"
        );
        let exhausted = LlmError::RetriesExhausted {
            attempts: 6,
            last: Box::new(error),
        };
        assert!(
            exhausted
                .to_string()
                .starts_with("gave up after 6 attempts: `http://")
        );
        assert_eq!(exhausted.status(), Some(429));
        assert_eq!(exhausted.attempts(), 6);
    }
}
