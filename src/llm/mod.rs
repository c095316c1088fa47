//! The LLM program source's transport: the only module that touches the network.
//!
//! Input: a [`ChatRequest`] (model, messages, sampling parameters) and a [`ClientConfig`]
//! (endpoint, key, timeouts, retry and rate limits). Output: a [`Completion`] (text, finish
//! reason, usage, the model the server reported, the raw JSON, attempts) or a classified
//! [`LlmError`]. It also owns the price table ([`Prices`]), a loopback mock server for tests
//! ([`mock`]) and the `bench llm` measurements ([`bench`](mod@bench)). It knows nothing of
//! questions, programs or the sandbox: it may use `crate::util` and, for types only,
//! `crate::prompt` and `crate::dataset` (`docs/architecture.md`, layers).
//!
//! Behaviour the rest of the crate relies on:
//!
//! * **Retries** only on connection errors, timeouts, 408, 429 and 5xx, at most
//!   `max_attempts` requests and within `total_retry_budget`, with capped exponential backoff
//!   and full jitter from a seeded RNG, and `Retry-After` honoured (capped at `backoff_cap`).
//!   Every other 4xx fails at once with the server's message.
//! * **Fatal errors** ([`LlmError::is_fatal_for_run`]): a bad key (401/403), an unknown model
//!   (404, `model_not_found`), an exhausted quota and an invalid configuration. The caller stops
//!   the run (exit 1) instead of failing every question alike.
//! * **Rate limits** (`rpm`, `tpm`) and the pause a 429's `Retry-After` sets are shared by every
//!   concurrent request of one [`Client`]; clone the client, do not make one per request.
//! * **Bounded everything:** every attempt runs under `request_timeout`; bodies over
//!   `max_body_bytes` are refused without being read.
//!
//! Driving it from the app (one client, `--jobs` concurrent requests):
//!
//! ```no_run
//! use std::sync::Arc;
//! use contphy_eval::llm::{ChatMessage, ChatRequest, Client, ClientConfig};
//!
//! # async fn run(prompts: Vec<String>) -> Result<(), contphy_eval::llm::LlmError> {
//! let client = Client::new(ClientConfig {
//!     api_key: std::env::var("OPENAI_API_KEY").ok(),
//!     rpm: Some(500),
//!     ..ClientConfig::default()
//! })?;
//! let jobs = Arc::new(tokio::sync::Semaphore::new(8));
//! let mut tasks = tokio::task::JoinSet::new();
//! for prompt in prompts {
//!     let (client, jobs) = (client.clone(), Arc::clone(&jobs));
//!     tasks.spawn(async move {
//!         let _permit = jobs.acquire_owned().await.ok()?;
//!         let request = ChatRequest::new("gpt-4o", vec![ChatMessage::user(prompt)]);
//!         Some(client.complete(&request).await)
//!     });
//! }
//! while let Some(Ok(Some(result))) = tasks.join_next().await {
//!     match result {
//!         Ok(completion) => { /* extract the program from `completion.content` */ }
//!         Err(error) if error.is_fatal_for_run() => return Err(error),
//!         Err(error) => { /* record `error.kind()` for this question */ }
//!     }
//! }
//! # Ok(())
//! # }
//! ```

pub mod bench;
mod client;
mod config;
mod error;
mod limiter;
pub mod mock;
mod prices;
mod retry;
mod types;

pub use bench::{BenchConfig, BenchError, BenchReport, run_bench};
pub use client::{Client, ClientStats, RetryNotice};
pub use config::{ClientConfig, DEFAULT_BASE_URL};
pub use error::LlmError;
pub use prices::{ModelPrice, Prices, PricesError};
pub use types::{ChatMessage, ChatRequest, Completion, SamplingParams, TokenUsage};
