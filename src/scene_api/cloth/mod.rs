//! The cloth scene (`cloth_collision`): objects from the annotation's boxes and the two cloths;
//! cloth properties and what happens to the boxes under the cloth from its records
//! (`--dynamics annotation`, the paper's offline mode) or from the video and a simulation
//! (`--dynamics simulate`).
//!
//! Input: a video's `outputs.json` ([`ClothAnnotation`]); under `--dynamics simulate` also its
//! tracked particles (`outputs4D.json`). Output: the scene's objects and the answers of `query`,
//! `register_event`, `happen` and `final_pose` (`docs/data/cloth.md`). Under `--dynamics
//! simulate` the cloths' properties are read from their particles ([`infer`]) and each half is
//! simulated ([`simulate`]) on the first question about one of its boxes (`runs`); of the
//! annotation only the boxes' sizes, shapes and start poses are read (what the first frames
//! show). Under `--perception maskrcnn` the detector's masks give the pillars and plates
//! (`perceived`: placed through the camera, named by colour and shape) and, under `--dynamics
//! simulate`, what the cloths do (`pixels`: spawn, pull, properties) and which boxes stand
//! still (`motion`: those get their pool's immovable mass); of
//! the annotation only the camera calibration is read (with `--dynamics annotation`, also the
//! recorded outcomes, keyed by the names perception must read right).
//!
//! Objects, in this order: the two cloths (`Cloth (Left)`, `Cloth (Right)`: kind `cloth`, no
//! colour, `side` left or right, so `left cloth`), then every pillar and plate of the left half
//! and of the right half in file order (`Green Plate`: kind `plate`, colour `green`). Cubes (tower
//! layers the release practically never leaves unmerged) are not objects: no question or scene
//! word names them.
//!
//! Under `--dynamics annotation`, answers agree with the question engine
//! (`dataset::engine::cloth`) by construction, reading the same keys with the same shared rules
//! (under `--dynamics simulate` the same rules read the simulated run, and a box the simulation
//! leaves leaning has fallen over when it tilts past 45°):
//!
//! * `elasticity` of a cloth is its `stretchingCompliance` (0.011 stretches, 0 does not: the
//!   larger is the more elastic); `bending` is its `bendingCompliance`, really the maximum
//!   bending (0.035 against 0.013: the larger bends and wrinkles more easily). Both are the
//!   release's values, so `query_pair` always compares the two cloths.
//! * events: `register_event([], 'simulate', '')` is the video's own future, the only run a
//!   cloth video has.
//! * `happen([box], 'falling', '')`: the box's end pose says it fell over
//!   ([`Pose::fell_over`]); a box that ends leaning (`Reclining`) decides neither way, which is
//!   [`ApiError::Unavailable`].
//! * `happen([box], 'collision' | 'touching', [other box])`: either box's records name the
//!   other ([`ClothAnnotation::collided`], [`ClothAnnotation::in_touch`]).
//! * `final_pose(box)`: the option phrase of its end pose ([`Pose::phrase`]), the words the
//!   pose questions offer.

pub mod infer;
mod inference_bench;
mod motion;
mod perceived;
pub(crate) mod physics_bench;
mod pixels;
mod reading_check;
mod runs;
pub mod simulate;
#[cfg(test)]
mod tests;

use crate::dataset::Scenario;
use crate::dataset::cloth::names::{Shape, Side, parse_box_name};
use crate::dataset::cloth::outcome::Pose;
use crate::dataset::cloth::{BoxRecord, ClothAnnotation, ClothProperties, VALUES, VOCABULARY};
use crate::perception::cloth::PERCEPTION;
use crate::physics::vector3 as v3;
use crate::scene_api::perceiver::{Perceiver, calibration};
use crate::scene_api::{
    ApiError, DynamicsBackend, EventAction, ObjectId, PerceptionBackend, Property, ScenarioBackend,
    SceneEvent, SceneObjectInfo, Target, VideoSpec, misuse, named_nothing, resolve_description,
    unknown_action,
};
pub use inference_bench::inference_report;
pub use reading_check::scene_report;
use runs::ClothRuns;
use simulate::{ClothModel, HalfRun};

/// The vocabulary attribute that tells the cloths apart.
const SIDE: &str = "side";
/// What messages call the objects `happen` and `final_pose` ask about.
const BOXES: &str = "pillar or plate";

/// Loads the backend of a cloth video (the scenario table's scene backend for cloth).
pub fn load(spec: &VideoSpec) -> Result<Box<dyn ScenarioBackend>, ApiError> {
    let annotation = ClothAnnotation::load(&spec.video_dir.join("outputs.json"))?;
    if spec.perception == PerceptionBackend::Annotation {
        let mut backend = ClothBackend::new(annotation);
        if spec.dynamics == DynamicsBackend::Simulate {
            backend.runs = Some(ClothRuns::new(
                spec.video_dir.clone(),
                ClothModel::default(),
            ));
        }
        return Ok(Box::new(backend));
    }
    // `--perception maskrcnn`: of the annotation only the camera calibration is read, unless
    // the dynamics are the annotation's (whose recorded outcomes are keyed by its names).
    let camera = calibration(annotation.camera.as_ref())?.clone();
    let mut perceiver = Perceiver::open_for(spec, PERCEPTION.classes, &VOCABULARY)?;
    let perceived = perceived::perceive_scene(&mut perceiver, &camera)?;
    perceiver.set_names(perceived.names.clone());
    let backend = match spec.dynamics {
        DynamicsBackend::Simulate => {
            let mut backend = ClothBackend::new(perceived.annotation.clone());
            backend.unread = perceived.unknown;
            backend.from_pixels = true;
            backend.runs = Some(ClothRuns::perceived(
                perceiver,
                camera,
                perceived.annotation.clone(),
                ClothModel::default(),
            ));
            backend
        }
        DynamicsBackend::Annotation => {
            // The boxes perception did not read (another colour or shape, not seen) are not
            // the annotated ones, whose outcomes are keyed by name; the cloths are always seen.
            let mut backend = ClothBackend::new(annotation);
            backend.from_pixels = true;
            backend.load_work = perceiver.work();
            for object in &mut backend.objects {
                object.visible =
                    object.kind == "cloth" || perceived.annotation.find_box(&object.name).is_some();
            }
            backend
        }
    };
    Ok(Box::new(backend))
}

/// What an object of the scene stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    /// The cloth of this half.
    Cloth(Side),
    /// A pillar or plate (its record is found by the object's name).
    Box,
}

/// A relation between two boxes that `happen` answers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Relation {
    /// The boxes collide at some point (`collisionEvents`).
    Collision,
    /// The boxes are in touch at the end (`touchers`).
    Touch,
}

impl Relation {
    /// The action word programs use.
    fn word(self) -> &'static str {
        match self {
            Relation::Collision => "collision",
            Relation::Touch => "touching",
        }
    }
}

/// What `happen` is asked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Question {
    /// Does the box fall over.
    Fall,
    /// Does the relation hold between the box and the target.
    Between(Relation),
}

/// One cloth video's answers, from its annotations or (`--dynamics simulate`) its runs.
pub(crate) struct ClothBackend {
    annotation: ClothAnnotation,
    objects: Vec<SceneObjectInfo>,
    roles: Vec<Role>,
    /// Under `--dynamics simulate`, the video's simulation (its parts made on first use);
    /// `None` answers from the annotation's records.
    runs: Option<ClothRuns>,
    /// Under `--perception maskrcnn --dynamics simulate`, what perception could not read of
    /// the boxes (one line each), for messages.
    unread: Vec<String>,
    /// Whether the objects were read from pixels (`--perception maskrcnn`): a name no object
    /// carries may then be a perception miss (`not_seen`) rather than the program's misuse.
    from_pixels: bool,
    /// Frames decoded and run through the detector at load, where the perceiver is not kept
    /// (`--perception maskrcnn --dynamics annotation`).
    load_work: (u64, u64),
}

impl ClothBackend {
    /// The backend of `annotation`.
    pub(crate) fn new(annotation: ClothAnnotation) -> ClothBackend {
        let mut named: Vec<(String, String, &'static str, Role)> = Side::BOTH
            .into_iter()
            .map(|side| {
                (
                    side.cloth_name().to_string(),
                    String::new(),
                    "cloth",
                    Role::Cloth(side),
                )
            })
            .collect();
        for (_, record) in annotation.boxes() {
            let Some(parsed) = parse_box_name(&record.name) else {
                continue;
            };
            let kind = match parsed.shape {
                Shape::Pillar => "pillar",
                Shape::Plate => "plate",
                Shape::Cube => continue,
            };
            named.push((
                record.name.clone(),
                parsed.color.to_lowercase(),
                kind,
                Role::Box,
            ));
        }
        let (objects, roles) = named
            .into_iter()
            .enumerate()
            .map(|(index, (name, color, kind, role))| {
                let attributes = match role {
                    Role::Cloth(side) => vec![(SIDE, side.word().to_string())],
                    Role::Box => Vec::new(),
                };
                let object = SceneObjectInfo::new(
                    ObjectId(u32::try_from(index).unwrap_or(u32::MAX)),
                    &name,
                    &color,
                    kind,
                    &attributes,
                    &VOCABULARY,
                );
                (object, role)
            })
            .unzip();
        ClothBackend {
            annotation,
            objects,
            roles,
            runs: None,
            unread: Vec::new(),
            from_pixels: false,
            load_work: (0, 0),
        }
    }

    fn info(&self, id: ObjectId, function: &str) -> Result<&SceneObjectInfo, ApiError> {
        self.objects.get(id.0 as usize).ok_or_else(|| {
            misuse(format!(
                "{function}: object #{} does not belong to this scene",
                id.0
            ))
        })
    }

    fn role(&self, object: &SceneObjectInfo) -> Option<Role> {
        self.roles.get(object.id.0 as usize).copied()
    }

    /// The short names of the scene's pillars and plates, for messages.
    fn box_names(&self) -> String {
        let names: Vec<String> = self
            .objects
            .iter()
            .filter(|object| self.role(object) == Some(Role::Box))
            .map(SceneObjectInfo::describe)
            .collect();
        let unread = if self.unread.is_empty() {
            String::new()
        } else {
            format!(" (not read from the video: {})", self.unread.join("; "))
        };
        format!("the pillars and plates are: {}{unread}", names.join(", "))
    }

    /// The record of `object`, which must be a pillar or a plate; a message says `{function}:
    /// {what} a pillar or plate, not the <object>` (`what`: `'falling' asks about`).
    fn box_record(
        &self,
        object: &SceneObjectInfo,
        function: &str,
        what: &str,
    ) -> Result<&BoxRecord, ApiError> {
        if self.role(object) != Some(Role::Box) {
            return Err(misuse(format!(
                "{function}: {what} a {BOXES}, not the {}",
                object.describe()
            )));
        }
        self.annotation
            .find_box(&object.name)
            .map(|(_, record)| record)
            .ok_or_else(|| {
                ApiError::Unavailable(format!(
                    "{function}: the video has no record of the {}",
                    object.describe()
                ))
            })
    }

    /// The properties of the cloth `object`, for `function`'s `property`.
    fn cloth(
        &self,
        object: &SceneObjectInfo,
        property: Property,
        function: &str,
    ) -> Result<&ClothProperties, ApiError> {
        match self.role(object) {
            Some(Role::Cloth(side)) => Ok(self.annotation.cloth(side)),
            _ => Err(misuse(format!(
                "{function}: {} is a property of cloths, not of the {}; the cloths are the left cloth and the right cloth",
                property.name(),
                object.describe()
            ))),
        }
    }

    /// The box `happen`'s target names for `relation`.
    fn target_box(
        &self,
        target: &Target,
        relation: Relation,
    ) -> Result<&SceneObjectInfo, ApiError> {
        let word = relation.word();
        let ids = match target {
            Target::Objects(ids) => ids.clone(),
            Target::Text(text) if text.trim().is_empty() => {
                return Err(misuse(format!(
                    "happen: '{word}' needs the other {BOXES} as the target, e.g. happen([green_plate], '{word}', [gray_pillar]); {}",
                    self.box_names()
                )));
            }
            Target::Text(text) => {
                let (_, found) = resolve_description(
                    &self.objects,
                    Scenario::Cloth.name(),
                    &VOCABULARY,
                    text,
                    "happen",
                )?;
                if found.is_empty() {
                    return Err(named_nothing(
                        format!(
                            "happen: the target `{}` of '{word}' names no object of this scene; {}",
                            text.trim(),
                            self.box_names()
                        ),
                        self.from_pixels,
                    ));
                }
                found
            }
        };
        match ids.as_slice() {
            [one] => self.info(*one, "happen"),
            [] => Err(named_nothing(
                format!(
                    "happen: the target of '{word}' names no {BOXES} (an empty list: `find` found no such object); {}",
                    self.box_names()
                ),
                self.from_pixels,
            )),
            many => Err(misuse(format!(
                "happen: the target of '{word}' is one {BOXES}, got {} objects",
                many.len()
            ))),
        }
    }

    /// Whether `subject` falls over: its end pose by the shared rule.
    fn fell_over(&self, subject: &SceneObjectInfo, target: &Target) -> Result<bool, ApiError> {
        let record = self.box_record(subject, "happen", "'falling' asks about")?;
        let no_target = match target {
            Target::Text(text) => text.trim().is_empty(),
            Target::Objects(ids) => ids.is_empty(),
        };
        if !no_target {
            return Err(misuse(format!(
                "happen: 'falling' takes no target (''): it asks whether the {} itself falls over",
                subject.describe()
            )));
        }
        if let Some((run, index)) = self.simulated(subject)? {
            return Ok(simulated_fall(run, index));
        }
        record.end_pose.fell_over().ok_or_else(|| {
            ApiError::Unavailable(format!(
                "happen: the {} ends leaning, its top still pointing up (final_pose: \"{}\"): it has neither clearly fallen over nor stayed upright, so 'falling' has no answer",
                subject.describe(),
                record.end_pose.phrase()
            ))
        })
    }

    /// Whether `relation` holds between `subject` and the box `target` names.
    fn related(
        &self,
        subject: &SceneObjectInfo,
        relation: Relation,
        target: &Target,
    ) -> Result<bool, ApiError> {
        let word = relation.word();
        self.box_record(subject, "happen", &format!("'{word}' asks about"))?;
        let other = self.target_box(target, relation)?;
        self.box_record(other, "happen", &format!("the target of '{word}' must be"))?;
        if other.id == subject.id {
            return Err(misuse(format!(
                "happen: '{word}' relates two different objects; the target is the {} itself",
                subject.describe()
            )));
        }
        if let Some((run, first)) = self.simulated(subject)? {
            let same_half = self
                .annotation
                .find_box(&subject.name)
                .map(|(side, _)| side)
                == self.annotation.find_box(&other.name).map(|(side, _)| side);
            let Some(second) = self.half_index(other).filter(|_| same_half) else {
                // The halves stand 4.8 units apart: boxes of different halves never meet.
                return Ok(false);
            };
            let pair = (first.min(second), first.max(second));
            return Ok(match relation {
                Relation::Collision => run.collided.contains(&pair),
                Relation::Touch => run.touching.contains(&pair),
            });
        }
        Ok(match relation {
            Relation::Collision => self.annotation.collided(&subject.name, &other.name),
            Relation::Touch => self.annotation.in_touch(&subject.name, &other.name),
        })
    }

    /// The index of `object` among its half's boxes.
    fn half_index(&self, object: &SceneObjectInfo) -> Option<usize> {
        let (side, _) = self.annotation.find_box(&object.name)?;
        self.annotation
            .objects(side)
            .boxes()
            .position(|record| record.name == object.name)
    }

    /// Under `--dynamics simulate`, the simulated run of the half of the box `object` and the
    /// box's index in it (simulated on first use); `None` under `--dynamics annotation`.
    fn simulated(&self, object: &SceneObjectInfo) -> Result<Option<(&HalfRun, usize)>, ApiError> {
        let Some(runs) = &self.runs else {
            return Ok(None);
        };
        let (side, index) = self
            .annotation
            .find_box(&object.name)
            .map(|(side, _)| side)
            .zip(self.half_index(object))
            .ok_or_else(|| {
                ApiError::Unavailable(format!(
                    "the video has no record of the {}",
                    object.describe()
                ))
            })?;
        Ok(Some((runs.half(&self.annotation, side)?, index)))
    }

    /// Under `--dynamics simulate`, which cloth the video shows to have more of `property`;
    /// [`Told::Recorded`] under `--dynamics annotation`.
    fn told(&self, property: Property) -> Result<Told, ApiError> {
        let Some(runs) = &self.runs else {
            return Ok(Told::Recorded);
        };
        let verdict = runs.observed()?.verdict;
        let evidence = runs.evidence();
        let more = match property {
            Property::Bending => verdict.bends,
            _ => verdict.stretches,
        };
        Ok(more.map_or(Told::Undecided(evidence), Told::More))
    }
}

/// Whether the simulated box `index` of `run` fell over: its end pose by the shared rule, and a
/// box that ends leaning by its tilt (past 45° it has fallen). A prediction that leans is
/// still an answer: the release's box either stood, lay or tipped, and the simulation's lean
/// is nearer one of them.
fn simulated_fall(run: &HalfRun, index: usize) -> bool {
    let pose = run.end_poses.get(index).copied().unwrap_or(Pose::Upright);
    pose.fell_over().unwrap_or_else(|| {
        let up = run
            .end_states
            .get(index)
            .map_or([0.0, 1.0, 0.0], |(_, orientation)| {
                v3::apply(&v3::rotation_matrix(*orientation), [0.0, 1.0, 0.0])
            });
        up[1] < std::f64::consts::FRAC_1_SQRT_2
    })
}

/// Which cloth has more of a property, as a backend tells it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Told {
    /// The annotation's values answer (`--dynamics annotation`).
    Recorded,
    /// The video shows this cloth to have more of it.
    More(Side),
    /// The video does not tell (by what it was read from: `tracked particles`, `masks`).
    Undecided(&'static str),
}

/// The question an action word of `happen` asks in cloth scenes.
fn parse_action(action: &str) -> Result<Question, ApiError> {
    match action {
        "falling" | "fall" | "falls" | "fall over" | "falling over" | "falls over" => {
            Ok(Question::Fall)
        }
        "collision" | "collide" | "collides" | "colliding" => {
            Ok(Question::Between(Relation::Collision))
        }
        "touching" | "touch" | "touches" | "in touch" => Ok(Question::Between(Relation::Touch)),
        "entering" | "passing" | "motion" | "rotation" | "droping" | "dropping" => {
            Err(misuse(format!(
                "happen: `{action}` belongs to other scenarios; cloth scenes answer 'falling', 'collision' and 'touching' (and final_pose for the end pose)"
            )))
        }
        _ => Err(unknown_action(
            action,
            "cloth",
            "falling, collision, touching",
        )),
    }
}

impl ScenarioBackend for ClothBackend {
    fn objects(&self) -> &[SceneObjectInfo] {
        &self.objects
    }

    fn query(
        &self,
        property: Property,
        objects: &[ObjectId],
        function: &str,
    ) -> Result<Vec<Option<f64>>, ApiError> {
        let value: fn(&ClothProperties) -> f64 = match property {
            Property::Elasticity => |cloth| cloth.stretching_compliance,
            Property::Bending => |cloth| cloth.bending_compliance,
            _ => {
                return Err(misuse(format!(
                    "{function}: property `{}` does not apply to cloth scenes; cloth scenes have elasticity and bending (cloths)",
                    property.name()
                )));
            }
        };
        let told = self.told(property)?;
        objects
            .iter()
            .map(|id| {
                let object = self.info(*id, function)?;
                let recorded = value(self.cloth(object, property, function)?);
                let Some(Role::Cloth(side)) = self.role(object) else {
                    return Ok(Some(recorded));
                };
                let values = match property {
                    Property::Bending => VALUES.max_bending,
                    _ => VALUES.stretch_compliance,
                };
                match told {
                    Told::Recorded => Ok(Some(recorded)),
                    Told::More(more) if more == side => Ok(Some(values[0])),
                    Told::More(_) => Ok(Some(values[1])),
                    Told::Undecided(evidence) => Err(ApiError::Unavailable(format!(
                        "{function}: the video does not tell which cloth {} more: the two cloths' {evidence} measure too alike",
                        match property {
                            Property::Bending => "bends",
                            _ => "stretches",
                        }
                    ))),
                }
            })
            .collect()
    }

    fn simulation_work(&self) -> (u64, u64) {
        self.runs.as_ref().map_or((0, 0), ClothRuns::work)
    }

    fn perception_work(&self) -> (u64, u64) {
        let (frames, detections) = self
            .runs
            .as_ref()
            .map_or((0, 0), ClothRuns::perception_work);
        (frames + self.load_work.0, detections + self.load_work.1)
    }

    fn check_event(&self, event: &SceneEvent) -> Result<(), ApiError> {
        match event.action {
            EventAction::Simulate => Ok(()),
            EventAction::Increase
            | EventAction::Decrease
            | EventAction::Emit
            | EventAction::Remove => Err(misuse(
                "register_event: cloth scenes support register_event([], 'simulate', '') only: their questions predict the video's own future",
            )),
        }
    }

    fn happen(
        &self,
        event: &SceneEvent,
        object: ObjectId,
        action: &str,
        target: &Target,
    ) -> Result<bool, ApiError> {
        self.check_event(event)?;
        let question = parse_action(action)?;
        let subject = self.info(object, "happen")?;
        match question {
            Question::Fall => self.fell_over(subject, target),
            Question::Between(relation) => self.related(subject, relation, target),
        }
    }

    fn final_pose(&self, event: &SceneEvent, object: ObjectId) -> Result<Option<String>, ApiError> {
        self.check_event(event)?;
        let subject = self.info(object, "final_pose")?;
        let record = self.box_record(subject, "final_pose", "it asks about")?;
        let pose = match self.simulated(subject)? {
            Some((run, index)) => run.end_poses.get(index).copied().unwrap_or(record.end_pose),
            None => record.end_pose,
        };
        Ok(Some(Pose::phrase(pose).to_string()))
    }
}
