//! `ApiClock`: splits a program's wall time into its own time and time spent inside the host API.
//!
//! Inputs are enter/leave events from host bindings (through [`ApiClock::call`] or
//! [`ApiClock::function`]); outputs are the own and API durations read by the watchdog and
//! reported per unit, the run's stop verdict ([`StopReason`]) and, in a worker, event lines that
//! let the parent pause its own-time clock while the program waits on the API.
//!
//! Every binding call goes through [`ApiClock::call`], which also catches a Rust panic inside
//! the binding: the program gets an exception and the unit fails as `internal`, while the worker
//! and the other programs carry on.

use std::cell::RefCell;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};
use std::rc::Rc;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};
use std::time::{Duration, Instant};

use rustpython_vm::function::FuncArgs;
use rustpython_vm::{PyObjectRef, PyResult, VirtualMachine};

/// Panic payload of the hard interrupt: unwinds out of the interpreter, which is then discarded.
/// A binding wrapper that catches it must let it through ([`ApiClock::call`] does).
#[derive(Debug)]
pub(crate) struct HardInterrupt;

/// Why the watchdog (or the clock) decided the current run must stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum StopReason {
    /// Own time ran past its budget.
    OwnTime,
    /// API time ran past its budget.
    ApiTime,
}

/// A change of state the parent process needs to see while a program runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum ApiEvent {
    /// The program entered the host API (outermost binding call).
    Enter,
    /// The program left the host API; the total API time so far.
    Exit {
        /// API time of this run so far, in milliseconds.
        api_ms: f64,
    },
}

/// Everything the watchdog thread reads; written by the interpreter thread.
#[derive(Debug)]
pub(crate) struct ClockState {
    run_started: Instant,
    api_depth: u32,
    api_entered_at: Option<Instant>,
    api_total: Duration,
    api_budget: Duration,
    stop: Option<(StopReason, Instant)>,
    host_panic: Option<String>,
}

impl ClockState {
    fn new() -> Self {
        Self {
            run_started: Instant::now(),
            api_depth: 0,
            api_entered_at: None,
            api_total: Duration::ZERO,
            api_budget: Duration::MAX,
            stop: None,
            host_panic: None,
        }
    }

    /// API time so far, including the call in progress.
    pub(crate) fn api_elapsed(&self, now: Instant) -> Duration {
        self.api_total
            + self.api_entered_at.map_or(Duration::ZERO, |entered| {
                now.saturating_duration_since(entered)
            })
    }

    /// Wall time since the run started minus API time.
    pub(crate) fn own_elapsed(&self, now: Instant) -> Duration {
        now.saturating_duration_since(self.run_started)
            .saturating_sub(self.api_elapsed(now))
    }

    /// Whether the program is inside a host call right now.
    pub(crate) fn in_api(&self) -> bool {
        self.api_depth > 0
    }

    /// The stop verdict and when it was reached, if any.
    pub(crate) fn stop(&self) -> Option<(StopReason, Instant)> {
        self.stop
    }

    /// Records a stop verdict; the first one wins.
    pub(crate) fn set_stop(&mut self, reason: StopReason, now: Instant) {
        if self.stop.is_none() {
            self.stop = Some((reason, now));
        }
    }
}

/// Receives [`ApiEvent`]s as they happen (the worker turns them into protocol lines).
pub(crate) type ApiListener = Box<dyn FnMut(ApiEvent)>;

/// Shared handle to one sandbox's clock. Cheap to clone; lives on the interpreter thread (the
/// watchdog holds only the inner state). Host bindings capture a clone to time their calls.
#[derive(Clone)]
pub struct ApiClock {
    state: Arc<Mutex<ClockState>>,
    listener: Rc<RefCell<Option<ApiListener>>>,
}

impl std::fmt::Debug for ApiClock {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter
            .debug_struct("ApiClock")
            .field("state", &self.state)
            .finish_non_exhaustive()
    }
}

impl ApiClock {
    pub(crate) fn new() -> Self {
        Self {
            state: Arc::new(Mutex::new(ClockState::new())),
            listener: Rc::new(RefCell::new(None)),
        }
    }

    /// Locks the state. A poisoned lock only means another thread panicked while holding it;
    /// the plain numbers inside are still meaningful, so the poison is ignored.
    pub(crate) fn lock(&self) -> MutexGuard<'_, ClockState> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The state shared with the watchdog thread.
    pub(crate) fn shared_state(&self) -> Arc<Mutex<ClockState>> {
        Arc::clone(&self.state)
    }

    /// Resets the clock for a new run with `api_budget`, sending API events to `listener`.
    pub(crate) fn begin_run(&self, api_budget: Duration, listener: Option<ApiListener>) {
        let mut state = self.lock();
        *state = ClockState::new();
        state.api_budget = api_budget;
        drop(state);
        *self.listener.borrow_mut() = listener;
    }

    /// Ends the run: returns (own time, API time, stop verdict, host panic message).
    pub(crate) fn end_run(&self) -> RunTimes {
        *self.listener.borrow_mut() = None;
        let state = self.lock();
        let now = Instant::now();
        RunTimes {
            own: state.own_elapsed(now),
            api: state.api_elapsed(now),
            stop: state.stop.map(|(reason, _)| reason),
            host_panic: state.host_panic.clone(),
        }
    }

    /// Runs one host binding: its time counts as API time, not own time, and a Rust panic
    /// inside it becomes a Python `RuntimeError` (the unit then fails as `internal`).
    ///
    /// When the call leaves the API time past its budget, the program gets a
    /// `KeyboardInterrupt` instead of the result and the unit fails as `api_timeout`.
    pub fn call<R>(
        &self,
        vm: &VirtualMachine,
        binding: impl FnOnce() -> PyResult<R>,
    ) -> PyResult<R> {
        self.enter();
        let result = catch_unwind(AssertUnwindSafe(binding));
        let over_budget = self.leave();
        match result {
            Ok(result) if !over_budget => result,
            Ok(_) => Err(vm.new_exception_msg(
                vm.ctx.exceptions.keyboard_interrupt.to_owned(),
                "sandbox: host api time budget exhausted".into(),
            )),
            Err(payload) if payload.is::<HardInterrupt>() => resume_unwind(payload),
            Err(payload) => {
                let message = panic_message(payload.as_ref());
                self.lock()
                    .host_panic
                    .get_or_insert_with(|| message.clone());
                Err(vm.new_runtime_error(format!("sandbox: host binding panicked: {message}")))
            }
        }
    }

    /// Makes a Python function named `name` whose calls go through [`ApiClock::call`].
    ///
    /// RustPython keeps native function definitions for the life of the process, so `binding`
    /// and what it captures are never freed: capture small handles (this clock, an `Rc` of
    /// host state), or build the function once per interpreter with
    /// [`crate::sandbox::InstallContext::cached`].
    pub fn function(
        &self,
        vm: &VirtualMachine,
        name: &'static str,
        binding: impl Fn(FuncArgs, &VirtualMachine) -> PyResult + 'static,
    ) -> PyObjectRef {
        let clock = self.clone();
        vm.new_function(name, move |arguments: FuncArgs, vm: &VirtualMachine| {
            clock.call(vm, || binding(arguments, vm))
        })
        .into()
    }

    fn enter(&self) {
        let mut state = self.lock();
        state.api_depth += 1;
        if state.api_depth > 1 {
            return;
        }
        state.api_entered_at = Some(Instant::now());
        drop(state);
        self.notify(ApiEvent::Enter);
    }

    /// Leaves the API; returns whether the API time is now past its budget.
    fn leave(&self) -> bool {
        let mut state = self.lock();
        state.api_depth = state.api_depth.saturating_sub(1);
        if state.api_depth > 0 {
            return false;
        }
        let now = Instant::now();
        if let Some(entered) = state.api_entered_at.take() {
            state.api_total += now.saturating_duration_since(entered);
        }
        let over_budget = state.api_total > state.api_budget;
        if over_budget {
            state.set_stop(StopReason::ApiTime, now);
        }
        let api_ms = state.api_total.as_secs_f64() * 1e3;
        drop(state);
        self.notify(ApiEvent::Exit { api_ms });
        over_budget
    }

    fn notify(&self, event: ApiEvent) {
        // A listener that is already borrowed means a nested notification from inside the
        // listener itself; dropping that one is harmless.
        if let Ok(mut listener) = self.listener.try_borrow_mut()
            && let Some(listener) = listener.as_mut()
        {
            listener(event);
        }
    }
}

/// What a run's clock measured.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RunTimes {
    /// Wall time outside the host API.
    pub(crate) own: Duration,
    /// Wall time inside the host API.
    pub(crate) api: Duration,
    /// The stop verdict, if a budget ran out.
    pub(crate) stop: Option<StopReason>,
    /// The message of the first host-binding panic, if one happened.
    pub(crate) host_panic: Option<String>,
}

/// The text of a panic payload (`&str` or `String`), or a placeholder.
pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(message) = payload.downcast_ref::<&str>() {
        (*message).to_owned()
    } else if let Some(message) = payload.downcast_ref::<String>() {
        message.clone()
    } else {
        "non-text panic payload".to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rustpython_vm::{AsObject, Settings};

    #[test]
    fn api_time_is_not_own_time() {
        let clock = ApiClock::new();
        let events = Rc::new(RefCell::new(Vec::new()));
        let sink = Rc::clone(&events);
        clock.begin_run(
            Duration::from_mins(1),
            Some(Box::new(move |event| sink.borrow_mut().push(event))),
        );
        rustpython_vm::Interpreter::without_stdlib(Settings::default()).enter(|vm| {
            let value = clock
                .call(vm, || {
                    // Nested calls count once.
                    clock.call(vm, || {
                        std::thread::sleep(Duration::from_millis(60));
                        Ok(7)
                    })
                })
                .unwrap();
            assert_eq!(value, 7);
        });
        let times = clock.end_run();
        assert!(times.api >= Duration::from_millis(60), "{times:?}");
        assert!(times.own < Duration::from_millis(60), "{times:?}");
        let events = events.borrow();
        assert_eq!(events.len(), 2, "{events:?}");
        assert_eq!(events[0], ApiEvent::Enter);
        assert!(matches!(events[1], ApiEvent::Exit { api_ms } if api_ms >= 60.0));
    }

    #[test]
    fn a_panicking_binding_becomes_an_exception_and_is_recorded() {
        let clock = ApiClock::new();
        clock.begin_run(Duration::from_mins(1), None);
        rustpython_vm::Interpreter::without_stdlib(Settings::default()).enter(|vm| {
            let result: PyResult<()> = clock.call(vm, || panic!("binding bug"));
            let exception = result.unwrap_err();
            assert_eq!(exception.class().name().to_string(), "RuntimeError");
        });
        let times = clock.end_run();
        assert_eq!(times.host_panic.as_deref(), Some("binding bug"));
        assert_eq!(clock.lock().api_depth, 0);
    }

    #[test]
    fn over_budget_api_time_sets_the_verdict() {
        let clock = ApiClock::new();
        clock.begin_run(Duration::from_millis(1), None);
        rustpython_vm::Interpreter::without_stdlib(Settings::default()).enter(|vm| {
            let result = clock.call(vm, || {
                std::thread::sleep(Duration::from_millis(5));
                Ok(())
            });
            let exception = result.unwrap_err();
            assert_eq!(exception.class().name().to_string(), "KeyboardInterrupt");
        });
        assert_eq!(clock.end_run().stop, Some(StopReason::ApiTime));
    }
}
