//! The cloth scene (`cloth_collision`): objects from the annotation's boxes and the two cloths;
//! cloth properties and what happens to the boxes under the cloth from its records
//! (`--dynamics annotation`, the paper's offline mode).
//!
//! Input: a video's `outputs.json` ([`ClothAnnotation`]). Output: the scene's objects and the
//! answers of `query`, `register_event`, `happen` and `final_pose` (`docs/data/cloth.md`).
//! Cloth has no simulation backend and no scene reading from pixels yet (its detector,
//! `perception::cloth`, finds the cloths, pillars and plates, but nothing reads a scene from its
//! detections): under `--dynamics simulate` or `--perception maskrcnn` loading the scene fails
//! with [`ApiError::Unavailable`] saying so.
//!
//! Objects, in this order: the two cloths (`Cloth (Left)`, `Cloth (Right)`: kind `cloth`, no
//! colour, `side` left or right, so `left cloth`), then every pillar and plate of the left half
//! and of the right half in file order (`Green Plate`: kind `plate`, colour `green`). Cubes (tower
//! layers the release practically never leaves unmerged) are not objects: no question or scene
//! word names them.
//!
//! Answers agree with the question engine (`dataset::engine::cloth`) by construction, reading
//! the same keys with the same shared rules:
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

#[cfg(test)]
mod tests;

use crate::dataset::Scenario;
use crate::dataset::cloth::names::{Shape, Side, parse_box_name};
use crate::dataset::cloth::outcome::Pose;
use crate::dataset::cloth::{BoxRecord, ClothAnnotation, ClothProperties, VOCABULARY};
use crate::scene_api::{
    ApiError, DynamicsBackend, EventAction, ObjectId, PerceptionBackend, Property, ScenarioBackend,
    SceneEvent, SceneObjectInfo, Target, VideoSpec, misuse, resolve_description, unknown_action,
};

/// The vocabulary attribute that tells the cloths apart.
const SIDE: &str = "side";
/// What messages call the objects `happen` and `final_pose` ask about.
const BOXES: &str = "pillar or plate";

/// Loads the backend of a cloth video (the scenario table's scene backend for cloth).
pub fn load(spec: &VideoSpec) -> Result<Box<dyn ScenarioBackend>, ApiError> {
    // The backends that do not exist yet are refused before any file is read: the message is
    // what the user must change, whatever the video holds.
    if spec.perception != PerceptionBackend::Annotation {
        return Err(ApiError::Unavailable(
            "--perception maskrcnn: cloth scenes are not read from pixels yet (the cloth detector finds cloths, pillars and plates, but no scene reading uses it); cloth scenes are read from their annotations (--perception annotation)"
                .to_string(),
        ));
    }
    if spec.dynamics != DynamicsBackend::Annotation {
        return Err(ApiError::Unavailable(
            "--dynamics simulate: there is no cloth simulation backend yet; cloth scenes answer from their recorded outcomes (--dynamics annotation)"
                .to_string(),
        ));
    }
    let annotation = ClothAnnotation::load(&spec.video_dir.join("outputs.json"))?;
    Ok(Box::new(ClothBackend::new(annotation)))
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

/// One cloth video's answers, from its annotations.
pub(crate) struct ClothBackend {
    annotation: ClothAnnotation,
    objects: Vec<SceneObjectInfo>,
    roles: Vec<Role>,
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
        format!("the pillars and plates are: {}", names.join(", "))
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
                    return Err(misuse(format!(
                        "happen: the target `{}` of '{word}' names no object of this scene; {}",
                        text.trim(),
                        self.box_names()
                    )));
                }
                found
            }
        };
        match ids.as_slice() {
            [one] => self.info(*one, "happen"),
            [] => Err(misuse(format!(
                "happen: the target of '{word}' names no {BOXES} (an empty list: `find` found no such object); {}",
                self.box_names()
            ))),
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
        Ok(match relation {
            Relation::Collision => self.annotation.collided(&subject.name, &other.name),
            Relation::Touch => self.annotation.in_touch(&subject.name, &other.name),
        })
    }
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
        objects
            .iter()
            .map(|id| {
                let object = self.info(*id, function)?;
                Ok(Some(value(self.cloth(object, property, function)?)))
            })
            .collect()
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
        Ok(Some(Pose::phrase(record.end_pose).to_string()))
    }
}
