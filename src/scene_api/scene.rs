//! [`Scene`]: one video's lazily loaded, memoised scene and the API calls on it.

use std::path::PathBuf;
use std::sync::{Mutex, OnceLock};

use serde::{Deserialize, Serialize};

use super::error::{ApiError, misuse};
use super::object::{ObjectId, SceneObjectInfo};
use super::rope::RopeBackend;
use super::vocabulary::parse_object_query;
use crate::dataset::{Scenario, VideoFolder};

/// Where objects, masks and tracks come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum PerceptionBackend {
    /// Read from `outputs.json` (the paper's oracle perception).
    #[default]
    Annotation,
    /// The Mask R-CNN ONNX model run on the video's frames (`perception::detector`), objects
    /// tracked across frames and named by their colour and class.
    #[serde(rename = "maskrcnn")]
    MaskRcnn,
}

/// The model files `--perception maskrcnn` runs.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PerceptionModels {
    /// The Mask R-CNN ONNX model.
    pub detector: PathBuf,
    /// The colour model (`perception fit-colors`).
    pub colors: PathBuf,
}

impl Default for PerceptionModels {
    fn default() -> Self {
        PerceptionModels {
            detector: PathBuf::from("models/maskrcnn-rope.onnx"),
            colors: PathBuf::from("models/color-model.json"),
        }
    }
}

/// Where dynamics answers come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum DynamicsBackend {
    /// Read from the counterfactual and factual result annotations (the paper's offline mode).
    #[default]
    Annotation,
    /// Simulated from the mechanism rebuilt from the video (rope: `physics::rope`), as ContPRO
    /// does.
    Simulate,
}

/// Everything needed to open a scene; sent to sandbox workers as JSON.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct VideoSpec {
    /// The video folder.
    pub video_dir: PathBuf,
    /// The video id (its folder name), as `SoftScene(..., video_id=...)` reports it.
    pub video_id: String,
    /// The scenario of the video.
    pub scenario: Scenario,
    /// The perception backend.
    pub perception: PerceptionBackend,
    /// The dynamics backend.
    pub dynamics: DynamicsBackend,
    /// The models of `--perception maskrcnn`.
    #[serde(default)]
    pub models: PerceptionModels,
}

impl VideoSpec {
    /// A spec for `video` with the given backends.
    pub fn new(
        video: &VideoFolder,
        perception: PerceptionBackend,
        dynamics: DynamicsBackend,
    ) -> Self {
        VideoSpec {
            video_dir: video.dir.clone(),
            video_id: video.id.0.clone(),
            scenario: video.scenario,
            perception,
            dynamics,
            models: PerceptionModels::default(),
        }
    }

    /// The spec with `models` for `--perception maskrcnn`.
    #[must_use]
    pub fn with_models(mut self, models: PerceptionModels) -> Self {
        self.models = models;
        self
    }
}

/// Work done on behalf of programs, so a prediction shows what it cost and a property question
/// can be checked to have run no simulation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct WorkCounters {
    /// Annotation files parsed.
    pub annotation_loads: u64,
    /// Video frames decoded.
    pub frames_decoded: u64,
    /// Object detections run (frames through the detector).
    pub detections: u64,
    /// Simulator runs.
    pub sim_runs: u64,
    /// Simulator steps over all runs.
    pub sim_steps: u64,
    /// Scene API calls made by programs.
    pub api_calls: u64,
}

impl WorkCounters {
    /// `self - earlier`, field by field: the work done between two snapshots.
    #[must_use]
    pub fn since(&self, earlier: &WorkCounters) -> WorkCounters {
        WorkCounters {
            annotation_loads: self
                .annotation_loads
                .saturating_sub(earlier.annotation_loads),
            frames_decoded: self.frames_decoded.saturating_sub(earlier.frames_decoded),
            detections: self.detections.saturating_sub(earlier.detections),
            sim_runs: self.sim_runs.saturating_sub(earlier.sim_runs),
            sim_steps: self.sim_steps.saturating_sub(earlier.sim_steps),
            api_calls: self.api_calls.saturating_sub(earlier.api_calls),
        }
    }
}

/// A queryable physical property.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Property {
    /// Load mass, kg.
    Mass,
    /// Rope tension, N.
    Tension,
    /// Fluid density, kg/m³.
    Density,
    /// Elasticity (cloth stretch, ball elasticity).
    Elasticity,
    /// Ball plasticity.
    Plasticity,
    /// Cloth bending.
    Bending,
}

impl Property {
    const ALL: [(&'static str, Property); 6] = [
        ("mass", Property::Mass),
        ("tension", Property::Tension),
        ("density", Property::Density),
        ("elasticity", Property::Elasticity),
        ("plasticity", Property::Plasticity),
        ("bending", Property::Bending),
    ];

    /// Parses a property name, explaining the allowed ones on failure.
    pub fn parse(text: &str, function: &str) -> Result<Property, ApiError> {
        let lower = text.trim().to_lowercase();
        Property::ALL.iter().find(|(name, _)| *name == lower).map(|(_, p)| *p).ok_or_else(|| {
            misuse(format!(
                "{function}: unknown property `{text}`; properties are mass, tension, density, elasticity, plasticity, bending"
            ))
        })
    }

    /// The property's name.
    pub fn name(self) -> &'static str {
        Property::ALL
            .iter()
            .find(|(_, p)| *p == self)
            .map_or("?", |(name, _)| name)
    }
}

/// The action of an event that starts a dynamic scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EventAction {
    /// Increase a property (rope: a load's mass).
    Increase,
    /// Decrease a property.
    Decrease,
    /// Emit (fluid).
    Emit,
    /// Remove an object (fluid sticks, ball walls).
    Remove,
    /// Simulate the factual future (predictive questions).
    Simulate,
}

impl EventAction {
    /// Parses an action; the paper's listing spells increase `increse` once, which is accepted.
    pub fn parse(text: &str) -> Result<EventAction, ApiError> {
        match text.trim().to_lowercase().as_str() {
            "increase" | "increse" => Ok(EventAction::Increase),
            "decrease" => Ok(EventAction::Decrease),
            "emit" => Ok(EventAction::Emit),
            "remove" => Ok(EventAction::Remove),
            "simulate" => Ok(EventAction::Simulate),
            _ => Err(misuse(format!(
                "register_event: unknown action `{text}`; actions are increase, decrease, emit, remove, simulate"
            ))),
        }
    }
}

/// An event registered on a scene (`register_event`), the start of a dynamic scene.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SceneEvent {
    /// What happens.
    pub action: EventAction,
    /// The object it happens to (none for `simulate`, or `remove` by description).
    pub object: Option<ObjectId>,
    /// The attribute (`mass`, `fluid`, a description such as `green stick`, or empty).
    pub attribute: String,
    /// Objects named by the attribute, when it was given as objects.
    pub attribute_objects: Vec<ObjectId>,
}

/// The target of `happen`: a word (`up`, `clockwise`) or objects (`[red_container]`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Target {
    /// A word or phrase; may be empty.
    Text(String),
    /// Objects.
    Objects(Vec<ObjectId>),
}

/// The per-scenario implementation behind a [`Scene`].
pub(crate) trait ScenarioBackend: Send + Sync {
    /// The scene's objects, in a fixed order; `ObjectId(i)` is element `i`.
    fn objects(&self) -> &[SceneObjectInfo];
    /// Property values of one or two objects; two `None`s when the video cannot compare them.
    fn query(
        &self,
        property: Property,
        objects: &[ObjectId],
        function: &str,
    ) -> Result<Vec<Option<f64>>, ApiError>;
    /// Validates an event for this scenario.
    fn check_event(&self, event: &SceneEvent) -> Result<(), ApiError>;
    /// Whether `action`/`target` happens to `object` in the dynamic scene started by `event`.
    fn happen(
        &self,
        event: &SceneEvent,
        object: ObjectId,
        action: &str,
        target: &Target,
    ) -> Result<bool, ApiError>;
    /// Simulator runs and steps this backend has done (0 for oracle backends).
    fn simulation_work(&self) -> (u64, u64) {
        (0, 0)
    }
    /// Frames decoded and run through the detector (0 without `--perception maskrcnn`).
    fn perception_work(&self) -> (u64, u64) {
        (0, 0)
    }
}

/// One video's scene. Opening reads nothing; the first call that needs data loads it once.
pub struct Scene {
    spec: VideoSpec,
    backend: OnceLock<Result<Box<dyn ScenarioBackend>, ApiError>>,
    work: Mutex<WorkCounters>,
}

impl std::fmt::Debug for Scene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Scene")
            .field("spec", &self.spec)
            .field("loaded", &self.backend.get().is_some())
            .finish_non_exhaustive()
    }
}

impl Scene {
    /// A scene for `spec`; nothing is read yet.
    pub fn open(spec: VideoSpec) -> Scene {
        Scene {
            spec,
            backend: OnceLock::new(),
            work: Mutex::new(WorkCounters::default()),
        }
    }

    /// The spec it was opened with.
    pub fn spec(&self) -> &VideoSpec {
        &self.spec
    }

    /// The work done so far on this scene.
    pub fn work(&self) -> WorkCounters {
        let mut work = self.work.lock().map(|w| *w).unwrap_or_default();
        if let Some(Ok(backend)) = self.backend.get() {
            let (runs, steps) = backend.simulation_work();
            work.sim_runs += runs;
            work.sim_steps += steps;
            let (frames, detections) = backend.perception_work();
            work.frames_decoded += frames;
            work.detections += detections;
        }
        work
    }

    fn count(&self, update: impl FnOnce(&mut WorkCounters)) {
        if let Ok(mut work) = self.work.lock() {
            update(&mut work);
        }
    }

    fn backend(&self) -> Result<&dyn ScenarioBackend, ApiError> {
        let loaded = self.backend.get_or_init(|| {
            self.count(|w| w.annotation_loads += 1);
            load_backend(&self.spec)
        });
        match loaded {
            Ok(backend) => Ok(backend.as_ref()),
            Err(error) => Err(error.clone()),
        }
    }

    /// All objects of the scene.
    pub fn objects(&self) -> Result<&[SceneObjectInfo], ApiError> {
        Ok(self.backend()?.objects())
    }

    /// The object with `id`.
    pub fn object(&self, id: ObjectId) -> Result<&SceneObjectInfo, ApiError> {
        self.objects()?
            .get(id.0 as usize)
            .ok_or_else(|| misuse(format!("object #{} does not belong to this scene", id.0)))
    }

    /// `find(name)`: the objects matching every colour, kind, shape, dynamics and grid word of
    /// `name`, in scene order; empty when nothing matches.
    pub fn find(&self, name: &str) -> Result<Vec<ObjectId>, ApiError> {
        self.count(|w| w.api_calls += 1);
        let query = parse_object_query(name, self.spec.scenario)?;
        if query.foreign_kind {
            return Ok(Vec::new());
        }
        let objects = self.objects()?;
        Ok(objects
            .iter()
            .filter(|o| o.visible)
            .filter(|o| query.color.as_ref().is_none_or(|c| *c == o.color))
            .filter(|o| match query.kind.as_deref() {
                None => true,
                Some("load") => o.kind == "cube" || o.kind == "sphere",
                Some(kind) => o.kind == kind,
            })
            .filter(|o| {
                query
                    .shape
                    .as_ref()
                    .is_none_or(|s| o.shape.as_ref() == Some(s))
            })
            .filter(|o| query.dynamics.as_ref().is_none_or(|d| *d == o.dynamics))
            .filter(|o| query.grid.is_none_or(|g| o.grid == Some(g)))
            .map(|o| o.id)
            .collect())
    }

    /// `query_single(property, object)`: the property value, or `None` when the object does not
    /// have it or the video cannot tell.
    pub fn query_single(&self, property: &str, object: ObjectId) -> Result<Option<f64>, ApiError> {
        self.count(|w| w.api_calls += 1);
        let property = Property::parse(property, "query_single")?;
        let values = self.backend()?.query(property, &[object], "query_single")?;
        Ok(values.first().copied().flatten())
    }

    /// `query_pair(property, a, b)`: both values, with their true ratio, or `(None, None)` when
    /// the video cannot compare them.
    pub fn query_pair(
        &self,
        property: &str,
        first: ObjectId,
        second: ObjectId,
    ) -> Result<(Option<f64>, Option<f64>), ApiError> {
        self.count(|w| w.api_calls += 1);
        let property = Property::parse(property, "query_pair")?;
        let values = self
            .backend()?
            .query(property, &[first, second], "query_pair")?;
        match values.as_slice() {
            [a, b] => Ok((*a, *b)),
            _ => Ok((None, None)),
        }
    }

    /// `register_event(objects, action, attribute)`.
    pub fn register_event(
        &self,
        objects: &[ObjectId],
        action: &str,
        attribute: &str,
        attribute_objects: Vec<ObjectId>,
    ) -> Result<SceneEvent, ApiError> {
        self.count(|w| w.api_calls += 1);
        let action = EventAction::parse(action)?;
        if objects.len() > 1 {
            return Err(misuse(format!(
                "register_event: one object at a time, got {}; register one event per object",
                objects.len()
            )));
        }
        let event = SceneEvent {
            action,
            object: objects.first().copied(),
            attribute: attribute.trim().to_lowercase(),
            attribute_objects,
        };
        self.backend()?.check_event(&event)?;
        Ok(event)
    }

    /// `SoftDynamicScene.happen(objects, action, target)`.
    pub fn happen(
        &self,
        event: &SceneEvent,
        objects: &[ObjectId],
        action: &str,
        target: &Target,
    ) -> Result<bool, ApiError> {
        self.count(|w| w.api_calls += 1);
        let [object] = objects else {
            return Err(misuse(format!(
                "happen: ask about one object at a time, got {}; e.g. happen([cube], 'motion', 'up')",
                objects.len()
            )));
        };
        self.backend()?
            .happen(event, *object, &action.trim().to_lowercase(), target)
    }
}

fn load_backend(spec: &VideoSpec) -> Result<Box<dyn ScenarioBackend>, ApiError> {
    match spec.scenario {
        Scenario::Rope => Ok(Box::new(RopeBackend::load(spec)?)),
        other => Err(ApiError::Unavailable(format!(
            "the {other} scene API has no backend yet; only rope scenes can be answered in this version"
        ))),
    }
}
