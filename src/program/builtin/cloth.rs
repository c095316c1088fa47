//! The builtin writer's cloth programs: the cloth engine's templates (`dataset::engine::cloth`,
//! the paper's table of cloth templates) parsed into programs that find the cloths and boxes,
//! compare a cloth property, or start the video's future and ask `happen` or `final_pose`.
//!
//! | question | program |
//! |---|---|
//! | `Is the elasticity of the left cloth much greater than / less than that of the other?` | `query_pair('elasticity', left cloth, right cloth)`; greater is `>` |
//! | `Is the left cloth much harder / easier to bend or have wrinkles than the other?` | `query_pair('bending', …)`: `bending` is how easily a cloth bends, so harder is `<` |
//! | `Does the C plate fall over?` \| `Yes` / `No` | `simulate`; the box `falling`, or not |
//! | `Does the C plate collide with the D pillar?` \| `Yes` / `No` | `simulate`; the first box `collision` with the second, or not |
//! | `Is the C plate finally in touch with the D pillar?` \| `Yes` / `No` | `simulate`; `touching`, or not |
//! | `Which phrase below can best describe the final pose of the C plate?` \| a pose phrase | `simulate`; `final_pose(box)` is the option's phrase |

use super::{Writer, WriterError, between, literal, object_phrase, unrecognised};
use crate::dataset::cloth::names::Side;
use crate::dataset::cloth::outcome::Pose;

/// The cloth writer.
pub const WRITER: Writer = Writer {
    version: "builtin-cloth-v1",
    open_body: open_ended_body,
    option_body: choice_body,
};

/// The elasticity template's comparators and the operator each means on `elasticity` values.
const ELASTICITY_COMPARATORS: [(&str, &str); 2] = [("greater than", ">"), ("less than", "<")];
/// The bending template's comparators: `bending` grows with how easily a cloth bends, so a
/// cloth harder to bend has the smaller value.
const BENDING_COMPARATORS: [(&str, &str); 2] = [("harder", "<"), ("easier", ">")];

/// The side a cloth phrase names (`left cloth`, `the left cloth`, `left`).
fn cloth_side(phrase: &str) -> Option<Side> {
    let phrase = object_phrase(phrase);
    let side = phrase.strip_suffix(" cloth").unwrap_or(phrase).trim();
    Side::BOTH
        .into_iter()
        .find(|candidate| candidate.word() == side)
}

/// Splits `<cloth> much <comparator>` into the cloth's side and the comparator's operator.
fn cloth_and_operator(
    rest: &str,
    comparators: &[(&str, &'static str)],
) -> Option<(Side, &'static str)> {
    comparators.iter().find_map(|(word, operator)| {
        let head = rest.strip_suffix(word)?.trim_end();
        let cloth = head.strip_suffix(" much").unwrap_or(head);
        Some((cloth_side(cloth)?, *operator))
    })
}

/// The body for an open cloth question: a comparison of the two cloths.
fn open_ended_body(title: &str) -> Result<String, WriterError> {
    let lower = title.trim().to_lowercase();
    let parsed =
        if let Some(rest) = between(&lower, "is the elasticity of the ", " that of the other?") {
            cloth_and_operator(rest, &ELASTICITY_COMPARATORS).map(|found| ("elasticity", found))
        } else {
            between(
                &lower,
                "is the ",
                " to bend or have wrinkles than the other?",
            )
            .and_then(|rest| cloth_and_operator(rest, &BENDING_COMPARATORS))
            .map(|found| ("bending", found))
        };
    let (property, (side, operator)) = parsed.ok_or_else(|| unrecognised("question", title))?;
    Ok(format!(
        "    cloth = cloth_scene.find({cloth})\n    other = cloth_scene.find({other})\n    \
         cloth_value, other_value = cloth_scene.query_pair('{property}', cloth, other)\n    \
         return bool_to_yesno(cloth_value {operator} other_value)\n",
        cloth = literal(&format!("{} cloth", side.word())),
        other = literal(&format!("{} cloth", side.other().word())),
    ))
}

/// A cloth choice question, parsed from its title (lower case); boxes are phrases such as
/// `green plate`.
#[derive(Debug, Clone, PartialEq, Eq)]
enum ChoiceQuestion {
    /// "Does the {box} fall over?"
    Fall { subject: String },
    /// "Does the {box} collide with the {box}?"
    Collision { subject: String, other: String },
    /// "Is the {box} finally in touch with the {box}?"
    Touch { subject: String, other: String },
    /// "Which phrase below can best describe the final pose of the {box}?"
    Pose { subject: String },
}

/// A pillar or plate phrase (`the green plate` → `green plate`); `None` for anything else, so
/// a question about another object is not guessed at.
fn box_phrase(text: &str) -> Option<String> {
    let phrase = object_phrase(text);
    (phrase.ends_with(" pillar") || phrase.ends_with(" plate")).then(|| phrase.to_string())
}

impl ChoiceQuestion {
    fn parse(title: &str) -> Option<ChoiceQuestion> {
        let lower = title.trim().to_lowercase();
        if let Some(subject) = between(&lower, "does ", " fall over?") {
            return Some(ChoiceQuestion::Fall {
                subject: box_phrase(subject)?,
            });
        }
        if let Some(rest) = between(&lower, "does ", "?") {
            let (subject, other) = rest.split_once(" collide with ")?;
            return Some(ChoiceQuestion::Collision {
                subject: box_phrase(subject)?,
                other: box_phrase(other)?,
            });
        }
        if let Some(rest) = between(&lower, "is ", "?") {
            let (subject, other) = rest.split_once(" finally in touch with ")?;
            return Some(ChoiceQuestion::Touch {
                subject: box_phrase(subject)?,
                other: box_phrase(other)?,
            });
        }
        let subject = between(
            &lower,
            "which phrase below can best describe the final pose of ",
            "?",
        )?;
        Some(ChoiceQuestion::Pose {
            subject: box_phrase(subject)?,
        })
    }
}

/// The lines that start the video's future as `dynamic_scene`.
const SIMULATE: &str = "    event = cloth_scene.register_event([], \"simulate\", \"\")\n    \
                        dynamic_scene = cloth_scene.init_dyn_simulation(event)\n";

/// `not ` for a `No` option, nothing for `Yes`.
fn negation(option: &str) -> Result<&'static str, WriterError> {
    match option.trim().trim_end_matches('.').to_lowercase().as_str() {
        "yes" => Ok(""),
        "no" => Ok("not "),
        _ => Err(unrecognised("option", option)),
    }
}

/// The body of a yes / no question about a relation between two boxes.
fn relation_body(
    subject: &str,
    other: &str,
    action: &str,
    option: &str,
) -> Result<String, WriterError> {
    Ok(format!(
        "{SIMULATE}    first = cloth_scene.find({})\n    second = cloth_scene.find({})\n    \
         return bool_to_yesno({}dynamic_scene.happen(first, \"{action}\", second))\n",
        literal(subject),
        literal(other),
        negation(option)?,
    ))
}

/// The body for one option of a cloth choice question; it returns "yes" when the option holds.
fn choice_body(title: &str, option: &str) -> Result<String, WriterError> {
    let question = ChoiceQuestion::parse(title).ok_or_else(|| unrecognised("question", title))?;
    match question {
        ChoiceQuestion::Fall { subject } => Ok(format!(
            "{SIMULATE}    box = cloth_scene.find({})\n    \
             return bool_to_yesno({}dynamic_scene.happen(box, \"falling\", \"\"))\n",
            literal(&subject),
            negation(option)?,
        )),
        ChoiceQuestion::Collision { subject, other } => {
            relation_body(&subject, &other, "collision", option)
        }
        ChoiceQuestion::Touch { subject, other } => {
            relation_body(&subject, &other, "touching", option)
        }
        ChoiceQuestion::Pose { subject } => {
            // The option's phrase as `final_pose` spells it, whatever its case or spacing.
            let pose = Pose::from_phrase(option.trim().trim_end_matches('.'))
                .ok_or_else(|| unrecognised("option", option))?;
            Ok(format!(
                "{SIMULATE}    box = cloth_scene.find({})\n    \
                 return bool_to_yesno(dynamic_scene.final_pose(box) == {})\n",
                literal(&subject),
                literal(pose.phrase()),
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::{Question, Scenario};
    use crate::program::builtin::test_question;
    use crate::program::builtin::{write_program as write, write_question_program};

    fn question(text: &str, answer: &str, family: &str, answer_type: &str) -> Question {
        test_question(Scenario::Cloth, text, answer, family, answer_type)
    }

    #[test]
    fn bending_question_becomes_a_query_pair_comparison() {
        let q = question(
            "Is the right cloth much harder to bend or have wrinkles than the other?",
            "no",
            "bending",
            "open_ended",
        );
        insta::assert_snapshot!(write(&q, None, &WRITER).unwrap());
    }

    #[test]
    fn pose_option_compares_the_final_pose_with_its_phrase() {
        let q = question(
            "Which phrase below can best describe the final pose of the light blue pillar?\nA. It stands upright\nB. it lies flat on its back, front or side.",
            "B",
            "cloth_predictive_pose",
            "multiple_choice",
        );
        insta::assert_snapshot!(write(&q, q.options.first(), &WRITER).unwrap());
        // An option in another case or with a full stop is still the pose's own phrase.
        let second = write(&q, q.options.get(1), &WRITER).unwrap();
        assert!(
            second.ends_with(
                "return bool_to_yesno(dynamic_scene.final_pose(box) == \"It lies flat on its back, front or side\")\n"
            ),
            "{second}"
        );
    }

    #[test]
    fn every_template_family_is_recognised() {
        let cases = [
            (
                "Is the elasticity of the left cloth much greater than that of the other?",
                "elasticity",
                false,
                "    cloth = cloth_scene.find(\"left cloth\")\n    other = cloth_scene.find(\"right cloth\")\n    cloth_value, other_value = cloth_scene.query_pair('elasticity', cloth, other)\n    return bool_to_yesno(cloth_value > other_value)\n",
            ),
            (
                "Is the elasticity of the right cloth much less than that of the other?",
                "elasticity",
                false,
                "return bool_to_yesno(cloth_value < other_value)",
            ),
            (
                "Is the left cloth much easier to bend or have wrinkles than the other?",
                "bending",
                false,
                "query_pair('bending', cloth, other)\n    return bool_to_yesno(cloth_value > other_value)",
            ),
            (
                "Does the green plate fall over?\nA. Yes\nB. No",
                "cloth_predictive_fall",
                true,
                "    box = cloth_scene.find(\"green plate\")\n    return bool_to_yesno(dynamic_scene.happen(box, \"falling\", \"\"))\n",
            ),
            (
                "Does the green plate collide with the gray pillar?\nA. Yes\nB. No",
                "cloth_predictive_collision",
                true,
                "    first = cloth_scene.find(\"green plate\")\n    second = cloth_scene.find(\"gray pillar\")\n    return bool_to_yesno(dynamic_scene.happen(first, \"collision\", second))\n",
            ),
            (
                "Is the orange plate finally in touch with the yellow pillar?\nA. Yes\nB. No",
                "cloth_predictive_touch",
                true,
                "return bool_to_yesno(dynamic_scene.happen(first, \"touching\", second))\n",
            ),
        ];
        for (text, family, choice, expected) in cases {
            let (answer, answer_type) = if choice {
                ("A", "multiple_choice")
            } else {
                ("yes", "open_ended")
            };
            let q = question(text, answer, family, answer_type);
            let option = q.options.first();
            let program = write(&q, option, &WRITER).unwrap();
            assert!(program.contains(expected), "{text}\n{program}");
            assert!(
                program.contains("    cloth_scene = SoftScene(video, 'cloth')\n"),
                "{program}"
            );
            assert_eq!(
                program.contains("register_event([], \"simulate\", \"\")"),
                choice,
                "{program}"
            );
            if choice {
                let no = write(&q, q.options.get(1), &WRITER).unwrap();
                assert!(
                    no.contains("return bool_to_yesno(not dynamic_scene.happen("),
                    "{no}"
                );
            }
        }
    }

    #[test]
    fn a_per_question_program_checks_every_pose() {
        let options: Vec<String> = Pose::ALL
            .iter()
            .zip(['A', 'B', 'C', 'D', 'E'])
            .map(|(pose, letter)| format!("{letter}. {}", pose.phrase()))
            .collect();
        let q = question(
            &format!(
                "Which phrase below can best describe the final pose of the green plate?\n{}",
                options.join("\n")
            ),
            "C",
            "cloth_predictive_pose",
            "multiple_choice",
        );
        let program = write_question_program(&q, &WRITER).unwrap();
        for pose in Pose::ALL {
            assert!(
                program.contains(&format!("final_pose(box) == \"{}\"", pose.phrase())),
                "{program}"
            );
        }
        assert_eq!(program.matches("def option_").count(), 5, "{program}");
    }

    #[test]
    fn unknown_text_or_options_are_errors_not_guesses() {
        let q = question(
            "Does the green plate fall over?\nA. Maybe",
            "A",
            "cloth_predictive_fall",
            "multiple_choice",
        );
        let error = write(&q, q.options.first(), &WRITER).unwrap_err();
        assert_eq!(
            error.to_string(),
            "the builtin writer does not recognise the option `Maybe`"
        );
        let q = question(
            "Which phrase below can best describe the final pose of the green plate?\nA. Upright",
            "A",
            "cloth_predictive_pose",
            "multiple_choice",
        );
        // The release's label is not an option phrase.
        assert!(write(&q, q.options.first(), &WRITER).is_err());
        for (text, family) in [
            ("Is the cloth soft?", "elasticity"),
            (
                "Is the elasticity of the middle cloth much greater than that of the other?",
                "elasticity",
            ),
            (
                "Is the left cloth much stiffer to bend or have wrinkles than the other?",
                "bending",
            ),
        ] {
            let q = question(text, "yes", family, "open_ended");
            assert!(write(&q, None, &WRITER).is_err(), "{text}");
        }
        // Only pillars and plates are asked about.
        let q = question(
            "Does the left cloth fall over?\nA. Yes",
            "A",
            "cloth_predictive_fall",
            "multiple_choice",
        );
        assert!(write(&q, q.options.first(), &WRITER).is_err());
    }
}
