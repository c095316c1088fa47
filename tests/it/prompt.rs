//! Prompts: the rendered text for fixed questions (snapshots), every demo question in both
//! modes, strict templates whose errors name the template and the variable, override
//! directories, and what a unit may be.

use contphy_eval::dataset::{
    Question, QuestionId, QuestionRecord, Scenario, VideoId, load_question_file,
};
use contphy_eval::prompt::{PromptError, PromptMode, PromptSet};
use contphy_eval::scenarios;
use contphy_eval::scenarios::render_prompt as render;

use crate::support::{demo, root};

/// Every question of the demo video's engine file (ids `0/<family>/<index>`).
fn demo_questions() -> Vec<Question> {
    load_question_file(
        &demo().join("pulley_group/0.json"),
        None,
        scenarios::families(),
    )
    .unwrap()
    .questions
}

fn demo_question(id: &str) -> Question {
    demo_questions()
        .into_iter()
        .find(|q| q.id.0 == id)
        .unwrap_or_else(|| panic!("no demo question `{id}`"))
}

fn make_question(
    scenario: Scenario,
    text: &str,
    answer: &str,
    family: &str,
    answer_type: &str,
) -> Question {
    Question::from_record(
        QuestionId("q".into()),
        VideoId("0".into()),
        scenario,
        QuestionRecord::new(text, answer, family, answer_type),
    )
    .unwrap()
}

/// The user message after the API listing (the listing has its own test against the bindings),
/// with the system message on top.
fn shown(system: Option<&str>, user: &str) -> String {
    let after_api = user
        .split_once("```\n\nWrite a function")
        .map(|(_, rest)| format!("[API: api_spec/scene_api.pyi]\n\nWrite a function{rest}"))
        .unwrap();
    format!(
        "[system]\n{}\n[user]\n{after_api}",
        system.unwrap_or("(none)")
    )
}

#[test]
fn open_question_prompt() {
    let question = demo_question("0/mass/1");
    let prompt = render(&question, None, PromptMode::PerOption).unwrap();
    let api = fs_err::read_to_string(root().join("api_spec/scene_api.pyi")).unwrap();
    assert!(
        prompt
            .user
            .starts_with(&format!("```python\n{}\n```\n", api.trim_end())),
        "the prompt opens with the API listing (API_INSERT_HERE)"
    );
    insta::assert_snapshot!(
        "open_question",
        shown(prompt.system.as_deref(), &prompt.user)
    );
    assert_eq!(
        prompt,
        render(&question, None, PromptMode::PerQuestion).unwrap(),
        "an open question is the same unit in both modes"
    );
}

#[test]
fn choice_option_prompt_per_option() {
    let question = demo_question("0/rope_counterfactual/0");
    let option = question.option('B').unwrap();
    let prompt = render(&question, Some(option), PromptMode::PerOption).unwrap();
    insta::assert_snapshot!(
        "choice_option_per_option",
        shown(prompt.system.as_deref(), &prompt.user)
    );
}

#[test]
fn choice_question_prompt_per_question() {
    let question = demo_question("0/rope_counterfactual/0");
    let prompt = render(&question, None, PromptMode::PerQuestion).unwrap();
    insta::assert_snapshot!(
        "choice_question_per_question",
        shown(prompt.system.as_deref(), &prompt.user)
    );
}

#[test]
fn every_demo_unit_renders_in_both_modes_with_its_family_examples() {
    let set = PromptSet::embedded(scenarios::scene_words()).unwrap();
    let mut rendered = 0;
    for question in demo_questions() {
        let family = question.family.0.as_str();
        for mode in PromptMode::ALL {
            let units: Vec<Option<&_>> =
                if question.options.is_empty() || mode == PromptMode::PerQuestion {
                    vec![None]
                } else {
                    question.options.iter().map(Some).collect()
                };
            for option in units {
                let prompt = set.render(&question, option, mode).unwrap();
                let query = match option {
                    Some(option) => format!("Query: {} | {}\n", question.title, option.text),
                    None => format!("Query: {}\n", question.title),
                };
                assert!(
                    prompt.user.contains(&query),
                    "{}: no `{query}`",
                    question.id
                );
                if mode == PromptMode::PerQuestion {
                    for option in &question.options {
                        assert!(
                            prompt
                                .user
                                .contains(&format!("\n{}. {}\n", option.letter, option.text))
                        );
                    }
                }
                // The family's own example comes first.
                let own = if mode == PromptMode::PerQuestion && question.answer_type.is_choice() {
                    format!("rope/{family}.per_question")
                } else {
                    format!("rope/{family}")
                };
                let example = set.examples().find(|e| e.name == own).unwrap();
                let first_example = prompt.user.split("```python\n").nth(2).unwrap();
                assert!(
                    first_example.starts_with(&example.prompt_text),
                    "{} ({mode}): the first example is not `{own}`",
                    question.id
                );
                assert!(
                    !prompt.user.contains("# expected:"),
                    "answers of examples stay hidden"
                );
                assert_eq!(prompt.api_spec_version, set.api_spec_version());
                rendered += 1;
            }
        }
    }
    assert!(rendered > 500, "{rendered}");
}

#[test]
fn every_fluid_family_renders_with_its_own_example_first_and_its_hints() {
    let set = PromptSet::embedded(scenarios::scene_words()).unwrap();
    // (family, a question of it, the example shown first per option, per question)
    let cases = [
        (
            "density",
            "Is the fluid density of the pink fluid greater than that of the yellow fluid?",
            "fluid/density",
            "fluid/density",
        ),
        (
            "stick_number",
            "How many sticks are there in the video?",
            "fluid/stick_number",
            "fluid/stick_number",
        ),
        (
            "fluid_predictive_pass",
            "Which stick will the fluid from the other blue emitter pass?\nA. Pink stick\nB. Red stick",
            "fluid/fluid_predictive_pass",
            "fluid/fluid_predictive_pass.per_question",
        ),
        (
            "fluid_predictive_container",
            "Which container will fluid from the other blue emitter flow into?\nA. Pink container\nB. Red container",
            "fluid/fluid_predictive_container",
            "fluid/fluid_predictive_container",
        ),
        (
            "fluid_counterfactual_pass",
            "If the gray stick were removed, which stick would pink fluid pass?\nA. Red stick\nB. Cyan stick",
            "fluid/fluid_counterfactual_pass",
            "fluid/fluid_counterfactual_pass.per_question",
        ),
        (
            "fluid_counterfactual_container",
            "If the gray stick were removed, which container would pink fluid flow into?\nA. Red container\nB. Cyan container",
            "fluid/fluid_counterfactual_container",
            "fluid/fluid_counterfactual_container",
        ),
        (
            "fluid_goaldriven_container",
            "What can we do to let most of the pink fluid enter the red container?\nA. Remove the gray stick\nB. Remove the cyan stick",
            "fluid/fluid_goaldriven_container",
            "fluid/fluid_goaldriven_container.per_question",
        ),
    ];
    for (family, text, per_option, per_question) in cases {
        let choice = text.contains('\n');
        let question = if choice {
            make_question(Scenario::Fluid, text, "A", family, "multiple_choice")
        } else {
            make_question(Scenario::Fluid, text, "yes", family, "open_ended")
        };
        for (mode, own) in [
            (PromptMode::PerOption, per_option),
            (PromptMode::PerQuestion, per_question),
        ] {
            let option = (choice && mode == PromptMode::PerOption).then(|| &question.options[0]);
            let prompt = set.render(&question, option, mode).unwrap();
            let example = set.examples().find(|e| e.name == own).unwrap();
            let first_example = prompt.user.split("```python\n").nth(2).unwrap();
            assert!(
                first_example.starts_with(&example.prompt_text),
                "{family} ({mode}): the first example is not `{own}`"
            );
            assert!(prompt.user.contains("use `SoftScene(video, 'fluid')`"));
            assert!(prompt.user.contains("find(\"other yellow emitter\")"));
            assert!(!prompt.user.contains("# expected:"));
            let after_api = prompt.user.split_once("Write a function").unwrap().1;
            assert!(!after_api.contains("rope_scene"), "{family}: rope examples");
        }
    }
}

#[test]
fn template_hash_covers_the_files_used_and_is_stable() {
    let question = demo_question("0/mass/1");
    let other_family = demo_question("0/shape/0");
    let first = render(&question, None, PromptMode::PerOption).unwrap();
    let again = PromptSet::embedded(scenarios::scene_words())
        .unwrap()
        .render(&question, None, PromptMode::PerOption)
        .unwrap();
    assert_eq!(first, again, "rendering is deterministic");
    assert_eq!(first.template_hash.len(), 64);
    let shape = render(&other_family, None, PromptMode::PerOption).unwrap();
    assert_ne!(
        first.template_hash, shape.template_hash,
        "different examples shown, different hash"
    );
    let fluid = make_question(
        Scenario::Fluid,
        "How many sticks are there in the video?",
        "3",
        "stick_number",
        "open_ended",
    );
    let fluid_prompt = render(&fluid, None, PromptMode::PerOption).unwrap();

    // Editing an example changes the hash of the prompts that show it, and only those.
    let dir = tempfile::tempdir().unwrap();
    let examples = dir.path().join("api_spec/examples/fluid");
    fs_err::create_dir_all(&examples).unwrap();
    let path = examples.join("fluid_goaldriven_container.py");
    let original = fs_err::read_to_string(
        root().join("api_spec/examples/fluid/fluid_goaldriven_container.py"),
    )
    .unwrap();
    fs_err::write(
        &path,
        original
            .replace("flag = ", "entered = ")
            .replace("(flag)", "(entered)"),
    )
    .unwrap();
    let edited = PromptSet::load(dir.path(), scenarios::scene_words()).unwrap();
    assert_eq!(
        edited
            .render(&question, None, PromptMode::PerOption)
            .unwrap(),
        first
    );
    let edited_fluid = edited.render(&fluid, None, PromptMode::PerOption).unwrap();
    assert_ne!(edited_fluid.template_hash, fluid_prompt.template_hash);
    assert!(
        edited_fluid
            .user
            .contains("entered = fluid_gd_scene.happen")
    );
    assert_ne!(
        edited.hash(),
        PromptSet::embedded(scenarios::scene_words())
            .unwrap()
            .hash()
    );
}

#[test]
fn other_scenarios_render_with_their_own_examples() {
    let cases = [
        (
            Scenario::Fluid,
            "fluid/fluid_goaldriven_container",
            "use `SoftScene(video, 'fluid')`",
        ),
        (
            Scenario::Cloth,
            "cloth/cloth_predictive_touch",
            "use `SoftScene(video, 'cloth')`",
        ),
        (
            Scenario::Ball,
            "ball/ball_counterfactual_remove",
            "use `SoftScene(video, 'ball')`",
        ),
    ];
    let set = PromptSet::embedded(scenarios::scene_words()).unwrap();
    for (scenario, example, hint) in cases {
        let open = make_question(scenario, "Is it so?", "yes", "some_family", "open_ended");
        let prompt = set.render(&open, None, PromptMode::PerOption).unwrap();
        let text = &set
            .examples()
            .find(|e| e.name == example)
            .unwrap()
            .prompt_text;
        assert!(
            prompt.user.contains(text.as_str()),
            "{scenario}: lacks `{example}`"
        );
        assert!(prompt.user.contains(hint), "{scenario}: lacks `{hint}`");
        assert!(
            !prompt.user.contains("```python\n# Is the mass of"),
            "{scenario}: shows rope examples"
        );
        let choice = make_question(
            scenario,
            "Which one?\nA. Left\nB. Right",
            "A",
            "some_family",
            "multiple_choice",
        );
        let prompt = set.render(&choice, None, PromptMode::PerQuestion).unwrap();
        assert!(
            prompt
                .user
                .contains("Query: Which one?\nA. Left\nB. Right\n")
        );
    }
}

#[test]
fn units_must_fit_the_question_and_the_mode() {
    let open = demo_question("0/mass/1");
    let choice = demo_question("0/rope_goaldriven/0");
    let stranger = demo_question("0/rope_goaldriven/1").options[0].clone();
    let cases = [
        (
            &open,
            Some(&choice.options[0]),
            PromptMode::PerOption,
            "option `A` was given, but the question is open-ended",
        ),
        (
            &choice,
            None,
            PromptMode::PerOption,
            "a choice question in per-option mode needs the option of the unit",
        ),
        (
            &choice,
            Some(&choice.options[0]),
            PromptMode::PerQuestion,
            "but per-question mode asks for the whole question",
        ),
        (
            &choice,
            Some(&stranger),
            PromptMode::PerOption,
            "is not one of the question's options",
        ),
    ];
    for (question, option, mode, expected) in cases {
        let error = render(question, option, mode).unwrap_err();
        assert!(matches!(error, PromptError::Unit { .. }), "{error:?}");
        let message = error.to_string();
        assert!(
            message.starts_with(&format!("question `{}`: ", question.id)),
            "{message}"
        );
        assert!(message.contains(expected), "`{message}` lacks `{expected}`");
    }
}

/// An override directory holding `files` (path → text).
fn override_dir(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (path, text) in files {
        let path = dir.path().join(path);
        fs_err::create_dir_all(path.parent().unwrap()).unwrap();
        fs_err::write(path, text).unwrap();
    }
    dir
}

#[test]
fn template_errors_name_the_template_and_the_variable() {
    let question = demo_question("0/mass/1");
    let cases: [(&[(&str, &str)], &str); 7] = [
        (
            &[(
                "prompts/partials/query.jinja",
                "Query: {{ question }}\n{{ questoin_text }}\n",
            )],
            "template `partials/query.jinja` line 2: undefined variable `questoin_text`",
        ),
        (
            &[(
                "prompts/partials/query.jinja",
                "{% if unit == \"open\" %}\nQuery: {{ option.text }}\n{% endif %}\n",
            )],
            "template `partials/query.jinja` line 2:",
        ),
        (
            &[("prompts/base.jinja", "{{ example(\"rope/nope\") }}\n")],
            "template `base.jinja` line 1: unknown example `rope/nope` (no api_spec/examples/rope/nope.py); examples are ",
        ),
        (
            &[(
                "prompts/partials/examples.jinja",
                "{% macro show(name) %}\n{{ example(name) }}\n{% endmacro %}\n{{ show(\"rope/nope\") }}\n",
            )],
            "template `partials/examples.jinja` line 2: unknown example `rope/nope`",
        ),
        (
            &[("prompts/system.jinja", "{% if %}\n")],
            "template `system.jinja` does not parse (line 1)",
        ),
        (
            &[(
                "api_spec/examples/rope/bad.py",
                "def execute_command(video):\n    return 1\n",
            )],
            "`api_spec/examples/rope/bad.py`: the first line must be a comment holding the question",
        ),
        (
            &[("api_spec/VERSION", "\n")],
            "`api_spec/VERSION`: must hold the api_spec version",
        ),
    ];
    let mut messages = Vec::new();
    for (files, expected) in cases {
        let dir = override_dir(files);
        let error = PromptSet::load(dir.path(), scenarios::scene_words())
            .and_then(|set| set.render(&question, None, PromptMode::PerOption))
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with(expected),
            "`{error}` does not start with `{expected}`"
        );
        messages.push(error);
    }
    insta::assert_snapshot!("template_errors", messages.join("\n"));
    let error = render_with(
        &[(
            "prompts/partials/query.jinja",
            "{% if unit == \"open\" %}\nQuery: {{ option.text }}\n{% endif %}\n",
        )],
        &question,
    );
    assert!(
        matches!(error, PromptError::UndefinedVariable { ref variable, .. } if variable.contains("text")),
        "{error:?}"
    );
    let empty = tempfile::tempdir().unwrap();
    let error = PromptSet::load(empty.path(), scenarios::scene_words())
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("has neither a `prompts/` nor an `api_spec/` folder"),
        "{error}"
    );
}

fn render_with(files: &[(&str, &str)], question: &Question) -> PromptError {
    let dir = override_dir(files);
    PromptSet::load(dir.path(), scenarios::scene_words())
        .unwrap()
        .render(question, None, PromptMode::PerOption)
        .unwrap_err()
}

#[test]
fn an_override_directory_replaces_single_files() {
    let question = demo_question("0/mass/1");
    let dir = override_dir(&[
        ("prompts/system.jinja", "{# no system message #}\n"),
        (
            "prompts/partials/query.jinja",
            "Question for the program: {{ question }}\n",
        ),
        ("README.md", "ignored"),
    ]);
    let set = PromptSet::load(dir.path(), scenarios::scene_words()).unwrap();
    let prompt = set.render(&question, None, PromptMode::PerOption).unwrap();
    assert_eq!(prompt.system, None);
    assert!(prompt.user.ends_with("Question for the program: Is the mass of the green cube greater than that of the purple cube?\n"));
    assert!(
        prompt.user.contains("Consider the following guidelines:"),
        "other templates stay"
    );
    assert_eq!(prompt.messages().len(), 1);
    let embedded = render(&question, None, PromptMode::PerOption).unwrap();
    assert_ne!(prompt.template_hash, embedded.template_hash);
    assert_eq!(embedded.messages().len(), 2);
    assert_eq!(embedded.messages()[0].role, "system");
}
