//! Budgets: how much time, CPU, memory and result size one program (or one worker) may use.
//!
//! Inputs are the run's settings (or the defaults below); outputs are plain numbers read by the
//! watchdog ([`crate::sandbox`]'s interpreter), the worker (rlimits) and the pool (wall-clock
//! kill). Times are in milliseconds so the structs serialise to readable JSON.
//!
//! | budget | default | enforced by |
//! |---|---|---|
//! | own time (wall time outside the host API) | 5 s | in-process watchdog: soft interrupt, then after `grace_ms` a hard one; the parent kills the worker at own time > budget + 2 × grace |
//! | API time (wall time inside host calls) | 120 s | checked when a call returns; the parent kills a worker stuck inside one call past budget + grace |
//! | CPU time (whole worker process) | 180 s | `RLIMIT_CPU` soft limit = used + budget, per request (`SIGXCPU`) |
//! | address space (per worker) | 2 GiB | `RLIMIT_AS`, set once at worker start: allocation bombs become `MemoryError` |
//! | result size | depth 32 (48 at most), 100 000 nodes, 1 MiB of text | conversion to [`crate::sandbox::SandboxValue`] |

use serde::{Deserialize, Serialize};

/// Per-program budgets, sent with every request.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct Budgets {
    /// Wall time the program may spend outside host API calls (default 5 000 ms: the paper's
    /// programs are a few lines and finish in milliseconds; this leaves room for slow loops).
    pub own_time_ms: u64,
    /// Wall time the program may spend inside host API calls (default 120 000 ms: a cold
    /// simulation or detection pass on one video can take tens of seconds).
    pub api_time_ms: u64,
    /// CPU time of the worker process for this request, all threads (default 180 000 ms: own
    /// time plus API time plus slack for the interpreter's own threads).
    pub cpu_time_ms: u64,
    /// Time between the soft interrupt (a catchable `KeyboardInterrupt`) and the hard one that
    /// discards the interpreter (default 1 000 ms). The parent's kill waits two of these.
    pub grace_ms: u64,
    /// Limits on the size of the program's result.
    pub result: ValueLimits,
}

impl Default for Budgets {
    fn default() -> Self {
        Self {
            own_time_ms: 5_000,
            api_time_ms: 120_000,
            cpu_time_ms: 180_000,
            grace_ms: 1_000,
            result: ValueLimits::default(),
        }
    }
}

/// Limits on converting a Python result into a [`crate::sandbox::SandboxValue`], so that a huge
/// or deeply nested result cannot blow up the worker, the JSON line or the report.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct ValueLimits {
    /// Deepest nesting of lists, tuples and dicts (default 32; answers are flat in practice).
    /// Values above 48 act as 48: each level is two levels of JSON on the worker protocol, whose
    /// parser stops at 128.
    pub max_depth: usize,
    /// Total number of values in the result, containers included (default 100 000).
    pub max_nodes: usize,
    /// Total bytes of text (strings, dict keys, reprs) in the result (default 1 MiB).
    pub max_text_bytes: usize,
    /// Longest `repr` kept for an object that has no structural conversion (default 200 chars).
    pub max_repr_chars: usize,
    /// Most decimal digits of an integer (default 4 300, Python's own `int_max_str_digits`).
    pub max_int_digits: usize,
}

impl Default for ValueLimits {
    fn default() -> Self {
        Self {
            max_depth: 32,
            max_nodes: 100_000,
            max_text_bytes: 1 << 20,
            max_repr_chars: 200,
            max_int_digits: 4_300,
        }
    }
}

/// Limits of a worker process, fixed when it starts (they cannot be raised again later).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct WorkerLimits {
    /// `RLIMIT_AS` of the worker (default 2 GiB; the largest honest scene-API workload, a fluid
    /// simulation, stays well below).
    pub address_space_bytes: u64,
    /// Stack of the interpreter thread (default 256 MiB of address space, touched only as
    /// needed: RustPython recurses in Rust for nested values and deep Python calls, and the
    /// probe saw stack-overflow aborts on small stacks).
    pub interpreter_stack_bytes: usize,
}

impl Default for WorkerLimits {
    fn default() -> Self {
        Self {
            address_space_bytes: 2 << 30,
            interpreter_stack_bytes: 256 << 20,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_fields_take_defaults() {
        let budgets: Budgets = serde_json::from_str(r#"{"own_time_ms": 250}"#).unwrap();
        assert_eq!(budgets.own_time_ms, 250);
        assert_eq!(budgets.api_time_ms, Budgets::default().api_time_ms);
        assert_eq!(budgets.result, ValueLimits::default());
    }
}
