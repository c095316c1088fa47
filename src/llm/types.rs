//! The request and completion types of the chat-completions API, and the lenient response parser.
//!
//! Inputs: a [`ChatRequest`] built by the caller; the raw bytes of a 2xx response body.
//! Outputs: the JSON body sent on the wire ([`ChatRequest::to_json`]), its canonical encoding
//! for cache keys ([`ChatRequest::canonical_json`]), and a [`Completion`] that keeps the raw JSON
//! next to the fields read from it.
//!
//! Parsing is lenient on purpose: "OpenAI-compatible" servers add fields, send `finish_reason`
//! values outside OpenAI's list (`""`, `eos`), omit `usage`, or send content as a list of parts
//! (mofa-org/mofa #1155, OpenSecretCloud/maple-proxy #3 broke strict clients). Only what the
//! evaluator needs is required: a first choice with non-empty text.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use super::error::LlmError;
use crate::util::canonical_json;

/// Bytes of a body quoted in a `Malformed` error.
const BODY_PREFIX_BYTES: usize = 200;

/// Completion tokens assumed for the rate limiter when a request sets no `max_tokens`; the
/// estimate is corrected with the usage the server reports.
const DEFAULT_COMPLETION_TOKENS_ESTIMATE: u64 = 1024;

/// One message of a chat.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct ChatMessage {
    /// `system`, `user` or `assistant`.
    pub role: String,
    /// The message text.
    pub content: String,
}

impl ChatMessage {
    /// A `system` message.
    pub fn system(content: impl Into<String>) -> Self {
        Self {
            role: "system".to_owned(),
            content: content.into(),
        }
    }

    /// A `user` message.
    pub fn user(content: impl Into<String>) -> Self {
        Self {
            role: "user".to_owned(),
            content: content.into(),
        }
    }

    /// An `assistant` message (a worked example in a few-shot prompt).
    pub fn assistant(content: impl Into<String>) -> Self {
        Self {
            role: "assistant".to_owned(),
            content: content.into(),
        }
    }
}

/// Sampling parameters. Only the ones that are set go on the wire, so a server's own defaults
/// apply to the rest (some models reject `temperature` or `max_tokens` outright).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct SamplingParams {
    /// Sampling temperature.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temperature: Option<f64>,
    /// Nucleus sampling mass.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub top_p: Option<f64>,
    /// Upper bound on completion tokens.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_tokens: Option<u32>,
    /// The server-side sampling seed (best effort on OpenAI's side).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Stop sequences.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stop: Vec<String>,
}

/// One chat-completions request.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChatRequest {
    /// The model id, e.g. `gpt-4o`.
    pub model: String,
    /// The conversation, oldest first.
    pub messages: Vec<ChatMessage>,
    /// Sampling parameters.
    #[serde(default)]
    pub sampling: SamplingParams,
    /// Provider-specific body fields (e.g. `max_completion_tokens`). They go on the wire and
    /// into the canonical encoding; a key that clashes with a typed field loses to it.
    #[serde(default, skip_serializing_if = "Map::is_empty")]
    pub extra: Map<String, Value>,
}

impl ChatRequest {
    /// A request with default sampling and no extra fields.
    pub fn new(model: impl Into<String>, messages: Vec<ChatMessage>) -> Self {
        Self {
            model: model.into(),
            messages,
            sampling: SamplingParams::default(),
            extra: Map::new(),
        }
    }

    /// The JSON body sent to `/chat/completions`: model, messages and the sampling parameters
    /// that are set, plus `extra`.
    pub fn to_json(&self) -> Value {
        let mut body = self.extra.clone();
        body.insert("model".to_owned(), Value::from(self.model.as_str()));
        let messages = self
            .messages
            .iter()
            .map(|message| {
                let mut object = Map::new();
                object.insert("role".to_owned(), Value::from(message.role.as_str()));
                object.insert("content".to_owned(), Value::from(message.content.as_str()));
                Value::Object(object)
            })
            .collect();
        body.insert("messages".to_owned(), Value::Array(messages));
        let sampling = &self.sampling;
        if let Some(temperature) = sampling.temperature {
            body.insert("temperature".to_owned(), Value::from(temperature));
        }
        if let Some(top_p) = sampling.top_p {
            body.insert("top_p".to_owned(), Value::from(top_p));
        }
        if let Some(max_tokens) = sampling.max_tokens {
            body.insert("max_tokens".to_owned(), Value::from(max_tokens));
        }
        if let Some(seed) = sampling.seed {
            body.insert("seed".to_owned(), Value::from(seed));
        }
        if !sampling.stop.is_empty() {
            body.insert(
                "stop".to_owned(),
                Value::Array(
                    sampling
                        .stop
                        .iter()
                        .map(|s| Value::from(s.as_str()))
                        .collect(),
                ),
            );
        }
        Value::Object(body)
    }

    /// The canonical encoding of [`ChatRequest::to_json`] (keys sorted at every depth): equal
    /// requests give equal strings, the input of program-cache keys.
    pub fn canonical_json(&self) -> String {
        canonical_json(&self.to_json())
    }

    /// Tokens this request may use, for the tokens-per-minute limiter: characters of all
    /// messages / 4, plus `max_tokens` (or 1024 when unset).
    pub fn estimated_tokens(&self) -> u64 {
        let characters: usize = self
            .messages
            .iter()
            .map(|message| message.content.chars().count())
            .sum();
        let prompt = u64::try_from(characters / 4).unwrap_or(u64::MAX);
        let completion = self
            .sampling
            .max_tokens
            .map_or(DEFAULT_COMPLETION_TOKENS_ESTIMATE, u64::from);
        prompt.saturating_add(completion)
    }

    /// The text of the last `user` message, if any.
    pub fn last_user_text(&self) -> Option<&str> {
        self.messages
            .iter()
            .rev()
            .find(|message| message.role == "user")
            .map(|message| message.content.as_str())
    }
}

/// Token counts as the server reported them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct TokenUsage {
    /// Tokens of the prompt.
    pub prompt_tokens: u64,
    /// Tokens of the completion.
    pub completion_tokens: u64,
    /// Their sum (as reported; computed when the server left it out).
    pub total_tokens: u64,
}

/// A successful chat completion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Completion {
    /// The text of the first choice.
    pub content: String,
    /// The first choice's `finish_reason`, as free text (`stop`, `length`, ...).
    pub finish_reason: Option<String>,
    /// Token counts, when the server reported them.
    pub usage: Option<TokenUsage>,
    /// The model id the server reported (often a dated snapshot of the one asked for).
    pub model: Option<String>,
    /// The server's `system_fingerprint`, for the run manifest.
    pub system_fingerprint: Option<String>,
    /// The whole response body, kept for the program cache.
    pub raw: Value,
    /// Requests sent to get this completion (1 when the first succeeded).
    pub attempts: u32,
}

/// Reads a 2xx body into a [`Completion`] (`attempts` is left at 1 for the caller to set).
pub(crate) fn parse_completion(
    body: &[u8],
    url: &str,
    status: u16,
) -> Result<Completion, LlmError> {
    let raw: Value = serde_json::from_slice(body).map_err(|error| LlmError::Malformed {
        url: url.to_owned(),
        status,
        message: error.to_string(),
        body_prefix: body_prefix(body),
    })?;
    let Some(object) = raw.as_object() else {
        return Err(LlmError::Malformed {
            url: url.to_owned(),
            status,
            message: "the body is JSON but not an object".to_owned(),
            body_prefix: body_prefix(body),
        });
    };
    let Some(first) = object
        .get("choices")
        .and_then(Value::as_array)
        .and_then(|choices| choices.first())
    else {
        return Err(LlmError::NoChoices {
            url: url.to_owned(),
            status,
            detail: error_message_of(&raw),
        });
    };
    let finish_reason = first
        .get("finish_reason")
        .and_then(Value::as_str)
        .map(str::to_owned);
    let content = first
        .get("message")
        .and_then(|message| message.get("content"))
        .and_then(content_text)
        // Legacy completions-style servers put the text on the choice itself.
        .or_else(|| first.get("text").and_then(Value::as_str).map(str::to_owned))
        .filter(|text| !text.is_empty());
    let Some(content) = content else {
        return Err(LlmError::EmptyCompletion {
            url: url.to_owned(),
            status,
            finish_reason,
        });
    };
    let usage = object.get("usage").and_then(usage_of);
    let model = object
        .get("model")
        .and_then(Value::as_str)
        .map(str::to_owned);
    let system_fingerprint = object
        .get("system_fingerprint")
        .and_then(Value::as_str)
        .map(str::to_owned);
    Ok(Completion {
        content,
        finish_reason,
        usage,
        model,
        system_fingerprint,
        raw,
        attempts: 1,
    })
}

/// Message content as text: a string, or a list of parts whose `text` fields are joined.
fn content_text(content: &Value) -> Option<String> {
    match content {
        Value::String(text) => Some(text.clone()),
        Value::Array(parts) => {
            let texts: Vec<&str> = parts
                .iter()
                .filter_map(|part| part.get("text").and_then(Value::as_str))
                .collect();
            (!texts.is_empty()).then(|| texts.concat())
        }
        _ => None,
    }
}

fn usage_of(usage: &Value) -> Option<TokenUsage> {
    let object = usage.as_object()?;
    let count = |name: &str| object.get(name).and_then(Value::as_u64);
    let prompt_tokens = count("prompt_tokens");
    let completion_tokens = count("completion_tokens");
    let total_tokens = count("total_tokens");
    if prompt_tokens.is_none() && completion_tokens.is_none() && total_tokens.is_none() {
        return None;
    }
    let prompt_tokens = prompt_tokens.unwrap_or(0);
    let completion_tokens = completion_tokens.unwrap_or(0);
    Some(TokenUsage {
        prompt_tokens,
        completion_tokens,
        total_tokens: total_tokens.unwrap_or(prompt_tokens.saturating_add(completion_tokens)),
    })
}

/// The server's error message in an error body: `{"error": {"message": ...}}`, `{"error":
/// "..."}`, `{"message": ...}` or `{"detail": ...}` (the shapes compatible servers use).
pub(crate) fn error_message_of(body: &Value) -> Option<String> {
    let error = body.get("error");
    error
        .and_then(|error| error.get("message"))
        .and_then(Value::as_str)
        .or_else(|| error.and_then(Value::as_str))
        .or_else(|| body.get("message").and_then(Value::as_str))
        .or_else(|| body.get("detail").and_then(Value::as_str))
        .map(str::to_owned)
}

/// The server's error code in an error body: `error.code`, else `error.type` (strings only).
pub(crate) fn error_code_of(body: &Value) -> Option<String> {
    let error = body.get("error")?;
    error
        .get("code")
        .and_then(Value::as_str)
        .or_else(|| error.get("type").and_then(Value::as_str))
        .map(str::to_owned)
}

/// The first [`BODY_PREFIX_BYTES`] bytes of `body` as lossy UTF-8.
pub(crate) fn body_prefix(body: &[u8]) -> String {
    let end = body.len().min(BODY_PREFIX_BYTES);
    String::from_utf8_lossy(body.get(..end).unwrap_or(body)).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    const URL: &str = "http://127.0.0.1:9/v1/chat/completions";

    fn parse(body: &Value) -> Result<Completion, LlmError> {
        parse_completion(body.to_string().as_bytes(), URL, 200)
    }

    #[test]
    fn wire_body_has_only_the_parameters_that_are_set() {
        let mut request = ChatRequest::new("gpt-4o", vec![ChatMessage::user("hi")]);
        assert_eq!(
            request.to_json(),
            json!({"model": "gpt-4o", "messages": [{"role": "user", "content": "hi"}]})
        );
        request.sampling = SamplingParams {
            temperature: Some(0.0),
            top_p: Some(1.0),
            max_tokens: Some(512),
            seed: Some(7),
            stop: vec!["```\n".into()],
        };
        request.extra.insert("model".into(), json!("ignored"));
        request
            .extra
            .insert("max_completion_tokens".into(), json!(9));
        assert_eq!(
            request.canonical_json(),
            r#"{"max_completion_tokens":9,"max_tokens":512,"messages":[{"content":"hi","role":"user"}],"model":"gpt-4o","seed":7,"stop":["```\n"],"temperature":0.0,"top_p":1.0}"#
        );
    }

    #[test]
    fn token_estimate_is_characters_over_four_plus_max_tokens() {
        let mut request = ChatRequest::new("m", vec![ChatMessage::user("x".repeat(400))]);
        assert_eq!(request.estimated_tokens(), 100 + 1024);
        request.sampling.max_tokens = Some(50);
        assert_eq!(request.estimated_tokens(), 150);
    }

    #[test]
    fn full_response_parses_content_usage_model_and_keeps_raw() {
        let body = json!({
            "id": "x", "model": "gpt-4o-2024-08-06", "system_fingerprint": "fp_1",
            "service_tier": "default", "unknown": {"nested": true},
            "choices": [{"index": 0, "message": {"role": "assistant", "content": "answer = 1"},
                         "finish_reason": "eos"}],
            "usage": {"prompt_tokens": 10, "completion_tokens": 3, "total_tokens": 13}
        });
        let completion = parse(&body).unwrap();
        assert_eq!(completion.content, "answer = 1");
        assert_eq!(completion.finish_reason.as_deref(), Some("eos"));
        assert_eq!(completion.model.as_deref(), Some("gpt-4o-2024-08-06"));
        assert_eq!(completion.system_fingerprint.as_deref(), Some("fp_1"));
        assert_eq!(
            completion.usage,
            Some(TokenUsage {
                prompt_tokens: 10,
                completion_tokens: 3,
                total_tokens: 13
            })
        );
        assert_eq!(completion.raw, body);
    }

    #[test]
    fn lenient_shapes() {
        // (body, expected content or error kind)
        let cases: Vec<(Value, Result<&str, &str>)> = vec![
            (
                json!({"choices": [{"message": {"content": [{"type": "text", "text": "a"}, {"type": "text", "text": "b"}]}}]}),
                Ok("ab"),
            ),
            (json!({"choices": [{"text": "legacy"}]}), Ok("legacy")),
            (
                json!({"choices": [{"message": {"content": "x"}, "finish_reason": ""}], "usage": null}),
                Ok("x"),
            ),
            (
                json!({"choices": [{"message": {"content": null}, "finish_reason": "content_filter"}]}),
                Err("empty_completion"),
            ),
            (
                json!({"choices": [{"message": {"role": "assistant"}}]}),
                Err("empty_completion"),
            ),
            (
                json!({"choices": [{"message": {"content": ""}}]}),
                Err("empty_completion"),
            ),
            (json!({"choices": []}), Err("no_choices")),
            (json!({"object": "chat.completion"}), Err("no_choices")),
            (json!({"choices": "nope"}), Err("no_choices")),
            (json!([1, 2]), Err("malformed")),
        ];
        for (body, expected) in cases {
            let got = parse(&body).map(|c| c.content).map_err(|e| e.kind());
            assert_eq!(got.as_deref().map_err(|e| *e), expected, "{body}");
        }
    }

    #[test]
    fn usage_fills_in_a_missing_total() {
        let body = json!({"choices": [{"message": {"content": "x"}}],
                          "usage": {"prompt_tokens": 4, "completion_tokens": 2}});
        assert_eq!(parse(&body).unwrap().usage.unwrap().total_tokens, 6);
    }

    #[test]
    fn no_choices_carries_an_error_message_in_the_body() {
        let body = json!({"error": {"message": "upstream failed"}});
        let error = parse(&body).unwrap_err();
        assert_eq!(
            error,
            LlmError::NoChoices {
                url: URL.into(),
                status: 200,
                detail: Some("upstream failed".into())
            }
        );
    }

    #[test]
    fn invalid_json_quotes_the_first_200_bytes() {
        let body = format!("<html>{}</html>", "x".repeat(500));
        let error = parse_completion(body.as_bytes(), URL, 200).unwrap_err();
        let LlmError::Malformed { body_prefix, .. } = &error else {
            panic!("{error:?}");
        };
        assert_eq!(body_prefix.len(), 200);
        assert!(body_prefix.starts_with("<html>xxx"));
    }

    #[test]
    fn error_bodies_in_several_shapes() {
        assert_eq!(
            error_message_of(&json!({"error": {"message": "m", "code": "c"}})).as_deref(),
            Some("m")
        );
        assert_eq!(
            error_message_of(&json!({"error": "s"})).as_deref(),
            Some("s")
        );
        assert_eq!(
            error_message_of(&json!({"detail": "d"})).as_deref(),
            Some("d")
        );
        assert_eq!(
            error_code_of(&json!({"error": {"type": "insufficient_quota", "code": null}}))
                .as_deref(),
            Some("insufficient_quota")
        );
    }
}
