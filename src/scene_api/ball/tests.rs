//! The ball scene on the hand-written video `tests/data/soft_body/0`, whose answers the engine's
//! tests work out by hand (`dataset/engine/ball/tests.rs`): red Elastic, blue Rigid, green
//! Plastic; factual: red left (in the video), blue right (after it), green no pit; without the
//! white wall: red right, blue right, green none; without the black wall: red left, blue right,
//! green left.

use std::path::{Path, PathBuf};

use super::*;
use crate::scene_api::Scene;
use crate::scene_api::test_support::open_scene;

fn fixture_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/soft_body/0")
}

fn open(perception: PerceptionBackend, dynamics: DynamicsBackend) -> Scene {
    open_scene(
        Scenario::Ball,
        fixture_dir(),
        (&VOCABULARY, load),
        perception,
        dynamics,
    )
}

fn scene() -> Scene {
    open(PerceptionBackend::Annotation, DynamicsBackend::Annotation)
}

fn one(scene: &Scene, query: &str) -> ObjectId {
    let found = scene.find(query).unwrap();
    assert_eq!(found.len(), 1, "{query}");
    found[0]
}

#[test]
fn objects_are_the_balls_walls_and_pits() {
    let scene = scene();
    let all: Vec<String> = scene
        .objects()
        .unwrap()
        .iter()
        .map(SceneObjectInfo::describe)
        .collect();
    assert_eq!(
        all,
        [
            "red ball",
            "blue ball",
            "green ball",
            "white floating wall",
            "black floating wall",
            "orange right ramp",
            "yellow left ramp",
            "left pit",
            "right pit"
        ]
    );
    let cases: [(&str, usize); 8] = [
        ("balls", 3),
        ("pits", 2),
        ("the left pit", 1),
        ("right", 1),
        ("floating walls", 2),
        ("ramps", 2),
        ("left ramp", 1),
        ("stick", 0),
    ];
    for (query, count) in cases {
        assert_eq!(scene.find(query).unwrap().len(), count, "{query}");
    }
    let pit = scene.object(one(&scene, "left pit")).unwrap();
    assert_eq!(pit.attribute("side"), Some("left"));
}

#[test]
fn materials_compare_where_the_release_orders_them() {
    let scene = scene();
    let (red, blue, green) = (
        one(&scene, "red ball"),
        one(&scene, "blue ball"),
        one(&scene, "green ball"),
    );
    let cases = [
        ("elasticity", red, blue, (Some(1.0), Some(0.0))),
        ("elasticity", green, red, (Some(0.0), Some(1.0))),
        ("elasticity", blue, green, (None, None)),
        ("plasticity", green, blue, (Some(1.0), Some(0.0))),
        ("plasticity", red, blue, (None, None)),
        ("plasticity", red, red, (Some(0.0), Some(0.0))),
    ];
    for (property, a, b, expected) in cases {
        assert_eq!(
            scene.query_pair(property, a, b).unwrap(),
            expected,
            "{property}"
        );
    }
    let error = scene.query_single("density", red).unwrap_err();
    assert!(
        error
            .to_string()
            .contains("ball scenes have elasticity and plasticity"),
        "{error}"
    );
    let wall = one(&scene, "white floating wall");
    assert!(scene.query_single("elasticity", wall).is_err());
}

#[test]
fn drops_are_read_from_the_run_the_event_starts() {
    let scene = scene();
    let factual = scene.register_event(&[], "simulate", "", vec![]).unwrap();
    let without_white = scene
        .register_event(&[], "remove", "white floating wall and other balls", vec![])
        .unwrap();
    let black = one(&scene, "black floating wall");
    let without_black = scene
        .register_event(&[black], "remove", "", vec![])
        .unwrap();
    let (left, right) = (one(&scene, "left pit"), one(&scene, "right pit"));
    let cases = [
        (&factual, "red ball", left, true),
        (&factual, "red ball", right, false),
        (&factual, "blue ball", right, true),
        (&factual, "green ball", left, false),
        (&factual, "green ball", right, false),
        (&without_white, "red ball", right, true),
        (&without_white, "green ball", left, false),
        (&without_white, "green ball", right, false),
        (&without_black, "red ball", left, true),
        (&without_black, "green ball", left, true),
        (&without_black, "blue ball", left, false),
    ];
    for (event, ball, pit, expected) in cases {
        let ball_id = one(&scene, ball);
        let happened = scene
            .happen(event, &[ball_id], "droping", &Target::Objects(vec![pit]))
            .unwrap();
        assert_eq!(happened, expected, "{ball} {event:?}");
    }
    // A pit by description; misuse says what is allowed.
    let red = one(&scene, "red ball");
    assert!(
        scene
            .happen(
                &factual,
                &[red],
                "dropping",
                &Target::Text("left pit".into())
            )
            .unwrap()
    );
    let wrong = scene
        .happen(&factual, &[red], "entering", &Target::Objects(vec![left]))
        .unwrap_err();
    assert!(
        wrong.to_string().contains("ball scenes answer 'droping'"),
        "{wrong}"
    );
    let wall = scene
        .happen(&factual, &[red], "droping", &Target::Objects(vec![black]))
        .unwrap_err();
    assert!(
        wall.to_string()
            .contains("takes a pit, not the black floating wall"),
        "{wall}"
    );
    let absent = scene
        .register_event(
            &[],
            "remove",
            "purple floating wall and other balls",
            vec![],
        )
        .unwrap_err();
    assert_eq!(
        absent.to_string(),
        "register_event: `purple floating wall` names no floating wall of this scene; the floating walls are: white floating wall, black floating wall"
    );
    let ball = scene
        .register_event(&[], "remove", "red ball", vec![])
        .unwrap_err();
    assert!(
        ball.to_string()
            .contains("takes a floating wall, not the red ball"),
        "{ball}"
    );
}

#[test]
fn simulate_reads_the_tracked_particles_only_when_a_question_needs_them() {
    // The hand fixture has no outputs4D.json: objects come from the layout, and the first
    // question that needs a material or a run says what is missing.
    let simulate = open(PerceptionBackend::Annotation, DynamicsBackend::Simulate);
    let balls = simulate.find("ball").unwrap();
    assert_eq!(balls.len(), 3);
    let error = simulate
        .query_pair("elasticity", balls[0], balls[1])
        .unwrap_err();
    assert!(matches!(error, ApiError::Unavailable(_)), "{error:?}");
    assert!(
        error.to_string().contains("tracked particles")
            && error.to_string().contains("outputs4D.json"),
        "{error}"
    );
    assert_eq!(simulate.work().sim_runs, 0);
}

#[test]
fn an_empty_list_from_pixels_is_a_perception_miss() {
    // `find` gives an empty list for a wall no object carries: under annotation perception the
    // program named something the scene lacks (misuse); under `--perception maskrcnn` the
    // detector may have missed the wall or read it in another colour (`not_seen`).
    let annotation = BallAnnotation::load(&fixture_dir().join("outputs.json")).unwrap();
    let mut backend = BallBackend::new(annotation);
    let error = backend
        .one_of_kind(&[], "floating wall", "register_event", "'remove'")
        .unwrap_err();
    assert_eq!(error.kind(), "misuse");
    backend.from_pixels = true;
    let error = backend
        .one_of_kind(&[], "floating wall", "register_event", "'remove'")
        .unwrap_err();
    assert_eq!(error.kind(), "not_seen");
    assert!(
        error.to_string().starts_with(
            "register_event: 'remove' names no floating wall (an empty list: `find` found no such object); the floating walls are: "
        ),
        "{error}"
    );
}
