//! Fluid scenes as the detector sees them: the four classes the fluid model was trained on (their
//! names are those of `models/maskrcnn-fluid.json`), their kind words, the class and truth
//! object of each release segmentation instance, and the default model files.
//!
//! The segmentation draws a container as five instances (its floor, two walls and two funnel
//! sticks) and a fluid as one instance per emitter, spread over the sticks and cups it reached;
//! the detector was trained on a container as one object and on each connected piece of a
//! fluid (all emitters of its colour) as one detection ([`ClassWords::pieces`]), and the truth
//! of `bench perception` is grouped the same way (`truth_object` below).

use super::ScenarioPerception;
use super::classes::{ClassWords, ScenarioClasses, TruthObject};
use super::color::palette_id_of_name;

/// Palette ids of the release's stick and container colours (`stick_clr_range`).
pub const STICK_COLORS: [u8; 12] = [11, 0, 10, 1, 2, 3, 4, 5, 6, 7, 8, 9];
/// Palette ids of the release's fluid colours (`fluid_clr_range`; 12 is light blue); an
/// emitter has its fluid's colour.
pub const FLUID_COLORS: [u8; 7] = [1, 2, 3, 4, 5, 7, 12];

/// What the release puts before a predictive emitter's fluid key (`Later Emitted Blue Fluid`).
const LATER_PREFIX: &str = "Later Emitted ";

/// The fluid classes, in the fluid model's label order. Sticks and containers are painted from
/// their own shuffled pools (`_Sample_Sticks`, `_Sample_Receptors`), so neither class repeats a
/// colour.
const CLASSES: [ClassWords; 4] = [
    ClassWords {
        name: "stick",
        kind: "stick",
        attributes: &[],
        colors: &STICK_COLORS,
        pieces: false,
        distinct_colors: true,
    },
    ClassWords {
        name: "container",
        kind: "container",
        attributes: &[],
        colors: &STICK_COLORS,
        pieces: false,
        distinct_colors: true,
    },
    ClassWords {
        name: "emitter",
        kind: "emitter",
        attributes: &[],
        colors: &FLUID_COLORS,
        pieces: false,
        // A fluid's first and later emitters share its colour.
        distinct_colors: false,
    },
    ClassWords {
        name: "fluid",
        kind: "fluid",
        attributes: &[],
        colors: &FLUID_COLORS,
        pieces: true,
        distinct_colors: false,
    },
];

/// Fluid perception: its classes and the committed models.
pub const PERCEPTION: ScenarioPerception = ScenarioPerception {
    classes: ScenarioClasses {
        classes: &CLASSES,
        class_of_object,
        truth_object,
    },
    detector: "models/maskrcnn-fluid.onnx",
    colors: "models/color-model-fluid.json",
};

/// The class of a release segmentation name (`Red Stick`, `Red Container Left Guided Stick`,
/// `Later Emitted Pink Fluid Emitter`, `Pink Fluid`); `None` for the tank's walls, floor and
/// ceiling.
fn class_of_object(name: &str) -> Option<&'static str> {
    let words: Vec<&str> = name.split(' ').collect();
    let has = |word: &str| words.contains(&word);
    if has("Container") {
        Some("container")
    } else if has("Emitter") {
        // Emitter side walls are colliders, never drawn; the box is the emitter.
        (!has("Wall")).then_some("emitter")
    } else if has("Stick") {
        Some("stick")
    } else if words.last() == Some(&"Fluid") {
        Some("fluid")
    } else {
        None
    }
}

/// The object a segmentation instance is part of: a container's parts are the container
/// (`Red Container Bottom Floor` → `Red Container`), a later emitter's fluid is its colour's
/// fluid (`Later Emitted Pink Fluid` → `Pink Fluid`); colours from the name's colour words.
fn truth_object(name: &str) -> TruthObject {
    let object = if let Some(at) = name.find(" Container") {
        format!("{} Container", &name[..at])
    } else if name.ends_with(" Fluid") {
        name.strip_prefix(LATER_PREFIX).unwrap_or(name).to_string()
    } else {
        name.to_string()
    };
    let color = palette_id_of_name(name.strip_prefix(LATER_PREFIX).unwrap_or(name));
    TruthObject {
        name: object,
        color,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn release_names_fall_into_the_four_classes() {
        let cases = [
            ("Red Stick", Some("stick")),
            ("Red Container Left Guided Stick", Some("container")),
            ("Red Container Bottom Floor", Some("container")),
            ("Red Container Right Vertical Wall", Some("container")),
            ("Pink Fluid Emitter", Some("emitter")),
            ("Later Emitted Light Blue Fluid Emitter", Some("emitter")),
            ("Pink Fluid Emitter Left Wall", None),
            ("Light Blue Fluid", Some("fluid")),
            ("Later Emitted Pink Fluid", Some("fluid")),
            ("Left Vertical Wall", None),
            ("Floor", None),
            ("Ceiling", None),
        ];
        for (name, class) in cases {
            assert_eq!(class_of_object(name), class, "{name}");
        }
    }

    #[test]
    fn container_parts_and_later_fluids_group_into_their_objects() {
        let object = |name| truth_object(name);
        assert_eq!(
            object("Red Container Left Guided Stick").name,
            "Red Container"
        );
        assert_eq!(
            object("Light Blue Container Bottom Floor").name,
            "Light Blue Container"
        );
        assert_eq!(object("Light Blue Container Bottom Floor").color, Some(12));
        assert_eq!(object("Later Emitted Pink Fluid").name, "Pink Fluid");
        assert_eq!(object("Later Emitted Pink Fluid").color, Some(7));
        // A later emitter is an object of its own, in its fluid's colour.
        let later = object("Later Emitted Cyan Fluid Emitter");
        assert_eq!(later.name, "Later Emitted Cyan Fluid Emitter");
        assert_eq!(later.color, Some(4));
        assert_eq!(object("Black Stick").color, Some(10));
    }

    #[test]
    fn the_class_list_is_the_fluid_model_s() {
        let description =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/maskrcnn-fluid.json");
        let classes = super::super::classes::read_classes(&description)
            .expect("models/maskrcnn-fluid.json lists the classes");
        let names: Vec<&str> = classes.iter().map(|(_, name)| name.as_str()).collect();
        let ours: Vec<&str> = CLASSES.iter().map(|class| class.name).collect();
        assert_eq!(names, ours);
    }
}
