//! The sandbox: runs untrusted, LLM-written Python programs against a host API, under limits.
//!
//! Input is a program (Python source), the host it runs against ([`HostSpec`]) and its
//! [`Budgets`]; output is a [`SandboxValue`] or a typed [`Error`], plus own time, API time and
//! the host's work counters. It owns everything between "program text" and "Python value":
//! the locked-down RustPython interpreter, the host seam, the budgets, and the worker processes.
//! It must not depend on the modules above it (`answer`, `score`, `report`, `app`, `cli`).
//!
//! Two layers (`docs/architecture.md`, sandbox):
//! 1. **Inside the interpreter** ([`Sandbox`]): no stdlib, builtins reduced to an allow-list,
//!    `import` limited to `math`, `__future__` and the host's modules, a static check of every
//!    name in the compiled code, a watchdog that interrupts programs past their own-time budget
//!    (soft, then hard), and bounded result conversion.
//! 2. **Around it** ([`Pool`]): programs run in worker processes (this binary started with
//!    [`WORKER_ARGUMENT`], entering [`worker_main`]) under `RLIMIT_AS` and `RLIMIT_CPU`, with a
//!    parent-side wall-clock kill for operations the VM cannot interrupt. A worker that dies
//!    fails only its unit and is replaced; a worker whose parent dies (a killed `run`) ends
//!    itself, even inside a long host call.
//!
//! Budget defaults are documented on [`Budgets`], [`ValueLimits`] and [`WorkerLimits`].
//!
//! ```text
//! Pool::submit(Unit) ──JSON line──► worker: Sandbox::run(host, source) ──JSON lines──► Pool::recv()
//!                                          ▲ api_enter / api_exit events pause the parent's clock
//! ```
//!
//! Running units (the application side):
//!
//! ```no_run
//! use contphy_eval::sandbox::{Budgets, HostSpec, Pool, PoolConfig, Unit, WorkerCommand};
//!
//! let pool = Pool::start(PoolConfig::new(WorkerCommand::current_exe()?, 4))?;
//! pool.submit(Unit {
//!     id: 0,
//!     key: "rope/0".into(), // units of one video share a worker and its memoised host
//!     host: HostSpec::stub(serde_json::json!({"video": "rope/0"})),
//!     source: "def execute_command(video):\n    return bool_to_yesno(True)\n".into(),
//!     budgets: Budgets::default(),
//! })?;
//! for result in pool.results() {
//!     match result.report.outcome {
//!         Ok(value) => { /* hand `value` to the answer module */ }
//!         Err(error) => { /* record `error.kind()` for unit `result.unit_id` */ }
//!     }
//! }
//! # Ok::<(), contphy_eval::sandbox::Error>(())
//! ```
//!
//! Registering a host (the binary's `main`, before any argument parsing):
//!
//! ```no_run
//! use contphy_eval::sandbox::{self, HostRegistry, SceneHost};
//!
//! fn main() -> std::process::ExitCode {
//!     if std::env::args_os().nth(1).is_some_and(|argument| argument == sandbox::WORKER_ARGUMENT) {
//!         return sandbox::worker_main(|| {
//!             let mut registry = HostRegistry::with_builtin_hosts();
//!             SceneHost::register(&mut registry);
//!             registry
//!         });
//!     }
//!     std::process::ExitCode::SUCCESS
//! }
//! ```

mod bench;
mod clock;
mod error;
mod host;
mod interpreter;
mod limits;
mod lockdown;
mod math;
mod pool;
mod protocol;
mod rlimit;
mod scene_host;
mod value;
mod watchdog;
mod worker;

pub use bench::{BenchConfig, BenchReport, PoolThroughput, ProgramTiming, TimeSummary, run_bench};
pub use clock::ApiClock;
pub use error::Error;
pub use host::{
    Host, HostConfigError, HostConstructor, HostRegistry, HostSpec, InstallContext, StubHost,
};
pub use interpreter::{RunReport, Sandbox};
pub use limits::{Budgets, ValueLimits, WorkerLimits};
pub use pool::{KILL_SLACK, Pool, PoolConfig, PoolStats, Unit, UnitResult, WorkerCommand};
pub use scene_host::{SCENE_HOST_NAME, SceneHost, scene_error_kind, scene_host_spec};
pub use value::{IntValue, SandboxValue};
pub use worker::{WORKER_ARGUMENT, worker_main};

#[cfg(test)]
mod tests;
