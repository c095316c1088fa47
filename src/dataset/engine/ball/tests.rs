//! Tests of the ball engine on the hand-written video `tests/data/soft_body/0` and on variants of
//! it made by editing its JSON. Expected answers, worked out by hand from that file:
//!
//! * materials: red Elastic, blue Rigid, green Plastic. Elasticity orders red above blue and
//!   green (blue–green is not asked); plasticity orders green above red and blue;
//! * factual: red drops into the left pit during the video (not asked), blue drops into the right
//!   pit after it, green drops nowhere;
//! * without the white wall: red → right, blue → right, green → no pit; without the black wall:
//!   red → left, blue → right, green → left;
//! * goal-driven: red left (remove black), red right (remove white), green left (remove black);
//!   blue right has both removals true and blue left both false, so neither is asked, nor is
//!   green right.

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value;

use super::templates::FAMILIES;
use super::*;
use crate::dataset::{AnswerType, Question, QuestionId, Scenario};

const SEEDS: std::ops::Range<u64> = 0..40;

fn fixture() -> Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/soft_body/0/outputs.json");
    serde_json::from_slice(&fs_err::read(path).unwrap()).unwrap()
}

fn annotation(value: &Value) -> BallAnnotation {
    BallAnnotation::from_json(Path::new("outputs.json"), value).unwrap()
}

fn generate(annotation: &BallAnnotation, seed: u64) -> PerVideoQuestions {
    generate_questions(&VideoId("0".into()), annotation, seed)
}

fn parse(record: &QuestionRecord) -> Question {
    Question::from_record(
        QuestionId("q".into()),
        VideoId("0".into()),
        Scenario::Ball,
        record.clone(),
    )
    .unwrap()
}

/// Title → (option text → truth) of a choice family, over many seeds, checking every record's
/// letters and programs against its options.
fn choice_truths(family: &str) -> BTreeMap<String, BTreeMap<String, bool>> {
    let annotation = annotation(&fixture());
    let mut truths: BTreeMap<String, BTreeMap<String, bool>> = BTreeMap::new();
    for seed in SEEDS {
        for record in &generate(&annotation, seed).question_dict[family] {
            let question = parse(record);
            assert_eq!(question.answer_type, AnswerType::MultipleChoice);
            let choices = record.program.as_ref().unwrap()["choices"]
                .as_object()
                .unwrap();
            assert_eq!(choices.len(), question.options.len());
            let title = record.question.lines().next().unwrap().to_string();
            let options = truths.entry(title).or_default();
            for option in &question.options {
                let previous = options.insert(option.text.clone(), option.correct);
                assert!(previous.is_none_or(|p| p == option.correct), "{record:?}");
            }
        }
    }
    truths
}

fn truth_table(entries: &[(&str, &[(&str, bool)])]) -> BTreeMap<String, BTreeMap<String, bool>> {
    entries
        .iter()
        .map(|(title, options)| {
            (
                (*title).to_string(),
                options
                    .iter()
                    .map(|(t, c)| ((*t).to_string(), *c))
                    .collect(),
            )
        })
        .collect()
}

#[test]
fn every_family_key_is_present_in_template_order() {
    let questions = generate(&annotation(&fixture()), 0);
    assert!(
        questions
            .question_dict
            .keys()
            .map(String::as_str)
            .eq(FAMILIES)
    );
}

#[test]
fn property_answers_follow_the_materials() {
    let annotation = annotation(&fixture());
    let mut answers: BTreeMap<String, String> = BTreeMap::new();
    let mut yes = 0;
    let mut total = 0;
    for seed in SEEDS {
        let questions = generate(&annotation, seed);
        for family in ["elasticity", "plasticity"] {
            let records = &questions.question_dict[family];
            assert_eq!(records.len(), 4, "{family}");
            for record in records {
                total += 1;
                yes += usize::from(record.answer == "yes");
                answers.insert(record.question.clone(), record.answer.clone());
            }
        }
    }
    let expected = [
        (
            "Is the elasticity of the red ball much greater than the blue ball?",
            "yes",
        ),
        (
            "Is the elasticity of the red ball much less than the green ball?",
            "no",
        ),
        (
            "Is the elasticity of the blue ball much greater than the red ball?",
            "no",
        ),
        (
            "Is the elasticity of the green ball much less than the red ball?",
            "yes",
        ),
        (
            "Is the plasticity of the green ball much greater than the blue ball?",
            "yes",
        ),
        (
            "Is the plasticity of the red ball much greater than the green ball?",
            "no",
        ),
        (
            "Is the plasticity of the blue ball much less than the green ball?",
            "yes",
        ),
    ];
    for (question, answer) in expected {
        assert_eq!(
            answers.get(question).map(String::as_str),
            Some(answer),
            "{question}"
        );
    }
    // Blue and green are never compared on elasticity, red and blue never on plasticity.
    assert!(
        answers
            .keys()
            .all(|q| !(q.contains("elasticity") && q.contains("blue") && q.contains("green")))
    );
    assert!(
        answers
            .keys()
            .all(|q| !(q.contains("plasticity") && q.contains("red") && q.contains("blue")))
    );
    // The coin flip balances yes and no.
    assert!(
        yes * 10 > total * 4 && yes * 10 < total * 6,
        "{yes} of {total}"
    );
}

#[test]
fn predictive_questions_ask_about_what_the_video_does_not_show() {
    let truths = choice_truths("ball_predictive_drop");
    let expected = truth_table(&[
        (
            "Will the blue ball finally drop into the right pit?",
            &[("Yes", true), ("No", false)],
        ),
        (
            "Will the blue ball finally drop into the left pit?",
            &[("Yes", false), ("No", true)],
        ),
        (
            "Will the green ball finally drop into the right pit?",
            &[("Yes", false), ("No", true)],
        ),
        (
            "Will the green ball finally drop into the left pit?",
            &[("Yes", false), ("No", true)],
        ),
    ]);
    assert_eq!(truths, expected);
}

#[test]
fn counterfactual_questions_read_the_run_without_the_wall() {
    let truths = choice_truths("ball_counterfactual_remove");
    let row = |left, right, neither| -> [(&str, bool); 3] {
        [
            ("The left pit", left),
            ("The right pit", right),
            ("Neither pit", neither),
        ]
    };
    let title = |wall: &str, ball: &str| {
        format!(
            "If we removed the {wall} floating wall and other balls, which pit would the {ball} ball drop into?"
        )
    };
    let cases = [
        ("white", "red", row(false, true, false)),
        ("white", "blue", row(false, true, false)),
        ("white", "green", row(false, false, true)),
        ("black", "red", row(true, false, false)),
        ("black", "blue", row(false, true, false)),
        ("black", "green", row(true, false, false)),
    ];
    assert_eq!(truths.len(), 6);
    for (wall, ball, options) in cases {
        let expected: BTreeMap<String, bool> = options
            .iter()
            .map(|(t, c)| ((*t).to_string(), *c))
            .collect();
        assert_eq!(truths[&title(wall, ball)], expected, "{wall} {ball}");
    }
}

#[test]
fn goal_questions_need_one_removal_that_works_and_one_that_does_not() {
    let truths = choice_truths("ball_goaldriven_drop");
    let white = "Remove the white floating wall and other balls";
    let black = "Remove the black floating wall and other balls";
    let expected = truth_table(&[
        (
            "What can we do to make the red ball drop into the left pit?",
            &[(white, false), (black, true)],
        ),
        (
            "What can we do to make the red ball drop into the right pit?",
            &[(white, true), (black, false)],
        ),
        (
            "What can we do to make the green ball drop into the left pit?",
            &[(white, false), (black, true)],
        ),
    ]);
    assert_eq!(truths, expected);
}

#[test]
fn the_same_seed_gives_the_same_file_and_malformed_annotations_name_their_field() {
    let annotation = annotation(&fixture());
    let a = serde_json::to_string(&generate(&annotation, 5)).unwrap();
    assert_eq!(a, serde_json::to_string(&generate(&annotation, 5)).unwrap());
    let mut broken = fixture();
    broken["trackingData"]["Blue Ball"]["pitResult"] = Value::from("Right Pit Maybe");
    let error = BallAnnotation::from_json(Path::new("outputs.json"), &broken).unwrap_err();
    assert!(
        error
            .to_string()
            .contains("trackingData.Blue Ball.pitResult"),
        "{error}"
    );
    let mut broken = fixture();
    broken["metaSamplingData"]["balls"][0]["color"] = Value::from(5);
    let error = BallAnnotation::from_json(Path::new("outputs.json"), &broken).unwrap_err();
    assert!(error.to_string().contains("Red Ball"), "{error}");
    let mut broken = fixture();
    broken["CounterFactualAnnotations"]["0"]["trackingData"]["onlyThatBall"]["pitResult"] =
        Value::from("Left Pit to Predict");
    assert!(BallAnnotation::from_json(Path::new("outputs.json"), &broken).is_err());
}
