//! The fluid question engine: the seven fluid families of one video, in template order.
//!
//! The release's fluid question code is not public. The templates are the paper's (table
//! `tab:fluid_q` and its prompts); which annotation key answers each, the option wording, the
//! family keys and the draws are this engine's, inferred from what the release's generator
//! records (`docs/data/fluid.md`). Inputs: a validated [`FluidAnnotation`] and a seed. Output: the
//! per-video engine file ([`PerVideoQuestions`]) with every family key present; the shared
//! sampler (`engine::sample_and_split`) draws the splits from many of those. Records go through
//! the shared `engine::record` helpers (lettered options, sorted answer letters, `program`
//! payloads). Randomness comes from one ChaCha8 stream per video,
//! `derive_seed(seed, "engine/fluid/<video_id>")`, so the same inputs and seed give
//! byte-identical output.
//!
//! | family | type | paper | answer from (inferred) |
//! |---|---|---|---|
//! | `density` | open: yes / no / can not answer | Density, factual | `allDensityRelations` after closure (`property`) |
//! | `stick_number` | open: a count | Stick Number, factual | `metaSamplingData.sticks` |
//! | `fluid_predictive_pass` | choice: sticks | Pass, predictive | `perEmitterStickStat["Later Emitted <C> Fluid"]` |
//! | `fluid_predictive_container` | choice: containers | Container, predictive | `perReceptorFluidStat[*]["Later Emitted <C> Fluid"]` |
//! | `fluid_counterfactual_pass` | choice: sticks | Pass, counterfactual | the run without the stick: `perEmitterStickStat` |
//! | `fluid_counterfactual_container` | choice: containers | Container, counterfactual | that run's `perReceptorFluidStat` |
//! | `fluid_goaldriven_container` | choice: removals | Container, goal-driven | each removal's run: does the container hold most of the fluid |
//!
//! Decisions, each named where it is made:
//!
//! * Wording. Titles are the paper's templates; the counterfactual ones read "If the {c} stick
//!   were removed", as in the paper's rephrasing prompt. Options name objects capitalised as the
//!   paper's prompt shows them (`Pink stick`, `Gray container`); goal-driven options read
//!   `Remove the {c} stick` (the paper's answer example: "Remove green stick").
//! * Density (`property`): answered from the recorded relations, normalised to base fluids by
//!   the reader and closed transitively, not from the layout's densities, because the paper's
//!   answer format has "can not answer" and the release records only what the containers show.
//!   The comparator is a coin flip; unrelated pairs are kept with probability 0.3 as in rope.
//! * Passing and entering (`dynamics`): a stick is passed when the run lists it for the fluid
//!   (more than 20 particles touched it), a container entered when it lists the fluid (more than
//!   20 particles end in it); "most" is strictly more than in every other container.
//! * Options (`dynamics`): 2–4 per question with at least one true and one false, drawn as the
//!   rope engine's goal-driven options; a question that cannot have both is not asked.
//! * Objects are named by colour alone; two objects of a kind sharing a colour are not asked
//!   about (`scene`). A run or key an option needs but the tracking data lacks skips that
//!   question, never the video.
//!
//! `program` payloads, in the spirit of rope's: open-ended `density` is
//! `[c1, "fluid", comparator, c2, "fluid"]` and `stick_number` is `["stick"]`. Choice questions
//! are `{"question": [...], "choices": {"A": [...]}}` with triples `[subject, verb, object]`:
//! an outcome `[fluid, "pass", "gray stick"]`, `[fluid, "enter", "red container"]` (the fluid
//! is `pink fluid`, or `later emitted yellow fluid` for a predictive emitter's), an intervention
//! `["brown stick", "remove", "stick"]`, a goal `[fluid, "enter most", "red container"]`. As in
//! rope, a counterfactual question's program is its intervention and its choices are outcomes; a
//! goal-driven question's program is the goal and its choices are interventions; a predictive
//! question's program is `[later fluid, "pass", "stick"]` or `[later fluid, "enter",
//! "container"]`.

mod dynamics;
mod property;
mod scene;
mod templates;

#[cfg(test)]
mod tests;

use indexmap::IndexMap;

use super::{EngineError, QuestionEngine, SamplerConfig};
use crate::dataset::fluid::FluidAnnotation;
use crate::dataset::{PerVideoQuestions, QuestionRecord, VideoFolder, VideoId};
use crate::util::{derive_seed, seeded_rng};

/// The fluid engine, as the scenario table lists it.
pub const ENGINE: QuestionEngine = QuestionEngine {
    families: &templates::FAMILIES,
    generate: generate_for_video,
    per_video: SamplerConfig {
        fact_per_video: 1,
        dynamics_per_video: 2,
    },
};

/// Reads the video's `outputs.json` and generates its questions.
fn generate_for_video(video: &VideoFolder, seed: u64) -> Result<PerVideoQuestions, EngineError> {
    let annotation = FluidAnnotation::load(&video.outputs_json())?;
    Ok(generate_questions(&video.id, &annotation, seed))
}

/// Generates all seven fluid families for one video, in template order: `density`,
/// `stick_number`, `fluid_predictive_pass`, `fluid_predictive_container`,
/// `fluid_counterfactual_pass`, `fluid_counterfactual_container`, `fluid_goaldriven_container`.
/// Every family key is present, possibly with no records. Generation cannot fail on a validated
/// annotation: a question that cannot be built soundly is skipped.
pub fn generate_questions(
    video_id: &VideoId,
    annotation: &FluidAnnotation,
    seed: u64,
) -> PerVideoQuestions {
    let scene = scene::FluidScene::new(annotation);
    let mut rng = seeded_rng(derive_seed(seed, &format!("engine/fluid/{video_id}")));
    let density = property::density_questions(&scene, &mut rng);
    let stick_number = property::stick_number_questions(annotation.layout.sticks.len());
    let (predictive_pass, predictive_container) =
        dynamics::predictive_questions(&scene, annotation, &mut rng);
    let (counterfactual_pass, counterfactual_container) =
        dynamics::counterfactual_questions(&scene, annotation, &mut rng);
    let goal_driven = dynamics::goal_driven_questions(&scene, annotation, &mut rng);
    let families: [(&str, Vec<QuestionRecord>); 7] = [
        (templates::DENSITY, density),
        (templates::STICK_NUMBER, stick_number),
        (templates::PREDICTIVE_PASS, predictive_pass),
        (templates::PREDICTIVE_CONTAINER, predictive_container),
        (templates::COUNTERFACTUAL_PASS, counterfactual_pass),
        (
            templates::COUNTERFACTUAL_CONTAINER,
            counterfactual_container,
        ),
        (templates::GOAL_DRIVEN_CONTAINER, goal_driven),
    ];
    let question_dict: IndexMap<String, Vec<QuestionRecord>> = families
        .into_iter()
        .map(|(family, records)| (family.to_string(), records))
        .collect();
    debug_assert!(
        question_dict
            .keys()
            .map(String::as_str)
            .eq(templates::FAMILIES)
    );
    PerVideoQuestions {
        video_id: video_id.0.clone(),
        question_dict,
    }
}
