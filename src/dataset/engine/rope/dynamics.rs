//! The dynamics families: `rope_counterfactual`, `rope_counterfactual2` and `rope_goaldriven`
//! (`docs/data/rope.md`, counterfactual and goal-driven options), all built from the mass
//! counterfactual records.
//!
//! Each mass counterfactual sub-entry (`"0"` simulated, `"1"` mirrored) says how every pulley
//! turned (`ResultRotation`, +1 clockwise on screen) and how every pulley and load moved
//! (`ResultMotion`, +1 up) after one load got lighter or heavier; "lighter" means
//! `round(Item1, 2) > round(Item2, 2)`. Pull records are ignored, as in the public engine. Shafts
//! and fixed points are never asked about, and neither is an object that cannot be referred to
//! unambiguously (see `scene`). Every option's truth is the sign in those results.

use indexmap::IndexMap;
use rand::Rng;
use rand::seq::{IndexedRandom, SliceRandom};

use super::scene::RopeScene;
use super::templates::{
    COUNTERFACTUAL, COUNTERFACTUAL_DIRECTION, COUNTERFACTUAL_TITLES, GOAL_DRIVEN, GOAL_TITLES,
    MOTION_DIRECTION_TITLES, ROTATION_DIRECTION_TITLES, fill,
};
use crate::dataset::QuestionRecord;
use crate::dataset::engine::record::{DraftOption, choice_record, draw_weighted};
use crate::dataset::rope::{RopeAnnotation, RopeChange, RopeCounterfactual, RopeObjectKind};

/// Probability of adding "would not rotate/move" as an extra false option for a moving object.
const EXTRA_STATIONARY_FALSE_PROBABILITY: f64 = 0.1;
/// Probability of offering "would not move" as a true option for a load or pulley that stays.
/// (A pulley that does not turn always gets "would not rotate" as a true option.)
const STATIONARY_MOTION_TRUE_PROBABILITY: f64 = 0.2;

/// Rotation (pulleys) or vertical motion (pulleys and loads).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Movement {
    Rotation,
    Motion,
}

impl Movement {
    /// The program word: `rotation` or `motion`.
    fn program_word(self) -> &'static str {
        match self {
            Movement::Rotation => "rotation",
            Movement::Motion => "motion",
        }
    }

    /// The direction word of a result sign: `clockwise`/`anti-clockwise` or `up`/`down`, and
    /// `stationary` for 0.
    fn direction(self, sign: i8) -> &'static str {
        match (self, sign.signum()) {
            (_, 0) => "stationary",
            (Movement::Rotation, 1) => "clockwise",
            (Movement::Rotation, _) => "anti-clockwise",
            (Movement::Motion, 1) => "up",
            (Movement::Motion, _) => "down",
        }
    }

    /// "The blue pulley would rotate clockwise", "The pink sphere would not move".
    fn outcome_text(self, reference: &str, sign: i8) -> String {
        match (self, sign) {
            (Movement::Rotation, 0) => format!("The {reference} would not rotate"),
            (Movement::Motion, 0) => format!("The {reference} would not move"),
            (Movement::Rotation, _) => {
                format!("The {reference} would rotate {}", self.direction(sign))
            }
            (Movement::Motion, _) => format!("The {reference} would move {}", self.direction(sign)),
        }
    }

    fn outcome_option(self, reference: &str, sign: i8, correct: bool) -> DraftOption {
        DraftOption {
            text: self.outcome_text(reference, sign),
            program: [
                reference.to_string(),
                self.program_word().to_string(),
                self.direction(sign).to_string(),
            ],
            correct,
        }
    }
}

/// One mass counterfactual sub-entry, resolved against the scene.
struct MassChange<'a> {
    /// The changed load's reference (`purple cube`).
    target: &'a str,
    lighter: bool,
    result: &'a RopeCounterfactual,
}

impl MassChange<'_> {
    /// `lighter` or `heavier`, as in the titles.
    fn change_word(&self) -> &'static str {
        if self.lighter { "lighter" } else { "heavier" }
    }

    /// The question program: `[target, "increase"|"decrease", "mass"]`.
    fn question_program(&self) -> [&str; 3] {
        [
            self.target,
            if self.lighter { "decrease" } else { "increase" },
            "mass",
        ]
    }

    /// The asked-about objects of one result map: `(reference, sign)` in file order, skipping
    /// shafts, fixed points, objects outside the scene and objects without an unambiguous
    /// reference (the public engine stopped in `breakpoint()` on unknown names).
    fn outcomes<'s>(
        &'s self,
        scene: &'s RopeScene,
        movement: Movement,
    ) -> impl Iterator<Item = (&'s str, i8)> {
        let results = match movement {
            Movement::Rotation => &self.result.rotation,
            Movement::Motion => &self.result.motion,
        };
        results.iter().filter_map(move |(name, &sign)| {
            let index = scene.index_of(name)?;
            if scene.object(index)?.kind == RopeObjectKind::FixedPoint {
                return None;
            }
            Some((scene.reference(index)?, sign))
        })
    }
}

/// The mass counterfactual sub-entries in file order whose changed load can be referred to.
fn mass_changes<'a>(scene: &'a RopeScene, annotation: &'a RopeAnnotation) -> Vec<MassChange<'a>> {
    annotation
        .mass_counterfactuals()
        .filter_map(|result| {
            let RopeChange::Mass { target, .. } = &result.change else {
                return None;
            };
            Some(MassChange {
                target: scene.reference_by_name(target)?,
                lighter: result.change.is_lighter()?,
                result,
            })
        })
        .collect()
}

/// `rope_counterfactual`: "If the {load} were much {lighter|heavier}, what would happen?" with
/// 3–5 outcome options, any number of them true.
pub(super) fn counterfactual_questions(
    scene: &RopeScene,
    annotation: &RopeAnnotation,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    let mut records = Vec::new();
    for change in mass_changes(scene, annotation) {
        let template = COUNTERFACTUAL_TITLES
            .choose(rng)
            .copied()
            .unwrap_or(COUNTERFACTUAL_TITLES[0]);
        let title = fill(template, &[change.target, change.change_word()]);
        let mut true_options = Vec::new();
        let mut false_options = Vec::new();
        for (reference, sign) in change.outcomes(scene, Movement::Rotation) {
            let movement = Movement::Rotation;
            if sign == 0 {
                let wrong_direction = if rng.random::<f64>() < 0.5 { 1 } else { -1 };
                false_options.push(movement.outcome_option(reference, wrong_direction, false));
                true_options.push(movement.outcome_option(reference, 0, true));
            } else {
                true_options.push(movement.outcome_option(reference, sign, true));
                false_options.push(movement.outcome_option(reference, -sign, false));
                if rng.random::<f64>() < EXTRA_STATIONARY_FALSE_PROBABILITY {
                    false_options.push(movement.outcome_option(reference, 0, false));
                }
            }
        }
        for (reference, sign) in change.outcomes(scene, Movement::Motion) {
            let movement = Movement::Motion;
            if sign == 0 {
                let wrong_direction = if rng.random::<f64>() < 0.5 { 1 } else { -1 };
                false_options.push(movement.outcome_option(reference, wrong_direction, false));
                if rng.random::<f64>() < STATIONARY_MOTION_TRUE_PROBABILITY {
                    true_options.push(movement.outcome_option(reference, 0, true));
                }
            } else {
                true_options.push(movement.outcome_option(reference, sign, true));
                false_options.push(movement.outcome_option(reference, -sign, false));
                if rng.random::<f64>() < EXTRA_STATIONARY_FALSE_PROBABILITY {
                    false_options.push(movement.outcome_option(reference, 0, false));
                }
            }
        }
        for options in counterfactual_option_sets(true_options, false_options, rng) {
            records.extend(choice_record(
                COUNTERFACTUAL,
                &title,
                change.question_program(),
                &options,
            ));
        }
    }
    records
}

/// Splits one counterfactual's true and false outcomes into option lists (`docs/data/rope.md`,
/// counterfactual and goal-driven options).
///
/// * One true outcome: it plus two random false ones. Bug fix (`docs/data/rope.md`, quirks of the
///   public engine): the public engine built this question's answer on a stale or uninitialised
///   `answer` variable (a crash, or extra/duplicated correct letters); the answer now follows from
///   the options emitted, which carry their own truth.
/// * One false outcome: it plus two random true ones. Bug fix: the public engine labelled every
///   option false here. The branch is unreachable from real data (each asked-about object adds at
///   least one false outcome and at most one true one), but stays correct if that changes.
/// * Otherwise: shuffle both lists and cut the longer to the shorter's length, then repeatedly
///   take one true outcome and 2–4 more, each false with probability |F|/(|F|+|T|). The question
///   that runs out of outcomes is dropped.
fn counterfactual_option_sets(
    mut true_options: Vec<DraftOption>,
    mut false_options: Vec<DraftOption>,
    rng: &mut impl Rng,
) -> Vec<Vec<DraftOption>> {
    if true_options.is_empty() || false_options.is_empty() {
        return Vec::new();
    }
    if true_options.len() == 1 || false_options.len() == 1 {
        let (single, others) = if true_options.len() == 1 {
            (true_options, false_options)
        } else {
            (false_options, true_options)
        };
        // The public engine raised `ValueError` when fewer than two others existed; skip instead.
        let picked: Vec<DraftOption> = others.choose_multiple(rng, 2).cloned().collect();
        if picked.len() < 2 {
            return Vec::new();
        }
        let mut options: Vec<DraftOption> = single.into_iter().chain(picked).collect();
        options.shuffle(rng);
        return vec![options];
    }
    true_options.shuffle(rng);
    false_options.shuffle(rng);
    let balanced = true_options.len().min(false_options.len());
    true_options.truncate(balanced);
    false_options.truncate(balanced);
    let mut option_sets = Vec::new();
    while let Some(first) = true_options.pop() {
        let mut options = vec![first];
        for _ in 0..rng.random_range(2..=4) {
            let Some(next) = draw_weighted(&mut true_options, &mut false_options, rng) else {
                // Out of outcomes: this partial question is dropped and the loop ends.
                return option_sets;
            };
            options.push(next);
        }
        options.shuffle(rng);
        option_sets.push(options);
    }
    option_sets
}

/// `rope_counterfactual2`: "If the {load} were much {…}, which direction would the {x}
/// rotate|move?" for every pulley (rotation) and every pulley or load (motion), three shuffled
/// options with exactly one true. The template orientation is drawn once per sub-entry and block.
pub(super) fn counterfactual_direction_questions(
    scene: &RopeScene,
    annotation: &RopeAnnotation,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    let mut records = Vec::new();
    for change in mass_changes(scene, annotation) {
        let blocks = [
            (
                Movement::Rotation,
                ROTATION_DIRECTION_TITLES,
                [("Clockwise", 1), ("Anti-clockwise", -1), ("Stationary", 0)],
            ),
            (
                Movement::Motion,
                MOTION_DIRECTION_TITLES,
                [("Down", -1), ("Up", 1), ("Stationary", 0)],
            ),
        ];
        for (movement, titles, answers) in blocks {
            let template = titles.choose(rng).copied().unwrap_or(titles[0]);
            for (reference, sign) in change.outcomes(scene, movement) {
                let title = fill(template, &[change.target, change.change_word(), reference]);
                let mut options: Vec<DraftOption> = answers
                    .iter()
                    .map(|&(text, answer_sign)| DraftOption {
                        text: text.to_string(),
                        program: [
                            reference.to_string(),
                            movement.program_word().to_string(),
                            movement.direction(answer_sign).to_string(),
                        ],
                        correct: answer_sign == sign,
                    })
                    .collect();
                // The public engine shuffled only this family's options after generation and
                // remapped the program's choice letters; each option carries its program here.
                options.shuffle(rng);
                records.extend(choice_record(
                    COUNTERFACTUAL_DIRECTION,
                    &title,
                    change.question_program(),
                    &options,
                ));
            }
        }
    }
    records
}

/// A mass change that can be proposed in a goal-driven option.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Lever<'a> {
    /// `true` for "Increase", `false` for "Decrease".
    increase: bool,
    /// The load's reference.
    target: &'a str,
}

impl Lever<'_> {
    fn option(self, correct: bool) -> DraftOption {
        let (change, program_change) = if self.increase {
            ("Increase", "increase")
        } else {
            ("Decrease", "decrease")
        };
        DraftOption {
            text: format!("{change} the mass of the {}", self.target),
            program: [
                self.target.to_string(),
                program_change.to_string(),
                "mass".to_string(),
            ],
            correct,
        }
    }
}

/// The levers that made one object go up/clockwise, down/anti-clockwise, or stay.
#[derive(Debug, Default)]
struct GoalOutcomes<'a> {
    positive: Vec<Lever<'a>>,
    negative: Vec<Lever<'a>>,
    stationary: Vec<Lever<'a>>,
}

impl<'a> GoalOutcomes<'a> {
    fn add(&mut self, sign: i8, lever: Lever<'a>) {
        match sign.signum() {
            1 => self.positive.push(lever),
            -1 => self.negative.push(lever),
            _ => self.stationary.push(lever),
        }
    }

    fn with_sign(&self, sign: i8) -> &[Lever<'a>] {
        if sign > 0 {
            &self.positive
        } else {
            &self.negative
        }
    }
}

/// `rope_goaldriven`: "If we want the {x} to {move up|…}, what can we do?" with options
/// "{Increase|Decrease} the mass of the {load}", for every pulley (rotation) and every pulley or
/// load (motion) that some mass change moves.
pub(super) fn goal_driven_questions(
    scene: &RopeScene,
    annotation: &RopeAnnotation,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    let changes = mass_changes(scene, annotation);
    let mut records = Vec::new();
    for movement in [Movement::Rotation, Movement::Motion] {
        // Keyed by reference, in first-appearance order over all sub-entries.
        let mut goals: IndexMap<&str, GoalOutcomes<'_>> = IndexMap::new();
        for change in &changes {
            let lever = Lever {
                increase: !change.lighter,
                target: change.target,
            };
            for (reference, sign) in change.outcomes(scene, movement) {
                goals.entry(reference).or_default().add(sign, lever);
            }
        }
        for (reference, outcomes) in &goals {
            let mut sign: i8 = if rng.random_range(0..=1) == 1 { 1 } else { -1 };
            if outcomes.positive.is_empty() && outcomes.negative.is_empty() {
                continue;
            }
            if outcomes.with_sign(sign).is_empty() {
                sign = -sign;
            }
            let direction = movement.direction(sign);
            let goal = match movement {
                Movement::Rotation => format!("rotate {direction}"),
                Movement::Motion => format!("move {direction}"),
            };
            let template = GOAL_TITLES.choose(rng).copied().unwrap_or(GOAL_TITLES[0]);
            let title = fill(template, &[reference, &goal]);
            let mut true_options: Vec<DraftOption> = outcomes
                .with_sign(sign)
                .iter()
                .map(|lever| lever.option(true))
                .collect();
            let mut false_options: Vec<DraftOption> = outcomes
                .with_sign(-sign)
                .iter()
                .chain(&outcomes.stationary)
                .map(|lever| lever.option(false))
                .collect();
            if true_options.is_empty() || false_options.is_empty() {
                continue;
            }
            true_options.shuffle(rng);
            false_options.shuffle(rng);
            let Some(options) = goal_option_set(true_options, false_options, rng) else {
                continue;
            };
            records.extend(choice_record(
                GOAL_DRIVEN,
                &title,
                [reference, movement.program_word(), direction],
                &options,
            ));
        }
    }
    records
}

/// The options of one goal-driven question from shuffled true and false levers
/// (`docs/data/rope.md`, counterfactual and goal-driven options): one true lever plus two false
/// ones when only one is true (`None` if fewer than two false exist); otherwise one true lever plus
/// 2–4 more drawn in proportion to the pools, or all of them when no more remain.
fn goal_option_set(
    mut true_options: Vec<DraftOption>,
    mut false_options: Vec<DraftOption>,
    rng: &mut impl Rng,
) -> Option<Vec<DraftOption>> {
    let first = true_options.pop()?;
    let mut options = vec![first];
    if true_options.is_empty() {
        options.push(false_options.pop()?);
        options.push(false_options.pop()?);
    } else {
        let extra = rng.random_range(2..=4);
        if true_options.len() + false_options.len() <= extra {
            options.append(&mut true_options);
            options.append(&mut false_options);
        } else {
            for _ in 0..extra {
                options.extend(draw_weighted(&mut true_options, &mut false_options, rng));
            }
        }
    }
    options.shuffle(rng);
    Some(options)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::util::seeded_rng;

    fn options(prefix: &str, count: usize, correct: bool) -> Vec<DraftOption> {
        (0..count)
            .map(|index| DraftOption {
                text: format!("{prefix}{index}"),
                program: [format!("{prefix}{index}"), "motion".into(), "up".into()],
                correct,
            })
            .collect()
    }

    #[test]
    fn counterfactual_option_sets_keep_each_option_truth() {
        // (true count, false count, expected question count or None for "any")
        let cases = [
            (1, 3, Some(1)),
            (3, 1, Some(1)),
            (1, 1, Some(0)),
            (0, 4, Some(0)),
            (6, 9, None),
        ];
        for seed in 0..50 {
            for (true_count, false_count, expected) in cases {
                let mut rng = seeded_rng(seed);
                let sets = counterfactual_option_sets(
                    options("t", true_count, true),
                    options("f", false_count, false),
                    &mut rng,
                );
                if let Some(expected) = expected {
                    assert_eq!(
                        sets.len(),
                        expected,
                        "{true_count}/{false_count} seed {seed}"
                    );
                }
                for set in &sets {
                    assert!((3..=5).contains(&set.len()), "{set:?}");
                    assert!(set.iter().any(|o| o.correct), "{set:?}");
                    for option in set {
                        assert_eq!(option.correct, option.text.starts_with('t'), "{option:?}");
                    }
                }
                if (true_count, false_count) == (1, 3) {
                    assert_eq!(sets[0].iter().filter(|o| o.correct).count(), 1);
                }
                if (true_count, false_count) == (3, 1) {
                    assert_eq!(sets[0].iter().filter(|o| !o.correct).count(), 1);
                }
            }
        }
    }

    #[test]
    fn goal_option_sets_follow_the_pool_sizes() {
        for seed in 0..50 {
            let mut rng = seeded_rng(seed);
            let single =
                goal_option_set(options("t", 1, true), options("f", 3, false), &mut rng).unwrap();
            assert_eq!(
                (single.len(), single.iter().filter(|o| o.correct).count()),
                (3, 1)
            );
            assert!(
                goal_option_set(options("t", 1, true), options("f", 1, false), &mut rng).is_none()
            );
            let all =
                goal_option_set(options("t", 2, true), options("f", 1, false), &mut rng).unwrap();
            assert_eq!(all.len(), 3);
            let drawn =
                goal_option_set(options("t", 2, true), options("f", 4, false), &mut rng).unwrap();
            assert!((3..=5).contains(&drawn.len()));
        }
    }
}
