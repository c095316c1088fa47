//! The builtin writer's fluid programs: the fluid engine's templates (`dataset::engine::fluid`,
//! the paper's table of fluid templates) parsed into programs that find the objects, query a
//! density or start the dynamic scene an event describes, and ask `happen`.
//!
//! | question | program |
//! |---|---|
//! | `Is the fluid density of the A fluid greater than / less than that of the B fluid?` | `query_pair('density', …)`; `(None, None)` is "can not answer" |
//! | `How many sticks are there in the video?` | `len(find("sticks"))` |
//! | `Which stick will the fluid from the other C emitter pass?` \| `Pink stick` | `emit` the other C emitter; C fluid `passing` the stick |
//! | `Which container will fluid from the other C emitter flow into?` \| `Gray container` | the same, `entering` the container |
//! | `If the S stick were removed, which stick would C fluid pass?` \| `Pink stick` | `remove` S stick; C fluid `passing` the stick |
//! | `If the S stick were removed, which container would C fluid flow into?` \| `Gray container` | the same, `entering` the container |
//! | `What can we do to let most of the C fluid enter the K container?` \| `Remove the S stick` | `remove` S stick; C fluid `entering most` K container |

use super::{Writer, WriterError, between, literal, object_phrase, unrecognised, with_kind};

/// The fluid writer.
pub const WRITER: Writer = Writer {
    version: "builtin-fluid-v1",
    open_body: open_ended_body,
    option_body: choice_body,
};

/// The body for an open fluid question: a density comparison or a count.
fn open_ended_body(title: &str) -> Result<String, WriterError> {
    let lower = title.trim().to_lowercase();
    let density = lower
        .strip_prefix("is the fluid density of ")
        .or_else(|| lower.strip_prefix("is the density of "));
    if let Some(rest) = density {
        return density_body(rest, title);
    }
    if let Some(phrase) = lower
        .strip_prefix("how many ")
        .and_then(|rest| rest.strip_suffix(" are there in the video?"))
    {
        return Ok(format!(
            "    found = fluid_scene.find({})\n    return len(found)\n",
            literal(phrase.trim())
        ));
    }
    Err(unrecognised("question", title))
}

/// `"{A} greater than / less than that of {B}?"` → compare the two densities.
fn density_body(rest: &str, title: &str) -> Result<String, WriterError> {
    let comparators = [(" greater than ", ">"), (" less than ", "<")];
    let (first, comparator, after) = comparators
        .iter()
        .filter_map(|(word, operator)| rest.find(word).map(|at| (at, *word, *operator)))
        .min_by_key(|(at, _, _)| *at)
        .map(|(at, word, operator)| (&rest[..at], operator, &rest[at + word.len()..]))
        .ok_or_else(|| unrecognised("question", title))?;
    let second = after
        .strip_prefix("that of ")
        .and_then(|text| text.strip_suffix('?'))
        .ok_or_else(|| unrecognised("question", title))?;
    Ok(format!(
        "    first = fluid_scene.find({first})\n    second = fluid_scene.find({second})\n    \
         first_density, second_density = fluid_scene.query_pair('density', first, second)\n    \
         if first_density is None or second_density is None:\n        return \"can not answer\"\n    \
         return bool_to_yesno(first_density {comparator} second_density)\n",
        first = literal(object_phrase(first)),
        second = literal(object_phrase(second)),
    ))
}

/// What a choice question asks of each option's object.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Asked {
    /// Which sticks the fluid passes: options are sticks.
    Pass,
    /// Which containers the fluid enters: options are containers.
    Enter,
}

impl Asked {
    /// `happen`'s action.
    fn action(self) -> &'static str {
        match self {
            Asked::Pass => "passing",
            Asked::Enter => "entering",
        }
    }

    /// The kind its options name.
    fn kind(self) -> &'static str {
        match self {
            Asked::Pass => "stick",
            Asked::Enter => "container",
        }
    }
}

/// A fluid choice question, parsed from its title (lower case).
#[derive(Debug, Clone, PartialEq, Eq)]
enum ChoiceQuestion {
    /// "Which stick / container will the fluid from the other {colour} emitter …?"
    Predictive { color: String, asked: Asked },
    /// "If the {stick} were removed, which stick / container would {fluid} …?"
    Counterfactual {
        removed: String,
        fluid: String,
        asked: Asked,
    },
    /// "What can we do to let most of the {fluid} enter the {container}?"
    GoalDriven { fluid: String, container: String },
}

impl ChoiceQuestion {
    fn parse(title: &str) -> Option<ChoiceQuestion> {
        let lower = title.trim().to_lowercase();
        let predictive = [
            (
                "which stick will the fluid from the other ",
                " emitter pass?",
                Asked::Pass,
            ),
            (
                "which container will fluid from the other ",
                " emitter flow into?",
                Asked::Enter,
            ),
            (
                "which container will the fluid from the other ",
                " emitter flow into?",
                Asked::Enter,
            ),
        ];
        for (prefix, suffix, asked) in predictive {
            if let Some(color) = between(&lower, prefix, suffix) {
                let color = color.to_string();
                return Some(ChoiceQuestion::Predictive { color, asked });
            }
        }
        if let Some(rest) = lower.strip_prefix("if ") {
            let (removed, rest) = rest.split_once(" were removed, ")?;
            let questions = [
                ("which stick would ", " pass?", Asked::Pass),
                ("which container would ", " flow into?", Asked::Enter),
            ];
            return questions.into_iter().find_map(|(prefix, suffix, asked)| {
                let fluid = between(rest, prefix, suffix)?;
                Some(ChoiceQuestion::Counterfactual {
                    removed: with_kind(removed, "stick"),
                    fluid: with_kind(fluid, "fluid"),
                    asked,
                })
            });
        }
        let goal = between(&lower, "what can we do to let most of ", "?")?;
        let (fluid, container) = goal.split_once(" enter ")?;
        Some(ChoiceQuestion::GoalDriven {
            fluid: with_kind(fluid, "fluid"),
            container: with_kind(container, "container"),
        })
    }
}

/// The lines that start a dynamic scene from `event` and ask whether `fluid` does `action` to
/// `target` in it.
fn dynamic_body(event: &str, fluid: &str, action: &str, target: &str) -> String {
    format!(
        "{event}    dynamic_scene = fluid_scene.init_dyn_simulation(event)\n    \
         fluid = fluid_scene.find({fluid})\n    \
         target = fluid_scene.find({target})\n    \
         return bool_to_yesno(dynamic_scene.happen(fluid, \"{action}\", target))\n",
        fluid = literal(fluid),
        target = literal(target),
    )
}

/// The `remove` event of the stick `stick`.
fn removal(stick: &str) -> String {
    format!(
        "    event = fluid_scene.register_event([], \"remove\", {})\n",
        literal(stick)
    )
}

/// An option naming an object of `kind` (`Pink stick`), as a `find` phrase (`pink stick`).
fn object_option(option: &str, kind: &str) -> Result<String, WriterError> {
    let phrase = object_phrase(&option.trim().to_lowercase()).to_string();
    if phrase.ends_with(&format!(" {kind}")) {
        Ok(phrase)
    } else {
        Err(unrecognised("option", option))
    }
}

/// The body for one option of a fluid choice question; it returns "yes" when the option holds.
fn choice_body(title: &str, option: &str) -> Result<String, WriterError> {
    let question = ChoiceQuestion::parse(title).ok_or_else(|| unrecognised("question", title))?;
    match question {
        ChoiceQuestion::Predictive { color, asked } => {
            let target = object_option(option, asked.kind())?;
            let event = format!(
                "    emitter = fluid_scene.find({})\n    \
                 event = fluid_scene.register_event(emitter, \"emit\", \"fluid\")\n",
                literal(&format!("other {color} emitter"))
            );
            Ok(dynamic_body(
                &event,
                &format!("{color} fluid"),
                asked.action(),
                &target,
            ))
        }
        ChoiceQuestion::Counterfactual {
            removed,
            fluid,
            asked,
        } => {
            let target = object_option(option, asked.kind())?;
            Ok(dynamic_body(
                &removal(&removed),
                &fluid,
                asked.action(),
                &target,
            ))
        }
        ChoiceQuestion::GoalDriven { fluid, container } => {
            let lower = option.trim().to_lowercase();
            let stick = lower
                .strip_prefix("remove ")
                .map(object_phrase)
                .filter(|stick| stick.ends_with(" stick"))
                .ok_or_else(|| unrecognised("option", option))?;
            Ok(dynamic_body(
                &removal(stick),
                &fluid,
                "entering most",
                &container,
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
        test_question(Scenario::Fluid, text, answer, family, answer_type)
    }

    fn option_program(text: &str, family: &str) -> String {
        let q = question(text, "A", family, "multiple_choice");
        write(&q, q.options.first(), &WRITER).unwrap()
    }

    #[test]
    fn density_question_becomes_a_query_pair_comparison() {
        let q = question(
            "Is the fluid density of the light blue fluid less than that of the pink fluid?",
            "yes",
            "density",
            "open_ended",
        );
        insta::assert_snapshot!(write(&q, None, &WRITER).unwrap());
    }

    #[test]
    fn predictive_option_emits_from_the_other_emitter() {
        insta::assert_snapshot!(option_program(
            "Which stick will the fluid from the other yellow emitter pass?\nA. Gray stick\nB. Brown stick",
            "fluid_predictive_pass",
        ));
    }

    #[test]
    fn counterfactual_option_removes_the_stick() {
        insta::assert_snapshot!(option_program(
            "If the brown stick were removed, which container would light blue fluid flow into?\nA. Green container\nB. Red container",
            "fluid_counterfactual_container",
        ));
    }

    #[test]
    fn goal_driven_option_asks_where_most_of_the_fluid_ends() {
        insta::assert_snapshot!(option_program(
            "What can we do to let most of the pink fluid enter the green container?\nA. Remove the brown stick\nB. Remove the gray stick",
            "fluid_goaldriven_container",
        ));
    }

    #[test]
    fn every_template_family_is_recognised() {
        // (question, family, whether it has options, a line the program must hold)
        let cases = [
            (
                "Is the fluid density of the pink fluid greater than that of the yellow fluid?",
                "density",
                false,
                "return bool_to_yesno(first_density > second_density)",
            ),
            (
                "How many sticks are there in the video?",
                "stick_number",
                false,
                "found = fluid_scene.find(\"sticks\")",
            ),
            (
                "Which container will fluid from the other blue emitter flow into?\nA. Light blue container",
                "fluid_predictive_container",
                true,
                "target = fluid_scene.find(\"light blue container\")",
            ),
            (
                "Which stick will the fluid from the other light blue emitter pass?\nA. Pink stick",
                "fluid_predictive_pass",
                true,
                "emitter = fluid_scene.find(\"other light blue emitter\")",
            ),
            (
                "If the gray stick were removed, which stick would orange fluid pass?\nA. Pink stick",
                "fluid_counterfactual_pass",
                true,
                "dynamic_scene.happen(fluid, \"passing\", target)",
            ),
            (
                "If the brown stick were removed, which container would pink fluid flow into?\nA. Gray container",
                "fluid_counterfactual_container",
                true,
                "register_event([], \"remove\", \"brown stick\")",
            ),
            // The paper's eg2 wording, without "the".
            (
                "What can we do to let most of the pink fluid enter black container?\nA. Remove green stick",
                "fluid_goaldriven_container",
                true,
                "target = fluid_scene.find(\"black container\")",
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
                program.contains("    fluid_scene = SoftScene(video, 'fluid')\n"),
                "{program}"
            );
        }
    }

    #[test]
    fn per_question_program_checks_every_option() {
        let q = question(
            "If the brown stick were removed, which stick would pink fluid pass?\nA. Cyan stick\nB. Gray stick",
            "A",
            "fluid_counterfactual_pass",
            "multiple_choice",
        );
        let program = write_question_program(&q, &WRITER).unwrap();
        assert!(program.contains("def option_a(video):"), "{program}");
        assert!(
            program.contains("target = fluid_scene.find(\"gray stick\")"),
            "{program}"
        );
        assert!(
            program.trim_end().ends_with("return \" \".join(chosen)"),
            "{program}"
        );
    }

    #[test]
    fn unknown_text_or_mismatched_options_are_errors_not_guesses() {
        let cases = [
            (
                question("Is the fluid hot?", "no", "density", "open_ended"),
                "the builtin writer does not recognise the question `Is the fluid hot?`",
            ),
            (
                question(
                    "Which stick will the fluid from the other blue emitter pass?\nA. Gray container",
                    "A",
                    "fluid_predictive_pass",
                    "multiple_choice",
                ),
                "the builtin writer does not recognise the option `Gray container`",
            ),
            (
                question(
                    "What can we do to let most of the pink fluid enter the gray container?\nA. Add a stick",
                    "A",
                    "fluid_goaldriven_container",
                    "multiple_choice",
                ),
                "the builtin writer does not recognise the option `Add a stick`",
            ),
        ];
        for (q, expected) in cases {
            let error = write(&q, q.options.first(), &WRITER).unwrap_err();
            assert_eq!(error.to_string(), expected);
        }
    }

    #[test]
    fn quotes_in_data_cannot_break_out_of_string_literals() {
        let q = question(
            "If the x\") or __import__(\"os stick were removed, which stick would pink fluid pass?\nA. Gray stick",
            "A",
            "fluid_counterfactual_pass",
            "multiple_choice",
        );
        let program = write(&q, q.options.first(), &WRITER).unwrap();
        assert!(
            program.contains(r#"register_event([], "remove", "x\") or __import__(\"os stick")"#),
            "{program}"
        );
    }
}
