//! The worker process: the binary re-started with [`WORKER_ARGUMENT`], serving one program at a
//! time over the [`protocol`](super::protocol) on stdin/stdout.
//!
//! Input is request lines; output is message lines. At start the worker caps its address space
//! (`RLIMIT_AS`) and turns off core dumps; per request it sets `RLIMIT_CPU` to the CPU used so
//! far plus the unit's budget. Programs run on one thread with a large stack, in one reused
//! [`Sandbox`]; hosts come from the [`HostRegistry`], which memoises them per spec. The worker
//! exits when stdin closes, or when its parent dies: a killed `run` closes the workers' stdin,
//! but a worker inside a long host call (a simulation) reads stdin only when the call returns,
//! so a thread watches the parent ([`watch_parent`]) and ends the orphan at once.

use std::io::{BufRead, Write};
use std::process::ExitCode;
use std::time::Duration;

use super::clock::ApiEvent;
use super::error::Error;
use super::host::HostRegistry;
use super::interpreter::{RunReport, Sandbox};
use super::limits::WorkerLimits;
use super::protocol::{Request, WorkerMessage};
use super::rlimit;

/// Hidden first argument that makes the binary a sandbox worker (see [`worker_main`]).
pub const WORKER_ARGUMENT: &str = "__sandbox-worker";

/// Exit status of a worker that could not set itself up (limits, thread).
const SETUP_FAILURE: u8 = 70;

/// Environment variable holding the pool process's id: the worker's parent, whose death ends
/// the worker. Without it the worker watches the parent it started with.
pub(super) const PARENT_VARIABLE: &str = "CONTPHY_SANDBOX_PARENT";

/// Exit status of a worker whose parent died (nobody reads it; for `ps` and tests).
const ORPHANED: i32 = 71;

/// How often the worker checks that its parent is alive.
const PARENT_CHECK: Duration = Duration::from_millis(200);

/// Entry point of a worker process; call it from `main` when `argv[1]` is [`WORKER_ARGUMENT`],
/// before any other argument parsing. `argv[2]`, if present, is the [`WorkerLimits`] as JSON.
/// `registry` builds the hosts programs may name; it runs on the interpreter thread, because
/// hosts hold interpreter-thread state and are not `Send`.
pub fn worker_main(registry: impl FnOnce() -> HostRegistry + Send + 'static) -> ExitCode {
    let limits = match std::env::args().nth(2) {
        None => WorkerLimits::default(),
        Some(json) => match serde_json::from_str(&json) {
            Ok(limits) => limits,
            Err(error) => return setup_failure(&format!("bad worker limits `{json}`: {error}")),
        },
    };
    if let Err(error) = rlimit::disable_core_dumps() {
        return setup_failure(&format!("cannot disable core dumps: {error}"));
    }
    if let Err(error) = watch_parent() {
        return setup_failure(&format!("cannot start the parent watch: {error}"));
    }
    // The address-space cap is set on the interpreter thread, after its large stack is
    // mapped: the stack counts against the cap like any mapping, but the thread always starts.
    let serving = std::thread::Builder::new()
        .name("sandbox-interpreter".into())
        .stack_size(limits.interpreter_stack_bytes)
        .spawn(move || serve(registry(), &limits));
    match serving.map(std::thread::JoinHandle::join) {
        Ok(Ok(code)) => code,
        Ok(Err(_panic)) => ExitCode::from(SETUP_FAILURE),
        Err(error) => setup_failure(&format!("cannot start the interpreter thread: {error}")),
    }
}

/// Starts a thread that ends this process when its parent dies. An orphan is re-parented (to
/// init or a subreaper), so a parent id other than the pool's ([`PARENT_VARIABLE`], which also
/// covers a parent that died before this check first ran) means the parent is gone. Polling,
/// rather than `PR_SET_PDEATHSIG`: that signal fires when the parent *thread* that spawned the
/// worker exits, and the pool spawns replacement workers from short-lived threads.
fn watch_parent() -> std::io::Result<()> {
    let parent = std::env::var(PARENT_VARIABLE)
        .ok()
        .and_then(|pid| pid.parse::<u32>().ok())
        .unwrap_or_else(std::os::unix::process::parent_id);
    std::thread::Builder::new()
        .name("sandbox-parent-watch".into())
        .spawn(move || {
            loop {
                std::thread::sleep(PARENT_CHECK);
                if std::os::unix::process::parent_id() != parent {
                    std::process::exit(ORPHANED);
                }
            }
        })
        .map(drop)
}

fn setup_failure(message: &str) -> ExitCode {
    // stderr is the worker's free-text channel; the parent keeps its tail for crash reports.
    let _ = writeln!(std::io::stderr(), "sandbox worker: {message}");
    ExitCode::from(SETUP_FAILURE)
}

/// Writes one protocol message as a line on stdout.
fn send(message: &WorkerMessage) -> std::io::Result<()> {
    let mut line = serde_json::to_string(message).map_err(std::io::Error::other)?;
    line.push('\n');
    let mut stdout = std::io::stdout().lock();
    stdout.write_all(line.as_bytes())?;
    stdout.flush()
}

fn serve(mut registry: HostRegistry, limits: &WorkerLimits) -> ExitCode {
    if let Err(error) = rlimit::limit_address_space(limits.address_space_bytes) {
        return setup_failure(&format!("cannot limit the address space: {error}"));
    }
    let mut sandbox = Sandbox::new();
    let pid = std::process::id();
    let mut built_before = sandbox.interpreters_built();
    let mut ready = |sandbox: &mut Sandbox| -> std::io::Result<()> {
        // Build (or rebuild, after a hard interrupt) now rather than inside the next unit.
        let build_time = sandbox.warm_up().ok();
        let built_now = sandbox.interpreters_built();
        let interpreter_build_ms = build_time
            .filter(|_| built_now > built_before)
            .map(|time| time.as_secs_f64() * 1e3);
        built_before = built_now;
        send(&WorkerMessage::Ready {
            pid,
            interpreter_build_ms,
        })
    };
    if ready(&mut sandbox).is_err() {
        return ExitCode::from(SETUP_FAILURE);
    }
    for line in std::io::stdin().lock().lines() {
        let Ok(line) = line else {
            break;
        };
        if line.trim().is_empty() {
            continue;
        }
        let message = match serde_json::from_str::<Request>(&line) {
            Ok(request) => {
                let unit_id = request.unit_id;
                WorkerMessage::Done {
                    unit_id,
                    report: run_request(&mut sandbox, &mut registry, request),
                }
            }
            Err(error) => WorkerMessage::Rejected {
                message: format!("cannot parse the request: {error}"),
            },
        };
        if send(&message).is_err() {
            break;
        }
        // The report is out; releasing the program's memory may take a while, or (for absurdly
        // nested values) crash, and must not take a unit's result down with it.
        drop(message);
        sandbox.collect_garbage();
        if ready(&mut sandbox).is_err() {
            break;
        }
    }
    ExitCode::SUCCESS
}

fn run_request(sandbox: &mut Sandbox, registry: &mut HostRegistry, request: Request) -> RunReport {
    let Request {
        unit_id,
        host,
        source,
        budgets,
    } = request;
    if let Err(error) = rlimit::limit_cpu_time_from_now(Duration::from_millis(budgets.cpu_time_ms))
    {
        return RunReport::failed(Error::internal(format!(
            "cannot set the cpu limit: {error}"
        )));
    }
    // Building a host (loading a video) is API work: the parent must not count it as the
    // program's own time.
    let _ = send(&WorkerMessage::ApiEnter { unit_id });
    let host = registry.host(&host);
    let _ = send(&WorkerMessage::ApiExit { unit_id });
    let host = match host {
        Ok(host) => host,
        Err(error) => return RunReport::failed(error),
    };
    let listener = Box::new(move |event: ApiEvent| {
        let message = match event {
            ApiEvent::Enter => WorkerMessage::ApiEnter { unit_id },
            ApiEvent::Exit { .. } => WorkerMessage::ApiExit { unit_id },
        };
        // If stdout is gone the parent is gone; the run ends on its own and the loop exits.
        let _ = send(&message);
    });
    sandbox.run_with_events(host, &source, &budgets, Some(listener))
}
