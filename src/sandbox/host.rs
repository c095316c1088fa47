//! The host seam: what a program may call besides Python's builtins and `math`.
//!
//! A [`Host`] binds names (the scene API, `video`, `bool_to_yesno`, ...) into each program's
//! fresh globals and may register importable modules. Requests name their host with a
//! [`HostSpec`] (a name plus a JSON config); the worker builds hosts through a [`HostRegistry`]
//! that memoises one host per spec, so repeated units on one video reuse its loaded state.
//!
//! The real scene-API host lives outside this module and is registered in the binary's worker
//! entry point with [`HostRegistry::register`]. This module ships one real host of its own,
//! [`StubHost`] (name `"stub"`), for tests and the sandbox benchmark.

use std::cell::Cell;
use std::collections::{BTreeMap, HashMap};
use std::rc::Rc;
use std::time::Duration;

use rustpython_vm::builtins::PyDictRef;
use rustpython_vm::function::FuncArgs;
use rustpython_vm::{PyObjectRef, PyPayload, PyResult, VirtualMachine};
use serde::{Deserialize, Serialize};

use super::clock::ApiClock;
use super::error::Error;

/// Which host a unit runs against: a registered name and that host's JSON config (for the scene
/// API: the video, the backends). Equal specs share one memoised host inside a worker.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HostSpec {
    /// Name the host was registered under, e.g. `"stub"`.
    pub name: String,
    /// Host-specific configuration.
    #[serde(default)]
    pub config: serde_json::Value,
}

impl HostSpec {
    /// The stub host with `config` (see [`StubHost`]).
    pub fn stub(config: serde_json::Value) -> Self {
        Self {
            name: StubHost::NAME.to_owned(),
            config,
        }
    }

    /// Canonical text of the spec, the memoisation key.
    fn memo_key(&self) -> String {
        format!(
            "{}\u{0}{}",
            self.name,
            crate::util::canonical_json(&self.config)
        )
    }
}

/// Binds an API into programs. Implemented by the scene API (later) and by [`StubHost`].
///
/// One host value serves many programs in a row (the registry memoises it per spec), on the
/// worker's interpreter thread. Every Python-callable it installs must time itself through the
/// context's [`ApiClock`] ([`ApiClock::function`] or [`ApiClock::call`]): that is what keeps
/// API time out of the program's own-time budget and turns a panic in a binding into a failure
/// of that program only.
pub trait Host {
    /// Binds this host's names into a fresh program's globals (and registers its importable
    /// modules). Called once per program, before the program runs.
    fn install(&mut self, context: &mut InstallContext<'_>) -> PyResult<()>;

    /// Work done since the previous call (frames decoded, simulations run, ...), reported with
    /// the unit that just ran. Taking resets the counters, so a memoised host reports each
    /// unit's own work.
    fn take_work_counters(&mut self) -> serde_json::Value {
        serde_json::Value::Null
    }

    /// Name of the exception class this host raises on API misuse (e.g. an unknown object
    /// name). A program that ends with it (or a subclass) fails as `api_exception` rather than
    /// `python_exception`.
    fn api_error_class(&self) -> Option<&str> {
        None
    }
}

/// What [`Host::install`] gets to work with for one program.
pub struct InstallContext<'a> {
    /// The interpreter.
    pub vm: &'a VirtualMachine,
    /// The program's globals (fresh for every program).
    pub globals: &'a PyDictRef,
    /// The clock every binding must go through.
    pub clock: &'a ApiClock,
    pub(crate) modules: &'a mut BTreeMap<String, PyObjectRef>,
    pub(crate) cache: &'a mut HashMap<String, PyObjectRef>,
}

impl InstallContext<'_> {
    /// Sets the global `name` of the program to `value`.
    pub fn set_global(&self, name: &str, value: PyObjectRef) -> PyResult<()> {
        self.globals.set_item(name, value, self.vm)
    }

    /// Makes `import name` / `from name import ...` return a module with the attributes in
    /// `attributes` (a fresh module object for this program, so changes to it do not leak).
    pub fn add_module(&mut self, name: &str, attributes: &PyDictRef) -> PyResult<()> {
        let dict = attributes.copy();
        let module = self.vm.new_module(name, dict.into_ref(&self.vm.ctx), None);
        self.modules.insert(name.to_owned(), module.into());
        Ok(())
    }

    /// The object cached under `key` in this interpreter, built by `build` on first use.
    ///
    /// Use it for objects that should be created once per interpreter rather than once per
    /// program: exception classes, native functions (whose definitions RustPython never frees).
    /// The cache is dropped with the interpreter, so keys never see objects of another one.
    pub fn cached(
        &mut self,
        key: &str,
        build: impl FnOnce(&VirtualMachine) -> PyResult<PyObjectRef>,
    ) -> PyResult<PyObjectRef> {
        if let Some(object) = self.cache.get(key) {
            return Ok(object.clone());
        }
        let object = build(self.vm)?;
        self.cache.insert(key.to_owned(), object.clone());
        Ok(object)
    }
}

/// Why a host could not be built from its JSON config (the message names the field).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct HostConfigError(pub String);

/// Builds a host from its JSON config, or says why it cannot.
pub type HostConstructor =
    Box<dyn Fn(&serde_json::Value) -> Result<Box<dyn Host>, HostConfigError>>;

/// The worker's host factory: named constructors plus a small memo of built hosts.
pub struct HostRegistry {
    constructors: BTreeMap<String, HostConstructor>,
    /// Built hosts, least recently used first.
    memo: Vec<(String, Box<dyn Host>)>,
    memo_capacity: usize,
}

impl std::fmt::Debug for HostRegistry {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter
            .debug_struct("HostRegistry")
            .field("hosts", &self.constructors.keys().collect::<Vec<_>>())
            .field("memoised", &self.memo.len())
            .field("memo_capacity", &self.memo_capacity)
            .finish_non_exhaustive()
    }
}

impl Default for HostRegistry {
    fn default() -> Self {
        Self::with_builtin_hosts()
    }
}

impl HostRegistry {
    /// How many built hosts a worker keeps: units are routed to workers by video, so a worker
    /// sees one video's units in a row and a few cached hosts cover interleaving.
    pub const DEFAULT_MEMO_CAPACITY: usize = 4;

    /// A registry with no hosts.
    pub fn empty() -> Self {
        Self {
            constructors: BTreeMap::new(),
            memo: Vec::new(),
            memo_capacity: Self::DEFAULT_MEMO_CAPACITY,
        }
    }

    /// A registry with the hosts this module provides (`"stub"`).
    pub fn with_builtin_hosts() -> Self {
        let mut registry = Self::empty();
        registry.register(StubHost::NAME, |config| {
            StubHost::from_config(config).map(|host| Box::new(host) as Box<dyn Host>)
        });
        registry
    }

    /// Registers (or replaces) the constructor for host `name`.
    pub fn register(
        &mut self,
        name: impl Into<String>,
        constructor: impl Fn(&serde_json::Value) -> Result<Box<dyn Host>, HostConfigError> + 'static,
    ) -> &mut Self {
        self.constructors.insert(name.into(), Box::new(constructor));
        self
    }

    /// Sets how many built hosts are kept (at least one).
    pub fn set_memo_capacity(&mut self, capacity: usize) -> &mut Self {
        self.memo_capacity = capacity.max(1);
        self
    }

    /// The host for `spec`: the memoised one if this spec was seen recently, else a new one.
    pub fn host(&mut self, spec: &HostSpec) -> Result<&mut dyn Host, Error> {
        let key = spec.memo_key();
        if let Some(position) = self.memo.iter().position(|(memo_key, _)| *memo_key == key) {
            let entry = self.memo.remove(position);
            self.memo.push(entry);
        } else {
            let constructor = self.constructors.get(&spec.name).ok_or_else(|| {
                Error::internal(format!(
                    "no host named `{}` is registered in the worker (known: {})",
                    spec.name,
                    self.constructors
                        .keys()
                        .map(String::as_str)
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            })?;
            // A panicking constructor is a host bug; it fails this unit, not the worker.
            let built = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                constructor(&spec.config)
            }))
            .unwrap_or_else(|payload| {
                Err(HostConfigError(format!(
                    "the constructor panicked: {}",
                    super::clock::panic_message(payload.as_ref())
                )))
            });
            let host = built.map_err(|message| {
                Error::internal(format!("cannot build host `{}`: {message}", spec.name))
            })?;
            if self.memo.len() >= self.memo_capacity {
                self.memo.remove(0);
            }
            self.memo.push((key, host));
        }
        let (_, host) = self
            .memo
            .last_mut()
            .expect("the memo holds the host just found or inserted");
        Ok(host.as_mut())
    }
}

/// The built-in test host (`"stub"`).
///
/// Binds:
/// * `video`: the config's `"video"` string (or `None`);
/// * `bool_to_yesno(b)`: `"yes"` if `b` is true, else `"no"`;
/// * `stub_api(value, delay_ms=0)`: spends `delay_ms` inside the API (sleeping), then returns
///   `value`; raises `StubApiError` (the host's API error class) for a negative delay;
/// * `stub_panic()`: panics inside the binding (to test that a binding bug fails one program);
/// * `stub_abort()`: aborts the worker process (to test that a crash fails one unit);
/// * `stub_programs_seen()`: how many programs this host value has been installed for (to test
///   that a worker reuses its memoised host);
/// * module `stub` with the same functions, for `import stub`.
///
/// Work counters: `{"api_calls": n, "delay_ms": total}` per unit.
#[derive(Debug, Default)]
pub struct StubHost {
    video: Option<String>,
    counters: Rc<StubCounters>,
    programs_seen: Rc<Cell<u64>>,
}

#[derive(Debug, Default)]
struct StubCounters {
    api_calls: Cell<u64>,
    delay_ms: Cell<u64>,
}

impl StubHost {
    /// The name the stub host is registered under.
    pub const NAME: &'static str = "stub";
    /// The stub host's API error class.
    pub const API_ERROR_CLASS: &'static str = "StubApiError";

    /// Builds a stub host from `{"video": "..."}` (all fields optional).
    pub fn from_config(config: &serde_json::Value) -> Result<Self, HostConfigError> {
        let video = match config.get("video") {
            None | Some(serde_json::Value::Null) => None,
            Some(serde_json::Value::String(video)) => Some(video.clone()),
            Some(other) => {
                return Err(HostConfigError(format!(
                    "`video` must be a string, found {other}"
                )));
            }
        };
        Ok(Self {
            video,
            ..Self::default()
        })
    }
}

impl Host for StubHost {
    fn install(&mut self, context: &mut InstallContext<'_>) -> PyResult<()> {
        let api_error = context.cached("stub/StubApiError", |vm| {
            Ok(vm
                .ctx
                .new_exception_type("stub", Self::API_ERROR_CLASS, None)
                .into())
        })?;
        let vm = context.vm;
        let video = self.video.as_ref().map_or_else(
            || vm.ctx.none(),
            |video| vm.ctx.new_str(video.as_str()).into(),
        );
        context.set_global("video", video)?;

        let counters = Rc::clone(&self.counters);
        let bool_to_yesno = context
            .clock
            .function(vm, "bool_to_yesno", move |arguments, vm| {
                counters.api_calls.set(counters.api_calls.get() + 1);
                let (value,): (PyObjectRef,) = arguments.bind(vm)?;
                let answer = if value.is_true(vm)? { "yes" } else { "no" };
                Ok(vm.ctx.new_str(answer).into())
            });

        let counters = Rc::clone(&self.counters);
        let error_class = api_error.clone();
        let stub_api = context
            .clock
            .function(vm, "stub_api", move |arguments, vm| {
                counters.api_calls.set(counters.api_calls.get() + 1);
                stub_api(&counters, &error_class, arguments, vm)
            });

        let stub_panic = context.clock.function(vm, "stub_panic", |_arguments, _vm| {
            #[expect(
                clippy::panic,
                reason = "the stub exists to test that binding panics are contained"
            )]
            {
                panic!("stub_panic called")
            }
        });

        let stub_abort = context
            .clock
            .function(vm, "stub_abort", |_arguments, _vm| std::process::abort());

        self.programs_seen.set(self.programs_seen.get() + 1);
        let programs_seen = Rc::clone(&self.programs_seen);
        let stub_programs_seen =
            context
                .clock
                .function(vm, "stub_programs_seen", move |_arguments, vm| {
                    Ok(vm.ctx.new_int(programs_seen.get()).into())
                });

        let module = vm.ctx.new_dict();
        for (name, object) in [
            ("bool_to_yesno", bool_to_yesno),
            ("stub_api", stub_api),
            ("stub_panic", stub_panic),
            ("stub_abort", stub_abort),
            ("stub_programs_seen", stub_programs_seen),
            (Self::API_ERROR_CLASS, api_error),
        ] {
            context.set_global(name, object.clone())?;
            module.set_item(name, object, vm)?;
        }
        context.add_module("stub", &module)
    }

    fn take_work_counters(&mut self) -> serde_json::Value {
        let counters = serde_json::json!({
            "api_calls": self.counters.api_calls.take(),
            "delay_ms": self.counters.delay_ms.take(),
        });
        counters
    }

    fn api_error_class(&self) -> Option<&str> {
        Some(Self::API_ERROR_CLASS)
    }
}

/// `stub_api(value, delay_ms=0)`.
fn stub_api(
    counters: &StubCounters,
    error_class: &PyObjectRef,
    mut arguments: FuncArgs,
    vm: &VirtualMachine,
) -> PyResult {
    let delay_keyword = arguments.take_keyword("delay_ms");
    let (value, delay): (PyObjectRef, rustpython_vm::function::OptionalArg<i64>) =
        arguments.bind(vm)?;
    let delay_ms = match (delay, delay_keyword) {
        (rustpython_vm::function::OptionalArg::Present(delay), None) => delay,
        (rustpython_vm::function::OptionalArg::Missing, Some(delay)) => delay.try_into_value(vm)?,
        (rustpython_vm::function::OptionalArg::Missing, None) => 0,
        (rustpython_vm::function::OptionalArg::Present(_), Some(_)) => {
            return Err(vm.new_type_error("stub_api() got multiple values for `delay_ms`"));
        }
    };
    let Ok(delay_ms) = u64::try_from(delay_ms) else {
        let class = error_class
            .clone()
            .downcast()
            .map_err(|_| vm.new_type_error("StubApiError is not a class"))?;
        return Err(vm.new_exception_msg(
            class,
            format!("delay_ms must be >= 0, got {delay_ms}").into(),
        ));
    };
    std::thread::sleep(Duration::from_millis(delay_ms));
    counters.delay_ms.set(counters.delay_ms.get() + delay_ms);
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registry_memoises_one_host_per_spec() {
        let built = Rc::new(Cell::new(0));
        let mut registry = HostRegistry::empty();
        let counter = Rc::clone(&built);
        registry.register("counting", move |_config| {
            counter.set(counter.get() + 1);
            Ok(Box::new(StubHost::default()) as Box<dyn Host>)
        });
        registry.set_memo_capacity(2);
        let spec = |video: &str| HostSpec {
            name: "counting".into(),
            config: serde_json::json!({"video": video, "mode": "offline"}),
        };
        registry.host(&spec("a")).unwrap();
        registry.host(&spec("a")).unwrap();
        assert_eq!(built.get(), 1, "same spec, one build");
        registry.host(&spec("b")).unwrap();
        registry.host(&spec("c")).unwrap();
        assert_eq!(built.get(), 3);
        registry.host(&spec("a")).unwrap();
        assert_eq!(built.get(), 4, "`a` was evicted by capacity 2");
    }

    #[test]
    fn unknown_hosts_and_bad_configs_are_errors_not_panics() {
        let mut registry = HostRegistry::with_builtin_hosts();
        let unknown = registry
            .host(&HostSpec {
                name: "scene".into(),
                config: serde_json::Value::Null,
            })
            .map(|_| ())
            .unwrap_err();
        assert!(unknown.to_string().contains("`scene`"), "{unknown}");
        let bad = registry
            .host(&HostSpec::stub(serde_json::json!({"video": 3})))
            .map(|_| ())
            .unwrap_err();
        assert_eq!(bad.kind(), "internal");
        registry.register("panicking", |_config| panic!("constructor bug"));
        let panicked = registry
            .host(&HostSpec {
                name: "panicking".into(),
                config: serde_json::Value::Null,
            })
            .map(|_| ())
            .unwrap_err();
        assert!(
            panicked.to_string().contains("constructor bug"),
            "{panicked}"
        );
    }
}
