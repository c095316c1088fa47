//! The site's files from a hand-made run: the leaderboard's numbers, the unit index, chunking,
//! missing units, program texts and escaping.

use serde_json::Value;

use super::*;
use crate::dataset::{AnswerType, ChoiceOption};
use crate::scene_api::WorkCounters;
use crate::score::{Priors, Stage, UnitError, score};

fn question(
    id: &str,
    family: &str,
    category: Category,
    options: Vec<ChoiceOption>,
) -> EvalQuestion {
    EvalQuestion {
        id: id.into(),
        scenario: Scenario::Rope,
        family: family.into(),
        category,
        answer_type: if options.is_empty() {
            AnswerType::OpenEnded
        } else {
            AnswerType::MultipleChoice
        },
        video_id: "0".into(),
        text: format!("Question {id} <b>?</b>"),
        answer: if options.is_empty() {
            "yes".into()
        } else {
            "A".into()
        },
        options,
    }
}

fn prediction(
    unit: &str,
    question: &EvalQuestion,
    correct: bool,
    error: Option<UnitError>,
) -> Prediction {
    Prediction {
        unit: unit.into(),
        question_id: question.id.clone(),
        option: unit
            .split_once(':')
            .and_then(|(_, letter)| letter.chars().next()),
        scenario: question.scenario,
        family: question.family.clone(),
        video_id: question.video_id.clone(),
        program_hash: Some(format!("hash-{unit}")),
        program_key: Some(format!("key-{unit}")),
        program_origin: Some("builtin".into()),
        value: Some(Value::String("yes".into())),
        answer: Some("yes".into()),
        correct,
        error,
        attempts: Vec::new(),
        votes: Vec::new(),
        usage: None,
        work: WorkCounters {
            api_calls: 3,
            frames_decoded: 2,
            ..WorkCounters::default()
        },
        own_ms: 1,
        api_ms: 2,
        wall_ms: 3,
    }
}

/// A rope run: a property question answered right, and a counterfactual question with two
/// options, A right and B failed in the sandbox.
pub(crate) fn fixture_run() -> (Vec<EvalQuestion>, Vec<Prediction>) {
    let property = question("0/mass/0", "mass", Category::Property, Vec::new());
    let options = vec![
        ChoiceOption {
            letter: 'A',
            text: "The load moves up".into(),
            correct: true,
        },
        ChoiceOption {
            letter: 'B',
            text: "The pulley turns".into(),
            correct: false,
        },
    ];
    let counterfactual = question(
        "0/counterfactual/0",
        "counterfactual",
        Category::Counterfactual,
        options,
    );
    let failure = UnitError {
        stage: Stage::Sandbox,
        kind: "NameError".into(),
        message: "name 'x' is not defined".into(),
    };
    let predictions = vec![
        prediction("0/mass/0", &property, true, None),
        prediction("0/counterfactual/0:A", &counterfactual, true, None),
        prediction(
            "0/counterfactual/0:B",
            &counterfactual,
            false,
            Some(failure),
        ),
    ];
    (vec![property, counterfactual], predictions)
}

fn file<'a>(files: &'a [SiteFile], path: &str) -> &'a str {
    let found = files.iter().find(|file| file.path == path);
    std::str::from_utf8(&found.unwrap_or_else(|| panic!("no {path}")).bytes).unwrap()
}

/// The JSON argument of a `units.js` or chunk file.
fn script_json(text: &str) -> Value {
    let start = text.find(['{', '[']).unwrap();
    let end = text.rfind([']', '}']).unwrap();
    serde_json::from_str(&text[start..=end]).unwrap()
}

#[test]
fn the_site_lists_every_unit_with_its_stage_and_the_programs_text() {
    let (mut questions, predictions) = fixture_run();
    // A question without a prediction: listed, wrong, under the `missing` stage.
    questions.push(question("1/mass/0", "mass", Category::Property, Vec::new()));
    let scores = score(&questions, &predictions, &Priors::default());
    let run = SiteRun {
        name: "run <1>".into(),
        facts: vec![("program source".into(), "builtin".into())],
        scores: &scores,
        questions: &questions,
        predictions: &predictions,
        plots: Vec::new(),
        frames: BTreeMap::new(),
    };
    let programs = |key: &str| {
        (key == "key-0/counterfactual/0:B").then(|| ProgramText {
            source: "builtin".into(),
            program: "x </script> & y".into(),
            completion: None,
        })
    };
    let files = build_site(&[run], &programs, &["a note".into()]);
    let paths: Vec<&str> = files.iter().map(|file| file.path.as_str()).collect();
    assert_eq!(
        paths,
        [
            "assets/viewer.js",
            "assets/style.css",
            SITE_MARKER,
            "index.html",
            "runs/1/index.html",
            "runs/1/units.js",
            "runs/1/units/0.js"
        ]
    );
    let index = script_json(file(&files, "runs/1/units.js"));
    assert_eq!(
        index["units"],
        serde_json::json!([
            ["0/mass/0", 0, 0, 1, -1],
            ["0/counterfactual/0:A", 0, 1, 1, -1],
            ["0/counterfactual/0:B", 0, 1, 0, 0],
            ["1/mass/0", 0, 0, 0, 1]
        ])
    );
    assert_eq!(index["stages"], serde_json::json!(["sandbox", "missing"]));
    assert_eq!(
        index["families"],
        serde_json::json!(["rope/mass", "rope/counterfactual"])
    );
    let details = script_json(file(&files, "runs/1/units/0.js"));
    assert_eq!(details[2]["program"]["text"], "x </script> & y");
    assert_eq!(details[2]["error"]["kind"], "NameError");
    assert_eq!(details[2]["truth"], "no");
    assert_eq!(details[1]["program"], Value::Null);
    assert_eq!(details[3]["error"]["stage"], "missing");
    // The leaderboard: the run's name escaped, Prop. 1 of 2 right, C-Ques. none, the paper's
    // ContPRO and human rows for rope.
    let leaderboard = file(&files, "index.html");
    assert!(leaderboard.contains("run &lt;1&gt;"));
    assert!(leaderboard.contains(
        "<tr><td>Rope</td><td>Prop.</td><td>50.0</td><td>—</td><td class=\"model\">50.0</td><td>71.4</td><td>84.7</td></tr>"
    ), "{leaderboard}");
    assert!(leaderboard.contains("<td>C-Ques.</td><td>25.0</td><td>—</td><td class=\"model\">0.0</td><td>48.8</td><td>75.0</td>"));
    assert!(leaderboard.contains("<li>a note</li>"));
    let page = file(&files, "runs/1/index.html");
    assert!(page.contains("<dt>program source</dt><dd>builtin</dd>"));
    assert!(
        !page.contains("<b>?</b>"),
        "question text is only in the data files"
    );
}

#[test]
fn details_come_in_chunks_of_a_fixed_size() {
    let questions: Vec<EvalQuestion> = (0..=CHUNK_UNITS * 2)
        .map(|index| {
            question(
                &format!("{index}/mass/0"),
                "mass",
                Category::Property,
                Vec::new(),
            )
        })
        .collect();
    let scores = score(&questions, &[], &Priors::default());
    let run = SiteRun {
        name: "big".into(),
        facts: Vec::new(),
        scores: &scores,
        questions: &questions,
        predictions: &[],
        plots: Vec::new(),
        frames: BTreeMap::new(),
    };
    let files = build_site(&[run], &|_| None, &[]);
    let chunks: Vec<usize> = (0..3)
        .map(|chunk| {
            script_json(file(&files, &format!("runs/1/units/{chunk}.js")))
                .as_array()
                .unwrap()
                .len()
        })
        .collect();
    assert_eq!(chunks, [CHUNK_UNITS, CHUNK_UNITS, 1]);
    assert!(!files.iter().any(|file| file.path == "runs/1/units/3.js"));
    let last = script_json(file(&files, "runs/1/units/2.js"));
    assert_eq!(last[0]["unit"], format!("{}/mass/0", CHUNK_UNITS * 2));
    assert!(file(&files, "runs/1/units/2.js").starts_with("window.contphyChunk(2, "));
}

#[test]
fn html_escaping_covers_markup_and_quotes() {
    assert_eq!(
        escape_html("<a href=\"x\">'&'</a>"),
        "&lt;a href=&quot;x&quot;&gt;&#39;&amp;&#39;&lt;/a&gt;"
    );
}
