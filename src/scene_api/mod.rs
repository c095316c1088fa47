//! The Rust side of the program API (`api_spec/`, the paper's listing `tb:oracle_prompt`):
//! scenes, objects, property queries, events and dynamic predictions.
//!
//! Input: a [`VideoSpec`] (video folder, scenario, perception and dynamics backends). Output:
//! plain Rust values ([`ObjectId`]s, numbers, booleans) or an [`ApiError`] whose message tells a
//! program's author what is allowed. The Python classes that wrap this live in `sandbox`.
//!
//! A [`Scene`] is lazy and memoised: opening one reads nothing; the first call that needs the
//! annotations loads them once, and every result is computed once. Each scene counts its own work
//! ([`WorkCounters`]) so a prediction can show what it cost (DESIGN.md §2).

mod error;
mod mechanism_check;
mod object;
mod perceived;
mod perceived_rope;
mod rope;
pub mod rope_sim;
mod rope_topology;
mod scene;
mod vocabulary;

pub use error::ApiError;
pub use mechanism_check::{MATCH_RADIUS, MechanismCheck, check_rope_mechanism};
pub use object::{ObjectId, SceneObjectInfo};
pub use scene::{
    DynamicsBackend, EventAction, PerceptionBackend, PerceptionModels, Property, Scene, SceneEvent,
    Target, VideoSpec, WorkCounters,
};
pub use vocabulary::{COLOR_NAMES, NameQuery, parse_object_query};
