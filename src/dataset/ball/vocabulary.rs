//! The words of ball scenes (`soft_body`), as the paper's prompt lists them, plus the floating
//! walls the paper's questions name.

use crate::dataset::vocabulary::Vocabulary;

/// Ball scenes: balls, the sticks and floating walls they bounce off, and the pits they drop
/// into. Ramps and plain walls are seen but never asked about.
pub const VOCABULARY: Vocabulary = Vocabulary {
    kinds: &["ball", "stick", "pit", "floating wall"],
    kind_groups: &[],
    attributes: &[],
    unfindable: &["wall", "ramp"],
    suffix: None,
};
