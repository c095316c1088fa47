//! The dynamics families: predictive (`ball_predictive_drop`), counterfactual
//! (`ball_counterfactual_remove`) and goal-driven (`ball_goaldriven_drop`).
//!
//! Truth comes from the runs' pit results: the factual run's for predictive questions, the run
//! without one floating wall and with the ball alone for the others.
//!
//! * Predictive questions ask about balls the video does not show dropping (a result "to
//!   Predict", or no pit): what is seen is not a prediction. A ball that drops later is asked
//!   about both pits (one "yes", one "no"); a ball that drops nowhere about one pit, with
//!   probability [`NO_PIT_PROBABILITY`] ("no"). On 100 generated videos a coin flip per ball gave
//!   29% "yes" (55 of 132 balls drop nowhere); this gives 45%. Options `Yes` and `No`.
//! * Counterfactual questions have three options, `The left pit`, `The right pit` and
//!   `Neither pit`, exactly one true, in random order.
//! * Goal-driven questions offer each floating wall's removal; one is asked only when one
//!   removal makes the ball drop into the pit and another does not (so an option set always
//!   holds a true and a false option, as in the other engines).

use rand::Rng;
use rand::seq::SliceRandom;

use super::scene::BallScene;
use super::templates::{
    COUNTERFACTUAL_REMOVE, COUNTERFACTUAL_REMOVE_TITLE, GOAL_DRIVEN_DROP, GOAL_DRIVEN_DROP_TITLE,
    NO, NO_PIT, PREDICTIVE_DROP, PREDICTIVE_DROP_TITLE, YES, fill, pit_option, removal_option,
};
use crate::dataset::QuestionRecord;
use crate::dataset::ball::BallAnnotation;
use crate::dataset::ball::outcome::{Pit, PitResult};
use crate::dataset::engine::record::{DraftOption, choice_record};

/// The program verb of dropping into a pit.
const DROP: &str = "drop";
/// The program verb of not dropping into it.
const NOT_DROP: &str = "not drop";
/// The program verb of removing a floating wall (and the other balls).
const REMOVE: &str = "remove";
/// The program object of no pit.
const NO_PIT_PROGRAM: &str = "no pit";
/// Probability that a ball dropping into no pit gets a predictive question (always "no"), so
/// that "yes" and "no" come out near even.
const NO_PIT_PROBABILITY: f64 = 0.3;

fn option(text: String, program: [&str; 3], correct: bool) -> DraftOption {
    DraftOption {
        text,
        program: program.map(str::to_string),
        correct,
    }
}

/// `ball_predictive_drop`: "Will the {c} ball finally drop into the {left|right} pit?" about
/// the balls the video does not show dropping. Question program `[ball, "drop", "left pit"]`; option
/// programs the same for `Yes`, `[ball, "not drop", "left pit"]` for `No`.
pub(super) fn predictive_questions(
    scene: &BallScene<'_>,
    annotation: &BallAnnotation,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    let mut records = Vec::new();
    for ball in &scene.balls {
        let Some(record) = annotation.tracking.get(ball.reference.name) else {
            continue;
        };
        let asked: Vec<(Pit, bool)> = match record.result {
            PitResult::Observed(_) => continue,
            PitResult::ToPredict(pit) => Pit::BOTH
                .into_iter()
                .map(|side| (side, side == pit))
                .collect(),
            PitResult::NoPit => {
                if !rng.random_bool(NO_PIT_PROBABILITY) {
                    continue;
                }
                let side = if rng.random_bool(0.5) {
                    Pit::Left
                } else {
                    Pit::Right
                };
                vec![(side, false)]
            }
        };
        let subject = format!("{} ball", ball.reference.word);
        for (side, drops) in asked {
            let pit = format!("{} pit", side.word());
            records.extend(choice_record(
                PREDICTIVE_DROP,
                &fill(PREDICTIVE_DROP_TITLE, &[&ball.reference.word, side.word()]),
                [&subject, DROP, &pit],
                &[
                    option(YES.to_string(), [&subject, DROP, &pit], drops),
                    option(NO.to_string(), [&subject, NOT_DROP, &pit], !drops),
                ],
            ));
        }
    }
    records
}

/// `ball_counterfactual_remove`: "If we removed the {w} floating wall and other balls, which pit
/// would the {c} ball drop into?" for each counterfactual run. Question program `[wall, "remove",
/// "floating wall"]`; option programs `[ball, "drop", "left pit" | "right pit" | "no pit"]`.
pub(super) fn counterfactual_questions(
    scene: &BallScene<'_>,
    annotation: &BallAnnotation,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    let mut records = Vec::new();
    for wall in &scene.walls {
        let wall_program = format!("{} floating wall", wall.word);
        for ball in &scene.balls {
            let Some(run) = annotation.counterfactual(wall.name, ball.reference.name) else {
                continue;
            };
            let subject = format!("{} ball", ball.reference.word);
            let landed = run.record.result.pit();
            let mut options: Vec<DraftOption> = Pit::BOTH
                .iter()
                .map(|pit| {
                    let program = format!("{} pit", pit.word());
                    option(
                        pit_option(pit.word()),
                        [&subject, DROP, &program],
                        landed == Some(*pit),
                    )
                })
                .collect();
            options.push(option(
                NO_PIT.to_string(),
                [&subject, DROP, NO_PIT_PROGRAM],
                landed.is_none(),
            ));
            options.shuffle(rng);
            records.extend(choice_record(
                COUNTERFACTUAL_REMOVE,
                &fill(
                    COUNTERFACTUAL_REMOVE_TITLE,
                    &[&wall.word, &ball.reference.word],
                ),
                [&wall_program, REMOVE, "floating wall"],
                &options,
            ));
        }
    }
    records
}

/// `ball_goaldriven_drop`: "What can we do to make the {c} ball drop into the {left|right} pit?"
/// for each ball and pit, options "Remove the {w} floating wall and other balls", true when that
/// run drops the ball into the pit. Question program `[ball, "drop", "left pit"]`; option
/// programs `[wall, "remove", "floating wall"]`.
pub(super) fn goal_driven_questions(
    scene: &BallScene<'_>,
    annotation: &BallAnnotation,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    let mut records = Vec::new();
    for ball in &scene.balls {
        let subject = format!("{} ball", ball.reference.word);
        for pit in Pit::BOTH {
            let pit_program = format!("{} pit", pit.word());
            let mut options: Vec<DraftOption> = scene
                .walls
                .iter()
                .filter_map(|wall| {
                    let run = annotation.counterfactual(wall.name, ball.reference.name)?;
                    let wall_program = format!("{} floating wall", wall.word);
                    Some(option(
                        removal_option(&wall.word),
                        [&wall_program, REMOVE, "floating wall"],
                        run.record.result.pit() == Some(pit),
                    ))
                })
                .collect();
            if !(options.iter().any(|o| o.correct) && options.iter().any(|o| !o.correct)) {
                continue;
            }
            options.shuffle(rng);
            records.extend(choice_record(
                GOAL_DRIVEN_DROP,
                &fill(GOAL_DRIVEN_DROP_TITLE, &[&ball.reference.word, pit.word()]),
                [&subject, DROP, &pit_program],
                &options,
            ));
        }
    }
    records
}
