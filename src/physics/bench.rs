//! What a simulator brings to `bench physics`: its swept resolution parameters (time step,
//! grid spacing, particles per cell), its cases with a known answer (a closed form, or a run
//! at a fine reference setting), each run at a sweep point and compared on the quantities it
//! reports, grouped by error measure.
//!
//! Input: the videos a simulator's cases are built from, if it needs any (the others build
//! their own scenes). Output: [`BenchCase`]s; the sweep, the timing and the report are shared
//! (`app`).

use std::path::{Path, PathBuf};

/// Why a benchmark case could not be built or run.
#[derive(Debug, thiserror::Error)]
#[error("benchmark case `{case}`: {message}")]
pub struct BenchError {
    /// The case.
    pub case: String,
    /// What failed.
    pub message: String,
}

impl BenchError {
    /// The error of `case`.
    pub fn new(case: &str, message: impl std::fmt::Display) -> BenchError {
        BenchError {
            case: case.to_string(),
            message: message.to_string(),
        }
    }
}

/// A video's name in case names: the last two components of its folder (`fluid_slides/0`).
pub fn video_name(video: &Path) -> String {
    let parts: Vec<String> = video
        .components()
        .rev()
        .take(2)
        .map(|part| part.as_os_str().to_string_lossy().into_owned())
        .collect();
    parts.into_iter().rev().collect::<Vec<_>>().join("/")
}

/// The digest of an input file a case is built from (its [`BenchCase::inputs`]).
///
/// # Errors
/// The file cannot be read.
pub fn input_digest(case: &str, path: &Path) -> Result<String, BenchError> {
    let bytes = fs_err::read(path).map_err(|error| BenchError::new(case, error))?;
    Ok(crate::util::content_hash(&bytes))
}

/// A sweep point: one value per parameter of the benchmark, in the order of
/// [`PhysicsBench::parameters`].
pub type SweepPoint = [f64];

/// What a run reports: per error measure of [`PhysicsBench::errors`], the compared quantities.
pub type Measured = Vec<Vec<f64>>;

/// What one run of a case gives: its compared quantities, and the work it took where the
/// simulator counts it (particle substeps: a cost that, unlike wall time, a loaded machine
/// does not disturb).
#[derive(Debug, Clone, PartialEq)]
pub struct CaseOutput {
    /// Per error measure, the compared quantities.
    pub quantities: Measured,
    /// The simulator's count of its work, if it keeps one.
    pub work: Option<u64>,
}

/// Runs a case at a sweep point.
pub type CaseRun = Box<dyn Fn(&SweepPoint) -> Result<CaseOutput, BenchError>>;

/// One case of a simulator's error-against-run-time benchmark.
pub struct BenchCase {
    /// Its name (`atwood_with_pulley_inertia`, `fluid_slides/0 factual`).
    pub name: String,
    /// The compared quantities by closed form; `None` when the case has none (a run at
    /// [`PhysicsBench::reference`] is the reference).
    pub exact: Option<Measured>,
    /// A digest of what the case is built from outside the code (its video's annotation,
    /// [`input_digest`]); empty when the code alone builds it. With the executable's own
    /// digest, it keys the case's stored reference run (`bench physics --reference-cache`).
    pub inputs: String,
    /// Per error measure, a name for each of its quantities (`touch Red Pillar – Blue Plate`,
    /// `Green Plate supine`), by which the report lists the decided labels a point gets
    /// otherwise than the reference; empty where the quantities are unnamed.
    pub label_names: Vec<Vec<String>>,
    /// Runs the case at a sweep point: the compared quantities.
    pub run: CaseRun,
}

impl std::fmt::Debug for BenchCase {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter
            .debug_struct("BenchCase")
            .field("name", &self.name)
            .field("exact", &self.exact)
            .field("inputs", &self.inputs)
            .finish_non_exhaustive()
    }
}

/// A swept parameter.
#[derive(Debug, Clone, Copy)]
pub struct Parameter {
    /// Its key in the report (`dt_s`, `grid_spacing`).
    pub key: &'static str,
    /// The `bench physics` option that sets its values (`--dt`).
    pub flag: &'static str,
    /// Its short name in the plot's point labels (`dt`, `dx`).
    pub label: &'static str,
    /// Whether the reference and the default take this parameter's value from the sweep
    /// instead of their own: an ensemble's size, which errors are comparable only at (a share
    /// of fifteen runs against one of five means nothing). The sweep then holds one value of it.
    pub follows_sweep: bool,
}

/// The setting cases without a closed form are compared against.
#[derive(Debug, Clone, Copy)]
pub enum Reference {
    /// The first parameter at a tenth of the smallest value swept, the others at their
    /// default (time steps: the error of a first-order method then falls tenfold).
    TenfoldFiner,
    /// This point, finer than any swept.
    Point(&'static [f64]),
}

/// How a measure's differences from the reference make one error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reduction {
    /// The largest absolute difference.
    Largest,
    /// The mean absolute difference (of 0/1 labels: the share that differ).
    Mean,
    /// The share of quantities unequal to the reference's: categories coded as numbers (a box's
    /// end pose), where how far apart two codes are means nothing.
    Mismatch,
    /// The mean absolute difference over the quantities the reference holds at exactly 0 or 1:
    /// of labels that are shares of an ensemble's runs, those every run of the reference's
    /// ensemble agrees on (none: 0).
    DecidedMean,
    /// Of categories as shares of an ensemble's runs, in groups of this many (one share per
    /// category: a box's end pose), the groups whose reference puts every run in one category
    /// (decided): the mean share of runs in another category (half the group's summed absolute
    /// difference; none decided: 0).
    DecidedCategories(usize),
}

impl Reduction {
    /// Whether the reduction is taken over the labels the reference decides (its ensemble's
    /// runs agree), so that its errors pool over those labels (categories in groups of none
    /// decide nothing).
    pub fn is_decided(self) -> bool {
        match self {
            Reduction::DecidedMean => true,
            Reduction::DecidedCategories(size) => size > 0,
            Reduction::Largest | Reduction::Mean | Reduction::Mismatch => false,
        }
    }
}

/// One error measure of a benchmark.
#[derive(Debug, Clone, Copy)]
pub struct ErrorMeasure {
    /// Its key in the report (`max_height_error_m`).
    pub key: &'static str,
    /// How its quantities' differences reduce to one error.
    pub reduction: Reduction,
    /// The error the default point should stay within, if the simulator states one.
    pub tolerance: Option<f64>,
    /// Whether the plot shows it.
    pub plotted: bool,
}

/// A simulator's benchmark.
#[derive(Debug, Clone, Copy)]
pub struct PhysicsBench {
    /// Simulated time per run, s.
    pub duration: f64,
    /// The swept parameters.
    pub parameters: &'static [Parameter],
    /// The points swept by default.
    pub sweep: &'static [&'static [f64]],
    /// The point `--dynamics simulate` uses; the sweep shows its error.
    pub default: &'static [f64],
    /// What cases without a closed form are compared against.
    pub reference: Reference,
    /// A point finer than the reference that confirms its decided labels (`--confirm`): a
    /// label the reference's ensemble decides counts only when every run of this point's
    /// ensemble repeats it. A label a finer setting changes is not converged at the reference,
    /// so no coarser point can be expected to repeat it. `None`: the simulator has no decided
    /// measures to confirm.
    pub confirmation: Option<&'static [f64]>,
    /// The error measures, in the order of the quantities a run reports.
    pub errors: &'static [ErrorMeasure],
    /// The plot's error axis (`largest error, m`): the largest error of the measures
    /// [`ErrorMeasure::plotted`].
    pub error_axis: &'static str,
    /// Timed runs per point; the best is reported (runs are deterministic, so every repeat
    /// gives the same quantities).
    pub repeats: usize,
    /// What the plot's title calls the simulator (`rope simulator`).
    pub title: &'static str,
    /// Whether the cases are built from videos (`--video`), else from nothing.
    pub uses_videos: bool,
    /// Builds the cases, from `videos` when [`PhysicsBench::uses_videos`].
    pub cases: fn(&[PathBuf]) -> Result<Vec<BenchCase>, BenchError>,
}

impl PhysicsBench {
    /// `point` with the parameters that follow the sweep ([`Parameter::follows_sweep`]) at the
    /// value of `sweep`'s first point.
    pub fn following(&self, point: &[f64], sweep: &[Vec<f64>]) -> Vec<f64> {
        let mut point = point.to_vec();
        for (index, parameter) in self.parameters.iter().enumerate() {
            let swept = sweep.first().and_then(|first| first.get(index));
            if let (true, Some(value), Some(slot)) =
                (parameter.follows_sweep, swept, point.get_mut(index))
            {
                *slot = *value;
            }
        }
        point
    }

    /// The default point for `sweep`.
    pub fn default_point(&self, sweep: &[Vec<f64>]) -> Vec<f64> {
        self.following(self.default, sweep)
    }

    /// The confirmation point for `sweep` ([`PhysicsBench::confirmation`]).
    pub fn confirmation_point(&self, sweep: &[Vec<f64>]) -> Option<Vec<f64>> {
        self.confirmation.map(|point| self.following(point, sweep))
    }

    /// The reference point for `sweep`.
    pub fn reference_point(&self, sweep: &[Vec<f64>]) -> Vec<f64> {
        let point = match self.reference {
            Reference::Point(point) => point.to_vec(),
            Reference::TenfoldFiner => {
                let finest = sweep
                    .iter()
                    .filter_map(|point| point.first().copied())
                    .fold(f64::INFINITY, f64::min);
                let mut point = self.default.to_vec();
                if let Some(first) = point.first_mut() {
                    *first = finest / 10.0;
                }
                point
            }
        };
        self.following(&point, sweep)
    }
}
