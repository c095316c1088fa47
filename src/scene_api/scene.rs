//! [`Scene`]: one video's lazily loaded, memoised scene and the API calls on it.

use std::path::PathBuf;
use std::sync::{Mutex, OnceLock};

use serde::{Deserialize, Serialize};

use super::error::{ApiError, misuse};
use super::find::{Words, parse_object_query};
use super::object::{ObjectId, SceneObjectInfo};
use crate::dataset::{Scenario, VideoFolder, Vocabulary};

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

/// The model files `--perception maskrcnn` runs (the scenario's defaults from the scenario
/// table, or the command line's).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct PerceptionModels {
    /// The Mask R-CNN ONNX model (its class description is the `.json` beside it).
    pub detector: PathBuf,
    /// The colour model (`perception fit-colors`).
    pub colors: PathBuf,
}

/// Where dynamics answers come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum DynamicsBackend {
    /// Read from the counterfactual and factual result annotations (the paper's offline mode).
    #[default]
    Annotation,
    /// Simulated from the scene rebuilt from the video with the scenario's simulator, as
    /// ContPRO does.
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
    /// The models of `--perception maskrcnn`; `None` for a scenario without perception.
    pub models: Option<PerceptionModels>,
    /// Where perception writes the frames it read with its detections drawn on them, for the
    /// run viewer (`RUN/frames/<scenario>/<video>/`); `None`: nowhere.
    #[serde(default)]
    pub overlays: Option<PathBuf>,
}

impl VideoSpec {
    /// A spec for `video` with the given backends and no perception models.
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
            models: None,
            overlays: None,
        }
    }

    /// The spec with `models` for `--perception maskrcnn`.
    #[must_use]
    pub fn with_models(mut self, models: Option<PerceptionModels>) -> Self {
        self.models = models;
        self
    }

    /// The spec writing perception's frames into `dir` (see [`VideoSpec::overlays`]).
    #[must_use]
    pub fn with_overlays(mut self, dir: Option<PathBuf>) -> Self {
        self.overlays = dir;
        self
    }

    /// The models of `--perception maskrcnn`, or the error a backend reports without them.
    pub fn perception_models(&self) -> Result<&PerceptionModels, ApiError> {
        self.models.as_ref().ok_or_else(|| {
            ApiError::Unavailable(format!(
                "perception (maskrcnn): there are no models for {} scenes",
                self.scenario
            ))
        })
    }
}

/// Loads the backend of one video of a scenario.
pub type BackendLoader = fn(&VideoSpec) -> Result<Box<dyn ScenarioBackend>, ApiError>;

/// A scenario's check of what perception reads of its scenes against their annotations (rope:
/// the mechanism), for `bench perception`: a JSON report over the videos.
pub type ReadingCheck =
    fn(&[VideoFolder], &PerceptionModels) -> Result<serde_json::Value, ApiError>;

/// A scenario's check of properties inferred from its videos against their annotations, for
/// `bench inference`: the valid videos and the noise levels (standard deviations, units) added
/// to the tracks, to a JSON report.
pub type InferenceBench = fn(&[VideoFolder], &[f64]) -> Result<serde_json::Value, ApiError>;

/// What the scene API needs of a scenario (its row of the scenario table): its words and its
/// backend.
#[derive(Debug, Clone, Copy)]
pub struct SceneParts {
    /// The scenario's vocabulary.
    pub vocabulary: &'static Vocabulary,
    /// Every scenario's vocabulary, for words that name other scenarios' objects.
    pub all_vocabularies: &'static [&'static Vocabulary],
    /// Its backend; `None` for a scenario without one yet.
    pub backend: Option<BackendLoader>,
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
    /// Adds `other`, field by field: the work of several units together.
    pub fn add(&mut self, other: &WorkCounters) {
        self.annotation_loads += other.annotation_loads;
        self.frames_decoded += other.frames_decoded;
        self.detections += other.detections;
        self.sim_runs += other.sim_runs;
        self.sim_steps += other.sim_steps;
        self.api_calls += other.api_calls;
    }

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

/// The per-scenario implementation behind a [`Scene`] (`scene_api/<scenario>/`).
pub trait ScenarioBackend: Send + Sync {
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
    /// The final pose of `object` in the dynamic scene started by `event`, in the words the
    /// scenario's pose questions offer (`SoftDynamicScene.final_pose`); `Ok(None)` when the
    /// scenario's objects have no pose to ask about.
    fn final_pose(&self, event: &SceneEvent, object: ObjectId) -> Result<Option<String>, ApiError> {
        let _ = (event, object);
        Ok(None)
    }
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
    parts: SceneParts,
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
    /// A scene for `spec`, answered by its scenario's `parts`; nothing is read yet.
    pub fn open(spec: VideoSpec, parts: SceneParts) -> Scene {
        Scene {
            spec,
            parts,
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
            match self.parts.backend {
                Some(load) => load(&self.spec),
                None => Err(ApiError::Unavailable(format!(
                    "the {} scene API has no backend yet",
                    self.spec.scenario
                ))),
            }
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

    /// `find(name)`: the objects matching every colour, kind and attribute word of `name`, in
    /// scene order; when none matches and `name` has a colour, the object perception gave that
    /// colour as its likeliest second choice ([`SceneObjectInfo::other_colors`]); else empty.
    pub fn find(&self, name: &str) -> Result<Vec<ObjectId>, ApiError> {
        self.count(|w| w.api_calls += 1);
        let words = Words {
            scenario: self.spec.scenario.name(),
            own: self.parts.vocabulary,
            all: self.parts.all_vocabularies,
        };
        let query = parse_object_query(name, words)?;
        if query.foreign_kind {
            return Ok(Vec::new());
        }
        let vocabulary = self.parts.vocabulary;
        let objects = self.objects()?;
        let found: Vec<ObjectId> = objects
            .iter()
            .filter(|object| query.matches(object, vocabulary))
            .map(|object| object.id)
            .collect();
        if !found.is_empty() || query.color.is_none() {
            return Ok(found);
        }
        Ok(query
            .second_choice_object(objects, vocabulary)
            .into_iter()
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
            let mut message = format!(
                "happen: ask about one object at a time, got {}; e.g. happen([cube], 'motion', 'up')",
                objects.len()
            );
            if objects.len() > 1 {
                // The paper's listings once pass both objects of a relation (`touching`).
                message.push_str(
                    "; a relation between two objects names the second as the target: happen([a], 'touching', [b])",
                );
            }
            // An empty list is what `find` gives for a name no object carries.
            return Err(if objects.is_empty() {
                super::error::named_nothing(
                    message,
                    self.spec.perception != PerceptionBackend::Annotation,
                )
            } else {
                misuse(message)
            });
        };
        self.backend()?
            .happen(event, *object, &action.trim().to_lowercase(), target)
    }

    /// `SoftDynamicScene.final_pose(object)`: how `object` ends in the dynamic scene `event`
    /// starts, in the words of the scenario's pose questions.
    pub fn final_pose(&self, event: &SceneEvent, object: ObjectId) -> Result<String, ApiError> {
        self.count(|w| w.api_calls += 1);
        self.backend()?.final_pose(event, object)?.ok_or_else(|| {
            misuse(format!(
                "final_pose: the objects of {} scenes have no final pose to ask about; use happen",
                self.spec.scenario
            ))
        })
    }
}
