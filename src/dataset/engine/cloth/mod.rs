//! The cloth question engine: the six cloth families of one video, in template order.
//!
//! The release's cloth question code is not public. The templates are the paper's (table
//! `tab:cloth_q` and its API docs); which annotation key answers each, the option wording, the
//! family keys and the draws are this engine's, inferred from what the release's generator
//! records (`docs/data/cloth.md`). As in the paper, cloth has property and predictive questions
//! only. Inputs: a validated [`ClothAnnotation`] and a seed. Output: the per-video engine file
//! ([`PerVideoQuestions`]) with every family key present; the shared sampler
//! (`engine::sample_and_split`) draws the splits from many of those, 1 property and 2 predictive
//! questions a video as the paper's. Randomness comes from one ChaCha8 stream per video,
//! `derive_seed(seed, "engine/cloth/<video_id>")`, so the same inputs and seed give
//! byte-identical output.
//!
//! | family | type | paper | answer from (inferred) |
//! |---|---|---|---|
//! | `elasticity` | open: yes / no | Elasticity, factual | `clothLeft/clothRight.stretchingCompliance` (`property`) |
//! | `bending` | open: yes / no | Bending, factual | `bendingCompliance` (the maximum bending) |
//! | `cloth_predictive_fall` | choice: Yes / No | Fall Over, predictive | the box's `endPoseDescription` (`dynamics`) |
//! | `cloth_predictive_collision` | choice: Yes / No | Collision, predictive | either box's `collisionEvents` |
//! | `cloth_predictive_touch` | choice: Yes / No | Touch, predictive | either box's `touchers` |
//! | `cloth_predictive_pose` | choice: five pose phrases | Pose, predictive | the box's `endPoseDescription` |
//!
//! Decisions are named where they are made (`property`, `dynamics`: which boxes and pairs are
//! asked, the balance of answers). Boxes are named by colour and shape, pairs within one half
//! (`scene`).
//!
//! `program` payloads, in the spirit of the other engines': the property families
//! `[side, "cloth", comparator, other side, "cloth"]` (`["left", "cloth", "greater than",
//! "right", "cloth"]`, `["right", "cloth", "harder", "left", "cloth"]`); choice questions
//! `{"question": [...], "choices": {"A": [...]}}` with triples `[subject, verb, object]`: the
//! question's triple is the outcome asked about, `["green plate", "fall over", ""]`, `["green
//! plate", "collide", "gray pillar"]`, `["green plate", "touch", "gray pillar"]`, `["green
//! plate", "pose", ""]`; the `Yes` option's is the same, the `No` option's negates the verb
//! (`"not fall over"`, `"not collide"`, `"not touch"`), and a pose option's names the release's
//! label (`["green plate", "pose", "Supine"]`).

mod dynamics;
mod property;
mod scene;
mod templates;

#[cfg(test)]
mod tests;

use indexmap::IndexMap;

use super::{EngineError, QuestionEngine, SamplerConfig};
use crate::dataset::cloth::ClothAnnotation;
use crate::dataset::{PerVideoQuestions, QuestionRecord, VideoFolder, VideoId};
use crate::util::{derive_seed, seeded_rng};

/// The cloth engine, as the scenario table lists it.
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
    let annotation = ClothAnnotation::load(&video.outputs_json())?;
    Ok(generate_questions(&video.id, &annotation, seed))
}

/// Generates all six cloth families for one video, in template order. Every family key is
/// present, possibly with no records; a question that cannot be built soundly is skipped.
pub fn generate_questions(
    video_id: &VideoId,
    annotation: &ClothAnnotation,
    seed: u64,
) -> PerVideoQuestions {
    let scene = scene::ClothScene::new(annotation);
    let mut rng = seeded_rng(derive_seed(seed, &format!("engine/cloth/{video_id}")));
    let elasticity = property::elasticity_questions(annotation, &mut rng);
    let bending = property::bending_questions(annotation, &mut rng);
    let fall = dynamics::fall_questions(&scene, &mut rng);
    let collision = dynamics::collision_questions(&scene, annotation, &mut rng);
    let touch = dynamics::touch_questions(&scene, annotation, &mut rng);
    let pose = dynamics::pose_questions(&scene, &mut rng);
    let families: [(&str, Vec<QuestionRecord>); 6] = [
        (templates::ELASTICITY, elasticity),
        (templates::BENDING, bending),
        (templates::PREDICTIVE_FALL, fall),
        (templates::PREDICTIVE_COLLISION, collision),
        (templates::PREDICTIVE_TOUCH, touch),
        (templates::PREDICTIVE_POSE, pose),
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
