//! The builtin writer's ball programs: the ball engine's templates (`dataset::engine::ball`, the
//! paper's table of ball templates) parsed into programs that find the balls, query a material
//! or start the dynamic scene an event describes, and ask `happen`.
//!
//! | question | program |
//! |---|---|
//! | `Is the elasticity / plasticity of the A ball much greater than / less than the B ball?` | `query_pair('elasticity' \| 'plasticity', …)`; `(None, None)` is "can not answer" |
//! | `Will the C ball finally drop into the left pit?` \| `Yes` / `No` | `simulate`; C ball `droping` into the pit, or not |
//! | `If we removed the W floating wall and other balls, which pit would the C ball drop into?` \| `The left pit` / `Neither pit` | `remove` W; C ball `droping` into that pit, or into neither |
//! | `What can we do to make the C ball drop into the left pit?` \| `Remove the W floating wall and other balls` | `remove` W; C ball `droping` into the pit |

use super::{Writer, WriterError, between, literal, object_phrase, unrecognised, with_kind};

/// The ball writer.
pub const WRITER: Writer = Writer {
    version: "builtin-ball-v1",
    open_body: open_ended_body,
    option_body: choice_body,
};

/// The body for an open ball question: a material comparison.
fn open_ended_body(title: &str) -> Result<String, WriterError> {
    let lower = title.trim().to_lowercase();
    let (property, rest) = ["elasticity", "plasticity"]
        .into_iter()
        .find_map(|property| {
            lower
                .strip_prefix(&format!("is the {property} of "))
                .map(|rest| (property, rest))
        })
        .ok_or_else(|| unrecognised("question", title))?;
    let comparators = [(" greater than ", ">"), (" less than ", "<")];
    let (first, operator, second) = comparators
        .iter()
        .filter_map(|(word, operator)| rest.find(word).map(|at| (at, *word, *operator)))
        .min_by_key(|(at, _, _)| *at)
        .map(|(at, word, operator)| (&rest[..at], operator, &rest[at + word.len()..]))
        .ok_or_else(|| unrecognised("question", title))?;
    let first = first.trim().strip_suffix(" much").unwrap_or(first.trim());
    let second = second
        .strip_prefix("that of ")
        .unwrap_or(second)
        .strip_suffix('?')
        .ok_or_else(|| unrecognised("question", title))?;
    Ok(format!(
        "    first = ball_scene.find({first})\n    second = ball_scene.find({second})\n    \
         first_value, second_value = ball_scene.query_pair('{property}', first, second)\n    \
         if first_value is None or second_value is None:\n        return \"can not answer\"\n    \
         return bool_to_yesno(first_value {operator} second_value)\n",
        first = literal(&with_kind(first, "ball")),
        second = literal(&with_kind(second, "ball")),
    ))
}

/// A ball choice question, parsed from its title (lower case).
#[derive(Debug, Clone, PartialEq, Eq)]
enum ChoiceQuestion {
    /// "Will the {ball} finally drop into the {side} pit?"
    Predictive { ball: String, pit: String },
    /// "If we removed the {wall} and other balls, which pit would the {ball} drop into?"
    Counterfactual { wall: String, ball: String },
    /// "What can we do to make the {ball} drop into the {side} pit?"
    GoalDriven { ball: String, pit: String },
}

impl ChoiceQuestion {
    fn parse(title: &str) -> Option<ChoiceQuestion> {
        let lower = title.trim().to_lowercase();
        if let Some(rest) = between(&lower, "will ", " pit?") {
            let (ball, side) = rest.split_once(" finally drop into ")?;
            return Some(ChoiceQuestion::Predictive {
                ball: with_kind(ball, "ball"),
                pit: with_kind(side, "pit"),
            });
        }
        if let Some(rest) = between(&lower, "if we removed ", " drop into?") {
            let (wall, ball) = rest.split_once(" and other balls, which pit would ")?;
            return Some(ChoiceQuestion::Counterfactual {
                wall: with_kind(wall, "floating wall"),
                ball: with_kind(ball, "ball"),
            });
        }
        let rest = between(&lower, "what can we do to make ", " pit?")?;
        let (ball, side) = rest.split_once(" drop into ")?;
        Some(ChoiceQuestion::GoalDriven {
            ball: with_kind(ball, "ball"),
            pit: with_kind(side, "pit"),
        })
    }
}

/// The lines that start the dynamic scene of `event` and set `dropped(pit)` to whether the ball
/// drops into a pit in it.
fn dynamic_lines(event: &str, ball: &str) -> String {
    format!(
        "{event}    dynamic_scene = ball_scene.init_dyn_simulation(event)\n    \
         ball = ball_scene.find({ball})\n\n    \
         def dropped(pit):\n        \
         return dynamic_scene.happen(ball, \"droping\", ball_scene.find(pit))\n\n",
        ball = literal(ball),
    )
}

/// The `remove` event of `wall` and the other balls.
fn removal(wall: &str) -> String {
    format!(
        "    event = ball_scene.register_event([], \"remove\", {})\n",
        literal(&format!("{wall} and other balls"))
    )
}

/// The body for one option of a ball choice question; it returns "yes" when the option holds.
fn choice_body(title: &str, option: &str) -> Result<String, WriterError> {
    let question = ChoiceQuestion::parse(title).ok_or_else(|| unrecognised("question", title))?;
    let lower = option.trim().trim_end_matches('.').to_lowercase();
    match question {
        ChoiceQuestion::Predictive { ball, pit } => {
            let simulate = "    event = ball_scene.register_event([], \"simulate\", \"\")\n";
            let negate = match lower.as_str() {
                "yes" => "",
                "no" => "not ",
                _ => return Err(unrecognised("option", option)),
            };
            Ok(format!(
                "{}    return bool_to_yesno({negate}dropped({}))\n",
                dynamic_lines(simulate, &ball),
                literal(&pit)
            ))
        }
        ChoiceQuestion::Counterfactual { wall, ball } => {
            let lines = dynamic_lines(&removal(&wall), &ball);
            let phrase = object_phrase(&lower);
            if matches!(
                phrase,
                "neither pit" | "no pit" | "none of them" | "neither"
            ) {
                return Ok(format!(
                    "{lines}    return bool_to_yesno(not dropped(\"left pit\") and not dropped(\"right pit\"))\n"
                ));
            }
            let pit = phrase
                .strip_suffix(" pit")
                .filter(|side| matches!(*side, "left" | "right"))
                .ok_or_else(|| unrecognised("option", option))?;
            Ok(format!(
                "{lines}    return bool_to_yesno(dropped({}))\n",
                literal(&format!("{pit} pit"))
            ))
        }
        ChoiceQuestion::GoalDriven { ball, pit } => {
            let wall = lower
                .strip_prefix("remove ")
                .map(|rest| rest.strip_suffix(" and other balls").unwrap_or(rest))
                .map(object_phrase)
                .filter(|wall| wall.ends_with(" floating wall"))
                .ok_or_else(|| unrecognised("option", option))?;
            Ok(format!(
                "{}    return bool_to_yesno(dropped({}))\n",
                dynamic_lines(&removal(wall), &ball),
                literal(&pit)
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::{Question, Scenario};
    use crate::program::builtin::test_question;
    use crate::program::builtin::write_program as write;

    fn question(text: &str, answer: &str, family: &str, answer_type: &str) -> Question {
        test_question(Scenario::Ball, text, answer, family, answer_type)
    }

    #[test]
    fn material_question_becomes_a_query_pair_comparison() {
        let q = question(
            "Is the plasticity of the light blue ball much less than the pink ball?",
            "yes",
            "plasticity",
            "open_ended",
        );
        insta::assert_snapshot!(write(&q, None, &WRITER).unwrap());
    }

    #[test]
    fn counterfactual_option_removes_the_wall_and_asks_about_the_pit() {
        let q = question(
            "If we removed the red floating wall and other balls, which pit would the black ball drop into?\nA. Neither pit\nB. The left pit",
            "B",
            "ball_counterfactual_remove",
            "multiple_choice",
        );
        insta::assert_snapshot!(write(&q, q.options.first(), &WRITER).unwrap());
        let second = write(&q, q.options.get(1), &WRITER).unwrap();
        assert!(
            second.ends_with("    return bool_to_yesno(dropped(\"left pit\"))\n"),
            "{second}"
        );
    }

    #[test]
    fn every_template_family_is_recognised() {
        let cases = [
            (
                "Is the elasticity of the red ball much greater than the blue ball?",
                "elasticity",
                false,
                "query_pair('elasticity', first, second)",
            ),
            (
                "Will the pink ball finally drop into the right pit?\nA. Yes\nB. No",
                "ball_predictive_drop",
                true,
                "register_event([], \"simulate\", \"\")",
            ),
            (
                "If we removed the white floating wall and other balls, which pit would the pink ball drop into?\nA. The right pit",
                "ball_counterfactual_remove",
                true,
                "register_event([], \"remove\", \"white floating wall and other balls\")",
            ),
            (
                "What can we do to make the pink ball drop into the left pit?\nA. Remove the green floating wall and other balls",
                "ball_goaldriven_drop",
                true,
                "return bool_to_yesno(dropped(\"left pit\"))",
            ),
        ];
        for (text, family, choice, expected) in cases {
            let (answer, answer_type) = if choice {
                ("A", "multiple_choice")
            } else {
                ("yes", "open_ended")
            };
            let q = question(text, answer, family, answer_type);
            let program = write(&q, q.options.first(), &WRITER).unwrap();
            assert!(program.contains(expected), "{text}\n{program}");
            assert!(
                program.contains("    ball_scene = SoftScene(video, 'ball')\n"),
                "{program}"
            );
        }
        let no = question(
            "Will the pink ball finally drop into the right pit?\nA. Yes\nB. No",
            "B",
            "ball_predictive_drop",
            "multiple_choice",
        );
        let program = write(&no, no.options.get(1), &WRITER).unwrap();
        assert!(
            program.ends_with("return bool_to_yesno(not dropped(\"right pit\"))\n"),
            "{program}"
        );
    }

    #[test]
    fn unknown_text_or_options_are_errors_not_guesses() {
        let q = question(
            "Will the pink ball finally drop into the right pit?\nA. Maybe",
            "A",
            "ball_predictive_drop",
            "multiple_choice",
        );
        let error = write(&q, q.options.first(), &WRITER).unwrap_err();
        assert_eq!(
            error.to_string(),
            "the builtin writer does not recognise the option `Maybe`"
        );
        let q = question("Is the ball bouncy?", "yes", "elasticity", "open_ended");
        assert!(write(&q, None, &WRITER).is_err());
    }
}
