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
    Mechanism::new(Network {
        bodies: vec![body("A", m1, -R, -2.0), body("B", m2, R, -3.0)],
        pulleys: vec![static_pulley("P", 0.0, 0.0, inertia)],
        ropes: vec![rope(
            "rope",
            vec![Point::Body(0), Point::Pulley(0), Point::Body(1)],
        )],
        floor: None,
        turns: Vec::new(),
        drives: Vec::new(),
    })
    .unwrap()
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
