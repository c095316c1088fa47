//! Tests of the fluid engine on the hand-written video `tests/data/fluid_slides/0` and on
//! variants of it made by editing its JSON. Every expected answer below was worked out by hand
//! from that file:
//!
//! * densities: the relations (pink, yellow) and (later yellow, light blue) give pink > yellow >
//!   light blue once normalised and closed;
//! * the other yellow emitter passes the gray and cyan sticks (not brown) and ends in the green
//!   container only;
//! * without the brown stick: pink passes cyan (not gray) and ends in both containers, light
//!   blue passes gray (not cyan) and ends in green only, yellow passes cyan and gray and ends in
//!   both; without the gray stick: pink passes brown and cyan and ends in red only, light blue
//!   passes brown (not cyan) and ends in both, yellow passes brown and cyan and ends in both;
//! * most of each fluid: without brown, pink → green (1100 vs 200), light blue → green, yellow
//!   → red (700 vs 500); without gray, pink → red (1200 vs 0), light blue → red (900 vs 450),
//!   yellow → red (1100 vs 60).

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::{Value, json};

use super::templates::FAMILIES;
use super::*;
use crate::dataset::engine::{SamplerConfig, sample_and_split};
use crate::dataset::{AnswerType, Category, Family, Question, QuestionId, Scenario};

const SEEDS: std::ops::Range<u64> = 0..60;

fn video_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fluid_slides/0")
}

fn fixture() -> Value {
    serde_json::from_slice(&fs_err::read(video_dir().join("outputs.json")).unwrap()).unwrap()
}

fn annotation(value: &Value) -> FluidAnnotation {
    FluidAnnotation::from_json(Path::new("outputs.json"), value).unwrap()
}

fn generate(annotation: &FluidAnnotation, seed: u64) -> PerVideoQuestions {
    generate_questions(&VideoId("0".into()), annotation, seed)
}

fn records<'a>(questions: &'a PerVideoQuestions, family: &str) -> &'a [QuestionRecord] {
    &questions.question_dict[family]
}

fn parse(record: &QuestionRecord) -> Question {
    Question::from_record(
        QuestionId("q".into()),
        VideoId("0".into()),
        Scenario::Fluid,
        record.clone(),
    )
    .unwrap()
}

/// Title → (option text → truth) of a choice family, checking that each record's answer letters,
/// `positive`/`negative` and `program.choices` agree with its options.
fn choice_truths(records: &[QuestionRecord]) -> BTreeMap<String, BTreeMap<String, bool>> {
    let mut truths = BTreeMap::new();
    for record in records {
        let question = parse(record);
        assert_eq!(question.answer_type, AnswerType::MultipleChoice);
        assert!((2..=4).contains(&question.options.len()), "{record:?}");
        let choices = record.program.as_ref().unwrap()["choices"]
            .as_object()
            .unwrap();
        assert_eq!(choices.len(), question.options.len());
        let mut options = BTreeMap::new();
        for option in &question.options {
            assert!(choices.contains_key(&option.letter.to_string()));
            let listed = if option.correct {
                &record.positive
            } else {
                &record.negative
            };
            assert!(listed.contains(&option.text), "{record:?}");
            options.insert(option.text.clone(), option.correct);
        }
        let previous = truths.insert(question.title.clone(), options);
        assert!(previous.is_none(), "asked twice: {}", question.title);
    }
    truths
}

/// `[(text, truth)]` as a map.
fn truths(options: &[(&str, bool)]) -> BTreeMap<String, bool> {
    options
        .iter()
        .map(|(t, c)| ((*t).to_string(), *c))
        .collect()
}

#[test]
fn every_family_is_present_in_order_and_every_record_parses() {
    let annotation = annotation(&fixture());
    for seed in SEEDS {
        let questions = generate(&annotation, seed);
        assert_eq!(questions.video_id, "0");
        assert!(
            questions
                .question_dict
                .keys()
                .map(String::as_str)
                .eq(FAMILIES)
        );
        for (family, records) in &questions.question_dict {
            let category = Family(family.clone()).category();
            for record in records {
                assert_eq!(&record.question_family, family);
                let question = parse(record);
                let expected_type = if category == Category::Property {
                    AnswerType::OpenEnded
                } else {
                    AnswerType::MultipleChoice
                };
                assert_eq!(question.answer_type, expected_type, "{record:?}");
            }
        }
    }
    let categories: Vec<Category> = FAMILIES
        .iter()
        .map(|family| Family((*family).to_string()).category())
        .collect();
    assert_eq!(
        categories,
        [
            Category::Property,
            Category::Property,
            Category::Predictive,
            Category::Predictive,
            Category::Counterfactual,
            Category::Counterfactual,
            Category::GoalDriven,
        ]
    );
}

#[test]
fn stick_number_counts_the_regular_sticks() {
    let questions = generate(&annotation(&fixture()), 0);
    let text = serde_json::to_string(records(&questions, "stick_number")).unwrap();
    assert_eq!(
        text,
        r#"[{"question":"How many sticks are there in the video?","answer":"3","question_family":"stick_number","positive":["3"],"negative":[],"program":["stick"],"answer_type":"open_ended"}]"#
    );
}

/// Pink > yellow > light blue.
fn density_rank(word: &str) -> u8 {
    match word {
        "pink" => 3,
        "yellow" => 2,
        "light blue" => 1,
        other => panic!("unknown fluid `{other}`"),
    }
}

/// `(first, comparator, second)` of a density title.
fn density_parts(title: &str) -> (&str, &str, &str) {
    let rest = title
        .strip_prefix("Is the fluid density of the ")
        .unwrap()
        .strip_suffix(" fluid?")
        .unwrap();
    let (first, rest) = rest.split_once(" fluid ").unwrap();
    let (comparator, second) = rest.split_once(" that of the ").unwrap();
    (first, comparator, second)
}

#[test]
fn density_answers_follow_the_closed_relations_and_are_balanced() {
    let annotation = annotation(&fixture());
    let mut answers = BTreeMap::new();
    for seed in SEEDS {
        let questions = generate(&annotation, seed);
        let density = records(&questions, "density");
        // Every ordered pair is related (pink–light blue only through the closure).
        assert_eq!(density.len(), 6);
        for record in density {
            let (first, comparator, second) = density_parts(&record.question);
            let greater = match comparator {
                "greater than" => true,
                "less than" => false,
                other => panic!("comparator `{other}`"),
            };
            let holds = greater == (density_rank(first) > density_rank(second));
            let expected = if holds { "yes" } else { "no" };
            assert_eq!(record.answer, expected, "{}", record.question);
            assert_eq!(
                record.program.as_ref().unwrap(),
                &json!([first, "fluid", comparator, second, "fluid"])
            );
            *answers.entry(record.answer.clone()).or_insert(0) += 1;
        }
    }
    // 360 questions, each "yes" with probability 1/2.
    assert!((140..=220).contains(&answers["yes"]), "{answers:?}");
    assert_eq!(answers["yes"] + answers["no"], 360);
}

#[test]
fn unrelated_fluids_can_not_be_answered() {
    let mut value = fixture();
    // Only pink > yellow is recorded: light blue is related to neither.
    value["trackingData"]["allDensityRelations"] =
        json!([{"Item1": "Pink Fluid", "Item2": "Yellow Fluid"}]);
    let annotation = annotation(&value);
    let mut cannot_answer = 0;
    for seed in 0..200 {
        let questions = generate(&annotation, seed);
        let mut answered_pairs = 0;
        for record in records(&questions, "density") {
            let (first, _, second) = density_parts(&record.question);
            if first == "light blue" || second == "light blue" {
                assert_eq!(record.answer, "can not answer", "{}", record.question);
                cannot_answer += 1;
            } else {
                assert_ne!(record.answer, "can not answer");
                answered_pairs += 1;
            }
        }
        assert_eq!(answered_pairs, 2);
    }
    // Four unrelated ordered pairs per video, each kept with probability 0.3: 240 expected.
    assert!((190..=290).contains(&cannot_answer), "{cannot_answer}");
}

#[test]
fn predictive_questions_ask_about_the_other_emitter() {
    let annotation = annotation(&fixture());
    let mut sizes = BTreeMap::new();
    for seed in SEEDS {
        let questions = generate(&annotation, seed);
        let pass = choice_truths(records(&questions, "fluid_predictive_pass"));
        let options = &pass["Which stick will the fluid from the other yellow emitter pass?"];
        assert_eq!(pass.len(), 1);
        let all = truths(&[
            ("Gray stick", true),
            ("Cyan stick", true),
            ("Brown stick", false),
        ]);
        // Brown is the only false stick, so it is always offered.
        assert_eq!(options.get("Brown stick"), Some(&false));
        for (text, truth) in options {
            assert_eq!(all.get(text), Some(truth), "{text}");
        }
        *sizes.entry(options.len()).or_insert(0) += 1;
        let record = &records(&questions, "fluid_predictive_pass")[0];
        let program = record.program.as_ref().unwrap();
        assert_eq!(
            program["question"],
            json!(["later emitted yellow fluid", "pass", "stick"])
        );
        let question = parse(record);
        let brown = question
            .options
            .iter()
            .find(|o| o.text == "Brown stick")
            .unwrap();
        assert_eq!(
            program["choices"][brown.letter.to_string()],
            json!(["later emitted yellow fluid", "pass", "brown stick"])
        );

        let container = choice_truths(records(&questions, "fluid_predictive_container"));
        assert_eq!(
            container,
            BTreeMap::from([(
                "Which container will fluid from the other yellow emitter flow into?".to_string(),
                truths(&[("Green container", true), ("Red container", false)])
            )])
        );
    }
    // Two or three options, both seen.
    assert_eq!(sizes.keys().copied().collect::<Vec<_>>(), [2, 3]);
}

#[test]
fn counterfactual_questions_read_the_run_without_the_stick() {
    let annotation = annotation(&fixture());
    for seed in SEEDS {
        let questions = generate(&annotation, seed);
        let pass = choice_truths(records(&questions, "fluid_counterfactual_pass"));
        // Yellow passes both remaining sticks in either run, pink both without gray: not asked.
        let expected_pass = BTreeMap::from([
            (
                "If the brown stick were removed, which stick would pink fluid pass?".to_string(),
                truths(&[("Cyan stick", true), ("Gray stick", false)]),
            ),
            (
                "If the brown stick were removed, which stick would light blue fluid pass?"
                    .to_string(),
                truths(&[("Gray stick", true), ("Cyan stick", false)]),
            ),
            (
                "If the gray stick were removed, which stick would light blue fluid pass?"
                    .to_string(),
                truths(&[("Brown stick", true), ("Cyan stick", false)]),
            ),
        ]);
        assert_eq!(pass, expected_pass);
        let container = choice_truths(records(&questions, "fluid_counterfactual_container"));
        let expected_container = BTreeMap::from([
            (
                "If the brown stick were removed, which container would light blue fluid flow into?"
                    .to_string(),
                truths(&[("Green container", true), ("Red container", false)]),
            ),
            (
                "If the gray stick were removed, which container would pink fluid flow into?"
                    .to_string(),
                truths(&[("Red container", true), ("Green container", false)]),
            ),
        ]);
        assert_eq!(container, expected_container);
        for record in records(&questions, "fluid_counterfactual_pass") {
            let program = record.program.as_ref().unwrap();
            let removed = if record.question.contains("brown stick were") {
                "brown stick"
            } else {
                "gray stick"
            };
            assert_eq!(program["question"], json!([removed, "remove", "stick"]));
        }
    }
}

#[test]
fn goal_driven_options_are_true_when_the_container_holds_most() {
    let annotation = annotation(&fixture());
    let title = |fluid: &str, container: &str| {
        format!("What can we do to let most of the {fluid} fluid enter the {container} container?")
    };
    let remove_gray = truths(&[
        ("Remove the gray stick", true),
        ("Remove the brown stick", false),
    ]);
    let remove_brown = truths(&[
        ("Remove the brown stick", true),
        ("Remove the gray stick", false),
    ]);
    let expected = BTreeMap::from([
        (title("pink", "red"), remove_gray.clone()),
        (title("pink", "green"), remove_brown.clone()),
        (title("light blue", "red"), remove_gray),
        (title("light blue", "green"), remove_brown),
    ]);
    for seed in SEEDS {
        let questions = generate(&annotation, seed);
        let goal = records(&questions, "fluid_goaldriven_container");
        assert_eq!(choice_truths(goal), expected);
        let first = goal
            .iter()
            .find(|r| r.question.starts_with(&title("pink", "red")))
            .unwrap();
        let program = first.program.as_ref().unwrap();
        assert_eq!(
            program["question"],
            json!(["pink fluid", "enter most", "red container"])
        );
        let question = parse(first);
        let gray = question
            .options
            .iter()
            .find(|o| o.text == "Remove the gray stick")
            .unwrap();
        assert_eq!(
            program["choices"][gray.letter.to_string()],
            json!(["gray stick", "remove", "stick"])
        );
    }
}

#[test]
fn a_tie_is_not_most() {
    let mut value = fixture();
    // Without brown, yellow now ends 700 in red and 700 in green: neither holds most, so
    // "yellow into red" has one true removal (gray) and one false (brown) and is asked.
    value["CounterFactualAnnotations"]["0"]["trackingData"]["perReceptorFluidStat"]["Green Container"]
        ["Yellow Fluid"] = json!(700);
    let annotation = annotation(&value);
    let questions = generate(&annotation, 3);
    let goal = choice_truths(records(&questions, "fluid_goaldriven_container"));
    assert_eq!(goal.len(), 5);
    assert_eq!(
        goal["What can we do to let most of the yellow fluid enter the red container?"],
        truths(&[
            ("Remove the gray stick", true),
            ("Remove the brown stick", false)
        ])
    );
    let without_brown = &annotation.counterfactuals[0].tracking;
    assert!(!without_brown.holds_most("Red Container", "Yellow Fluid"));
    assert!(!without_brown.holds_most("Green Container", "Yellow Fluid"));
    assert!(without_brown.holds_most("Green Container", "Pink Fluid"));
}

#[test]
fn missing_objects_skip_questions_not_the_video() {
    let mut value = fixture();
    // The factual run does not list the predictive emitter's contacts: no pass question, but
    // the container question still stands.
    value["trackingData"]["perEmitterStickStat"]
        .as_object_mut()
        .unwrap()
        .shift_remove("Later Emitted Yellow Fluid");
    // The run without brown does not list light blue's contacts: that pass question goes.
    value["CounterFactualAnnotations"]["0"]["trackingData"]["perEmitterStickStat"]
        .as_object_mut()
        .unwrap()
        .shift_remove("Light Blue Fluid");
    // A run without a stick the layout does not have: nothing can name it.
    let mut extra = value["CounterFactualAnnotations"]["1"].clone();
    extra["removedStickName"] = json!("White Stick");
    value["CounterFactualAnnotations"]["2"] = extra;
    let annotation = annotation(&value);
    for seed in 0..10 {
        let questions = generate(&annotation, seed);
        assert!(records(&questions, "fluid_predictive_pass").is_empty());
        assert_eq!(records(&questions, "fluid_predictive_container").len(), 1);
        let pass = choice_truths(records(&questions, "fluid_counterfactual_pass"));
        assert_eq!(pass.len(), 2);
        assert!(!pass.contains_key(
            "If the brown stick were removed, which stick would light blue fluid pass?"
        ));
        assert_eq!(
            records(&questions, "fluid_counterfactual_container").len(),
            2
        );
        for record in questions.question_dict.values().flatten() {
            assert!(!record.question.contains("white"), "{record:?}");
        }
        assert_eq!(records(&questions, "fluid_goaldriven_container").len(), 4);
    }
}

#[test]
fn the_same_seed_gives_the_same_records() {
    let annotation = annotation(&fixture());
    let serialised = |seed| serde_json::to_string(&generate(&annotation, seed)).unwrap();
    for seed in [0, 1, 42] {
        assert_eq!(serialised(seed), serialised(seed));
    }
    let first = serialised(0);
    assert!((1..20).any(|seed| serialised(seed) != first));
    // The video id is part of the stream.
    let other_video = generate_questions(&VideoId("1".into()), &annotation, 0);
    assert_eq!(other_video.video_id, "1");
}

#[test]
fn the_engine_reads_the_video_folder() {
    let video = VideoFolder::open(&video_dir(), None).unwrap();
    assert_eq!(video.scenario, Scenario::Fluid);
    assert_eq!(ENGINE.families, FAMILIES);
    let from_folder = (ENGINE.generate)(&video, 5).unwrap();
    let direct = generate(&annotation(&fixture()), 5);
    assert_eq!(from_folder, direct);
}

#[test]
fn the_sampler_draws_one_property_and_two_dynamics_questions_per_video() {
    let annotation = annotation(&fixture());
    let per_video: Vec<PerVideoQuestions> = (0..10)
        .map(|id| generate_questions(&VideoId(id.to_string()), &annotation, 9))
        .collect();
    let config = SamplerConfig {
        fact_per_video: 1,
        dynamics_per_video: 2,
    };
    let splits = sample_and_split(Scenario::Fluid, &per_video, &config, 9);
    let all: Vec<&QuestionRecord> = splits.all().collect();
    assert_eq!(all.len(), 30);
    for chunk in all.chunks(3) {
        let categories: Vec<Category> = chunk
            .iter()
            .map(|r| Family(r.qtype.clone().unwrap()).category())
            .collect();
        assert_eq!(categories[0], Category::Property);
        assert!(categories[1..].iter().all(|c| *c != Category::Property));
    }
}
