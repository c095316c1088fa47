//! Rope scenes as the detector sees them: the eight classes the rope model was trained on (their
//! names are those of `models/maskrcnn-rope.json`), their kind and attribute words, and the class
//! of each release object name (ground truth), with the default model files.

use super::ScenarioPerception;
use super::classes::{ClassWords, ScenarioClasses};

/// The base colour list of the release's objects: loads, pulleys and fixed points take every
/// colour but black (`PlacementConfig`'s pools; palette ids of `perception::palette`).
pub const OBJECT_COLORS: [u8; 11] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 11];
/// The base colour list of the release's ropes: no orange, brown or gray.
pub const ROPE_COLORS: [u8; 9] = [0, 2, 3, 4, 5, 6, 7, 10, 11];

/// The colours an object can have: its base list, then the light colours (12–16) a pool hands
/// out once its base list is used up.
const OBJECT_PALETTE: [u8; 16] = with_light_colors(OBJECT_COLORS);
/// The colours a rope can have.
const ROPE_PALETTE: [u8; 14] = with_light_colors(ROPE_COLORS);

/// `base` followed by the light colours (`M` = `N` + 5, checked when the constant is built).
const fn with_light_colors<const N: usize, const M: usize>(base: [u8; N]) -> [u8; M] {
    let light = super::palette::LIGHT_COLORS;
    assert!(
        M == N + light.len(),
        "a palette is its base list and the light colours"
    );
    let mut out = [0; M];
    let mut i = 0;
    while i < M {
        out[i] = if i < N { base[i] } else { light[i - N] };
        i += 1;
    }
    out
}

/// The rope classes, in the rope model's label order.
const CLASSES: [ClassWords; 8] = [
    ClassWords {
        name: "cube",
        kind: "cube",
        attributes: &[("dynamic", "dynamic")],
        colors: &OBJECT_PALETTE,
        pieces: false,
        // The release fills each of the eight classes from its own shuffled colour pool, and a
        // pool repeats only after its 16 colours.
        distinct_colors: true,
    },
    ClassWords {
        name: "sphere",
        kind: "sphere",
        attributes: &[("dynamic", "dynamic")],
        colors: &OBJECT_PALETTE,
        pieces: false,
        // The release fills each of the eight classes from its own shuffled colour pool, and a
        // pool repeats only after its 16 colours.
        distinct_colors: true,
    },
    ClassWords {
        name: "rope",
        kind: "rope",
        attributes: &[("dynamic", "dynamic")],
        colors: &ROPE_PALETTE,
        pieces: false,
        // The release fills each of the eight classes from its own shuffled colour pool, and a
        // pool repeats only after its 16 colours.
        distinct_colors: true,
    },
    ClassWords {
        name: "fixed point",
        kind: "fixed point",
        attributes: &[("dynamic", "static")],
        colors: &OBJECT_PALETTE,
        pieces: false,
        // The release fills each of the eight classes from its own shuffled colour pool, and a
        // pool repeats only after its 16 colours.
        distinct_colors: true,
    },
    ClassWords {
        name: "solid static pulley",
        kind: "pulley",
        attributes: &[("shape", "solid"), ("dynamic", "static")],
        colors: &OBJECT_PALETTE,
        pieces: false,
        // The release fills each of the eight classes from its own shuffled colour pool, and a
        // pool repeats only after its 16 colours.
        distinct_colors: true,
    },
    ClassWords {
        name: "hollow static pulley",
        kind: "pulley",
        attributes: &[("shape", "hollow"), ("dynamic", "static")],
        colors: &OBJECT_PALETTE,
        pieces: false,
        // The release fills each of the eight classes from its own shuffled colour pool, and a
        // pool repeats only after its 16 colours.
        distinct_colors: true,
    },
    ClassWords {
        name: "solid dynamic pulley",
        kind: "pulley",
        attributes: &[("shape", "solid"), ("dynamic", "dynamic")],
        colors: &OBJECT_PALETTE,
        pieces: false,
        // The release fills each of the eight classes from its own shuffled colour pool, and a
        // pool repeats only after its 16 colours.
        distinct_colors: true,
    },
    ClassWords {
        name: "hollow dynamic pulley",
        kind: "pulley",
        attributes: &[("shape", "hollow"), ("dynamic", "dynamic")],
        colors: &OBJECT_PALETTE,
        pieces: false,
        // The release fills each of the eight classes from its own shuffled colour pool, and a
        // pool repeats only after its 16 colours.
        distinct_colors: true,
    },
];

/// Rope perception: its classes and the committed models.
pub const PERCEPTION: ScenarioPerception = ScenarioPerception {
    classes: ScenarioClasses {
        classes: &CLASSES,
        class_of_object,
        truth_object: super::classes::instance_is_object,
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
    fn class_colours_are_the_release_pools_then_the_light_colours() {
        use crate::perception::palette::LIGHT_COLORS;
        let object: Vec<u8> = OBJECT_COLORS.iter().chain(&LIGHT_COLORS).copied().collect();
        let rope: Vec<u8> = ROPE_COLORS.iter().chain(&LIGHT_COLORS).copied().collect();
        for class in CLASSES {
            let expected = if class.name == "rope" { &rope } else { &object };
            assert_eq!(class.colors, expected.as_slice(), "{}", class.name);
        }
        // Black (10) is a rope colour only; gray (9) an object colour only.
        assert!(!OBJECT_PALETTE.contains(&10) && ROPE_PALETTE.contains(&10));
        assert!(OBJECT_PALETTE.contains(&9) && !ROPE_PALETTE.contains(&9));
    }

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
