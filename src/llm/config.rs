//! `ClientConfig`: where the client sends requests, with which key, and how hard it tries.
//!
//! Input: values from the caller's settings (the API key from `OPENAI_API_KEY`, read by the
//! caller). Output: a validated configuration for [`super::Client::new`]. The key never leaves
//! this struct except as the `Authorization` header: `Debug` redacts it and the struct is not
//! serialisable; [`ClientConfig::manifest_json`] is the key-free description for run manifests.

use std::fmt;
use std::time::Duration;

use serde_json::{Value, json};

/// OpenAI's own endpoint, the base URL when the caller names none. Tests never use it: they pass
/// the loopback URL of [`super::mock::MockServer`].
pub const DEFAULT_BASE_URL: &str = "https://api.openai.com/v1";

/// How the client talks to one OpenAI-compatible endpoint.
#[derive(Clone, PartialEq, Eq)]
pub struct ClientConfig {
    /// Base URL; requests go to `{base_url}/chat/completions`.
    pub base_url: String,
    /// Bearer token; `None` sends no `Authorization` header (local servers).
    pub api_key: Option<String>,
    /// Time for one attempt, from sending the request to the last byte of the body. Default
    /// 120 s: long programs from slow models take tens of seconds; a hung connection must not
    /// hold a job slot for ever (openai/evals #1292).
    pub request_timeout: Duration,
    /// Time to establish a connection. Default 10 s.
    pub connect_timeout: Duration,
    /// Requests sent for one completion, the first included. Default 6.
    pub max_attempts: u32,
    /// Upper bound of the first retry's random delay; doubles per retry. Default 1 s.
    pub backoff_base: Duration,
    /// Largest delay between attempts, `Retry-After` included. Default 60 s.
    pub backoff_cap: Duration,
    /// Wall time from the first attempt after which no new attempt starts. Default 10 min.
    pub total_retry_budget: Duration,
    /// Requests per minute across all concurrent requests of the client (each attempt counts).
    pub rpm: Option<u32>,
    /// Tokens per minute across all concurrent requests of the client (estimated before the
    /// request, corrected by the reported usage).
    pub tpm: Option<u32>,
    /// Largest accepted response body. Default 8 MiB: a completion is a few KiB; anything far
    /// larger is a misbehaving server and is not read into memory.
    pub max_body_bytes: u64,
    /// Seed of the retry jitter. Jitter only shifts when retries happen, never what is returned.
    pub jitter_seed: u64,
}

impl ClientConfig {
    /// The defaults, against `base_url`.
    pub fn new(base_url: impl Into<String>) -> Self {
        Self {
            base_url: base_url.into(),
            api_key: None,
            request_timeout: Duration::from_mins(2),
            connect_timeout: Duration::from_secs(10),
            max_attempts: 6,
            backoff_base: Duration::from_secs(1),
            backoff_cap: Duration::from_mins(1),
            total_retry_budget: Duration::from_mins(10),
            rpm: None,
            tpm: None,
            max_body_bytes: 8 * 1024 * 1024,
            jitter_seed: 0,
        }
    }

    /// The settings that shape results and timing, without the key, for run manifests.
    pub fn manifest_json(&self) -> Value {
        json!({
            "base_url": super::client::redacted_url(&self.base_url),
            "api_key_set": self.api_key.is_some(),
            "request_timeout_ms": duration_ms(self.request_timeout),
            "connect_timeout_ms": duration_ms(self.connect_timeout),
            "max_attempts": self.max_attempts,
            "backoff_base_ms": duration_ms(self.backoff_base),
            "backoff_cap_ms": duration_ms(self.backoff_cap),
            "total_retry_budget_ms": duration_ms(self.total_retry_budget),
            "rpm": self.rpm,
            "tpm": self.tpm,
            "max_body_bytes": self.max_body_bytes,
        })
    }
}

impl Default for ClientConfig {
    fn default() -> Self {
        Self::new(DEFAULT_BASE_URL)
    }
}

impl fmt::Debug for ClientConfig {
    // By hand so that the key can never reach a log line or a panic message.
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        formatter
            .debug_struct("ClientConfig")
            .field("base_url", &super::client::redacted_url(&self.base_url))
            .field("api_key", &self.api_key.as_ref().map(|_| "<redacted>"))
            .field("request_timeout", &self.request_timeout)
            .field("connect_timeout", &self.connect_timeout)
            .field("max_attempts", &self.max_attempts)
            .field("backoff_base", &self.backoff_base)
            .field("backoff_cap", &self.backoff_cap)
            .field("total_retry_budget", &self.total_retry_budget)
            .field("rpm", &self.rpm)
            .field("tpm", &self.tpm)
            .field("max_body_bytes", &self.max_body_bytes)
            .field("jitter_seed", &self.jitter_seed)
            .finish()
    }
}

/// Whole milliseconds, saturating.
pub(crate) fn duration_ms(duration: Duration) -> u64 {
    u64::try_from(duration.as_millis()).unwrap_or(u64::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn debug_and_manifest_never_show_the_key() {
        let mut config = ClientConfig::new("http://user:secret-pass@127.0.0.1:9/v1");
        config.api_key = Some("sk-test-do-not-print".into());
        let debug = format!("{config:?}");
        assert!(!debug.contains("sk-test-do-not-print"), "{debug}");
        assert!(!debug.contains("secret-pass"), "{debug}");
        assert!(debug.contains("<redacted>"), "{debug}");
        let manifest = config.manifest_json().to_string();
        assert!(!manifest.contains("sk-test"), "{manifest}");
        assert!(!manifest.contains("secret-pass"), "{manifest}");
        assert!(manifest.contains(r#""api_key_set":true"#), "{manifest}");
    }
}
