//! Rope scenes as the detector sees them: the eight classes the rope model was trained on (their
//! names are those of `models/maskrcnn-rope.json`), their kind and attribute words, and the class
//! of each release object name (ground truth), with the default model files.

use super::ScenarioPerception;
use super::classes::{ClassWords, ScenarioClasses};

/// The rope classes, in the rope model's label order.
const CLASSES: [ClassWords; 8] = [
    ClassWords {
        name: "cube",
        kind: "cube",
        attributes: &[("dynamic", "dynamic")],
    },
    ClassWords {
        name: "sphere",
        kind: "sphere",
        attributes: &[("dynamic", "dynamic")],
    },
    ClassWords {
        name: "rope",
        kind: "rope",
        attributes: &[("dynamic", "dynamic")],
    },
    ClassWords {
        name: "fixed point",
        kind: "fixed point",
        attributes: &[("dynamic", "static")],
    },
    ClassWords {
        name: "solid static pulley",
        kind: "pulley",
        attributes: &[("shape", "solid"), ("dynamic", "static")],
    },
    ClassWords {
        name: "hollow static pulley",
        kind: "pulley",
        attributes: &[("shape", "hollow"), ("dynamic", "static")],
    },
    ClassWords {
        name: "solid dynamic pulley",
        kind: "pulley",
        attributes: &[("shape", "solid"), ("dynamic", "dynamic")],
    },
    ClassWords {
        name: "hollow dynamic pulley",
        kind: "pulley",
        attributes: &[("shape", "hollow"), ("dynamic", "dynamic")],
    },
];

/// Rope perception: its classes and the committed models.
pub const PERCEPTION: ScenarioPerception = ScenarioPerception {
    classes: ScenarioClasses {
        classes: &CLASSES,
        class_of_object,
    },
    detector: "models/maskrcnn-rope.onnx",
    colors: "models/color-model.json",
};

/// The class of a release object name (`Pink Hollow Static Pulley (0 5)`, `Gray Sphere`,
/// `Red Fixed Point`); `None` for names that are no class (`Solver`, `Shaft of …`).
fn class_of_object(name: &str) -> Option<&'static str> {
    let lower = name.to_lowercase();
    let words: Vec<&str> = lower
        .split(|c: char| !c.is_ascii_alphabetic())
        .filter(|w| !w.is_empty())
        .collect();
    let has = |word: &str| words.contains(&word);
    if has("shaft") {
        return None;
    }
    if has("pulley") {
        return Some(match (has("hollow"), has("dynamic")) {
            (false, false) => "solid static pulley",
            (true, false) => "hollow static pulley",
            (false, true) => "solid dynamic pulley",
            (true, true) => "hollow dynamic pulley",
        });
    }
    if has("cube") {
        Some("cube")
    } else if has("sphere") {
        Some("sphere")
    } else if has("rope") {
        Some("rope")
    } else if has("fixed") && has("point") {
        Some("fixed point")
    } else {
        None
    }
}

/// The rope class called `name`, labelled as in the rope model (for tests of shared perception
/// code).
#[cfg(test)]
pub(crate) fn test_class(name: &str) -> super::classes::Class {
    let table = super::classes::ClassTable::of_scenario(PERCEPTION.classes);
    table
        .all()
        .find(|class| table.name(*class) == name)
        .expect("a rope class name")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::classes::{ClassTable, read_classes};

    #[test]
    fn object_names_of_the_release_map_to_classes() {
        let cases = [
            (
                "Pink Hollow Static Pulley (0 5)",
                Some("hollow static pulley"),
            ),
            (
                "Blue Solid Static Pulley (0 1)",
                Some("solid static pulley"),
            ),
            (
                "Red Hollow Dynamic Pulley (1 2)",
                Some("hollow dynamic pulley"),
            ),
            (
                "Green Solid Dynamic Pulley (1 0)",
                Some("solid dynamic pulley"),
            ),
            ("Gray Sphere", Some("sphere")),
            ("Light Blue Cube", Some("cube")),
            ("Purple Rope", Some("rope")),
            ("Brown Fixed Point", Some("fixed point")),
            ("Solver", None),
        ];
        for (name, class) in cases {
            assert_eq!(class_of_object(name), class, "{name}");
        }
    }

    #[test]
    fn the_committed_model_describes_exactly_these_classes_in_this_order() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/maskrcnn-rope.json");
        let described = read_classes(&path).unwrap();
        let expected: Vec<(u16, String)> = CLASSES
            .iter()
            .zip(1_u16..)
            .map(|(class, label)| (label, class.name.to_string()))
            .collect();
        assert_eq!(described, expected);
        let table =
            ClassTable::for_model(&path.with_extension("onnx"), PERCEPTION.classes).unwrap();
        assert_eq!(table.all().count(), 8);
    }
}
