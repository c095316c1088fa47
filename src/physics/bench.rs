//! What a simulator brings to `bench physics`: cases with a known answer (a closed form, or none
//! and a run at a much finer step as the reference), each run at a given step and compared on
//! the quantities it reports (metres).
//!
//! Input: nothing (each simulator builds its own cases). Output: [`BenchCase`]s; the sweep over
//! steps, the timing and the report are shared (`app`).

/// Why a benchmark case could not be built or run.
#[derive(Debug, thiserror::Error)]
#[error("benchmark case `{case}`: {message}")]
pub struct BenchError {
    /// The case.
    pub case: &'static str,
    /// What failed.
    pub message: String,
}

/// One case of a simulator's error-against-run-time benchmark.
pub struct BenchCase {
    /// Its name (`atwood_with_pulley_inertia`).
    pub name: &'static str,
    /// The compared quantities at the end of the run by closed form, m; `None` when the case
    /// has none (a run at a step ten times finer than the finest swept is the reference).
    pub exact: Option<Vec<f64>>,
    /// Runs the case for the benchmark's duration at step `dt` (s): the compared quantities, m.
    pub run: Box<dyn Fn(f64) -> Result<Vec<f64>, BenchError>>,
}

impl std::fmt::Debug for BenchCase {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter
            .debug_struct("BenchCase")
            .field("name", &self.name)
            .field("exact", &self.exact)
            .finish_non_exhaustive()
    }
}

/// A simulator's benchmark.
#[derive(Debug, Clone, Copy)]
pub struct PhysicsBench {
    /// Simulated time per run, s.
    pub duration: f64,
    /// The steps swept by default, s.
    pub steps: &'static [f64],
    /// The step `--dynamics simulate` uses, s; the sweep shows its error.
    pub default_dt: f64,
    /// What the error measures, as the report's key (`max_height_error_m`).
    pub error: &'static str,
    /// What the plot's title calls the simulator (`rope simulator`).
    pub title: &'static str,
    /// Builds the cases.
    pub cases: fn() -> Result<Vec<BenchCase>, BenchError>,
}
