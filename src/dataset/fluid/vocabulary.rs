//! The words of fluid scenes (`fluid_slides`), as the paper's prompt lists them, plus the words
//! that tell a fluid's two emitters apart.

use crate::dataset::vocabulary::{Attribute, Vocabulary};

/// Fluid scenes: fluids, the containers they flow into, sticks and emitters. Emitters carry
/// their `emission`: `first` for the emitter that opens at the start of the video, `later` for
/// a fluid's second emitter, which opens some 20 frames before the video ends (`Later Emitted
/// <C> Fluid Emitter`, the paper's "the other yellow emitter": `find("other yellow emitter")`).
pub const VOCABULARY: Vocabulary = Vocabulary {
    kinds: &["fluid", "container", "stick", "emitter"],
    kind_groups: &[],
    attributes: &[Attribute {
        name: "emission",
        plural: "emitter emissions",
        words: &[
            ("first", "first"),
            ("original", "first"),
            ("later", "later"),
            ("other", "later"),
            ("second", "later"),
            ("predictive", "later"),
        ],
        implies_kind: Some("emitter"),
        in_name: true,
    }],
    unfindable: &[],
    suffix: None,
};
