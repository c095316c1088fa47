//! `bench physics`: a simulator's error against its run time over a sweep of its resolution
//! parameters (time step; grid spacing and particles per cell), as JSON on stdout and an SVG
//! plot (`--svg FILE`).
//!
//! The scenario's simulator brings its parameters, sweep and cases (`physics::bench`, the
//! scenario table's `physics_bench`): each case with a closed form, or else a run at the
//! simulator's reference point. Every case runs at every point (best of the simulator's repeats
//! for the time; the results are identical each time), and each error measure is the largest
//! difference of its quantities from the reference at the end. The default point is always
//! measured, and the report ends with its largest error and its run time as a share of the
//! reference's. A case with measures over the labels the reference decides (its ensemble's runs
//! agree) also says how many labels each was taken over (`decided_labels`): what its errors can
//! tell apart, and each point the decided labels it gets otherwise in some run
//! (`differing_labels`, by the names the case gives them). With `--reference-cache DIR`,
//! reference runs are stored and reused (`bench_reference`): a sweep of new points over the
//! same cases runs only those points.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use serde_json::{Map, Value, json};

use super::bench::print_report;
use super::bench_confirmation::{confirmed, label_name};
use super::bench_reference::ReferenceCache;
use super::error::{AppError, Classify as _, user_error};
use super::settings::BenchPhysicsSettings;
use crate::physics::bench::{
    BenchCase, CaseOutput, ErrorMeasure, Measured, PhysicsBench, Reduction,
};
use crate::scenarios;

/// One case's sweep for the plot: its name and `(point, largest error, run time ms)` per point.
type Series = (String, Vec<(Vec<f64>, f64, f64)>);

/// What `case` gives at `point`, and the wall time, ms.
fn simulate(case: &BenchCase, point: &[f64]) -> Result<(CaseOutput, f64), AppError> {
    let started = Instant::now();
    let output = (case.run)(point).user()?;
    Ok((output, started.elapsed().as_secs_f64() * 1e3))
}

/// The default point's largest error and its cost against the references', summed over the
/// cases.
#[derive(Debug, Default)]
struct DefaultTotals {
    error: f64,
    /// Per measure, the largest error over the cases.
    measures: Vec<f64>,
    /// Per decided measure, its error summed over the cases weighted by their decided labels,
    /// and those labels' number: the pooled error is their quotient (a case deciding one
    /// label weighs one label, not a case's worth).
    pooled: Vec<(f64, usize)>,
    ms: f64,
    reference_ms: f64,
    work: u64,
    reference_work: u64,
}

/// The points every case is measured against.
struct Anchors {
    /// The reference's.
    reference: Vec<f64>,
    /// The default's, whose figures the summary totals.
    default: Vec<f64>,
    /// Under `--confirm`, the point whose runs must repeat a decided label for it to count.
    confirmation: Option<Vec<f64>>,
}

/// One case over the sweep: its report and its plot series; adds the default point's figures
/// to `totals`. The reference run comes from `cache` when stored there, and is stored there
/// when run. Progress goes to stderr.
fn sweep_case(
    bench: &PhysicsBench,
    case: &BenchCase,
    points: &[Vec<f64>],
    anchors: &Anchors,
    cache: Option<&ReferenceCache>,
    totals: &mut DefaultTotals,
) -> Result<(Value, Series), AppError> {
    let mut progress = std::io::stderr().lock();
    let (reference, reference_kind, reference_run, reference_cached) =
        if let Some(exact) = &case.exact {
            (exact.clone(), "closed form".to_string(), None, false)
        } else {
            let words = point_words(bench, &anchors.reference);
            let _ = write!(progress, "{}: reference ({words})... ", case.name);
            let (output, ms, stored) =
                reference_output(case, &anchors.reference, cache, &mut progress)?;
            (output.quantities, words, Some((ms, output.work)), stored)
        };
    let mut confirmation_report = Map::new();
    let reference = match (&anchors.confirmation, &case.exact) {
        (Some(point), None) => {
            let words = point_words(bench, point);
            let _ = write!(progress, "{}: confirmation ({words})... ", case.name);
            let (output, ms, stored) = reference_output(case, point, cache, &mut progress)?;
            let (kept, dropped) = confirmed(
                bench.errors,
                &case.label_names,
                &reference,
                &output.quantities,
            );
            confirmation_report.insert("confirmation".into(), json!(words));
            if stored {
                confirmation_report.insert("confirmation_stored".into(), json!(true));
            }
            confirmation_report.insert("confirmation_run_time_ms".into(), json!(ms));
            confirmation_report.insert("unconfirmed_labels".into(), Value::Array(dropped));
            kept
        }
        _ => reference,
    };
    // How many labels each decided measure is taken over: what its errors can tell.
    let decided: Vec<Option<usize>> = bench
        .errors
        .iter()
        .zip(&reference)
        .map(|(measure, expected)| {
            (measure.reduction.is_decided())
                .then(|| decided_labels(measure.reduction, expected).len())
        })
        .collect();
    let mut points_out = Vec::new();
    let mut rows = Vec::new();
    for point in points {
        let _ = write!(progress, "{}: {}... ", case.name, point_words(bench, point));
        let mut best = f64::INFINITY;
        let mut output = None;
        for _ in 0..bench.repeats.max(1) {
            let (run, ms) = simulate(case, point)?;
            best = best.min(ms);
            output = Some(run);
        }
        let _ = writeln!(progress, "{:.1} s", best / 1e3);
        let (quantities, work) = output.map_or((Vec::new(), None), |o| (o.quantities, o.work));
        let case_errors = errors(bench.errors, &quantities, &reference);
        // The plotted error: the largest of the plotted measures.
        let largest = case_errors
            .iter()
            .zip(bench.errors)
            .filter(|(_, measure)| measure.plotted)
            .map(|(error, _)| *error)
            .fold(0.0_f64, f64::max);
        let mut row = point_json(bench, point);
        for (measure, error) in bench.errors.iter().zip(&case_errors) {
            row.insert(measure.key.to_string(), json!(error));
        }
        let differing = differing_labels(bench.errors, &case.label_names, &quantities, &reference);
        if !differing.is_empty() {
            row.insert("differing_labels".into(), Value::Array(differing));
        }
        row.insert("run_time_ms".into(), json!(best));
        if let Some(work) = work {
            row.insert("work".into(), json!(work));
        }
        if let Some((reference_ms, reference_work)) = reference_run {
            row.insert("run_time_share".into(), json!(best / reference_ms));
            if let (Some(work), Some(reference_work)) = (work, reference_work) {
                row.insert(
                    "work_share".into(),
                    json!(work as f64 / reference_work.max(1) as f64),
                );
            }
        }
        if *point == anchors.default {
            totals.error = totals.error.max(largest);
            totals.measures.resize(case_errors.len(), 0.0);
            for (total, error) in totals.measures.iter_mut().zip(&case_errors) {
                *total = total.max(*error);
            }
            totals.pooled.resize(case_errors.len(), (0.0, 0));
            for ((pooled, error), labels) in
                totals.pooled.iter_mut().zip(&case_errors).zip(&decided)
            {
                if let Some(labels) = labels {
                    pooled.0 += error * *labels as f64;
                    pooled.1 += labels;
                }
            }
            totals.ms += best;
            totals.work += work.unwrap_or(0);
            if let Some((reference_ms, reference_work)) = reference_run {
                totals.reference_ms += reference_ms;
                totals.reference_work += reference_work.unwrap_or(0);
            }
        }
        points_out.push((point.clone(), largest, best));
        rows.push(Value::Object(row));
    }
    let mut case_report = Map::new();
    case_report.insert("case".into(), json!(case.name));
    case_report.insert("reference".into(), json!(reference_kind));
    if reference_cached {
        case_report.insert("reference_stored".into(), json!(true));
    }
    if let Some((reference_ms, reference_work)) = reference_run {
        case_report.insert("reference_run_time_ms".into(), json!(reference_ms));
        if let Some(work) = reference_work {
            case_report.insert("reference_work".into(), json!(work));
        }
    }
    case_report.extend(confirmation_report);
    let decided: Map<String, Value> = bench
        .errors
        .iter()
        .zip(&decided)
        .filter_map(|(measure, labels)| Some((measure.key.to_string(), json!((*labels)?))))
        .collect();
    if !decided.is_empty() {
        case_report.insert("decided_labels".into(), Value::Object(decided));
    }
    case_report.insert("sweep".into(), Value::Array(rows));
    Ok((Value::Object(case_report), (case.name.clone(), points_out)))
}

/// `case`'s run at `reference_point`: from `cache` when stored there (`true`), else run (and
/// stored there); with its wall time, ms (a stored run's when it ran). Ends the progress line.
fn reference_output(
    case: &BenchCase,
    reference_point: &[f64],
    cache: Option<&ReferenceCache>,
    progress: &mut impl std::io::Write,
) -> Result<(CaseOutput, f64, bool), AppError> {
    match cache.map(|cache| cache.load(case, reference_point)) {
        Some(Ok(Some(stored))) => {
            let _ = writeln!(
                progress,
                "stored ({:.1} s when run)",
                stored.run_time_ms / 1e3
            );
            return Ok((stored.output, stored.run_time_ms, true));
        }
        Some(Err(reason)) => {
            let _ = write!(progress, "(warning: {reason}; running it again) ");
        }
        Some(Ok(None)) | None => {}
    }
    let (output, ms) = simulate(case, reference_point)?;
    let _ = writeln!(progress, "{:.1} s", ms / 1e3);
    if let Some(cache) = cache {
        cache.store(case, reference_point, &output, ms)?;
    }
    Ok((output, ms, false))
}

/// Per error measure, the differences of `measured` from `reference` reduced as the measure
/// says (the largest, or the mean; none differ: 0); a quantity missing on one side counts as
/// infinitely wrong.
fn errors(measures: &[ErrorMeasure], measured: &Measured, reference: &Measured) -> Vec<f64> {
    reference
        .iter()
        .enumerate()
        .map(|(index, expected)| {
            let Some(got) = measured.get(index) else {
                return f64::INFINITY;
            };
            if got.len() != expected.len() {
                return f64::INFINITY;
            }
            let differences = got.iter().zip(expected).map(|(a, b)| (a - b).abs());
            match measures
                .get(index)
                .map_or(Reduction::Largest, |m| m.reduction)
            {
                Reduction::Largest => differences.fold(0.0_f64, f64::max),
                Reduction::Mean => differences.sum::<f64>() / expected.len().max(1) as f64,
                Reduction::Mismatch => {
                    differences.filter(|difference| *difference > 1e-9).count() as f64
                        / expected.len().max(1) as f64
                }
                Reduction::DecidedMean => {
                    let (sum, count) = got
                        .iter()
                        .zip(expected)
                        .filter(|(_, expected)| is_label(**expected))
                        .fold((0.0, 0usize), |(sum, count), (a, b)| {
                            (sum + (a - b).abs(), count + 1)
                        });
                    if count == 0 { 0.0 } else { sum / count as f64 }
                }
                Reduction::DecidedCategories(size) => decided_categories(got, expected, size),
            }
        })
        .collect()
}

/// The decided labels a point gets otherwise in some run than the reference: per label its
/// measure, its name (or `#index`), the reference's share of runs (0 or 1; a category's 1)
/// and the point's.
fn differing_labels(
    measures: &[ErrorMeasure],
    names: &[Vec<String>],
    measured: &Measured,
    reference: &Measured,
) -> Vec<Value> {
    let mut differing = Vec::new();
    for (index, (measure, expected)) in measures.iter().zip(reference).enumerate() {
        let Some(got) = measured
            .get(index)
            .filter(|got| got.len() == expected.len())
        else {
            continue;
        };
        let name = |label: usize| label_name(names, index, label);
        let mut push = |label: usize, reference: f64, share: f64| {
            differing.push(json!({
                "measure": measure.key,
                "label": name(label),
                "reference": reference,
                "share": share,
            }));
        };
        for decided in decided_labels(measure.reduction, expected) {
            let Some(share) = got.get(decided.index).copied() else {
                continue;
            };
            if (share - decided.share).abs() > 1e-9 {
                push(decided.index, decided.share, share);
            }
        }
    }
    differing
}

/// Whether a share is a label: the reference's ensemble agreed on it (0 or 1).
fn is_label(share: f64) -> bool {
    share.abs() < 1e-9 || (share - 1.0).abs() < 1e-9
}

/// Whether a group of category shares is decided: one category holds every run.
fn decided_group(shares: &[f64]) -> bool {
    shares.iter().all(|share| is_label(*share))
        && shares.iter().filter(|share| **share > 0.5).count() == 1
}

/// One label a decided reduction is taken over.
#[derive(Debug, PartialEq)]
pub(super) struct DecidedLabel {
    /// Its index among the measure's quantities (a category's own).
    pub index: usize,
    /// The reference's share of runs with it: 0 or 1 (a category's 1).
    pub share: f64,
    /// The quantities it stands for: itself, or its category's whole group.
    pub span: std::ops::Range<usize>,
}

/// The labels a decided reduction of `expected` is taken over: the labels the reference's runs
/// agree on, or the groups of categories they put in one category (none for the other
/// reductions).
pub(super) fn decided_labels(reduction: Reduction, expected: &[f64]) -> Vec<DecidedLabel> {
    match reduction {
        Reduction::DecidedMean => expected
            .iter()
            .enumerate()
            .filter(|(_, share)| is_label(**share))
            .map(|(index, share)| DecidedLabel {
                index,
                share: *share,
                span: index..index + 1,
            })
            .collect(),
        Reduction::DecidedCategories(size) if size > 0 => expected
            .chunks(size)
            .enumerate()
            .filter(|(_, group)| decided_group(group))
            .filter_map(|(group, shares)| {
                let category = shares.iter().position(|share| *share > 0.5)?;
                Some(DecidedLabel {
                    index: group * size + category,
                    share: 1.0,
                    span: group * size..(group + 1) * size,
                })
            })
            .collect(),
        _ => Vec::new(),
    }
}

/// The error of [`Reduction::DecidedCategories`]: over the groups of `size` shares that the
/// reference holds one-hot, the mean share of runs outside the reference's category.
fn decided_categories(got: &[f64], expected: &[f64], size: usize) -> f64 {
    if size == 0 {
        return f64::INFINITY;
    }
    let (sum, count) = got
        .chunks(size)
        .zip(expected.chunks(size))
        .filter(|(_, expected)| decided_group(expected))
        .fold((0.0, 0usize), |(sum, count), (got, expected)| {
            let difference: f64 = got.iter().zip(expected).map(|(a, b)| (a - b).abs()).sum();
            (sum + difference / 2.0, count + 1)
        });
    if count == 0 { 0.0 } else { sum / count as f64 }
}

/// The points to sweep: the simulator's, or the product of the values given per parameter
/// (the others at their default); the default point is added when missing.
fn sweep_points(
    bench: &PhysicsBench,
    scenario: &str,
    overrides: &[(&'static str, Vec<f64>)],
) -> Result<Vec<Vec<f64>>, AppError> {
    let flags = || {
        bench
            .parameters
            .iter()
            .map(|parameter| parameter.flag)
            .collect::<Vec<_>>()
            .join(", ")
    };
    for (flag, values) in overrides {
        if !bench
            .parameters
            .iter()
            .any(|parameter| parameter.flag == *flag)
        {
            return Err(user_error(format!(
                "bench physics: the {scenario} simulator does not sweep {flag} (it sweeps {})",
                flags()
            )));
        }
        // A shift may be zero or negative; resolutions must be positive.
        let positive = !matches!(*flag, "--emitter-shift" | "--start-shift");
        if values.is_empty()
            || values
                .iter()
                .any(|value| !value.is_finite() || (positive && *value <= 0.0))
        {
            return Err(user_error(format!(
                "bench physics: {flag} needs {} values",
                if positive { "positive" } else { "finite" }
            )));
        }
    }
    let mut points: Vec<Vec<f64>> = if overrides.is_empty() {
        bench.sweep.iter().map(|point| point.to_vec()).collect()
    } else {
        let mut points = vec![Vec::new()];
        for (index, parameter) in bench.parameters.iter().enumerate() {
            let values = overrides
                .iter()
                .find(|(flag, _)| *flag == parameter.flag)
                .map_or_else(
                    || vec![bench.default.get(index).copied().unwrap_or(f64::NAN)],
                    |(_, values)| values.clone(),
                );
            points = points
                .into_iter()
                .flat_map(|point| {
                    values.iter().map(move |value| {
                        let mut next = point.clone();
                        next.push(*value);
                        next
                    })
                })
                .collect();
        }
        points
    };
    // A parameter the reference follows takes one value, or the points would be compared
    // with references of different kinds.
    for (index, parameter) in bench.parameters.iter().enumerate() {
        let value = |point: &Vec<f64>| point.get(index).copied().map(f64::to_bits);
        if parameter.follows_sweep
            && points
                .iter()
                .any(|point| value(point) != points.first().and_then(value))
        {
            return Err(user_error(format!(
                "bench physics: {} takes one value (the reference runs at it too)",
                parameter.flag
            )));
        }
    }
    let default_point = bench.default_point(&points);
    if !points.contains(&default_point) {
        points.push(default_point);
    }
    Ok(points)
}

/// `point` as a JSON object keyed by the parameters.
fn point_json(bench: &PhysicsBench, point: &[f64]) -> Map<String, Value> {
    bench
        .parameters
        .iter()
        .zip(point)
        .map(|(parameter, value)| (parameter.key.to_string(), json!(value)))
        .collect()
}

/// `point` in words (`grid_spacing = 0.02, particles_per_cell_side = 2`).
fn point_words(bench: &PhysicsBench, point: &[f64]) -> String {
    bench
        .parameters
        .iter()
        .zip(point)
        .map(|(parameter, value)| format!("{} = {value}", parameter.key))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Runs `bench physics`.
pub(crate) fn bench_physics(settings: &BenchPhysicsSettings) -> Result<ExitCode, AppError> {
    let with_bench = || scenarios::names_with(|row| row.physics_bench.is_some());
    let scenario = settings
        .scenario
        .or_else(|| scenarios::only_with(|row| row.physics_bench.is_some()))
        .ok_or_else(|| {
            user_error(format!(
                "bench physics: pass --scenario (simulators: {})",
                with_bench()
            ))
        })?;
    let Some(bench) = scenarios::parts(scenario).physics_bench else {
        return Err(user_error(format!(
            "bench physics: no simulator for scenario `{scenario}` yet (simulators: {})",
            with_bench()
        )));
    };
    let points = sweep_points(bench, scenario.name(), &settings.sweep)?;
    let videos: Vec<PathBuf> = if settings.videos.is_empty() {
        scenarios::parts(scenario)
            .demo
            .map(PathBuf::from)
            .into_iter()
            .collect()
    } else if bench.uses_videos {
        settings.videos.clone()
    } else {
        return Err(user_error(format!(
            "bench physics: the {scenario} simulator builds its own cases; --video is not used"
        )));
    };
    let cache = settings
        .reference_cache
        .as_deref()
        .map(|folder| ReferenceCache::open(folder, scenario.name()))
        .transpose()?;
    let confirmation = if settings.confirm {
        let point = bench.confirmation_point(&points).ok_or_else(|| {
            user_error(format!(
                "bench physics: --confirm: the {scenario} simulator has no finer point to confirm \
                 its reference's labels with (simulators with one: {})",
                scenarios::names_with(|row| row
                    .physics_bench
                    .is_some_and(|bench| bench.confirmation.is_some()))
            ))
        })?;
        Some(point)
    } else {
        None
    };
    let anchors = Anchors {
        reference: bench.reference_point(&points),
        default: bench.default_point(&points),
        confirmation,
    };
    let mut report_cases = Vec::new();
    let mut series: Vec<Series> = Vec::new();
    let mut totals = DefaultTotals::default();
    for case in (bench.cases)(&videos).user()? {
        let (case_report, case_series) =
            sweep_case(bench, &case, &points, &anchors, cache.as_ref(), &mut totals)?;
        report_cases.push(case_report);
        series.push(case_series);
    }
    let default_summary = default_summary(bench, &totals);
    let mut report: Value = json!({
        "scenario": scenario.name(),
        "simulated_seconds": bench.duration,
        "default": point_json(bench, &anchors.default),
        "errors": bench.errors.iter().map(|measure| measure.key).collect::<Vec<_>>(),
        "cases": report_cases,
        "default_summary": default_summary,
    });
    if let (Some(point), Value::Object(report)) = (&anchors.confirmation, &mut report) {
        report.insert(
            "confirmation".into(),
            Value::Object(point_json(bench, point)),
        );
    }
    if let Some(path) = &settings.svg {
        crate::util::write_atomic(path, svg_plot(&series, bench).as_bytes()).user()?;
    }
    print_report(&report)
}

/// The report's closing summary: the default point's largest plotted error, its run time and
/// work as shares of the references', and per measure its error (decided measures: pooled over
/// the cases' decided labels) against the simulator's tolerance.
fn default_summary(bench: &PhysicsBench, totals: &DefaultTotals) -> Map<String, Value> {
    let mut default_summary = Map::new();
    default_summary.insert("largest_plotted_error".into(), json!(totals.error));
    if totals.reference_ms > 0.0 {
        default_summary.insert(
            "run_time_share_of_reference".into(),
            json!(totals.ms / totals.reference_ms),
        );
    }
    if totals.reference_work > 0 {
        default_summary.insert(
            "work_share_of_reference".into(),
            json!(totals.work as f64 / totals.reference_work as f64),
        );
    }
    for (index, (measure, largest)) in bench.errors.iter().zip(&totals.measures).enumerate() {
        let mut entry = Map::new();
        // A decided measure's error is pooled over every case's decided labels; the largest
        // case's error rides along (a case deciding two labels can show 0.5 on one run).
        let error = match totals.pooled.get(index) {
            Some((sum, labels)) if measure.reduction.is_decided() => {
                entry.insert("labels".into(), json!(labels));
                entry.insert("largest_case_error".into(), json!(largest));
                if *labels == 0 {
                    0.0
                } else {
                    sum / *labels as f64
                }
            }
            _ => *largest,
        };
        entry.insert("error".into(), json!(error));
        if let Some(tolerance) = measure.tolerance {
            entry.insert("tolerance".into(), json!(tolerance));
            entry.insert("within_tolerance".into(), json!(error <= tolerance));
        }
        default_summary.insert(measure.key.to_string(), Value::Object(entry));
    }
    default_summary
}

/// A log–log plot of the largest error against run time (ms), one polyline per case, each point
/// labelled with its parameters.
fn svg_plot(series: &[Series], bench: &PhysicsBench) -> String {
    let (width, height, margin) = (720.0, 480.0, 70.0);
    let all = series.iter().flat_map(|(_, p)| p.iter());
    let floor = 1e-12;
    let (mut x_min, mut x_max, mut y_min, mut y_max) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (_, error, ms) in all {
        let (error, ms) = (*error, *ms);
        x_min = x_min.min(ms.max(1e-6).log10());
        x_max = x_max.max(ms.max(1e-6).log10());
        y_min = y_min.min(error.max(floor).log10());
        y_max = y_max.max(error.max(floor).log10());
    }
    let (x_min, x_max) = (x_min.floor(), x_max.ceil().max(x_min.floor() + 1.0));
    let (y_min, y_max) = (y_min.floor(), y_max.ceil().max(y_min.floor() + 1.0));
    let sx = |v: f64| margin + (v - x_min) / (x_max - x_min) * (width - 2.0 * margin);
    let sy = |v: f64| height - margin - (v - y_min) / (y_max - y_min) * (height - 2.0 * margin);
    let colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"];
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        svg,
        r#"<text x="{}" y="24" text-anchor="middle" font-size="15">{}: error at t = {} s against run time ({} labelled)</text>"#,
        width / 2.0,
        bench.title,
        bench.duration,
        bench
            .parameters
            .iter()
            .map(|parameter| parameter.label)
            .collect::<Vec<_>>()
            .join(", ")
    );
    // Axes with decade ticks.
    let _ = writeln!(
        svg,
        r#"<path d="M{margin},{top} V{bottom} H{right}" stroke="black" fill="none"/>"#,
        top = margin,
        bottom = height - margin,
        right = width - margin
    );
    let mut decade = x_min;
    while decade <= x_max + 1e-9 {
        let x = sx(decade);
        let _ = writeln!(
            svg,
            r#"<text x="{x}" y="{}" text-anchor="middle">1e{decade}</text>"#,
            height - margin + 18.0
        );
        decade += 1.0;
    }
    let mut decade = y_min;
    while decade <= y_max + 1e-9 {
        let y = sy(decade);
        let _ = writeln!(
            svg,
            r#"<text x="{}" y="{y}" text-anchor="end" dominant-baseline="middle">1e{decade}</text>"#,
            margin - 6.0
        );
        decade += 1.0;
    }
    let _ = writeln!(
        svg,
        r#"<text x="{}" y="{}" text-anchor="middle">run time, ms</text>"#,
        width / 2.0,
        height - 20.0
    );
    let _ = writeln!(
        svg,
        r#"<text x="18" y="{}" text-anchor="middle" transform="rotate(-90 18 {})">{}</text>"#,
        height / 2.0,
        height / 2.0,
        bench.error_axis
    );
    for (index, (name, points)) in series.iter().enumerate() {
        let colour = colours[index % colours.len()];
        let path: Vec<String> = points
            .iter()
            .map(|(_, error, ms)| {
                let (error, ms) = (*error, *ms);
                format!(
                    "{:.1},{:.1}",
                    sx(ms.max(1e-6).log10()),
                    sy(error.max(floor).log10())
                )
            })
            .collect();
        let _ = writeln!(
            svg,
            r#"<polyline points="{}" stroke="{colour}" fill="none" stroke-width="2"/>"#,
            path.join(" ")
        );
        for (point, error, ms) in points {
            let (x, y) = (sx(ms.max(1e-6).log10()), sy(error.max(floor).log10()));
            let label: Vec<String> = bench
                .parameters
                .iter()
                .zip(point)
                .map(|(parameter, value)| format!("{} {value}", parameter.label))
                .collect();
            let label = label.join(" ");
            let _ = writeln!(
                svg,
                r#"<circle cx="{x:.1}" cy="{y:.1}" r="3" fill="{colour}"/><text x="{:.1}" y="{:.1}" font-size="10">{label}</text>"#,
                x + 5.0,
                y - 5.0
            );
        }
        let _ = writeln!(
            svg,
            r#"<text x="{}" y="{}" fill="{colour}">{name}</text>"#,
            width - margin - 200.0,
            margin + 16.0 * index as f64
        );
    }
    svg.push_str("</svg>\n");
    svg
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::Scenario;

    fn bench(scenario: Scenario) -> &'static PhysicsBench {
        scenarios::parts(scenario).physics_bench.unwrap()
    }

    #[test]
    fn given_values_sweep_their_parameter_with_the_others_at_their_default() {
        let fluid = bench(Scenario::Fluid);
        let points = sweep_points(fluid, "fluid", &[("--grid-spacing", vec![0.1, 0.04])]).unwrap();
        // The default point (0.05, 2, 0) is always measured.
        assert_eq!(
            points,
            vec![
                vec![0.1, 2.0, 0.0],
                vec![0.04, 2.0, 0.0],
                vec![0.05, 2.0, 0.0]
            ]
        );
        let both = sweep_points(
            fluid,
            "fluid",
            &[
                ("--grid-spacing", vec![0.1, 0.05]),
                ("--particles-per-cell", vec![1.0, 2.0]),
            ],
        )
        .unwrap();
        assert_eq!(
            both,
            vec![
                vec![0.1, 1.0, 0.0],
                vec![0.1, 2.0, 0.0],
                vec![0.05, 1.0, 0.0],
                vec![0.05, 2.0, 0.0]
            ]
        );
        let own = sweep_points(fluid, "fluid", &[]).unwrap();
        assert_eq!(own.len(), fluid.sweep.len());
        assert!(own.iter().any(|point| point.as_slice() == fluid.default));
    }

    #[test]
    fn the_reference_and_the_default_follow_the_ensemble_size_swept() {
        let cloth = bench(Scenario::Cloth);
        let points = sweep_points(
            cloth,
            "cloth",
            &[("--substeps", vec![5.0]), ("--ensemble-runs", vec![15.0])],
        )
        .unwrap();
        // The default point, with fifteen runs, is added; the reference runs fifteen too.
        assert_eq!(
            points,
            vec![
                vec![16.0, 5.0, 1.0, 0.0, 15.0, 0.4],
                vec![16.0, 20.0, 1.0, 0.0, 15.0, 0.4]
            ]
        );
        assert_eq!(cloth.default_point(&points), points[1]);
        assert_eq!(
            cloth.reference_point(&points),
            vec![31.0, 50.0, 4.0, 0.0, 15.0, 0.4]
        );
        // Unswept, every point keeps the default ensemble of five.
        let own = sweep_points(cloth, "cloth", &[]).unwrap();
        assert!(
            own.iter()
                .all(|point| point[4].to_bits() == 5.0_f64.to_bits())
        );
        assert_eq!(cloth.reference_point(&own)[4].to_bits(), 5.0_f64.to_bits());
        // Two sizes would compare points with references of different kinds.
        let error = sweep_points(cloth, "cloth", &[("--ensemble-runs", vec![5.0, 15.0])])
            .unwrap_err()
            .error
            .to_string();
        assert!(error.contains("--ensemble-runs takes one value"), "{error}");
        // A start shift may be negative or zero.
        assert!(sweep_points(cloth, "cloth", &[("--start-shift", vec![-0.01, 0.0])]).is_ok());
    }

    #[test]
    fn a_decided_measure_s_summary_error_is_pooled_over_the_cases_labels() {
        let cloth = bench(Scenario::Cloth);
        // Two cases: one deciding 40 contact labels with none wrong, one deciding 2 with one
        // run in ten off on one of them (0.05 in that case).
        let totals = DefaultTotals {
            error: 0.05,
            measures: vec![0.0, 0.0, 0.05, 0.3],
            pooled: vec![(0.0, 10), (0.0, 12), (0.05 * 2.0, 42), (0.0, 0)],
            ms: 5.0,
            reference_ms: 100.0,
            work: 0,
            reference_work: 0,
        };
        let summary = default_summary(cloth, &totals);
        let contact = &summary["contact_disagreement"];
        assert!((contact["error"].as_f64().unwrap() - 0.1 / 42.0).abs() < 1e-15);
        assert_eq!(contact["labels"], 42);
        assert_eq!(contact["largest_case_error"], 0.05);
        assert_eq!(contact["within_tolerance"], true);
        // A plain mean is the largest case's, with no labels.
        assert_eq!(summary["box_position_error"]["error"], 0.3);
        assert!(summary["box_position_error"].get("labels").is_none());
        assert_eq!(summary["run_time_share_of_reference"], 0.05);
    }

    #[test]
    fn each_reduction_turns_differences_from_the_reference_into_its_error() {
        let measure = |reduction| ErrorMeasure {
            key: "measure",
            reduction,
            tolerance: None,
            plotted: false,
        };
        let measures = [
            measure(Reduction::Largest),
            measure(Reduction::Mean),
            measure(Reduction::Mismatch),
            measure(Reduction::DecidedMean),
            measure(Reduction::DecidedCategories(3)),
        ];
        // Codes 0, 3, 1, 4 against the reference's 0, 1, 1, 2: two of four differ, by 2 each.
        let got = vec![vec![0.0, 3.0, 1.0, 4.0]; 3];
        let reference = vec![vec![0.0, 1.0, 1.0, 2.0]; 3];
        let mut measured = got;
        measured.push(vec![0.5, 1.0, 0.0]);
        let mut expected = reference;
        expected.push(vec![1.0, 0.5, 1.0]);
        // Decided: the labels the reference holds at 0 or 1 (the first and third), off by 0.5
        // and 1.
        // Categories, three to a group: the reference's first group is decided (all runs in
        // the second category), where the point has a quarter of its runs in the third; the
        // second group is split, left out.
        measured.push(vec![0.0, 0.75, 0.25, 0.5, 0.5, 0.0]);
        expected.push(vec![0.0, 1.0, 0.0, 0.5, 0.0, 0.5]);
        assert_eq!(
            errors(&measures, &measured, &expected),
            vec![2.0, 1.0, 0.5, 0.75, 0.25]
        );
        // Nothing decided: no error; a group size of 0: no meaning.
        assert!(decided_categories(&[0.5, 0.5], &[0.5, 0.5], 2).abs() < 1e-15);
        assert!(decided_categories(&[1.0], &[1.0], 0).is_infinite());
        // The labels each decided measure is taken over: two of three shares, one of two
        // groups; none for the other reductions.
        let label = |index: usize, share: f64, span: std::ops::Range<usize>| DecidedLabel {
            index,
            share,
            span,
        };
        assert_eq!(
            decided_labels(Reduction::DecidedMean, &[1.0, 0.5, 1.0]),
            vec![label(0, 1.0, 0..1), label(2, 1.0, 2..3)]
        );
        assert_eq!(
            decided_labels(
                Reduction::DecidedCategories(3),
                &[0.0, 1.0, 0.0, 0.5, 0.0, 0.5]
            ),
            vec![label(1, 1.0, 0..3)]
        );
        assert!(decided_labels(Reduction::Mean, &[1.0]).is_empty());
        // The labels it gets otherwise: the decided ones that differ at all, by name where
        // the case names them (the categories' first group, by its reference category).
        let names = vec![
            Vec::new(),
            Vec::new(),
            Vec::new(),
            vec![
                "a fell".to_string(),
                "b fell".to_string(),
                "c fell".to_string(),
            ],
        ];
        let differing = differing_labels(&measures, &names, &measured, &expected);
        let listed: Vec<String> = differing
            .iter()
            .map(|label| {
                format!(
                    "{} {} {}",
                    label["label"], label["reference"], label["share"]
                )
            })
            .collect();
        assert_eq!(
            listed,
            [
                "\"a fell\" 1.0 0.5",
                "\"c fell\" 1.0 0.0",
                "\"#1\" 1.0 0.75"
            ]
        );
    }

    #[test]
    fn the_reference_is_fixed_or_tenfold_finer_than_the_finest_step() {
        let rope = bench(Scenario::Rope);
        let points = sweep_points(rope, "rope", &[("--dt", vec![0.02, 0.005])]).unwrap();
        assert_eq!(rope.reference_point(&points), vec![0.0001]);
        let fluid = bench(Scenario::Fluid);
        assert_eq!(fluid.reference_point(&points), vec![0.02, 2.0, 0.0]);
        // The reference is finer than every point swept by default but its own perturbed twin.
        for point in fluid.sweep {
            assert!(point[0] > 0.02 || point[2] != 0.0, "{point:?}");
        }
    }

    /// A bench of one decided measure over two labels and a reference at point 1, confirmed at
    /// point 2; its one case's runs are [`labels_at`].
    const CONFIRMED_BENCH: PhysicsBench = PhysicsBench {
        duration: 1.0,
        parameters: &[crate::physics::bench::Parameter {
            key: "setting",
            flag: "--setting",
            label: "s",
            follows_sweep: false,
        }],
        sweep: &[&[3.0]],
        default: &[3.0],
        reference: crate::physics::bench::Reference::Point(&[1.0]),
        confirmation: Some(&[2.0]),
        errors: &[ErrorMeasure {
            key: "contact_disagreement",
            reduction: Reduction::DecidedMean,
            tolerance: Some(0.01),
            plotted: true,
        }],
        error_axis: "share",
        repeats: 1,
        title: "labels",
        uses_videos: false,
        cases: |_| Ok(Vec::new()),
    };

    /// The case's labels at a point: the reference decides both (1, 0), the confirmation
    /// repeats only the first, the default point misses the first in a fifth of its runs and
    /// the second in three fifths.
    fn labels_at(point: &[f64]) -> Measured {
        let setting = point.first().copied().unwrap_or(0.0);
        if setting < 1.5 {
            vec![vec![1.0, 0.0]]
        } else if setting < 2.5 {
            vec![vec![1.0, 0.4]]
        } else {
            vec![vec![0.8, 0.6]]
        }
    }

    #[test]
    fn under_confirm_the_errors_are_over_the_labels_a_finer_point_repeats() {
        let case = || BenchCase {
            name: "half".into(),
            exact: None,
            inputs: String::new(),
            label_names: vec![vec!["touch A – B".into(), "collide A – B".into()]],
            run: Box::new(|point| {
                Ok(CaseOutput {
                    quantities: labels_at(point),
                    work: None,
                })
            }),
        };
        let points = vec![vec![3.0]];
        let sweep = |confirmation: Option<Vec<f64>>| {
            let anchors = Anchors {
                reference: vec![1.0],
                default: vec![3.0],
                confirmation,
            };
            let mut totals = DefaultTotals::default();
            let (report, _) = sweep_case(
                &CONFIRMED_BENCH,
                &case(),
                &points,
                &anchors,
                None,
                &mut totals,
            )
            .unwrap();
            (report, default_summary(&CONFIRMED_BENCH, &totals))
        };
        let (plain, plain_summary) = sweep(None);
        assert_eq!(plain["decided_labels"]["contact_disagreement"], 2);
        assert!(plain.get("unconfirmed_labels").is_none());
        let error = |summary: &Map<String, Value>| {
            summary["contact_disagreement"]["error"].as_f64().unwrap()
        };
        assert!((error(&plain_summary) - 0.4).abs() < 1e-12);
        let (confirmed, confirmed_summary) = sweep(CONFIRMED_BENCH.confirmation_point(&points));
        assert_eq!(confirmed["decided_labels"]["contact_disagreement"], 1);
        assert_eq!(confirmed["confirmation"], "setting = 2");
        assert_eq!(
            confirmed["unconfirmed_labels"],
            json!([{"measure": "contact_disagreement", "label": "collide A – B",
                    "reference": 0.0, "confirmation": 0.4}])
        );
        // Only the confirmed label counts: the default's error is its miss on it, a fifth.
        assert!((error(&confirmed_summary) - 0.2).abs() < 1e-12);
        let differing = &confirmed["sweep"][0]["differing_labels"];
        assert_eq!(differing.as_array().unwrap().len(), 1, "{differing}");
        assert_eq!(differing[0]["label"], "touch A – B");
    }

    #[test]
    fn errors_are_per_measure_and_a_missing_quantity_is_infinitely_wrong() {
        let reference = vec![vec![0.5, 0.25], vec![1.0]];
        let measures = &scenarios::parts(Scenario::Rope)
            .physics_bench
            .unwrap()
            .errors;
        let got = errors(measures, &vec![vec![0.5, 0.5], vec![0.9]], &reference);
        assert!(
            (got[0] - 0.25).abs() < 1e-15 && (got[1] - 0.1).abs() < 1e-15,
            "{got:?}"
        );
        assert_eq!(
            errors(measures, &vec![vec![0.5], vec![1.0]], &reference),
            vec![f64::INFINITY, 0.0]
        );
        assert!(errors(measures, &vec![vec![0.5, 0.25]], &reference)[1].is_infinite());
        // A mean measure: the share of labels that differ.
        let labels = [ErrorMeasure {
            key: "labels",
            reduction: Reduction::Mean,
            tolerance: None,
            plotted: false,
        }];
        let share = errors(
            &labels,
            &vec![vec![1.0, 0.0, 1.0, 1.0]],
            &vec![vec![1.0, 1.0, 1.0, 0.0]],
        );
        assert!((share[0] - 0.5).abs() < 1e-15, "{share:?}");
        // A decided mean: only where the reference's ensemble agrees (0 or 1), here the first
        // and last labels; the reference's split label (⅓) is left out. None decided: 0.
        let decided = [ErrorMeasure {
            key: "decided",
            reduction: Reduction::DecidedMean,
            tolerance: Some(0.01),
            plotted: false,
        }];
        let reference = vec![vec![1.0, 1.0 / 3.0, 0.0]];
        let got = errors(&decided, &vec![vec![2.0 / 3.0, 1.0, 0.0]], &reference);
        assert!((got[0] - 1.0 / 6.0).abs() < 1e-15, "{got:?}");
        let split = errors(&decided, &vec![vec![1.0]], &vec![vec![0.5]]);
        assert_eq!(split, vec![0.0]);
    }
}
