//! The predictive families: `cloth_predictive_fall`, `cloth_predictive_collision`,
//! `cloth_predictive_touch` and `cloth_predictive_pose`. The cloth hides the boxes, so each asks
//! what happened under it; truth comes from the boxes' records in `objectFullAnnotation`.
//!
//! * Fall over: a box has fallen over when it ends `Supine`, `Swooping` or `Other`, and stayed up
//!   when it ends `Upright` (`Pose::fell_over`); a box that ends `Reclining` (leaning, from just
//!   off vertical to resting on a neighbour) is not asked about.
//! * Collision and touch: asked of every unordered pair of boxes in one half, the box named first
//!   a coin flip. Two boxes collide when either's `collisionEvents` names the other, and are
//!   finally in touch when either's `touchers` does (`ClothAnnotation::collided`, `in_touch`).
//!   The cloth is not asked about: the templates' `_OBJ_` is a plate or a pillar.
//! * Pose: every box; the options are the five pose phrases (`Pose::phrase`), one true, in
//!   random order.
//!
//! **Balance.** Within a video, each family asks about as many boxes (or pairs) of each answer as
//! the rarest answer it has: for the yes / no families as many "yes" as "no", for the pose family
//! as many of each end pose present; which ones is drawn at random. A family whose boxes all share
//! one answer in a video is not asked there. So every family's answers are balanced over any set
//! of videos, whatever the solver's rates of falling and colliding, and a question's answer
//! cannot be guessed from how often it is true elsewhere. The yes / no questions offer `Yes` and
//! `No`, in that order, as the ball engine's predictive questions.

use std::collections::BTreeMap;

use rand::Rng;
use rand::seq::SliceRandom;

use super::scene::{BoxReference, ClothScene};
use super::templates::{
    COLLISION_TITLE, FALL_TITLE, NO, POSE_TITLE, PREDICTIVE_COLLISION, PREDICTIVE_FALL,
    PREDICTIVE_POSE, PREDICTIVE_TOUCH, TOUCH_TITLE, YES, fill,
};
use crate::dataset::QuestionRecord;
use crate::dataset::cloth::ClothAnnotation;
use crate::dataset::cloth::outcome::Pose;
use crate::dataset::engine::record::{DraftOption, choice_record};

/// The program verb of falling over.
const FALL_OVER: &str = "fall over";
/// The program verb of not falling over.
const NOT_FALL_OVER: &str = "not fall over";
/// The program verb of colliding.
const COLLIDE: &str = "collide";
/// The program verb of not colliding.
const NOT_COLLIDE: &str = "not collide";
/// The program verb of being in touch at the end.
const TOUCH: &str = "touch";
/// The program verb of not being in touch at the end.
const NOT_TOUCH: &str = "not touch";
/// The program verb of ending in a pose.
const POSE: &str = "pose";

fn option(text: &str, program: [&str; 3], correct: bool) -> DraftOption {
    DraftOption {
        text: text.to_string(),
        program: program.map(str::to_string),
        correct,
    }
}

/// The candidates to ask, in their given order: of each answer as many as the rarest answer has,
/// drawn at random; none when fewer than two answers occur (see the module's balance rule).
fn balanced<T, A: Ord + Copy>(candidates: Vec<(T, A)>, rng: &mut impl Rng) -> Vec<(T, A)> {
    let mut by_answer: BTreeMap<A, Vec<usize>> = BTreeMap::new();
    for (index, (_, answer)) in candidates.iter().enumerate() {
        by_answer.entry(*answer).or_default().push(index);
    }
    if by_answer.len() < 2 {
        return Vec::new();
    }
    let keep = by_answer.values().map(Vec::len).min().unwrap_or(0);
    let mut kept: Vec<usize> = by_answer
        .into_values()
        .flat_map(|mut indices| {
            indices.shuffle(rng);
            indices.truncate(keep);
            indices
        })
        .collect();
    kept.sort_unstable();
    candidates
        .into_iter()
        .enumerate()
        .filter(|(index, _)| kept.binary_search(index).is_ok())
        .map(|(_, candidate)| candidate)
        .collect()
}

/// A yes / no question about `subject` (and `object`, the program's third slot): options `Yes`
/// (program `[subject, verb, object]`) and `No` (`[subject, negated, object]`).
fn yes_no_record(
    family: &str,
    title: &str,
    [subject, verb, negated, object]: [&str; 4],
    holds: bool,
) -> Option<QuestionRecord> {
    choice_record(
        family,
        title,
        [subject, verb, object],
        &[
            option(YES, [subject, verb, object], holds),
            option(NO, [subject, negated, object], !holds),
        ],
    )
}

/// `cloth_predictive_fall`: "Does the {box} fall over?" Question program `[box, "fall over",
/// ""]`; options `Yes` (the same) and `No` (`[box, "not fall over", ""]`).
pub(super) fn fall_questions(scene: &ClothScene<'_>, rng: &mut impl Rng) -> Vec<QuestionRecord> {
    let candidates: Vec<(&BoxReference<'_>, bool)> = scene
        .boxes
        .iter()
        .filter_map(|reference| Some((reference, reference.pose().fell_over()?)))
        .collect();
    balanced(candidates, rng)
        .into_iter()
        .filter_map(|(reference, fell)| {
            let word = reference.reference.word.as_str();
            yes_no_record(
                PREDICTIVE_FALL,
                &fill(FALL_TITLE, &[word]),
                [word, FALL_OVER, NOT_FALL_OVER, ""],
                fell,
            )
        })
        .collect()
}

/// The pair questions of one family: every pair of the half, named in a random order, with
/// `holds` its truth.
fn pair_questions(
    scene: &ClothScene<'_>,
    family: &str,
    title: &str,
    [verb, negated]: [&str; 2],
    holds: impl Fn(&str, &str) -> bool,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    let candidates: Vec<((&BoxReference<'_>, &BoxReference<'_>), bool)> = scene
        .pairs()
        .into_iter()
        .map(|(first, second)| {
            let truth = holds(first.reference.name, second.reference.name);
            ((first, second), truth)
        })
        .collect();
    let mut records = Vec::new();
    for ((first, second), truth) in balanced(candidates, rng) {
        let (first, second) = if rng.random_bool(0.5) {
            (first, second)
        } else {
            (second, first)
        };
        let (a, b) = (
            first.reference.word.as_str(),
            second.reference.word.as_str(),
        );
        records.extend(yes_no_record(
            family,
            &fill(title, &[a, b]),
            [a, verb, negated, b],
            truth,
        ));
    }
    records
}

/// `cloth_predictive_collision`: "Does the {box} collide with the {box}?" Question program
/// `[box, "collide", other box]`; options `Yes` (the same) and `No` (`"not collide"`).
pub(super) fn collision_questions(
    scene: &ClothScene<'_>,
    annotation: &ClothAnnotation,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    pair_questions(
        scene,
        PREDICTIVE_COLLISION,
        COLLISION_TITLE,
        [COLLIDE, NOT_COLLIDE],
        |first, second| annotation.collided(first, second),
        rng,
    )
}

/// `cloth_predictive_touch`: "Is the {box} finally in touch with the {box}?" Question program
/// `[box, "touch", other box]`; options `Yes` (the same) and `No` (`"not touch"`).
pub(super) fn touch_questions(
    scene: &ClothScene<'_>,
    annotation: &ClothAnnotation,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    pair_questions(
        scene,
        PREDICTIVE_TOUCH,
        TOUCH_TITLE,
        [TOUCH, NOT_TOUCH],
        |first, second| annotation.in_touch(first, second),
        rng,
    )
}

/// `cloth_predictive_pose`: "Which phrase below can best describe the final pose of the {box}?"
/// with the five pose phrases in random order, the box's end pose true. Question program `[box,
/// "pose", ""]`; option programs `[box, "pose", label]`, the release's label (`Upright`).
pub(super) fn pose_questions(scene: &ClothScene<'_>, rng: &mut impl Rng) -> Vec<QuestionRecord> {
    let candidates: Vec<(&BoxReference<'_>, Pose)> = scene
        .boxes
        .iter()
        .map(|reference| (reference, reference.pose()))
        .collect();
    let mut records = Vec::new();
    for (reference, pose) in balanced(candidates, rng) {
        let word = reference.reference.word.as_str();
        let mut options: Vec<DraftOption> = Pose::ALL
            .into_iter()
            .map(|option_pose| {
                option(
                    option_pose.phrase(),
                    [word, POSE, option_pose.as_str()],
                    option_pose == pose,
                )
            })
            .collect();
        options.shuffle(rng);
        records.extend(choice_record(
            PREDICTIVE_POSE,
            &fill(POSE_TITLE, &[word]),
            [word, POSE, ""],
            &options,
        ));
    }
    records
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::util::seeded_rng;

    #[test]
    fn balance_keeps_as_many_of_each_answer_as_the_rarest_has() {
        let candidates: Vec<(u32, bool)> = vec![
            (0, false),
            (1, true),
            (2, false),
            (3, false),
            (4, true),
            (5, false),
        ];
        for seed in 0..20 {
            let kept = balanced(candidates.clone(), &mut seeded_rng(seed));
            assert_eq!(kept.len(), 4, "{kept:?}");
            assert_eq!(kept.iter().filter(|(_, yes)| *yes).count(), 2);
            // Both "yes" candidates are always kept, in their order.
            assert!(kept.windows(2).all(|pair| pair[0].0 < pair[1].0));
            assert!(kept.contains(&(1, true)) && kept.contains(&(4, true)));
        }
        let one_answer = vec![(0, true), (1, true)];
        assert!(balanced(one_answer, &mut seeded_rng(0)).is_empty());
        let none: Vec<(u32, bool)> = Vec::new();
        assert!(balanced(none, &mut seeded_rng(0)).is_empty());
    }
}
