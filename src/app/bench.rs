//! `bench sandbox` and `bench llm`, as JSON on stdout.
//!
//! `bench llm` runs `llm::run_bench`: the client against a loopback mock with a fixed latency,
//! throughput per concurrency level as a fraction of the ideal `jobs / latency`, and the request
//! rate achieved under each `--rpm` limit; beside it, in the same run, CPython's standard library
//! (`benches/cpython_llm_peer.py`: thread pool, `http.client`) at the same levels.
//!
//! `bench sandbox` measures what the sandbox costs:
//!
//! * the sandbox's own measurements (interpreter start-up, small programs, pool throughput on
//!   trivial units, worker start), from `sandbox::run_bench`;
//! * every builtin program for the video's generated questions (the video's scenario's engine
//!   and writer, from the scenario table), timed in-process against the real scene API, next to
//!   CPython (`python3`) running the same program text against a stub API in the same run, best
//!   of several rounds each; the ratio of medians is reported;
//! * the video's units through a worker pool: units per second and the projected time of
//!   10,000 units.

use std::collections::BTreeMap;
use std::io::Write as _;
use std::process::{Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

use super::error::{AppError, Classify as _, user_error};
use super::pipeline::{sandbox_budgets, start_pool};
use super::settings::{BenchLlmSettings, BenchSettings, Budgets};
use crate::dataset::{Question, QuestionId, VideoFolder, VideoId};
use crate::program::builtin::write_program;
use crate::sandbox::{
    self, BenchConfig, SceneHost, TimeSummary, Unit, WorkerCommand, scene_host_spec,
};
use crate::scenarios;
use crate::scene_api::{DynamicsBackend, PerceptionBackend, VideoSpec};

/// The CPython peer of `bench llm`.
const CPYTHON_LLM_PEER: &str = include_str!("../../benches/cpython_llm_peer.py");

/// The CPython side: a stub of the scene API plus a timing harness.
const CPYTHON_STUB: &str = include_str!("../../benches/cpython_stub_api.py");

/// Rounds per program; the best round is kept (both interpreters alike).
const ROUNDS: usize = 5;

pub(crate) fn bench_sandbox(settings: &BenchSettings) -> Result<ExitCode, AppError> {
    let video_dir = match &settings.video {
        Some(dir) => dir.clone(),
        None => scenarios::all()
            .iter()
            .find_map(|row| row.demo)
            .map(std::path::PathBuf::from)
            .ok_or_else(|| {
                user_error("bench sandbox: pass --video (no scenario has a demo video)")
            })?,
    };
    let video = VideoFolder::open(&video_dir, None).user()?;
    let programs = builtin_programs(&video)?;
    let spec = VideoSpec::new(
        &video,
        PerceptionBackend::Annotation,
        DynamicsBackend::Annotation,
    );
    let mut stderr = std::io::stderr().lock();
    let _ = writeln!(
        stderr,
        "timing {} distinct {} programs ({ROUNDS} rounds each)...",
        programs.len(),
        video.scenario
    );

    let timed_programs = time_programs(&programs, &spec);

    // The video's units through a worker pool.
    let _ = writeln!(
        stderr,
        "pushing {} {} units through {} workers...",
        settings.units, video.scenario, settings.jobs
    );
    let pool = run_pool(settings, &programs, &spec)?;

    // The sandbox's own measurements.
    let _ = writeln!(
        stderr,
        "sandbox measurements (start-up, small programs, trivial units)..."
    );
    let config = BenchConfig {
        worker: Some(WorkerCommand::current_exe().internal()?),
        jobs: settings.jobs,
        pool_units: settings.units,
        ..BenchConfig::default()
    };
    let sandbox_report = sandbox::run_bench(&config).internal()?;

    let report = json!({
        "benchmark": "sandbox",
        "profile": if cfg!(debug_assertions) { "debug" } else { "release" },
        "video": video.dir.display().to_string(),
        "scenario": video.scenario,
        "programs": timed_programs,
        "pool": pool,
        "sandbox": sandbox_report,
    });
    print_report(&report)
}

/// Every distinct builtin program for the questions generated for `video`, with its family; an
/// error when its scenario has no engine or writer, or none can be written.
fn builtin_programs(video: &VideoFolder) -> Result<Vec<(String, String)>, AppError> {
    let parts = scenarios::parts(video.scenario);
    let (Some(engine), Some(writer)) = (parts.engine, parts.writer) else {
        return Err(user_error(format!(
            "bench sandbox: {} scenes have no question engine and builtin writer yet; pass a video of {}",
            video.scenario,
            scenarios::names_with(|row| row.engine.is_some() && row.writer.is_some())
        )));
    };
    let generated = (engine.generate)(video, 0).user()?;
    let mut programs: Vec<(String, String)> = Vec::new();
    for (family, records) in &generated.question_dict {
        for (index, record) in records.iter().enumerate() {
            let question = Question::from_record(
                QuestionId(format!("{family}/{index}")),
                VideoId(video.id.0.clone()),
                video.scenario,
                record.clone(),
            )
            .user()?;
            for (_, option) in question.units() {
                if let Ok(source) = write_program(&question, option, writer)
                    && !programs.iter().any(|(_, s)| *s == source)
                {
                    programs.push((family.clone(), source));
                }
            }
        }
    }
    if programs.is_empty() {
        return Err(user_error(format!(
            "no {} programs could be written for `{}`",
            video.scenario,
            video.dir.display()
        )));
    }
    Ok(programs)
}

/// Times every program in-process against the real scene API (best of [`ROUNDS`]) and in
/// CPython against the stub API; the `programs` section of the report, with medians per family.
fn time_programs(programs: &[(String, String)], spec: &VideoSpec) -> Value {
    // RustPython, in-process, real scene API (memoised after the first program).
    let mut sandbox_in_process = sandbox::Sandbox::new();
    let mut host = SceneHost::new(spec.clone());
    let budgets = sandbox::Budgets::default();
    let mut rust_times = Vec::with_capacity(programs.len());
    let mut failures = 0;
    for (_, source) in programs {
        let mut best = Duration::MAX;
        for _ in 0..ROUNDS {
            let started = Instant::now();
            let report = sandbox_in_process.run(&mut host, source, &budgets);
            best = best.min(started.elapsed());
            if report.outcome.is_err() {
                failures += 1;
            }
        }
        rust_times.push(best);
    }

    // CPython, same program texts, stub API.
    let cpython = run_cpython(programs);

    let mut by_family: BTreeMap<&str, (Vec<Duration>, Vec<Duration>)> = BTreeMap::new();
    for (index, (family, _)) in programs.iter().enumerate() {
        let entry = by_family.entry(family.as_str()).or_default();
        entry.0.push(rust_times[index]);
        if let Ok((_, _, times)) = &cpython
            && let Some(time) = times.get(index)
        {
            entry.1.push(*time);
        }
    }
    let rust_summary = TimeSummary::of(&rust_times);
    let families: Vec<Value> = by_family
        .iter()
        .map(|(family, (rust, python))| {
            json!({
                "family": family,
                "programs": rust.len(),
                "rustpython_median_ms": TimeSummary::of(rust).median_ms,
                "cpython_median_ms": (!python.is_empty()).then(|| TimeSummary::of(python).median_ms),
            })
        })
        .collect();
    let cpython_json = match &cpython {
        Ok((version, startup, times)) => {
            let summary = TimeSummary::of(times);
            json!({
                "version": version,
                "startup": startup,
                "per_program": summary,
                "ratio_rustpython_to_cpython_median": if summary.median_ms > 0.0 { rust_summary.median_ms / summary.median_ms } else { 0.0 },
            })
        }
        Err(message) => json!({ "unavailable": message }),
    };
    json!({
        "programs": programs.len(),
        "rounds": ROUNDS,
        "failures": failures,
        "rustpython_in_process": rust_summary,
        "cpython_stub_api": cpython_json,
        "by_family": families,
    })
}

/// Pushes `settings.units` units through a pool of `settings.jobs` workers; the `pool` section
/// of the report: throughput, unit wall times and the projected time of 10,000 units.
fn run_pool(
    settings: &BenchSettings,
    programs: &[(String, String)],
    spec: &VideoSpec,
) -> Result<Value, AppError> {
    let run_budgets = Budgets {
        program_seconds: 5.0,
        api_seconds: 300.0,
        memory_mib: 2048,
    };
    let pool = start_pool(settings.jobs, run_budgets)?;
    let started = Instant::now();
    for index in 0..settings.units {
        let (_, source) = &programs[index % programs.len()];
        pool.submit(Unit {
            id: index as u64,
            // Spread over as many keys as workers, as a run over several videos would.
            key: format!("video-{}", index % settings.jobs.max(1)),
            host: scene_host_spec(spec),
            source: source.clone(),
            budgets: sandbox_budgets(run_budgets),
        })
        .internal()?;
    }
    let mut pool_failures = 0;
    let mut unit_walls = Vec::with_capacity(settings.units);
    for result in pool.results() {
        if result.report.outcome.is_err() {
            pool_failures += 1;
        }
        unit_walls.push(Duration::from_secs_f64(result.wall_ms.max(0.0) / 1000.0));
    }
    let elapsed = started.elapsed().as_secs_f64();
    let units_per_second = if elapsed > 0.0 {
        settings.units as f64 / elapsed
    } else {
        0.0
    };
    drop(pool);
    Ok(json!({
        "jobs": settings.jobs,
        "units": settings.units,
        "failures": pool_failures,
        "seconds": elapsed,
        "units_per_second": units_per_second,
        "unit_wall": TimeSummary::of(&unit_walls),
        "projected_seconds_for_10000_units": if units_per_second > 0.0 { 10_000.0 / units_per_second } else { 0.0 },
    }))
}

/// Prints a JSON report, pretty, on standard output: every `bench` command (and `perception
/// fit-colors`'s summary) ends so.
pub(super) fn print_report(report: &Value) -> Result<ExitCode, AppError> {
    let text = serde_json::to_string_pretty(report).internal()?;
    let _ = writeln!(std::io::stdout().lock(), "{text}");
    Ok(ExitCode::SUCCESS)
}

/// Runs the programs under `python3` with the stub API: (version, start-up times, per-program
/// best times). An error message when CPython cannot be run.
fn run_cpython(
    programs: &[(String, String)],
) -> Result<(String, TimeSummary, Vec<Duration>), String> {
    let dir = std::env::temp_dir().join(format!("contphy-eval-bench-{}", std::process::id()));
    fs_err::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let script = dir.join("cpython_stub_api.py");
    fs_err::write(&script, CPYTHON_STUB).map_err(|e| e.to_string())?;
    let mut startups = Vec::new();
    for _ in 0..5 {
        let started = Instant::now();
        let status = Command::new("python3")
            .args(["-c", "pass"])
            .status()
            .map_err(|e| format!("python3: {e}"))?;
        if !status.success() {
            return Err("python3 -c pass failed".to_string());
        }
        startups.push(started.elapsed());
    }
    let request = json!({ "programs": programs.iter().map(|(_, s)| s).collect::<Vec<_>>(), "rounds": ROUNDS });
    let mut child = Command::new("python3")
        .arg(&script)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .map_err(|e| format!("python3: {e}"))?;
    if let Some(mut stdin) = child.stdin.take() {
        stdin
            .write_all(request.to_string().as_bytes())
            .map_err(|e| e.to_string())?;
    }
    let output = child.wait_with_output().map_err(|e| e.to_string())?;
    let _ = fs_err::remove_dir_all(&dir);
    if !output.status.success() {
        return Err(format!("the CPython harness failed with {}", output.status));
    }
    let parsed: Value = serde_json::from_slice(&output.stdout)
        .map_err(|e| format!("CPython harness output: {e}"))?;
    let version = parsed["version"].as_str().unwrap_or("?").to_string();
    let times = parsed["per_program_ns"]
        .as_array()
        .ok_or("CPython harness output lacks per_program_ns")?
        .iter()
        .map(|ns| Duration::from_nanos(ns.as_u64().unwrap_or(0)))
        .collect();
    Ok((version, TimeSummary::of(&startups), times))
}

pub(crate) fn bench_llm(settings: &BenchLlmSettings) -> Result<ExitCode, AppError> {
    if settings.jobs.is_empty() || settings.jobs.contains(&0) {
        return Err(user_error("--jobs needs concurrency levels of at least 1"));
    }
    if !(settings.rpm_seconds.is_finite() && settings.rpm_seconds > 0.0) {
        return Err(user_error("--rpm-seconds must be a positive number"));
    }
    let config = crate::llm::BenchConfig {
        latency: Duration::from_millis(settings.latency_ms),
        jobs_levels: settings.jobs.clone(),
        rpm_limits: settings.rpm.clone(),
        rpm_span: Duration::from_secs_f64(settings.rpm_seconds),
        ..crate::llm::BenchConfig::default()
    };
    let report = crate::llm::run_bench(&config).internal()?;
    let levels: Vec<(usize, usize)> = config
        .jobs_levels
        .iter()
        .map(|&jobs| (jobs, (jobs * config.rounds).max(config.min_requests)))
        .collect();
    let peer = match llm_peer(config.latency, &levels) {
        Ok(peer) => peer,
        Err(error) => json!({ "error": error }),
    };
    let report = json!({
        "client": report,
        "peer_cpython_http_client": peer,
    });
    print_report(&report)
}

/// The peer of `bench llm`: CPython's standard library (thread pool, `http.client`) sending the
/// same requests to the same kind of mock, at the same concurrency levels, in the same run.
fn llm_peer(latency: Duration, levels: &[(usize, usize)]) -> Result<Value, String> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| e.to_string())?;
    let server = runtime
        .block_on(
            crate::llm::mock::MockServer::builder()
                .latency(latency)
                .start(),
        )
        .map_err(|e| e.to_string())?;
    let request = json!({
        "url": server.base_url(),
        "latency_ms": latency.as_secs_f64() * 1e3,
        "levels": levels,
    });
    let mut child = Command::new("python3")
        .args(["-c", CPYTHON_LLM_PEER])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .map_err(|e| format!("python3: {e}"))?;
    if let Some(mut stdin) = child.stdin.take() {
        stdin
            .write_all(request.to_string().as_bytes())
            .map_err(|e| e.to_string())?;
    }
    let output = child.wait_with_output().map_err(|e| e.to_string())?;
    drop(server);
    if !output.status.success() {
        return Err(format!("the CPython peer failed ({})", output.status));
    }
    serde_json::from_slice(&output.stdout).map_err(|e| format!("the CPython peer's output: {e}"))
}
