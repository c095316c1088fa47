//! The rope question engine: the eight rope families of one video, in template order.
//!
//! This is a re-implementation of the public rope engine (`questions/question_engine_pulley.py`,
//! `read_file.py`, `agent_pulley_dev.py` and `tools/utils.py` of the ContPhy release; see
//! `docs/data/rope.md`). Inputs: a validated [`RopeAnnotation`] and a seed. Output: the per-video
//! engine file ([`PerVideoQuestions`]) with the eight families in template order; the shared
//! sampler (`engine::sample_and_split`) draws the train/val/test lists from many of those.
//!
//! Records match the public engine's field by field: the same template strings, option and
//! letter formats, `program` payloads, answer types and sampling probabilities. Randomness comes
//! from one ChaCha8 stream per video, `derive_seed(seed, "engine/rope/<video_id>")`: the same
//! inputs and seed give byte-identical output (the public engine never seeded its RNG and
//! iterated Python sets; see the public engine's quirks in `docs/data/rope.md`). The stream
//! differs from Python's Mersenne Twister, so individual questions differ from any public run while their distribution matches.
//!
//! Bugs of the public engine fixed here (its quirks in `docs/data/rope.md`), each also commented
//! where it is fixed:
//!
//! * `rope_counterfactual` with one true outcome used a stale or uninitialised `answer`; the
//!   answer now follows from the options emitted (`dynamics`).
//! * `rope_counterfactual` with one false outcome labelled every option false (`dynamics`).
//! * `breakpoint()` calls: an unreadable mass is an [`RopeEngineError`]; an unknown object, a
//!   repeated option text or an impossible option draw skips that option or question.
//! * Unseeded RNG and `set` iteration: seeded stream, fixed colour and shape orders
//!   (`templates`), `negative` in option order (`record`).
//!
//! Decisions, each named where it is made: (a) no attribute-based de-duplication of objects
//! (`scene`); (b) existence matches colours exactly (`property`); (c) tension pairs on a rope
//! carrying loads of different mass are skipped when answerable (`property`); (d) nominal masses
//! `ceil(m·100)/100`, others an error (`scene`); (e) objects that no phrase tells apart are never
//! asked about, references keep full colour words such as "light blue", and the rope map and
//! movable-pulley links are bounds-checked (`scene`); mass and tension answers are computed from
//! the masses rather than copied from the branch labels (`property`).
//!
//! The public driver's hard-coded skip of video `1846` is the caller's business and not done
//! here.

mod dynamics;
mod error;
mod property;
mod scene;
mod templates;

#[cfg(test)]
mod tests;

use indexmap::IndexMap;

pub use error::RopeEngineError;
pub use scene::{EngineObject, RopeScene};

use super::{EngineError, QuestionEngine, SamplerConfig};
use crate::dataset::rope::RopeAnnotation;
use crate::dataset::{PerVideoQuestions, QuestionRecord, VideoFolder, VideoId};
use crate::util::{derive_seed, seeded_rng};

/// The rope engine, as the scenario table lists it.
pub const ENGINE: QuestionEngine = QuestionEngine {
    families: &templates::FAMILIES,
    generate: generate_for_video,
    per_video: SamplerConfig {
        fact_per_video: 2,
        dynamics_per_video: 2,
    },
};

/// Reads the video's `outputs.json` and generates its questions.
fn generate_for_video(video: &VideoFolder, seed: u64) -> Result<PerVideoQuestions, EngineError> {
    let annotation = RopeAnnotation::load(&video.outputs_json())?;
    generate_questions(&video.id, &annotation, seed)
        .map_err(|error| EngineError::Scene(Box::new(error)))
}

/// Generates all eight rope families for one video, in template order: `mass`, `tension`,
/// `shape`, `color`, `existence`, `rope_counterfactual`, `rope_counterfactual2`,
/// `rope_goaldriven`. Every family key is present, possibly with no records.
///
/// Fails only when the annotation cannot be read into the engine's object list (a load mass that
/// is not nominal, a name outside the generator's grammar).
pub fn generate_questions(
    video_id: &VideoId,
    annotation: &RopeAnnotation,
    seed: u64,
) -> Result<PerVideoQuestions, RopeEngineError> {
    let scene = RopeScene::from_annotation(&video_id.0, annotation)?;
    let mut rng = seeded_rng(derive_seed(seed, &format!("engine/rope/{video_id}")));
    let families: [(&str, Vec<QuestionRecord>); 8] = [
        (templates::MASS, property::mass_questions(&scene, &mut rng)),
        (
            templates::TENSION,
            property::tension_questions(&scene, &mut rng),
        ),
        (templates::SHAPE, property::shape_questions(&scene)),
        (templates::COLOR, property::color_questions(&scene)),
        (templates::EXISTENCE, property::existence_questions(&scene)),
        (
            templates::COUNTERFACTUAL,
            dynamics::counterfactual_questions(&scene, annotation, &mut rng),
        ),
        (
            templates::COUNTERFACTUAL_DIRECTION,
            dynamics::counterfactual_direction_questions(&scene, annotation, &mut rng),
        ),
        (
            templates::GOAL_DRIVEN,
            dynamics::goal_driven_questions(&scene, annotation, &mut rng),
        ),
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
    Ok(PerVideoQuestions {
        video_id: video_id.0.clone(),
        question_dict,
    })
}
