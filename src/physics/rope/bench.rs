//! `bench physics` for the rope simulator: an Atwood machine with pulley inertia, the same with
//! a Coulomb bearing torque on its pulley (the rope slides over the bearing), and a two-rope
//! network with a movable pulley, all with closed-form trajectories (constant accelerations
//! while the ropes stay taut), and a load landing on the floor so that its rope goes slack and
//! re-tightens, whose reference is the same simulator at a step 10× finer than the finest
//! swept. Error: the largest difference of any body's height from the reference at the end, m.

use super::{Body, GRAVITY, Mechanism, Mount, Network, Point, Pulley, Rope};
use std::path::PathBuf;

use crate::physics::bench::{
    BenchCase, BenchError, CaseOutput, ErrorMeasure, Parameter, PhysicsBench, Reduction, Reference,
};

/// Simulated time per run, s.
const DURATION: f64 = 1.0;

/// The rope simulator's benchmark.
pub const BENCH: PhysicsBench = PhysicsBench {
    duration: DURATION,
    parameters: &[Parameter {
        key: "dt_s",
        flag: "--dt",
        label: "dt",
        follows_sweep: false,
    }],
    sweep: &[
        &[2e-2],
        &[1e-2],
        &[5e-3],
        &[2e-3],
        &[1e-3],
        &[5e-4],
        &[2e-4],
        &[1e-4],
    ],
    default: &[1e-3],
    reference: Reference::TenfoldFiner,
    confirmation: None,
    errors: &[ErrorMeasure {
        key: "max_height_error_m",
        reduction: Reduction::Largest,
        tolerance: None,
        plotted: true,
    }],
    error_axis: "largest error, m",
    repeats: 3,
    title: "rope simulator",
    uses_videos: false,
    cases,
};

/// A case running `mechanism` for [`DURATION`]: the bodies' end heights.
fn case(name: &'static str, mechanism: Mechanism, exact: Option<Vec<f64>>) -> BenchCase {
    BenchCase {
        name: name.to_string(),
        exact: exact.map(|heights| vec![heights]),
        inputs: String::new(),
        label_names: Vec::new(),
        run: Box::new(move |point| {
            let dt = point.first().copied().unwrap_or(f64::NAN);
            let mut state = mechanism.initial_state();
            mechanism
                .run(&mut state, DURATION, dt)
                .map_err(|error| BenchError::new(name, error))?;
            Ok(CaseOutput {
                quantities: vec![state.y],
                work: None,
            })
        }),
    }
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

fn cases(_videos: &[PathBuf]) -> Result<Vec<BenchCase>, BenchError> {
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
    .map_err(|error| BenchError::new("mechanism", error))?;
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
    .map_err(|error| BenchError::new("mechanism", error))?;
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
    .map_err(|error| BenchError::new("mechanism", error))?;
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
    let landing = Mechanism::new(landing_network)
        .map_err(|error| BenchError::new("landing_slack_retighten", error))?;
    Ok(vec![
        case("atwood_with_pulley_inertia", atwood, Some(atwood_exact)),
        case("atwood_with_bearing_friction", bearing, Some(bearing_exact)),
        case("two_rope_network", network, Some(network_exact)),
        case("landing_slack_retighten", landing, None),
    ])
}
