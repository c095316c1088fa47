//! The fluid engine's family keys, question templates and option texts, from the paper's table
//! of fluid templates (`tab:fluid_q`) and its prompts (`docs/data/fluid.md`, questions).
//!
//! Keys follow the category rule of the sampler: a key containing `predict`, `counterfact` or
//! `goal` is a dynamics family, any other a property family.

/// The family keys in generation order.
pub(crate) const FAMILIES: [&str; 7] = [
    DENSITY,
    STICK_NUMBER,
    PREDICTIVE_PASS,
    PREDICTIVE_CONTAINER,
    COUNTERFACTUAL_PASS,
    COUNTERFACTUAL_CONTAINER,
    GOAL_DRIVEN_CONTAINER,
];

/// Family key: compare two fluids' densities (yes / no / can not answer).
pub(super) const DENSITY: &str = "density";
/// Family key: count the sticks.
pub(super) const STICK_NUMBER: &str = "stick_number";
/// Family key: which sticks the predictive emitter's fluid passes.
pub(super) const PREDICTIVE_PASS: &str = "fluid_predictive_pass";
/// Family key: which containers the predictive emitter's fluid flows into.
pub(super) const PREDICTIVE_CONTAINER: &str = "fluid_predictive_container";
/// Family key: which sticks a fluid passes once a stick is removed.
pub(super) const COUNTERFACTUAL_PASS: &str = "fluid_counterfactual_pass";
/// Family key: which containers a fluid flows into once a stick is removed.
pub(super) const COUNTERFACTUAL_CONTAINER: &str = "fluid_counterfactual_container";
/// Family key: which stick removals send most of a fluid into a container.
pub(super) const GOAL_DRIVEN_CONTAINER: &str = "fluid_goaldriven_container";

/// The open-ended answer when no recorded relation links two fluids' densities.
pub(super) const CANNOT_ANSWER: &str = "can not answer";

/// `density`; `{0}` and `{2}` are fluid colours, `{1}` `greater than` or `less than`.
pub(super) const DENSITY_TITLE: &str =
    "Is the fluid density of the {0} fluid {1} that of the {2} fluid?";
/// `stick_number`.
pub(super) const STICK_NUMBER_TITLE: &str = "How many sticks are there in the video?";
/// `fluid_predictive_pass`; `{0}` is the fluid colour.
pub(super) const PREDICTIVE_PASS_TITLE: &str =
    "Which stick will the fluid from the other {0} emitter pass?";
/// `fluid_predictive_container`; `{0}` is the fluid colour.
pub(super) const PREDICTIVE_CONTAINER_TITLE: &str =
    "Which container will fluid from the other {0} emitter flow into?";
/// `fluid_counterfactual_pass`; `{0}` is the removed stick's colour, `{1}` the fluid's.
pub(super) const COUNTERFACTUAL_PASS_TITLE: &str =
    "If the {0} stick were removed, which stick would {1} fluid pass?";
/// `fluid_counterfactual_container`; as [`COUNTERFACTUAL_PASS_TITLE`].
pub(super) const COUNTERFACTUAL_CONTAINER_TITLE: &str =
    "If the {0} stick were removed, which container would {1} fluid flow into?";
/// `fluid_goaldriven_container`; `{0}` is the fluid colour, `{1}` the container's.
pub(super) const GOAL_DRIVEN_CONTAINER_TITLE: &str =
    "What can we do to let most of the {0} fluid enter the {1} container?";

/// Fills `{0}`, `{1}`, `{2}` in a template. Templates are constants of this module, so a
/// placeholder without an argument is a bug; it is left as written rather than panicking.
pub(super) fn fill(template: &str, arguments: &[&str]) -> String {
    let mut text = template.to_string();
    for (index, argument) in arguments.iter().enumerate() {
        text = text.replace(&format!("{{{index}}}"), argument);
    }
    text
}

/// An option naming an object, capitalised as the paper's options are (`Pink stick`,
/// `Light blue container`).
pub(super) fn object_option(color_word: &str, kind: &str) -> String {
    let mut chars = color_word.chars();
    match chars.next() {
        Some(first) => format!("{}{} {kind}", first.to_uppercase(), chars.as_str()),
        None => kind.to_string(),
    }
}

/// A goal-driven option: `Remove the {colour} stick`.
pub(super) fn removal_option(stick_word: &str) -> String {
    format!("Remove the {stick_word} stick")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn templates_fill_and_options_read_as_the_papers() {
        let cases = [
            (
                fill(DENSITY_TITLE, &["pink", "greater than", "light blue"]),
                "Is the fluid density of the pink fluid greater than that of the light blue fluid?",
            ),
            (
                fill(PREDICTIVE_PASS_TITLE, &["blue"]),
                "Which stick will the fluid from the other blue emitter pass?",
            ),
            (
                fill(PREDICTIVE_CONTAINER_TITLE, &["blue"]),
                "Which container will fluid from the other blue emitter flow into?",
            ),
            (
                fill(COUNTERFACTUAL_PASS_TITLE, &["gray", "orange"]),
                "If the gray stick were removed, which stick would orange fluid pass?",
            ),
            (
                fill(COUNTERFACTUAL_CONTAINER_TITLE, &["brown", "pink"]),
                "If the brown stick were removed, which container would pink fluid flow into?",
            ),
            (
                fill(GOAL_DRIVEN_CONTAINER_TITLE, &["pink", "gray"]),
                "What can we do to let most of the pink fluid enter the gray container?",
            ),
            (object_option("pink", "stick"), "Pink stick"),
            (
                object_option("light blue", "container"),
                "Light blue container",
            ),
            (removal_option("green"), "Remove the green stick"),
        ];
        for (text, expected) in cases {
            assert_eq!(text, expected);
        }
    }
}
