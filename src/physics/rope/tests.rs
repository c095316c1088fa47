//! Analytic validation: closed forms for the Atwood machine, a movable-pulley compound system
//! and a two-rope network; conservation of rope length and energy; stiff and extreme cases.

use super::*;

const R: f64 = 0.5;

fn body(name: &str, mass: f64, x: f64, y: f64) -> Body {
    Body {
        name: name.to_string(),
        mass,
        position: [x, y],
        floor_clearance: None,
    }
}

fn static_pulley(name: &str, x: f64, y: f64, inertia: f64) -> Pulley {
    Pulley {
        name: name.to_string(),
        radius: R,
        inertia,
        friction_torque: 0.0,
        mount: Mount::Fixed([x, y]),
    }
}

fn rope(name: &str, path: Vec<Point>) -> Rope {
    Rope {
        name: name.to_string(),
        path,
    }
}

/// Within 1e-6 relative (1e-9 absolute near zero: the rope geometry's derivatives are taken
/// by differences, exact to about 1e-11).
fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-6 * want.abs() + 1e-9,
        "{what}: got {got}, want {want}"
    );
}

/// Two loads on one rope over a static pulley at the origin, hanging under its rims.
fn atwood(m1: f64, m2: f64, inertia: f64) -> Mechanism {
    atwood_with_bearing(m1, m2, inertia, 0.0)
}

/// [`atwood`] with a bearing friction torque `torque` (N·m) on the pulley.
fn atwood_with_bearing(m1: f64, m2: f64, inertia: f64, torque: f64) -> Mechanism {
    Mechanism::new(atwood_network(m1, m2, inertia, torque)).unwrap()
}

/// The network of [`atwood_with_bearing`], unchecked.
fn atwood_network(m1: f64, m2: f64, inertia: f64, torque: f64) -> Network {
    Network {
        bodies: vec![body("A", m1, -R, -2.0), body("B", m2, R, -3.0)],
        pulleys: vec![Pulley {
            friction_torque: torque,
            ..static_pulley("P", 0.0, 0.0, inertia)
        }],
        ropes: vec![rope(
            "rope",
            vec![Point::Body(0), Point::Pulley(0), Point::Body(1)],
        )],
        floor: None,
        turns: Vec::new(),
        drives: Vec::new(),
    }
}

#[test]
fn atwood_machine_acceleration_and_tension() {
    for (m1, m2, inertia) in [(0.25, 0.15, 0.0), (0.2, 0.5, 0.0), (0.3, 0.1, 0.02)] {
        let mechanism = atwood(m1, m2, inertia);
        let (a, tensions) = mechanism.accelerations(&mechanism.initial_state()).unwrap();
        let effective = m1 + m2 + inertia / (R * R);
        let expected = GRAVITY * (m2 - m1) / effective;
        close(a[0], expected, "a of A");
        close(a[1], -expected, "a of B");
        // The reported tension is the last segment's (B's side): m2 (g + a2). A's side differs
        // by the pulley's I·α/R; with an ideal pulley both are 2 m1 m2 g / (m1 + m2).
        close(tensions[0], m2 * (GRAVITY - expected), "tension");
        if inertia == 0.0 {
            close(
                tensions[0],
                2.0 * m1 * m2 * GRAVITY / (m1 + m2),
                "ideal tension",
            );
        }
    }
}

#[test]
fn atwood_trajectory_converges_to_the_closed_form_and_turns_the_pulley() {
    let (m1, m2) = (0.25, 0.15);
    let mechanism = atwood(m1, m2, 0.0);
    let a = GRAVITY * (m2 - m1) / (m1 + m2);
    let duration = 0.5;
    let mut errors = Vec::new();
    for dt in [1e-2, 1e-3, 1e-4] {
        let mut state = mechanism.initial_state();
        mechanism.run(&mut state, duration, dt).unwrap();
        let exact = -2.0 + 0.5 * a * duration * duration;
        errors.push((state.y[0] - exact).abs());
        // Rope length conserved to well below a millimetre.
        let drift = (mechanism.rope_length(0, &state.y) - mechanism.rest_lengths()[0]).abs();
        assert!(drift < 1e-9, "rope length drift {drift} at dt {dt}");
        // A goes down on the left: the rope over the top runs right to left, feeding A's side,
        // so the pulley turns counter-clockwise (as the real video's pulleys do: the side of
        // the descending load turns down).
        assert!(state.angles[0] > 0.5, "angle {}", state.angles[0]);
        close(
            state.angles[0],
            (state.y[0] + 2.0).abs() / R,
            "angle = displacement / radius",
        );
    }
    // First order in dt: each tenfold smaller step cuts the error about tenfold.
    assert!(
        errors[1] < errors[0] / 5.0 && errors[2] < errors[1] / 5.0,
        "{errors:?}"
    );
    assert!(errors[2] < 1e-4, "{errors:?}");
}

#[test]
fn movable_pulley_compound_system() {
    // A rope from a ceiling point down under a movable pulley (mass mp, carrying a load mb, as one
    // body), up over a static pulley, down to a load m.
    for (m, big) in [(0.2, 0.3), (0.15, 0.5), (0.25, 0.4)] {
        let ceiling = [-2.0 * R, 2.0];
        let mechanism = Mechanism::new(Network {
            bodies: vec![
                body("pulley+load", big, -R, -3.0),
                body("m", m, 2.0 * R, -2.0),
            ],
            pulleys: vec![
                Pulley {
                    name: "movable".into(),
                    radius: R,
                    inertia: 0.0,
                    friction_torque: 0.0,
                    mount: Mount::Body(0),
                },
                static_pulley("static", R, 2.0, 0.0),
            ],
            ropes: vec![rope(
                "main",
                vec![
                    Point::Fixed(ceiling),
                    Point::Pulley(0),
                    Point::Pulley(1),
                    Point::Body(1),
                ],
            )],
            floor: None,
            turns: Vec::new(),
            drives: Vec::new(),
        })
        .unwrap();
        let (a, tensions) = mechanism.accelerations(&mechanism.initial_state()).unwrap();
        // Constraint 2 y_p + y_m = const: a_m = 2 g (M − 2m) / (4m + M), a_p = −a_m / 2.
        let a_m = 2.0 * GRAVITY * (big - 2.0 * m) / (4.0 * m + big);
        close(a[1], a_m, "a of m");
        close(a[0], -a_m / 2.0, "a of the movable pulley");
        close(tensions[0], m * (GRAVITY + a_m), "tension");
    }
}

#[test]
fn two_rope_network_matches_the_reduced_coordinate_closed_form() {
    // Rope 1: load A over static S1 down to the movable pulley P (tied to its frame).
    // Rope 2: a ceiling point down under P, up over static S2, down to load B.
    // Every segment is vertical: y_A + y_P = c₁ and 2 y_P + y_B = c₂. With q = y_P,
    // T = ½ (mA + mP + 4 mB) q̇² and V = g (mP − mA − 2 mB) q.
    for (ma, mp, mb) in [(0.25, 0.2, 0.15), (0.1, 0.3, 0.05), (0.2, 0.2, 0.2)] {
        let x = -4.0;
        let mechanism = Mechanism::new(Network {
            bodies: vec![
                body("A", ma, x - R, -2.0),
                body("P", mp, x + R, -3.0),
                body("B", mb, x + 4.0 * R, -2.5),
            ],
            pulleys: vec![
                static_pulley("S1", x, 0.0, 0.0),
                Pulley {
                    name: "P pulley".into(),
                    radius: R,
                    inertia: 0.0,
                    friction_torque: 0.0,
                    mount: Mount::Body(1),
                },
                static_pulley("S2", x + 3.0 * R, 1.0, 0.0),
            ],
            ropes: vec![
                rope(
                    "rope 1",
                    vec![Point::Body(0), Point::Pulley(0), Point::Body(1)],
                ),
                rope(
                    "rope 2",
                    vec![
                        Point::Fixed([x, 2.0]),
                        Point::Pulley(1),
                        Point::Pulley(2),
                        Point::Body(2),
                    ],
                ),
            ],
            floor: None,
            turns: Vec::new(),
            drives: Vec::new(),
        })
        .unwrap();
        let (a, tensions) = mechanism.accelerations(&mechanism.initial_state()).unwrap();
        let q = -GRAVITY * (mp - ma - 2.0 * mb) / (ma + mp + 4.0 * mb);
        close(a[1], q, "a of P");
        close(a[0], -q, "a of A");
        close(a[2], -2.0 * q, "a of B");
        close(tensions[0], ma * (GRAVITY - q), "tension of rope 1");
        close(tensions[1], mb * (GRAVITY - 2.0 * q), "tension of rope 2");
        // Both ropes keep their lengths along the trajectory.
        let mut state = mechanism.initial_state();
        mechanism.run(&mut state, 0.3, 1e-3).unwrap();
        for rope in 0..2 {
            let drift = mechanism.rope_length(rope, &state.y) - mechanism.rest_lengths()[rope];
            assert!(drift.abs() < 1e-9, "rope {rope} drift {drift}");
        }
    }
}

#[test]
fn energy_is_conserved_with_friction_off() {
    let mechanism = atwood(0.25, 0.15, 0.02);
    let mut state = mechanism.initial_state();
    let start = mechanism.energy(&state);
    mechanism.run(&mut state, 0.5, 1e-4).unwrap();
    let end = mechanism.energy(&state);
    let moved = 0.25 * GRAVITY * (state.y[0] + 2.0).abs();
    assert!(
        (end - start).abs() < 1e-3 * moved,
        "energy {start} → {end}, work scale {moved}"
    );
}

#[test]
fn extreme_mass_ratios_stay_finite_and_go_the_right_way() {
    for (m1, m2) in [(1e-3, 1.0), (1.0, 1e-3), (1e3, 1.0), (1.0, 1e3)] {
        let mechanism = atwood(m1, m2, 0.0);
        let (a, _) = mechanism.accelerations(&mechanism.initial_state()).unwrap();
        close(a[0], GRAVITY * (m2 - m1) / (m1 + m2), "a of A");
        let mut state = mechanism.initial_state();
        mechanism.run(&mut state, 0.3, 1e-3).unwrap();
        assert!(state.y.iter().chain(&state.v).all(|v| v.is_finite()));
        assert!(
            (state.y[0] + 2.0) * (m2 - m1) > 0.0,
            "A moved the wrong way"
        );
        assert!(a[0].abs() <= GRAVITY * (1.0 + 1e-12));
    }
}

#[test]
fn nearly_equal_masses_move_the_heavier_side_down() {
    let m = 0.2;
    let mechanism = atwood(m * (1.0 + 1e-9), m, 0.0);
    let (a, _) = mechanism.accelerations(&mechanism.initial_state()).unwrap();
    assert!(a[0] < 0.0 && a[0] > -1e-8, "{}", a[0]);
    let mut state = mechanism.initial_state();
    mechanism.run(&mut state, 1.0, 1e-3).unwrap();
    assert!(state.y[0] < -2.0, "{}", state.y[0]);
    assert!((state.y[0] + 2.0).abs() < 1e-6);
}

#[test]
fn a_load_reaching_its_pulley_stops_there() {
    // B (heavy) pulls A up; A starts 0.6 m under the rim and stops at its clearance.
    let mut network = Network {
        bodies: vec![body("A", 0.1, -R, -0.6), body("B", 1.0, R, -3.0)],
        pulleys: vec![static_pulley("P", 0.0, 0.0, 0.0)],
        ropes: vec![rope(
            "rope",
            vec![Point::Body(0), Point::Pulley(0), Point::Body(1)],
        )],
        floor: None,
        turns: Vec::new(),
        drives: Vec::new(),
    };
    network.bodies[0].floor_clearance = Some(0.05);
    let mechanism = Mechanism::new(network).unwrap();
    let mut state = mechanism.initial_state();
    mechanism.run(&mut state, 1.0, 1e-3).unwrap();
    // The segment's minimum is the pulley radius plus A's clearance.
    let top = -(R + 0.05);
    assert!((state.y[0] - top).abs() < 1e-6, "A at {}", state.y[0]);
    assert!(state.v.iter().all(|v| v.abs() < 1e-6), "{:?}", state.v);
}

#[test]
fn a_load_on_the_floor_lets_its_rope_go_slack() {
    // A (heavy) lands on the floor; B flies on upward, the rope goes slack, B falls back and
    // the rope tightens again; nothing passes through the floor.
    let mut network = Network {
        bodies: vec![body("A", 1.0, -R, -2.0), body("B", 0.2, R, -3.0)],
        pulleys: vec![static_pulley("P", 0.0, 0.0, 0.0)],
        ropes: vec![rope(
            "rope",
            vec![Point::Body(0), Point::Pulley(0), Point::Body(1)],
        )],
        floor: Some(-2.6),
        turns: Vec::new(),
        drives: Vec::new(),
    };
    network.bodies[0].floor_clearance = Some(0.1);
    let mechanism = Mechanism::new(network).unwrap();
    let mut state = mechanism.initial_state();
    let mut slack_seen = false;
    for _ in 0..3000 {
        mechanism.step(&mut state, 1e-3).unwrap();
        assert!(
            state.y[0] >= -2.5 - 1e-6,
            "A below the floor: {}",
            state.y[0]
        );
        let length = mechanism.rope_length(0, &state.y);
        assert!(
            length <= mechanism.rest_lengths()[0] + 1e-6,
            "rope stretched"
        );
        if length < mechanism.rest_lengths()[0] - 1e-3 {
            slack_seen = true;
            assert!(state.tensions[0].abs() < 1e-9);
        }
    }
    assert!(slack_seen, "the rope never went slack");
}

#[test]
fn a_chain_of_six_pulleys_is_finite_and_balanced() {
    // Six static pulleys in a row, one rope over all of them, a load at each end: the rope
    // runs along the top (a straight pass is taken as over the top); equal loads stay, unequal
    // ones move the heavier down, and every pulley turns alike.
    for (m1, m2) in [(0.2, 0.2), (0.25, 0.15)] {
        let pulleys: Vec<Pulley> = (0..6)
            .map(|i| static_pulley(&format!("P{i}"), f64::from(i) * 3.0 * R, 0.0, 0.01))
            .collect();
        let mut path = vec![Point::Body(0)];
        path.extend((0..6).map(Point::Pulley));
        path.push(Point::Body(1));
        let mechanism = Mechanism::new(Network {
            bodies: vec![body("A", m1, -R, -2.0), body("B", m2, 15.0 * R + R, -2.0)],
            pulleys,
            ropes: vec![rope("rope", path)],
            floor: None,
            turns: Vec::new(),
            drives: Vec::new(),
        })
        .unwrap();
        let (a, tensions) = mechanism.accelerations(&mechanism.initial_state()).unwrap();
        let effective = m1 + m2 + 6.0 * 0.01 / (R * R);
        close(a[0], GRAVITY * (m2 - m1) / effective, "a of A");
        assert!(tensions[0] > 0.0);
        let mut state = mechanism.initial_state();
        mechanism.run(&mut state, 0.5, 1e-3).unwrap();
        // Every pulley turns the same way by the same angle (the same rope speed).
        for angle in &state.angles {
            close(*angle, state.angles[0], "pulley angles");
        }
    }
}

#[test]
fn zero_length_segments_and_bad_parameters_are_typed_errors() {
    let error = Mechanism::new(Network {
        bodies: vec![body("A", 0.2, -R, 0.0), body("B", 0.2, R, -2.0)],
        pulleys: vec![static_pulley("P", 0.0, 0.0, 0.0)],
        ropes: vec![rope(
            "rope",
            vec![Point::Body(0), Point::Pulley(0), Point::Body(1)],
        )],
        floor: None,
        turns: Vec::new(),
        drives: Vec::new(),
    })
    .unwrap_err();
    assert_eq!(
        error,
        SimulationError::DegenerateSegment {
            rope: "rope".into(),
            segment: 0
        }
    );
    let error = Mechanism::new(Network {
        bodies: vec![body("A", f64::NAN, 0.0, 0.0)],
        ..Network::default()
    })
    .unwrap_err();
    assert!(error.to_string().contains("A: mass NaN kg"), "{error}");
    let mechanism = atwood(0.2, 0.1, 0.0);
    let mut state = mechanism.initial_state();
    assert!(mechanism.run(&mut state, 1.0, 0.0).is_err());
}

#[test]
fn golden_trajectory_hash() {
    // Bit-for-bit determinism: the same inputs give the same trajectory on every run and
    // machine (f64, fixed operation order, no parallel reductions). Update the hash only for a
    // deliberate change of the integrator, and say so in the commit.
    let mechanism = atwood(0.25, 0.15, 0.02);
    let mut state = mechanism.initial_state();
    let mut bytes = Vec::new();
    for _ in 0..100 {
        mechanism.run(&mut state, 0.01, 1e-3).unwrap();
        for value in state
            .y
            .iter()
            .chain(&state.v)
            .chain(&state.angles)
            .chain(&state.tensions)
        {
            bytes.extend_from_slice(&value.to_bits().to_le_bytes());
        }
    }
    assert_eq!(
        crate::util::content_hash(&bytes),
        "932126e0e289c4193ea1736001cae41dd54c2142247b07f0d98599c9b686d634"
    );
}

#[test]
fn the_real_videos_purple_rope_turns_its_pulleys_as_annotated() {
    // The Purple Rope of the released video (pulley_group/0, metaSamplingData positions): the
    // Purple Cube (0.2 kg) under Blue's left rim, over Blue and the Gray pulley, down across to
    // the left rim of the Pink pulley straight below Gray, down to the Green Cube (0.25 kg). The
    // tracked rope particles show it passing Pink on Pink's left, so the path turns
    // counter-clockwise there, which the centres alone (Gray straight above) cannot tell.
    let radius = 1.48;
    let pulley = |name: &str, x: f64, y: f64| Pulley {
        name: name.into(),
        radius,
        inertia: 0.0,
        friction_torque: 0.0,
        mount: Mount::Fixed([x, y]),
    };
    let network = Network {
        bodies: vec![
            body("Purple Cube", 0.2, -24.61, 6.4),
            body("Green Cube", 0.25, -20.91, -5.6),
        ],
        pulleys: vec![
            pulley("Blue", -23.13, 12.0),
            pulley("Gray", -19.43, 20.0),
            pulley("Pink", -19.43, 0.0),
        ],
        ropes: vec![rope(
            "Purple Rope",
            vec![
                Point::Body(0),
                Point::Pulley(0),
                Point::Pulley(1),
                Point::Pulley(2),
                Point::Body(1),
            ],
        )],
        floor: None,
        turns: vec![(0, 3, Turn::CounterClockwise)],
        drives: Vec::new(),
    };
    // Inferred from the centres alone, Pink would turn the wrong way.
    let guessed = Mechanism::new(Network {
        turns: Vec::new(),
        drives: Vec::new(),
        ..network.clone()
    })
    .unwrap();
    let mut state = guessed.initial_state();
    guessed.run(&mut state, 0.5, 1e-3).unwrap();
    assert!(state.angles[2] < 0.0, "{:?}", state.angles);

    let mechanism = Mechanism::new(network).unwrap();
    let mut state = mechanism.initial_state();
    mechanism.run(&mut state, 1.0, 1e-3).unwrap();
    // ResultMotion: Purple Cube +1, Green Cube −1.
    assert!(
        state.y[0] > 6.4 + 0.1 && state.y[1] < -5.6 - 0.1,
        "{:?}",
        state.y
    );
    // ResultRotation (camera mirrored: +1 is clockwise as drawn): Blue +1, Gray +1, Pink −1.
    assert!(state.angles[0] < -0.1, "Blue {:?}", state.angles);
    assert!(state.angles[1] < -0.1, "Gray {:?}", state.angles);
    assert!(state.angles[2] > 0.1, "Pink {:?}", state.angles);
    // The rope keeps its length, arcs included, although its wrap on Blue and Pink changes.
    let drift = mechanism.rope_length(0, &state.y) - mechanism.rest_lengths()[0];
    assert!(drift.abs() < 1e-6, "drift {drift}");
}

#[test]
fn a_pulled_anchor_lifts_its_load_and_turns_the_pulley() {
    // A ceiling anchor above the pulley's left rim, the rope down past the rim (touching it on
    // the pulley's left, a counter-clockwise turn) to a load under it; the anchor is pulled up
    // 2 m at 1 m/s.
    let anchor = [-R, 3.0];
    let mechanism = Mechanism::new(Network {
        bodies: vec![body("load", 0.2, -R, -4.0)],
        pulleys: vec![static_pulley("P", 0.0, 0.0, 0.0)],
        ropes: vec![rope(
            "rope",
            vec![Point::Fixed(anchor), Point::Pulley(0), Point::Body(0)],
        )],
        floor: None,
        turns: vec![(0, 1, Turn::CounterClockwise)],
        drives: vec![Drive {
            point: DrivenPoint::Fixed(anchor),
            velocity: 1.0,
            start: 0.0,
            distance: 2.0,
        }],
    })
    .unwrap();
    let mut state = mechanism.initial_state();
    mechanism.run(&mut state, 3.0, 1e-3).unwrap();
    // The load hangs from the anchor and rises by what the anchor moved.
    assert!((state.y[0] + 2.0).abs() < 1e-2, "load at {}", state.y[0]);
    // Rope flows backwards (towards the anchor) over a counter-clockwise turn: clockwise, by
    // 2 m of rope.
    assert!(
        (state.angles[0] + 2.0 / R).abs() < 1e-2,
        "angle {}",
        state.angles[0]
    );
    assert!(
        state.v[0].abs() < 1e-6,
        "the load stops when the anchor does"
    );
}

// Bearing friction. A Coulomb bearing torque τ on a pulley of radius R carries up to τ/R of
// tension difference across the pulley at rest; once the rope flows over it, it resists with
// exactly τ/R against the flow.

/// Semi-implicit Euler from rest under a constant acceleration `a` overshoots the closed form
/// `½·a·T²` by exactly `½·a·dt·T` (its first-order error): `y_n = ½·a·dt²·n(n+1)`.
fn euler_offset(a: f64, dt: f64, duration: f64) -> f64 {
    0.5 * a * dt * duration
}

/// `got` is the closed form `exact` plus the semi-implicit Euler offset of `a`, to 1e-6 of the
/// offset (1e-10 m absolute).
fn first_order(got: f64, exact: f64, a: f64, dt: f64, duration: f64, what: &str) {
    let offset = euler_offset(a, dt, duration);
    assert!(
        (got - exact - offset).abs() <= 1e-6 * offset.abs() + 1e-10,
        "{what} at dt {dt}: got {got}, closed form {exact}, expected offset {offset}"
    );
}

/// Largest height change from the start, m.
fn largest_move(mechanism: &Mechanism, state: &State) -> f64 {
    state
        .y
        .iter()
        .zip(&mechanism.initial_state().y)
        .map(|(y, start)| (y - start).abs())
        .fold(0.0, f64::max)
}

#[test]
fn atwood_with_bearing_friction_slides_at_the_closed_form() {
    // a = (g·|m2 − m1| − τ/R) / (m1 + m2 + I/R²); the heavier side's tension exceeds the
    // lighter side's by τ/R + I·a/R².
    for (m1, m2, inertia, torque) in [
        (0.15, 0.25, 0.0, 0.1),
        (0.15, 0.25, 0.02, 0.2),
        (0.3, 0.1, 0.02, 0.3),
    ] {
        let mechanism = atwood_with_bearing(m1, m2, inertia, torque);
        let effective = m1 + m2 + inertia / (R * R);
        // +1 when B is the heavier (A rises, and the pulley turns clockwise).
        let d = (m2 - m1).signum();
        let magnitude = (GRAVITY * (m2 - m1).abs() - torque / R) / effective;
        let check = |solution: &Instantaneous, magnitude: f64, what: &str| {
            close(solution.accelerations[0], d * magnitude, what);
            close(solution.accelerations[1], -d * magnitude, what);
            // B's side is the reported tension; A's follows from A's own equation of motion.
            let t_b = solution.tensions[0];
            let t_a = m1 * (GRAVITY + solution.accelerations[0]);
            close(t_b, m2 * (GRAVITY - d * magnitude), what);
            close(
                d * (t_b - t_a),
                torque / R + inertia * magnitude / (R * R),
                what,
            );
        };
        // From rest the bearing starts to slip at once (the static branch, a boxed force).
        let start = mechanism.initial_state();
        let solution = mechanism.instantaneous(&start).unwrap();
        check(&solution, magnitude, "from rest");
        // The bearing's full torque, against the turning (clockwise turning when d = +1).
        close(solution.friction_torques[0], d * torque, "bearing torque");
        // Moving with the pull: the same (the sliding branch, a known force).
        let mut moving = start.clone();
        moving.v = vec![d * 0.3, -d * 0.3];
        check(
            &mechanism.instantaneous(&moving).unwrap(),
            magnitude,
            "sliding with the pull",
        );
        // Moving against the pull: the bearing now brakes with the pull, a = (g·Δm + τ/R)/M.
        moving.v = vec![-d * 0.3, d * 0.3];
        let braking = (GRAVITY * (m2 - m1).abs() + torque / R) / effective;
        let solution = mechanism.instantaneous(&moving).unwrap();
        close(solution.accelerations[0], d * braking, "braking");
        close(solution.friction_torques[0], -d * torque, "braking torque");

        // Stepping: the closed form plus the first-order offset ½·a·dt·T, at every step.
        let duration = 0.5;
        for dt in [1e-2, 1e-3, 1e-4] {
            let mut state = mechanism.initial_state();
            mechanism.run(&mut state, duration, dt).unwrap();
            let a = d * magnitude;
            first_order(
                state.y[0],
                -2.0 + 0.5 * a * duration * duration,
                a,
                dt,
                duration,
                "A",
            );
            first_order(
                state.y[1],
                -3.0 - 0.5 * a * duration * duration,
                -a,
                dt,
                duration,
                "B",
            );
            close(state.tensions[0], m2 * (GRAVITY - a), "stepped tension");
            close(
                state.friction_torques[0],
                d * torque,
                "stepped bearing torque",
            );
            // The pulley turns by the rope that flowed over it (counter-clockwise as A falls).
            close(state.angles[0], -(state.y[0] + 2.0) / R, "angle");
        }
    }
}

#[test]
fn a_bearing_holds_below_its_torque_and_slips_just_above() {
    let (m1, m2, inertia) = (0.2, 0.25, 0.02);
    // The tension difference that holding the loads takes, N, and the torque it needs, N·m.
    let pull = GRAVITY * (m2 - m1);
    let threshold = pull * R;
    let duration = 2.0;

    // 1% more torque than that: nothing moves, and the bearing carries exactly the imbalance.
    let mechanism = atwood_with_bearing(m1, m2, inertia, 1.01 * threshold);
    let start = mechanism.initial_state();
    let solution = mechanism.instantaneous(&start).unwrap();
    assert!(
        solution.accelerations.iter().all(|a| a.abs() < 1e-9),
        "{:?}",
        solution.accelerations
    );
    close(solution.tensions[0], m2 * GRAVITY, "held tension");
    // B would pull A up and turn the pulley clockwise; the bearing holds counter-clockwise.
    close(solution.friction_torques[0], threshold, "holding torque");
    let mut state = start.clone();
    mechanism.run(&mut state, duration, 1e-3).unwrap();
    let moved = largest_move(&mechanism, &state);
    assert!(moved < 1e-9, "held loads moved {moved} m");
    assert!(
        state.angles[0] == 0.0,
        "a held pulley turned {}",
        state.angles[0]
    );
    close(state.tensions[0], m2 * GRAVITY, "stepped held tension");
    close(
        state.friction_torques[0],
        threshold,
        "stepped holding torque",
    );

    // 1% less: it slips, a = 0.01·g·Δm / (m1 + m2 + I/R²).
    let mechanism = atwood_with_bearing(m1, m2, inertia, 0.99 * threshold);
    let a = (pull - 0.99 * threshold / R) / (m1 + m2 + inertia / (R * R));
    let solution = mechanism.instantaneous(&start).unwrap();
    close(solution.accelerations[0], a, "a just above the threshold");
    let dt = 1e-3;
    let mut state = mechanism.initial_state();
    mechanism.run(&mut state, duration, dt).unwrap();
    first_order(
        state.y[0],
        -2.0 + 0.5 * a * duration * duration,
        a,
        dt,
        duration,
        "A just above the threshold",
    );
    assert!(
        state.y[0] + 2.0 > 0.01,
        "A rose only {} m",
        state.y[0] + 2.0
    );
    close(state.angles[0], -(state.y[0] + 2.0) / R, "angle");
}

/// A rope from A over two static pulleys side by side (the rope along their tops) down to B,
/// each pulley with inertia `inertia` and its own bearing torque.
fn chain_with_bearings(m1: f64, m2: f64, inertia: f64, torques: [f64; 2]) -> Mechanism {
    Mechanism::new(Network {
        bodies: vec![body("A", m1, -R, -2.0), body("B", m2, 4.0 * R, -3.0)],
        pulleys: vec![
            Pulley {
                friction_torque: torques[0],
                ..static_pulley("P0", 0.0, 0.0, inertia)
            },
            Pulley {
                friction_torque: torques[1],
                ..static_pulley("P1", 3.0 * R, 0.0, inertia)
            },
        ],
        ropes: vec![rope(
            "rope",
            vec![
                Point::Body(0),
                Point::Pulley(0),
                Point::Pulley(1),
                Point::Body(1),
            ],
        )],
        floor: None,
        turns: Vec::new(),
        drives: Vec::new(),
    })
    .unwrap()
}

#[test]
fn friction_work_balances_the_lost_energy() {
    // E(0) − E(t) = Σ τ·|Δθ| over the pulleys, while the rope slides over both bearings.
    let (m1, m2, inertia, torques) = (0.15, 0.3, 0.01, [0.1, 0.15]);
    let mechanism = chain_with_bearings(m1, m2, inertia, torques);
    let a =
        (GRAVITY * (m2 - m1) - (torques[0] + torques[1]) / R) / (m1 + m2 + 2.0 * inertia / (R * R));
    let solution = mechanism.instantaneous(&mechanism.initial_state()).unwrap();
    close(solution.accelerations[0], a, "a of A over two bearings");
    let mut state = mechanism.initial_state();
    let start = mechanism.energy(&state);
    mechanism.run(&mut state, 0.5, 1e-4).unwrap();
    let lost = start - mechanism.energy(&state);
    let work: f64 = torques
        .iter()
        .zip(&state.angles)
        .map(|(torque, angle)| torque * angle.abs())
        .sum();
    // Both pulleys turned by the same rope: by the rope length over R.
    close(state.angles[0], state.angles[1], "angles");
    close(state.angles[0].abs(), (state.y[0] + 2.0) / R, "angle");
    assert!(work > 0.1, "friction work {work} J");
    assert!(
        (lost - work).abs() < 1e-3 * work,
        "energy lost {lost} J, friction work {work} J"
    );
    // What remains is semi-implicit Euler's own first-order energy error under a constant
    // acceleration, ½·M·a²·dt·T (4.5e-5 J here, 3.9e-4 of the work).
    let effective = m1 + m2 + 2.0 * inertia / (R * R);
    let integrator = 0.5 * effective * a * a * 1e-4 * 0.5;
    assert!(
        (lost - work - integrator).abs() < 1e-3 * integrator,
        "energy lost {lost} J, friction work {work} J, integrator error {integrator} J"
    );
}

#[test]
fn bearings_on_a_movable_pulley_system_match_the_reduced_closed_form() {
    // The compound system of `movable_pulley_compound_system` with bearings on both pulleys.
    // With q = y_m (and y_p = (c − q)/2) the rope runs over the static pulley at |q̇| and over
    // the movable one at |q̇|/2, so the bearings' generalised force is f_s + f_p/2 (f = τ/R):
    // (m + M/4)·q̈ = g·(M/2 − m) − f_s − f_p/2 while M > 2m lifts m.
    let (m, big, tau_p, tau_s) = (0.15, 0.5, 0.2, 0.1);
    let ceiling = [-2.0 * R, 2.0];
    let mechanism = Mechanism::new(Network {
        bodies: vec![
            body("pulley+load", big, -R, -3.0),
            body("m", m, 2.0 * R, -2.0),
        ],
        pulleys: vec![
            Pulley {
                name: "movable".into(),
                radius: R,
                inertia: 0.0,
                friction_torque: tau_p,
                mount: Mount::Body(0),
            },
            Pulley {
                friction_torque: tau_s,
                ..static_pulley("static", R, 2.0, 0.0)
            },
        ],
        ropes: vec![rope(
            "main",
            vec![
                Point::Fixed(ceiling),
                Point::Pulley(0),
                Point::Pulley(1),
                Point::Body(1),
            ],
        )],
        floor: None,
        turns: Vec::new(),
        drives: Vec::new(),
    })
    .unwrap();
    let a_m = (GRAVITY * (big / 2.0 - m) - tau_s / R - tau_p / (2.0 * R)) / (m + big / 4.0);
    let solution = mechanism.instantaneous(&mechanism.initial_state()).unwrap();
    close(solution.accelerations[1], a_m, "a of m");
    close(
        solution.accelerations[0],
        -a_m / 2.0,
        "a of the movable pulley",
    );
    close(solution.tensions[0], m * (GRAVITY + a_m), "tension");
    let dt = 1e-3;
    let mut state = mechanism.initial_state();
    mechanism.run(&mut state, 0.5, dt).unwrap();
    first_order(state.y[1], -2.0 + 0.125 * a_m, a_m, dt, 0.5, "m");
}

#[test]
fn extreme_bearing_friction_stays_finite() {
    // A bearing of 1e6 N·m holds the loads still and stays finite.
    let (m1, m2) = (0.2, 0.3);
    let mechanism = atwood_with_bearing(m1, m2, 0.02, 1e6);
    let mut state = mechanism.initial_state();
    mechanism.run(&mut state, 2.0, 1e-3).unwrap();
    let moved = largest_move(&mechanism, &state);
    assert!(moved < 1e-9, "moved {moved} m");
    assert!(state.angles[0] == 0.0);
    close(
        state.friction_torques[0],
        GRAVITY * (m2 - m1) * R,
        "holding torque",
    );
    // Mass ratios of 1e3: sliding at a quarter of the pull's torque, held at four times it.
    for (m1, m2) in [(1.0, 1e3), (1e3, 1.0), (1e-3, 1.0_f64)] {
        let pull = GRAVITY * (m2 - m1).abs();
        let d = (m2 - m1).signum();
        let sliding = atwood_with_bearing(m1, m2, 0.0, 0.25 * pull * R);
        let a = d * 0.75 * pull / (m1 + m2);
        let solution = sliding.instantaneous(&sliding.initial_state()).unwrap();
        close(solution.accelerations[0], a, "a of A");
        let dt = 1e-3;
        let mut state = sliding.initial_state();
        sliding.run(&mut state, 0.3, dt).unwrap();
        assert!(state.y.iter().chain(&state.v).all(|v| v.is_finite()));
        first_order(state.y[0], -2.0 + 0.045 * a, a, dt, 0.3, "A");
        let held = atwood_with_bearing(m1, m2, 0.0, 4.0 * pull * R);
        let mut state = held.initial_state();
        held.run(&mut state, 0.3, dt).unwrap();
        let moved = largest_move(&held, &state);
        assert!(moved < 1e-9, "{m1} / {m2}: moved {moved} m");
        close(state.friction_torques[0], d * pull * R, "holding torque");
    }
}

#[test]
fn two_held_bearings_on_one_rope_keep_it_still() {
    // Each bearing alone would slip (0.6 of the pull each), together they hold; their rows are
    // the same (both measure the flow of A's side), so the split between them is not unique,
    // only the sum, which must be the pull.
    let (m1, m2) = (0.15, 0.3);
    let pull_torque = GRAVITY * (m2 - m1) * R;
    let mechanism = chain_with_bearings(m1, m2, 0.01, [0.6 * pull_torque; 2]);
    let mut state = mechanism.initial_state();
    mechanism.run(&mut state, 2.0, 1e-3).unwrap();
    let moved = largest_move(&mechanism, &state);
    assert!(moved < 1e-9, "moved {moved} m");
    assert!(
        state.angles.iter().all(|a| a.abs() < 1e-12),
        "{:?}",
        state.angles
    );
    close(
        state.friction_torques[0] + state.friction_torques[1],
        pull_torque,
        "held torque",
    );
}

#[test]
fn invalid_bearing_friction_is_a_typed_error() {
    for torque in [-0.1, f64::NAN, f64::INFINITY] {
        let error = Mechanism::new(atwood_network(0.2, 0.3, 0.0, torque)).unwrap_err();
        let SimulationError::InvalidParameter { object, problem } = &error else {
            panic!("{error:?}");
        };
        assert_eq!(object, "P");
        assert!(problem.contains("friction torque"), "{error}");
    }
    // Zero is an ideal bearing.
    assert!(Mechanism::new(atwood_network(0.2, 0.3, 0.0, 0.0)).is_ok());
}

#[test]
fn a_driven_pulley_with_a_bearing_is_the_atwood_machine_in_its_frame() {
    // The pulley rises at a constant u and the loads start rising with it: in the pulley's
    // (inertial) frame this is the Atwood machine with bearing friction, so A's height is
    // −2 + u·T + ½·a·T² with a = (g·(m2 − m1) − τ/R)/(m1 + m2 + I/R²) while the bearing slips,
    // and −2 + u·T with the pulley not turning while it holds. The bearing sees only the rope's
    // flow relative to the pulley, v_A − u.
    let (m1, m2, inertia, u) = (0.15, 0.25, 0.02, 0.5);
    let threshold = GRAVITY * (m2 - m1) * R;
    let driven = |torque: f64| {
        Mechanism::new(Network {
            drives: vec![Drive {
                point: DrivenPoint::Pulley(0),
                velocity: u,
                start: 0.0,
                distance: 10.0,
            }],
            ..atwood_network(m1, m2, inertia, torque)
        })
        .unwrap()
    };
    let duration = 1.0;
    let dt = 1e-3;

    let mechanism = driven(0.5 * threshold);
    let a = (GRAVITY * (m2 - m1) - 0.5 * threshold / R) / (m1 + m2 + inertia / (R * R));
    let mut state = mechanism.initial_state();
    state.v = vec![u, u];
    let solution = mechanism.instantaneous(&state).unwrap();
    close(solution.accelerations[0], a, "a of A in the pulley's frame");
    close(
        solution.friction_torques[0],
        0.5 * threshold,
        "bearing torque",
    );
    mechanism.run(&mut state, duration, dt).unwrap();
    first_order(
        state.y[0] - u * duration,
        -2.0 + 0.5 * a * duration * duration,
        a,
        dt,
        duration,
        "A relative to the pulley",
    );
    close(
        state.angles[0],
        -(state.y[0] + 2.0 - u * duration) / R,
        "angle from the relative flow",
    );

    let mechanism = driven(1.01 * threshold);
    let mut state = mechanism.initial_state();
    state.v = vec![u, u];
    mechanism.run(&mut state, duration, dt).unwrap();
    for (y, start) in state.y.iter().zip([-2.0, -3.0]) {
        assert!(
            (y - start - u * duration).abs() < 1e-9,
            "{:?} after riding up {} m",
            state.y,
            u * duration
        );
    }
    assert!(state.angles[0] == 0.0, "{}", state.angles[0]);
    close(state.friction_torques[0], threshold, "holding torque");
}

/// A rope running straight down past a pulley's rim: an Atwood machine whose left load hangs
/// from a second pulley below the first, on the same vertical line, so the rope only grazes the
/// lower pulley. Its wrap angle is 0 (or a hair either side of it), never a full turn, and stays
/// continuous as the load moves: the rope is as long as its straight pieces and arc, and the
/// loads move as the plain Atwood machine predicts.
#[test]
fn a_rope_grazing_a_pulley_is_not_wrapped_all_the_way_round() {
    for shift in [0.0, 1e-9, -1e-9, 1e-4] {
        let network = Network {
            bodies: vec![body("A", 0.2, -R + shift, -6.0), body("B", 0.25, R, -3.0)],
            pulleys: vec![
                static_pulley("Top", 0.0, 0.0, 0.0),
                static_pulley("Grazed", 0.0, -3.0, 0.0),
            ],
            ropes: vec![rope(
                "rope",
                vec![
                    Point::Body(0),
                    Point::Pulley(1),
                    Point::Pulley(0),
                    Point::Body(1),
                ],
            )],
            // Up the left side of the lower pulley (it is on the path's right), over the top
            // one clockwise.
            turns: vec![(0, 1, Turn::Clockwise), (0, 2, Turn::Clockwise)],
            ..Network::default()
        };
        let mechanism = Mechanism::new(network).unwrap();
        // 6 up to the top pulley's rim, half its circumference, 3 down.
        close(
            mechanism.rest_lengths()[0],
            6.0 + std::f64::consts::PI * R + 3.0,
            &format!("rest length, shift {shift}"),
        );
        let mut state = mechanism.initial_state();
        mechanism.run(&mut state, 0.5, 1e-3).unwrap();
        let polyline = mechanism.rope_polyline(0, &state, 0.05);
        let length: f64 = polyline
            .windows(2)
            .map(|w| (w[0][0] - w[1][0]).hypot(w[0][1] - w[1][1]))
            .sum();
        assert!(
            (length - mechanism.rest_lengths()[0]).abs() < 1e-3,
            "shift {shift}: the drawn rope is {length} long"
        );
        // B (heavier) goes down as an Atwood machine's: a = g·0.05/0.45.
        let a = GRAVITY * 0.05 / 0.45;
        let expected = -3.0 - 0.5 * a * 0.25;
        assert!(
            (state.y[1] - expected).abs() < 5e-3,
            "shift {shift}: B at {}, want {expected}",
            state.y[1]
        );
    }
}
