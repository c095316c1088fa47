//! Client-wide pacing: requests-per-minute and tokens-per-minute limiters, and the shared pause
//! a 429's `Retry-After` sets.
//!
//! Inputs: the cost of each attempt (1 request; its estimated tokens) and the time now. Outputs:
//! the instant at which the attempt may start. Every concurrent `complete` call of one client
//! shares these, so `--rpm` and `--tpm` hold however many jobs run.
//!
//! [`Pacer`] is GCRA's virtual-scheduling form without a burst allowance: it keeps the
//! theoretical arrival time `tat` of the next unit; a caller reserves `cost` units at
//! `start = max(now, tat)` and moves `tat` to `start + cost · interval`. Reservations are taken
//! under a mutex in arrival order, so callers start in the order they asked and the long-run
//! rate never exceeds the limit. Pure functions of `now` (the "clock" is an argument), so the
//! schedule is tested without sleeping; the async side uses `tokio::time`, which tests can pause.

use std::sync::{Mutex, MutexGuard, PoisonError};
use std::time::Duration;

use tokio::time::Instant;

/// Paces units (requests or tokens) to at most `per_minute` per minute.
#[derive(Debug)]
pub(crate) struct Pacer {
    /// Time one unit occupies: a minute divided by the limit.
    interval: Duration,
    /// The largest cost one reservation is charged: a request whose estimate exceeds a whole
    /// minute's budget waits one minute, instead of for ever or an error.
    max_cost: u64,
    /// Theoretical arrival time of the next unit.
    next_free: Mutex<Option<Instant>>,
}

impl Pacer {
    /// A pacer for `per_minute` units per minute (`per_minute` ≥ 1, checked by the client).
    pub(crate) fn per_minute(per_minute: u32) -> Self {
        let per_minute = per_minute.max(1);
        Self {
            interval: Duration::from_mins(1) / per_minute,
            max_cost: u64::from(per_minute),
            next_free: Mutex::new(None),
        }
    }

    fn state(&self) -> MutexGuard<'_, Option<Instant>> {
        // A panic while holding this lock cannot leave the instant half-written.
        self.next_free
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
    }

    /// Reserves `cost` units for a caller arriving at `now`; returns when it may start.
    pub(crate) fn reserve(&self, now: Instant, cost: u64) -> Instant {
        let cost = cost.clamp(1, self.max_cost);
        let mut next_free = self.state();
        let start = next_free.map_or(now, |tat| tat.max(now));
        *next_free = Some(start + self.occupied(cost));
        start
    }

    /// Corrects an earlier reservation by `delta` units (reported minus estimated tokens):
    /// positive pushes later callers back, negative gives time back.
    pub(crate) fn adjust(&self, delta: i64) {
        let mut next_free = self.state();
        if let Some(tat) = next_free.as_mut() {
            let shift = self.occupied(delta.unsigned_abs().min(self.max_cost));
            *tat = if delta >= 0 {
                *tat + shift
            } else {
                tat.checked_sub(shift).unwrap_or(*tat)
            };
        }
    }

    fn occupied(&self, units: u64) -> Duration {
        self.interval
            .saturating_mul(u32::try_from(units).unwrap_or(u32::MAX))
    }

    /// Waits for a reservation of `cost` units.
    pub(crate) async fn acquire(&self, cost: u64) {
        let start = self.reserve(Instant::now(), cost);
        tokio::time::sleep_until(start).await;
    }
}

/// A client-wide "nobody sends before" instant, set from a 429's `Retry-After` so that every
/// in-flight worker backs off together instead of each finding the limit on its own.
#[derive(Debug, Default)]
pub(crate) struct PauseGate {
    until: Mutex<Option<Instant>>,
}

impl PauseGate {
    fn state(&self) -> MutexGuard<'_, Option<Instant>> {
        self.until.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Pauses every sender until at least `until` (an earlier instant never shortens a pause).
    pub(crate) fn pause_until(&self, until: Instant) {
        let mut state = self.state();
        *state = Some(state.map_or(until, |current| current.max(until)));
    }

    /// The instant senders must wait for, if it is after `now`.
    pub(crate) fn paused_until(&self, now: Instant) -> Option<Instant> {
        self.state().filter(|until| *until > now)
    }

    /// Waits until no pause is in force (a pause set while waiting is honoured too).
    pub(crate) async fn wait(&self) {
        while let Some(until) = self.paused_until(Instant::now()) {
            tokio::time::sleep_until(until).await;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    #[test]
    fn requests_are_spaced_by_the_interval_in_arrival_order() {
        let pacer = Pacer::per_minute(600); // 100 ms apart
        let now = Instant::now();
        let starts: Vec<Duration> = (0..30).map(|_| pacer.reserve(now, 1) - now).collect();
        assert_eq!(starts[0], Duration::ZERO);
        assert_eq!(starts[1], Duration::from_millis(100));
        assert_eq!(starts[29], Duration::from_millis(2900));
        // A caller arriving after an idle gap starts at once and does not bank the idle time.
        let later = now + Duration::from_secs(10);
        assert_eq!(pacer.reserve(later, 1), later);
        assert_eq!(pacer.reserve(later, 1), later + Duration::from_millis(100));
    }

    #[test]
    fn token_costs_occupy_proportional_time_and_are_corrected() {
        let pacer = Pacer::per_minute(60_000); // 1 ms per token
        let now = Instant::now();
        assert_eq!(pacer.reserve(now, 500), now);
        assert_eq!(pacer.reserve(now, 500), now + Duration::from_millis(500));
        // The second request reported 200 tokens more than estimated.
        pacer.adjust(200);
        assert_eq!(pacer.reserve(now, 1), now + Duration::from_millis(1200));
        pacer.adjust(-1000);
        assert_eq!(pacer.reserve(now, 1), now + Duration::from_millis(201));
        // One request larger than a minute's budget is charged one minute.
        let oversized = Pacer::per_minute(1000);
        assert_eq!(oversized.reserve(now, 5000), now);
        assert_eq!(oversized.reserve(now, 1), now + Duration::from_mins(1));
    }

    #[tokio::test(start_paused = true)]
    async fn thirty_concurrent_requests_at_600_rpm_take_2_9_virtual_seconds() {
        let pacer = Arc::new(Pacer::per_minute(600));
        let started = Instant::now();
        let mut tasks = tokio::task::JoinSet::new();
        for _ in 0..30 {
            let pacer = Arc::clone(&pacer);
            tasks.spawn(async move {
                pacer.acquire(1).await;
                Instant::now()
            });
        }
        let mut finished = Vec::new();
        while let Some(at) = tasks.join_next().await {
            finished.push(at.unwrap() - started);
        }
        finished.sort();
        assert_eq!(finished[0], Duration::ZERO);
        assert_eq!(finished[29], Duration::from_millis(2900));
    }

    #[tokio::test(start_paused = true)]
    async fn pause_gate_holds_every_waiter_and_only_extends() {
        let gate = Arc::new(PauseGate::default());
        let started = Instant::now();
        gate.pause_until(started + Duration::from_secs(2));
        gate.pause_until(started + Duration::from_secs(1));
        let waiter = {
            let gate = Arc::clone(&gate);
            tokio::spawn(async move {
                gate.wait().await;
                Instant::now()
            })
        };
        // Extended while the waiter sleeps: it must see the new instant.
        tokio::time::sleep(Duration::from_millis(500)).await;
        gate.pause_until(started + Duration::from_secs(3));
        assert_eq!(waiter.await.unwrap() - started, Duration::from_secs(3));
        assert_eq!(gate.paused_until(Instant::now()), None);
    }
}
