//! `Sandbox`: one locked-down RustPython interpreter that runs programs one after another.
//!
//! Input is a program's source, a [`Host`] and [`Budgets`]; output is a [`RunReport`] (the
//! result as a [`SandboxValue`] or an [`Error`], own and API time, the host's work counters,
//! captured `print` output). The interpreter is built once (no stdlib, builtins locked,
//! `sys.modules` emptied, fixed hash seed, recursion limit 1000 in every build profile) and
//! reused: each program gets fresh globals and fresh copies of its importable modules. After a
//! hard interrupt it is discarded and rebuilt on the next run.
//!
//! A program either defines `execute_command(video)`, which is called with the global `video`,
//! or sets a global `answer`; `execute_command` wins if both exist.
//!
//! The sandbox is not `Send` and must live on a thread with a large stack (see
//! [`crate::sandbox::WorkerLimits::interpreter_stack_bytes`]): RustPython recurses on the native
//! stack for nested values and calls, and sizes its own overflow guard from that thread's stack.

use std::cell::RefCell;
use std::collections::{BTreeMap, HashMap};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::rc::Rc;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use rustpython_vm::builtins::{PyBaseExceptionRef, PyDictRef};
use rustpython_vm::bytecode::CodeObject;
use rustpython_vm::common::rc::PyRc;
use rustpython_vm::scope::Scope;
use rustpython_vm::signal::{UserSignalSender, user_signal_channel};
use rustpython_vm::{
    AsObject, Interpreter, PyObjectRef, PyPayload, PyResult, Settings, VirtualMachine,
};
use serde::{Deserialize, Serialize};

use super::clock::{ApiClock, ApiListener, HardInterrupt, StopReason, panic_message};
use super::error::Error;
use super::host::{Host, InstallContext};
use super::limits::Budgets;
use super::lockdown::{
    ProgramEnvironment, compile_checked, exception_is_a, future_module_dict, lock_builtins,
};
use super::math::math_module_dict;
use super::value::{SandboxValue, to_sandbox_value};
use super::watchdog::{Interrupter, Watchdog};

/// Python recursion limit, fixed so debug and release builds fail (or not) at the same depth
/// (RustPython defaults to 256 with debug assertions and 1000 without).
const RECURSION_LIMIT: usize = 1000;

/// Native modules RustPython registers that no program needs and that touch the clock, the
/// garbage collector or raw code objects; dropped so even the importer machinery cannot build
/// them. (A whitelist of module definitions makes interpreter start-up fail, as a probe showed.)
const DENIED_MODULE_DEFINITIONS: &[&str] = &[
    "posix",
    "pwd",
    "_ctypes",
    "_interpreters",
    "_interpchannels",
    "_interpqueues",
    "_testinternalcapi",
    "_sysconfig",
    "_sysconfigdata",
    "marshal",
    "gc",
    "time",
];

/// What running one program produced.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunReport {
    /// The result, or why there is none.
    pub outcome: Result<SandboxValue, Error>,
    /// Wall time outside host API calls, in milliseconds.
    pub own_ms: f64,
    /// Wall time inside host API calls, in milliseconds.
    pub api_ms: f64,
    /// The host's work counters for this program.
    pub work_counters: serde_json::Value,
    /// What the program printed (at most 64 KiB).
    pub printed: String,
}

/// A reusable, locked-down interpreter plus the clock its host bindings use.
pub struct Sandbox {
    clock: ApiClock,
    interpreter: Option<LockedInterpreter>,
    /// Id of the run in progress; interrupts carry the id of the run they were sent for.
    current_run: Arc<AtomicU64>,
    interpreters_built: u64,
}

impl std::fmt::Debug for Sandbox {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter
            .debug_struct("Sandbox")
            .field("interpreter_ready", &self.interpreter.is_some())
            .field("interpreters_built", &self.interpreters_built)
            .finish_non_exhaustive()
    }
}

/// The interpreter and what was built alongside it.
struct LockedInterpreter {
    interpreter: Interpreter,
    signal_sender: UserSignalSender,
    environment: Rc<RefCell<ProgramEnvironment>>,
    /// Attributes of the modules every program may import (`math`, `__future__`), copied into
    /// fresh module objects for each program.
    base_modules: Vec<(&'static str, PyDictRef)>,
    /// Host objects built once per interpreter ([`InstallContext::cached`]).
    cache: HashMap<String, PyObjectRef>,
    /// The last program's globals and result, dropped after its report is out (dropping a
    /// deeply nested value is the step most likely to crash, so it comes last).
    garbage: Vec<PyObjectRef>,
}

impl LockedInterpreter {
    fn build() -> Result<Self, Error> {
        let (signal_sender, signal_receiver) = user_signal_channel();
        let interpreter = Interpreter::builder(sandbox_settings())
            .init_hook(move |vm| {
                vm.set_user_signal_channel(signal_receiver);
                vm.recursion_limit.set(RECURSION_LIMIT);
                if let Some(state) = PyRc::get_mut(&mut vm.state) {
                    state
                        .module_defs
                        .retain(|name, _| !DENIED_MODULE_DEFINITIONS.contains(name));
                }
            })
            .build();
        let environment = Rc::new(RefCell::new(ProgramEnvironment::default()));
        let base_modules = interpreter
            .enter(|vm| -> PyResult<Vec<(&'static str, PyDictRef)>> {
                lock_builtins(vm, &environment)?;
                Ok(vec![
                    ("math", math_module_dict(vm)?),
                    ("__future__", future_module_dict(vm)?),
                ])
            })
            .map_err(|exception| {
                Error::internal(format!(
                    "cannot lock down a new interpreter: {}",
                    exception.class().name()
                ))
            })?;
        Ok(Self {
            interpreter,
            signal_sender,
            environment,
            base_modules,
            cache: HashMap::new(),
            garbage: Vec::new(),
        })
    }
}

fn sandbox_settings() -> Settings {
    let mut settings = Settings::default();
    settings.isolated = true;
    settings.ignore_environment = true;
    settings.import_site = false;
    settings.user_site_directory = false;
    settings.safe_path = true;
    settings.write_bytecode = false;
    settings.install_signal_handlers = false;
    settings.allow_external_library = false;
    settings.hash_seed = Some(0);
    settings.path_list.clear();
    settings.argv.clear();
    settings
}

impl Default for Sandbox {
    fn default() -> Self {
        Self::new()
    }
}

impl Sandbox {
    /// A sandbox with no interpreter yet (the first run builds it; see [`Sandbox::warm_up`]).
    pub fn new() -> Self {
        install_quiet_interrupt_hook();
        Self {
            clock: ApiClock::new(),
            interpreter: None,
            current_run: Arc::new(AtomicU64::new(0)),
            interpreters_built: 0,
        }
    }

    /// Builds the interpreter now instead of on the first run; returns how long it took.
    pub fn warm_up(&mut self) -> Result<Duration, Error> {
        let started = Instant::now();
        ensure_interpreter(&mut self.interpreter, &mut self.interpreters_built)?;
        Ok(started.elapsed())
    }

    /// How many interpreters this sandbox has built (more than one after hard interrupts).
    pub fn interpreters_built(&self) -> u64 {
        self.interpreters_built
    }

    /// Runs `source` against `host` within `budgets`.
    pub fn run(&mut self, host: &mut dyn Host, source: &str, budgets: &Budgets) -> RunReport {
        self.run_with_events(host, source, budgets, None)
    }

    /// [`Sandbox::run`], reporting host API entries and exits to `listener` as they happen.
    pub(crate) fn run_with_events(
        &mut self,
        host: &mut dyn Host,
        source: &str,
        budgets: &Budgets,
        listener: Option<ApiListener>,
    ) -> RunReport {
        self.collect_garbage();
        let code = match compile_checked(source) {
            Ok(code) => code,
            Err(error) => return RunReport::failed(error),
        };
        let locked = match ensure_interpreter(&mut self.interpreter, &mut self.interpreters_built) {
            Ok(locked) => locked,
            Err(error) => return RunReport::failed(error),
        };

        let run_id = self.current_run.fetch_add(1, Ordering::SeqCst) + 1;
        self.clock
            .begin_run(Duration::from_millis(budgets.api_time_ms), listener);
        let interrupter = Interrupter::new(
            locked.signal_sender.clone(),
            run_id,
            Arc::clone(&self.current_run),
        );
        let watchdog = match Watchdog::start(self.clock.shared_state(), interrupter, budgets) {
            Ok(watchdog) => watchdog,
            Err(error) => {
                self.clock.end_run();
                return RunReport::failed(Error::internal(format!(
                    "cannot start the watchdog thread: {error}"
                )));
            }
        };

        let clock = &self.clock;
        let execution = catch_unwind(AssertUnwindSafe(|| {
            let LockedInterpreter {
                interpreter,
                environment,
                base_modules,
                cache,
                ..
            } = &mut *locked;
            interpreter.enter(|vm| {
                let program = Program {
                    vm,
                    environment,
                    base_modules,
                    clock,
                    budgets,
                };
                program.execute(host, cache, code)
            })
        }));

        watchdog.stop();
        // Interrupts still queued from now on belong to no run.
        self.current_run.fetch_add(1, Ordering::SeqCst);
        let times = self.clock.end_run();
        let printed = std::mem::take(&mut locked.environment.borrow_mut().printed);

        let outcome = match execution {
            Ok((outcome, garbage)) => {
                locked.garbage = garbage;
                outcome
            }
            Err(payload) => {
                let hard_interrupt = payload.is::<HardInterrupt>();
                let message = panic_message(payload.as_ref());
                self.discard_interpreter();
                if hard_interrupt {
                    // The verdict below names the budget that ran out.
                    Err(Error::internal("hard interrupt without a verdict"))
                } else {
                    Err(Error::internal(format!(
                        "the interpreter panicked: {message}"
                    )))
                }
            }
        };
        let outcome = match (times.stop, times.host_panic) {
            (Some(StopReason::OwnTime), _) => Err(Error::Timeout {
                budget_ms: budgets.own_time_ms,
            }),
            (Some(StopReason::ApiTime), _) => Err(Error::ApiTimeout {
                budget_ms: budgets.api_time_ms,
            }),
            (None, Some(message)) => Err(Error::internal(format!(
                "a host binding panicked: {message}"
            ))),
            (None, None) => outcome,
        };
        let work_counters = catch_unwind(AssertUnwindSafe(|| host.take_work_counters()))
            .unwrap_or_else(|payload| {
                serde_json::json!({ "error": format!(
                    "take_work_counters panicked: {}",
                    panic_message(payload.as_ref())
                ) })
            });
        RunReport {
            outcome,
            own_ms: times.own.as_secs_f64() * 1e3,
            api_ms: times.api.as_secs_f64() * 1e3,
            work_counters,
            printed,
        }
    }

    /// Drops what the last program left behind (its globals and result).
    pub fn collect_garbage(&mut self) {
        let Some(locked) = self.interpreter.as_mut() else {
            return;
        };
        if locked.garbage.is_empty() {
            return;
        }
        let garbage = std::mem::take(&mut locked.garbage);
        let dropped = catch_unwind(AssertUnwindSafe(|| {
            locked.interpreter.enter(move |_vm| drop(garbage));
        }));
        if dropped.is_err() {
            self.discard_interpreter();
        }
    }

    /// Throws the interpreter away after a panic unwound through it. Its destructors may trip
    /// over the state the panic left behind; if they panic too, the rest is leaked.
    fn discard_interpreter(&mut self) {
        if let Some(locked) = self.interpreter.take() {
            let _ = catch_unwind(AssertUnwindSafe(move || drop(locked)));
        }
    }
}

/// The interpreter in `slot`, built first if there is none (counted in `built`).
fn ensure_interpreter<'a>(
    slot: &'a mut Option<LockedInterpreter>,
    built: &mut u64,
) -> Result<&'a mut LockedInterpreter, Error> {
    if let Some(locked) = slot.take() {
        return Ok(slot.insert(locked));
    }
    let locked = LockedInterpreter::build()?;
    *built += 1;
    Ok(slot.insert(locked))
}

impl RunReport {
    /// A report for a program that failed before it ran.
    pub(crate) fn failed(error: Error) -> Self {
        Self {
            outcome: Err(error),
            own_ms: 0.0,
            api_ms: 0.0,
            work_counters: serde_json::Value::Null,
            printed: String::new(),
        }
    }
}

/// One program's run inside the interpreter.
struct Program<'a> {
    vm: &'a VirtualMachine,
    environment: &'a Rc<RefCell<ProgramEnvironment>>,
    base_modules: &'a [(&'static str, PyDictRef)],
    clock: &'a ApiClock,
    budgets: &'a Budgets,
}

impl Program<'_> {
    /// Runs the program; returns its outcome and the objects to drop later.
    fn execute(
        &self,
        host: &mut dyn Host,
        cache: &mut HashMap<String, PyObjectRef>,
        code: CodeObject,
    ) -> (Result<SandboxValue, Error>, Vec<PyObjectRef>) {
        let vm = self.vm;
        let globals = vm.ctx.new_dict();
        let mut garbage = vec![globals.clone().into()];
        let outcome = self
            .prepare(host, cache, &globals)
            .and_then(|()| self.run_program(host, code, &globals, &mut garbage));
        // Host modules of this program must not be importable by the next one.
        self.environment.borrow_mut().modules.clear();
        (outcome, garbage)
    }

    /// Fresh environment and host bindings for the program.
    fn prepare(
        &self,
        host: &mut dyn Host,
        cache: &mut HashMap<String, PyObjectRef>,
        globals: &PyDictRef,
    ) -> Result<(), Error> {
        let vm = self.vm;
        let mut modules = BTreeMap::new();
        let prepared = (|| -> PyResult<()> {
            globals.set_item("__name__", vm.ctx.new_str("__main__").into(), vm)?;
            for (name, attributes) in self.base_modules {
                let module = vm.new_module(name, attributes.copy().into_ref(&vm.ctx), None);
                modules.insert((*name).to_owned(), module.into());
            }
            let mut context = InstallContext {
                vm,
                globals,
                clock: self.clock,
                modules: &mut modules,
                cache,
            };
            host.install(&mut context)
        })();
        if let Err(exception) = prepared {
            let (class_name, message) = describe(vm, &exception);
            return Err(Error::internal(format!(
                "the host failed to install its bindings: {class_name}: {message}"
            )));
        }
        let mut environment = self.environment.borrow_mut();
        environment.modules = modules;
        environment.refused_import = None;
        environment.printed.clear();
        Ok(())
    }

    fn run_program(
        &self,
        host: &dyn Host,
        code: CodeObject,
        globals: &PyDictRef,
        garbage: &mut Vec<PyObjectRef>,
    ) -> Result<SandboxValue, Error> {
        let vm = self.vm;
        // RustPython 0.5 has no `PyCode::new_ref_from_bytecode`; `new_code` panics only on
        // frozenset constants, which `check_code` has already refused.
        let code = vm.ctx.new_code(code);
        let scope = Scope::with_builtins(None, globals.clone(), vm);
        let value = vm
            .run_code_obj(code, scope)
            .and_then(|_| self.result_object(globals))
            .map_err(|exception| self.exception_error(host, &exception))?;
        let Some(value) = value else {
            return Err(Error::NoResult);
        };
        garbage.push(value.clone());
        to_sandbox_value(vm, &value, &self.budgets.result)
    }

    /// `execute_command(video)` if the program defines it, else the global `answer`.
    fn result_object(&self, globals: &PyDictRef) -> PyResult<Option<PyObjectRef>> {
        let vm = self.vm;
        if let Some(execute_command) = globals.get_item_opt("execute_command", vm)? {
            let video = globals
                .get_item_opt("video", vm)?
                .unwrap_or_else(|| vm.ctx.none());
            return execute_command.call((video,), vm).map(Some);
        }
        globals.get_item_opt("answer", vm)
    }

    fn exception_error(&self, host: &dyn Host, exception: &PyBaseExceptionRef) -> Error {
        let vm = self.vm;
        let (class_name, message) = describe(vm, exception);
        let line = exception
            .__traceback__()
            .map(|mut traceback| {
                // The innermost entry is where the exception was raised.
                loop {
                    let next = traceback.next.lock().clone();
                    match next {
                        Some(next) => traceback = next,
                        None => break,
                    }
                }
                traceback.lineno.get()
            })
            .and_then(|line| u32::try_from(line).ok());
        if exception
            .class()
            .fast_issubclass(vm.ctx.exceptions.memory_error)
        {
            return Error::Memory {
                message: format!("{class_name}: {message}"),
            };
        }
        let refused_import = self.environment.borrow().refused_import.clone();
        if let Some(module) = refused_import
            && exception
                .class()
                .fast_issubclass(vm.ctx.exceptions.import_error)
        {
            return Error::forbidden(module, message);
        }
        if let Some(api_error_class) = host.api_error_class()
            && exception_is_a(exception, api_error_class)
        {
            return Error::ApiException {
                class_name,
                message,
                line,
            };
        }
        Error::PythonException {
            class_name,
            message,
            line,
        }
    }
}

/// Class name and `str()` of an exception (`str()` may run program code and fail itself).
fn describe(vm: &VirtualMachine, exception: &PyBaseExceptionRef) -> (String, String) {
    let class_name = exception.class().name().to_string();
    let message = exception.as_object().str(vm).map_or_else(
        |_| "<str() of the exception failed>".to_owned(),
        |message| message.to_string_lossy().into_owned(),
    );
    (class_name, message)
}

/// Keeps hard interrupts (an expected control-flow panic) out of stderr; other panics still go
/// to the previous hook.
fn install_quiet_interrupt_hook() {
    static INSTALLED: std::sync::Once = std::sync::Once::new();
    INSTALLED.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !info.payload().is::<HardInterrupt>() {
                previous(info);
            }
        }));
    });
}
