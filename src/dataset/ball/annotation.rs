//! Typed ball annotations (`soft_body/<id>/outputs.json`, `docs/data/ball.md`): each ball's pit
//! in the factual run and in each counterfactual run, the sampled layout (ramps, floor pieces,
//! floating walls, balls and their materials, the pits), the camera and the light.
//!
//! Every key the engine and backends need is required; names must follow the release's grammar
//! ([`super::names`]), colour ids must be palette ids matching the name, pit results must be the
//! release's strings. Errors name the file and the dotted field. Maps keep file order.

use std::path::Path;

use indexmap::IndexMap;
use serde::Serialize;

use super::names::{BallObjectKind, parse_ball_object_name};
use super::outcome::{Pit, PitRecord, PitResult};
use crate::dataset::DatasetError;
use crate::dataset::camera::{Camera, parse_camera};
use crate::dataset::fields::{Node, expect_mode, light_rotations, read_json};
use crate::dataset::palette::palette_name;
use crate::dataset::segmentation::parse_image_descriptions;

/// `mode` of a factual record.
const FACTUAL_MODE: &str = "FACTUAL_PREDICTIVE";
/// `mode` of a counterfactual record.
const COUNTERFACTUAL_MODE: &str = "COUNTERFACTUAL_";
/// The key of a counterfactual run's one tracked ball.
const ONLY_THAT_BALL: &str = "onlyThatBall";

/// A ball's `elasticityType`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ElasticityType {
    /// `Elastic` ("Ball More Elastic").
    Elastic,
    /// `Rigid` ("Ball Less Elastic").
    Rigid,
    /// `Plastic`.
    Plastic,
}

impl ElasticityType {
    /// The release's word.
    pub fn as_str(self) -> &'static str {
        match self {
            ElasticityType::Elastic => "Elastic",
            ElasticityType::Rigid => "Rigid",
            ElasticityType::Plastic => "Plastic",
        }
    }

    /// All three, in the release's order.
    pub const ALL: [ElasticityType; 3] = [
        ElasticityType::Elastic,
        ElasticityType::Rigid,
        ElasticityType::Plastic,
    ];
}

/// A slab of `metaSamplingData` (a ramp, floor piece or floating wall), in world units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlabRecord {
    /// Its name.
    pub name: String,
    /// Palette colour id.
    pub color: u8,
    /// Centre, units.
    pub position: [f64; 3],
    /// Unity Euler angles, degrees (only z is non-zero).
    pub rotation_deg: [f64; 3],
    /// `(length, thickness, depth)`, units.
    pub scale: [f64; 3],
    /// One end of the centre line `(x, y)`, units.
    pub start: [f64; 2],
    /// The other end, units.
    pub end: [f64; 2],
    /// Length, units.
    pub length: f64,
    /// Angle to the x axis, radians.
    pub angle_rad: f64,
}

/// A ball of `metaSamplingData.balls`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BallRecord {
    /// `<C> Ball`.
    pub name: String,
    /// Palette colour id.
    pub color: u8,
    /// Its material.
    pub elasticity: ElasticityType,
    /// Where it is released, units.
    pub release_position: [f64; 3],
}

/// `metaSamplingData`: the sampled layout.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct BallLayout {
    /// `Right Ramp`, `Left Ramp`.
    pub ramps: Vec<SlabRecord>,
    /// The floor pieces, left to right.
    pub floor_pieces: Vec<SlabRecord>,
    /// The floating walls: the slanted one, then the vertical one.
    pub floating_walls: Vec<SlabRecord>,
    /// The balls.
    pub balls: Vec<BallRecord>,
    /// The pits' centres `[right (+), left (−)]`, units.
    pub holes_centre_x: [f64; 2],
}

impl BallLayout {
    /// The ball named `name`.
    pub fn ball(&self, name: &str) -> Option<&BallRecord> {
        self.balls.iter().find(|ball| ball.name == name)
    }

    /// The centre of `pit`, units.
    pub fn pit_centre(&self, pit: Pit) -> f64 {
        match pit {
            Pit::Right => self.holes_centre_x[0],
            Pit::Left => self.holes_centre_x[1],
        }
    }
}

/// One counterfactual run: one ball alone, one floating wall removed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BallCounterfactual {
    /// The record key in `CounterFactualAnnotations`.
    pub key: String,
    /// The removed floating wall.
    pub removed_wall: String,
    /// The one ball simulated.
    pub ball: String,
    /// Its outcome.
    pub record: PitRecord,
}

/// The ball annotations of one valid video.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BallAnnotation {
    /// Each ball's outcome in the factual run, by name, in file order.
    pub tracking: IndexMap<String, PitRecord>,
    /// The sampled layout.
    pub layout: BallLayout,
    /// The main camera, when recorded.
    pub camera: Option<Camera>,
    /// The light's Euler angles in degrees, by light object name.
    pub light_rotation_deg: IndexMap<String, [f64; 3]>,
    /// The counterfactual runs in file order.
    pub counterfactuals: Vec<BallCounterfactual>,
    /// Instance id → scene object name (`Id2ObjectNameDict`), in file order; empty if absent.
    pub id_to_object_name: Vec<(u32, String)>,
    /// Number of annotated frames (`perFrameAnnotations`), 0 if absent.
    pub frame_count: usize,
}

impl BallAnnotation {
    /// Loads and validates the annotations of `path` (an `outputs.json`).
    pub fn load(path: &Path) -> Result<BallAnnotation, DatasetError> {
        let value = read_json(path)?;
        BallAnnotation::from_json(path, &value)
    }

    /// Validates an already parsed document; `path` is used in error messages.
    pub fn from_json(
        path: &Path,
        value: &serde_json::Value,
    ) -> Result<BallAnnotation, DatasetError> {
        let root = Node::root(path, value);
        if !root.field("validity", |n| n.boolean())? {
            return Err(root.error("has `validity: false`: an invalid trial has no annotations"));
        }
        root.field("mode", |n| expect_mode(n, FACTUAL_MODE))?;
        let tracking = root.field("trackingData", |n| {
            Ok(n.entries(|name, record| {
                object_name(&record, name, BallObjectKind::Ball)?;
                Ok((name.to_string(), parse_pit_record(record)?))
            })?
            .into_iter()
            .collect())
        })?;
        let layout = root.field("metaSamplingData", parse_layout)?;
        let camera = root.field("outputCamera", parse_camera)?;
        let light_rotation_deg = root.field("outputLight", light_rotations)?;
        let counterfactuals = root.field("CounterFactualAnnotations", |n| {
            n.entries(parse_counterfactual)
        })?;
        let (id_to_object_name, frame_count) = root
            .optional_field("imgAnnotationDescriptions", parse_image_descriptions)?
            .unwrap_or_default();
        let annotation = BallAnnotation {
            tracking,
            layout,
            camera,
            light_rotation_deg,
            counterfactuals,
            id_to_object_name,
            frame_count,
        };
        for name in annotation.tracking.keys() {
            if annotation.layout.ball(name).is_none() {
                return Err(root.error(format!(
                    "tracks `{name}` in `trackingData`, a ball `metaSamplingData.balls` does not list"
                )));
            }
        }
        Ok(annotation)
    }

    /// The counterfactual run of `ball` without `wall`, if there is one.
    pub fn counterfactual(&self, wall: &str, ball: &str) -> Option<&BallCounterfactual> {
        self.counterfactuals
            .iter()
            .find(|run| run.removed_wall == wall && run.ball == ball)
    }
}

/// Checks that `name` is a name of `kind`; returns its colour word, if any.
fn object_name(
    node: &Node<'_>,
    name: &str,
    kind: BallObjectKind,
) -> Result<Option<&'static str>, DatasetError> {
    let described = match kind {
        BallObjectKind::Ball => "a ball name (`<Colour> Ball`)",
        BallObjectKind::FloatingWall => "a floating wall name (`<Colour> Floating Wall`)",
        BallObjectKind::Ramp => "a ramp name (`Left Ramp` or `Right Ramp`)",
        BallObjectKind::FloorPiece => "a floor piece name (`Floor Piece 1st`, `2nd` or `3rd`)",
    };
    parse_ball_object_name(name)
        .filter(|parsed| parsed.kind == kind)
        .map(|parsed| parsed.color)
        .ok_or_else(|| node.error(format!("names `{name}`, which is not {described}")))
}

fn parse_pit_record(node: Node<'_>) -> Result<PitRecord, DatasetError> {
    let result = node.field("pitResult", |n| {
        let text = n.string()?;
        PitResult::parse(&text).ok_or_else(|| {
            n.error(format!(
                "must be a pit result (`Left Pit Observed`, `Right Pit to Predict`, `No Pit Observed or to Predict`, …), found `{text}`"
            ))
        })
    })?;
    let frame = node.field("pitFrame", |n| {
        let frame = n.integer()?;
        u32::try_from(frame)
            .map_err(|_| n.error(format!("must be a frame (0 or more), found {frame}")))
    })?;
    Ok(PitRecord { result, frame })
}

/// A palette colour id, matching `color` (the name's colour) when the name has one.
fn palette_color(node: Node<'_>, name: &str, color: Option<&str>) -> Result<u8, DatasetError> {
    let id = node.integer()?;
    let Some(palette) = palette_name(id) else {
        return Err(node.error(format!("must be a palette colour id (0 to 16), found {id}")));
    };
    if let Some(color) = color
        && color != palette
    {
        return Err(node.error(format!(
            "is {id} ({palette}), but the object is named `{name}`"
        )));
    }
    u8::try_from(id).map_err(|_| node.error("must be a palette colour id (0 to 16)"))
}

fn parse_slab(node: Node<'_>, kind: BallObjectKind) -> Result<SlabRecord, DatasetError> {
    let name = node.field("name", |n| n.string())?;
    let color = node.field("name", |n| object_name(&n, &name, kind))?;
    Ok(SlabRecord {
        color: node.field("color", |n| palette_color(n, &name, color))?,
        position: node.field("position", |n| n.unity_vector3())?,
        rotation_deg: node.field("rotation", |n| n.unity_vector3())?,
        scale: node.field("scale", |n| n.unity_vector3())?,
        start: node.field("startP", |n| n.number_pair())?,
        end: node.field("endP", |n| n.number_pair())?,
        length: node.field("length", |n| n.number())?,
        angle_rad: node.field("angleRad", |n| n.number())?,
        name,
    })
}

fn parse_ball(node: Node<'_>) -> Result<BallRecord, DatasetError> {
    let name = node.field("name", |n| n.string())?;
    let color = node.field("name", |n| object_name(&n, &name, BallObjectKind::Ball))?;
    let elasticity = node.field("elasticityType", |n| {
        let text = n.string()?;
        ElasticityType::ALL
            .into_iter()
            .find(|kind| kind.as_str() == text)
            .ok_or_else(|| {
                n.error(format!(
                    "must be `Elastic`, `Rigid` or `Plastic`, found `{text}`"
                ))
            })
    })?;
    let release = node.field("releasePos", |n| n.numbers(Some(3)))?;
    Ok(BallRecord {
        color: node.field("color", |n| palette_color(n, &name, color))?,
        elasticity,
        release_position: [release[0], release[1], release[2]],
        name,
    })
}

fn parse_layout(node: Node<'_>) -> Result<BallLayout, DatasetError> {
    let slabs = |key: &str, kind: BallObjectKind| {
        node.field(key, |n| n.items(|slab| parse_slab(slab, kind)))
    };
    let holes = node.field("holesCenterXValue", |n| n.numbers(Some(2)))?;
    Ok(BallLayout {
        ramps: slabs("ramps", BallObjectKind::Ramp)?,
        floor_pieces: slabs("floorPieces", BallObjectKind::FloorPiece)?,
        floating_walls: slabs("floatingWalls", BallObjectKind::FloatingWall)?,
        balls: node.field("balls", |n| n.items(parse_ball))?,
        holes_centre_x: [holes[0], holes[1]],
    })
}

fn parse_counterfactual(key: &str, node: Node<'_>) -> Result<BallCounterfactual, DatasetError> {
    node.field("mode", |n| expect_mode(n, COUNTERFACTUAL_MODE))?;
    let removed_wall = node.field("removedWall", |n| {
        let name = n.string()?;
        object_name(&n, &name, BallObjectKind::FloatingWall)?;
        Ok(name)
    })?;
    let ball = node.field("ball", |n| {
        let name = n.string()?;
        object_name(&n, &name, BallObjectKind::Ball)?;
        Ok(name)
    })?;
    let record = node.field("trackingData", |n| {
        n.field(ONLY_THAT_BALL, parse_pit_record)
    })?;
    if matches!(record.result, PitResult::ToPredict(_)) {
        return Err(node.error(format!(
            "has `{}`: a counterfactual run only observes",
            record.result.as_str()
        )));
    }
    Ok(BallCounterfactual {
        key: key.to_string(),
        removed_wall,
        ball,
        record,
    })
}
