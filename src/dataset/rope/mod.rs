//! Rope–pulley scenes (`pulley_group`): the annotations of a video ([`RopeAnnotation`]), the
//! grammar of object names ([`parse_rope_object_name`]), the release's rope world ([`world`]),
//! its outcome labelling ([`outcome`]) and the words of rope scenes ([`VOCABULARY`]).
//!
//! The format is described in `docs/data/rope.md`.

mod annotation;
mod names;
pub mod outcome;
mod vocabulary;
pub mod world;

pub use annotation::{RopeAnnotation, RopeChange, RopeCounterfactual, RopeCounterfactualPair};
pub use names::{RopeObjectKind, RopeObjectName, parse_rope_object_name};
pub use vocabulary::VOCABULARY;
