//! The scoring arithmetic: counts per scenario × category and per family, for the model and the
//! two baselines, plus failure and coverage counts.

use std::collections::{BTreeMap, HashMap};

use serde::{Deserialize, Serialize};

use super::baseline::family_key;
use super::{EvalQuestion, Prediction, Priors};
use crate::dataset::{Category, Scenario};

/// Integer counts of correct options and questions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Tally {
    /// Questions.
    pub questions: u64,
    /// Questions with every option (or the open answer) correct.
    pub questions_correct: u64,
    /// Options (open-ended questions count one each).
    pub options: u64,
    /// Correct options.
    pub options_correct: u64,
}

/// Expected counts of a random baseline.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ExpectedTally {
    /// Questions.
    pub questions: u64,
    /// Expected number of correct questions.
    pub questions_correct: f64,
    /// Options.
    pub options: u64,
    /// Expected number of correct options.
    pub options_correct: f64,
}

/// Scores of one group of questions: a scenario × category, or one family.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GroupScore {
    /// The scenario.
    pub scenario: Scenario,
    /// The category.
    pub category: Category,
    /// The family, for family rows.
    pub family: Option<String>,
    /// The evaluated model.
    pub model: Tally,
    /// The RND baseline's expectation.
    pub rnd: ExpectedTally,
    /// The FRQ baseline; `None` when a family of the group has no train prior.
    pub frq: Option<Tally>,
    /// Failed units by stage.
    pub failed_units: BTreeMap<String, u64>,
    /// Units with no prediction at all.
    pub missing_units: u64,
}

/// Everything the reports show.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Scores {
    /// Scenario × category rows, in Table-2 order.
    pub categories: Vec<GroupScore>,
    /// Family rows, sorted by scenario, category and family.
    pub families: Vec<GroupScore>,
    /// Units expected from the questions.
    pub units: u64,
    /// Units whose program produced an answer.
    pub units_answered: u64,
    /// Failures by stage, then kind.
    pub failures: BTreeMap<String, BTreeMap<String, u64>>,
    /// Units without a prediction.
    pub missing_units: u64,
    /// Predictions whose unit is not among the questions (ignored).
    pub unknown_units: u64,
    /// Extra predictions for a unit already predicted (the first is used).
    pub duplicate_units: u64,
}

impl Scores {
    /// Units that failed at some stage (units without a prediction are not counted).
    pub fn failed_units(&self) -> u64 {
        self.failures
            .values()
            .flat_map(|kinds| kinds.values())
            .sum()
    }
}

struct Accumulator {
    model: Tally,
    rnd: ExpectedTally,
    frq: Tally,
    frq_complete: bool,
    failed_units: BTreeMap<String, u64>,
    missing_units: u64,
}

impl Default for Accumulator {
    /// Empty; FRQ is complete until a question without a prior is added.
    fn default() -> Self {
        Accumulator {
            model: Tally::default(),
            rnd: ExpectedTally::default(),
            frq: Tally::default(),
            frq_complete: true,
            failed_units: BTreeMap::new(),
            missing_units: 0,
        }
    }
}

impl Accumulator {
    fn finish(self, scenario: Scenario, category: Category, family: Option<String>) -> GroupScore {
        GroupScore {
            scenario,
            category,
            family,
            model: self.model,
            rnd: self.rnd,
            frq: self.frq_complete.then_some(self.frq),
            failed_units: self.failed_units,
            missing_units: self.missing_units,
        }
    }
}

/// One question's contribution.
struct QuestionResult {
    model: Tally,
    rnd: ExpectedTally,
    frq: Option<Tally>,
    failed: Vec<String>,
    missing: u64,
}

fn add(total: &mut Accumulator, result: &QuestionResult) {
    let add_tally = |a: &mut Tally, b: &Tally| {
        a.questions += b.questions;
        a.questions_correct += b.questions_correct;
        a.options += b.options;
        a.options_correct += b.options_correct;
    };
    add_tally(&mut total.model, &result.model);
    total.rnd.questions += result.rnd.questions;
    total.rnd.questions_correct += result.rnd.questions_correct;
    total.rnd.options += result.rnd.options;
    total.rnd.options_correct += result.rnd.options_correct;
    match &result.frq {
        Some(frq) => add_tally(&mut total.frq, frq),
        None => total.frq_complete = false,
    }
    for stage in &result.failed {
        *total.failed_units.entry(stage.clone()).or_insert(0) += 1;
    }
    total.missing_units += result.missing;
}

/// Scores `predictions` against `questions`.
pub fn score(questions: &[EvalQuestion], predictions: &[Prediction], priors: &Priors) -> Scores {
    let (by_unit, duplicate_units) = first_predictions(predictions);
    let mut coverage = Coverage::default();
    let mut categories: BTreeMap<(Scenario, Category), Accumulator> = BTreeMap::new();
    let mut families: BTreeMap<(Scenario, Category, String), Accumulator> = BTreeMap::new();

    // Gold answers per family, for RND's answer spaces.
    let gold_answers = gold_answers(questions);

    for question in questions {
        let key = family_key(question.scenario, &question.family);
        let unit_ids = question.unit_ids();
        coverage.expected_units += unit_ids.len() as u64;
        let unit_predictions: Vec<Option<&Prediction>> = unit_ids
            .iter()
            .map(|id| by_unit.get(id.as_str()).copied())
            .collect();
        let (failed, missing) = coverage.count(&unit_predictions);
        let correct: Vec<bool> = unit_predictions
            .iter()
            .map(|p| p.is_some_and(|p| p.correct && p.error.is_none()))
            .collect();
        let options = unit_ids.len() as u64;
        let options_correct = correct.iter().filter(|c| **c).count() as u64;
        let model = Tally {
            questions: 1,
            questions_correct: u64::from(correct.iter().all(|c| *c)),
            options,
            options_correct,
        };
        let (rnd, frq) = if question.options.is_empty() {
            open_baselines(question, &key, &gold_answers, priors)
        } else {
            option_baselines(question, &key, options, priors)
        };
        let result = QuestionResult {
            model,
            rnd,
            frq,
            failed,
            missing,
        };
        add(
            categories
                .entry((question.scenario, question.category))
                .or_default(),
            &result,
        );
        add(
            families
                .entry((
                    question.scenario,
                    question.category,
                    question.family.clone(),
                ))
                .or_default(),
            &result,
        );
    }
    let known: std::collections::HashSet<String> =
        questions.iter().flat_map(EvalQuestion::unit_ids).collect();
    let unknown_units = by_unit
        .keys()
        .filter(|unit| !known.contains(**unit))
        .count() as u64;
    Scores {
        categories: categories
            .into_iter()
            .map(|((s, c), acc)| acc.finish(s, c, None))
            .collect(),
        families: families
            .into_iter()
            .map(|((s, c, f), acc)| acc.finish(s, c, Some(f)))
            .collect(),
        units: coverage.expected_units,
        units_answered: coverage.units_answered,
        failures: coverage.failures,
        missing_units: coverage.missing_units,
        unknown_units,
        duplicate_units,
    }
}

/// The first prediction of each unit, and how many later ones were duplicates.
fn first_predictions(predictions: &[Prediction]) -> (HashMap<&str, &Prediction>, u64) {
    let mut by_unit: HashMap<&str, &Prediction> = HashMap::with_capacity(predictions.len());
    let mut duplicate_units = 0_u64;
    for prediction in predictions {
        // The first prediction of a unit counts; later ones are reported as duplicates.
        match by_unit.entry(prediction.unit.as_str()) {
            std::collections::hash_map::Entry::Occupied(_) => duplicate_units += 1,
            std::collections::hash_map::Entry::Vacant(slot) => {
                slot.insert(prediction);
            }
        }
    }
    (by_unit, duplicate_units)
}

/// The gold answers of the open-ended questions, per family.
fn gold_answers(questions: &[EvalQuestion]) -> BTreeMap<String, Vec<&str>> {
    let mut gold_answers: BTreeMap<String, Vec<&str>> = BTreeMap::new();
    for question in questions.iter().filter(|q| q.options.is_empty()) {
        gold_answers
            .entry(family_key(question.scenario, &question.family))
            .or_default()
            .push(&question.answer);
    }
    gold_answers
}

/// Unit counts over all questions.
#[derive(Default)]
struct Coverage {
    /// Units the questions ask for.
    expected_units: u64,
    /// Units whose program produced an answer.
    units_answered: u64,
    /// Units without a prediction.
    missing_units: u64,
    /// Failed units by stage, then kind.
    failures: BTreeMap<String, BTreeMap<String, u64>>,
}

impl Coverage {
    /// Counts one question's unit predictions (answered, failed by stage and kind, missing);
    /// returns the stages its units failed at and how many units have no prediction.
    fn count(&mut self, unit_predictions: &[Option<&Prediction>]) -> (Vec<String>, u64) {
        let mut failed = Vec::new();
        let mut missing = 0_u64;
        for prediction in unit_predictions {
            match prediction {
                None => missing += 1,
                Some(p) => match &p.error {
                    Some(error) => {
                        failed.push(error.stage.name().to_string());
                        *self
                            .failures
                            .entry(error.stage.name().to_string())
                            .or_default()
                            .entry(error.kind.clone())
                            .or_insert(0) += 1;
                    }
                    None => self.units_answered += 1,
                },
            }
        }
        self.missing_units += missing;
        (failed, missing)
    }
}

/// The baselines of an open-ended question: RND picks uniformly from its family's answer space,
/// FRQ gives the family's most frequent train answer (`None` without a prior).
fn open_baselines(
    question: &EvalQuestion,
    key: &str,
    gold_answers: &BTreeMap<String, Vec<&str>>,
    priors: &Priors,
) -> (ExpectedTally, Option<Tally>) {
    let evaluated = gold_answers.get(key).into_iter().flatten().copied();
    let space = priors.answer_space(key, evaluated).len().max(1) as f64;
    let rnd = ExpectedTally {
        questions: 1,
        questions_correct: 1.0 / space,
        options: 1,
        options_correct: 1.0 / space,
    };
    let frq = priors.frequent_answer(key).map(|answer| {
        let hit = u64::from(answer == question.answer);
        Tally {
            questions: 1,
            questions_correct: hit,
            options: 1,
            options_correct: hit,
        }
    });
    (rnd, frq)
}

/// The baselines of a question with `options` options: RND guesses each option's truth with
/// probability ½, FRQ answers every option with its family's most frequent train truth (`None`
/// without a prior).
fn option_baselines(
    question: &EvalQuestion,
    key: &str,
    options: u64,
    priors: &Priors,
) -> (ExpectedTally, Option<Tally>) {
    let rnd = ExpectedTally {
        questions: 1,
        questions_correct: 0.5_f64.powi(i32::try_from(options).unwrap_or(i32::MAX)),
        options,
        options_correct: options as f64 / 2.0,
    };
    let frq = priors.frequent_option_truth(key).map(|truth| {
        let hits = question
            .options
            .iter()
            .filter(|o| o.correct == truth)
            .count() as u64;
        Tally {
            questions: 1,
            questions_correct: u64::from(hits == options),
            options,
            options_correct: hits,
        }
    });
    (rnd, frq)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::{AnswerType, ChoiceOption};
    use crate::scene_api::WorkCounters;
    use crate::score::{Stage, UnitError};

    fn open(id: &str, family: &str, answer: &str) -> EvalQuestion {
        EvalQuestion {
            id: id.into(),
            scenario: Scenario::Rope,
            family: family.into(),
            category: Category::Property,
            answer_type: AnswerType::OpenEnded,
            video_id: "0".into(),
            text: String::new(),
            answer: answer.into(),
            options: vec![],
        }
    }

    fn choice(id: &str, truths: &[bool]) -> EvalQuestion {
        let options = truths
            .iter()
            .enumerate()
            .map(|(i, t)| ChoiceOption {
                letter: char::from(b'A' + u8::try_from(i).unwrap()),
                text: format!("o{i}"),
                correct: *t,
            })
            .collect();
        EvalQuestion {
            id: id.into(),
            scenario: Scenario::Rope,
            family: "rope_counterfactual".into(),
            category: Category::Counterfactual,
            answer_type: AnswerType::MultipleChoice,
            video_id: "0".into(),
            text: String::new(),
            answer: String::new(),
            options,
        }
    }

    fn prediction(unit: &str, correct: bool, error: Option<Stage>) -> Prediction {
        Prediction {
            unit: unit.into(),
            question_id: unit.split(':').next().unwrap().into(),
            option: None,
            scenario: Scenario::Rope,
            family: String::new(),
            video_id: "0".into(),
            program_hash: None,
            program_key: None,
            program_origin: None,
            value: None,
            answer: None,
            correct,
            attempts: vec![],
            votes: vec![],
            usage: None,
            error: error.map(|stage| UnitError {
                stage,
                kind: "timeout".into(),
                message: String::new(),
            }),
            work: WorkCounters::default(),
            own_ms: 0,
            api_ms: 0,
            wall_ms: 0,
        }
    }

    #[test]
    fn options_and_questions_are_counted_as_the_paper_defines() {
        let questions = [
            choice("1", &[true, false, false]),
            choice("2", &[true, true]),
            open("3", "mass", "yes"),
        ];
        let predictions = [
            prediction("1:A", true, None),
            prediction("1:B", true, None),
            prediction("1:C", false, None),
            prediction("2:A", true, None),
            prediction("2:B", true, None),
            prediction("3", false, Some(Stage::Sandbox)),
            prediction("9:Z", true, None),
            prediction("2:B", false, None),
        ];
        let scores = score(&questions, &predictions, &Priors::default());
        let counterfactual = &scores.categories[1];
        assert_eq!(counterfactual.category, Category::Counterfactual);
        assert_eq!(
            counterfactual.model,
            Tally {
                questions: 2,
                questions_correct: 1,
                options: 5,
                options_correct: 4
            }
        );
        // RND: 5 options × 1/2; questions (1/2)^3 + (1/2)^2.
        assert!((counterfactual.rnd.options_correct - 2.5).abs() < 1e-12);
        assert!((counterfactual.rnd.questions_correct - 0.375).abs() < 1e-12);
        assert_eq!(counterfactual.frq, None, "no train priors");
        let property = &scores.categories[0];
        assert_eq!(property.model.questions_correct, 0);
        assert_eq!(property.failed_units["sandbox"], 1);
        assert_eq!(scores.failures["sandbox"]["timeout"], 1);
        assert_eq!((scores.units, scores.units_answered), (6, 5));
        assert_eq!(
            (
                scores.unknown_units,
                scores.duplicate_units,
                scores.missing_units
            ),
            (1, 1, 0)
        );
    }

    #[test]
    fn missing_units_count_as_wrong() {
        let questions = [choice("1", &[true, false])];
        let scores = score(
            &questions,
            &[prediction("1:A", true, None)],
            &Priors::default(),
        );
        assert_eq!(
            scores.categories[0].model,
            Tally {
                questions: 1,
                questions_correct: 0,
                options: 2,
                options_correct: 1
            }
        );
        assert_eq!(scores.missing_units, 1);
    }

    #[test]
    fn frq_uses_train_majorities_and_rnd_the_answer_space() {
        let mut priors = Priors::default();
        let mass = priors.families.entry("rope/mass".into()).or_default();
        mass.answers.insert("yes".into(), 3);
        mass.answers.insert("no".into(), 3);
        mass.answers.insert("can not answer".into(), 1);
        let cf = priors
            .families
            .entry("rope/rope_counterfactual".into())
            .or_default();
        cf.option_true = 2;
        cf.option_false = 5;
        let questions = [
            open("1", "mass", "no"),
            open("2", "mass", "yes"),
            choice("3", &[false, false]),
            choice("4", &[true, false]),
        ];
        let scores = score(&questions, &[], &priors);
        let property = &scores.categories[0];
        // Tie between "no" and "yes" at 3: the smaller text, "no", is FRQ's answer.
        assert_eq!(property.frq.unwrap().questions_correct, 1);
        assert!((property.rnd.questions_correct - 2.0 / 3.0).abs() < 1e-12);
        let counterfactual = &scores.categories[1];
        assert_eq!(
            counterfactual.frq.unwrap(),
            Tally {
                questions: 2,
                questions_correct: 1,
                options: 4,
                options_correct: 3
            }
        );
        assert_eq!(scores.missing_units, 6);
    }
}
