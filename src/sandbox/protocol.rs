//! The worker protocol: JSON lines between the pool (parent) and a worker process.
//!
//! Parent → worker, on stdin: one [`Request`] per line. Worker → parent, on stdout: one
//! [`WorkerMessage`] per line: `ready` when the worker can take a request (at start and after
//! each unit, once the previous program's memory is released), `api_enter` / `api_exit` while a
//! program waits on the host (the parent pauses its own-time clock in between), and `done` with
//! the unit's [`RunReport`]. Nothing else may write to the worker's stdout; its stderr is free
//! text that the parent keeps the tail of for crash reports.

use serde::{Deserialize, Serialize};

use super::host::HostSpec;
use super::interpreter::RunReport;
use super::limits::Budgets;

/// One program to run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct Request {
    /// The caller's id for the unit, echoed in every message about it.
    pub(crate) unit_id: u64,
    /// The host to bind.
    pub(crate) host: HostSpec,
    /// Python source.
    pub(crate) source: String,
    /// Budgets of this program.
    pub(crate) budgets: Budgets,
}

/// A line the worker writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub(crate) enum WorkerMessage {
    /// The worker is idle and can take a request.
    Ready {
        /// Process id of the worker.
        pid: u32,
        /// Time the last interpreter build took, if one happened since the previous `ready`.
        interpreter_build_ms: Option<f64>,
    },
    /// The program (or the host's construction) entered the host API.
    ApiEnter {
        /// The unit.
        unit_id: u64,
    },
    /// The program left the host API.
    ApiExit {
        /// The unit.
        unit_id: u64,
    },
    /// The unit is finished.
    Done {
        /// The unit.
        unit_id: u64,
        /// What the run produced.
        report: RunReport,
    },
    /// The worker could not read a request line.
    Rejected {
        /// Why.
        message: String,
    },
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sandbox::{Error, SandboxValue};

    #[test]
    fn messages_are_single_json_lines_that_round_trip() {
        let messages = [
            WorkerMessage::Ready {
                pid: 7,
                interpreter_build_ms: Some(9.5),
            },
            WorkerMessage::ApiEnter { unit_id: 1 },
            WorkerMessage::Done {
                unit_id: 1,
                report: RunReport {
                    outcome: Ok(SandboxValue::Str("yes\nno".into())),
                    own_ms: 1.0,
                    api_ms: 0.0,
                    work_counters: serde_json::json!({"api_calls": 1}),
                    printed: "line\n".into(),
                },
            },
            WorkerMessage::Done {
                unit_id: 2,
                report: RunReport {
                    outcome: Err(Error::NoResult),
                    own_ms: 1.0,
                    api_ms: 0.0,
                    work_counters: serde_json::Value::Null,
                    printed: String::new(),
                },
            },
        ];
        for message in messages {
            let line = serde_json::to_string(&message).unwrap();
            assert!(!line.contains('\n'), "{line}");
            let back: WorkerMessage = serde_json::from_str(&line).unwrap();
            assert_eq!(back, message);
        }
    }
}
