//! The watchdog: a thread per run that stops a program whose own time (or API time) runs out.
//!
//! Input is the run's [`ClockState`] (shared with the interpreter thread) and its budgets;
//! output is interrupts sent through RustPython's user-signal channel. A soft interrupt raises
//! `KeyboardInterrupt` in the program (a `BaseException`, so `except Exception` does not catch
//! it). The watchdog re-sends it every tick, because one send can be delayed or eaten (the VM's
//! wake-up flag is process-global, as probing RustPython 0.5 showed), and after the grace
//! period it sends a hard interrupt instead: a [`HardInterrupt`] panic that unwinds out of the
//! interpreter, which the sandbox then discards. That stops `while True: pass` inside
//! `try: ... except BaseException: pass`.
//!
//! The VM checks for interrupts only between bytecode instructions, so a single long operation
//! (`10 ** 10 ** 8`) or a host call cannot be interrupted from here; the parent process kills
//! the worker for those.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use rustpython_vm::signal::UserSignalSender;

use super::clock::{ClockState, HardInterrupt, StopReason};
use super::limits::Budgets;

/// How often the watchdog looks at the clock (and re-sends an interrupt once one is due).
const TICK: Duration = Duration::from_millis(10);

/// Sends interrupts into one run. Interrupts still queued when the run ends do nothing: each
/// checks that its run is still the current one.
#[derive(Clone)]
pub(crate) struct Interrupter {
    sender: UserSignalSender,
    run_id: u64,
    current_run: Arc<AtomicU64>,
}

impl Interrupter {
    pub(crate) fn new(sender: UserSignalSender, run_id: u64, current_run: Arc<AtomicU64>) -> Self {
        Self {
            sender,
            run_id,
            current_run,
        }
    }

    /// Raises `KeyboardInterrupt` in the program at its next instruction.
    fn soft(&self, reason: StopReason) {
        let run_id = self.run_id;
        let current_run = Arc::clone(&self.current_run);
        let message = match reason {
            StopReason::OwnTime => "sandbox: own-time budget exhausted",
            StopReason::ApiTime => "sandbox: host api time budget exhausted",
        };
        // A send fails only when the interpreter is gone, and then there is nothing to stop.
        let _ = self.sender.send(Box::new(move |vm| {
            if current_run.load(Ordering::SeqCst) != run_id {
                return Ok(());
            }
            Err(vm.new_exception_msg(
                vm.ctx.exceptions.keyboard_interrupt.to_owned(),
                message.into(),
            ))
        }));
    }

    /// Unwinds out of the interpreter at its next instruction (see [`HardInterrupt`]).
    fn hard(&self) {
        let run_id = self.run_id;
        let current_run = Arc::clone(&self.current_run);
        let _ = self.sender.send(Box::new(move |_vm| {
            if current_run.load(Ordering::SeqCst) != run_id {
                return Ok(());
            }
            #[expect(
                clippy::panic,
                reason = "the hard interrupt is a panic by design: the one way out of a program \
                          that swallows every exception; the sandbox catches it and discards the \
                          interpreter"
            )]
            std::panic::panic_any(HardInterrupt)
        }));
    }
}

/// A running watchdog; [`Watchdog::stop`] ends it.
pub(crate) struct Watchdog {
    stop: mpsc::Sender<()>,
    thread: JoinHandle<()>,
}

impl Watchdog {
    /// Starts watching a run that has just begun.
    pub(crate) fn start(
        clock: Arc<Mutex<ClockState>>,
        interrupter: Interrupter,
        budgets: &Budgets,
    ) -> std::io::Result<Self> {
        let (stop, stopped) = mpsc::channel();
        let own_budget = Duration::from_millis(budgets.own_time_ms);
        let api_budget = Duration::from_millis(budgets.api_time_ms);
        let grace = Duration::from_millis(budgets.grace_ms);
        let thread = std::thread::Builder::new()
            .name("sandbox-watchdog".into())
            .stack_size(64 * 1024)
            .spawn(move || {
                while let Err(RecvTimeoutError::Timeout) = stopped.recv_timeout(TICK) {
                    let now = Instant::now();
                    let mut state = clock.lock().unwrap_or_else(PoisonError::into_inner);
                    if state.own_elapsed(now) > own_budget {
                        state.set_stop(StopReason::OwnTime, now);
                    }
                    if state.api_elapsed(now) > api_budget {
                        state.set_stop(StopReason::ApiTime, now);
                    }
                    // Inside a host call the VM runs no bytecode and would only queue the
                    // interrupts; they are sent once the program is back.
                    let Some((reason, since)) = state.stop().filter(|_| !state.in_api()) else {
                        continue;
                    };
                    drop(state);
                    if now.saturating_duration_since(since) >= grace {
                        interrupter.hard();
                    } else {
                        interrupter.soft(reason);
                    }
                }
            })?;
        Ok(Self { stop, thread })
    }

    /// Stops the watchdog and waits for its thread.
    pub(crate) fn stop(self) {
        drop(self.stop);
        // The thread only sleeps and sends; a panic there would be a bug with nothing to undo.
        let _ = self.thread.join();
    }
}
