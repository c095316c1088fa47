//! The words of fluid scenes (`fluid_slides`), as the paper's prompt lists them.

use crate::dataset::vocabulary::Vocabulary;

/// Fluid scenes: fluids, the containers they flow into, sticks and emitters.
pub const VOCABULARY: Vocabulary = Vocabulary {
    kinds: &["fluid", "container", "stick", "emitter"],
    kind_groups: &[],
    attributes: &[],
    unfindable: &[],
    suffix: None,
};
