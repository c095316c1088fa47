//! The fluid scene on the hand-written video `tests/data/fluid_slides/0`, whose answers the
//! engine's tests work out by hand (`dataset/engine/fluid/tests.rs`):
//!
//! * densities: pink 4400 > yellow 3000 > light blue 1600 kg/m³; the relations (pink, yellow)
//!   and (later yellow, light blue) order every pair once normalised and closed;
//! * factual run: pink passes brown and cyan and ends in red; light blue passes gray and ends in
//!   green; yellow passes brown and cyan and ends in red; the other yellow emitter's fluid passes
//!   gray and cyan (not brown) and ends in green only;
//! * without the brown stick: pink passes cyan (not gray), ends in red (200) and green (1100);
//!   light blue passes gray, ends in green; yellow passes cyan and gray, red 700 against green
//!   500; without the gray stick: pink passes brown and cyan, ends in red only; light blue
//!   passes brown (not cyan), red 900 against green 450; yellow red 1100 against green 60;
//! * no run removes the cyan stick.

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::*;
use crate::dataset::Scenario;
use crate::scene_api::test_support::open_scene;
use crate::scene_api::{EventAction, Scene};

fn fixture_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fluid_slides/0")
}

/// A fluid scene of `dir` with fluid's parts (the scenario table's fluid row).
fn open(dir: PathBuf, perception: PerceptionBackend, dynamics: DynamicsBackend) -> Scene {
    open_scene(
        Scenario::Fluid,
        dir,
        (&VOCABULARY, load),
        perception,
        dynamics,
    )
}

fn scene() -> Scene {
    open(
        fixture_dir(),
        PerceptionBackend::Annotation,
        DynamicsBackend::Annotation,
    )
}

/// A scene of the fixture edited by `edit`.
fn edited_scene(edit: impl FnOnce(&mut Value)) -> (tempfile::TempDir, Scene) {
    let mut value: Value =
        serde_json::from_slice(&fs_err::read(fixture_dir().join("outputs.json")).unwrap()).unwrap();
    edit(&mut value);
    let dir = tempfile::tempdir().unwrap();
    fs_err::write(
        dir.path().join("outputs.json"),
        serde_json::to_vec(&value).unwrap(),
    )
    .unwrap();
    let scene = open(
        dir.path().to_path_buf(),
        PerceptionBackend::Annotation,
        DynamicsBackend::Annotation,
    );
    (dir, scene)
}

fn names(scene: &Scene, query: &str) -> Vec<String> {
    scene
        .find(query)
        .unwrap()
        .into_iter()
        .map(|id| scene.object(id).unwrap().describe())
        .collect()
}

fn one(scene: &Scene, query: &str) -> ObjectId {
    let found = scene.find(query).unwrap();
    assert_eq!(found.len(), 1, "{query}");
    found[0]
}

fn text(value: &str) -> Target {
    Target::Text(value.to_string())
}

#[test]
fn objects_are_the_layouts_and_find_tells_the_emitters_apart() {
    let scene = scene();
    assert_eq!(scene.work().annotation_loads, 0, "opening reads nothing");
    let all: Vec<(String, String)> = scene
        .objects()
        .unwrap()
        .iter()
        .map(|o| (o.name.clone(), o.describe()))
        .collect();
    let expected = [
        ("Pink Fluid", "pink fluid"),
        ("Light Blue Fluid", "light blue fluid"),
        ("Yellow Fluid", "yellow fluid"),
        ("Red Container", "red container"),
        ("Green Container", "green container"),
        ("Brown Stick", "brown stick"),
        ("Cyan Stick", "cyan stick"),
        ("Gray Stick", "gray stick"),
        ("Pink Fluid Emitter", "pink first emitter"),
        ("Light Blue Fluid Emitter", "light blue first emitter"),
        ("Yellow Fluid Emitter", "yellow first emitter"),
        ("Later Emitted Yellow Fluid Emitter", "yellow later emitter"),
    ];
    assert_eq!(
        all,
        expected.map(|(name, short)| (name.to_string(), short.to_string()))
    );
    let cases: [(&str, &[&str]); 11] = [
        (
            "fluids",
            &["pink fluid", "light blue fluid", "yellow fluid"],
        ),
        ("blue fluid", &[]),
        ("the other yellow emitter", &["yellow later emitter"]),
        ("later", &["yellow later emitter"]),
        (
            "yellow emitter",
            &["yellow first emitter", "yellow later emitter"],
        ),
        (
            "yellow",
            &[
                "yellow fluid",
                "yellow first emitter",
                "yellow later emitter",
            ],
        ),
        (
            "first emitters",
            &[
                "pink first emitter",
                "light blue first emitter",
                "yellow first emitter",
            ],
        ),
        ("sticks", &["brown stick", "cyan stick", "gray stick"]),
        ("green", &["green container"]),
        ("other pink emitter", &[]),
        ("cube", &[]),
    ];
    for (query, expected) in cases {
        assert_eq!(names(&scene, query), expected, "{query}");
    }
    let later = scene.object(one(&scene, "other yellow emitter")).unwrap();
    assert_eq!(later.attribute("emission"), Some("later"));
    let fluid = scene.object(one(&scene, "pink fluid")).unwrap();
    assert_eq!(fluid.attribute("emission"), None);
    assert_eq!(scene.work().annotation_loads, 1, "loaded once");
}

#[test]
fn densities_compare_when_the_recorded_relations_order_them() {
    let scene = scene();
    let pink = one(&scene, "pink fluid");
    let yellow = one(&scene, "yellow fluid");
    let light_blue = one(&scene, "light blue fluid");
    let cases = [
        (pink, yellow, (Some(4400.0), Some(3000.0))),
        (yellow, pink, (Some(3000.0), Some(4400.0))),
        // Recorded against the later yellow emitter's fluid, read as yellow's.
        (yellow, light_blue, (Some(3000.0), Some(1600.0))),
        // Only through the closure.
        (light_blue, pink, (Some(1600.0), Some(4400.0))),
        (pink, pink, (Some(4400.0), Some(4400.0))),
    ];
    for (first, second, expected) in cases {
        assert_eq!(
            scene.query_pair("density", first, second).unwrap(),
            expected
        );
    }
    assert_eq!(
        scene.query_single("density", light_blue).unwrap(),
        Some(1600.0)
    );
    // Without the later emitter's relation nothing links light blue to the others.
    let (_dir, unrelated) = edited_scene(|value| {
        let relations = value["trackingData"]["allDensityRelations"]
            .as_array_mut()
            .unwrap();
        relations.truncate(1);
    });
    let pink = one(&unrelated, "pink fluid");
    let yellow = one(&unrelated, "yellow fluid");
    let light_blue = one(&unrelated, "light blue fluid");
    assert_eq!(
        unrelated.query_pair("density", pink, yellow).unwrap(),
        (Some(4400.0), Some(3000.0))
    );
    for other in [pink, yellow] {
        assert_eq!(
            unrelated.query_pair("density", other, light_blue).unwrap(),
            (None, None),
            "can not answer"
        );
    }
    let scene = self::scene();
    let stick = one(&scene, "brown stick");
    let cases = [
        (
            scene.query_single("density", stick).unwrap_err(),
            "query_single: density is a property of fluids, not of the brown stick",
        ),
        (
            scene
                .query_pair("density", one(&scene, "pink fluid"), one(&scene, "later"))
                .unwrap_err(),
            "query_pair: density is a property of fluids, not of the yellow later emitter",
        ),
        (
            scene
                .query_single("mass", one(&scene, "pink fluid"))
                .unwrap_err(),
            "query_single: property `mass` does not apply to fluid scenes; fluid scenes have density (fluids)",
        ),
    ];
    for (error, expected) in cases {
        assert_eq!(error.kind(), "misuse");
        assert_eq!(error.to_string(), expected);
    }
}

#[test]
fn outcomes_come_from_the_factual_the_emitted_and_the_counterfactual_runs() {
    let scene = scene();
    let find = |query: &str| one(&scene, query);
    let (pink, light_blue, yellow) = (
        find("pink fluid"),
        find("light blue fluid"),
        find("yellow fluid"),
    );
    let later = find("other yellow emitter");
    let (brown, cyan, gray) = (find("brown stick"), find("cyan stick"), find("gray stick"));
    let (red, green) = (find("red container"), find("green container"));
    let factual = scene.register_event(&[], "simulate", "", vec![]).unwrap();
    let emitted = scene
        .register_event(&[later], "emit", "fluid", vec![])
        .unwrap();
    let without_brown = scene
        .register_event(&[], "remove", "Brown Stick", vec![])
        .unwrap();
    let without_gray = scene
        .register_event(&[gray], "remove", "stick", vec![])
        .unwrap();
    let pass = "passing";
    let enter = "entering";
    let most = "entering most";
    let cases = [
        (&factual, pink, pass, brown, true),
        (&factual, pink, pass, cyan, true),
        (&factual, pink, pass, gray, false),
        (&factual, pink, enter, red, true),
        (&factual, pink, enter, green, false),
        (&factual, pink, most, red, true),
        (&factual, light_blue, pass, gray, true),
        (&factual, light_blue, enter, green, true),
        (&factual, yellow, pass, brown, true),
        (&factual, yellow, enter, red, true),
        (&factual, yellow, enter, green, false),
        // The emitter stands for its fluid.
        (&factual, later, pass, gray, true),
        (&factual, later, pass, brown, false),
        (&factual, later, enter, green, true),
        (&factual, later, enter, red, false),
        // In the emit scene, yellow fluid is the fluid the other yellow emitter emits.
        (&emitted, yellow, pass, gray, true),
        (&emitted, yellow, pass, cyan, true),
        (&emitted, yellow, pass, brown, false),
        (&emitted, yellow, enter, green, true),
        (&emitted, yellow, enter, red, false),
        (&emitted, pink, pass, brown, true),
        (&without_brown, pink, pass, cyan, true),
        (&without_brown, pink, pass, gray, false),
        (&without_brown, pink, pass, brown, false),
        (&without_brown, pink, enter, red, true),
        (&without_brown, pink, enter, green, true),
        (&without_brown, pink, most, green, true),
        (&without_brown, pink, most, red, false),
        (&without_brown, light_blue, pass, gray, true),
        (&without_brown, light_blue, pass, cyan, false),
        (&without_brown, light_blue, enter, red, false),
        (&without_brown, yellow, pass, gray, true),
        (&without_brown, yellow, most, red, true),
        (&without_brown, yellow, most, green, false),
        (&without_gray, pink, pass, brown, true),
        (&without_gray, pink, enter, green, false),
        (&without_gray, light_blue, pass, brown, true),
        (&without_gray, light_blue, pass, cyan, false),
        (&without_gray, light_blue, enter, green, true),
        (&without_gray, light_blue, most, red, true),
        (&without_gray, yellow, most, red, true),
        (&without_gray, yellow, most, green, false),
    ];
    for (index, (event, subject, action, target, expected)) in cases.into_iter().enumerate() {
        assert_eq!(
            scene
                .happen(event, &[subject], action, &Target::Objects(vec![target]))
                .unwrap(),
            expected,
            "case {index}"
        );
    }
    // A target may be a description, as in the paper's docstring.
    assert!(
        scene
            .happen(&factual, &[pink], "entering", &text("the red container"))
            .unwrap()
    );
    // Engine verbs are understood too.
    assert!(
        scene
            .happen(
                &without_brown,
                &[pink],
                "enter most",
                &text("green container")
            )
            .unwrap()
    );
    assert_eq!(scene.work().sim_runs, 0, "annotations, no simulation");
}

#[test]
fn misuse_names_the_object_and_what_is_allowed() {
    let scene = scene();
    let find = |query: &str| one(&scene, query);
    let pink = find("pink fluid");
    let later = find("other yellow emitter");
    let brown = find("brown stick");
    let red = find("red container");
    let green = find("green container");
    let factual = scene.register_event(&[], "simulate", "", vec![]).unwrap();
    let without_brown = scene
        .register_event(&[], "remove", "brown stick", vec![])
        .unwrap();
    let remove = |attribute: &str| {
        scene
            .register_event(&[], "remove", attribute, vec![])
            .unwrap_err()
    };
    let cases = [
        (
            remove("purple stick"),
            "register_event: `purple stick` names no object of this scene; the sticks are: brown stick, cyan stick, gray stick",
        ),
        (
            remove("red container"),
            "register_event: only sticks can be removed in fluid scenes, not the red container",
        ),
        (
            remove(""),
            "register_event: 'remove' needs the stick (got none; an empty list from `find` names none)",
        ),
        (
            remove("sticks"),
            "register_event: 'remove' takes one stick, but `sticks` names 3 objects (brown stick, cyan stick, gray stick)",
        ),
        (
            remove("banana stick"),
            "register_event: cannot read `banana stick`: unknown word `banana` in `banana stick`; a fluid scene understands",
        ),
        (
            scene
                .register_event(&[brown], "remove", "gray stick", vec![])
                .unwrap_err(),
            "register_event: 'remove' names its stick once, as the object or as the attribute",
        ),
        (
            scene
                .register_event(&[pink], "emit", "fluid", vec![])
                .unwrap_err(),
            "register_event: 'emit' takes an emitter, not the pink fluid, e.g. register_event(fluid_scene.find('other yellow emitter'), 'emit', 'fluid')",
        ),
        (
            scene
                .register_event(&[pink], "increase", "mass", vec![])
                .unwrap_err(),
            "register_event: fluid scenes support register_event([], 'remove', 'green stick')",
        ),
        (
            scene
                .happen(&factual, &[brown], "passing", &Target::Objects(vec![red]))
                .unwrap_err(),
            "happen: only fluids flow in fluid scenes; ask about a fluid or an emitter (its fluid), not the brown stick",
        ),
        (
            scene
                .happen(&factual, &[pink], "passing", &Target::Objects(vec![red]))
                .unwrap_err(),
            "happen: 'passing' takes a stick, not the red container",
        ),
        (
            scene
                .happen(&factual, &[pink], "entering", &text(""))
                .unwrap_err(),
            "happen: 'entering' needs the container, e.g. happen([fluid], 'entering', [container])",
        ),
        (
            scene
                .happen(&factual, &[pink], "entering", &Target::Objects(vec![]))
                .unwrap_err(),
            "happen: the target of 'entering' names no container (an empty list: `find` found no such object); the containers are: red container, green container",
        ),
        (
            scene
                .happen(
                    &factual,
                    &[pink],
                    "entering",
                    &Target::Objects(vec![red, green]),
                )
                .unwrap_err(),
            "happen: ask about one container at a time, got 2 objects",
        ),
        (
            scene
                .happen(&factual, &[pink], "motion", &text("up"))
                .unwrap_err(),
            "happen: `motion` belongs to other scenarios; fluid scenes answer 'passing' (a stick), 'entering' and 'entering most' (a container)",
        ),
        (
            scene
                .happen(&factual, &[pink], "flying", &text("up"))
                .unwrap_err(),
            "happen: unknown action `flying`",
        ),
    ];
    for (index, (error, expected)) in cases.into_iter().enumerate() {
        assert_eq!(error.kind(), "misuse", "case {index}: {error}");
        assert!(
            error.to_string().starts_with(expected),
            "case {index}: `{error}` does not start with `{expected}`"
        );
    }
    let unavailable = [
        (
            scene
                .register_event(&[find("cyan stick")], "remove", "", vec![])
                .unwrap_err(),
            "register_event: this video has no counterfactual run without the cyan stick (its runs remove: brown stick, gray stick)",
        ),
        (
            scene
                .happen(
                    &without_brown,
                    &[later],
                    "entering",
                    &Target::Objects(vec![green]),
                )
                .unwrap_err(),
            "happen: counterfactual runs start the first emitters only; the yellow later emitter does not emit in the run without the brown stick",
        ),
    ];
    for (error, expected) in unavailable {
        assert_eq!(error.kind(), "unavailable", "{error}");
        assert_eq!(error.to_string(), expected);
    }
}

#[test]
fn a_fluid_a_run_does_not_list_has_no_passing_answer() {
    let (_dir, scene) = edited_scene(|value| {
        value["CounterFactualAnnotations"]["0"]["trackingData"]["perEmitterStickStat"]
            .as_object_mut()
            .unwrap()
            .remove("Pink Fluid");
    });
    let event = scene
        .register_event(&[], "remove", "brown stick", vec![])
        .unwrap();
    let pink = one(&scene, "pink fluid");
    let error = scene
        .happen(&event, &[pink], "passing", &text("cyan stick"))
        .unwrap_err();
    assert_eq!(error.kind(), "unavailable");
    assert_eq!(
        error.to_string(),
        "happen: the run without the brown stick records no sticks the fluid of the pink fluid touched"
    );
    // Containers are still answered: an unlisted fluid ends in none.
    assert!(
        scene
            .happen(&event, &[pink], "entering", &text("green container"))
            .unwrap()
    );
}

#[test]
fn simulate_needs_the_tracked_particles_and_maskrcnn_its_models() {
    // The hand-written video has no outputs4D.json: nothing to infer the properties from.
    let scene = open(
        fixture_dir(),
        PerceptionBackend::Annotation,
        DynamicsBackend::Simulate,
    );
    let pink = one(&scene, "pink fluid");
    let yellow = one(&scene, "yellow fluid");
    let error = scene.query_pair("density", pink, yellow).unwrap_err();
    assert_eq!(error.kind(), "unavailable");
    assert!(
        error
            .to_string()
            .starts_with("fluid properties are inferred from the tracked particles, and this video has no outputs4D.json"),
        "{error}"
    );
    // Misuse is still reported as misuse.
    let error = scene
        .register_event(&[], "remove", "purple stick", vec![])
        .unwrap_err();
    assert_eq!(error.kind(), "misuse", "{error}");
    assert_eq!(scene.find("sticks").unwrap().len(), 3, "objects still load");

    let scene = open(
        fixture_dir(),
        PerceptionBackend::MaskRcnn,
        DynamicsBackend::Annotation,
    );
    let error = scene.find("fluid").unwrap_err();
    assert_eq!(error.kind(), "unavailable");
    assert_eq!(
        error.to_string(),
        "perception (maskrcnn): there are no models for fluid scenes"
    );
}

/// The generated demo video under `--dynamics simulate` on a coarse grid: property questions
/// simulate nothing; each run is simulated once, when first asked; the robust facts of the
/// video's truth hold (the pink fluid runs down the red stick into the pink container; without
/// the red stick it lands on the gray stick instead; the light blue fluid runs down the pink
/// stick).
#[test]
fn simulate_answers_the_demo_video_and_runs_each_simulation_once_when_asked() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/fluid_slides/0");
    let annotation = FluidAnnotation::load(&dir.join("outputs.json")).unwrap();
    let coarse = RunSettings {
        grid_spacing: 0.1,
        ..RunSettings::default()
    };
    let backend =
        FluidBackend::new(annotation, DynamicsBackend::Simulate, dir).with_run_settings(coarse);
    let id = |name: &str| {
        backend
            .objects()
            .iter()
            .find(|object| object.name == name)
            .unwrap()
            .id
    };
    let (pink, yellow, light_blue) = (id("Pink Fluid"), id("Yellow Fluid"), id("Light Blue Fluid"));
    // Densities: 1600 (pink) < 3000 (yellow) < 4400 (light blue). The layering decides the
    // pairs with light blue; pink and yellow it leaves undecided (4 pink particles in a cup), and
    // they compare by the order the simulator runs with (the weak evidence puts pink above). Asking simulates
    // nothing.
    for (lighter, heavier) in [(pink, yellow), (pink, light_blue), (yellow, light_blue)] {
        let values = backend
            .query(Property::Density, &[lighter, heavier], "query_pair")
            .unwrap();
        assert!(
            matches!(values.as_slice(), [Some(a), Some(b)] if a < b),
            "{values:?}"
        );
    }
    assert_eq!(backend.simulation_work(), (0, 0));
    let factual = SceneEvent {
        action: EventAction::Simulate,
        object: None,
        attribute: String::new(),
        attribute_objects: Vec::new(),
    };
    let objects = |name: &str| Target::Objects(vec![id(name)]);
    let happens = |event: &SceneEvent, fluid, action: &str, target: &str| {
        backend
            .happen(event, fluid, action, &objects(target))
            .unwrap()
    };
    assert!(happens(&factual, pink, "passing", "Red Stick"));
    assert!(happens(&factual, pink, "entering", "Pink Container"));
    assert!(happens(&factual, light_blue, "passing", "Pink Stick"));
    let (runs, particle_substeps) = backend.simulation_work();
    assert_eq!(runs, 1, "one factual run for three questions");
    assert!(particle_substeps > 0);
    let without = |stick: &str| SceneEvent {
        action: EventAction::Remove,
        object: Some(id(stick)),
        attribute: "stick".to_string(),
        attribute_objects: Vec::new(),
    };
    assert!(!happens(
        &without("Red Stick"),
        pink,
        "passing",
        "Red Stick"
    ));
    assert!(happens(
        &without("Red Stick"),
        pink,
        "passing",
        "Gray Stick"
    ));
    assert_eq!(backend.simulation_work().0, 2);
    // A stick the release did not re-simulate without can be removed too.
    assert!(!happens(
        &without("Purple Stick"),
        pink,
        "passing",
        "Purple Stick"
    ));
    assert_eq!(backend.simulation_work().0, 3);
}

#[test]
fn broken_annotation_is_a_data_error_on_first_use() {
    let (_dir, scene) = edited_scene(|value| {
        value.as_object_mut().unwrap().remove("trackingData");
    });
    let error = scene.find("fluid").unwrap_err();
    assert_eq!(error.kind(), "data");
    assert!(
        error.to_string().contains("`trackingData` is missing"),
        "{error}"
    );
    assert_eq!(
        scene.find("fluid").unwrap_err().to_string(),
        error.to_string()
    );
    assert_eq!(scene.work().annotation_loads, 1);
}
