//! The retry schedule: capped exponential backoff with full jitter, and `Retry-After` parsing.
//!
//! Inputs: the number of the attempt that just failed, the configured base and cap, a seeded
//! RNG, and response headers. Outputs: the delay before the next attempt. Which errors are
//! retried at all is [`super::LlmError::is_retryable`]; the loop itself is in `client.rs`.
//!
//! Full jitter (a uniform delay in `[0, min(cap, base·2^(n-1))]`) spreads the retries of many
//! concurrent requests that failed together, instead of sending them back in one wave. The RNG
//! is seeded (house rule 5: no `thread_rng`); jitter only moves retries in time, so results do
//! not depend on it.

use std::time::{Duration, SystemTime};

use rand::Rng;
use reqwest::header::HeaderMap;

/// The delay after failed attempt number `failed_attempt` (1-based) when the server gave no
/// `Retry-After`: uniform in `[0, min(cap, base · 2^(failed_attempt - 1))]`.
pub(crate) fn backoff_delay(
    failed_attempt: u32,
    base: Duration,
    cap: Duration,
    rng: &mut impl Rng,
) -> Duration {
    let doublings = failed_attempt.saturating_sub(1).min(30);
    let ceiling = base.saturating_mul(1_u32 << doublings).min(cap);
    let ceiling_nanos = u64::try_from(ceiling.as_nanos()).unwrap_or(u64::MAX);
    if ceiling_nanos == 0 {
        return Duration::ZERO;
    }
    Duration::from_nanos(rng.random_range(0..=ceiling_nanos))
}

/// The wait a response asks for: `retry-after-ms` (milliseconds, sent by OpenAI and Azure), else
/// `Retry-After` as delay-seconds or an HTTP date (RFC 9110 §10.2.3). A date in the past is zero;
/// a value that parses as neither is ignored.
pub(crate) fn retry_after(headers: &HeaderMap, now: SystemTime) -> Option<Duration> {
    let text = |name: &str| {
        headers
            .get(name)
            .and_then(|value| value.to_str().ok())
            .map(str::trim)
    };
    if let Some(milliseconds) = text("retry-after-ms").and_then(parse_seconds_or_fraction) {
        return Some(milliseconds.mul_f64(1e-3));
    }
    let value = text("retry-after")?;
    if let Some(seconds) = parse_seconds_or_fraction(value) {
        return Some(seconds);
    }
    let date = httpdate::parse_http_date(value).ok()?;
    Some(date.duration_since(now).unwrap_or(Duration::ZERO))
}

/// A non-negative decimal number of units, as a `Duration` of that many seconds.
fn parse_seconds_or_fraction(text: &str) -> Option<Duration> {
    let number: f64 = text.parse().ok()?;
    (number.is_finite() && number >= 0.0)
        .then(|| Duration::try_from_secs_f64(number).ok())
        .flatten()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::util::seeded_rng;
    use reqwest::header::HeaderValue;

    #[test]
    fn backoff_stays_under_the_doubling_ceiling_and_the_cap() {
        let base = Duration::from_millis(100);
        let cap = Duration::from_millis(700);
        let mut rng = seeded_rng(1);
        // (failed attempt, ceiling)
        let cases = [
            (1, 100),
            (2, 200),
            (3, 400),
            (4, 700),
            (10, 700),
            (u32::MAX, 700),
        ];
        for (attempt, ceiling_ms) in cases {
            let mut largest = Duration::ZERO;
            for _ in 0..200 {
                let delay = backoff_delay(attempt, base, cap, &mut rng);
                assert!(
                    delay <= Duration::from_millis(ceiling_ms),
                    "{attempt}: {delay:?}"
                );
                largest = largest.max(delay);
            }
            // Full jitter reaches well into the upper half of the range.
            assert!(largest > Duration::from_millis(ceiling_ms / 2), "{attempt}");
        }
        assert_eq!(
            backoff_delay(3, Duration::ZERO, cap, &mut rng),
            Duration::ZERO
        );
    }

    #[test]
    fn backoff_repeats_for_the_same_seed() {
        let draw = |seed| {
            let mut rng = seeded_rng(seed);
            (1..6)
                .map(|attempt| {
                    backoff_delay(
                        attempt,
                        Duration::from_secs(1),
                        Duration::from_mins(1),
                        &mut rng,
                    )
                })
                .collect::<Vec<_>>()
        };
        assert_eq!(draw(5), draw(5));
        assert_ne!(draw(5), draw(6));
    }

    #[test]
    fn retry_after_forms() {
        let now = SystemTime::UNIX_EPOCH + Duration::from_secs(784_111_777); // 06 Nov 1994 08:49:37
        // (header, value, expected)
        let cases: [(&str, &str, Option<Duration>); 8] = [
            ("retry-after", "1", Some(Duration::from_secs(1))),
            ("retry-after", " 2.5 ", Some(Duration::from_millis(2500))),
            ("retry-after-ms", "250", Some(Duration::from_millis(250))),
            (
                "retry-after",
                "Sun, 06 Nov 1994 08:49:47 GMT",
                Some(Duration::from_secs(10)),
            ),
            (
                "retry-after",
                "Sun, 06 Nov 1994 08:49:00 GMT",
                Some(Duration::ZERO),
            ),
            ("retry-after", "-3", None),
            ("retry-after", "soon", None),
            ("x-other", "5", None),
        ];
        for (name, value, expected) in cases {
            let mut headers = HeaderMap::new();
            headers.insert(name, HeaderValue::from_static(value));
            assert_eq!(retry_after(&headers, now), expected, "{name}: {value}");
        }
    }
}
