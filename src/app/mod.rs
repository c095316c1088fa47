//! Orchestration: runs the commands, decides stage order and concurrency, turns every unit into
//! an outcome, and owns the run directory. This is the `anyhow` boundary (house rule 1).
//!
//! Input: a [`Request`] built by `cli`. Output: files, text on stdout, and an exit code: 0 when
//! the command finished (per-question failures are data), 1 for user or data errors, 2 for
//! internal errors.

mod bench;
mod bench_confirmation;
mod bench_inference;
mod bench_mpm;
mod bench_physics;
mod bench_reference;
mod bench_view;
mod error;
mod evaluate;
mod exec;
mod generate;
mod llm_source;
mod perception;
mod pipeline;
mod prerequisites;
mod progress;
mod questions;
mod render;
mod run;
mod run_dir;
mod score;
mod settings;
mod source;
mod view;

pub use bench_mpm::BenchMpm88Settings;
pub use bench_view::BenchViewSettings;
pub use error::{AppError, ErrorClass};
pub use perception::{BenchPerceptionSettings, FitColorsSettings, FrameSelection};
pub use settings::{
    BenchLlmSettings, BenchPhysicsSettings, BenchSettings, Budgets, CacheExportSettings,
    CacheImportSettings, CacheSettings, DEFAULT_LLM_JOBS, ExecSettings, FramesSelection,
    GenerateSettings, LlmSettings, ModelOverrides, QuestionsSettings, RenderSettings, Request,
    RunSettings, ScoreSettings, SplitSelection, ViewSettings,
};

use std::io::Write as _;
use std::process::ExitCode;

/// Runs a request; errors are printed to stderr and mapped to the exit code.
pub fn execute(request: Request) -> ExitCode {
    let result = match request {
        Request::Run(settings) => run::run(&settings),
        Request::Exec(settings) => exec::exec(&settings),
        Request::Questions(settings) => questions::questions(&settings),
        Request::Score(settings) => score::score_runs(&settings),
        Request::View(settings) => view::view(&settings),
        Request::CacheList(settings) => score::cache_list(&settings),
        Request::CacheExport(settings) => score::cache_export(&settings),
        Request::CacheImport(settings) => score::cache_import(&settings),
        Request::BenchSandbox(settings) => bench::bench_sandbox(&settings),
        Request::BenchLlm(settings) => bench::bench_llm(&settings),
        Request::BenchPhysics(settings) => bench_physics::bench_physics(&settings),
        Request::BenchView(settings) => bench_view::bench_view(&settings),
        Request::Render(settings) => render::render(&settings),
        Request::BenchInference(data, noise) => bench_inference::bench_inference(&data, &noise),
        Request::Generate(settings) => generate::generate(&settings),
        Request::FitColors(settings) => perception::fit_colors(&settings),
        Request::BenchPerception(settings) => perception::bench_perception(&settings),
        Request::BenchMpm88(settings) => bench_mpm::bench_mpm88(&settings),
    };
    match result {
        Ok(code) => code,
        Err(error) => {
            let mut stderr = std::io::stderr().lock();
            let _ = writeln!(stderr, "error: {:#}", error.error);
            ExitCode::from(match error.class {
                ErrorClass::User => 1,
                ErrorClass::Internal => 2,
            })
        }
    }
}
