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

/// The release's two values of each cloth property, the one with more of it first; the two
/// cloths of a video always take different values of each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PropertyValues {
    /// `stretchingCompliance`, m/N: the cloth that stretches, the one that does not.
    pub stretch_compliance: [f64; 2],
    /// `bendingCompliance` (Obi's max bending), units: the cloth that bends easily, the stiffer.
    pub max_bending: [f64; 2],
    /// The friction coefficient of `HighFriction`, `LowFriction`.
    pub friction: [f64; 2],
}

/// The release's cloth property values.
pub const VALUES: PropertyValues = PropertyValues {
    stretch_compliance: [0.011, 0.0],
    max_bending: [0.035, 0.013],
    friction: [4.0, 0.5],
};

#[cfg(test)]
mod tests;
