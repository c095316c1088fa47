//! Cloth scenes as the detector sees them: the three classes the cloth model was trained on
//! (their names are those of `models/maskrcnn-cloth.json`), their kind words, the class and truth
//! object of each release segmentation name, and the default model files.
//!
//! Each half of the table has its cloth (`Cloth (Left)`, `Cloth (Right)`), one or two pillars
//! (`<C> Pillar`) and one or two plates (`<C> Plate`); the table is background and a cube (`<C>
//! Cube`, a tower layer the release practically never writes) is no class. A cloth's side is not
//! a class (its position tells it), and neither is its colour: the cloth is painted a random soft
//! tint that no name or question uses, so it may read as any palette colour and carries no
//! colour truth. Pillars and plates take their colours from one palette list, each shape from
//! its own shuffled copy, so neither class repeats a colour.

use super::ScenarioPerception;
use super::classes::{ClassWords, ScenarioClasses, instance_is_object};
use super::color::palette_id_of_name;

/// Palette ids of the pillars' and plates' colours (Orange, Yellow, Green, Cyan, Blue, Purple,
/// Pink, Brown, Gray, White): at most four boxes of a shape are drawn from the shuffled ten, so
/// the light colours that follow them in the release's list are never reached.
pub const BOX_COLORS: [u8; 10] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 11];

/// The cloth classes, in the cloth model's label order.
const CLASSES: [ClassWords; 3] = [
    ClassWords {
        name: "cloth",
        kind: "cloth",
        attributes: &[],
        // Any: the cloth's tint is not a palette colour, and the colour read for it is unused.
        colors: &[],
        pieces: false,
        distinct_colors: false,
    },
    ClassWords {
        name: "pillar",
        kind: "pillar",
        attributes: &[],
        colors: &BOX_COLORS,
        pieces: false,
        distinct_colors: true,
    },
    ClassWords {
        name: "plate",
        kind: "plate",
        attributes: &[],
        colors: &BOX_COLORS,
        pieces: false,
        distinct_colors: true,
    },
];

/// Cloth perception: its classes and the committed models.
pub const PERCEPTION: ScenarioPerception = ScenarioPerception {
    classes: ScenarioClasses {
        classes: &CLASSES,
        class_of_object,
        truth_object: instance_is_object,
    },
    detector: "models/maskrcnn-cloth.onnx",
    colors: "models/color-model-cloth.json",
};

/// The class of a release segmentation name (`Cloth (Left)`, `Gray Pillar`, `Light Blue
/// Plate`); `None` for anything else (`Table`, `Green Cube`).
fn class_of_object(name: &str) -> Option<&'static str> {
    if name == "Cloth (Left)" || name == "Cloth (Right)" {
        return Some("cloth");
    }
    palette_id_of_name(name)?;
    if name.ends_with(" Pillar") {
        Some("pillar")
    } else if name.ends_with(" Plate") {
        Some("plate")
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn release_names_fall_into_the_three_classes() {
        let cases = [
            ("Cloth (Left)", Some("cloth")),
            ("Cloth (Right)", Some("cloth")),
            ("Gray Pillar", Some("pillar")),
            ("Light Blue Pillar", Some("pillar")),
            ("Orange Plate", Some("plate")),
            ("White Plate", Some("plate")),
            ("Green Cube", None),
            ("Table", None),
            ("Cloth", None),
            ("Pillar", None),
            ("Plate", None),
        ];
        for (name, class) in cases {
            assert_eq!(class_of_object(name), class, "{name}");
        }
    }

    #[test]
    fn boxes_are_coloured_by_their_names_and_cloths_not_at_all() {
        let truth = PERCEPTION.classes.truth_object;
        assert_eq!(truth("Gray Pillar").color, Some(9));
        assert_eq!(truth("White Plate").color, Some(11));
        assert_eq!(truth("Cloth (Left)").color, None);
        assert_eq!(truth("Cloth (Right)").name, "Cloth (Right)");
    }

    #[test]
    fn box_colours_are_the_generator_s_and_the_cloth_any() {
        let names: Vec<&str> = BOX_COLORS
            .iter()
            .filter_map(|id| crate::perception::palette::palette_color(*id))
            .map(|color| color.name)
            .collect();
        assert_eq!(
            names,
            [
                "Orange", "Yellow", "Green", "Cyan", "Blue", "Purple", "Pink", "Brown", "Gray",
                "White"
            ]
        );
        assert!(CLASSES[0].colors.is_empty());
    }

    #[test]
    fn the_class_list_is_the_cloth_model_s() {
        let description =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/maskrcnn-cloth.json");
        let classes = super::super::classes::read_classes(&description)
            .expect("models/maskrcnn-cloth.json lists the classes");
        let names: Vec<&str> = classes.iter().map(|(_, name)| name.as_str()).collect();
        let ours: Vec<&str> = CLASSES.iter().map(|class| class.name).collect();
        assert_eq!(names, ours);
    }
}
