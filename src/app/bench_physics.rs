//! `bench physics --scenario rope`: the rope simulator's error against its run time over a sweep
//! of time steps, as JSON on stdout and an SVG plot (`--svg FILE`).
//!
//! Mechanisms: an Atwood machine with pulley inertia, the same with a Coulomb bearing torque on
//! its pulley (the rope slides over the bearing), and a two-rope network with a movable pulley,
//! all with closed-form trajectories (constant accelerations while the ropes stay taut), and a
//! load landing on the floor so that its rope goes slack and re-tightens, whose
//! reference is the same simulator at a step 10× finer than the finest swept. Error: the largest
//! difference of any body's height from the reference at the end, m.

use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use serde_json::{Value, json};

use super::bench::print_report;
use super::error::{AppError, Classify as _, user_error};
use crate::physics::rope::{Body, GRAVITY, Mechanism, Mount, Network, Point, Pulley, Rope};

/// Simulated time per run, s.
const DURATION: f64 = 1.0;
/// Steps swept by default, s.
pub(crate) const STEPS: [f64; 8] = [2e-2, 1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4];
/// The step `--dynamics simulate` uses; the sweep shows its error.
pub(crate) const DEFAULT_DT: f64 = 1e-3;

/// One mechanism's sweep: its name and `(dt s, error m, run time ms)` per step.
type Series = (&'static str, Vec<(f64, f64, f64)>);

/// A benchmark mechanism and, when it has one, its closed-form end heights.
struct Case {
    name: &'static str,
    mechanism: Mechanism,
    exact: Option<Vec<f64>>,
}

fn body(name: &str, mass: f64, x: f64, y: f64) -> Body {
    Body {
        name: name.to_string(),
        mass,
        position: [x, y],
        floor_clearance: None,
    }
}

fn pulley(name: &str, radius: f64, inertia: f64, mount: Mount) -> Pulley {
    Pulley {
        name: name.to_string(),
        radius,
        inertia,
        friction_torque: 0.0,
        mount,
    }
}

fn cases() -> Result<Vec<Case>, AppError> {
    let radius = 0.5;
    // Atwood: a = g (m2 − m1) / (m1 + m2 + I/R²).
    let (m1, m2, inertia) = (0.25, 0.15, 0.02);
    let atwood = Mechanism::new(Network {
        bodies: vec![body("A", m1, -radius, -2.0), body("B", m2, radius, -3.0)],
        pulleys: vec![pulley("P", radius, inertia, Mount::Fixed([0.0, 0.0]))],
        ropes: vec![Rope {
            name: "rope".into(),
            path: vec![Point::Body(0), Point::Pulley(0), Point::Body(1)],
        }],
        floor: None,
        turns: Vec::new(),
        drives: Vec::new(),
    })
    .internal()?;
    let a = GRAVITY * (m2 - m1) / (m1 + m2 + inertia / (radius * radius));
    let fall = 0.5 * a * DURATION * DURATION;
    let atwood_exact = vec![-2.0 + fall, -3.0 - fall];

    // The same with a bearing torque τ below the pull (g·|m2 − m1|·R = 0.49 N·m), so A falls
    // with the rope sliding over the bearing: a = (g (m2 − m1) + τ/R) / (m1 + m2 + I/R²) for
    // A (the bearing's τ/R opposes A's fall).
    let torque = 0.2;
    let bearing = Mechanism::new(Network {
        bodies: vec![body("A", m1, -radius, -2.0), body("B", m2, radius, -3.0)],
        pulleys: vec![Pulley {
            friction_torque: torque,
            ..pulley("P", radius, inertia, Mount::Fixed([0.0, 0.0]))
        }],
        ropes: vec![Rope {
            name: "rope".into(),
            path: vec![Point::Body(0), Point::Pulley(0), Point::Body(1)],
        }],
        floor: None,
        turns: Vec::new(),
        drives: Vec::new(),
    })
    .internal()?;
    let a = (GRAVITY * (m2 - m1) + torque / radius) / (m1 + m2 + inertia / (radius * radius));
    let fall = 0.5 * a * DURATION * DURATION;
    let bearing_exact = vec![-2.0 + fall, -3.0 - fall];

    // Two ropes: y_A + y_P = c₁, 2 y_P + y_B = c₂, q̈ = −g (mP − mA − 2 mB)/(mA + mP + 4 mB).
    let (ma, mp, mb) = (0.1, 0.3, 0.05);
    let x = -4.0;
    let network = Mechanism::new(Network {
        bodies: vec![
            body("A", ma, x - radius, -2.0),
            body("P", mp, x + radius, -3.0),
            body("B", mb, x + 4.0 * radius, -2.5),
        ],
        pulleys: vec![
            pulley("S1", radius, 0.0, Mount::Fixed([x, 0.0])),
            pulley("P pulley", radius, 0.0, Mount::Body(1)),
            pulley("S2", radius, 0.0, Mount::Fixed([x + 3.0 * radius, 1.0])),
        ],
        ropes: vec![
            Rope {
                name: "rope 1".into(),
                path: vec![Point::Body(0), Point::Pulley(0), Point::Body(1)],
            },
            Rope {
                name: "rope 2".into(),
                path: vec![
                    Point::Fixed([x, 2.0]),
                    Point::Pulley(1),
                    Point::Pulley(2),
                    Point::Body(2),
                ],
            },
        ],
        floor: None,
        turns: Vec::new(),
        drives: Vec::new(),
    })
    .internal()?;
    let q = -GRAVITY * (mp - ma - 2.0 * mb) / (ma + mp + 4.0 * mb);
    let moved = 0.5 * q * DURATION * DURATION;
    let network_exact = vec![-2.0 - moved, -3.0 + moved, -2.5 - 2.0 * moved];

    // A heavy load lands on the floor; the light one flies on, the rope goes slack and snaps
    // taut again: events, no closed form.
    let mut landing_network = Network {
        bodies: vec![body("A", 1.0, -radius, -2.0), body("B", 0.2, radius, -3.0)],
        pulleys: vec![pulley("P", radius, 0.01, Mount::Fixed([0.0, 0.0]))],
        ropes: vec![Rope {
            name: "rope".into(),
            path: vec![Point::Body(0), Point::Pulley(0), Point::Body(1)],
        }],
        floor: Some(-2.6),
        turns: Vec::new(),
        drives: Vec::new(),
    };
    landing_network.bodies[0].floor_clearance = Some(0.1);
    let landing = Mechanism::new(landing_network).internal()?;
    Ok(vec![
        Case {
            name: "atwood_with_pulley_inertia",
            mechanism: atwood,
            exact: Some(atwood_exact),
        },
        Case {
            name: "atwood_with_bearing_friction",
            mechanism: bearing,
            exact: Some(bearing_exact),
        },
        Case {
            name: "two_rope_network",
            mechanism: network,
            exact: Some(network_exact),
        },
        Case {
            name: "landing_slack_retighten",
            mechanism: landing,
            exact: None,
        },
    ])
}

/// End heights after `DURATION` at step `dt`, and the wall time, ms.
fn simulate(mechanism: &Mechanism, dt: f64) -> Result<(Vec<f64>, f64), AppError> {
    let mut state = mechanism.initial_state();
    let started = Instant::now();
    mechanism.run(&mut state, DURATION, dt).user()?;
    Ok((state.y, started.elapsed().as_secs_f64() * 1e3))
}

pub(crate) fn bench_physics(
    scenario: &str,
    steps: &[f64],
    svg: Option<&Path>,
) -> Result<ExitCode, AppError> {
    if steps.is_empty() || steps.iter().any(|dt| !(dt.is_finite() && *dt > 0.0)) {
        return Err(user_error("bench physics: --dt needs positive time steps"));
    }
    if scenario != "rope" {
        return Err(user_error(format!(
            "bench physics: no simulator for scenario `{scenario}` yet (rope only)"
        )));
    }
    let mut report_cases = Vec::new();
    let mut series: Vec<Series> = Vec::new();
    for case in cases()? {
        let (reference, reference_kind) = if let Some(exact) = &case.exact {
            (exact.clone(), "closed form".to_string())
        } else {
            let fine = steps.iter().copied().fold(f64::INFINITY, f64::min) / 10.0;
            (
                simulate(&case.mechanism, fine)?.0,
                format!("dt = {fine:e} s"),
            )
        };
        let mut points = Vec::new();
        let mut rows = Vec::new();
        for &dt in steps {
            // Best of three for the time; the heights are identical each time.
            let mut best = f64::INFINITY;
            let mut heights = Vec::new();
            for _ in 0..3 {
                let (y, ms) = simulate(&case.mechanism, dt)?;
                best = best.min(ms);
                heights = y;
            }
            let error = heights
                .iter()
                .zip(&reference)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0_f64, f64::max);
            points.push((dt, error, best));
            rows.push(json!({ "dt_s": dt, "max_height_error_m": error, "run_time_ms": best }));
        }
        report_cases.push(json!({
            "mechanism": case.name,
            "reference": reference_kind,
            "sweep": rows,
        }));
        series.push((case.name, points));
    }
    let report: Value = json!({
        "scenario": "rope",
        "simulated_seconds": DURATION,
        "default_dt_s": DEFAULT_DT,
        "cases": report_cases,
    });
    if let Some(path) = svg {
        crate::util::write_atomic(path, svg_plot(&series).as_bytes()).user()?;
    }
    print_report(&report)
}

/// A log–log plot of error (m) against run time (ms), one polyline per mechanism, each point
/// labelled with its step.
fn svg_plot(series: &[Series]) -> String {
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
        r#"<text x="{}" y="24" text-anchor="middle" font-size="15">rope simulator: error at t = {DURATION} s against run time (dt labelled)</text>"#,
        width / 2.0
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
        r#"<text x="18" y="{}" text-anchor="middle" transform="rotate(-90 18 {})">largest height error, m</text>"#,
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
