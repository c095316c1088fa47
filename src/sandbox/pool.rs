//! The pool: N worker processes, each owned by one thread, running units grouped by key.
//!
//! Input is [`Unit`]s (a program, its host, its budgets, and a key such as the video id);
//! output is [`UnitResult`]s, delivered as they finish through [`Pool::recv`]. Units with the same
//! key go to the same worker, in submission order, so the worker's memoised host (the loaded
//! video) serves all of them. A new key goes to the worker with the fewest queued units.
//!
//! The parent watches each unit's clock from the worker's `api_enter`/`api_exit` lines and kills
//! the worker (`SIGKILL`) when own time passes its budget plus twice the grace period plus
//! [`KILL_SLACK`] (the in-process hard interrupt should have fired long before), or when one
//! host call keeps the API time past its budget plus grace. That covers what the VM cannot
//! interrupt (`10 ** 10 ** 8`, a huge allocation, a stuck binding). A worker that dies, for
//! whatever reason, fails only the unit it was running, with a typed error (`timeout`,
//! `api_timeout`, `cpu` for `SIGXCPU`, `memory` when it died allocating, else `crashed` with the
//! signal and its last stderr line), and is replaced for the next unit.
//!
//! Workers get an empty environment: programs cannot read it anyway, and the worker has no
//! use for secrets such as API keys.

use std::collections::{HashMap, VecDeque};
use std::ffi::OsString;
use std::io::{BufRead, BufReader, Read, Write};
use std::os::unix::process::ExitStatusExt;
use std::path::PathBuf;
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use super::error::Error;
use super::host::HostSpec;
use super::interpreter::RunReport;
use super::limits::{Budgets, WorkerLimits};
use super::protocol::{Request, WorkerMessage};
use super::rlimit::signal_name;
use super::worker::{PARENT_VARIABLE, WORKER_ARGUMENT};

/// Extra own time the parent allows before killing, for what happens around the program in
/// the worker (reading the request, compiling, rebuilding an interpreter) and for scheduling.
pub const KILL_SLACK: Duration = Duration::from_millis(500);

/// Lines of a worker's stderr kept for crash reports.
const STDERR_TAIL_LINES: usize = 20;

/// How long a worker gets to exit after its stdin is closed before it is killed.
const SHUTDOWN_WAIT: Duration = Duration::from_secs(1);

/// How to start a worker process.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WorkerCommand {
    /// The executable (this binary).
    pub program: PathBuf,
    /// Arguments before the limits argument; normally just [`WORKER_ARGUMENT`].
    pub arguments: Vec<OsString>,
    /// The only environment variables the worker starts with: its environment is cleared so
    /// that nothing of the user's shell reaches the sandbox, but the scene API it hosts may need
    /// a few (where ONNX Runtime is).
    pub environment: Vec<(OsString, OsString)>,
}

impl WorkerCommand {
    /// `program __sandbox-worker`.
    pub fn new(program: impl Into<PathBuf>) -> Self {
        Self {
            program: program.into(),
            arguments: vec![WORKER_ARGUMENT.into()],
            environment: Vec::new(),
        }
    }

    /// The running executable as a worker (what the application uses).
    pub fn current_exe() -> Result<Self, Error> {
        std::env::current_exe()
            .map(Self::new)
            .map_err(|error| Error::internal(format!("cannot locate the running binary: {error}")))
    }
}

/// Settings of a [`Pool`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PoolConfig {
    /// Number of worker processes (at least one).
    pub jobs: usize,
    /// How to start a worker.
    pub worker: WorkerCommand,
    /// Limits every worker sets on itself at start.
    pub limits: WorkerLimits,
    /// How long a worker may take to start, or to release a finished program's memory, before
    /// it is replaced (default 60 s).
    pub ready_timeout: Duration,
}

impl PoolConfig {
    /// `jobs` workers started with `worker`, default limits.
    pub fn new(worker: WorkerCommand, jobs: usize) -> Self {
        Self {
            jobs,
            worker,
            limits: WorkerLimits::default(),
            ready_timeout: Duration::from_mins(1),
        }
    }
}

/// One program to run.
#[derive(Debug, Clone, PartialEq)]
pub struct Unit {
    /// The caller's id, echoed in the result.
    pub id: u64,
    /// Routing key: units with equal keys run on the same worker, in order (use the video id).
    pub key: String,
    /// The host the program runs against.
    pub host: HostSpec,
    /// Python source.
    pub source: String,
    /// Budgets of this program.
    pub budgets: Budgets,
}

/// A finished unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UnitResult {
    /// The unit's id.
    pub unit_id: u64,
    /// The unit's routing key.
    pub key: String,
    /// What the run produced (or why it failed).
    pub report: RunReport,
    /// Wall time from the worker thread taking the unit to its result, in milliseconds.
    pub wall_ms: f64,
    /// Process id of the worker that ran it, if one started.
    pub worker_pid: Option<u32>,
}

/// Counters of a pool's life so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct PoolStats {
    /// Worker processes started (including replacements).
    pub workers_started: u64,
    /// Worker processes that died or were killed while the pool was running.
    pub workers_lost: u64,
}

/// Worker processes running units; see the module docs.
pub struct Pool {
    slots: Vec<Slot>,
    /// Which slot each key was given to.
    assignments: Mutex<HashMap<String, usize>>,
    results: Mutex<Receiver<UnitResult>>,
    outstanding: AtomicUsize,
    shared: Arc<Shared>,
}

impl std::fmt::Debug for Pool {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter
            .debug_struct("Pool")
            .field("jobs", &self.slots.len())
            .field("outstanding", &self.outstanding.load(Ordering::SeqCst))
            .field("stats", &self.stats())
            .finish_non_exhaustive()
    }
}

/// One worker's queue and the thread that owns the worker.
struct Slot {
    units: Option<Sender<Unit>>,
    queued: Arc<AtomicUsize>,
    thread: Option<JoinHandle<()>>,
}

/// State every slot thread reads.
struct Shared {
    config: PoolConfig,
    closing: AtomicBool,
    workers_started: AtomicU64,
    workers_lost: AtomicU64,
}

impl Pool {
    /// Starts `config.jobs` workers (each slot starts its worker at once, so start-up is not
    /// charged to the first unit).
    pub fn start(config: PoolConfig) -> Result<Self, Error> {
        if !config.worker.program.is_file() {
            return Err(Error::internal(format!(
                "worker program `{}` does not exist",
                config.worker.program.display()
            )));
        }
        let jobs = config.jobs.max(1);
        let shared = Arc::new(Shared {
            config,
            closing: AtomicBool::new(false),
            workers_started: AtomicU64::new(0),
            workers_lost: AtomicU64::new(0),
        });
        let (results_sender, results) = mpsc::channel();
        let mut slots = Vec::with_capacity(jobs);
        for index in 0..jobs {
            let (units_sender, units) = mpsc::channel();
            let queued = Arc::new(AtomicUsize::new(0));
            let thread = {
                let queued = Arc::clone(&queued);
                let shared = Arc::clone(&shared);
                let results = results_sender.clone();
                std::thread::Builder::new()
                    .name(format!("sandbox-slot-{index}"))
                    .spawn(move || slot_main(&units, &results, &queued, &shared))
                    .map_err(|error| {
                        Error::internal(format!("cannot start a pool thread: {error}"))
                    })?
            };
            slots.push(Slot {
                units: Some(units_sender),
                queued,
                thread: Some(thread),
            });
        }
        Ok(Self {
            slots,
            assignments: Mutex::new(HashMap::new()),
            results: Mutex::new(results),
            outstanding: AtomicUsize::new(0),
            shared,
        })
    }

    /// Queues `unit` on the worker that owns its key (assigning the key if it is new).
    pub fn submit(&self, unit: Unit) -> Result<(), Error> {
        let index = {
            let mut assignments = self
                .assignments
                .lock()
                .unwrap_or_else(PoisonError::into_inner);
            if let Some(&index) = assignments.get(&unit.key) {
                index
            } else {
                let index = self
                    .slots
                    .iter()
                    .enumerate()
                    .min_by_key(|(_, slot)| slot.queued.load(Ordering::SeqCst))
                    .map_or(0, |(index, _)| index);
                assignments.insert(unit.key.clone(), index);
                index
            }
        };
        let slot = self
            .slots
            .get(index)
            .ok_or_else(|| Error::internal(format!("no worker slot {index}")))?;
        let sender = slot
            .units
            .as_ref()
            .ok_or_else(|| Error::internal("the pool is shutting down"))?;
        slot.queued.fetch_add(1, Ordering::SeqCst);
        self.outstanding.fetch_add(1, Ordering::SeqCst);
        sender.send(unit).map_err(|_| {
            slot.queued.fetch_sub(1, Ordering::SeqCst);
            self.outstanding.fetch_sub(1, Ordering::SeqCst);
            Error::internal(format!("worker slot {index} has stopped"))
        })
    }

    /// The next finished unit, waiting for it; `None` when no submitted unit is outstanding.
    pub fn recv(&self) -> Option<UnitResult> {
        self.recv_within(None)
    }

    /// Like [`Pool::recv`], but gives up after `timeout` (also returning `None`).
    pub fn recv_timeout(&self, timeout: Duration) -> Option<UnitResult> {
        self.recv_within(Some(timeout))
    }

    fn recv_within(&self, timeout: Option<Duration>) -> Option<UnitResult> {
        if self.outstanding.load(Ordering::SeqCst) == 0 {
            return None;
        }
        let results = self.results.lock().unwrap_or_else(PoisonError::into_inner);
        let result = match timeout {
            None => results.recv().ok(),
            Some(timeout) => results.recv_timeout(timeout).ok(),
        };
        if result.is_some() {
            self.outstanding.fetch_sub(1, Ordering::SeqCst);
        }
        result
    }

    /// Results as they finish, until none is outstanding.
    pub fn results(&self) -> impl Iterator<Item = UnitResult> + '_ {
        std::iter::from_fn(|| self.recv())
    }

    /// Submits all `units` and waits for all their results (in finishing order).
    pub fn run_all(&self, units: impl IntoIterator<Item = Unit>) -> Result<Vec<UnitResult>, Error> {
        for unit in units {
            self.submit(unit)?;
        }
        Ok(self.results().collect())
    }

    /// Submitted units whose results have not been received yet.
    pub fn outstanding(&self) -> usize {
        self.outstanding.load(Ordering::SeqCst)
    }

    /// Workers started and lost so far.
    pub fn stats(&self) -> PoolStats {
        PoolStats {
            workers_started: self.shared.workers_started.load(Ordering::SeqCst),
            workers_lost: self.shared.workers_lost.load(Ordering::SeqCst),
        }
    }
}

impl Drop for Pool {
    /// Stops taking units, lets running units finish (within their budgets), skips queued ones,
    /// and shuts the workers down.
    fn drop(&mut self) {
        self.shared.closing.store(true, Ordering::SeqCst);
        for slot in &mut self.slots {
            slot.units = None;
        }
        for slot in &mut self.slots {
            if let Some(thread) = slot.thread.take() {
                let _ = thread.join();
            }
        }
    }
}

/// A slot thread: owns one worker process at a time and runs its queue.
fn slot_main(
    units: &Receiver<Unit>,
    results: &Sender<UnitResult>,
    queued: &AtomicUsize,
    shared: &Shared,
) {
    let mut worker = WorkerProcess::spawn(shared).ok();
    for unit in units {
        if shared.closing.load(Ordering::SeqCst) {
            break;
        }
        let started = Instant::now();
        let (report, worker_pid) = run_unit(&mut worker, shared, &unit);
        queued.fetch_sub(1, Ordering::SeqCst);
        let result = UnitResult {
            unit_id: unit.id,
            key: unit.key,
            report,
            wall_ms: started.elapsed().as_secs_f64() * 1e3,
            worker_pid,
        };
        if results.send(result).is_err() {
            break;
        }
    }
    if let Some(worker) = worker {
        worker.shut_down();
    }
}

/// Runs `unit` on the slot's worker, starting or replacing the worker as needed.
fn run_unit(
    worker: &mut Option<WorkerProcess>,
    shared: &Shared,
    unit: &Unit,
) -> (RunReport, Option<u32>) {
    // A worker that finished its last unit but died (or hung) releasing its memory is replaced
    // here, without blaming this unit.
    if let Some(process) = worker.as_mut()
        && process.wait_ready(shared.config.ready_timeout).is_err()
    {
        shared.workers_lost.fetch_add(1, Ordering::SeqCst);
        if let Some(process) = worker.take() {
            process.kill_and_reap();
        }
    }
    let process = match worker.take() {
        Some(process) => worker.insert(process),
        None => match WorkerProcess::spawn(shared) {
            Ok(process) => worker.insert(process),
            Err(error) => return (RunReport::failed(error), None),
        },
    };
    let pid = process.pid;
    match process.run(unit) {
        Ok(report) => (report, Some(pid)),
        Err(ending) => {
            shared.workers_lost.fetch_add(1, Ordering::SeqCst);
            let (own, api) = (process.unit_own, process.unit_api);
            let error = match worker.take() {
                Some(dead) => dead.classify_ending(ending, &unit.budgets),
                None => Error::internal("the worker vanished"),
            };
            // The worker's own measurement died with it; the parent's clock is the next best.
            let mut report = RunReport::failed(error);
            report.own_ms = own.as_secs_f64() * 1e3;
            report.api_ms = api.as_secs_f64() * 1e3;
            (report, Some(pid))
        }
    }
}

/// A line read from a worker's stdout.
enum Line {
    Message(WorkerMessage),
    /// Not a protocol message (a worker bug): the start of the line, for the error report.
    Unparsable(String),
}

/// How a unit ended without a report.
enum Ending {
    /// The parent killed the worker for this reason.
    Killed(Error),
    /// The worker's stdout closed: it died on its own.
    Died,
}

/// The last lines of a worker's stderr, numbered so a crash report shows only the lines
/// written during the unit that crashed.
#[derive(Default)]
struct StderrTail {
    lines: VecDeque<String>,
    total: u64,
}

/// A running worker process and the threads that read its output.
struct WorkerProcess {
    child: Child,
    stdin: Option<ChildStdin>,
    messages: Receiver<Line>,
    stderr_tail: Arc<Mutex<StderrTail>>,
    stderr_reader: Option<JoinHandle<()>>,
    pid: u32,
    /// Whether the worker said `ready` since its last unit.
    idle: bool,
    /// [`WorkerProcess::stderr_mark`] when the current unit was sent.
    unit_stderr_mark: u64,
    /// Own time of the current unit as the parent measures it.
    unit_own: Duration,
    /// API time of the current unit as the parent measures it.
    unit_api: Duration,
}

impl WorkerProcess {
    fn spawn(shared: &Shared) -> Result<Self, Error> {
        let config = &shared.config;
        let limits = serde_json::to_string(&config.limits)
            .map_err(|error| Error::internal(format!("cannot encode worker limits: {error}")))?;
        let mut child = Command::new(&config.worker.program)
            .args(&config.worker.arguments)
            .arg(limits)
            .env_clear()
            .envs(config.worker.environment.iter().cloned())
            // The worker ends itself when this process is gone (see `worker::watch_parent`).
            .env(PARENT_VARIABLE, std::process::id().to_string())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|error| {
                Error::internal(format!(
                    "cannot start worker `{}`: {error}",
                    config.worker.program.display()
                ))
            })?;
        let pid = child.id();
        let (Some(stdin), Some(stdout), Some(stderr)) =
            (child.stdin.take(), child.stdout.take(), child.stderr.take())
        else {
            let _ = child.kill();
            let _ = child.wait();
            return Err(Error::internal("worker pipes were not created"));
        };
        let (line_sender, messages) = mpsc::channel();
        let stdout_reader = std::thread::Builder::new()
            .name(format!("sandbox-worker-{pid}-out"))
            .spawn(move || read_messages(stdout, &line_sender));
        let stderr_tail = Arc::new(Mutex::new(StderrTail::default()));
        let stderr_reader = {
            let tail = Arc::clone(&stderr_tail);
            std::thread::Builder::new()
                .name(format!("sandbox-worker-{pid}-err"))
                .spawn(move || read_stderr(stderr, &tail))
        };
        let (Ok(_detached), Ok(stderr_reader)) = (stdout_reader, stderr_reader) else {
            let _ = child.kill();
            let _ = child.wait();
            return Err(Error::internal("cannot start worker reader threads"));
        };
        shared.workers_started.fetch_add(1, Ordering::SeqCst);
        let mut process = Self {
            child,
            stdin: Some(stdin),
            messages,
            stderr_tail,
            stderr_reader: Some(stderr_reader),
            pid,
            idle: false,
            unit_stderr_mark: 0,
            unit_own: Duration::ZERO,
            unit_api: Duration::ZERO,
        };
        if let Err(error) = process.wait_ready(config.ready_timeout) {
            let detail = process.stderr_since(0);
            process.kill_and_reap();
            return Err(Error::internal(format!(
                "worker did not start: {error}{}",
                if detail.is_empty() {
                    String::new()
                } else {
                    format!("; stderr: {detail}")
                }
            )));
        }
        Ok(process)
    }

    /// Waits until the worker says `ready` (it does after start-up and after each unit).
    fn wait_ready(&mut self, timeout: Duration) -> Result<(), String> {
        if self.idle {
            return Ok(());
        }
        let deadline = Instant::now() + timeout;
        loop {
            let remaining = deadline.saturating_duration_since(Instant::now());
            match self.messages.recv_timeout(remaining) {
                Ok(Line::Message(WorkerMessage::Ready { .. })) => {
                    self.idle = true;
                    return Ok(());
                }
                Ok(_) => {}
                Err(RecvTimeoutError::Timeout) => {
                    return Err(format!("no `ready` within {} ms", timeout.as_millis()));
                }
                Err(RecvTimeoutError::Disconnected) => return Err("the worker exited".into()),
            }
        }
    }

    /// Sends `unit` and follows it to its report, or kills the worker when a budget is
    /// exceeded beyond what the worker enforces itself.
    fn run(&mut self, unit: &Unit) -> Result<RunReport, Ending> {
        let request = Request {
            unit_id: unit.id,
            host: unit.host.clone(),
            source: unit.source.clone(),
            budgets: unit.budgets.clone(),
        };
        let mut line = serde_json::to_string(&request).map_err(|error| {
            Ending::Killed(Error::internal(format!(
                "cannot encode the request: {error}"
            )))
        })?;
        line.push('\n');
        self.unit_stderr_mark = self.stderr_mark();
        (self.unit_own, self.unit_api) = (Duration::ZERO, Duration::ZERO);
        let sent = self.stdin.as_mut().map(|stdin| {
            stdin
                .write_all(line.as_bytes())
                .and_then(|()| stdin.flush())
        });
        if !matches!(sent, Some(Ok(()))) {
            return Err(Ending::Died);
        }
        self.idle = false;

        let budgets = &unit.budgets;
        let grace = Duration::from_millis(budgets.grace_ms);
        let own_limit = Duration::from_millis(budgets.own_time_ms) + 2 * grace + KILL_SLACK;
        let api_limit = Duration::from_millis(budgets.api_time_ms) + grace;
        let started = Instant::now();
        let mut api_total = Duration::ZERO;
        let mut api_since: Option<Instant> = None;
        loop {
            let now = Instant::now();
            let api = api_total + api_since.map_or(Duration::ZERO, |since| now - since);
            let own = now.saturating_duration_since(started).saturating_sub(api);
            (self.unit_own, self.unit_api) = (own, api);
            if own > own_limit {
                return Err(Ending::Killed(Error::Timeout {
                    budget_ms: budgets.own_time_ms,
                }));
            }
            if api > api_limit {
                return Err(Ending::Killed(Error::ApiTimeout {
                    budget_ms: budgets.api_time_ms,
                }));
            }
            // Sleep until the clock that is running could pass its limit.
            let wait = if api_since.is_some() {
                api_limit.saturating_sub(api)
            } else {
                own_limit.saturating_sub(own)
            } + Duration::from_millis(1);
            match self.messages.recv_timeout(wait) {
                Ok(Line::Message(message)) => match message {
                    WorkerMessage::ApiEnter { unit_id } if unit_id == unit.id => {
                        api_since.get_or_insert_with(Instant::now);
                    }
                    WorkerMessage::ApiExit { unit_id } if unit_id == unit.id => {
                        if let Some(since) = api_since.take() {
                            api_total += since.elapsed();
                        }
                    }
                    WorkerMessage::Done { unit_id, report } if unit_id == unit.id => {
                        return Ok(report);
                    }
                    WorkerMessage::Rejected { message } => {
                        return Ok(RunReport::failed(Error::internal(format!(
                            "the worker rejected the request: {message}"
                        ))));
                    }
                    _ => {}
                },
                Ok(Line::Unparsable(line)) => {
                    // The protocol is out of step: nothing later from this worker can be
                    // trusted to belong to this unit.
                    return Err(Ending::Killed(Error::internal(format!(
                        "the worker wrote a line that is not a protocol message: {line:?}"
                    ))));
                }
                Err(RecvTimeoutError::Timeout) => {}
                Err(RecvTimeoutError::Disconnected) => return Err(Ending::Died),
            }
        }
    }

    /// Ends the worker after `ending` and says what happened to the unit.
    fn classify_ending(mut self, ending: Ending, budgets: &Budgets) -> Error {
        let mark = self.unit_stderr_mark;
        let killed = match ending {
            Ending::Killed(error) => Some(error),
            Ending::Died => None,
        };
        let status = self.kill_and_wait();
        let stderr = self.stderr_since(mark);
        if let Some(error) = killed {
            return error;
        }
        // Rust aborts when an allocation fails (RustPython 0.5 sizes some buffers with
        // `Vec::with_capacity`, e.g. `[0] * 10 ** 9`), after printing this line.
        if let Some(line) = stderr
            .lines()
            .find(|line| line.contains("memory allocation of"))
        {
            return Error::Memory {
                message: format!("the worker died allocating memory: {line}"),
            };
        }
        let last_line = stderr.lines().last().unwrap_or("").to_owned();
        match status.and_then(|status| status.signal()) {
            Some(libc::SIGXCPU) => Error::Cpu {
                budget_ms: budgets.cpu_time_ms,
            },
            Some(signal) => Error::Crashed {
                signal: Some(signal),
                signal_name: Some(signal_name(signal)),
                detail: format!("killed by {}; stderr: {last_line}", signal_name(signal)),
            },
            None => Error::Crashed {
                signal: None,
                signal_name: None,
                detail: format!(
                    "exited with {}; stderr: {last_line}",
                    status.map_or_else(
                        || "an unknown status".to_owned(),
                        |status| status.to_string()
                    )
                ),
            },
        }
    }

    /// Number of stderr lines seen so far (to show only later ones in a crash report).
    fn stderr_mark(&self) -> u64 {
        self.stderr_tail
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .total
    }

    /// Stderr lines after `mark` that are still in the tail, joined.
    fn stderr_since(&self, mark: u64) -> String {
        let tail = self
            .stderr_tail
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        let kept = tail.lines.len() as u64;
        let first_kept = tail.total.saturating_sub(kept);
        let skip = usize::try_from(mark.saturating_sub(first_kept)).unwrap_or(usize::MAX);
        tail.lines
            .iter()
            .skip(skip)
            .map(String::as_str)
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// Kills the worker (if still running), reaps it, and waits for its stderr to drain.
    fn kill_and_wait(&mut self) -> Option<ExitStatus> {
        self.stdin = None;
        let _ = self.child.kill();
        let status = self.child.wait().ok();
        if let Some(reader) = self.stderr_reader.take() {
            let _ = reader.join();
        }
        status
    }

    fn kill_and_reap(mut self) {
        self.kill_and_wait();
    }

    /// Closes stdin so the worker exits on its own; kills it if it has not after a moment.
    fn shut_down(mut self) {
        self.stdin = None;
        let deadline = Instant::now() + SHUTDOWN_WAIT;
        while Instant::now() < deadline {
            if matches!(self.child.try_wait(), Ok(Some(_))) {
                break;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        self.kill_and_wait();
    }
}

impl Drop for WorkerProcess {
    fn drop(&mut self) {
        // Never leave a worker running or a zombie behind (idempotent after kill_and_wait).
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Reads protocol lines until the worker's stdout closes (dropping `lines` tells the owner).
fn read_messages(stdout: impl Read, lines: &Sender<Line>) {
    let mut reader = BufReader::new(stdout);
    let mut buffer = Vec::new();
    loop {
        buffer.clear();
        match reader.read_until(b'\n', &mut buffer) {
            Ok(0) | Err(_) => return,
            Ok(_) => {}
        }
        let line = if let Ok(message) = serde_json::from_slice::<WorkerMessage>(&buffer) {
            Line::Message(message)
        } else {
            let text = String::from_utf8_lossy(&buffer);
            Line::Unparsable(text.trim_end().chars().take(200).collect())
        };
        if lines.send(line).is_err() {
            return;
        }
    }
}

/// Keeps the last [`STDERR_TAIL_LINES`] lines of the worker's stderr.
fn read_stderr(stderr: impl Read, tail: &Mutex<StderrTail>) {
    let mut reader = BufReader::new(stderr);
    let mut buffer = Vec::new();
    loop {
        buffer.clear();
        match reader.read_until(b'\n', &mut buffer) {
            Ok(0) | Err(_) => return,
            Ok(_) => {}
        }
        let line = String::from_utf8_lossy(&buffer).trim_end().to_owned();
        let mut tail = tail.lock().unwrap_or_else(PoisonError::into_inner);
        tail.total += 1;
        tail.lines.push_back(line);
        if tail.lines.len() > STDERR_TAIL_LINES {
            tail.lines.pop_front();
        }
    }
}
