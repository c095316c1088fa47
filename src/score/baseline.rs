//! Baseline priors: per family, how often each answer (property questions) and each option truth
//! (choice questions) occurs in the train split, as the public `tools/sampler.py` baselines use.
//!
//! * FRQ predicts the family's most frequent train answer (ties: the smallest answer text) and,
//!   per option, the family's more frequent option truth (ties: false). A family absent from the
//!   train split has no FRQ prediction; its cells show "—".
//! * RND is reported as its exact expectation instead of one random draw: a property question is
//!   right with probability 1/|answers of its family| (train answers ∪ evaluated gold answers, the
//!   "possible answers"); an option with probability 1/2; a question with k options 1/2^k.

use std::collections::{BTreeMap, BTreeSet};

use serde::{Deserialize, Serialize};

use crate::dataset::Question;

/// Answer statistics of one family.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct FamilyPrior {
    /// Open-ended answer → count.
    pub answers: BTreeMap<String, u64>,
    /// Choice options whose gold truth is true.
    pub option_true: u64,
    /// Choice options whose gold truth is false.
    pub option_false: u64,
}

/// Per-family priors (keys: `<scenario>/<family>`).
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Priors {
    /// The number of train questions the priors were built from.
    pub train_questions: u64,
    /// Per family.
    pub families: BTreeMap<String, FamilyPrior>,
}

/// The key of a family in [`Priors::families`].
pub(crate) fn family_key(scenario: crate::dataset::Scenario, family: &str) -> String {
    format!("{scenario}/{family}")
}

impl Priors {
    /// Counts answers and option truths of `train` questions.
    pub fn from_train(train: &[Question]) -> Priors {
        let mut families: BTreeMap<String, FamilyPrior> = BTreeMap::new();
        for question in train {
            let prior = families
                .entry(family_key(question.scenario, &question.family.0))
                .or_default();
            if question.options.is_empty() {
                *prior.answers.entry(question.answer.clone()).or_insert(0) += 1;
            } else {
                for option in &question.options {
                    if option.correct {
                        prior.option_true += 1;
                    } else {
                        prior.option_false += 1;
                    }
                }
            }
        }
        Priors {
            train_questions: train.len() as u64,
            families,
        }
    }

    /// FRQ's answer for an open-ended question of `family`.
    pub fn frequent_answer(&self, family_key: &str) -> Option<&str> {
        let prior = self.families.get(family_key)?;
        // Highest count; among equal counts the smallest text (BTreeMap order), so ties are stable.
        let mut best: Option<(&String, u64)> = None;
        for (answer, count) in &prior.answers {
            if best.is_none_or(|(_, best_count)| *count > best_count) {
                best = Some((answer, *count));
            }
        }
        best.map(|(answer, _)| answer.as_str())
    }

    /// FRQ's truth for any option of `family`.
    pub fn frequent_option_truth(&self, family_key: &str) -> Option<bool> {
        let prior = self.families.get(family_key)?;
        (prior.option_true + prior.option_false > 0)
            .then_some(prior.option_true > prior.option_false)
    }

    /// The possible answers of an open-ended family: train answers plus `evaluated` gold answers;
    /// a family answered `yes` or `no` can always be answered either way, even when the
    /// questions at hand all have the same answer (a small run: RND would otherwise score 100%).
    pub(crate) fn answer_space<'a>(
        &'a self,
        family_key: &str,
        evaluated: impl Iterator<Item = &'a str>,
    ) -> BTreeSet<&'a str> {
        let mut space: BTreeSet<&str> = evaluated.collect();
        if let Some(prior) = self.families.get(family_key) {
            space.extend(prior.answers.keys().map(String::as_str));
        }
        if space.contains("yes") || space.contains("no") {
            space.extend(["yes", "no"]);
        }
        space
    }
}
