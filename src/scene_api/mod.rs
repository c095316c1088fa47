//! The Rust side of the program API (`api_spec/`, the paper's listing `tb:oracle_prompt`):
//! scenes, objects, property queries, events and dynamic predictions.
//!
//! Input: a [`VideoSpec`] (video folder, scenario, perception and dynamics backends) and the
//! scenario's [`SceneParts`] (its vocabulary and backend, from the scenario table). Output: plain
//! Rust values ([`ObjectId`]s, numbers, booleans) or an [`ApiError`] whose message tells a
//! program's author what is allowed. The Python classes that wrap this live in `sandbox`.
//!
//! A [`Scene`] is lazy and memoised: opening one reads nothing; the first call that needs the
//! annotations loads its scenario's backend once, and every result is computed once. Each scene
//! counts its own work ([`WorkCounters`]) so a prediction can show what it cost.
//!
//! Shared here: scenes, objects, `find`'s parser, the detector-backed [`perceiver`] and the
//! frames it keeps for the viewer (`overlays`). Each scenario's backend lives in
//! `scene_api/<scenario>/`.

pub mod ball;
pub mod cloth;
mod error;
mod find;
pub mod fluid;
mod object;
mod overlays;
pub mod perceiver;
pub mod rope;
mod scene;

pub use error::ApiError;
pub(crate) use error::{misuse, named_nothing, unknown_action};
pub(crate) use find::resolve_description;
pub use find::{NameQuery, Words, parse_object_query};
pub use object::{ObjectAttribute, ObjectId, SceneObjectInfo};
pub use scene::{
    BackendLoader, DynamicsBackend, EventAction, InferenceBench, PerceptionBackend,
    PerceptionModels, Property, ReadingCheck, ScenarioBackend, Scene, SceneEvent, SceneParts,
    Target, VideoSpec, WorkCounters,
};

#[cfg(test)]
pub(crate) mod test_support {
    //! Test helpers of the scenario backends: a scene over a fixture video with the parts the
    //! scenario table gives its scenario (its vocabulary, every scenario's, its backend).

    use std::path::PathBuf;

    use crate::dataset::{Scenario, VideoFolder, VideoId, Vocabulary, ball, cloth, fluid, rope};
    use crate::scene_api::{
        BackendLoader, DynamicsBackend, PerceptionBackend, Scene, SceneParts, VideoSpec,
    };

    /// Every scenario's vocabulary, in the scenario table's order.
    pub(crate) const ALL_VOCABULARIES: [&Vocabulary; 4] = [
        &rope::VOCABULARY,
        &fluid::VOCABULARY,
        &cloth::VOCABULARY,
        &ball::VOCABULARY,
    ];

    /// The scene of video `0` of `scenario` in `dir`, with the scenario's `vocabulary` and
    /// `backend`.
    pub(crate) fn open_scene(
        scenario: Scenario,
        dir: PathBuf,
        (vocabulary, backend): (&'static Vocabulary, BackendLoader),
        perception: PerceptionBackend,
        dynamics: DynamicsBackend,
    ) -> Scene {
        let video = VideoFolder {
            scenario,
            id: VideoId("0".into()),
            dir,
        };
        Scene::open(
            VideoSpec::new(&video, perception, dynamics),
            SceneParts {
                vocabulary,
                all_vocabularies: &ALL_VOCABULARIES,
                backend: Some(backend),
            },
        )
    }
}
