//! The builtin writer's rope programs: the public engine's templates (the rope templates of the
//! data format) parsed into programs that find the objects, query or simulate, and compare.

use super::{Writer, WriterError, literal, object_phrase, unrecognised};

/// The rope writer.
pub const WRITER: Writer = Writer {
    version: "builtin-rope-v1",
    open_body: open_ended_body,
    option_body: choice_body,
};

/// The body for an open rope question: a comparison, a count or an existence check.
fn open_ended_body(title: &str) -> Result<String, WriterError> {
    if let Some(rest) = title.strip_prefix("Is the mass of the ") {
        return comparison_body("mass", rest, title);
    }
    if let Some(rest) = title.strip_prefix("Is the tension of the ") {
        return comparison_body("tension", rest, title);
    }
    if let Some(rest) = title.strip_prefix("How many ") {
        let phrase = rest
            .strip_suffix(" are there in the video?")
            .ok_or_else(|| unrecognised("question", title))?;
        // "How many blue objects" asks for a colour; "How many solid pulleys" for a kind.
        let phrase = phrase.strip_suffix(" objects").unwrap_or(phrase);
        return Ok(format!(
            "    found = rope_scene.find({})\n    return len(found)\n",
            literal(phrase)
        ));
    }
    if let Some(rest) = title.strip_prefix("Is there any ") {
        let phrase = rest
            .strip_suffix(" in the video?")
            .ok_or_else(|| unrecognised("question", title))?;
        return Ok(format!(
            "    found = rope_scene.find({})\n    return bool_to_yesno(len(found) > 0)\n",
            literal(phrase)
        ));
    }
    Err(unrecognised("question", title))
}

/// `"{A} {cmp} {factor}that of the {B}?"` → compare `A` with `factor · B`.
fn comparison_body(property: &str, rest: &str, title: &str) -> Result<String, WriterError> {
    let comparators = [
        (" greater than ", ">"),
        (" less than ", "<"),
        (" equal to ", "=="),
    ];
    let (first, comparator, after) = comparators
        .iter()
        .filter_map(|(word, op)| rest.find(word).map(|at| (at, *word, *op)))
        .min_by_key(|(at, _, _)| *at)
        .map(|(at, word, op)| (&rest[..at], op, &rest[at + word.len()..]))
        .ok_or_else(|| unrecognised("question", title))?;
    let (factor, after) = if let Some(after) = after.strip_prefix("twice ") {
        ("2.0", after)
    } else if let Some(after) = after.strip_prefix("half ") {
        ("0.5", after)
    } else {
        ("1.0", after)
    };
    let second = after
        .strip_prefix("that of ")
        .and_then(|s| s.strip_suffix('?'))
        .ok_or_else(|| unrecognised("question", title))?;
    // The benchmark compares with a tolerance of 1e-5 (the public engine's EPS).
    let test = match comparator {
        ">" => "first_value > factor * second_value + 1e-5",
        "<" => "first_value < factor * second_value - 1e-5",
        _ => "abs(first_value - factor * second_value) < 1e-5",
    };
    Ok(format!(
        "    first = rope_scene.find({first})\n    second = rope_scene.find({second})\n    \
         first_value, second_value = rope_scene.query_pair('{property}', first, second)\n    \
         if first_value is None or second_value is None:\n        return \"can not answer\"\n    \
         factor = {factor}\n    return bool_to_yesno({test})\n",
        first = literal(object_phrase(first)),
        second = literal(object_phrase(second)),
    ))
}

/// A mass change named in a counterfactual question: `(object, "increase" | "decrease")`.
fn mass_change(title: &str) -> Option<(String, &'static str)> {
    let lower = title.to_lowercase();
    let at = lower.find(" were much ")?;
    let before = &lower[..at];
    let start = before.rfind("if the ")? + "if the ".len();
    let object = before[start..].trim().to_string();
    let after = &lower[at + " were much ".len()..];
    let change = if after.starts_with("lighter") {
        "decrease"
    } else if after.starts_with("heavier") {
        "increase"
    } else {
        return None;
    };
    Some((object, change))
}

/// A motion or rotation outcome; no direction means "does not move / rotate".
struct Outcome {
    action: &'static str,
    direction: Option<&'static str>,
}

fn outcome_test(outcome: &Outcome) -> String {
    if let Some(direction) = outcome.direction {
        format!(
            "dynamic_scene.happen(target, \"{}\", \"{direction}\")",
            outcome.action
        )
    } else {
        let (a, b) = if outcome.action == "motion" {
            ("up", "down")
        } else {
            ("clockwise", "anti-clockwise")
        };
        format!(
            "not (dynamic_scene.happen(target, \"{action}\", \"{a}\") or dynamic_scene.happen(target, \"{action}\", \"{b}\"))",
            action = outcome.action
        )
    }
}

fn counterfactual_body(changed: &str, change: &str, target: &str, outcome: &Outcome) -> String {
    format!(
        "    changed = rope_scene.find({changed})\n    \
         event = rope_scene.register_event(changed, \"{change}\", \"mass\")\n    \
         dynamic_scene = rope_scene.init_dyn_simulation(event)\n    \
         target = rope_scene.find({target})\n    \
         return bool_to_yesno({test})\n",
        changed = literal(changed),
        target = literal(target),
        test = outcome_test(outcome),
    )
}

/// The body for one option of a rope choice question.
fn choice_body(title: &str, option: &str) -> Result<String, WriterError> {
    let lower_title = title.to_lowercase();
    // Goal-driven: "If we want the X to <goal>, what can we do?" | "Increase the mass of the Y".
    if lower_title.starts_with("if we want the ")
        || lower_title.starts_with("what can we do to let the ")
    {
        let rest = lower_title
            .strip_prefix("if we want the ")
            .or_else(|| lower_title.strip_prefix("what can we do to let the "))
            .unwrap_or_default();
        let (target, goal) = rest
            .split_once(" to ")
            .ok_or_else(|| unrecognised("question", title))?;
        let goal = goal
            .trim_end_matches('?')
            .trim_end_matches(", what can we do");
        let outcome = match goal {
            "move up" => Outcome {
                action: "motion",
                direction: Some("up"),
            },
            "move down" => Outcome {
                action: "motion",
                direction: Some("down"),
            },
            "rotate clockwise" => Outcome {
                action: "rotation",
                direction: Some("clockwise"),
            },
            "rotate anti-clockwise" => Outcome {
                action: "rotation",
                direction: Some("anti-clockwise"),
            },
            _ => return Err(unrecognised("question", title)),
        };
        let lower_option = option.to_lowercase();
        let (change, rest) = if let Some(rest) = lower_option.strip_prefix("increase the mass of ")
        {
            ("increase", rest)
        } else if let Some(rest) = lower_option.strip_prefix("decrease the mass of ") {
            ("decrease", rest)
        } else {
            return Err(unrecognised("option", option));
        };
        return Ok(counterfactual_body(
            object_phrase(rest),
            change,
            target.trim(),
            &outcome,
        ));
    }
    let (changed, change) = mass_change(title).ok_or_else(|| unrecognised("question", title))?;
    // Counterfactual "which direction would the X move/rotate" with one-word options.
    if let Some(at) = lower_title.find("which direction would the ") {
        let rest = &lower_title[at + "which direction would the ".len()..];
        let (target, action) = if let Some(at) = rest.find(" move") {
            (&rest[..at], "motion")
        } else if let Some(at) = rest.find(" rotate") {
            (&rest[..at], "rotation")
        } else {
            return Err(unrecognised("question", title));
        };
        let direction = match (action, option.trim().to_lowercase().as_str()) {
            ("motion", "up") => Some("up"),
            ("motion", "down") => Some("down"),
            ("rotation", "clockwise") => Some("clockwise"),
            ("rotation", "anti-clockwise") => Some("anti-clockwise"),
            (_, "stationary") => None,
            _ => return Err(unrecognised("option", option)),
        };
        return Ok(counterfactual_body(
            &changed,
            change,
            target.trim(),
            &Outcome { action, direction },
        ));
    }
    // Counterfactual "what would happen" with sentence options.
    let lower_option = option.trim().to_lowercase();
    let rest = lower_option
        .strip_prefix("the ")
        .ok_or_else(|| unrecognised("option", option))?;
    let endings: [(&str, &str, Option<&str>); 6] = [
        (" would rotate clockwise", "rotation", Some("clockwise")),
        (
            " would rotate anti-clockwise",
            "rotation",
            Some("anti-clockwise"),
        ),
        (" would not rotate", "rotation", None),
        (" would move up", "motion", Some("up")),
        (" would move down", "motion", Some("down")),
        (" would not move", "motion", None),
    ];
    for (ending, action, direction) in endings {
        if let Some(target) = rest.strip_suffix(ending) {
            return Ok(counterfactual_body(
                &changed,
                change,
                target.trim(),
                &Outcome { action, direction },
            ));
        }
    }
    Err(unrecognised("option", option))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::{Question, Scenario};
    use crate::program::builtin::test_question;
    use crate::program::builtin::{write_program as write, write_question_program};

    fn write_program(
        question: &Question,
        option: Option<&crate::dataset::ChoiceOption>,
    ) -> Result<String, WriterError> {
        write(question, option, &WRITER)
    }

    fn question(text: &str, answer: &str, family: &str, answer_type: &str) -> Question {
        test_question(Scenario::Rope, text, answer, family, answer_type)
    }

    #[test]
    fn mass_question_becomes_a_query_pair_comparison() {
        let q = question(
            "Is the mass of the green cube greater than half that of the purple sphere?",
            "yes",
            "mass",
            "open_ended",
        );
        let program = write_program(&q, None).unwrap();
        insta::assert_snapshot!(program);
    }

    #[test]
    fn counterfactual_option_becomes_an_event_and_happen() {
        let q = question(
            "If the purple cube were much lighter, what would happen?\nA. The blue pulley would rotate clockwise\nB. The green cube would not move",
            "A",
            "rope_counterfactual",
            "multiple_choice",
        );
        let first = write_program(&q, q.options.first()).unwrap();
        assert!(
            first.contains("rope_scene.register_event(changed, \"decrease\", \"mass\")"),
            "{first}"
        );
        assert!(
            first.contains("dynamic_scene.happen(target, \"rotation\", \"clockwise\")"),
            "{first}"
        );
        let second = write_program(&q, q.options.get(1)).unwrap();
        insta::assert_snapshot!(second);
    }

    #[test]
    fn per_question_program_checks_every_option_and_returns_letters() {
        let q = question(
            "If the purple cube were much lighter, what would happen?\nA. The blue pulley would rotate clockwise\nB. The green cube would not move",
            "A",
            "rope_counterfactual",
            "multiple_choice",
        );
        let program = write_question_program(&q, &WRITER).unwrap();
        assert!(program.contains("def option_a(video):"), "{program}");
        assert!(program.contains("def option_b(video):"), "{program}");
        assert!(
            program.contains("    if option_b(video) == \"yes\":\n        chosen.append(\"B\")"),
            "{program}"
        );
        assert!(
            program.trim_end().ends_with("return \" \".join(chosen)"),
            "{program}"
        );
    }

    #[test]
    fn every_template_family_is_recognised() {
        let cases = [
            (
                "Is the tension of the green rope less than twice that of the purple rope?",
                "open_ended",
                None,
                "query_pair('tension'",
            ),
            (
                "How many solid pulleys are there in the video?",
                "open_ended",
                None,
                "find(\"solid pulleys\")",
            ),
            (
                "How many blue objects are there in the video?",
                "open_ended",
                None,
                "find(\"blue\")",
            ),
            (
                "Is there any gray hollow pulley in the video?",
                "open_ended",
                None,
                "find(\"gray hollow pulley\")",
            ),
            (
                "Which direction would the blue pulley rotate if the green cube were much heavier?\nA. Clockwise",
                "multiple_choice",
                Some(0),
                "\"increase\"",
            ),
            (
                "If the pink sphere were much lighter, which direction would the pink sphere move?\nA. Stationary",
                "multiple_choice",
                Some(0),
                "not (dynamic_scene.happen(target, \"motion\", \"up\")",
            ),
            (
                "What can we do to let the gray pulley to rotate anti-clockwise?\nA. Decrease the mass of the purple cube",
                "multiple_choice",
                Some(0),
                "happen(target, \"rotation\", \"anti-clockwise\")",
            ),
            (
                "Which of the following would happen if the green cube were much heavier?\nA. The purple cube would move up",
                "multiple_choice",
                Some(0),
                "happen(target, \"motion\", \"up\")",
            ),
        ];
        for (text, answer_type, option, expected) in cases {
            let answer = if option.is_some() { "A" } else { "yes" };
            let q = question(text, answer, "family", answer_type);
            let program = write_program(&q, option.map(|i| &q.options[i])).unwrap();
            assert!(program.contains(expected), "{text}\n{program}");
        }
    }

    #[test]
    fn unknown_text_is_an_error_not_a_guess() {
        let q = question("Why is the sky blue?", "no", "mass", "open_ended");
        assert_eq!(
            write_program(&q, None).unwrap_err().to_string(),
            "the builtin writer does not recognise the question `Why is the sky blue?`"
        );
        let q = question(
            "If the purple cube were much lighter, what would happen?\nA. Nothing",
            "A",
            "rope_counterfactual",
            "multiple_choice",
        );
        assert!(write_program(&q, q.options.first()).is_err());
    }

    #[test]
    fn quotes_in_data_cannot_break_out_of_string_literals() {
        assert_eq!(literal("a\"b\\c\nd"), "\"a\\\"b\\\\c\\nd\"");
        let q = question(
            "How many x\") or __import__(\"os objects are there in the video?",
            "0",
            "color",
            "open_ended",
        );
        let program = write_program(&q, None).unwrap();
        assert!(
            program.contains(r#"find("x\") or __import__(\"os")"#),
            "{program}"
        );
    }
}
