//! The dynamics families: predictive (`fluid_predictive_pass`, `fluid_predictive_container`),
//! counterfactual (`fluid_counterfactual_pass`, `fluid_counterfactual_container`) and
//! goal-driven (`fluid_goaldriven_container`).
//!
//! Every option is an object of the scene and its truth is read from one run's tracking data: a
//! stick is passed when the fluid's `perEmitterStickStat` lists it, a container is entered when
//! its `perReceptorFluidStat` lists the fluid, and "most of the fluid" enters a container when it
//! holds strictly more of the fluid than every other container (a tie is not "most").
//!
//! Options are drawn as the rope engine's goal-driven ones (`option_set`): each question has one
//! true and one false option at least, and 2–4 in all, the rest drawn false with probability
//! |F|/(|F|+|T|) of the remaining pools. A question without a true or without a false option is
//! not asked. Counterfactual runs start the factual emitters only, so their questions ask about
//! factual fluids only.

use rand::Rng;
use rand::seq::SliceRandom;

use super::scene::{FluidScene, Reference};
use super::templates::{
    COUNTERFACTUAL_CONTAINER, COUNTERFACTUAL_CONTAINER_TITLE, COUNTERFACTUAL_PASS,
    COUNTERFACTUAL_PASS_TITLE, GOAL_DRIVEN_CONTAINER, GOAL_DRIVEN_CONTAINER_TITLE,
    PREDICTIVE_CONTAINER, PREDICTIVE_CONTAINER_TITLE, PREDICTIVE_PASS, PREDICTIVE_PASS_TITLE, fill,
    object_option, removal_option,
};
use crate::dataset::QuestionRecord;
use crate::dataset::engine::record::{DraftOption, choice_record, draw_weighted};
use crate::dataset::fluid::{FluidAnnotation, FluidTracking};

/// Fewest options of a question.
const MIN_OPTIONS: usize = 2;
/// Most options of a question.
const MAX_OPTIONS: usize = 4;
/// The program verb of passing a stick.
const PASS: &str = "pass";
/// The program verb of ending in a container.
const ENTER: &str = "enter";
/// The program verb of ending mostly in a container.
const ENTER_MOST: &str = "enter most";
/// The program verb of removing a stick.
const REMOVE: &str = "remove";

/// The sticks and containers a fluid's options name, with their truth in one run.
struct Outcomes<'s> {
    /// The fluid as option programs name it (`pink fluid`).
    subject: String,
    /// Passed sticks (`true`) and the others; `None` when the run does not list the fluid in
    /// `perEmitterStickStat`, so nothing is known about the sticks it passed.
    sticks: Option<Vec<(&'s Reference<'s>, bool)>>,
    /// Entered containers (`true`) and the others.
    containers: Vec<(&'s Reference<'s>, bool)>,
}

impl Outcomes<'_> {
    /// `fluid`'s outcomes in `tracking`, over the scene's sticks (less `removed`) and
    /// containers.
    fn of<'s>(
        scene: &'s FluidScene<'s>,
        tracking: &FluidTracking,
        fluid: &str,
        subject: String,
        removed: Option<&str>,
    ) -> Outcomes<'s> {
        let sticks = tracking.contacts(fluid).map(|contacts| {
            scene
                .sticks
                .iter()
                .filter(|stick| Some(stick.name) != removed)
                .map(|stick| (stick, contacts.contains_key(stick.name)))
                .collect()
        });
        let containers = scene
            .containers
            .iter()
            .map(|container| (container, tracking.particles_in(container.name, fluid) > 0))
            .collect();
        Outcomes {
            subject,
            sticks,
            containers,
        }
    }

    /// Stick options: `Pink stick`, program `[subject, "pass", "pink stick"]`; both pools empty
    /// when the run does not list the fluid (the question is then not asked).
    fn stick_options(&self) -> (Vec<DraftOption>, Vec<DraftOption>) {
        let sticks = self.sticks.as_deref().unwrap_or_default();
        split(sticks.iter().map(|(stick, passed)| DraftOption {
            text: object_option(&stick.word, "stick"),
            program: [
                self.subject.clone(),
                PASS.to_string(),
                format!("{} stick", stick.word),
            ],
            correct: *passed,
        }))
    }

    /// Container options: `Gray container`, program `[subject, "enter", "gray container"]`.
    fn container_options(&self) -> (Vec<DraftOption>, Vec<DraftOption>) {
        split(
            self.containers
                .iter()
                .map(|(container, entered)| DraftOption {
                    text: object_option(&container.word, "container"),
                    program: [
                        self.subject.clone(),
                        ENTER.to_string(),
                        format!("{} container", container.word),
                    ],
                    correct: *entered,
                }),
        )
    }
}

/// True options, then false options, each in the given order.
fn split(options: impl Iterator<Item = DraftOption>) -> (Vec<DraftOption>, Vec<DraftOption>) {
    options.partition(|option| option.correct)
}

/// `fluid_predictive_pass` and `fluid_predictive_container`: "Which stick will the fluid from the
/// other {c} emitter pass?" and "Which container will fluid from the other {c} emitter flow
/// into?", one each per fluid with a predictive emitter, from the factual run's records of
/// `Later Emitted <C> Fluid`. Question programs: `[later fluid, "pass", "stick"]` and
/// `[later fluid, "enter", "container"]`.
pub(super) fn predictive_questions(
    scene: &FluidScene<'_>,
    annotation: &FluidAnnotation,
    rng: &mut impl Rng,
) -> (Vec<QuestionRecord>, Vec<QuestionRecord>) {
    let mut pass = Vec::new();
    let mut container = Vec::new();
    for later in &scene.later_fluids {
        let subject = later.program_name();
        let outcomes = Outcomes::of(scene, &annotation.tracking, &later.key, subject, None);
        let word = later.fluid.word.as_str();
        let (true_options, false_options) = outcomes.stick_options();
        if let Some(options) = option_set(true_options, false_options, rng) {
            pass.extend(choice_record(
                PREDICTIVE_PASS,
                &fill(PREDICTIVE_PASS_TITLE, &[word]),
                [&outcomes.subject, PASS, "stick"],
                &options,
            ));
        }
        let (true_options, false_options) = outcomes.container_options();
        if let Some(options) = option_set(true_options, false_options, rng) {
            container.extend(choice_record(
                PREDICTIVE_CONTAINER,
                &fill(PREDICTIVE_CONTAINER_TITLE, &[word]),
                [&outcomes.subject, ENTER, "container"],
                &options,
            ));
        }
    }
    (pass, container)
}

/// `fluid_counterfactual_pass` and `fluid_counterfactual_container`: "If the {s} stick were
/// removed, which stick would {c} fluid pass?" and "… which container would {c} fluid flow
/// into?", one each per counterfactual run and factual fluid, from that run's records. The
/// removed stick is not an option. Question program: `[removed stick, "remove", "stick"]`.
pub(super) fn counterfactual_questions(
    scene: &FluidScene<'_>,
    annotation: &FluidAnnotation,
    rng: &mut impl Rng,
) -> (Vec<QuestionRecord>, Vec<QuestionRecord>) {
    let mut pass = Vec::new();
    let mut container = Vec::new();
    for run in &annotation.counterfactuals {
        // A removed stick outside the layout (or sharing its colour): it cannot be named.
        let Some(removed) = scene.stick(&run.removed_stick) else {
            continue;
        };
        let removed_program = format!("{} stick", removed.word);
        let question_program = [removed_program.as_str(), REMOVE, "stick"];
        for fluid in &scene.fluids {
            let subject = format!("{} fluid", fluid.word);
            let outcomes = Outcomes::of(
                scene,
                &run.tracking,
                fluid.name,
                subject,
                Some(removed.name),
            );
            let (true_options, false_options) = outcomes.stick_options();
            if let Some(options) = option_set(true_options, false_options, rng) {
                pass.extend(choice_record(
                    COUNTERFACTUAL_PASS,
                    &fill(COUNTERFACTUAL_PASS_TITLE, &[&removed.word, &fluid.word]),
                    question_program,
                    &options,
                ));
            }
            let (true_options, false_options) = outcomes.container_options();
            if let Some(options) = option_set(true_options, false_options, rng) {
                container.extend(choice_record(
                    COUNTERFACTUAL_CONTAINER,
                    &fill(
                        COUNTERFACTUAL_CONTAINER_TITLE,
                        &[&removed.word, &fluid.word],
                    ),
                    question_program,
                    &options,
                ));
            }
        }
    }
    (pass, container)
}

/// `fluid_goaldriven_container`: "What can we do to let most of the {c} fluid enter the {k}
/// container?" for every factual fluid and container, with options "Remove the {s} stick", one
/// per counterfactual run (the first run of a stick removed twice), true when that run leaves
/// most of the fluid in the container ([`FluidTracking::holds_most`]). Question program:
/// `[fluid, "enter most", container]`; option programs `[stick, "remove", "stick"]`.
pub(super) fn goal_driven_questions(
    scene: &FluidScene<'_>,
    annotation: &FluidAnnotation,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    let mut runs: Vec<(&Reference<'_>, &FluidTracking)> = Vec::new();
    for run in &annotation.counterfactuals {
        if let Some(stick) = scene.stick(&run.removed_stick)
            && runs.iter().all(|(seen, _)| seen.name != stick.name)
        {
            runs.push((stick, &run.tracking));
        }
    }
    let mut records = Vec::new();
    for fluid in &scene.fluids {
        let fluid_program = format!("{} fluid", fluid.word);
        for container in &scene.containers {
            let container_program = format!("{} container", container.word);
            let (true_options, false_options) =
                split(runs.iter().map(|(stick, tracking)| DraftOption {
                    text: removal_option(&stick.word),
                    program: [
                        format!("{} stick", stick.word),
                        REMOVE.to_string(),
                        "stick".to_string(),
                    ],
                    correct: tracking.holds_most(container.name, fluid.name),
                }));
            let Some(options) = option_set(true_options, false_options, rng) else {
                continue;
            };
            records.extend(choice_record(
                GOAL_DRIVEN_CONTAINER,
                &fill(GOAL_DRIVEN_CONTAINER_TITLE, &[&fluid.word, &container.word]),
                [&fluid_program, ENTER_MOST, &container_program],
                &options,
            ));
        }
    }
    records
}

/// One question's options from its true and false pools: one of each, then up to 2–4 in all
/// (drawn once per question, capped by the pools), each further option false with probability
/// |F|/(|F|+|T|) of what remains; shuffled. `None` when either pool is empty.
fn option_set(
    mut true_options: Vec<DraftOption>,
    mut false_options: Vec<DraftOption>,
    rng: &mut impl Rng,
) -> Option<Vec<DraftOption>> {
    if true_options.is_empty() || false_options.is_empty() {
        return None;
    }
    true_options.shuffle(rng);
    false_options.shuffle(rng);
    let available = true_options.len() + false_options.len();
    let wanted = rng.random_range(MIN_OPTIONS..=MAX_OPTIONS).min(available);
    let mut options = Vec::with_capacity(wanted);
    options.extend(true_options.pop());
    options.extend(false_options.pop());
    while options.len() < wanted {
        let Some(next) = draw_weighted(&mut true_options, &mut false_options, rng) else {
            break;
        };
        options.push(next);
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
                program: [format!("{prefix}{index}"), "pass".into(), "x".into()],
                correct,
            })
            .collect()
    }

    #[test]
    fn option_sets_hold_both_truths_and_two_to_four_options() {
        // (true pool, false pool, possible sizes)
        let cases: [(usize, usize, &[usize]); 5] = [
            (1, 1, &[2]),
            (1, 2, &[2, 3]),
            (2, 1, &[2, 3]),
            (3, 5, &[2, 3, 4]),
            (6, 6, &[2, 3, 4]),
        ];
        for seed in 0..100 {
            let mut rng = seeded_rng(seed);
            for (true_count, false_count, sizes) in cases {
                let set = option_set(
                    options("t", true_count, true),
                    options("f", false_count, false),
                    &mut rng,
                )
                .unwrap();
                assert!(
                    sizes.contains(&set.len()),
                    "{true_count}/{false_count}: {set:?}"
                );
                assert!(set.iter().any(|o| o.correct) && set.iter().any(|o| !o.correct));
                for option in &set {
                    assert_eq!(option.correct, option.text.starts_with('t'));
                }
            }
            assert!(option_set(options("t", 3, true), Vec::new(), &mut rng).is_none());
            assert!(option_set(Vec::new(), options("f", 3, false), &mut rng).is_none());
        }
    }
}
