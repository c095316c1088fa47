//! The words of ball scenes (`soft_body`), as the paper's prompt lists them, plus the floating
//! walls the paper's questions name, the ramps, and the side that tells the two pits (and the
//! two ramps) apart.

use crate::dataset::vocabulary::{Attribute, Vocabulary};

/// Ball scenes: balls, the sticks and floating walls they bounce off, the ramps they roll down,
/// and the pits they drop into. Pits and ramps carry their `side`, `left` or `right`
/// (`find("left pit")`, `find("right ramp")`; a side alone means a pit). The paper's prompt
/// lists sticks, which ball scenes have none of; plain walls are never asked about.
pub const VOCABULARY: Vocabulary = Vocabulary {
    kinds: &["ball", "stick", "pit", "floating wall", "ramp"],
    kind_groups: &[],
    attributes: &[Attribute {
        name: "side",
        plural: "pit sides",
        words: &[("left", "left"), ("right", "right")],
        implies_kind: Some("pit"),
        in_name: true,
    }],
    unfindable: &["wall"],
    suffix: None,
};
