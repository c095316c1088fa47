//! Sandbox measurements for `contphy-eval bench sandbox`: interpreter start-up, per-program time
//! in-process, and the pool's cost per unit.
//!
//! Input is a [`BenchConfig`]; output is a serde-serialisable [`BenchReport`]. Nothing here is a
//! pass/fail test: it reports times so that budget defaults and `--jobs` can be chosen from
//! numbers. Run it from a release build; debug builds are several times slower.

use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use super::error::Error;
use super::host::{HostSpec, StubHost};
use super::interpreter::Sandbox;
use super::limits::{Budgets, WorkerLimits};
use super::pool::{Pool, PoolConfig, PoolStats, Unit, WorkerCommand};

/// The small programs timed in-process, by name.
const PROGRAMS: &[(&str, &str)] = &[
    ("trivial", "answer = 1"),
    (
        "paper_shape",
        "def execute_command(video):\n    found = stub_api(['first', 'second'])\n    return bool_to_yesno(len(found) == 2)\n",
    ),
    (
        "loop_10k",
        "total = 0\nfor index in range(10000):\n    total += index * index\nanswer = total",
    ),
    (
        "api_calls_1000",
        "total = 0\nfor index in range(1000):\n    total += stub_api(index)\nanswer = total",
    ),
    (
        "classes_and_comprehensions",
        "import math\n\nclass Body:\n    def __init__(self, name, mass):\n        self.name = name\n        self.mass = mass\n    def __repr__(self):\n        return f'Body({self.name}, {self.mass})'\n\nbodies = [Body(f'cube{i}', math.sqrt(i + 1)) for i in range(100)]\nheavy = sorted((b for b in bodies if b.mass > 5), key=lambda b: -b.mass)\nanswer = {'heaviest': repr(heavy[0]), 'count': len(heavy)}\n",
    ),
];

/// What to measure.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BenchConfig {
    /// Fresh interpreters built to time start-up.
    pub interpreter_builds: usize,
    /// Runs of each small program on one reused interpreter.
    pub program_runs: usize,
    /// Worker command for the pool measurement; `None` skips it.
    pub worker: Option<WorkerCommand>,
    /// Workers in the measured pool.
    pub jobs: usize,
    /// Trivial units pushed through the pool.
    pub pool_units: usize,
    /// Distinct keys (videos) the pool units are spread over.
    pub pool_keys: usize,
    /// One-worker pools started (and sent one trivial unit) to time a worker's start.
    pub worker_starts: usize,
    /// Units of 1 000 host API calls each, to time the API event lines through the pool.
    pub api_heavy_units: usize,
}

impl Default for BenchConfig {
    fn default() -> Self {
        Self {
            interpreter_builds: 10,
            program_runs: 200,
            worker: None,
            jobs: 2,
            pool_units: 2000,
            pool_keys: 20,
            worker_starts: 5,
            api_heavy_units: 20,
        }
    }
}

/// Order statistics of a set of durations, in milliseconds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TimeSummary {
    /// Number of samples.
    pub samples: usize,
    /// Fastest.
    pub min_ms: f64,
    /// Median.
    pub median_ms: f64,
    /// Mean.
    pub mean_ms: f64,
    /// 95th percentile.
    pub p95_ms: f64,
    /// Slowest.
    pub max_ms: f64,
}

impl TimeSummary {
    /// The order statistics of `durations`.
    pub fn of(durations: &[Duration]) -> Self {
        let mut milliseconds: Vec<f64> = durations
            .iter()
            .map(|duration| duration.as_secs_f64() * 1e3)
            .collect();
        milliseconds.sort_by(f64::total_cmp);
        let at = |fraction: f64| -> f64 {
            if milliseconds.is_empty() {
                return 0.0;
            }
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "an index into a non-empty vector, rounded from a fraction in [0, 1]"
            )]
            let index = ((milliseconds.len() - 1) as f64 * fraction).round() as usize;
            milliseconds[index.min(milliseconds.len() - 1)]
        };
        Self {
            samples: milliseconds.len(),
            min_ms: at(0.0),
            median_ms: at(0.5),
            mean_ms: if milliseconds.is_empty() {
                0.0
            } else {
                milliseconds.iter().sum::<f64>() / milliseconds.len() as f64
            },
            p95_ms: at(0.95),
            max_ms: at(1.0),
        }
    }
}

/// Time of one small program, run repeatedly in one interpreter (compile, name check, host
/// install, run and result conversion included).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProgramTiming {
    /// Name of the program.
    pub name: String,
    /// Its times.
    pub time: TimeSummary,
}

/// The pool's throughput on trivial units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PoolThroughput {
    /// Workers.
    pub jobs: usize,
    /// Units run.
    pub units: usize,
    /// Time from `Pool::start` until all workers were ready, in milliseconds.
    pub start_ms: f64,
    /// Wall time from the first submit to the last result, in milliseconds.
    pub total_ms: f64,
    /// Units per second over that time.
    pub units_per_second: f64,
    /// Per-unit wall time as seen by the pool (send to report).
    pub unit_wall: TimeSummary,
    /// Units that did not produce a value (should be 0).
    pub failures: usize,
    /// Workers started and lost.
    pub stats: PoolStats,
    /// Starting a one-worker pool until its first trivial unit is back (process start,
    /// interpreter build, one unit).
    pub worker_start: TimeSummary,
    /// Per-unit wall time of units making 1 000 host API calls each (two event lines per call);
    /// compare with `api_calls_1000` in-process.
    pub api_heavy_unit_wall: TimeSummary,
}

/// Everything [`run_bench`] measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BenchReport {
    /// Building a fresh locked-down interpreter.
    pub interpreter_build: TimeSummary,
    /// Small programs in a reused interpreter.
    pub programs: Vec<ProgramTiming>,
    /// The pool, if a worker command was given.
    pub pool: Option<PoolThroughput>,
}

/// Runs the measurements of `config`.
pub fn run_bench(config: &BenchConfig) -> Result<BenchReport, Error> {
    let (interpreter_build, programs) = measure_in_process(config)?;
    let pool = match &config.worker {
        Some(worker) => Some(measure_pool(config, worker)?),
        None => None,
    };
    Ok(BenchReport {
        interpreter_build,
        programs,
        pool,
    })
}

/// Interpreter builds and program runs, on a thread with the workers' stack size.
fn measure_in_process(config: &BenchConfig) -> Result<(TimeSummary, Vec<ProgramTiming>), Error> {
    let builds = config.interpreter_builds.max(1);
    let runs = config.program_runs.max(1);
    let thread = std::thread::Builder::new()
        .name("sandbox-bench".into())
        .stack_size(WorkerLimits::default().interpreter_stack_bytes)
        .spawn(
            move || -> Result<(TimeSummary, Vec<ProgramTiming>), Error> {
                let mut build_times = Vec::with_capacity(builds);
                for _ in 0..builds {
                    let mut sandbox = Sandbox::new();
                    build_times.push(sandbox.warm_up()?);
                }
                let mut sandbox = Sandbox::new();
                sandbox.warm_up()?;
                let mut host = StubHost::from_config(&serde_json::json!({"video": "bench"}))
                    .map_err(|error| Error::internal(error.0))?;
                let budgets = Budgets::default();
                let mut timings = Vec::new();
                for (name, source) in PROGRAMS {
                    let mut times = Vec::with_capacity(runs);
                    for _ in 0..runs {
                        let started = Instant::now();
                        let report = sandbox.run(&mut host, source, &budgets);
                        sandbox.collect_garbage();
                        times.push(started.elapsed());
                        if let Err(error) = report.outcome {
                            return Err(Error::internal(format!(
                                "bench program `{name}` failed: {error}"
                            )));
                        }
                    }
                    timings.push(ProgramTiming {
                        name: (*name).to_owned(),
                        time: TimeSummary::of(&times),
                    });
                }
                Ok((TimeSummary::of(&build_times), timings))
            },
        )
        .map_err(|error| Error::internal(format!("cannot start the bench thread: {error}")))?;
    thread
        .join()
        .map_err(|_| Error::internal("the bench thread panicked"))?
}

fn measure_pool(config: &BenchConfig, worker: &WorkerCommand) -> Result<PoolThroughput, Error> {
    let jobs = config.jobs.max(1);
    let units = config.pool_units;
    let keys = config.pool_keys.max(1);
    let started = Instant::now();
    let pool = Pool::start(PoolConfig::new(worker.clone(), jobs))?;
    // One unit per worker first, so the throughput below excludes process start-up.
    for warm_up_unit in 0..jobs {
        pool.submit(trivial_unit(
            u64::MAX - warm_up_unit as u64,
            warm_up_unit,
            keys,
        ))?;
    }
    let _ = pool.results().count();
    let start_ms = started.elapsed().as_secs_f64() * 1e3;

    let started = Instant::now();
    for index in 0..units {
        pool.submit(trivial_unit(index as u64, index, keys))?;
    }
    let mut unit_walls = Vec::with_capacity(units);
    let mut failures = 0;
    for result in pool.results() {
        unit_walls.push(Duration::from_secs_f64(result.wall_ms / 1e3));
        if result.report.outcome.is_err() {
            failures += 1;
        }
    }
    let total = started.elapsed();

    let api_heavy_source = PROGRAMS
        .iter()
        .find(|(name, _)| *name == "api_calls_1000")
        .map_or("answer = 0", |(_, source)| source);
    for index in 0..config.api_heavy_units {
        let mut unit = trivial_unit(index as u64, index, keys);
        api_heavy_source.clone_into(&mut unit.source);
        pool.submit(unit)?;
    }
    let mut api_heavy_walls = Vec::with_capacity(config.api_heavy_units);
    for result in pool.results() {
        api_heavy_walls.push(Duration::from_secs_f64(result.wall_ms / 1e3));
        if result.report.outcome.is_err() {
            failures += 1;
        }
    }
    let stats = pool.stats();
    drop(pool);

    let mut start_times = Vec::with_capacity(config.worker_starts);
    for index in 0..config.worker_starts {
        let started = Instant::now();
        let pool = Pool::start(PoolConfig::new(worker.clone(), 1))?;
        pool.submit(trivial_unit(index as u64, index, keys))?;
        if pool
            .recv()
            .is_none_or(|result| result.report.outcome.is_err())
        {
            failures += 1;
        }
        start_times.push(started.elapsed());
    }

    Ok(PoolThroughput {
        jobs,
        units,
        start_ms,
        total_ms: total.as_secs_f64() * 1e3,
        units_per_second: units as f64 / total.as_secs_f64().max(f64::MIN_POSITIVE),
        unit_wall: TimeSummary::of(&unit_walls),
        failures,
        stats,
        worker_start: TimeSummary::of(&start_times),
        api_heavy_unit_wall: TimeSummary::of(&api_heavy_walls),
    })
}

fn trivial_unit(id: u64, index: usize, keys: usize) -> Unit {
    let key = format!("video-{}", index % keys);
    Unit {
        id,
        host: HostSpec::stub(serde_json::json!({"video": key})),
        key,
        source: "def execute_command(video):\n    return bool_to_yesno(len(video) > 0)\n"
            .to_owned(),
        budgets: Budgets::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_summary_of_known_samples() {
        let samples: Vec<Duration> = (1..=5).map(Duration::from_millis).collect();
        let summary = TimeSummary::of(&samples);
        assert_eq!(summary.samples, 5);
        assert!((summary.min_ms - 1.0).abs() < 1e-9);
        assert!((summary.median_ms - 3.0).abs() < 1e-9);
        assert!((summary.mean_ms - 3.0).abs() < 1e-9);
        assert!((summary.max_ms - 5.0).abs() < 1e-9);
        assert_eq!(TimeSummary::of(&[]).samples, 0);
    }
}
