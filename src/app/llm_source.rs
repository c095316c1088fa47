//! The LLM program source: an OpenAI-compatible model writes each program (ContPRO's program
//! generation), with the program cache in front of it.
//!
//! For each request the prompt is rendered (`prompt`), followed by the repair turns of earlier
//! attempts; the cache key covers the model, the sampling parameters, every message, the
//! template hash, the api_spec version and the sample index (`docs/architecture.md`, program
//! cache). Cache hits are replayed; misses go to the model, `--jobs` at a time; identical requests
//! share one call; and each completion is written to the cache the moment it arrives, so a killed
//! run loses no completion it paid for. A rejected key or an unknown model stops the run (exit 1);
//! any other failure fails its unit at stage `llm`, or `extract` when the completion holds no
//! program.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use serde_json::{Value, json};

use super::error::{AppError, Classify as _, user_error};
use super::progress::Progress;
use super::source::{CacheAccess, Failed, Lookup, Obtain, Obtained, ProgramRequest, ProgramSource};
use crate::llm::{
    ChatMessage, ChatRequest, Client, ClientConfig, Completion, LlmError, Prices, SamplingParams,
    TokenUsage,
};
use crate::program::{CacheEntry, Program, ProgramOrigin, cache_key, extract_program};
use crate::prompt::{PromptMode, PromptSet};
use crate::scenarios;
use crate::score::{Stage, UnitError, Usage};

/// The source name of LLM programs in cache keys and manifests.
pub(crate) const LLM_SOURCE: &str = "openai";

/// How the run talks to the model.
pub(crate) struct LlmSourceSettings {
    /// The endpoint, key, timeouts and limits.
    pub(crate) client: ClientConfig,
    /// The model id.
    pub(crate) model: String,
    /// Sampling parameters (part of every cache key).
    pub(crate) sampling: SamplingParams,
    /// Requests in flight at once.
    pub(crate) jobs: usize,
    /// The price table.
    pub(crate) prices: Prices,
    /// No progress bar.
    pub(crate) quiet: bool,
    /// Stop sending requests once this run's new completions cost this much, USD.
    pub(crate) max_cost_usd: Option<f64>,
}

/// An OpenAI-compatible model as a program source.
pub(crate) struct LlmSource {
    client: Client,
    runtime: tokio::runtime::Runtime,
    model: String,
    sampling: SamplingParams,
    cache: CacheAccess,
    prices: Prices,
    jobs: usize,
    quiet: bool,
    prompts: &'static PromptSet,
    endpoint_json: Value,
    /// Keys whose tokens are already counted in this run: units that share a completion (the
    /// same prompt on another video) count its tokens once, in a fresh run and in a replay alike.
    counted: Mutex<BTreeSet<String>>,
    /// The spending cap, USD.
    max_cost_usd: Option<f64>,
    /// What this run's new completions cost so far, USD.
    spent_usd: Arc<Mutex<f64>>,
}

/// What one model call returned.
type CallResult = Result<Completion, LlmError>;

/// A call to make: the request, its key material, the first unit that asked for it.
struct PendingCall {
    request: ChatRequest,
    key_material: Value,
    unit: String,
}

impl LlmSource {
    /// A source for `settings.model` at `settings.client.base_url`, reading through `cache`.
    pub(crate) fn new(
        settings: LlmSourceSettings,
        cache: CacheAccess,
    ) -> Result<LlmSource, AppError> {
        if let Some(cap) = settings.max_cost_usd {
            if !(cap.is_finite() && cap > 0.0) {
                return Err(user_error(
                    "--max-cost must be a positive number of US dollars",
                ));
            }
            if settings.prices.price(&settings.model).is_none() {
                return Err(user_error(format!(
                    "--max-cost needs a price for model `{}`; add it to a price table and pass --prices FILE",
                    settings.model
                )));
            }
        }
        let endpoint_json = settings.client.manifest_json();
        let client = Client::new(settings.client).user()?;
        let prompts = scenarios::prompts().internal()?;
        let runtime = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .enable_all()
            .build()
            .internal()?;
        Ok(LlmSource {
            client,
            runtime,
            model: settings.model,
            sampling: settings.sampling,
            cache,
            prices: settings.prices,
            jobs: settings.jobs.max(1),
            quiet: settings.quiet,
            prompts,
            endpoint_json,
            counted: Mutex::new(BTreeSet::new()),
            max_cost_usd: settings.max_cost_usd,
            spent_usd: Arc::new(Mutex::new(0.0)),
        })
    }

    /// Checks, before any question is asked, that the server answers, accepts the key and serves
    /// the model, so that a typo costs one line and not a run of failed units.
    pub(crate) fn preflight(&self) -> Result<(), AppError> {
        let listed = self.runtime.block_on(self.client.list_models());
        match listed {
            Ok(Some(models)) if !models.iter().any(|m| m == &self.model) => {
                let mut shown: Vec<&str> = models.iter().map(String::as_str).collect();
                shown.sort_unstable();
                let more = shown.len().saturating_sub(12);
                shown.truncate(12);
                let list = if shown.is_empty() {
                    "none".to_string()
                } else if more > 0 {
                    format!("{} and {more} more", shown.join(", "))
                } else {
                    shown.join(", ")
                };
                Err(user_error(format!(
                    "model `{}` is not served by `{}` (it lists: {list}); check --model and --base-url",
                    self.model,
                    self.client.base_url()
                )))
            }
            Err(error) if error.is_fatal_for_run() => Err(user_error(error)),
            Err(LlmError::Connection {
                address, detail, ..
            }) => Err(user_error(format!(
                "cannot reach the model server `{}` ({address}): {detail}; check --base-url",
                self.client.base_url()
            ))),
            Err(LlmError::Timeout { timeout_ms, .. }) => Err(user_error(format!(
                "the model server `{}` did not answer within {timeout_ms} ms; check --base-url or raise --request-timeout",
                self.client.base_url()
            ))),
            // Listed (or no list to check against), or a busy or odd server: the requests
            // themselves retry and report.
            Ok(_) | Err(_) => Ok(()),
        }
    }

    /// The chat messages of a request (the rendered prompt, then each repair turn) and the
    /// prompt's identity.
    fn messages(
        &self,
        request: &ProgramRequest<'_>,
    ) -> Result<(Vec<ChatMessage>, Value), UnitError> {
        let mode = if request.whole_question {
            PromptMode::PerQuestion
        } else {
            PromptMode::PerOption
        };
        let rendered = self
            .prompts
            .render(request.question, request.option, mode)
            .map_err(|error| UnitError {
                stage: Stage::Prompt,
                kind: "render".to_string(),
                message: error.to_string(),
            })?;
        let mut messages = Vec::with_capacity(2 + 2 * request.repairs.len());
        if let Some(system) = rendered.system {
            messages.push(ChatMessage::system(system));
        }
        messages.push(ChatMessage::user(rendered.user));
        for turn in request.repairs {
            messages.push(ChatMessage::assistant(turn.completion.clone()));
            messages.push(ChatMessage::user(turn.feedback.clone()));
        }
        let prompt = json!({
            "template_hash": rendered.template_hash,
            "api_spec_version": rendered.api_spec_version,
        });
        Ok((messages, prompt))
    }

    /// The usage a unit reports for the completion under `key`: the tokens and cost the first
    /// time the run uses the key, nothing after.
    fn usage_of(&self, key: &str, usage: Option<TokenUsage>, requests: u32) -> Usage {
        let first = self
            .counted
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .insert(key.to_string());
        if !first {
            return Usage::default();
        }
        let usage = usage.unwrap_or_default();
        Usage {
            prompt_tokens: usage.prompt_tokens,
            completion_tokens: usage.completion_tokens,
            cost_usd: self.prices.cost(&self.model, &usage),
            requests,
        }
    }

    /// Sends every pending call, `jobs` at a time, caching each completion as it arrives. A
    /// fatal error (bad key, unknown model) stops further sends and is returned.
    fn call_all(
        &self,
        pending: BTreeMap<String, PendingCall>,
    ) -> Result<BTreeMap<String, CallResult>, AppError> {
        if pending.is_empty() {
            return Ok(BTreeMap::new());
        }
        let progress = Progress::labelled(pending.len() as u64, "completions", self.quiet);
        let over_budget = Arc::new(AtomicBool::new(false));
        let results = self.runtime.block_on(async {
            let semaphore = Arc::new(tokio::sync::Semaphore::new(self.jobs));
            let stop = Arc::new(AtomicBool::new(false));
            let mut set = tokio::task::JoinSet::new();
            for (key, call) in pending {
                let semaphore = Arc::clone(&semaphore);
                let client = self.client.clone();
                let cache = self.cache.clone();
                let stop = Arc::clone(&stop);
                let progress = progress.clone();
                let spent = Arc::clone(&self.spent_usd);
                let over_budget = Arc::clone(&over_budget);
                let (cap, prices, model) =
                    (self.max_cost_usd, self.prices.clone(), self.model.clone());
                set.spawn(async move {
                    let Ok(_permit) = semaphore.acquire_owned().await else {
                        return (key, None);
                    };
                    if stop.load(Ordering::SeqCst) {
                        return (key, None);
                    }
                    // The cap is checked before each request; requests already in flight when
                    // it is reached still finish (and are cached), so a run overshoots by at
                    // most `--jobs` completions.
                    if let Some(cap) = cap
                        && *spent.lock().unwrap_or_else(PoisonError::into_inner) >= cap
                    {
                        over_budget.store(true, Ordering::SeqCst);
                        stop.store(true, Ordering::SeqCst);
                        return (key, None);
                    }
                    let observer = |notice: &crate::llm::RetryNotice<'_>| {
                        progress.message(format!(
                            "(retry {}/{} in {:.1} s: {})",
                            notice.failed_attempt,
                            notice.max_attempts,
                            notice.delay.as_secs_f64(),
                            notice.error.kind()
                        ));
                    };
                    let result = client.complete_observed(&call.request, &observer).await;
                    if let Ok(completion) = &result
                        && let Some(cost) = completion
                            .usage
                            .and_then(|usage| prices.cost(&model, &usage))
                    {
                        *spent.lock().unwrap_or_else(PoisonError::into_inner) += cost;
                    }
                    let recorded = match &result {
                        Ok(completion) => cache.record(entry_of(&key, call, completion)),
                        Err(error) => {
                            if error.is_fatal_for_run() {
                                stop.store(true, Ordering::SeqCst);
                            }
                            Ok(())
                        }
                    };
                    progress.advance(0);
                    (key, Some(recorded.map(|()| result)))
                });
            }
            let mut results = BTreeMap::new();
            while let Some(joined) = set.join_next().await {
                // Not sent (the run is stopping), or a task that panicked: its units fail as
                // not sent rather than take the run down.
                if let Ok((key, Some(result))) = joined {
                    results.insert(key, result);
                }
            }
            results
        });
        progress.finish();
        let mut calls = BTreeMap::new();
        let mut fatal = None;
        for (key, result) in results {
            match result {
                Err(error) => return Err(error),
                Ok(Err(error)) if error.is_fatal_for_run() => {
                    fatal.get_or_insert(error);
                }
                Ok(result) => {
                    calls.insert(key, result);
                }
            }
        }
        if let Some(error) = fatal {
            return Err(user_error(error));
        }
        if over_budget.load(Ordering::SeqCst) {
            let spent = *self
                .spent_usd
                .lock()
                .unwrap_or_else(PoisonError::into_inner);
            return Err(user_error(format!(
                "stopped at the spending cap: this run's completions cost ${spent:.4} of --max-cost ${:.4}; every completion is cached, so raise --max-cost and pass --resume to go on",
                self.max_cost_usd.unwrap_or_default()
            )));
        }
        Ok(calls)
    }
}

/// The cache entry of a completion. The program is extracted now for `cache ls` and export;
/// replays extract again from the raw completion, so a better extractor applies to old entries.
fn entry_of(key: &str, call: PendingCall, completion: &Completion) -> CacheEntry {
    CacheEntry {
        key: key.to_string(),
        key_material: call.key_material,
        program: extract_program(&completion.content).unwrap_or_default(),
        raw_completion: Some(completion.content.clone()),
        source: LLM_SOURCE.to_string(),
        first_unit: call.unit,
        details: json!({
            "usage": completion.usage,
            "finish_reason": completion.finish_reason,
            "model": completion.model,
            "system_fingerprint": completion.system_fingerprint,
        }),
    }
}

/// The program in a completion, or the extract failure with the completion (kept for the repair
/// turn, the usage and the key a replay needs).
fn obtained_from(completion: String, key: &str, origin: ProgramOrigin, usage: Usage) -> Obtain {
    match extract_program(&completion) {
        Ok(source) => Ok(Obtained {
            program: Program {
                source,
                origin,
                key: Some(key.to_string()),
            },
            completion: Some(completion),
            usage: Some(usage),
        }),
        Err(error) => Err(Box::new(Failed {
            error: UnitError {
                stage: Stage::Extract,
                kind: error.kind().to_string(),
                message: error.to_string(),
            },
            key: Some(key.to_string()),
            completion: Some(completion),
            usage: Some(usage),
        })),
    }
}

/// What became of one request before any call.
enum Plan {
    /// Answered from the cache, or failed before a call.
    Done(Obtain),
    /// Waits for the call with this key.
    Call(String),
}

impl ProgramSource for LlmSource {
    fn name(&self) -> String {
        self.model.clone()
    }

    fn can_repair(&self) -> bool {
        true
    }

    fn obtain_batch(&self, requests: &[ProgramRequest<'_>]) -> Result<Vec<Obtain>, AppError> {
        // 1. Messages, keys and cache lookups.
        let mut plans = Vec::with_capacity(requests.len());
        let mut pending: BTreeMap<String, PendingCall> = BTreeMap::new();
        for request in requests {
            let (messages, prompt) = match self.messages(request) {
                Ok(parts) => parts,
                Err(error) => {
                    plans.push(Plan::Done(Err(error.into())));
                    continue;
                }
            };
            let mut chat = ChatRequest::new(self.model.clone(), messages);
            chat.sampling = self.sampling.clone();
            let key_material = json!({
                "source": LLM_SOURCE,
                "model": self.model,
                "sampling": chat.sampling,
                "messages": chat.messages,
                "prompt": prompt,
                "sample": request.sample,
            });
            let key = cache_key(&key_material);
            match self.cache.lookup(&key, request.unit)? {
                Lookup::Hit(entry) => {
                    let completion = entry.raw_completion.unwrap_or(entry.program);
                    let usage = entry
                        .details
                        .get("usage")
                        .and_then(|usage| serde_json::from_value(usage.clone()).ok());
                    let usage = self.usage_of(&key, usage, 0);
                    plans.push(Plan::Done(obtained_from(
                        completion,
                        &key,
                        ProgramOrigin::Cache,
                        usage,
                    )));
                }
                Lookup::OfflineMiss(error) => plans.push(Plan::Done(Err(error.into()))),
                Lookup::Miss => {
                    pending.entry(key.clone()).or_insert_with(|| PendingCall {
                        request: chat,
                        key_material,
                        unit: request.unit.to_string(),
                    });
                    plans.push(Plan::Call(key));
                }
            }
        }

        // 2. Model calls.
        let calls = self.call_all(pending)?;

        // 3. Results in request order.
        Ok(plans
            .iter()
            .map(|plan| match plan {
                Plan::Done(result) => result.clone(),
                Plan::Call(key) => {
                    match calls.get(key) {
                        Some(Ok(completion)) => obtained_from(
                            completion.content.clone(),
                            key,
                            ProgramOrigin::Llm,
                            self.usage_of(key, completion.usage, completion.attempts),
                        ),
                        // The kind of the last attempt's error (`timeout`, not
                        // `retries_exhausted`), so that reports group failures by cause; the
                        // message tells the attempts.
                        Some(Err(error)) => Err(UnitError {
                            stage: Stage::Llm,
                            kind: error.root().kind().to_string(),
                            message: error.to_string(),
                        }
                        .into()),
                        None => Err(UnitError {
                            stage: Stage::Llm,
                            kind: "not_sent".to_string(),
                            message: "the request was not sent: the run stopped first".to_string(),
                        }
                        .into()),
                    }
                }
            })
            .collect())
    }

    fn describe(&self) -> Value {
        json!({
            "source": LLM_SOURCE,
            "model": self.model,
            "sampling": self.sampling,
            "endpoint": self.endpoint_json,
            "prompt_set_hash": self.prompts.hash(),
            "api_spec_version": self.prompts.api_spec_version(),
            "prices": self.prices.price(&self.model),
        })
    }
}
