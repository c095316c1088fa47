//! The rope engine's fixed word lists and question templates (`docs/data/rope.md`), spelled
//! exactly as the public engine writes them.
//!
//! The public engine iterates Python `set`s of colours and shapes, so its question order depended
//! on `PYTHONHASHSEED` (`docs/data/rope.md`, "quirks of the public engine"). Fix: fixed orders. Colours follow the set literal of the
//! public engine with its duplicate `black` dropped; shapes follow their set literal.

/// The 12 colours asked about, in the order of the public engine's set literal.
pub(super) const COLORS: [&str; 12] = [
    "black", "orange", "yellow", "brown", "purple", "cyan", "gray", "red", "white", "pink", "blue",
    "green",
];

/// The shapes counted by the `shape` family. `pulley` counts solid and hollow pulleys together.
pub(super) const SHAPES: [&str; 7] = [
    "cube",
    "sphere",
    "pulley",
    "solid pulley",
    "hollow pulley",
    "rope",
    "fixed point",
];

/// The shapes of the `existence` family: [`SHAPES`] without the bare `pulley`.
pub(super) const EXACT_SHAPES: [&str; 6] = [
    "cube",
    "sphere",
    "solid pulley",
    "hollow pulley",
    "rope",
    "fixed point",
];

/// The family keys in template order, which is also generation order.
pub(crate) const FAMILIES: [&str; 8] = [
    MASS,
    TENSION,
    SHAPE,
    COLOR,
    EXISTENCE,
    COUNTERFACTUAL,
    COUNTERFACTUAL_DIRECTION,
    GOAL_DRIVEN,
];

/// Family key: compare two loads' masses.
pub(super) const MASS: &str = "mass";
/// Family key: compare two ropes' tensions (answered from the hanging loads' masses).
pub(super) const TENSION: &str = "tension";
/// Family key: count objects of a shape.
pub(super) const SHAPE: &str = "shape";
/// Family key: count objects of a colour.
pub(super) const COLOR: &str = "color";
/// Family key: is there an object of a colour and shape.
pub(super) const EXISTENCE: &str = "existence";
/// Family key: which outcomes follow a load's mass change (3–5 options, any number true).
pub(super) const COUNTERFACTUAL: &str = "rope_counterfactual";
/// Family key: which direction one object moves or turns after a mass change (3 options).
pub(super) const COUNTERFACTUAL_DIRECTION: &str = "rope_counterfactual2";
/// Family key: which mass changes make an object move or turn a given way.
pub(super) const GOAL_DRIVEN: &str = "rope_goaldriven";

/// The open-ended answer for two loads in different related groups.
pub(super) const CANNOT_ANSWER: &str = "can not answer";

/// `rope_counterfactual` titles; `{0}` is the changed load, `{1}` `lighter` or `heavier`.
pub(super) const COUNTERFACTUAL_TITLES: [&str; 4] = [
    "If the {0} were much {1}, what would happen?",
    "If the {0} were much {1}, which of the following would happen?",
    "What would happen if the {0} were much {1}?",
    "Which of the following would happen if the {0} were much {1}?",
];

/// `rope_counterfactual2` rotation titles, forward then reversed; `{0}` is the changed load,
/// `{1}` `lighter` or `heavier`, `{2}` the pulley asked about.
pub(super) const ROTATION_DIRECTION_TITLES: [&str; 2] = [
    "If the {0} were much {1}, which direction would the {2} rotate?",
    "Which direction would the {2} rotate if the {0} were much {1}?",
];

/// `rope_counterfactual2` motion titles, as [`ROTATION_DIRECTION_TITLES`].
pub(super) const MOTION_DIRECTION_TITLES: [&str; 2] = [
    "If the {0} were much {1}, which direction would the {2} move?",
    "Which direction would the {2} move if the {0} were much {1}?",
];

/// `rope_goaldriven` titles; `{0}` is the object, `{1}` the goal (`move up`, `rotate clockwise`).
pub(super) const GOAL_TITLES: [&str; 2] = [
    "If we want the {0} to {1}, what can we do?",
    "What can we do to let the {0} to {1}?",
];

/// Fills `{0}`, `{1}`, `{2}` in a template. Templates are constants of this module, so a
/// placeholder without an argument is a bug; it is left as written rather than panicking.
pub(super) fn fill(template: &str, arguments: &[&str]) -> String {
    let mut text = template.to_string();
    for (index, argument) in arguments.iter().enumerate() {
        text = text.replace(&format!("{{{index}}}"), argument);
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn templates_fill_in_any_argument_order() {
        let cases = [
            (
                COUNTERFACTUAL_TITLES[2],
                vec!["pink sphere", "lighter"],
                "What would happen if the pink sphere were much lighter?",
            ),
            (
                ROTATION_DIRECTION_TITLES[1],
                vec!["purple cube", "heavier", "blue pulley"],
                "Which direction would the blue pulley rotate if the purple cube were much heavier?",
            ),
            (
                GOAL_TITLES[1],
                vec!["green cube", "move up"],
                "What can we do to let the green cube to move up?",
            ),
        ];
        for (template, arguments, expected) in cases {
            assert_eq!(fill(template, &arguments), expected);
        }
    }

    #[test]
    fn exact_shapes_are_the_shapes_without_bare_pulley() {
        let without_pulley: Vec<&str> = SHAPES.iter().copied().filter(|s| *s != "pulley").collect();
        assert_eq!(without_pulley, EXACT_SHAPES);
    }
}
