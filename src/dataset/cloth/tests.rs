//! The cloth reader on the hand-written video `tests/data/cloth_collision/0` and on variants of
//! it made by editing its JSON: what it reads (checked by hand against the file), that what it
//! writes reads back equal, and that every malformed field is an error naming the file and the
//! field.

use std::path::Path;

use serde_json::{Value, json};

use super::names::{Shape, Side};
use super::outcome::Pose;
use super::*;

fn fixture() -> Value {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/cloth_collision/0/outputs.json");
    serde_json::from_slice(&fs_err::read(path).unwrap()).unwrap()
}

/// A number's bits: the reader must give exactly the number written (JSON numbers round-trip).
fn bits(number: f64) -> u64 {
    number.to_bits()
}

fn read(value: &Value) -> Result<ClothAnnotation, crate::dataset::DatasetError> {
    ClothAnnotation::from_json(Path::new("cloth_collision/0/outputs.json"), value)
}

#[test]
fn the_fixture_reads_with_every_key() {
    let annotation = read(&fixture()).unwrap();
    assert_eq!(
        bits(annotation.left_cloth.stretching_compliance),
        bits(0.011)
    );
    assert_eq!(bits(annotation.left_cloth.bending_compliance), bits(0.013));
    assert_eq!(annotation.left_cloth.friction, Friction::Low);
    assert_eq!(annotation.right_cloth.friction, Friction::High);
    assert_eq!(
        annotation.right_cloth.region_forces,
        RegionForces {
            red: 3.5,
            blue: 1.0,
            yellow: 0.25,
            green: 4.5
        }
    );
    let names: Vec<(Side, &str)> = annotation
        .boxes()
        .map(|(side, record)| (side, record.name.as_str()))
        .collect();
    assert_eq!(
        names,
        [
            (Side::Left, "Green Plate"),
            (Side::Left, "Gray Pillar"),
            (Side::Left, "Blue Plate"),
            (Side::Right, "Yellow Pillar"),
            (Side::Right, "Orange Plate"),
            (Side::Right, "Green Pillar"),
        ]
    );
    let (side, plate) = annotation.find_box("Green Plate").unwrap();
    assert_eq!(side, Side::Left);
    assert_eq!(plate.shape, Shape::Plate);
    assert_eq!(plate.color, "Green");
    assert_eq!(
        plate.color_rgba.map(bits),
        [0.396, 0.576, 0.29, 1.0].map(bits)
    );
    assert_eq!(plate.end_pose, Pose::Supine);
    assert_eq!(bits(plate.mass), bits(2.0));
    assert_eq!(plate.start_moving_update, Some(140));
    assert_eq!(
        plate.collision_events,
        [
            CollisionEvent {
                update: 131,
                other: "Cloth (Left)".into()
            },
            CollisionEvent {
                update: 170,
                other: "Gray Pillar".into()
            }
        ]
    );
    // The blue plate's scale is written as Unity's vector string; it never moved (-1).
    let (_, blue) = annotation.find_box("Blue Plate").unwrap();
    assert_eq!(blue.scale.map(bits), [1.1, 1.6, 0.4].map(bits));
    assert_eq!(blue.start_moving_update, None);
    assert_eq!(bits(blue.mass), bits(99_999.0));
    assert_eq!(
        bits(annotation.camera.as_ref().unwrap().vertical_fov_deg),
        bits(35.2)
    );
    assert_eq!(annotation.id_to_object_name.len(), 9);
    assert_eq!(annotation.frame_count, 0);
}

#[test]
fn collisions_and_contacts_count_when_either_box_records_them() {
    let annotation = read(&fixture()).unwrap();
    // Only the green plate records its collision with the gray pillar, and only the gray pillar
    // its final contact with the green plate.
    for (first, second) in [
        ("Green Plate", "Gray Pillar"),
        ("Gray Pillar", "Green Plate"),
    ] {
        assert!(annotation.collided(first, second));
        assert!(annotation.in_touch(first, second));
    }
    assert!(annotation.collided("Orange Plate", "Green Pillar"));
    assert!(!annotation.in_touch("Orange Plate", "Green Pillar"));
    assert!(!annotation.collided("Green Plate", "Blue Plate"));
    assert!(!annotation.collided("Green Plate", "No Such Box"));
}

/// The world direction of a box's local up axis under Unity's Euler angles (degrees, applied
/// z, then x, then y).
fn unity_up_axis(euler_deg: [f64; 3]) -> [f64; 3] {
    let [x, y, z] = euler_deg.map(f64::to_radians);
    let after_z = [-z.sin(), z.cos(), 0.0];
    let after_x = [
        after_z[0],
        after_z[1] * x.cos() - after_z[2] * x.sin(),
        after_z[1] * x.sin() + after_z[2] * x.cos(),
    ];
    [
        after_x[0] * y.cos() + after_x[2] * y.sin(),
        after_x[1],
        -after_x[0] * y.sin() + after_x[2] * y.cos(),
    ]
}

#[test]
fn the_fixtures_end_poses_follow_the_releases_rule_from_their_end_rotations() {
    let annotation = read(&fixture()).unwrap();
    for (_, record) in annotation.boxes() {
        let up = unity_up_axis(record.end_rotation);
        assert_eq!(Pose::from_up_axis(up), record.end_pose, "{}", record.name);
    }
}

#[test]
fn what_is_written_reads_back_equal() {
    let annotation = read(&fixture()).unwrap();
    let written = annotation.to_json();
    assert_eq!(read(&written).unwrap(), annotation);
    let scenario_keys = annotation.scenario_keys();
    let keys: Vec<&str> = scenario_keys.keys().map(String::as_str).collect();
    assert_eq!(
        keys,
        [
            "validity",
            "mode",
            "clothLeft",
            "clothRight",
            "objectFullAnnotation"
        ]
    );
    // Towers, an empty touch list and a moved box write and read back too.
    let mut towered = annotation.clone();
    let (_, layer) = annotation.find_box("Gray Pillar").unwrap();
    let mut bottom = layer.clone();
    bottom.name = "Pink Cube".into();
    bottom.color = "Pink".into();
    bottom.shape = Shape::Cube;
    bottom.touchers.clear();
    bottom.start_moving_update = Some(0);
    let mut top = bottom.clone();
    top.name = "Light Blue Cube".into();
    top.color = "Light Blue".into();
    towered.right_objects.towers.push(Tower {
        name: "2-Object Tower (Right)".into(),
        base_xz: [2.5, -1.25],
        layer_count: 2,
        layers: vec![bottom, top],
    });
    towered.camera = None;
    towered.id_to_object_name.clear();
    assert_eq!(read(&towered.to_json()).unwrap(), towered);
    assert_eq!(towered.boxes().count(), 8);
}

/// Edits the fixture at a path of object keys and array indices (removing the field when
/// `value` is `None`) and returns the read error.
fn error_after(path: &[String], value: Option<Value>) -> String {
    let mut document = fixture();
    let (last, parents) = path.split_last().unwrap();
    let mut node = &mut document;
    for key in parents {
        node = match key.parse::<usize>() {
            Ok(index) => &mut node[index],
            Err(_) => &mut node[key.as_str()],
        };
    }
    match (value, last.parse::<usize>()) {
        (Some(value), Ok(index)) => node[index] = value,
        (Some(value), Err(_)) => node[last.as_str()] = value,
        (None, _) => {
            node.as_object_mut().unwrap().remove(last);
        }
    }
    read(&document).unwrap_err().to_string()
}

/// A path from the document root.
fn at(keys: &[&str]) -> Vec<String> {
    keys.iter().map(ToString::to_string).collect()
}

/// A path inside the green plate's record.
fn green_plate(keys: &[&str]) -> Vec<String> {
    let mut path = at(&[
        "objectFullAnnotation",
        "leftAll",
        "isolatedObjects",
        "Green Plate",
    ]);
    path.extend(at(keys));
    path
}

#[test]
fn malformed_fields_are_errors_naming_the_file_and_the_field() {
    let plate = "objectFullAnnotation.leftAll.isolatedObjects.Green Plate";
    let cases: Vec<(Vec<String>, Option<Value>, String, &str)> = vec![
        (
            at(&["validity"]),
            Some(json!(false)),
            "<root>".into(),
            "validity: false",
        ),
        (
            at(&["mode"]),
            Some(json!("COUNTERFACTUAL_")),
            "mode".into(),
            "FACTUAL_PREDICTIVE",
        ),
        (
            at(&["clothLeft", "friction"]),
            Some(json!("MEDIUM")),
            "clothLeft.friction".into(),
            "`LOW` or `HIGH`",
        ),
        (
            at(&["clothRight", "stretchingCompliance"]),
            Some(json!(-0.01)),
            "clothRight.stretchingCompliance".into(),
            "0 or more",
        ),
        (
            at(&["clothRight", "perRegionAvgForce", "Yellow"]),
            None,
            "clothRight.perRegionAvgForce.Yellow".into(),
            "is missing",
        ),
        (
            green_plate(&["endPoseDescription"]),
            Some(json!("Lying")),
            format!("{plate}.endPoseDescription"),
            "`Upright`, `Reclining`",
        ),
        (
            green_plate(&["colorName"]),
            Some(json!("Blue")),
            format!("{plate}.colorName"),
            "named `Green Plate`",
        ),
        (
            green_plate(&["shape"]),
            Some(json!("Pillar")),
            format!("{plate}.shape"),
            "named `Green Plate`",
        ),
        (
            green_plate(&["colorRGB"]),
            Some(json!("(0.1, 0.2, 0.3)")),
            format!("{plate}.colorRGB"),
            "RGBA(r, g, b, a)",
        ),
        (
            green_plate(&["scale"]),
            Some(json!([1.0, 2.0])),
            format!("{plate}.scale"),
            "3 numbers",
        ),
        (
            green_plate(&["startMovingFrame"]),
            Some(json!(-2)),
            format!("{plate}.startMovingFrame"),
            "or -1",
        ),
        (
            green_plate(&["collisionEvents", "1", "Item1"]),
            Some(json!(-5)),
            format!("{plate}.collisionEvents.1.Item1"),
            "an update",
        ),
        (
            green_plate(&["collisionEvents", "0", "Item2"]),
            Some(json!("")),
            format!("{plate}.collisionEvents.0.Item2"),
            "must name an object",
        ),
        (
            green_plate(&["touchers"]),
            None,
            format!("{plate}.touchers"),
            "is missing",
        ),
        (
            green_plate(&["mass"]),
            Some(json!(0.0)),
            format!("{plate}.mass"),
            "more than 0",
        ),
        (
            green_plate(&["name"]),
            Some(json!("Teal Plate")),
            format!("{plate}.name"),
            "not a box name",
        ),
        (
            at(&[
                "objectFullAnnotation",
                "rightAll",
                "isolatedObjects",
                "Orange Plate",
                "name",
            ]),
            Some(json!("Green Plate")),
            "objectFullAnnotation.rightAll.isolatedObjects.Orange Plate.name".into(),
            "names `Green Plate`, which another box already has",
        ),
        (
            at(&["objectFullAnnotation", "rightAll", "towers"]),
            None,
            "objectFullAnnotation.rightAll.towers".into(),
            "is missing",
        ),
        (
            at(&["outputCamera"]),
            None,
            "outputCamera".into(),
            "is missing",
        ),
    ];
    for (path, value, field, problem) in cases {
        let error = error_after(&path, value);
        assert!(
            error.starts_with("`cloth_collision/0/outputs.json`: field `"),
            "{error}"
        );
        assert!(
            error.contains(&format!("field `{field}`")),
            "{field}: {error}"
        );
        assert!(error.contains(problem), "{field}: {error}");
    }
    // A box keyed under another name.
    let mut document = fixture();
    let isolated = &mut document["objectFullAnnotation"]["rightAll"]["isolatedObjects"];
    isolated["Green Pillar"]["name"] = json!("Pink Pillar");
    isolated["Green Pillar"]["colorName"] = json!("Pink");
    let error = read(&document).unwrap_err().to_string();
    assert!(
        error.contains(
            "isolatedObjects.Green Pillar` is keyed `Green Pillar` but names itself `Pink Pillar`"
        ),
        "{error}"
    );
}
