//! The question engine: generates ContPhy questions from annotations (rope only; the other
//! scenarios' engines are not public), and samples and splits them.
//!
//! This is a re-implementation of the public rope engine (`questions/question_engine_pulley.py`,
//! `read_file.py`, `agent_pulley_dev.py` and `tools/utils.py` of the ContPhy release; see
//! `contphy/FORMAT.md` §6–8). Inputs: a validated [`RopeAnnotation`] and a seed. Outputs: the
//! per-video engine file ([`PerVideoQuestions`]) with the eight families in template order, and
//! from many of those, sampled train/val/test lists ([`sample_and_split`]).
//!
//! Records match the public engine's field by field: the same template strings, option and
//! letter formats, `program` payloads, answer types and sampling probabilities. Randomness comes
//! from one ChaCha8 stream per video, `derive_seed(seed, "engine/rope/<video_id>")`: the same
//! inputs and seed give byte-identical output (the public engine never seeded its RNG and
//! iterated Python sets, FORMAT §10.8). The stream differs from Python's Mersenne Twister, so
//! individual questions differ from any public run while their distribution matches.
//!
//! Bugs of the public engine fixed here (FORMAT §10.8), each also commented where it is fixed:
//!
//! * `rope_counterfactual` with one true outcome used a stale or uninitialised `answer`; the
//!   answer now follows from the options emitted (`dynamics`).
//! * `rope_counterfactual` with one false outcome labelled every option false (`dynamics`).
//! * `breakpoint()` calls: an unreadable mass is an [`EngineError`]; an unknown object, a
//!   repeated option text or an impossible option draw skips that option or question.
//! * Unseeded RNG and `set` iteration: seeded stream, fixed colour and shape orders
//!   (`vocabulary`), `negative` in option order (`record`).
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
//! here. This module depends only on `dataset` types and `util`.

mod dynamics;
mod error;
mod property;
mod record;
mod sampler;
mod scene;
mod vocabulary;

#[cfg(test)]
mod tests;

use indexmap::IndexMap;

pub use error::EngineError;
pub use sampler::{SampledSplits, SamplerConfig, sample_and_split, split_boundaries};
pub use scene::{EngineObject, RopeScene};

use crate::dataset::{PerVideoQuestions, QuestionRecord, RopeAnnotation, VideoId};
use crate::util::{derive_seed, seeded_rng};

/// Generates all eight rope families for one video, in template order: `mass`, `tension`,
/// `shape`, `color`, `existence`, `rope_counterfactual`, `rope_counterfactual2`,
/// `rope_goaldriven`. Every family key is present, possibly with no records.
///
/// Fails only when the annotation cannot be read into the engine's object list (a load mass that
/// is not nominal, a name outside the generator's grammar).
pub fn generate_rope_questions(
    video_id: &VideoId,
    annotation: &RopeAnnotation,
    seed: u64,
) -> Result<PerVideoQuestions, EngineError> {
    let scene = RopeScene::from_annotation(&video_id.0, annotation)?;
    let mut rng = seeded_rng(derive_seed(seed, &format!("engine/rope/{video_id}")));
    let families: [(&str, Vec<QuestionRecord>); 8] = [
        (vocabulary::MASS, property::mass_questions(&scene, &mut rng)),
        (
            vocabulary::TENSION,
            property::tension_questions(&scene, &mut rng),
        ),
        (vocabulary::SHAPE, property::shape_questions(&scene)),
        (vocabulary::COLOR, property::color_questions(&scene)),
        (vocabulary::EXISTENCE, property::existence_questions(&scene)),
        (
            vocabulary::COUNTERFACTUAL,
            dynamics::counterfactual_questions(&scene, annotation, &mut rng),
        ),
        (
            vocabulary::COUNTERFACTUAL_DIRECTION,
            dynamics::counterfactual_direction_questions(&scene, annotation, &mut rng),
        ),
        (
            vocabulary::GOAL_DRIVEN,
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
            .eq(vocabulary::FAMILIES)
    );
    Ok(PerVideoQuestions {
        video_id: video_id.0.clone(),
        question_dict,
    })
}
