//! The cloth engine's family keys, question templates and option texts, from the paper's table of
//! cloth templates (`tab:cloth_q`, `docs/data/cloth.md`). The pose options are the pose phrases
//! of `dataset::cloth::outcome` (`Pose::phrase`), so the readers of questions map an option back
//! to the release's label one way.
//!
//! Keys follow the category rule of the sampler: a key containing `predict` is a dynamics
//! (predictive) family, any other a property family.

/// The family keys in generation order.
pub(crate) const FAMILIES: [&str; 6] = [
    ELASTICITY,
    BENDING,
    PREDICTIVE_FALL,
    PREDICTIVE_COLLISION,
    PREDICTIVE_TOUCH,
    PREDICTIVE_POSE,
];

/// Family key: is one cloth much more or less elastic (stretchy) than the other (yes / no).
pub(super) const ELASTICITY: &str = "elasticity";
/// Family key: is one cloth much harder or easier to bend than the other (yes / no).
pub(super) const BENDING: &str = "bending";
/// Family key: does a box fall over.
pub(super) const PREDICTIVE_FALL: &str = "cloth_predictive_fall";
/// Family key: do two boxes collide.
pub(super) const PREDICTIVE_COLLISION: &str = "cloth_predictive_collision";
/// Family key: are two boxes in touch at the end.
pub(super) const PREDICTIVE_TOUCH: &str = "cloth_predictive_touch";
/// Family key: which phrase describes a box's final pose.
pub(super) const PREDICTIVE_POSE: &str = "cloth_predictive_pose";

/// `elasticity`; `{0}` is `left` or `right`, `{1}` `greater than` or `less than`.
pub(super) const ELASTICITY_TITLE: &str =
    "Is the elasticity of the {0} cloth much {1} that of the other?";
/// `bending`; `{0}` is `left` or `right`, `{1}` `harder` or `easier`.
pub(super) const BENDING_TITLE: &str =
    "Is the {0} cloth much {1} to bend or have wrinkles than the other?";
/// `cloth_predictive_fall`; `{0}` is a box (`green plate`).
pub(super) const FALL_TITLE: &str = "Does the {0} fall over?";
/// `cloth_predictive_collision`; `{0}` and `{1}` are boxes.
pub(super) const COLLISION_TITLE: &str = "Does the {0} collide with the {1}?";
/// `cloth_predictive_touch`; `{0}` and `{1}` are boxes.
pub(super) const TOUCH_TITLE: &str = "Is the {0} finally in touch with the {1}?";
/// `cloth_predictive_pose`; `{0}` is a box.
pub(super) const POSE_TITLE: &str =
    "Which phrase below can best describe the final pose of the {0}?";

/// The options of the yes / no predictive questions.
pub(super) const YES: &str = "Yes";
/// See [`YES`].
pub(super) const NO: &str = "No";

/// Fills `{0}`, `{1}` in a template (a placeholder without an argument stays as written).
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
    fn templates_fill_as_the_papers_examples() {
        let cases = [
            (
                fill(ELASTICITY_TITLE, &["left", "greater than"]),
                "Is the elasticity of the left cloth much greater than that of the other?",
            ),
            (
                fill(BENDING_TITLE, &["right", "harder"]),
                "Is the right cloth much harder to bend or have wrinkles than the other?",
            ),
            (
                fill(FALL_TITLE, &["green plate"]),
                "Does the green plate fall over?",
            ),
            (
                fill(COLLISION_TITLE, &["green plate", "gray pillar"]),
                "Does the green plate collide with the gray pillar?",
            ),
            (
                fill(TOUCH_TITLE, &["green plate", "gray pillar"]),
                "Is the green plate finally in touch with the gray pillar?",
            ),
            (
                fill(POSE_TITLE, &["green plate"]),
                "Which phrase below can best describe the final pose of the green plate?",
            ),
        ];
        for (text, expected) in cases {
            assert_eq!(text, expected);
        }
    }

    #[test]
    fn property_keys_are_property_and_the_others_predictive() {
        for family in FAMILIES {
            let predictive = family.contains("predict");
            assert_eq!(
                predictive,
                ![ELASTICITY, BENDING].contains(&family),
                "{family}"
            );
            assert!(!family.contains("counterfact") && !family.contains("goal"));
        }
    }
}
