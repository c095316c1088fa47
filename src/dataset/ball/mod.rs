//! Ball scenes (`soft_body`, `docs/data/ball.md`): the typed annotations ([`BallAnnotation`]),
//! the release's object names ([`names`]), the labelling of a run ([`outcome`]: which pit a ball
//! drops into and when), and the scene words.

mod annotation;
pub mod names;
pub mod outcome;
mod vocabulary;

pub use annotation::{
    BallAnnotation, BallCounterfactual, BallLayout, BallRecord, ElasticityType, SlabRecord,
};
pub use vocabulary::VOCABULARY;
