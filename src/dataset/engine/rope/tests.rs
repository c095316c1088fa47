//! Tests of the rope engine on the real demo video (`eval/demo/pulley_group/0`) and on synthetic
//! variants of it, made by editing its JSON. Expected values come from running the public engine
//! on the same video over 300 seeds (exact answers of the deterministic families, count ranges of
//! the others). Every choice option's truth is re-derived here from the counterfactual records by
//! parsing the option text, independently of the engine's code.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use serde_json::{Value, json};

use super::*;
use crate::dataset::rope::{RopeChange, RopeObjectKind};
use crate::dataset::{AnswerType, Category, Family, Question, QuestionId, Scenario, Split};

const SEEDS: std::ops::Range<u64> = 0..300;

fn real_json() -> Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/pulley_group/0/outputs.json");
    serde_json::from_slice(&fs_err::read(&path).unwrap()).unwrap()
}

fn annotation(value: &Value) -> RopeAnnotation {
    RopeAnnotation::from_json(Path::new("outputs.json"), value).unwrap()
}

fn generate(annotation: &RopeAnnotation, seed: u64) -> PerVideoQuestions {
    generate_questions(&VideoId("0".into()), annotation, seed).unwrap()
}

/// Renames an object everywhere in the annotation (every key and string value).
fn rename(value: &Value, from: &str, to: &str) -> Value {
    let text = serde_json::to_string(value)
        .unwrap()
        .replace(&format!("\"{from}"), &format!("\"{to}"));
    serde_json::from_str(&text).unwrap()
}

fn records<'a>(questions: &'a PerVideoQuestions, family: &str) -> &'a [QuestionRecord] {
    &questions.question_dict[family]
}

fn parse(record: &QuestionRecord) -> Question {
    Question::from_record(
        QuestionId("q".into()),
        VideoId("0".into()),
        Scenario::Rope,
        record.clone(),
    )
    .unwrap()
}

// ---------------------------------------------------------------------------------------------
// Independent ground truth, computed from the annotation without the engine's code.

/// The annotation name a question phrase refers to: the phrase's words must appear in order in
/// the name, starting with its first (colour) word, and exactly one name may match.
fn resolve<'a>(phrase: &str, names: &'a BTreeSet<String>) -> &'a str {
    let phrase_words: Vec<&str> = phrase.split(' ').collect();
    let matches: Vec<&String> = names
        .iter()
        .filter(|name| {
            let lower = name.split('(').next().unwrap().trim().to_lowercase();
            let words: Vec<&str> = lower.split(' ').collect();
            let mut remaining = words.iter();
            words.first() == phrase_words.first()
                && phrase_words.iter().all(|word| remaining.any(|w| w == word))
        })
        .collect();
    assert_eq!(matches.len(), 1, "`{phrase}` matches {matches:?}");
    matches[0]
}

/// All object names a counterfactual mentions, plus the loads.
fn object_names(annotation: &RopeAnnotation) -> BTreeSet<String> {
    let mut names: BTreeSet<String> = annotation.output_mass_kg.keys().cloned().collect();
    for cf in annotation.mass_counterfactuals() {
        names.extend(cf.rotation.keys().cloned());
        names.extend(cf.motion.keys().cloned());
    }
    names
}

/// The sign the counterfactual records give `object`'s rotation or motion after `target` got
/// lighter or heavier (lighter: `round(Item1, 2) > round(Item2, 2)`).
fn counterfactual_sign(
    annotation: &RopeAnnotation,
    target: &str,
    lighter: bool,
    rotation: bool,
    object: &str,
) -> i8 {
    let round = |kg: f64| (kg * 100.0).round();
    let entry = annotation
        .mass_counterfactuals()
        .find(|cf| match &cf.change {
            RopeChange::Mass {
                target: t,
                before_kg,
                after_kg,
            } => t == target && (round(*before_kg) > round(*after_kg)) == lighter,
            _ => false,
        })
        .unwrap_or_else(|| panic!("no counterfactual for {target} lighter={lighter}"));
    let results = if rotation {
        &entry.rotation
    } else {
        &entry.motion
    };
    results[object]
}

/// `(rotation?, sign)` of a direction word.
fn direction_sign(word: &str) -> (Option<bool>, i8) {
    match word {
        "clockwise" | "Clockwise" => (Some(true), 1),
        "anti-clockwise" | "Anti-clockwise" => (Some(true), -1),
        "up" | "Up" => (Some(false), 1),
        "down" | "Down" => (Some(false), -1),
        "stationary" | "Stationary" => (None, 0),
        other => panic!("unknown direction `{other}`"),
    }
}

/// The text between `start` and the next `end` in `text`.
fn between<'a>(text: &'a str, start: &str, end: &str) -> &'a str {
    let after = &text[text
        .find(start)
        .unwrap_or_else(|| panic!("`{start}` not in `{text}`"))
        + start.len()..];
    &after[..after
        .find(end)
        .unwrap_or_else(|| panic!("`{end}` not in `{after}`"))]
}

/// The changed load and "lighter?" of a counterfactual title.
fn changed_load(title: &str) -> (&str, bool) {
    let before = &title[..title.find(" were much ").unwrap()];
    let load = before.rsplit_once("the ").unwrap().1;
    let change = between(
        title,
        " were much ",
        if title.contains(',') { "," } else { "?" },
    );
    assert!(change == "lighter" || change == "heavier", "{title}");
    (load, change == "lighter")
}

/// Re-derives the truth of every option of a choice record and checks it against the record.
fn check_choice_record(annotation: &RopeAnnotation, record: &QuestionRecord) {
    let names = object_names(annotation);
    let question = parse(record);
    assert_eq!(question.answer_type, AnswerType::MultipleChoice);
    let texts: BTreeSet<&str> = question.options.iter().map(|o| o.text.as_str()).collect();
    assert_eq!(
        texts.len(),
        question.options.len(),
        "duplicate option text in {record:?}"
    );
    let program = record.program.as_ref().unwrap();
    let choices = program["choices"].as_object().unwrap();
    assert_eq!(choices.len(), question.options.len());
    let title = question.title.as_str();
    for option in &question.options {
        let choice = &choices[&option.letter.to_string()];
        let truth = match record.question_family.as_str() {
            "rope_counterfactual" => {
                let (load, lighter) = changed_load(title);
                let (object, outcome) = option
                    .text
                    .strip_prefix("The ")
                    .unwrap()
                    .split_once(" would ")
                    .unwrap();
                let (rotation, sign) = match outcome {
                    "rotate clockwise" => (true, 1),
                    "rotate anti-clockwise" => (true, -1),
                    "not rotate" => (true, 0),
                    "move up" => (false, 1),
                    "move down" => (false, -1),
                    "not move" => (false, 0),
                    other => panic!("unknown outcome `{other}`"),
                };
                let movement = if rotation { "rotation" } else { "motion" };
                let direction = match (rotation, sign) {
                    (_, 0) => "stationary",
                    (true, 1) => "clockwise",
                    (true, _) => "anti-clockwise",
                    (false, 1) => "up",
                    (false, _) => "down",
                };
                assert_eq!(choice, &json!([object, movement, direction]), "{record:?}");
                assert_eq!(
                    program["question"],
                    json!([load, if lighter { "decrease" } else { "increase" }, "mass"])
                );
                let target = resolve(load, &names);
                counterfactual_sign(
                    annotation,
                    target,
                    lighter,
                    rotation,
                    resolve(object, &names),
                ) == sign
            }
            "rope_counterfactual2" => {
                let rotation = title.contains(" rotate");
                let object = between(
                    title,
                    "direction would the ",
                    if rotation { " rotate" } else { " move" },
                );
                let load = if title.starts_with("If the ") {
                    between(title, "If the ", " were much ")
                } else {
                    between(title, " if the ", " were much ")
                };
                let lighter = between(
                    title,
                    " were much ",
                    if title.starts_with("If") { "," } else { "?" },
                ) == "lighter";
                let (option_rotation, sign) = direction_sign(&option.text);
                assert!(option_rotation.is_none_or(|r| r == rotation), "{record:?}");
                let words = choice.as_array().unwrap();
                assert_eq!(words[0], json!(object));
                assert_eq!(
                    words[1],
                    json!(if rotation { "rotation" } else { "motion" })
                );
                assert_eq!(direction_sign(words[2].as_str().unwrap()).1, sign);
                let target = resolve(load, &names);
                counterfactual_sign(
                    annotation,
                    target,
                    lighter,
                    rotation,
                    resolve(object, &names),
                ) == sign
            }
            "rope_goaldriven" => {
                let (rest, end) = match title.strip_prefix("If we want the ") {
                    Some(rest) => (rest, ", what can we do?"),
                    None => (title.split_once("let the ").unwrap().1, "?"),
                };
                let (object, goal) = rest.strip_suffix(end).unwrap().split_once(" to ").unwrap();
                let (verb, direction) = goal.split_once(' ').unwrap();
                let rotation = verb == "rotate";
                let (_, goal_sign) = direction_sign(direction);
                assert_eq!(
                    program["question"],
                    json!([
                        object,
                        if rotation { "rotation" } else { "motion" },
                        direction
                    ])
                );
                let (change, load) = option.text.split_once(" the mass of the ").unwrap();
                let lighter = match change {
                    "Decrease" => true,
                    "Increase" => false,
                    other => panic!("unknown change `{other}`"),
                };
                assert_eq!(choice, &json!([load, change.to_lowercase(), "mass"]));
                let target = resolve(load, &names);
                counterfactual_sign(
                    annotation,
                    target,
                    lighter,
                    rotation,
                    resolve(object, &names),
                ) == goal_sign
            }
            other => panic!("not a choice family: {other}"),
        };
        assert_eq!(
            option.correct, truth,
            "option {} of {record:#?}",
            option.letter
        );
        let listed = if truth {
            &record.positive
        } else {
            &record.negative
        };
        assert!(listed.contains(&option.text), "{record:?}");
    }
    assert_eq!(
        record.positive.len() + record.negative.len(),
        question.options.len()
    );
    let option_count = question.options.len();
    let correct_count = question.options.iter().filter(|o| o.correct).count();
    match record.question_family.as_str() {
        "rope_counterfactual" | "rope_goaldriven" => {
            assert!(
                (3..=5).contains(&option_count) && correct_count >= 1,
                "{record:?}"
            );
        }
        _ => assert_eq!((option_count, correct_count), (3, 1), "{record:?}"),
    }
}

/// Nominal masses by question phrase (`purple cube`), computed here as `ceil(m·100)/100`.
fn nominal_masses(annotation: &RopeAnnotation) -> BTreeMap<String, f64> {
    annotation
        .output_mass_kg
        .iter()
        .map(|(name, kg)| (name.to_lowercase(), (kg * 100.0).ceil() / 100.0))
        .collect()
}

/// Whether two loads share a `relatedGroups` group.
fn related(annotation: &RopeAnnotation, first: &str, second: &str) -> bool {
    annotation.related_groups.iter().any(|group| {
        let lower: Vec<String> = group.iter().map(|name| name.to_lowercase()).collect();
        lower.iter().any(|n| n == first) && lower.iter().any(|n| n == second)
    })
}

/// The truth of `m1 <cmp> factor·m2` with the public engine's tolerance.
fn statement_holds(first_kg: f64, comparator: &str, factor: &str, second_kg: f64) -> bool {
    let scaled = second_kg
        * match factor {
            "" => 1.0,
            "twice " => 2.0,
            "half " => 0.5,
            other => panic!("unknown factor `{other}`"),
        };
    match comparator {
        "greater than" => first_kg > scaled + 1e-5,
        "less than" => first_kg < scaled - 1e-5,
        "equal to" => (first_kg - scaled).abs() < 1e-5,
        other => panic!("unknown comparator `{other}`"),
    }
}

/// The six program words of a mass or tension record, checked against the question text.
fn comparison_program(record: &QuestionRecord, noun: &str) -> [String; 6] {
    let words: Vec<String> = record
        .program
        .as_ref()
        .unwrap()
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap().to_string())
        .collect();
    let words: [String; 6] = words.try_into().unwrap();
    let [c1, s1, comparator, factor, c2, s2] = &words;
    assert_eq!(
        record.question,
        format!("Is the {noun} of the {c1} {s1} {comparator} {factor}that of the {c2} {s2}?")
    );
    assert_eq!(record.positive, std::slice::from_ref(&record.answer));
    assert!(record.negative.is_empty());
    words
}

/// Checks every mass record against the masses and groups of the annotation.
fn check_mass_records(annotation: &RopeAnnotation, records: &[QuestionRecord]) {
    let masses = nominal_masses(annotation);
    for record in records {
        let [c1, s1, comparator, factor, c2, s2] = comparison_program(record, "mass");
        let (first, second) = (format!("{c1} {s1}"), format!("{c2} {s2}"));
        let expected = if related(annotation, &first, &second) {
            if statement_holds(masses[&first], &comparator, &factor, masses[&second]) {
                "yes"
            } else {
                "no"
            }
        } else {
            assert_eq!(factor, "", "{record:?}");
            "can not answer"
        };
        assert_eq!(record.answer, expected, "{record:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// The real video.

/// (name key, colour, shape, dynamics, class, nominal mass) of an engine object.
type ObjectRow<'a> = (&'a str, &'a str, &'a str, &'a str, &'a str, Option<f64>);

#[test]
fn real_video_object_list_mirrors_the_public_engine() {
    let annotation = annotation(&real_json());
    let scene = RopeScene::from_annotation("0", &annotation).unwrap();
    let expected: [ObjectRow<'_>; 10] = [
        (
            "purple cube",
            "purple",
            "cube",
            "dynamic",
            "object",
            Some(0.2),
        ),
        (
            "green cube",
            "green",
            "cube",
            "dynamic",
            "object",
            Some(0.25),
        ),
        (
            "pink sphere",
            "pink",
            "sphere",
            "dynamic",
            "object",
            Some(0.15),
        ),
        ("purple rope", "purple", "rope", "dynamic", "rope", None),
        ("green rope", "green", "rope", "dynamic", "rope", None),
        (
            "blue solid static pulley",
            "blue",
            "solid pulley",
            "static",
            "pulley",
            None,
        ),
        (
            "gray hollow static pulley",
            "gray",
            "hollow pulley",
            "static",
            "pulley",
            None,
        ),
        (
            "pink solid static pulley",
            "pink",
            "solid pulley",
            "static",
            "pulley",
            None,
        ),
        (
            "brown fixed point",
            "brown",
            "fixed point",
            "static",
            "fixed point",
            None,
        ),
        (
            "purple solid static pulley",
            "purple",
            "solid pulley",
            "static",
            "pulley",
            None,
        ),
    ];
    let actual: Vec<ObjectRow<'_>> = scene
        .objects()
        .iter()
        .map(|o| {
            (
                o.name_key.as_str(),
                o.color.as_str(),
                o.shape.as_str(),
                o.dynamics.as_str(),
                o.class_type(),
                o.nominal_mass_kg,
            )
        })
        .collect();
    assert_eq!(actual, expected);
    let tensions: Vec<Option<f64>> = scene
        .objects()
        .iter()
        .map(|o| o.rope_tension_newtons)
        .collect();
    assert_eq!(tensions[3..5], [Some(1.947_815_18), Some(1.998_609)]);

    let index = |name: &str| scene.index_of(name).unwrap();
    let (purple, green, pink) = (
        index("Purple Cube"),
        index("Green Cube"),
        index("Pink Sphere"),
    );
    assert!(scene.are_related(purple, green) && scene.are_related(green, purple));
    assert!(!scene.are_related(purple, pink) && !scene.are_related(green, pink));
    assert!(
        scene
            .loads()
            .all(|load| !scene.hangs_under_movable_pulley(load))
    );
    let rope = |load: usize| {
        scene
            .object(scene.rope_of(load).unwrap())
            .unwrap()
            .name_key
            .clone()
    };
    assert_eq!(
        [rope(purple), rope(green), rope(pink)],
        ["purple rope", "purple rope", "green rope"]
    );
    let references: Vec<&str> = (0..10).map(|i| scene.reference(i).unwrap()).collect();
    assert_eq!(
        references,
        [
            "purple cube",
            "green cube",
            "pink sphere",
            "purple rope",
            "green rope",
            "blue pulley",
            "gray pulley",
            "pink pulley",
            "brown fixed point",
            "purple pulley"
        ]
    );
}

#[test]
fn real_video_property_counts_match_the_public_engine_in_fixed_order() {
    let annotation = annotation(&real_json());
    for seed in [0, 1, 299] {
        let questions = generate(&annotation, seed);
        let answers = |family: &str| -> Vec<(String, String)> {
            records(&questions, family)
                .iter()
                .map(|r| (r.question.clone(), r.answer.clone()))
                .collect()
        };
        let shape: Vec<(String, String)> = [
            ("cube", "2"),
            ("sphere", "1"),
            ("pulley", "4"),
            ("solid pulley", "3"),
            ("hollow pulley", "1"),
            ("rope", "2"),
            ("fixed point", "1"),
        ]
        .iter()
        .map(|(shape, count)| {
            (
                format!("How many {shape}s are there in the video?"),
                (*count).to_string(),
            )
        })
        .collect();
        assert_eq!(answers("shape"), shape);
        let color: Vec<(String, String)> = [
            ("black", 0),
            ("orange", 0),
            ("yellow", 0),
            ("brown", 1),
            ("purple", 3),
            ("cyan", 0),
            ("gray", 1),
            ("red", 0),
            ("white", 0),
            ("pink", 2),
            ("blue", 1),
            ("green", 2),
        ]
        .iter()
        .map(|(color, count)| {
            (
                format!("How many {color} objects are there in the video?"),
                count.to_string(),
            )
        })
        .collect();
        assert_eq!(answers("color"), color);
        let existing = [
            "blue solid pulley",
            "brown fixed point",
            "gray hollow pulley",
            "green cube",
            "green rope",
            "pink solid pulley",
            "pink sphere",
            "purple cube",
            "purple rope",
            "purple solid pulley",
        ];
        let existence = records(&questions, "existence");
        assert_eq!(existence.len(), 72);
        assert_eq!(
            existence[0].question,
            "Is there any black cube in the video?"
        );
        assert_eq!(
            existence[71].question,
            "Is there any green fixed point in the video?"
        );
        for record in existence {
            let [color, shape] = [0, 1].map(|i| {
                record.program.as_ref().unwrap()[i]
                    .as_str()
                    .unwrap()
                    .to_string()
            });
            assert_eq!(
                record.question,
                format!("Is there any {color} {shape} in the video?")
            );
            let expected = if existing.contains(&format!("{color} {shape}").as_str()) {
                "yes"
            } else {
                "no"
            };
            assert_eq!(record.answer, expected, "{}", record.question);
        }
    }
}

#[test]
fn real_video_mass_answers_follow_the_masses_and_tension_cannot_be_answered() {
    let annotation = annotation(&real_json());
    let mut mass_answers = BTreeSet::new();
    let mut tension_pairs = BTreeSet::new();
    for seed in SEEDS {
        let questions = generate(&annotation, seed);
        let mass = records(&questions, "mass");
        check_mass_records(&annotation, mass);
        mass_answers.extend(mass.iter().map(|r| r.answer.clone()));
        for record in records(&questions, "tension") {
            let [c1, _, _, factor, c2, _] = comparison_program(record, "tension");
            assert_eq!(
                (record.answer.as_str(), factor.as_str()),
                ("can not answer", ""),
                "{record:?}"
            );
            tension_pairs.insert((c1, c2));
        }
    }
    let expected_answers: BTreeSet<String> =
        ["yes", "no", "can not answer"].map(String::from).into();
    assert_eq!(mass_answers, expected_answers);
    let expected_pairs: BTreeSet<(String, String)> = [("green", "purple"), ("purple", "green")]
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .into();
    assert_eq!(tension_pairs, expected_pairs);
}

#[test]
fn real_video_choice_options_are_true_exactly_when_the_counterfactuals_say_so() {
    let annotation = annotation(&real_json());
    let mut correct_by_family: BTreeMap<String, BTreeSet<bool>> = BTreeMap::new();
    for seed in 0..100 {
        let questions = generate(&annotation, seed);
        for family in [
            "rope_counterfactual",
            "rope_counterfactual2",
            "rope_goaldriven",
        ] {
            for record in records(&questions, family) {
                check_choice_record(&annotation, record);
                let question = parse(record);
                correct_by_family
                    .entry(family.into())
                    .or_default()
                    .extend(question.options.iter().map(|o| o.correct));
            }
        }
    }
    // Every family offers both true and false options.
    assert!(
        correct_by_family.values().all(|seen| seen.len() == 2),
        "{correct_by_family:?}"
    );
}

#[test]
fn real_video_every_record_is_a_valid_question() {
    let annotation = annotation(&real_json());
    for seed in 0..50 {
        let questions = generate(&annotation, seed);
        let families: Vec<&str> = questions.question_dict.keys().map(String::as_str).collect();
        assert_eq!(
            families,
            [
                "mass",
                "tension",
                "shape",
                "color",
                "existence",
                "rope_counterfactual",
                "rope_counterfactual2",
                "rope_goaldriven"
            ]
        );
        for (family, family_records) in &questions.question_dict {
            for record in family_records {
                assert_eq!(&record.question_family, family);
                let question = parse(record);
                let open =
                    ["mass", "tension", "shape", "color", "existence"].contains(&family.as_str());
                assert_eq!(
                    question.answer_type == AnswerType::OpenEnded,
                    open,
                    "{record:?}"
                );
                assert!(
                    record.qtype.is_none()
                        && record.question_id.is_none()
                        && record.split.is_none()
                );
            }
        }
    }
}

/// Family sizes over seeds 0..300: fixed where the public engine's are, and within the public
/// engine's observed range otherwise. Prints the histograms (`--nocapture`) for comparison.
#[test]
fn real_video_family_counts_match_the_public_engine() {
    let annotation = annotation(&real_json());
    let mut histograms: BTreeMap<&str, BTreeMap<usize, usize>> = BTreeMap::new();
    for seed in SEEDS {
        let questions = generate(&annotation, seed);
        for (family, family_records) in &questions.question_dict {
            let family = templates::FAMILIES
                .iter()
                .find(|f| **f == family.as_str())
                .unwrap();
            *histograms
                .entry(family)
                .or_default()
                .entry(family_records.len())
                .or_default() += 1;
        }
    }
    for (family, histogram) in &histograms {
        let total: usize = histogram.iter().map(|(count, seeds)| count * seeds).sum();
        eprintln!(
            "{family}: mean {:.2} histogram {histogram:?}",
            total as f64 / 300.0
        );
    }
    let fixed = [
        ("shape", 7),
        ("color", 12),
        ("existence", 72),
        ("rope_counterfactual2", 66),
        ("rope_goaldriven", 5),
    ];
    for (family, count) in fixed {
        assert_eq!(
            histograms[family].keys().copied().collect::<Vec<_>>(),
            [count],
            "{family}"
        );
    }
    let ranges = [
        ("mass", 2..=6),
        ("tension", 0..=4),
        ("rope_counterfactual", 13..=22),
    ];
    for (family, range) in ranges {
        let counts: Vec<usize> = histograms[family].keys().copied().collect();
        assert!(
            counts.iter().all(|count| range.contains(count)),
            "{family}: {counts:?}"
        );
        assert!(
            counts.len() >= 4,
            "{family} should vary with the seed: {counts:?}"
        );
    }
}

/// Shares of questions by option count and by correct-option count, against the public engine
/// run on this video over 3000 seeds (`random.seed(s)` before the family).
#[test]
fn real_video_option_statistics_match_the_public_engine() {
    // (family, [share with 3, 4, 5 options], [share with 1, 2, 3, 4, 5 correct options])
    let reference: [(&str, [f64; 3], [f64; 5]); 2] = [
        (
            "rope_counterfactual",
            [0.3597, 0.3322, 0.3080],
            [0.2474, 0.4484, 0.2529, 0.0482, 0.0031],
        ),
        (
            "rope_goaldriven",
            [0.3323, 0.3395, 0.3282],
            [0.3990, 0.6010, 0.0, 0.0, 0.0],
        ),
    ];
    let annotation = annotation(&real_json());
    let all: Vec<PerVideoQuestions> = SEEDS.map(|seed| generate(&annotation, seed)).collect();
    for (family, option_shares, correct_shares) in reference {
        let questions: Vec<Question> = all
            .iter()
            .flat_map(|q| records(q, family))
            .map(parse)
            .collect();
        let share = |predicate: &dyn Fn(&Question) -> bool| {
            questions.iter().filter(|q| predicate(q)).count() as f64 / questions.len() as f64
        };
        for (count, expected) in (3..=5).zip(option_shares) {
            let actual = share(&|q| q.options.len() == count);
            eprintln!("{family}: {count} options {actual:.4} (public engine {expected:.4})");
            assert!(
                (actual - expected).abs() < 0.03,
                "{family}: {count} options {actual} vs {expected}"
            );
        }
        for (count, expected) in (1..=5).zip(correct_shares) {
            let actual = share(&|q| q.options.iter().filter(|o| o.correct).count() == count);
            eprintln!("{family}: {count} correct {actual:.4} (public engine {expected:.4})");
            assert!(
                (actual - expected).abs() < 0.03,
                "{family}: {count} correct {actual} vs {expected}"
            );
        }
    }
}

#[test]
fn same_seed_same_bytes_and_different_seeds_differ() {
    let annotation = annotation(&real_json());
    let bytes = |seed| serde_json::to_vec(&generate(&annotation, seed)).unwrap();
    assert_eq!(bytes(7), bytes(7));
    assert_ne!(bytes(7), bytes(8));
    // The stream is per video: another video id draws differently from the same seed.
    let other = generate_questions(&VideoId("1".into()), &annotation, 7).unwrap();
    assert_eq!(other.video_id, "1");
    assert_ne!(
        serde_json::to_vec(&other.question_dict).unwrap(),
        serde_json::to_vec(&generate(&annotation, 7).question_dict).unwrap()
    );
}

#[test]
fn counterfactual_direction_questions_are_shuffled_with_their_programs() {
    let annotation = annotation(&real_json());
    let questions = generate(&annotation, 0);
    let direction_records = records(&questions, "rope_counterfactual2");
    let orders: BTreeSet<String> = direction_records
        .iter()
        .map(|r| r.question.split('\n').skip(1).collect::<Vec<_>>().join("|"))
        .collect();
    // Rotation and motion each have 6 orders of 3 options; 66 questions show many of them.
    assert!(orders.len() > 6, "{orders:?}");
    let first = &direction_records[0];
    assert!(
        first.question.starts_with(
            "If the purple cube were much lighter, which direction would the blue pulley rotate?"
        ) || first.question.starts_with(
            "Which direction would the blue pulley rotate if the purple cube were much lighter?"
        )
    );
}

// ---------------------------------------------------------------------------------------------
// Synthetic variants.

/// The real video with its Pink static pulley made movable and a Red Sphere (0.2 kg × 1.975)
/// hanging under it on a Yellow Rope; the Green Cube weighs `green_kg`.
fn movable_pulley_variant(green_kg: f64) -> RopeAnnotation {
    let mut value = rename(
        &real_json(),
        "Pink Solid Static Pulley",
        "Pink Solid Dynamic Pulley",
    );
    let group = value["relatedGroups"][0].as_array_mut().unwrap();
    let pulley = group
        .iter()
        .position(|name| name == "Pink Solid Dynamic Pulley (1 2)")
        .unwrap();
    group.insert(pulley + 1, json!("Yellow Rope"));
    group.insert(pulley + 2, json!("Red Sphere"));
    value["relatedGroupsInRope"][0]["Yellow Rope"] = json!([
        "Pink Solid Dynamic Pulley (1 2)",
        "Yellow Rope",
        "Red Sphere"
    ]);
    value["outputMass"]["Red Sphere"] = json!(0.395);
    value["outputMass"]["Green Cube"] = json!(green_kg);
    value["ResultTension"]["Yellow Rope"] =
        json!({"(Pink Solid Dynamic Pulley (1 2), Red Sphere)": -3.87});
    annotation(&value)
}

#[test]
fn movable_pulley_loads_compare_with_twice_and_half() {
    for green_kg in [0.15, 0.2, 0.25] {
        let annotation = movable_pulley_variant(green_kg);
        let scene = RopeScene::from_annotation("0", &annotation).unwrap();
        assert_eq!(scene.objects().len(), 12);
        let red = scene.index_of("Red Sphere").unwrap();
        assert_eq!(scene.object(red).unwrap().nominal_mass_kg, Some(0.4));
        assert!(scene.hangs_under_movable_pulley(red));
        assert_eq!(
            scene
                .loads()
                .filter(|&load| scene.hangs_under_movable_pulley(load))
                .count(),
            1
        );
        assert_eq!(
            scene.object(scene.rope_of(red).unwrap()).unwrap().name_key,
            "yellow rope"
        );
        let purple = scene.index_of("Purple Cube").unwrap();
        assert!(scene.are_related(red, purple));
        assert_eq!(
            scene.reference_by_name("Pink Solid Dynamic Pulley (1 2)"),
            Some("pink pulley")
        );

        let mut statements = BTreeSet::new();
        for seed in SEEDS {
            let questions = generate(&annotation, seed);
            check_mass_records(&annotation, records(&questions, "mass"));
            for record in records(&questions, "mass") {
                let [c1, _, comparator, factor, c2, _] = comparison_program(record, "mass");
                if c1 == "red" || c2 == "red" {
                    statements.insert((c1 == "red", comparator, factor));
                }
            }
            for family in [
                "rope_counterfactual",
                "rope_counterfactual2",
                "rope_goaldriven",
            ] {
                for record in records(&questions, family) {
                    check_choice_record(&annotation, record);
                }
            }
        }
        let factors: BTreeSet<&str> = statements
            .iter()
            .map(|(_, _, factor)| factor.as_str())
            .collect();
        assert_eq!(
            factors,
            BTreeSet::from(["", "twice ", "half "]),
            "green {green_kg}: {statements:?}"
        );
        // The red sphere first compares with twice the other load, second with half of it.
        assert!(
            statements
                .iter()
                .any(|(red_first, _, f)| *red_first && f == "twice ")
        );
        assert!(
            statements
                .iter()
                .any(|(red_first, _, f)| !*red_first && f == "half ")
        );
    }
}

#[test]
fn tension_skips_answerable_pairs_on_a_rope_with_different_masses() {
    // Loads per rope in the movable-pulley variant.
    let rope_loads = [
        ("yellow", vec!["red sphere"]),
        ("purple", vec!["purple cube", "green cube"]),
        ("green", vec!["pink sphere"]),
    ];
    for (green_kg, purple_rope_ambiguous) in [(0.2, false), (0.25, true)] {
        let annotation = movable_pulley_variant(green_kg);
        let masses = nominal_masses(&annotation);
        let mut answers_by_question: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for seed in SEEDS {
            for record in records(&generate(&annotation, seed), "tension") {
                let [c1, _, comparator, factor, c2, _] = comparison_program(record, "tension");
                answers_by_question
                    .entry(record.question.clone())
                    .or_default()
                    .insert(record.answer.clone());
                if record.answer == "can not answer" {
                    continue;
                }
                let loads = |color: &str| &rope_loads.iter().find(|(c, _)| *c == color).unwrap().1;
                assert!(
                    !purple_rope_ambiguous || (c1 != "purple" && c2 != "purple"),
                    "{record:?}"
                );
                // Every load pair behind this rope pair gives the recorded answer.
                for first in loads(&c1) {
                    for second in loads(&c2) {
                        let holds =
                            statement_holds(masses[*first], &comparator, &factor, masses[*second]);
                        assert_eq!(
                            record.answer,
                            if holds { "yes" } else { "no" },
                            "{record:?}"
                        );
                    }
                }
            }
        }
        assert!(
            answers_by_question
                .values()
                .all(|answers| answers.len() == 1),
            "{answers_by_question:?}"
        );
        let answerable = answers_by_question
            .values()
            .filter(|a| !a.contains("can not answer"))
            .count();
        // Only the yellow and purple ropes are in one group; with an ambiguous purple rope no
        // answerable tension question is left.
        assert_eq!(
            answerable > 0,
            !purple_rope_ambiguous,
            "{answers_by_question:?}"
        );
    }
}

#[test]
fn single_true_counterfactuals_get_their_answer_from_the_emitted_options() {
    let mut value = real_json();
    // As the reference's synthetic variant A: the pink sphere's counterfactuals only move the
    // purple cube, so they have one true outcome (unless "green cube would not move" is drawn).
    for (sub_entry, sign) in [("0", 1), ("1", -1)] {
        value["CounterFactualAnnotations"]["4"][sub_entry]["ResultRotation"] = json!({});
        value["CounterFactualAnnotations"]["4"][sub_entry]["ResultMotion"] =
            json!({"Purple Cube": sign, "Green Cube": 0});
    }
    let variant_a = value.clone();
    // Variant B also drops the purple cube's counterfactual, so a single-true entry comes first
    // (the public engine then crashed with `UnboundLocalError`).
    value["CounterFactualAnnotations"]
        .as_object_mut()
        .unwrap()
        .remove("2");
    for variant in [variant_a, value] {
        let annotation = annotation(&variant);
        let mut single_true = 0;
        for seed in 0..100 {
            let questions = generate(&annotation, seed);
            for record in records(&questions, "rope_counterfactual") {
                check_choice_record(&annotation, record);
                let question = parse(record);
                if changed_load(&question.title).0 == "pink sphere" {
                    // The single-true branch: the one true outcome plus two false ones.
                    let correct = question.options.iter().filter(|o| o.correct).count();
                    if correct == 1 && record.positive[0].starts_with("The purple cube would move")
                    {
                        single_true += 1;
                        assert_eq!(question.options.len(), 3, "{record:?}");
                        assert_eq!(record.answer.len(), 1);
                    }
                }
            }
            for family in ["rope_counterfactual2", "rope_goaldriven"] {
                for record in records(&questions, family) {
                    check_choice_record(&annotation, record);
                }
            }
        }
        // Two pink-sphere entries per seed, each single-true with probability 0.8.
        assert!(single_true > 120, "{single_true}");
    }
}

#[test]
fn same_attribute_objects_are_not_merged_and_are_never_asked_about() {
    // Decision (a): two blue solid static pulleys; the public engine merged them into one.
    let value = rename(
        &real_json(),
        "Purple Solid Static Pulley",
        "Blue Solid Static Pulley",
    );
    let annotation = annotation(&value);
    let scene = RopeScene::from_annotation("0", &annotation).unwrap();
    assert_eq!(scene.objects().len(), 10);
    assert_eq!(
        scene.reference_by_name("Blue Solid Static Pulley (0 1)"),
        None
    );
    assert_eq!(
        scene.reference_by_name("Blue Solid Static Pulley (1 0)"),
        None
    );
    let questions = generate(&annotation, 3);
    let answer = |family: &str, question: &str| {
        records(&questions, family)
            .iter()
            .find(|r| r.question == question)
            .unwrap()
            .answer
            .clone()
    };
    assert_eq!(
        answer("color", "How many blue objects are there in the video?"),
        "2"
    );
    assert_eq!(
        answer("color", "How many purple objects are there in the video?"),
        "2"
    );
    assert_eq!(
        answer("shape", "How many solid pulleys are there in the video?"),
        "3"
    );
    // 6 mass entries × (2 pulleys turning + 2 pulleys and 3 loads moving).
    assert_eq!(records(&questions, "rope_counterfactual2").len(), 42);
    for family in [
        "rope_counterfactual",
        "rope_counterfactual2",
        "rope_goaldriven",
    ] {
        for record in records(&questions, family) {
            assert!(!record.question.contains("blue"), "{record:?}");
        }
    }
}

#[test]
fn light_colours_are_exact_in_counts_existence_and_references() {
    // Decisions (b) and (e): a light blue pulley is neither counted as blue nor exists as one,
    // and questions call it "light blue pulley" (the public engine said "blue pulley").
    let value = rename(
        &real_json(),
        "Blue Solid Static Pulley",
        "Light Blue Solid Static Pulley",
    );
    let annotation = annotation(&value);
    let questions = generate(&annotation, 5);
    let answer = |family: &str, question: &str| {
        records(&questions, family)
            .iter()
            .find(|r| r.question == question)
            .unwrap()
            .answer
            .clone()
    };
    assert_eq!(
        answer("color", "How many blue objects are there in the video?"),
        "0"
    );
    assert_eq!(
        answer("existence", "Is there any blue solid pulley in the video?"),
        "no"
    );
    let cf2 = records(&questions, "rope_counterfactual2");
    assert!(
        cf2.iter()
            .any(|r| r.question.contains("would the light blue pulley rotate"))
    );
    for family in [
        "rope_counterfactual",
        "rope_counterfactual2",
        "rope_goaldriven",
    ] {
        for record in records(&questions, family) {
            check_choice_record(&annotation, record);
        }
    }
}

#[test]
fn unreadable_annotations_are_errors_naming_the_object() {
    let video = VideoId("12".into());
    let mut value = real_json();
    value["outputMass"]["Green Cube"] = json!(0.213);
    let error = generate_questions(&video, &annotation(&value), 0).unwrap_err();
    assert_eq!(
        error,
        RopeEngineError::UnexpectedMass {
            video_id: "12".into(),
            load: "Green Cube".into(),
            mass_kg: 0.213,
            nominal_kg: 0.22
        }
    );
    assert!(
        error
            .to_string()
            .starts_with("video `12`: load `Green Cube` has mass 0.213 kg"),
        "{error}"
    );

    let mut value = real_json();
    value["outputMass"]["Brown Fixed Point"] = json!(0.2);
    let error = generate_questions(&video, &annotation(&value), 0).unwrap_err();
    assert_eq!(
        error,
        RopeEngineError::NotALoad {
            video_id: "12".into(),
            name: "Brown Fixed Point".into()
        }
    );

    let value = rename(&real_json(), "Green Rope", "Green Cable");
    let error = generate_questions(&video, &annotation(&value), 0).unwrap_err();
    assert!(
        matches!(&error, RopeEngineError::UnparsableName { name, .. } if name == "Green Cable"),
        "{error}"
    );
}

#[test]
fn objects_missing_from_the_lists_are_skipped_not_fatal() {
    // A counterfactual names a pulley that no rope list mentions, and a group names a load that
    // has no mass: the public engine stopped or crashed; here they are simply not asked about.
    let mut value = real_json();
    value["CounterFactualAnnotations"]["2"]["0"]["ResultRotation"]["Cyan Solid Static Pulley (2 2)"] =
        json!(1);
    value["relatedGroups"][1]
        .as_array_mut()
        .unwrap()
        .push(json!("Orange Cube"));
    let annotation = annotation(&value);
    for seed in 0..20 {
        let questions = generate(&annotation, seed);
        assert_eq!(records(&questions, "rope_counterfactual2").len(), 66);
        let asking_about_objects = [
            "mass",
            "tension",
            "rope_counterfactual",
            "rope_counterfactual2",
            "rope_goaldriven",
        ];
        for record in asking_about_objects
            .iter()
            .flat_map(|family| records(&questions, family))
        {
            assert!(
                !record.question.contains("cyan pulley")
                    && !record.question.contains("orange cube"),
                "{record:?}"
            );
        }
    }
    let scene = RopeScene::from_annotation("0", &annotation).unwrap();
    assert!(
        scene
            .objects()
            .iter()
            .all(|o| o.kind != RopeObjectKind::Pulley || o.color != "cyan")
    );
}

// ---------------------------------------------------------------------------------------------
// Sampler on engine output.

#[test]
fn sampler_splits_engine_output_by_video_with_valid_records() {
    let annotation = annotation(&real_json());
    // (N, videos in train, val, test); N = 90 is where the public float boundary is off by one.
    let cases = [(1, 0, 0, 1), (2, 1, 0, 1), (10, 5, 2, 3), (90, 45, 18, 27)];
    for (video_count, train, val, test) in cases {
        let per_video: Vec<PerVideoQuestions> = (0..video_count)
            .map(|id| generate_questions(&VideoId(id.to_string()), &annotation, 42).unwrap())
            .collect();
        let splits = crate::dataset::engine::sample_and_split(
            Scenario::Rope,
            &per_video,
            &SamplerConfig::default(),
            42,
        );
        let videos = |split: Split| -> BTreeSet<u32> {
            splits
                .get(split)
                .iter()
                .map(|r| r.video_id.as_ref().unwrap().parse().unwrap())
                .collect()
        };
        assert_eq!(
            [
                videos(Split::Train).len(),
                videos(Split::Val).len(),
                videos(Split::Test).len()
            ],
            [train, val, test]
        );
        // Contiguous numeric ranges: train ids, then val ids, then test ids make up 0..N.
        let in_order: Vec<u32> = Split::ALL.into_iter().flat_map(videos).collect();
        assert_eq!(
            in_order,
            (0..u32::try_from(video_count).unwrap()).collect::<Vec<_>>()
        );
        let all: Vec<&QuestionRecord> = splits.all().collect();
        assert_eq!(all.len(), 4 * video_count);
        for (position, record) in all.iter().enumerate() {
            assert_eq!(
                record.question_id.as_deref(),
                Some(format!("{position:05}").as_str())
            );
            let video_id = VideoId(record.video_id.clone().unwrap());
            let question_id = QuestionId(record.question_id.clone().unwrap());
            let question =
                Question::from_record(question_id, video_id, Scenario::Rope, (*record).clone())
                    .unwrap();
            assert_eq!(question.split.map(Split::as_str), record.split.as_deref());
        }
        // Per video: two property questions, then two dynamics questions.
        for chunk in all.chunks(4) {
            let categories: Vec<Category> = chunk
                .iter()
                .map(|r| Family(r.qtype.clone().unwrap()).category())
                .collect();
            assert_eq!(categories[..2], [Category::Property, Category::Property]);
            assert!(categories[2..].iter().all(|c| *c != Category::Property));
        }
    }
}
