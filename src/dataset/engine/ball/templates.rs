//! The ball engine's family keys, question templates and option texts, from the paper's table of
//! ball templates (`tab:ball_q`) and its API docs (`docs/data/ball.md`, questions).
//!
//! Keys follow the category rule of the sampler: a key containing `predict`, `counterfact` or
//! `goal` is a dynamics family, any other a property family.

/// The family keys in generation order.
pub(crate) const FAMILIES: [&str; 5] = [
    ELASTICITY,
    PLASTICITY,
    PREDICTIVE_DROP,
    COUNTERFACTUAL_REMOVE,
    GOAL_DRIVEN_DROP,
];

/// Family key: compare two balls' elasticity (yes / no).
pub(super) const ELASTICITY: &str = "elasticity";
/// Family key: compare two balls' plasticity (yes / no).
pub(super) const PLASTICITY: &str = "plasticity";
/// Family key: will a ball finally drop into a pit.
pub(super) const PREDICTIVE_DROP: &str = "ball_predictive_drop";
/// Family key: which pit a ball drops into once a floating wall and the other balls are gone.
pub(super) const COUNTERFACTUAL_REMOVE: &str = "ball_counterfactual_remove";
/// Family key: which removals make a ball drop into a pit.
pub(super) const GOAL_DRIVEN_DROP: &str = "ball_goaldriven_drop";

/// `elasticity`; `{0}` and `{2}` are ball colours, `{1}` `greater than` or `less than`.
pub(super) const ELASTICITY_TITLE: &str =
    "Is the elasticity of the {0} ball much {1} the {2} ball?";
/// `plasticity`; as [`ELASTICITY_TITLE`].
pub(super) const PLASTICITY_TITLE: &str =
    "Is the plasticity of the {0} ball much {1} the {2} ball?";
/// `ball_predictive_drop`; `{0}` is the ball's colour, `{1}` `left` or `right`.
pub(super) const PREDICTIVE_DROP_TITLE: &str = "Will the {0} ball finally drop into the {1} pit?";
/// `ball_counterfactual_remove`; `{0}` is the wall's colour, `{1}` the ball's.
pub(super) const COUNTERFACTUAL_REMOVE_TITLE: &str =
    "If we removed the {0} floating wall and other balls, which pit would the {1} ball drop into?";
/// `ball_goaldriven_drop`; `{0}` is the ball's colour, `{1}` `left` or `right`.
pub(super) const GOAL_DRIVEN_DROP_TITLE: &str =
    "What can we do to make the {0} ball drop into the {1} pit?";

/// The options of a predictive question.
pub(super) const YES: &str = "Yes";
/// See [`YES`].
pub(super) const NO: &str = "No";
/// The counterfactual option of a ball that drops into no pit.
pub(super) const NO_PIT: &str = "Neither pit";

/// Fills `{0}`, `{1}`, `{2}` in a template (a placeholder without an argument stays as written).
pub(super) fn fill(template: &str, arguments: &[&str]) -> String {
    let mut text = template.to_string();
    for (index, argument) in arguments.iter().enumerate() {
        text = text.replace(&format!("{{{index}}}"), argument);
    }
    text
}

/// A counterfactual option naming a pit: `The left pit`.
pub(super) fn pit_option(side: &str) -> String {
    format!("The {side} pit")
}

/// A goal-driven option, the paper's API wording: `Remove the red floating wall and other balls`.
pub(super) fn removal_option(wall_word: &str) -> String {
    format!("Remove the {wall_word} floating wall and other balls")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn templates_fill_as_the_papers() {
        let cases = [
            (
                fill(ELASTICITY_TITLE, &["red", "greater than", "light blue"]),
                "Is the elasticity of the red ball much greater than the light blue ball?",
            ),
            (
                fill(PLASTICITY_TITLE, &["red", "less than", "blue"]),
                "Is the plasticity of the red ball much less than the blue ball?",
            ),
            (
                fill(PREDICTIVE_DROP_TITLE, &["pink", "left"]),
                "Will the pink ball finally drop into the left pit?",
            ),
            (
                fill(COUNTERFACTUAL_REMOVE_TITLE, &["white", "pink"]),
                "If we removed the white floating wall and other balls, which pit would the pink ball drop into?",
            ),
            (
                fill(GOAL_DRIVEN_DROP_TITLE, &["pink", "right"]),
                "What can we do to make the pink ball drop into the right pit?",
            ),
            (pit_option("left"), "The left pit"),
            (
                removal_option("green"),
                "Remove the green floating wall and other balls",
            ),
        ];
        for (text, expected) in cases {
            assert_eq!(text, expected);
        }
    }
}
