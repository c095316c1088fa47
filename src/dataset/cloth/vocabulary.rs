//! The words of cloth scenes (`cloth_collision`), as the paper's prompt lists them.

use crate::dataset::vocabulary::Vocabulary;

/// Cloth scenes: the two cloths and the pillars and plates they fall on.
pub const VOCABULARY: Vocabulary = Vocabulary {
    kinds: &["cloth", "pillar", "plate"],
    kind_groups: &[],
    attributes: &[],
    unfindable: &[],
    suffix: None,
};
