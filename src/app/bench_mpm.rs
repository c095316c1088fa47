//! `bench mpm88`: the MPM core on the exact configuration of Taichi's `mpm88.py` example
//! (`physics::mpm::mpm88`), from positions in a `.npy` file, printed as one JSON object with the
//! same fields as `benches/mpm88_taichi.py` prints for Taichi, so the two can be compared side by
//! side (`benches/mpm88.sh`). One untimed substep first warms the caches and the thread pool;
//! the solver is then rebuilt from the file, so the summary is exactly `--steps` substeps.
//! `--material elastic|plastic` runs an elastoplastic solid on the same configuration
//! (`benches/mpm_materials.sh`); its report adds the material, its parameters and how often the
//! return map projected or clamped, and the liquid's report is unchanged.

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use serde_json::json;

use super::bench::print_report;
use super::error::{AppError, Classify as _, user_error};
use crate::physics::mpm::Material;
use crate::physics::mpm::mpm88::{Mpm88, Mpm88Material, summary};

/// Settings of `bench mpm88`.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchMpm88Settings {
    /// The `(N, 2)` float32 or float64 `.npy` positions.
    pub init: std::path::PathBuf,
    /// Substeps timed.
    pub steps: u64,
    /// Worker threads.
    pub threads: usize,
    /// The particles' material (the example's liquid by default).
    pub material: Mpm88Material,
}

pub(crate) fn bench_mpm88(settings: &BenchMpm88Settings) -> Result<ExitCode, AppError> {
    let positions = read_positions(&settings.init)?;
    let Some(config) = Mpm88::for_particles(positions.len()) else {
        return Err(user_error(format!(
            "bench mpm88: {} holds {} particles; the mpm88 configurations have 8192 or 32768",
            settings.init.display(),
            positions.len()
        )));
    };
    let threads = settings.threads.max(1);
    let mut warm = config
        .solver(&positions, settings.material, threads)
        .user()?;
    warm.step(config.time_step).user()?;
    let mut solver = config
        .solver(&positions, settings.material, threads)
        .user()?;
    let started = Instant::now();
    for _ in 0..settings.steps {
        solver.step(config.time_step).user()?;
    }
    let seconds = started.elapsed().as_secs_f64();
    let summary = summary(&solver);
    let particle_steps = positions.len() as f64 * settings.steps as f64;
    let mut report = json!({
        "implementation": "contphy-eval",
        "precision": "f64",
        "particles": positions.len(),
        "steps": settings.steps,
        "threads": threads,
        "mean_x": summary.mean_x,
        "mean_y": summary.mean_y,
        "kinetic_energy": summary.kinetic_energy,
        "mean_J": summary.mean_j,
        "seconds": seconds,
        "particle_steps_per_s": if seconds > 0.0 { particle_steps / seconds } else { 0.0 },
        "clamped": solver.counters().clamped,
    });
    if let (Material::Elastoplastic(solid), Some(fields)) =
        (settings.material.material(), report.as_object_mut())
    {
        let counters = solver.counters();
        fields.insert("material".into(), json!(settings.material.name()));
        fields.insert("youngs_modulus".into(), json!(solid.youngs_modulus));
        fields.insert("poisson_ratio".into(), json!(solid.poisson_ratio));
        // JSON has no infinity: a solid that never yields reports null.
        let yield_stress = Some(solid.yield_stress).filter(|value| value.is_finite());
        fields.insert("yield_stress".into(), json!(yield_stress));
        fields.insert("yielded".into(), json!(counters.yielded));
        fields.insert("stretch_clamped".into(), json!(counters.stretch_clamped));
    }
    print_report(&report)
}

fn read_positions(path: &Path) -> Result<Vec<[f64; 2]>, AppError> {
    let bytes = fs_err::read(path).map_err(|error| user_error(format!("bench mpm88: {error}")))?;
    crate::util::npy::read_points(&bytes)
        .map_err(|error| user_error(format!("bench mpm88: {}: {error}", path.display())))
}
