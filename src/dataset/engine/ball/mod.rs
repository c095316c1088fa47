//! The ball question engine: the five ball families of one video, in template order.
//!
//! The release's ball question code is not public. The templates are the paper's (table
//! `tab:ball_q` and its API docs); which annotation key answers each, the option wording, the
//! family keys and the draws are this engine's, inferred from what the release's generator
//! records (`docs/data/ball.md`). Inputs: a validated [`BallAnnotation`] and a seed. Output: the
//! per-video engine file ([`PerVideoQuestions`]) with every family key present; the shared
//! sampler (`engine::sample_and_split`) draws the splits from many of those. Randomness comes
//! from one ChaCha8 stream per video, `derive_seed(seed, "engine/ball/<video_id>")`, so the same
//! inputs and seed give byte-identical output.
//!
//! | family | type | paper | answer from (inferred) |
//! |---|---|---|---|
//! | `elasticity` | open: yes / no | Elasticity, factual | `metaSamplingData.balls[*].elasticityType` (`property`) |
//! | `plasticity` | open: yes / no | Plasticity, factual | the same |
//! | `ball_predictive_drop` | choice: Yes / No | Final drop, predictive | `trackingData[ball].pitResult` ("to Predict" or no pit) |
//! | `ball_counterfactual_remove` | choice: left / right / neither pit | Remove, counterfactual | the run with that `removedWall` and `ball` |
//! | `ball_goaldriven_drop` | choice: removals | Drop, goal-driven | each removal's run: does the ball drop into the pit |
//!
//! Decisions are named where they are made (`property`, `dynamics`). Objects are named by
//! colour alone (`scene`).
//!
//! `program` payloads, in the spirit of the other engines': the property families
//! `[c1, "ball", comparator, c2, "ball"]`; choice questions `{"question": [...], "choices":
//! {"A": [...]}}` with triples: an outcome `["pink ball", "drop", "left pit"]` (or `"not drop"`,
//! or the object `"no pit"`), an intervention `["white floating wall", "remove", "floating
//! wall"]`. A counterfactual question's program is its intervention and its choices outcomes; a
//! goal-driven question's program is the goal and its choices interventions; a predictive
//! question's program is the outcome asked about.

mod dynamics;
mod property;
mod scene;
mod templates;

#[cfg(test)]
mod tests;

use indexmap::IndexMap;

use super::{EngineError, QuestionEngine, SamplerConfig};
use crate::dataset::ball::BallAnnotation;
use crate::dataset::{PerVideoQuestions, QuestionRecord, VideoFolder, VideoId};
use crate::util::{derive_seed, seeded_rng};

/// The ball engine, as the scenario table lists it.
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
    let annotation = BallAnnotation::load(&video.outputs_json())?;
    Ok(generate_questions(&video.id, &annotation, seed))
}

/// Generates all five ball families for one video, in template order. Every family key is
/// present, possibly with no records; a question that cannot be built soundly is skipped.
pub fn generate_questions(
    video_id: &VideoId,
    annotation: &BallAnnotation,
    seed: u64,
) -> PerVideoQuestions {
    let scene = scene::BallScene::new(annotation);
    let mut rng = seeded_rng(derive_seed(seed, &format!("engine/ball/{video_id}")));
    let elasticity = property::elasticity_questions(&scene, &mut rng);
    let plasticity = property::plasticity_questions(&scene, &mut rng);
    let predictive = dynamics::predictive_questions(&scene, annotation, &mut rng);
    let counterfactual = dynamics::counterfactual_questions(&scene, annotation, &mut rng);
    let goal_driven = dynamics::goal_driven_questions(&scene, annotation, &mut rng);
    let families: [(&str, Vec<QuestionRecord>); 5] = [
        (templates::ELASTICITY, elasticity),
        (templates::PLASTICITY, plasticity),
        (templates::PREDICTIVE_DROP, predictive),
        (templates::COUNTERFACTUAL_REMOVE, counterfactual),
        (templates::GOAL_DRIVEN_DROP, goal_driven),
    ];
    let question_dict: IndexMap<String, Vec<QuestionRecord>> = families
        .into_iter()
        .map(|(family, records)| (family.to_string(), records))
        .collect();
    PerVideoQuestions {
        video_id: video_id.0.clone(),
        question_dict,
    }
}
