//! Ball scenes as the detector sees them: the four classes the ball model was trained on (their
//! names are those of `models/maskrcnn-ball.json`), their kind words, the class and truth object
//! of each release segmentation name, and the default model files.
//!
//! Material is not a class: the release draws the elastic and the rigid ball with one prefab,
//! and a plastic ball differs from them only by its dent, which the dynamics read from the
//! ball's track (`scene_api::ball`). A ramp's side is not a class either (its position tells
//! it). The ramps' colours are not in their segmentation names (`Right Ramp`), so ramps carry no
//! colour truth; the balls' and floating walls' colours come from the same palette list.

use super::ScenarioPerception;
use super::classes::{ClassWords, ScenarioClasses, TruthObject, instance_is_object};

/// Palette ids of the release's ramp, floating wall and ball colours (White, Red, Black, Orange,
/// Yellow, Green, Cyan, Blue, Purple, Pink, Brown).
pub const SLAB_AND_BALL_COLORS: [u8; 11] = [11, 0, 10, 1, 2, 3, 4, 5, 6, 7, 8];
/// The floor pieces' colour (Gray).
pub const FLOOR_COLORS: [u8; 1] = [9];

/// The ball classes, in the ball model's label order. Balls take three distinct colours from one
/// shuffled pool, ramps and floating walls four distinct colours from another, so neither class
/// repeats a colour; the three floor pieces are all gray.
const CLASSES: [ClassWords; 4] = [
    ClassWords {
        name: "ball",
        kind: "ball",
        attributes: &[],
        colors: &SLAB_AND_BALL_COLORS,
        pieces: false,
        distinct_colors: true,
    },
    ClassWords {
        name: "floating wall",
        kind: "floating wall",
        attributes: &[],
        colors: &SLAB_AND_BALL_COLORS,
        pieces: false,
        distinct_colors: true,
    },
    ClassWords {
        name: "ramp",
        kind: "ramp",
        attributes: &[],
        colors: &SLAB_AND_BALL_COLORS,
        pieces: false,
        distinct_colors: true,
    },
    ClassWords {
        name: "floor piece",
        kind: "floor piece",
        attributes: &[],
        colors: &FLOOR_COLORS,
        pieces: false,
        distinct_colors: false,
    },
];

/// Ball perception: its classes and the committed models.
pub const PERCEPTION: ScenarioPerception = ScenarioPerception {
    classes: ScenarioClasses {
        classes: &CLASSES,
        class_of_object,
        truth_object,
    },
    detector: "models/maskrcnn-ball.onnx",
    colors: "models/color-model-ball.json",
};

/// The class of a release segmentation name (`Red Ball`, `White Floating Wall`, `Right Ramp`,
/// `Floor Piece 2nd`); `None` for anything else (the backdrop).
fn class_of_object(name: &str) -> Option<&'static str> {
    if name.ends_with(" Ball") {
        Some("ball")
    } else if name.ends_with(" Floating Wall") {
        Some("floating wall")
    } else if name == "Right Ramp" || name == "Left Ramp" {
        Some("ramp")
    } else if name.starts_with("Floor Piece") {
        Some("floor piece")
    } else {
        None
    }
}

/// Every instance is its own object; balls and walls are coloured by their names' colour words,
/// floor pieces are gray, ramps' colours are not in their names.
fn truth_object(name: &str) -> TruthObject {
    let mut object = instance_is_object(name);
    if name.starts_with("Floor Piece") {
        object.color = Some(FLOOR_COLORS[0]);
    }
    object
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn release_names_fall_into_the_four_classes() {
        let cases = [
            ("Red Ball", Some("ball")),
            ("Light Blue Ball", Some("ball")),
            ("White Floating Wall", Some("floating wall")),
            ("Right Ramp", Some("ramp")),
            ("Left Ramp", Some("ramp")),
            ("Floor Piece 1st", Some("floor piece")),
            ("Floor Piece 3rd", Some("floor piece")),
            ("Backdrop", None),
            ("Ramp", None),
        ];
        for (name, class) in cases {
            assert_eq!(class_of_object(name), class, "{name}");
        }
    }

    #[test]
    fn balls_and_walls_are_coloured_by_their_names_and_floor_pieces_gray() {
        assert_eq!(truth_object("Red Ball").color, Some(0));
        assert_eq!(truth_object("Brown Floating Wall").color, Some(8));
        assert_eq!(truth_object("Floor Piece 2nd").color, Some(9));
        assert_eq!(truth_object("Right Ramp").color, None);
        assert_eq!(truth_object("Right Ramp").name, "Right Ramp");
    }

    #[test]
    fn the_class_list_is_the_ball_model_s() {
        let description =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/maskrcnn-ball.json");
        let classes = super::super::classes::read_classes(&description)
            .expect("models/maskrcnn-ball.json lists the classes");
        let names: Vec<&str> = classes.iter().map(|(_, name)| name.as_str()).collect();
        let ours: Vec<&str> = CLASSES.iter().map(|class| class.name).collect();
        assert_eq!(names, ours);
    }
}
