//! Cloth scenes (`cloth_collision`, `docs/data/cloth.md`): the typed annotations
//! ([`ClothAnnotation`], read and written), the release's names ([`names`]: boxes, cloths, the two
//! halves), the labelling of how a run ends for a box ([`outcome`]: its end pose), and the scene
//! words.

mod annotation;
pub mod names;
pub mod outcome;
mod vocabulary;

pub use annotation::{
    BoxRecord, ClothAnnotation, ClothProperties, CollisionEvent, Friction, HalfObjects,
    RegionForces, Tower,
};
pub use vocabulary::VOCABULARY;

#[cfg(test)]
mod tests;
