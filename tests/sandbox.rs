//! The sandbox pool against the real binary: each resource attack fails its own unit with the
//! right typed error within its budget, and the next unit on the same pool still runs.
//!
//! Workers are this crate's binary started with the hidden worker argument. Budgets are small so
//! the suite stays fast; time assertions are generous upper bounds ("fails within its budget"),
//! never exact timings.

#![expect(
    clippy::unwrap_used,
    clippy::panic,
    reason = "test helpers outside #[test] functions fail the test by panicking"
)]

use std::time::{Duration, Instant};

use contphy_eval::sandbox::{
    Budgets, Error, HostSpec, Pool, PoolConfig, SandboxValue, Unit, UnitResult, WorkerCommand,
};
use serde_json::json;

fn worker() -> WorkerCommand {
    WorkerCommand::new(env!("CARGO_BIN_EXE_contphy-eval"))
}

/// A pool of `jobs` workers capped at 1 GiB of address space each.
fn pool(jobs: usize) -> Pool {
    let mut config = PoolConfig::new(worker(), jobs);
    config.limits.address_space_bytes = 1 << 30;
    Pool::start(config).unwrap()
}

fn budgets() -> Budgets {
    Budgets {
        own_time_ms: 1_000,
        api_time_ms: 5_000,
        cpu_time_ms: 20_000,
        grace_ms: 300,
        ..Budgets::default()
    }
}

fn unit(id: u64, key: &str, source: &str, budgets: Budgets) -> Unit {
    Unit {
        id,
        key: key.to_owned(),
        host: HostSpec::stub(json!({"video": key})),
        source: source.to_owned(),
        budgets,
    }
}

/// A program every healthy worker answers with `"yes"`.
const HEALTHY: &str = "def execute_command(video):\n    return bool_to_yesno(video == 'v')\n";

/// Runs `attack` and then [`HEALTHY`] on a one-worker pool (same key, so the same worker slot);
/// returns both results and the time the attack took.
fn attack_then_healthy(attack: &str, budgets: Budgets) -> (UnitResult, UnitResult, Duration) {
    let pool = pool(1);
    let started = Instant::now();
    pool.submit(unit(1, "v", attack, budgets)).unwrap();
    let attacked = pool.recv().unwrap();
    let elapsed = started.elapsed();
    pool.submit(unit(2, "v", HEALTHY, self::budgets())).unwrap();
    let healthy = pool.recv().unwrap();
    assert_eq!(attacked.unit_id, 1);
    assert_eq!(
        healthy.report.outcome,
        Ok(SandboxValue::Str("yes".into())),
        "the unit after `{attack}` must run normally"
    );
    (attacked, healthy, elapsed)
}

fn kind(result: &UnitResult) -> &'static str {
    match &result.report.outcome {
        Ok(_) => "ok",
        Err(error) => error.kind(),
    }
}

/// Asserts a `memory` failure. RustPython 0.5 sizes these buffers with `Vec::with_capacity`, so
/// under `RLIMIT_AS` the worker aborts ("memory allocation of N bytes failed") rather than
/// raising `MemoryError`; the pool recognises the abort and replaces the worker.
fn assert_memory_error(attacked: &UnitResult) {
    match &attacked.report.outcome {
        Err(Error::Memory { message }) => {
            assert!(
                message.contains("memory allocation of") || message.contains("MemoryError"),
                "{message}"
            );
        }
        other => panic!("expected a memory error, got {other:?}"),
    }
}

#[test]
fn a_huge_string_is_a_memory_error() {
    let (attacked, _, elapsed) = attack_then_healthy("answer = 'a' * 10 ** 10", budgets());
    assert_memory_error(&attacked);
    assert!(elapsed < Duration::from_secs(10), "{elapsed:?}");
}

#[test]
fn a_huge_list_is_a_memory_error() {
    let (attacked, _, elapsed) = attack_then_healthy("answer = [0] * 10 ** 9", budgets());
    assert_memory_error(&attacked);
    assert!(elapsed < Duration::from_secs(10), "{elapsed:?}");
}

#[test]
fn an_uninterruptible_power_is_killed_as_a_timeout() {
    // One bytecode instruction that computes for many seconds: only the parent can stop it.
    let (attacked, healthy, elapsed) = attack_then_healthy("answer = 10 ** 10 ** 8", budgets());
    assert_eq!(
        attacked.report.outcome,
        Err(Error::Timeout { budget_ms: 1_000 }),
        "{attacked:?}"
    );
    // own 1 s + 2 x 0.3 s grace + 0.5 s slack, with room for a loaded machine.
    assert!(elapsed < Duration::from_secs(8), "{elapsed:?}");
    assert_ne!(
        attacked.worker_pid, healthy.worker_pid,
        "the killed worker is replaced"
    );
    assert!(
        attacked.report.own_ms >= 1_000.0,
        "the parent's clock: {attacked:?}"
    );
}

#[test]
fn an_infinite_loop_that_swallows_interrupts_times_out() {
    let source = "while True:\n    try:\n        while True:\n            pass\n    except BaseException:\n        pass\n";
    let (attacked, healthy, elapsed) = attack_then_healthy(source, budgets());
    assert_eq!(
        attacked.report.outcome,
        Err(Error::Timeout { budget_ms: 1_000 }),
        "{attacked:?}"
    );
    assert!(elapsed < Duration::from_secs(8), "{elapsed:?}");
    // The in-process hard interrupt stopped it: the worker itself survived.
    assert_eq!(attacked.worker_pid, healthy.worker_pid);
}

#[test]
fn deep_recursion_is_a_recursion_error() {
    let (attacked, _, _) = attack_then_healthy("def f():\n    f()\nf()\nanswer = 1", budgets());
    assert!(
        matches!(&attacked.report.outcome, Err(Error::PythonException { class_name, .. }) if class_name == "RecursionError"),
        "{attacked:?}"
    );
}

#[test]
fn a_million_deep_nested_list_returned_is_result_too_large() {
    let source = "x = []\nfor i in range(10 ** 6):\n    x = [x]\nanswer = x";
    let budgets = Budgets {
        own_time_ms: 10_000,
        ..budgets()
    };
    let (attacked, _, _) = attack_then_healthy(source, budgets);
    assert_eq!(kind(&attacked), "result_too_large", "{attacked:?}");
}

#[test]
fn a_million_deep_nested_list_not_returned_is_harmless() {
    let source = "x = []\nfor i in range(10 ** 6):\n    x = [x]\nanswer = 1";
    let budgets = Budgets {
        own_time_ms: 10_000,
        ..budgets()
    };
    let (attacked, _, _) = attack_then_healthy(source, budgets);
    assert_eq!(
        attacked.report.outcome,
        Ok(SandboxValue::Int(contphy_eval::sandbox::IntValue::Small(1))),
        "{attacked:?}"
    );
}

#[test]
fn unbounded_nesting_stops_within_its_budget() {
    let (attacked, _, elapsed) =
        attack_then_healthy("x = []\nwhile True:\n    x = [x]\n", budgets());
    // Whichever limit comes first: the own-time budget or the address space.
    assert!(
        matches!(kind(&attacked), "timeout" | "memory"),
        "{attacked:?}"
    );
    assert!(elapsed < Duration::from_secs(15), "{elapsed:?}");
}

#[test]
fn the_cpu_limit_kills_a_spinning_worker() {
    let budgets = Budgets {
        own_time_ms: 30_000,
        cpu_time_ms: 1_000,
        ..budgets()
    };
    let (attacked, _, elapsed) = attack_then_healthy("while True:\n    pass\n", budgets);
    assert_eq!(
        attacked.report.outcome,
        Err(Error::Cpu { budget_ms: 1_000 }),
        "{attacked:?}"
    );
    assert!(elapsed < Duration::from_secs(10), "{elapsed:?}");
}

#[test]
fn a_crashing_worker_fails_only_its_unit_and_is_replaced() {
    let pool = pool(1);
    pool.submit(unit(1, "v", "stub_abort()", budgets()))
        .unwrap();
    pool.submit(unit(2, "v", HEALTHY, budgets())).unwrap();
    let mut results: Vec<UnitResult> = pool.results().collect();
    results.sort_by_key(|result| result.unit_id);
    match &results[0].report.outcome {
        Err(Error::Crashed {
            signal_name,
            signal,
            ..
        }) => {
            assert_eq!(signal_name.as_deref(), Some("SIGABRT"));
            assert_eq!(*signal, Some(libc_sigabrt()));
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        results[1].report.outcome,
        Ok(SandboxValue::Str("yes".into()))
    );
    let stats = pool.stats();
    assert_eq!(stats.workers_lost, 1, "{stats:?}");
    assert_eq!(stats.workers_started, 2, "{stats:?}");
}

fn libc_sigabrt() -> i32 {
    6
}

#[test]
fn api_time_is_not_own_time_in_the_pool() {
    let source =
        "def execute_command(video):\n    return stub_api('slow but fine', delay_ms=2000)\n";
    let pool = pool(1);
    pool.submit(unit(1, "v", source, budgets())).unwrap();
    let result = pool.recv().unwrap();
    assert_eq!(
        result.report.outcome,
        Ok(SandboxValue::Str("slow but fine".into())),
        "{result:?}"
    );
    assert!(result.report.api_ms >= 2_000.0, "{result:?}");
    assert!(result.report.own_ms < 1_000.0, "{result:?}");
    assert_eq!(
        result.report.work_counters,
        json!({"api_calls": 1, "delay_ms": 2000})
    );
}

#[test]
fn a_stuck_api_call_is_killed_as_an_api_timeout() {
    let budgets = Budgets {
        api_time_ms: 500,
        ..budgets()
    };
    let (attacked, _, elapsed) =
        attack_then_healthy("answer = stub_api(1, delay_ms=60000)", budgets);
    assert_eq!(
        attacked.report.outcome,
        Err(Error::ApiTimeout { budget_ms: 500 }),
        "{attacked:?}"
    );
    assert!(elapsed < Duration::from_secs(8), "{elapsed:?}");
}

#[test]
fn the_papers_program_shape_runs_in_the_pool() {
    let source = "def execute_command(video):\n    objects = stub_api(['rope', 'pulley'])\n    return bool_to_yesno(len(objects) == 2)\n";
    let pool = pool(1);
    pool.submit(unit(7, "rope/0", source, budgets())).unwrap();
    let result = pool.recv().unwrap();
    assert_eq!(result.unit_id, 7);
    assert_eq!(result.key, "rope/0");
    assert_eq!(result.report.outcome, Ok(SandboxValue::Str("yes".into())));
    assert!(pool.recv().is_none(), "nothing else is outstanding");
}

#[test]
fn units_of_one_key_run_in_order_on_one_worker_with_one_host() {
    let pool = pool(2);
    let keys = ["a", "b"];
    for id in 0..8_u64 {
        let key = keys[usize::try_from(id % 2).unwrap()];
        pool.submit(unit(id, key, "answer = stub_programs_seen()", budgets()))
            .unwrap();
    }
    let mut results: Vec<UnitResult> = pool.results().collect();
    assert_eq!(results.len(), 8);
    results.sort_by_key(|result| result.unit_id);
    for key in keys {
        let of_key: Vec<&UnitResult> = results.iter().filter(|result| result.key == key).collect();
        let seen: Vec<SandboxValue> = of_key
            .iter()
            .map(|result| result.report.outcome.clone().unwrap())
            .collect();
        let expected: Vec<SandboxValue> = (1..=4)
            .map(|count| SandboxValue::Int(contphy_eval::sandbox::IntValue::Small(count)))
            .collect();
        assert_eq!(
            seen, expected,
            "key {key}: one memoised host, units in order"
        );
        assert!(
            of_key
                .iter()
                .all(|result| result.worker_pid == of_key[0].worker_pid),
            "key {key} stayed on one worker"
        );
    }
    assert_ne!(
        results[0].worker_pid, results[1].worker_pid,
        "two keys spread over two workers"
    );
}

#[test]
fn a_worker_starts_with_its_listed_variables_and_no_others() {
    // A fake worker that answers with its own environment, which the parent reports as an
    // unparsable line: the listed variable is there, one of the parent's (cargo sets it for
    // every test process) is not.
    let script = r#"echo '{"event":"ready","pid":1,"interpreter_build_ms":null}'; read request; echo "kept=$CONTPHY_KEPT parent=$CARGO_MANIFEST_DIR."; exit 3"#;
    let mut config = PoolConfig::new(
        WorkerCommand {
            program: "/bin/sh".into(),
            arguments: vec!["-c".into(), script.into(), "fake-worker".into()],
            environment: vec![("CONTPHY_KEPT".into(), "yes".into())],
        },
        1,
    );
    config.ready_timeout = Duration::from_secs(10);
    assert!(std::env::var_os("CARGO_MANIFEST_DIR").is_some_and(|value| !value.is_empty()));
    let pool = Pool::start(config).unwrap();
    pool.submit(unit(1, "v", HEALTHY, budgets())).unwrap();
    let result = pool.recv().unwrap();
    match &result.report.outcome {
        Err(Error::Internal { message }) => {
            assert!(message.contains("kept=yes parent=."), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn unparsable_worker_output_fails_the_unit_without_a_panic() {
    // A fake worker: says `ready`, then answers the request with garbage (text, then bytes that
    // are not UTF-8) and exits.
    let script = r#"echo '{"event":"ready","pid":1,"interpreter_build_ms":null}'; read request; echo 'this is not json'; printf '\377\376 binary\n'; echo 'fake worker gives up' >&2; exit 3"#;
    let mut config = PoolConfig::new(
        WorkerCommand {
            program: "/bin/sh".into(),
            arguments: vec!["-c".into(), script.into(), "fake-worker".into()],
            environment: Vec::new(),
        },
        1,
    );
    config.ready_timeout = Duration::from_secs(10);
    let pool = Pool::start(config).unwrap();
    pool.submit(unit(1, "v", HEALTHY, budgets())).unwrap();
    let result = pool.recv().unwrap();
    match &result.report.outcome {
        Err(Error::Internal { message }) => {
            assert!(message.contains("this is not json"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // The next unit gets a fresh fake worker, which dies the same way.
    let script = r#"echo '{"event":"ready","pid":1,"interpreter_build_ms":null}'; read request; printf '\377\376 binary'; echo 'fake worker gives up' >&2; exit 3"#;
    let mut config = PoolConfig::new(
        WorkerCommand {
            program: "/bin/sh".into(),
            arguments: vec!["-c".into(), script.into(), "fake-worker".into()],
            environment: Vec::new(),
        },
        1,
    );
    config.ready_timeout = Duration::from_secs(10);
    let pool = Pool::start(config).unwrap();
    pool.submit(unit(1, "v", HEALTHY, budgets())).unwrap();
    let result = pool.recv().unwrap();
    match &result.report.outcome {
        Err(Error::Internal { message }) => {
            assert!(message.contains("binary"), "{message}");
        }
        Err(Error::Crashed { signal, detail, .. }) => {
            // The unterminated binary line arrives only at exit, as the pipe closes.
            assert_eq!(*signal, None);
            assert!(detail.contains("exit status: 3"), "{detail}");
            assert!(detail.contains("fake worker gives up"), "{detail}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn results_at_the_depth_ceiling_cross_the_process_boundary() {
    // 48 levels of lists is the deepest result the protocol carries (two JSON levels each).
    let source = "x = 1
for i in range(47):
    x = [x]
answer = x";
    let budgets = Budgets {
        result: contphy_eval::sandbox::ValueLimits {
            max_depth: 1_000,
            ..contphy_eval::sandbox::ValueLimits::default()
        },
        ..budgets()
    };
    let pool = pool(1);
    pool.submit(unit(1, "v", source, budgets.clone())).unwrap();
    let mut value = pool.recv().unwrap().report.outcome.unwrap();
    let mut depth = 0;
    while let SandboxValue::List(mut items) = value {
        depth += 1;
        value = items.remove(0);
    }
    assert_eq!(depth, 47);
    pool.submit(unit(2, "v", &source.replace("47", "60"), budgets))
        .unwrap();
    assert_eq!(kind(&pool.recv().unwrap()), "result_too_large");
}

#[test]
fn a_missing_worker_binary_is_a_setup_error() {
    let error = Pool::start(PoolConfig::new(
        WorkerCommand::new("/nonexistent/contphy-eval"),
        1,
    ))
    .unwrap_err();
    assert_eq!(error.kind(), "internal");
}
