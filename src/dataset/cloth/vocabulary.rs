//! The words of cloth scenes (`cloth_collision`), as the paper's prompt lists them, plus the side
//! that tells the two cloths apart (the paper's `_POS_`: "the left cloth").

use crate::dataset::vocabulary::{Attribute, Vocabulary};

/// Cloth scenes: the two cloths and the pillars and plates they fall on. The cloths carry their
/// `side`, `left` or `right` (`find("left cloth")`; a side alone means a cloth); the boxes have
/// no side (the questions name them by colour and shape, which are unique per shape).
pub const VOCABULARY: Vocabulary = Vocabulary {
    kinds: &["cloth", "pillar", "plate"],
    kind_groups: &[],
    attributes: &[Attribute {
        name: "side",
        plural: "cloth sides",
        words: &[("left", "left"), ("right", "right")],
        implies_kind: Some("cloth"),
        in_name: true,
    }],
    unfindable: &[],
    suffix: None,
};
