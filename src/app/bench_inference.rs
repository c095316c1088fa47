//! `bench inference --data DIR`: how well each scenario's properties inferred from the video
//! (what `--dynamics simulate` answers property questions with) match the values the videos were
//! made with, as JSON on stdout. The scenario's part of the scenario table does the scoring
//! (rope: masses from tracked motion, `scene_api::rope`; fluid: density order, viscosity and
//! density ranks from tracked particles, `scene_api::fluid`); `--noise σ,…` perturbs the tracks.

use std::process::ExitCode;

use serde_json::Value;

use super::bench::print_report;
use super::error::{AppError, Classify as _, user_error};
use crate::dataset::DataRoot;
use crate::scenarios;

pub(crate) fn bench_inference(
    data: &std::path::Path,
    noise_levels: &[f64],
) -> Result<ExitCode, AppError> {
    if noise_levels.iter().any(|n| !(n.is_finite() && *n >= 0.0)) {
        return Err(user_error(
            "bench inference: --noise takes non-negative standard deviations (units)",
        ));
    }
    let root = DataRoot::open(data).user()?;
    let mut reports: Vec<Value> = Vec::new();
    for scenario in root.scenarios() {
        let Some(bench) = scenarios::parts(scenario).inference_bench else {
            continue;
        };
        let listing = root.list_videos(scenario).user()?;
        if listing.valid.is_empty() {
            return Err(user_error(format!(
                "`{}` has no valid {scenario} video",
                root.scenario_dir(scenario).display()
            )));
        }
        reports.push(bench(&listing.valid, noise_levels).user()?);
    }
    match reports.len() {
        0 => Err(user_error(format!(
            "`{}` has no folder of a scenario with property inference ({})",
            data.display(),
            scenarios::names_with(|row| row.inference_bench.is_some())
        ))),
        1 => print_report(&reports[0]),
        _ => print_report(&Value::Array(reports)),
    }
}
