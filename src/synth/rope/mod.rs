//! Rope–pulley scenes (`pulley_group`, FORMAT.md §2): layouts sampled as the release samples
//! them, simulated with `physics::rope`, described for rendering and written in the release's
//! format.

pub mod layout;
