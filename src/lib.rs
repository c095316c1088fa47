//! contphy-eval: an evaluator for the ContPhy benchmark (ICML 2024) and its oracle model ContPRO.
//!
//! ```text
//! questions ──► program source (builtin | cache | LLM) ──► program (Python text)
//! program ──► sandbox (RustPython, no stdlib, worker processes with limits)
//!         ──► SoftScene API (Rust) ──► perception | dynamics backends
//!         ──► value ──► answer (per option) ──► score (Opt / Ques) ──► report
//! ```
//!
//! Modules are layered (`docs/architecture.md`, layers) and data flows one way: `util` → `dataset`
//! → `program` → `scene_api` → `sandbox` → `answer` → `score` → `report` → `app` → `cli`. A lower
//! module never names a higher one; `tests/it/architecture.rs` enforces it.

pub mod answer;
pub mod app;
pub mod cli;
pub mod dataset;
pub mod llm;
pub mod perception;
pub mod physics;
pub mod program;
pub mod prompt;
pub mod report;
pub mod sandbox;
pub mod scenarios;
pub mod scene_api;
pub mod score;
pub mod synth;
pub mod util;
