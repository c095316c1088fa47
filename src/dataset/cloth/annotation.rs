//! Typed cloth annotations (`cloth_collision/<id>/outputs.json`, `docs/data/cloth.md`): the two
//! cloths' properties (`clothLeft`, `clothRight`), every box of each half with its sampled and
//! end states, end pose, collisions, first movement and final contacts
//! (`objectFullAnnotation`), and the camera. Read from a file, and written back in the same form
//! ([`ClothAnnotation::scenario_keys`], [`ClothAnnotation::to_json`]) so the generator writes
//! what the reader accepts.
//!
//! Every key the release writes for these blocks is required; box names must follow the
//! release's grammar ([`super::names`]) and agree with `colorName` and `shape`, and a name may
//! appear once in the file. No real cloth video is public, so two forms are accepted where the
//! release's code leaves the JSON open: a vector is an array of three numbers or Unity's
//! `"(x, y, z)"` string, and a tower's key is not checked against its name. Names in
//! `collisionEvents` and `touchers` are any text (the release lists boxes, the cloths and other
//! colliders there). Errors name the file and the dotted field. Lists keep file order.

use std::collections::BTreeSet;
use std::path::Path;

use serde::Serialize;
use serde_json::{Map, Value, json};

use super::names::{Shape, Side, parse_box_name};
use super::outcome::Pose;
use crate::dataset::DatasetError;
use crate::dataset::camera::{Camera, camera_record, parse_camera};
use crate::dataset::fields::{Node, expect_mode, read_json};
use crate::dataset::segmentation::parse_image_descriptions;

/// `mode` of the factual record (cloth has no counterfactual runs).
const FACTUAL_MODE: &str = "FACTUAL_PREDICTIVE";
/// `startMovingFrame` of a box that never moved.
const NEVER_MOVED: i64 = -1;

/// A cloth's friction class (`LowFriction`, dynamic 0.5; `HighFriction`, dynamic 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Friction {
    /// `LOW`.
    Low,
    /// `HIGH`.
    High,
}

impl Friction {
    /// The release's word (`LOW`).
    pub fn as_str(self) -> &'static str {
        match self {
            Friction::Low => "LOW",
            Friction::High => "HIGH",
        }
    }
}

/// `perRegionAvgForce`: the mean constraint force in each quadrant of the cloth at the last
/// step, keyed by the release's quadrant colours.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RegionForces {
    /// `Red`.
    pub red: f64,
    /// `Blue`.
    pub blue: f64,
    /// `Yellow`.
    pub yellow: f64,
    /// `Green`.
    pub green: f64,
}

/// One cloth's properties (`clothLeft`, `clothRight`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ClothProperties {
    /// `stretchingCompliance`: 0.011 (stretches) or 0 (does not).
    pub stretching_compliance: f64,
    /// `bendingCompliance`, really Obi's maximum bending: 0.035 bends more easily than 0.013.
    pub bending_compliance: f64,
    /// `friction`.
    pub friction: Friction,
    /// `perRegionAvgForce`.
    pub region_forces: RegionForces,
}

/// One entry of `collisionEvents`: the box touched `other` at `update` (a simulation update,
/// about twice the video frame).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct CollisionEvent {
    /// `Item1`: the update.
    pub update: u32,
    /// `Item2`: the other object's name (a box, `Cloth (Left)`, …).
    pub other: String,
}

/// A box (pillar, plate or cube): one `OBJ` record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoxRecord {
    /// `name`: `<C> <Shape>`.
    pub name: String,
    /// `colorName`: the palette name in its name.
    pub color: String,
    /// `colorRGB`, parsed from `"RGBA(r, g, b, a)"`.
    pub color_rgba: [f64; 4],
    /// `shape`.
    pub shape: Shape,
    /// `scale`, units.
    pub scale: [f64; 3],
    /// `sampledPos_Local`: the sampled position relative to the half's centre, units.
    pub sampled_position_local: [f64; 3],
    /// `sampledRot`: the sampled Euler angles, degrees.
    pub sampled_rotation: [f64; 3],
    /// `startPos`, units.
    pub start_position: [f64; 3],
    /// `startRot`, degrees.
    pub start_rotation: [f64; 3],
    /// `endPos`, units.
    pub end_position: [f64; 3],
    /// `endRot`, degrees.
    pub end_rotation: [f64; 3],
    /// `endPoseDescription`.
    pub end_pose: Pose,
    /// `mass`, kg (99998 and 99999 are the release's immovable boxes).
    pub mass: f64,
    /// `collisionEvents`, in file order (by time).
    pub collision_events: Vec<CollisionEvent>,
    /// `startMovingFrame`: the first update it moved, `None` for the release's `-1`.
    pub start_moving_update: Option<u32>,
    /// `touchers`: what it touches at the end.
    pub touchers: Vec<String>,
}

impl BoxRecord {
    /// Whether its `collisionEvents` name `other`.
    pub fn collided_with(&self, other: &str) -> bool {
        self.collision_events
            .iter()
            .any(|event| event.other == other)
    }

    /// Whether its `touchers` name `other`.
    pub fn touches(&self, other: &str) -> bool {
        self.touchers.iter().any(|toucher| toucher == other)
    }
}

/// A tower of stacked boxes (`towers`); the release moves one-box towers to `isolatedObjects`,
/// so this is normally empty.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Tower {
    /// `name`: `<n>-Object Tower (Left)`.
    pub name: String,
    /// `baseXZ`, units.
    pub base_xz: [f64; 2],
    /// `layerNum`.
    pub layer_count: u32,
    /// `layersDownToUpList`, bottom first.
    pub layers: Vec<BoxRecord>,
}

/// The boxes of one half (`leftAll`, `rightAll`).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct HalfObjects {
    /// `towers`, in file order.
    pub towers: Vec<Tower>,
    /// `isolatedObjects`, in file order.
    pub isolated: Vec<BoxRecord>,
}

impl HalfObjects {
    /// Every box of the half: the isolated ones, then each tower's from the bottom up.
    pub fn boxes(&self) -> impl Iterator<Item = &BoxRecord> {
        self.isolated
            .iter()
            .chain(self.towers.iter().flat_map(|tower| tower.layers.iter()))
    }
}

/// The cloth annotations of one valid video.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClothAnnotation {
    /// `clothLeft`.
    pub left_cloth: ClothProperties,
    /// `clothRight`.
    pub right_cloth: ClothProperties,
    /// `objectFullAnnotation.leftAll`.
    pub left_objects: HalfObjects,
    /// `objectFullAnnotation.rightAll`.
    pub right_objects: HalfObjects,
    /// The main camera, when recorded.
    pub camera: Option<Camera>,
    /// Instance id → scene object name (`Id2ObjectNameDict`), in file order; empty if absent.
    pub id_to_object_name: Vec<(u32, String)>,
    /// Number of annotated frames (`perFrameAnnotations`), 0 if absent.
    pub frame_count: usize,
}

impl ClothAnnotation {
    /// Loads and validates the annotations of `path` (an `outputs.json`).
    pub fn load(path: &Path) -> Result<ClothAnnotation, DatasetError> {
        let value = read_json(path)?;
        ClothAnnotation::from_json(path, &value)
    }

    /// Validates an already parsed document; `path` is used in error messages.
    pub fn from_json(path: &Path, value: &Value) -> Result<ClothAnnotation, DatasetError> {
        let root = Node::root(path, value);
        if !root.field("validity", |n| n.boolean())? {
            return Err(root.error("has `validity: false`: an invalid trial has no annotations"));
        }
        root.field("mode", |n| expect_mode(n, FACTUAL_MODE))?;
        let left_cloth = root.field(Side::Left.cloth_key(), parse_cloth)?;
        let right_cloth = root.field(Side::Right.cloth_key(), parse_cloth)?;
        let (left_objects, right_objects) = root.field("objectFullAnnotation", |n| {
            let mut seen = BTreeSet::new();
            let left = n.field(Side::Left.objects_key(), |h| parse_half(h, &mut seen))?;
            let right = n.field(Side::Right.objects_key(), |h| parse_half(h, &mut seen))?;
            Ok((left, right))
        })?;
        let camera = root.field("outputCamera", parse_camera)?;
        let (id_to_object_name, frame_count) = root
            .optional_field("imgAnnotationDescriptions", parse_image_descriptions)?
            .unwrap_or_default();
        Ok(ClothAnnotation {
            left_cloth,
            right_cloth,
            left_objects,
            right_objects,
            camera,
            id_to_object_name,
            frame_count,
        })
    }

    /// The cloth of `side`.
    pub fn cloth(&self, side: Side) -> &ClothProperties {
        match side {
            Side::Left => &self.left_cloth,
            Side::Right => &self.right_cloth,
        }
    }

    /// The boxes of `side`.
    pub fn objects(&self, side: Side) -> &HalfObjects {
        match side {
            Side::Left => &self.left_objects,
            Side::Right => &self.right_objects,
        }
    }

    /// Every box with its half: the left half's, then the right's.
    pub fn boxes(&self) -> impl Iterator<Item = (Side, &BoxRecord)> {
        Side::BOTH
            .into_iter()
            .flat_map(move |side| self.objects(side).boxes().map(move |record| (side, record)))
    }

    /// The box named `name`, with its half.
    pub fn find_box(&self, name: &str) -> Option<(Side, &BoxRecord)> {
        self.boxes().find(|(_, record)| record.name == name)
    }

    /// Whether boxes `first` and `second` collide in the run: either's `collisionEvents` names
    /// the other (the release records a contact on each body; one record is enough).
    pub fn collided(&self, first: &str, second: &str) -> bool {
        self.either_lists(first, second, BoxRecord::collided_with)
    }

    /// Whether boxes `first` and `second` touch at the end: either's `touchers` names the other.
    pub fn in_touch(&self, first: &str, second: &str) -> bool {
        self.either_lists(first, second, BoxRecord::touches)
    }

    fn either_lists(&self, first: &str, second: &str, lists: fn(&BoxRecord, &str) -> bool) -> bool {
        let names = |of: &str, other: &str| {
            self.find_box(of)
                .is_some_and(|(_, record)| lists(record, other))
        };
        names(first, second) || names(second, first)
    }

    /// The keys the scenario writes before `outputCamera`, in the release's order:
    /// `validity`, `mode`, `clothLeft`, `clothRight`, `objectFullAnnotation`. The generator
    /// writes these; the shared code adds the camera, the image annotations and the empty
    /// `CounterFactualAnnotations`.
    pub fn scenario_keys(&self) -> Map<String, Value> {
        let mut keys = Map::new();
        keys.insert("validity".into(), json!(true));
        keys.insert("mode".into(), json!(FACTUAL_MODE));
        for side in Side::BOTH {
            keys.insert(side.cloth_key().into(), cloth_json(self.cloth(side)));
        }
        let halves: Map<String, Value> = Side::BOTH
            .into_iter()
            .map(|side| {
                (
                    side.objects_key().to_string(),
                    half_json(self.objects(side)),
                )
            })
            .collect();
        keys.insert("objectFullAnnotation".into(), Value::Object(halves));
        keys
    }

    /// The whole `outputs.json` this annotation reads back from: [`Self::scenario_keys`], the
    /// camera, `Id2ObjectNameDict` when there is one, and `CounterFactualAnnotations: {}`. The
    /// per-frame image annotations are the shared generator's to write, so an annotation with a
    /// `frame_count` reads back with 0.
    pub fn to_json(&self) -> Value {
        let mut keys = self.scenario_keys();
        keys.insert("outputCamera".into(), camera_record(self.camera.as_ref()));
        if !self.id_to_object_name.is_empty() {
            let names: Map<String, Value> = self
                .id_to_object_name
                .iter()
                .map(|(id, name)| (id.to_string(), json!(name)))
                .collect();
            keys.insert(
                "imgAnnotationDescriptions".into(),
                json!({ "Id2ObjectNameDict": names }),
            );
        }
        keys.insert("CounterFactualAnnotations".into(), json!({}));
        Value::Object(keys)
    }
}

fn parse_cloth(node: Node<'_>) -> Result<ClothProperties, DatasetError> {
    let compliance = |key: &str| {
        node.field(key, |n| {
            let value = n.number()?;
            if value < 0.0 {
                return Err(n.error(format!("must be 0 or more, found {value}")));
            }
            Ok(value)
        })
    };
    let friction = node.field("friction", |n| {
        let text = n.string()?;
        [Friction::Low, Friction::High]
            .into_iter()
            .find(|friction| friction.as_str() == text)
            .ok_or_else(|| n.error(format!("must be `LOW` or `HIGH`, found `{text}`")))
    })?;
    let region_forces = node.field("perRegionAvgForce", |n| {
        Ok(RegionForces {
            red: n.field("Red", |f| f.number())?,
            blue: n.field("Blue", |f| f.number())?,
            yellow: n.field("Yellow", |f| f.number())?,
            green: n.field("Green", |f| f.number())?,
        })
    })?;
    Ok(ClothProperties {
        stretching_compliance: compliance("stretchingCompliance")?,
        bending_compliance: compliance("bendingCompliance")?,
        friction,
        region_forces,
    })
}

/// One half's `towers` and `isolatedObjects`; `seen` holds every box name read so far, so a name
/// used twice in the file is an error.
fn parse_half(node: Node<'_>, seen: &mut BTreeSet<String>) -> Result<HalfObjects, DatasetError> {
    let towers = node.field("towers", |n| n.entries(|_, tower| parse_tower(tower, seen)))?;
    let isolated = node.field("isolatedObjects", |n| {
        n.entries(|key, record| {
            let parsed = parse_box(record, seen)?;
            if parsed.name != key {
                return Err(record.error(format!(
                    "is keyed `{key}` but names itself `{}`",
                    parsed.name
                )));
            }
            Ok(parsed)
        })
    })?;
    Ok(HalfObjects { towers, isolated })
}

fn parse_tower(node: Node<'_>, seen: &mut BTreeSet<String>) -> Result<Tower, DatasetError> {
    let base = node.field("baseXZ", |n| n.numbers(Some(2)))?;
    Ok(Tower {
        name: node.field("name", |n| n.string())?,
        base_xz: [base[0], base[1]],
        layer_count: node.field("layerNum", |n| {
            let count = n.integer()?;
            u32::try_from(count)
                .map_err(|_| n.error(format!("must be a count (0 or more), found {count}")))
        })?,
        layers: node.field("layersDownToUpList", |n| {
            n.items(|record| parse_box(record, seen))
        })?,
    })
}

/// A vector: an array of three numbers, or Unity's `"(x, y, z)"`.
fn vector3(node: Node<'_>) -> Result<[f64; 3], DatasetError> {
    if node.string().is_ok() {
        return node.unity_vector3();
    }
    let values = node.numbers(Some(3))?;
    Ok([values[0], values[1], values[2]])
}

/// Unity's `Color.ToString()`: `"RGBA(0.396, 0.576, 0.290, 1.000)"`.
fn parse_rgba(node: Node<'_>) -> Result<[f64; 4], DatasetError> {
    let text = node.string()?;
    let parsed = text
        .trim()
        .strip_prefix("RGBA(")
        .and_then(|rest| rest.strip_suffix(')'))
        .and_then(|inner| {
            let values: Vec<f64> = inner
                .split(',')
                .map(|part| part.trim().parse::<f64>().ok())
                .collect::<Option<_>>()?;
            let rgba: [f64; 4] = values.try_into().ok()?;
            rgba.iter().all(|c| c.is_finite()).then_some(rgba)
        });
    parsed.ok_or_else(|| {
        node.error(format!(
            "must be a Unity colour string \"RGBA(r, g, b, a)\" of four finite numbers, found \"{text}\""
        ))
    })
}

fn parse_box(node: Node<'_>, seen: &mut BTreeSet<String>) -> Result<BoxRecord, DatasetError> {
    let name = node.field("name", |n| {
        let name = n.string()?;
        if !seen.insert(name.clone()) {
            return Err(n.error(format!("names `{name}`, which another box already has")));
        }
        Ok(name)
    })?;
    let parsed = node.field("name", |n| {
        parse_box_name(&name).ok_or_else(|| {
            n.error(format!(
                "names `{name}`, which is not a box name (`<Colour> Pillar`, `<Colour> Plate` or `<Colour> Cube`)"
            ))
        })
    })?;
    let color = node.field("colorName", |n| {
        let color = n.string()?;
        if color == parsed.color {
            Ok(color)
        } else {
            Err(n.error(format!("is `{color}`, but the box is named `{name}`")))
        }
    })?;
    let shape = node.field("shape", |n| {
        let text = n.string()?;
        match Shape::parse(&text) {
            Some(shape) if shape == parsed.shape => Ok(shape),
            Some(_) => Err(n.error(format!("is `{text}`, but the box is named `{name}`"))),
            None => Err(n.error(format!(
                "must be `Pillar`, `Plate` or `Cube`, found `{text}`"
            ))),
        }
    })?;
    Ok(BoxRecord {
        color,
        color_rgba: node.field("colorRGB", parse_rgba)?,
        shape,
        scale: node.field("scale", vector3)?,
        sampled_position_local: node.field("sampledPos_Local", vector3)?,
        sampled_rotation: node.field("sampledRot", vector3)?,
        start_position: node.field("startPos", vector3)?,
        start_rotation: node.field("startRot", vector3)?,
        end_position: node.field("endPos", vector3)?,
        end_rotation: node.field("endRot", vector3)?,
        end_pose: node.field("endPoseDescription", |n| {
            let text = n.string()?;
            Pose::parse(&text).ok_or_else(|| {
                n.error(format!(
                    "must be `Upright`, `Reclining`, `Supine`, `Swooping` or `Other`, found `{text}`"
                ))
            })
        })?,
        mass: node.field("mass", |n| {
            let mass = n.number()?;
            if mass > 0.0 {
                Ok(mass)
            } else {
                Err(n.error(format!("must be more than 0, found {mass}")))
            }
        })?,
        collision_events: node.field("collisionEvents", |n| n.items(parse_collision))?,
        start_moving_update: node.field("startMovingFrame", |n| {
            let update = n.integer()?;
            if update == NEVER_MOVED {
                return Ok(None);
            }
            u32::try_from(update).map(Some).map_err(|_| {
                n.error(format!(
                    "must be an update (0 or more) or -1 (never moved), found {update}"
                ))
            })
        })?,
        touchers: node.field("touchers", |n| n.items(|item| object_reference(&item)))?,
        name,
    })
}

/// A name in `collisionEvents` or `touchers`: any non-empty text.
fn object_reference(node: &Node<'_>) -> Result<String, DatasetError> {
    let name = node.string()?;
    if name.is_empty() {
        Err(node.error("must name an object, found an empty string"))
    } else {
        Ok(name)
    }
}

fn parse_collision(node: Node<'_>) -> Result<CollisionEvent, DatasetError> {
    Ok(CollisionEvent {
        update: node.field("Item1", |n| {
            let update = n.integer()?;
            u32::try_from(update)
                .map_err(|_| n.error(format!("must be an update (0 or more), found {update}")))
        })?,
        other: node.field("Item2", |n| object_reference(&n))?,
    })
}

fn cloth_json(cloth: &ClothProperties) -> Value {
    let forces = &cloth.region_forces;
    json!({
        "stretchingCompliance": cloth.stretching_compliance,
        "bendingCompliance": cloth.bending_compliance,
        "friction": cloth.friction.as_str(),
        "perRegionAvgForce": {
            "Red": forces.red,
            "Blue": forces.blue,
            "Yellow": forces.yellow,
            "Green": forces.green,
        },
    })
}

/// Unity's `Color.ToString()`: three decimals.
fn rgba_text(rgba: [f64; 4]) -> String {
    let [r, g, b, a] = rgba;
    format!("RGBA({r:.3}, {g:.3}, {b:.3}, {a:.3})")
}

fn box_json(record: &BoxRecord) -> Value {
    json!({
        "name": record.name,
        "colorName": record.color,
        "colorRGB": rgba_text(record.color_rgba),
        "shape": record.shape.as_str(),
        "scale": record.scale,
        "sampledPos_Local": record.sampled_position_local,
        "sampledRot": record.sampled_rotation,
        "startPos": record.start_position,
        "startRot": record.start_rotation,
        "endPos": record.end_position,
        "endRot": record.end_rotation,
        "endPoseDescription": record.end_pose.as_str(),
        "mass": record.mass,
        "collisionEvents": record
            .collision_events
            .iter()
            .map(|event| json!({"Item1": event.update, "Item2": event.other}))
            .collect::<Vec<_>>(),
        "startMovingFrame": record
            .start_moving_update
            .map_or(NEVER_MOVED, i64::from),
        "touchers": record.touchers,
    })
}

fn half_json(half: &HalfObjects) -> Value {
    let towers: Map<String, Value> = half
        .towers
        .iter()
        .map(|tower| {
            let layers: Vec<Value> = tower.layers.iter().map(box_json).collect();
            (
                tower.name.clone(),
                json!({
                    "name": tower.name,
                    "baseXZ": tower.base_xz,
                    "layerNum": tower.layer_count,
                    "layersDownToUpList": layers,
                }),
            )
        })
        .collect();
    let isolated: Map<String, Value> = half
        .isolated
        .iter()
        .map(|record| (record.name.clone(), box_json(record)))
        .collect();
    json!({"towers": towers, "isolatedObjects": isolated})
}
