//! `sandbox::Error`: every way one program can fail, as data the pipeline records per unit.
//!
//! Inputs are failures seen by the interpreter (compile errors, Python exceptions, budgets
//! running out) and by the pool (a worker that died or wrote garbage). The output is one enum
//! whose [`Error::kind`] is a short stable string for reports. The enum is serde-serialisable
//! because it crosses the worker/parent process boundary as a JSON line; for the same reason the
//! underlying causes are carried as text rather than as `#[source]` values.

use serde::{Deserialize, Serialize};

/// Why one program failed. Each variant is a failure of that program only, never of the run.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Error {
    /// The source does not parse or compile.
    #[error("syntax error at line {line}: {message}")]
    Syntax {
        /// The compiler's message.
        message: String,
        /// 1-based line of the error (0 when unknown).
        line: u32,
    },
    /// The program names something the sandbox does not allow (static check or import).
    #[error("forbidden: {message}")]
    Forbidden {
        /// The offending name or module.
        name: String,
        /// What was refused and why.
        message: String,
    },
    /// The program raised a Python exception that is not the host's API error.
    #[error("python exception `{class_name}`: {message}{}", location_suffix(*.line))]
    PythonException {
        /// The exception class, e.g. `ZeroDivisionError`.
        class_name: String,
        /// `str(exception)`.
        message: String,
        /// Line of the program where it was raised (innermost program frame), if known.
        line: Option<u32>,
    },
    /// The program ended with the host's API error class, i.e. it misused the scene API.
    #[error("api exception `{class_name}`: {message}{}", location_suffix(*.line))]
    ApiException {
        /// The host's API error class name (see `Host::api_error_class`).
        class_name: String,
        /// `str(exception)`.
        message: String,
        /// Line of the program where it was raised, if known.
        line: Option<u32>,
    },
    /// The program's own time (wall time outside the host API) ran past its budget.
    #[error("program ran past its own-time budget of {budget_ms} ms")]
    Timeout {
        /// The budget that was exceeded.
        budget_ms: u64,
    },
    /// Time spent inside the host API ran past its budget.
    #[error("host api calls ran past their budget of {budget_ms} ms")]
    ApiTimeout {
        /// The budget that was exceeded.
        budget_ms: u64,
    },
    /// The program ran out of address space (`MemoryError`, or a worker that died allocating).
    #[error("out of memory: {message}")]
    Memory {
        /// What ran out, as far as it is known.
        message: String,
    },
    /// The worker ran past its CPU-time limit (`SIGXCPU`).
    #[error("cpu-time limit of {budget_ms} ms exceeded")]
    Cpu {
        /// The CPU budget of the unit.
        budget_ms: u64,
    },
    /// The worker process died while running the program.
    #[error("worker crashed ({}): {detail}", signal_name.as_deref().unwrap_or("no signal"))]
    Crashed {
        /// The signal that ended the worker, if it died of one.
        signal: Option<i32>,
        /// The signal's name, e.g. `SIGABRT`.
        signal_name: Option<String>,
        /// Exit status and the last line the worker wrote to stderr.
        detail: String,
    },
    /// The program neither defined `execute_command(video)` nor set a global `answer`.
    #[error("program produced no result: define `execute_command(video)` or set `answer`")]
    NoResult,
    /// The result is bigger or deeper than the result limits allow.
    #[error("result too large: {message}")]
    ResultTooLarge {
        /// Which limit was hit.
        message: String,
    },
    /// A bug or an environment failure in the sandbox itself (not the program's fault).
    #[error("internal sandbox error: {message}")]
    Internal {
        /// What went wrong.
        message: String,
    },
}

fn location_suffix(line: Option<u32>) -> String {
    line.map(|line| format!(" (line {line})"))
        .unwrap_or_default()
}

impl Error {
    /// Short stable name of the failure kind, as recorded in predictions and reports.
    pub fn kind(&self) -> &'static str {
        match self {
            Error::Syntax { .. } => "syntax",
            Error::Forbidden { .. } => "forbidden",
            Error::PythonException { .. } => "python_exception",
            Error::ApiException { .. } => "api_exception",
            Error::Timeout { .. } => "timeout",
            Error::ApiTimeout { .. } => "api_timeout",
            Error::Memory { .. } => "memory",
            Error::Cpu { .. } => "cpu",
            Error::Crashed { .. } => "crashed",
            Error::NoResult => "no_result",
            Error::ResultTooLarge { .. } => "result_too_large",
            Error::Internal { .. } => "internal",
        }
    }

    /// Shorthand for an [`Error::Internal`] with `message`.
    pub(crate) fn internal(message: impl Into<String>) -> Self {
        Error::Internal {
            message: message.into(),
        }
    }

    /// Shorthand for an [`Error::Forbidden`] naming `name`.
    pub(crate) fn forbidden(name: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Forbidden {
            name: name.into(),
            message: message.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kind_is_the_serde_tag() {
        let cases = [
            Error::Syntax {
                message: "invalid syntax".into(),
                line: 3,
            },
            Error::forbidden("open", "name `open` is not available"),
            Error::PythonException {
                class_name: "ZeroDivisionError".into(),
                message: "division by zero".into(),
                line: Some(2),
            },
            Error::ApiException {
                class_name: "SceneApiError".into(),
                message: "unknown object".into(),
                line: None,
            },
            Error::Timeout { budget_ms: 5 },
            Error::ApiTimeout { budget_ms: 5 },
            Error::Memory {
                message: "MemoryError".into(),
            },
            Error::Cpu { budget_ms: 1000 },
            Error::Crashed {
                signal: Some(6),
                signal_name: Some("SIGABRT".into()),
                detail: "stack overflow".into(),
            },
            Error::NoResult,
            Error::ResultTooLarge {
                message: "deeper than 100".into(),
            },
            Error::internal("bug"),
        ];
        for error in cases {
            let json = serde_json::to_value(&error).unwrap();
            assert_eq!(json["kind"], error.kind(), "{error}");
            let back: Error = serde_json::from_value(json).unwrap();
            assert_eq!(back, error);
        }
    }

    #[test]
    fn messages_name_the_location() {
        let error = Error::PythonException {
            class_name: "KeyError".into(),
            message: "'x'".into(),
            line: Some(7),
        };
        assert_eq!(
            error.to_string(),
            "python exception `KeyError`: 'x' (line 7)"
        );
    }
}
