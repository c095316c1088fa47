//! `bench physics`: a simulator's error against its run time over a sweep of time steps, as
//! JSON on stdout and an SVG plot (`--svg FILE`).
//!
//! The scenario's simulator brings its cases (`physics::bench`, the scenario table's
//! `physics_bench`): each with a closed form, or else a run at a step 10× finer than the finest
//! swept as the reference. Every case runs at every step (best of three for the time; the
//! results are identical each time), and its error is the largest difference of any compared
//! quantity from the reference at the end.

use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use serde_json::{Value, json};

use super::bench::print_report;
use super::error::{AppError, Classify as _, user_error};
use crate::dataset::Scenario;
use crate::physics::bench::{BenchCase, PhysicsBench};
use crate::scenarios;

/// One case's sweep: its name and `(dt s, error m, run time ms)` per step.
type Series = (&'static str, Vec<(f64, f64, f64)>);

/// The quantities of `case` at step `dt`, and the wall time, ms.
fn simulate(case: &BenchCase, dt: f64) -> Result<(Vec<f64>, f64), AppError> {
    let started = Instant::now();
    let quantities = (case.run)(dt).user()?;
    Ok((quantities, started.elapsed().as_secs_f64() * 1e3))
}

pub(crate) fn bench_physics(
    scenario: Option<Scenario>,
    steps: Option<&[f64]>,
    svg: Option<&Path>,
) -> Result<ExitCode, AppError> {
    let with_bench = || scenarios::names_with(|row| row.physics_bench.is_some());
    let scenario = scenario
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
    let steps = steps.unwrap_or(bench.steps);
    if steps.is_empty() || steps.iter().any(|dt| !(dt.is_finite() && *dt > 0.0)) {
        return Err(user_error("bench physics: --dt needs positive time steps"));
    }
    let mut report_cases = Vec::new();
    let mut series: Vec<Series> = Vec::new();
    for case in (bench.cases)().internal()? {
        let (reference, reference_kind) = if let Some(exact) = &case.exact {
            (exact.clone(), "closed form".to_string())
        } else {
            let fine = steps.iter().copied().fold(f64::INFINITY, f64::min) / 10.0;
            (simulate(&case, fine)?.0, format!("dt = {fine:e} s"))
        };
        let mut points = Vec::new();
        let mut rows = Vec::new();
        for &dt in steps {
            // Best of three for the time; the results are identical each time.
            let mut best = f64::INFINITY;
            let mut quantities = Vec::new();
            for _ in 0..3 {
                let (values, ms) = simulate(&case, dt)?;
                best = best.min(ms);
                quantities = values;
            }
            let error = quantities
                .iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0_f64, f64::max);
            points.push((dt, error, best));
            rows.push(json!({ "dt_s": dt, bench.error: error, "run_time_ms": best }));
        }
        report_cases.push(json!({
            "mechanism": case.name,
            "reference": reference_kind,
            "sweep": rows,
        }));
        series.push((case.name, points));
    }
    let report: Value = json!({
        "scenario": scenario.name(),
        "simulated_seconds": bench.duration,
        "default_dt_s": bench.default_dt,
        "cases": report_cases,
    });
    if let Some(path) = svg {
        crate::util::write_atomic(path, svg_plot(&series, bench).as_bytes()).user()?;
    }
    print_report(&report)
}

/// A log–log plot of error (m) against run time (ms), one polyline per mechanism, each point
/// labelled with its step.
fn svg_plot(series: &[Series], bench: &PhysicsBench) -> String {
    let (width, height, margin) = (720.0, 480.0, 70.0);
    let all = series.iter().flat_map(|(_, p)| p.iter());
    let floor = 1e-12;
    let (mut x_min, mut x_max, mut y_min, mut y_max) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(_, error, ms) in all {
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
        r#"<text x="{}" y="24" text-anchor="middle" font-size="15">{}: error at t = {} s against run time (dt labelled)</text>"#,
        width / 2.0,
        bench.title,
        bench.duration
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
        r#"<text x="18" y="{}" text-anchor="middle" transform="rotate(-90 18 {})">largest error, m</text>"#,
        height / 2.0,
        height / 2.0
    );
    for (index, (name, points)) in series.iter().enumerate() {
        let colour = colours[index % colours.len()];
        let path: Vec<String> = points
            .iter()
            .map(|&(_, error, ms)| {
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
        for &(dt, error, ms) in points {
            let (x, y) = (sx(ms.max(1e-6).log10()), sy(error.max(floor).log10()));
            let _ = writeln!(
                svg,
                r#"<circle cx="{x:.1}" cy="{y:.1}" r="3" fill="{colour}"/><text x="{:.1}" y="{:.1}" font-size="10">{dt:e}</text>"#,
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
