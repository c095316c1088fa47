//! Client measurements for `contphy-eval bench llm`, against the loopback mock server.
//!
//! Input: a [`BenchConfig`]. Output: a serde-serialisable [`BenchReport`] with two questions
//! answered in numbers:
//!
//! * **Does concurrency pay?** With a fixed server latency `L`, `jobs` concurrent requests can
//!   at best complete `jobs / L` per second. Each level reports the achieved rate as a fraction
//!   of that ideal (the client's own overhead is what is missing), and the most requests the
//!   server saw in flight at once.
//! * **Does `--rpm` hold?** Many concurrent workers run against a limit; the request rate the
//!   server saw (from arrival times) is reported against the limit.
//!
//! Requests are driven the way the app drives them: one shared [`Client`], one task per request,
//! a semaphore of `jobs` permits. Run from a release build; nothing here passes or fails.

use std::sync::Arc;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};
use tokio::sync::Semaphore;
use tokio::task::JoinSet;

use super::client::Client;
use super::config::ClientConfig;
use super::error::LlmError;
use super::mock::MockServer;
use super::types::{ChatMessage, ChatRequest, SamplingParams};

/// What to measure.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BenchConfig {
    /// The mock server's latency per request.
    pub latency: Duration,
    /// Concurrency levels of the throughput measurement.
    pub jobs_levels: Vec<usize>,
    /// Requests per level, as a multiple of its concurrency (at least `min_requests`).
    pub rounds: usize,
    /// Fewest requests per level.
    pub min_requests: usize,
    /// Limits of the rate measurement, in requests per minute.
    pub rpm_limits: Vec<u32>,
    /// Time each rate measurement should span at its limit (sets its request count).
    pub rpm_span: Duration,
    /// Concurrency of the rate measurement (well above what the limit needs).
    pub rpm_jobs: usize,
}

impl Default for BenchConfig {
    fn default() -> Self {
        Self {
            latency: Duration::from_millis(50),
            jobs_levels: vec![1, 8, 32, 128],
            rounds: 20,
            min_requests: 20,
            rpm_limits: vec![600, 3000],
            rpm_span: Duration::from_secs(10),
            rpm_jobs: 32,
        }
    }
}

/// Everything measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BenchReport {
    /// The mock's latency per request.
    pub latency_ms: f64,
    /// One entry per concurrency level.
    pub throughput: Vec<ThroughputPoint>,
    /// One entry per rate limit.
    pub rate_limits: Vec<RateLimitPoint>,
}

/// Throughput at one concurrency level.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ThroughputPoint {
    /// Concurrent requests allowed.
    pub jobs: usize,
    /// Requests completed (or failed).
    pub requests: usize,
    /// Requests that failed (expected 0).
    pub failures: usize,
    /// Wall time of the whole level.
    pub elapsed_ms: f64,
    /// Achieved requests per second.
    pub requests_per_second: f64,
    /// `jobs / latency`.
    pub ideal_requests_per_second: f64,
    /// Achieved / ideal.
    pub fraction_of_ideal: f64,
    /// The most requests the server had in flight at once.
    pub max_in_flight: usize,
}

/// The request rate the server saw under one `--rpm` limit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RateLimitPoint {
    /// The configured limit.
    pub rpm_limit: u32,
    /// Requests sent.
    pub requests: usize,
    /// Requests that failed (expected 0).
    pub failures: usize,
    /// Concurrent requests allowed.
    pub jobs: usize,
    /// Time from the first request's arrival to the last's.
    pub span_ms: f64,
    /// `(requests - 1)` arrivals per span, per minute.
    pub achieved_rpm: f64,
    /// Achieved / limit (1.0 is exact; above 1.0 breaks the limit).
    pub ratio_to_limit: f64,
}

/// A measurement that could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The runtime or the mock server could not start.
    #[error("cannot start the llm bench")]
    Start(#[from] std::io::Error),
    /// The client refused its configuration.
    #[error(transparent)]
    Client(#[from] LlmError),
}

/// Runs every measurement of `config` on a fresh multi-threaded runtime.
pub fn run_bench(config: &BenchConfig) -> Result<BenchReport, BenchError> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()?;
    runtime.block_on(async {
        let mut throughput = Vec::new();
        for &jobs in &config.jobs_levels {
            let requests = (jobs * config.rounds).max(config.min_requests);
            throughput.push(bench_throughput(config.latency, jobs, requests).await?);
        }
        let mut rate_limits = Vec::new();
        for &rpm_limit in &config.rpm_limits {
            let span_minutes = config.rpm_span.as_secs_f64() / 60.0;
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a small positive request count"
            )]
            let requests = (f64::from(rpm_limit) * span_minutes).round() as usize + 1;
            rate_limits.push(
                bench_rate_limit(config.latency, rpm_limit, config.rpm_jobs, requests.max(3))
                    .await?,
            );
        }
        Ok(BenchReport {
            latency_ms: config.latency.as_secs_f64() * 1e3,
            throughput,
            rate_limits,
        })
    })
}

/// `requests` requests at `jobs` concurrency against a mock with `latency`.
pub async fn bench_throughput(
    latency: Duration,
    jobs: usize,
    requests: usize,
) -> Result<ThroughputPoint, BenchError> {
    let server = MockServer::builder().latency(latency).start().await?;
    let client = Client::new(bench_client_config(&server, None))?;
    let started = Instant::now();
    let failures = drive(&client, jobs, requests).await;
    let elapsed = started.elapsed().as_secs_f64();
    let requests_per_second = requests as f64 / elapsed;
    let ideal_requests_per_second = jobs as f64 / latency.as_secs_f64();
    Ok(ThroughputPoint {
        jobs,
        requests,
        failures,
        elapsed_ms: elapsed * 1e3,
        requests_per_second,
        ideal_requests_per_second,
        fraction_of_ideal: requests_per_second / ideal_requests_per_second,
        max_in_flight: server.max_in_flight(),
    })
}

/// `requests` requests at `jobs` concurrency under an `rpm_limit` limit.
pub async fn bench_rate_limit(
    latency: Duration,
    rpm_limit: u32,
    jobs: usize,
    requests: usize,
) -> Result<RateLimitPoint, BenchError> {
    let server = MockServer::builder().latency(latency).start().await?;
    let client = Client::new(bench_client_config(&server, Some(rpm_limit)))?;
    let failures = drive(&client, jobs, requests).await;
    let arrivals: Vec<Instant> = server
        .requests()
        .iter()
        .map(|request| request.received_at)
        .collect();
    let span = match (arrivals.iter().min(), arrivals.iter().max()) {
        (Some(first), Some(last)) => last.duration_since(*first).as_secs_f64(),
        _ => 0.0,
    };
    let achieved_rpm = if span > 0.0 {
        arrivals.len().saturating_sub(1) as f64 * 60.0 / span
    } else {
        0.0
    };
    Ok(RateLimitPoint {
        rpm_limit,
        requests,
        failures,
        jobs,
        span_ms: span * 1e3,
        achieved_rpm,
        ratio_to_limit: achieved_rpm / f64::from(rpm_limit),
    })
}

fn bench_client_config(server: &MockServer, rpm: Option<u32>) -> ClientConfig {
    ClientConfig {
        api_key: Some("bench-key".to_owned()),
        request_timeout: Duration::from_secs(30),
        max_attempts: 1,
        rpm,
        ..ClientConfig::new(server.base_url())
    }
}

/// Sends `requests` distinct requests, at most `jobs` at a time; returns how many failed.
async fn drive(client: &Client, jobs: usize, requests: usize) -> usize {
    let permits = Arc::new(Semaphore::new(jobs.max(1)));
    let mut tasks = JoinSet::new();
    for index in 0..requests {
        let client = client.clone();
        let permits = Arc::clone(&permits);
        tasks.spawn(async move {
            let Ok(_permit) = permits.acquire_owned().await else {
                return false;
            };
            let request = ChatRequest {
                sampling: SamplingParams {
                    temperature: Some(0.0),
                    max_tokens: Some(256),
                    ..SamplingParams::default()
                },
                ..ChatRequest::new(
                    "gpt-4o",
                    vec![
                        ChatMessage::system("Write a Python program."),
                        ChatMessage::user(format!("question {index}")),
                    ],
                )
            };
            client.complete(&request).await.is_ok()
        });
    }
    let mut failures = 0;
    while let Some(joined) = tasks.join_next().await {
        if !matches!(joined, Ok(true)) {
            failures += 1;
        }
    }
    failures
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_bench_runs_and_reports_every_level() {
        let config = BenchConfig {
            latency: Duration::from_millis(20),
            jobs_levels: vec![1, 4],
            rounds: 3,
            min_requests: 4,
            rpm_limits: vec![6000],
            rpm_span: Duration::from_millis(200),
            rpm_jobs: 4,
        };
        let report = run_bench(&config).unwrap();
        assert_eq!(report.throughput.len(), 2);
        assert_eq!(report.throughput[1].jobs, 4);
        assert_eq!(report.throughput[1].requests, 12);
        assert_eq!(report.throughput[1].max_in_flight, 4);
        assert!(report.throughput.iter().all(|point| point.failures == 0));
        let rate = &report.rate_limits[0];
        assert_eq!((rate.requests, rate.failures), (21, 0));
        // 6000 rpm = one request per 10 ms; never faster than the limit (a little slack for
        // timer rounding).
        assert!(rate.ratio_to_limit <= 1.05, "{rate:?}");
        let json = serde_json::to_value(&report).unwrap();
        assert!(json["throughput"][0]["fraction_of_ideal"].is_number());
    }
}
