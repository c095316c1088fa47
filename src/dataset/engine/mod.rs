//! The question engine: generates ContPhy questions from a video's annotations, then samples and
//! splits them.
//!
//! Shared here: the record format (`record`: the public engine's field order, lettered options,
//! sorted answer letters), the sampler and the per-video split ([`sample_and_split`]), and the
//! [`QuestionEngine`] each scenario provides. A scenario's families live in its folder
//! (`engine/<scenario>/`); the scenario table (`scenarios`) names each scenario's engine.
//!
//! Only the rope engine is public (`rope`, a re-implementation of the release's
//! `question_engine_pulley.py`); the others follow the paper's templates (`fluid`, `cloth`,
//! `ball`). Randomness comes from seeded ChaCha8 streams derived from the seed, the scenario and
//! the video id, so the same inputs give byte-identical files. This module depends only on
//! `dataset` types and `util`.

pub mod ball;
pub mod cloth;
mod error;
pub mod fluid;
pub(crate) mod record;
pub mod rope;
mod sampler;

pub use error::EngineError;
pub use sampler::{SampledSplits, SamplerConfig, sample_and_split, split_boundaries};

use crate::dataset::{PerVideoQuestions, VideoFolder};

/// A scenario's question engine.
#[derive(Debug, Clone, Copy)]
pub struct QuestionEngine {
    /// Its family keys, in generation order (every key is present in each video's output).
    pub families: &'static [&'static str],
    /// Every family's questions for one video: reads the video's annotations and generates from
    /// them with the given seed.
    pub generate: fn(&VideoFolder, u64) -> Result<PerVideoQuestions, EngineError>,
    /// Questions the sampler draws per video unless told otherwise (the paper: rope 2 + 2, the
    /// other scenarios 1 property + 2 dynamics).
    pub per_video: SamplerConfig,
}

/// An object an engine can ask about.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Reference<'a> {
    /// Its annotation name (`Light Blue Fluid`).
    pub(crate) name: &'a str,
    /// Its colour as questions write it (`light blue`).
    pub(crate) word: String,
}

/// The objects of `names` with their colour words (`color_word` of a name; names it cannot read
/// are left out), leaving out every object whose colour word another of them shares: questions
/// name objects by colour alone, so no phrase would tell those apart.
pub(crate) fn colour_references<'a>(
    names: impl Iterator<Item = &'a str>,
    color_word: impl Fn(&str) -> Option<String>,
) -> Vec<Reference<'a>> {
    let named: Vec<Reference<'a>> = names
        .filter_map(|name| {
            Some(Reference {
                name,
                word: color_word(name)?,
            })
        })
        .collect();
    named
        .iter()
        .filter(|reference| named.iter().filter(|o| o.word == reference.word).count() == 1)
        .cloned()
        .collect()
}
