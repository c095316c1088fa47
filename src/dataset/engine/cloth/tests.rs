//! Tests of the cloth engine on the hand-written video `tests/data/cloth_collision/0` and on
//! variants of it made by editing its JSON. Expected answers, worked out by hand from that file:
//!
//! * cloths: left stretching compliance 0.011, right 0, so the left cloth is the more elastic;
//!   left maximum bending 0.013, right 0.035, so the left cloth is the harder to bend;
//! * left half: the green plate ends `Supine` (fell over), the gray pillar `Reclining` (not asked
//!   whether it fell), the blue plate `Upright`. The green plate's `collisionEvents` name the gray
//!   pillar (the pillar's do not), and the gray pillar's `touchers` name the green plate (the
//!   plate's do not): that pair collides and ends in touch, the other two pairs do neither;
//! * right half: the yellow pillar ends `Upright`, the orange plate `Swooping` (fell over), the
//!   green pillar `Upright`. Yellow pillar and orange plate collide and end in touch; the orange
//!   plate and the green pillar collide but do not end in touch; the two pillars do neither;
//! * so, per video, fall over: 2 yes (green plate, orange plate) and 3 no → 2 + 2 asked;
//!   collision: 3 yes and 3 no → all 6 asked; touch: 2 yes and 4 no → 2 + 2 asked; pose:
//!   `Supine`, `Reclining` and `Swooping` once, `Upright` three times → 4 asked, one of each.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use serde_json::{Value, json};

use super::templates::FAMILIES;
use super::*;
use crate::dataset::cloth::outcome::Pose;
use crate::dataset::engine::{SampledSplits, sample_and_split};
use crate::dataset::{AnswerType, Question, QuestionId, Scenario};

const SEEDS: std::ops::Range<u64> = 0..40;

fn fixture() -> Value {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/cloth_collision/0/outputs.json");
    serde_json::from_slice(&fs_err::read(path).unwrap()).unwrap()
}

fn annotation(value: &Value) -> ClothAnnotation {
    ClothAnnotation::from_json(Path::new("outputs.json"), value).unwrap()
}

fn generate(annotation: &ClothAnnotation, seed: u64) -> PerVideoQuestions {
    generate_questions(&VideoId("0".into()), annotation, seed)
}

fn parse(record: &QuestionRecord) -> Question {
    Question::from_record(
        QuestionId("q".into()),
        VideoId("0".into()),
        Scenario::Cloth,
        record.clone(),
    )
    .unwrap()
}

fn title(record: &QuestionRecord) -> String {
    record.question.lines().next().unwrap().to_string()
}

/// Title → (option text → truth) of a choice family over many seeds, checking every record's
/// letters and program choices against its options; also each seed's number of questions.
fn choice_truths(family: &str) -> (BTreeMap<String, BTreeMap<String, bool>>, BTreeSet<usize>) {
    let annotation = annotation(&fixture());
    let mut truths: BTreeMap<String, BTreeMap<String, bool>> = BTreeMap::new();
    let mut counts = BTreeSet::new();
    for seed in SEEDS {
        let records = &generate(&annotation, seed).question_dict[family];
        counts.insert(records.len());
        for record in records {
            let question = parse(record);
            assert_eq!(question.answer_type, AnswerType::MultipleChoice);
            let choices = record.program.as_ref().unwrap()["choices"]
                .as_object()
                .unwrap();
            assert_eq!(choices.len(), question.options.len());
            let options = truths.entry(title(record)).or_default();
            for option in &question.options {
                let previous = options.insert(option.text.clone(), option.correct);
                assert!(previous.is_none_or(|p| p == option.correct), "{record:?}");
            }
        }
    }
    (truths, counts)
}

fn yes_no(holds: bool) -> BTreeMap<String, bool> {
    BTreeMap::from([("Yes".to_string(), holds), ("No".to_string(), !holds)])
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
    assert!(
        questions
            .question_dict
            .values()
            .all(|records| !records.is_empty())
    );
}

#[test]
fn property_answers_follow_the_cloths_values() {
    let annotation = annotation(&fixture());
    let mut answers: BTreeMap<String, String> = BTreeMap::new();
    let mut yes = 0;
    let mut total = 0;
    for seed in SEEDS {
        let questions = generate(&annotation, seed);
        for family in ["elasticity", "bending"] {
            let records = &questions.question_dict[family];
            assert_eq!(records.len(), 2, "{family}: one question per cloth");
            for record in records {
                assert_eq!(parse(record).answer_type, AnswerType::OpenEnded);
                total += 1;
                yes += usize::from(record.answer == "yes");
                answers.insert(record.question.clone(), record.answer.clone());
            }
        }
    }
    let expected = BTreeMap::from(
        [
            (
                "Is the elasticity of the left cloth much greater than that of the other?",
                "yes",
            ),
            (
                "Is the elasticity of the left cloth much less than that of the other?",
                "no",
            ),
            (
                "Is the elasticity of the right cloth much greater than that of the other?",
                "no",
            ),
            (
                "Is the elasticity of the right cloth much less than that of the other?",
                "yes",
            ),
            (
                "Is the left cloth much harder to bend or have wrinkles than the other?",
                "yes",
            ),
            (
                "Is the left cloth much easier to bend or have wrinkles than the other?",
                "no",
            ),
            (
                "Is the right cloth much harder to bend or have wrinkles than the other?",
                "no",
            ),
            (
                "Is the right cloth much easier to bend or have wrinkles than the other?",
                "yes",
            ),
        ]
        .map(|(q, a)| (q.to_string(), a.to_string())),
    );
    assert_eq!(answers, expected);
    // The coin flip balances yes and no.
    assert!(
        yes * 10 > total * 4 && yes * 10 < total * 6,
        "{yes} of {total}"
    );
    let record = &generate(&annotation, 0).question_dict["bending"][0];
    let comparator = if record.question.contains("harder") {
        "harder"
    } else {
        "easier"
    };
    assert_eq!(
        record.program,
        Some(json!(["left", "cloth", comparator, "right", "cloth"]))
    );
}

#[test]
fn cloths_with_equal_values_are_not_compared() {
    let mut document = fixture();
    document["clothRight"]["bendingCompliance"] = json!(0.013);
    let questions = generate(&annotation(&document), 0);
    assert!(questions.question_dict["bending"].is_empty());
    assert_eq!(questions.question_dict["elasticity"].len(), 2);
}

#[test]
fn fall_questions_read_the_end_pose_and_balance_yes_and_no() {
    let (truths, counts) = choice_truths("cloth_predictive_fall");
    let expected: BTreeMap<String, BTreeMap<String, bool>> = [
        ("green plate", true),
        ("orange plate", true),
        ("blue plate", false),
        ("yellow pillar", false),
        ("green pillar", false),
    ]
    .into_iter()
    .map(|(object, fell)| (format!("Does the {object} fall over?"), yes_no(fell)))
    .collect();
    // The reclining gray pillar is never asked; every other box is, over the seeds.
    assert_eq!(truths, expected);
    assert_eq!(counts, BTreeSet::from([4]));
    let annotation = annotation(&fixture());
    for seed in SEEDS {
        let records = &generate(&annotation, seed).question_dict["cloth_predictive_fall"];
        assert_eq!(records.iter().filter(|r| r.answer == "A").count(), 2);
    }
    let record = &generate(&annotation, 0).question_dict["cloth_predictive_fall"][0];
    let object = title(record)
        .strip_prefix("Does the ")
        .and_then(|rest| rest.strip_suffix(" fall over?"))
        .unwrap()
        .to_string();
    assert_eq!(
        record.program,
        Some(json!({
            "question": [object, "fall over", ""],
            "choices": {"A": [object, "fall over", ""], "B": [object, "not fall over", ""]},
        }))
    );
}

/// The truth of each unordered pair of a pair family, whichever box the title names first.
fn pair_truths(family: &str, prefix: &str, joiner: &str) -> BTreeMap<BTreeSet<String>, bool> {
    let (truths, _) = choice_truths(family);
    let mut by_pair = BTreeMap::new();
    let mut orders = BTreeSet::new();
    for (title, options) in truths {
        let (first, second) = title
            .strip_prefix(prefix)
            .and_then(|rest| rest.strip_suffix('?'))
            .and_then(|rest| rest.split_once(joiner))
            .unwrap();
        orders.insert((first.to_string(), second.to_string()));
        let pair = BTreeSet::from([first.to_string(), second.to_string()]);
        assert_eq!(options, yes_no(options["Yes"]));
        let previous = by_pair.insert(pair, options["Yes"]);
        assert!(previous.is_none_or(|p| p == options["Yes"]));
    }
    // The box named first is a coin flip: both orders occur over the seeds.
    assert!(orders.len() > by_pair.len(), "{orders:?}");
    by_pair
}

fn pairs(entries: &[(&str, &str, bool)]) -> BTreeMap<BTreeSet<String>, bool> {
    entries
        .iter()
        .map(|(a, b, holds)| (BTreeSet::from([(*a).to_string(), (*b).to_string()]), *holds))
        .collect()
}

#[test]
fn collision_questions_ask_every_pair_of_a_half() {
    let truths = pair_truths(
        "cloth_predictive_collision",
        "Does the ",
        " collide with the ",
    );
    let expected = pairs(&[
        ("green plate", "gray pillar", true),
        ("green plate", "blue plate", false),
        ("gray pillar", "blue plate", false),
        ("yellow pillar", "orange plate", true),
        ("yellow pillar", "green pillar", false),
        ("orange plate", "green pillar", true),
    ]);
    assert_eq!(truths, expected);
    let (_, counts) = choice_truths("cloth_predictive_collision");
    assert_eq!(counts, BTreeSet::from([6]));
}

#[test]
fn touch_questions_ask_about_the_end_and_balance_yes_and_no() {
    let truths = pair_truths(
        "cloth_predictive_touch",
        "Is the ",
        " finally in touch with the ",
    );
    let expected = pairs(&[
        ("green plate", "gray pillar", true),
        ("green plate", "blue plate", false),
        ("gray pillar", "blue plate", false),
        ("yellow pillar", "orange plate", true),
        ("yellow pillar", "green pillar", false),
        ("orange plate", "green pillar", false),
    ]);
    assert_eq!(truths, expected);
    let annotation = annotation(&fixture());
    for seed in SEEDS {
        let records = &generate(&annotation, seed).question_dict["cloth_predictive_touch"];
        assert_eq!(records.len(), 4);
        assert_eq!(records.iter().filter(|r| r.answer == "A").count(), 2);
    }
}

#[test]
fn pose_questions_offer_the_five_phrases_with_the_end_pose_true() {
    let (truths, counts) = choice_truths("cloth_predictive_pose");
    let expected_pose = [
        ("green plate", Pose::Supine),
        ("gray pillar", Pose::Reclining),
        ("blue plate", Pose::Upright),
        ("yellow pillar", Pose::Upright),
        ("orange plate", Pose::Swooping),
        ("green pillar", Pose::Upright),
    ];
    let expected: BTreeMap<String, BTreeMap<String, bool>> = expected_pose
        .iter()
        .map(|(object, truth)| {
            (
                format!("Which phrase below can best describe the final pose of the {object}?"),
                Pose::ALL
                    .into_iter()
                    .map(|pose| (pose.phrase().to_string(), pose == *truth))
                    .collect(),
            )
        })
        .collect();
    assert_eq!(truths, expected);
    assert_eq!(counts, BTreeSet::from([4]));
    // Each seed asks one box of each end pose, with the options in a random order.
    let annotation = annotation(&fixture());
    let mut answers = BTreeSet::new();
    for seed in SEEDS {
        let records = &generate(&annotation, seed).question_dict["cloth_predictive_pose"];
        let poses: BTreeSet<Pose> = records
            .iter()
            .map(|record| Pose::from_phrase(&record.positive[0]).unwrap())
            .collect();
        assert_eq!(poses.len(), 4);
        answers.extend(records.iter().map(|record| record.answer.clone()));
    }
    assert_eq!(answers.len(), 5, "{answers:?}");
    let record = &generate(&annotation, 0).question_dict["cloth_predictive_pose"][0];
    let program = record.program.as_ref().unwrap();
    let object = program["question"][0].as_str().unwrap();
    assert_eq!(program["question"], json!([object, "pose", ""]));
    let labels: BTreeSet<&str> = program["choices"]
        .as_object()
        .unwrap()
        .values()
        .map(|triple| triple[2].as_str().unwrap())
        .collect();
    assert_eq!(labels, Pose::ALL.map(Pose::as_str).into_iter().collect());
}

#[test]
fn a_family_whose_boxes_share_one_answer_is_not_asked() {
    let mut document = fixture();
    let halves = &mut document["objectFullAnnotation"];
    for (half, name) in [
        ("leftAll", "Green Plate"),
        ("leftAll", "Gray Pillar"),
        ("rightAll", "Orange Plate"),
        ("rightAll", "Yellow Pillar"),
        ("rightAll", "Green Pillar"),
    ] {
        let record = &mut halves[half]["isolatedObjects"][name];
        record["endPoseDescription"] = json!("Upright");
        record["collisionEvents"] = json!([{"Item1": 120, "Item2": "Cloth (Left)"}]);
        record["touchers"] = json!([]);
    }
    let questions = generate(&annotation(&document), 3);
    for family in [
        "cloth_predictive_fall",
        "cloth_predictive_collision",
        "cloth_predictive_touch",
        "cloth_predictive_pose",
    ] {
        assert!(questions.question_dict[family].is_empty(), "{family}");
    }
    assert_eq!(questions.question_dict["elasticity"].len(), 2);
}

#[test]
fn cubes_are_not_asked_about() {
    let mut document = fixture();
    let isolated = &mut document["objectFullAnnotation"]["leftAll"]["isolatedObjects"];
    let mut cube = isolated["Blue Plate"].clone();
    cube["name"] = json!("Pink Cube");
    cube["colorName"] = json!("Pink");
    cube["shape"] = json!("Cube");
    cube["endPoseDescription"] = json!("Supine");
    isolated["Pink Cube"] = cube;
    let annotation = annotation(&document);
    for seed in SEEDS {
        let questions = generate(&annotation, seed);
        assert!(
            questions
                .question_dict
                .values()
                .flatten()
                .all(|record| !record.question.contains("cube")),
            "seed {seed}"
        );
    }
}

#[test]
fn the_same_seed_gives_the_same_file_and_another_seed_another() {
    let annotation = annotation(&fixture());
    let a = serde_json::to_string(&generate(&annotation, 5)).unwrap();
    assert_eq!(a, serde_json::to_string(&generate(&annotation, 5)).unwrap());
    assert_ne!(a, serde_json::to_string(&generate(&annotation, 6)).unwrap());
    let other_video = generate_questions(&VideoId("1".into()), &annotation, 5);
    assert_ne!(a, serde_json::to_string(&other_video).unwrap());
}

#[test]
fn the_engine_reads_a_video_folder_and_names_a_malformed_field() {
    let root = tempfile::tempdir().unwrap();
    let dir = root.path().join("cloth_collision/0");
    fs_err::create_dir_all(&dir).unwrap();
    let mut document = fixture();
    fs_err::write(dir.join("outputs.json"), document.to_string()).unwrap();
    let video = VideoFolder::open(&dir, Some(Scenario::Cloth)).unwrap();
    let questions = (ENGINE.generate)(&video, 7).unwrap();
    assert_eq!(
        serde_json::to_string(&questions).unwrap(),
        serde_json::to_string(&generate(&annotation(&document), 7)).unwrap()
    );
    document["objectFullAnnotation"]["rightAll"]["isolatedObjects"]["Orange Plate"]["endPoseDescription"] =
        json!("Sideways");
    fs_err::write(dir.join("outputs.json"), document.to_string()).unwrap();
    let error = (ENGINE.generate)(&video, 7).unwrap_err().to_string();
    assert!(
        error.contains("outputs.json`: field `objectFullAnnotation.rightAll.isolatedObjects.Orange Plate.endPoseDescription` must be"),
        "{error}"
    );
}

#[test]
fn the_shared_sampler_draws_one_property_and_two_predictive_questions_a_video() {
    let annotation = annotation(&fixture());
    let videos: Vec<PerVideoQuestions> = (0..10)
        .map(|id| generate_questions(&VideoId(id.to_string()), &annotation, 11))
        .collect();
    let splits: SampledSplits = sample_and_split(Scenario::Cloth, &videos, &ENGINE.per_video, 11);
    assert_eq!(
        (splits.train.len(), splits.val.len(), splits.test.len()),
        (15, 6, 9)
    );
    for record in splits.all() {
        let predictive = record.question_family.contains("predict");
        assert_eq!(predictive, record.answer_type == "multiple_choice");
    }
    let property = splits
        .all()
        .filter(|record| !record.question_family.contains("predict"))
        .count();
    assert_eq!(property, 10);
}
