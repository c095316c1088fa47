//! Shared low-level helpers: stable content hashing, seed derivation, crash-safe file writes and
//! `.npy` point arrays.
//!
//! Inputs are bytes, JSON values and paths; outputs are hex digests, seeded RNGs and files on disk.
//! This module depends on nothing else in the crate (layer 0 of `docs/architecture.md`, layers).

mod fs;
mod hash;
pub mod npy;
mod seed;

pub use fs::{FsError, append_line_durable, write_atomic};
pub use hash::{canonical_json, content_hash, content_hash_json};
pub use seed::{derive_seed, seeded_rng, standard_normal};
