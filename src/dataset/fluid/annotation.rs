//! Typed fluid annotations (`fluid_slides/<id>/outputs.json`, `docs/data/fluid.md`): the
//! tracking data of the factual run and of each counterfactual run, the sampled layout (tank,
//! sticks, containers, fluids), collider transforms, the camera and the light.
//!
//! Only what the release's generator writes is accepted: every key it writes for the engine and
//! backends is required, names must follow the generator's grammar (`names`), colour ids must be
//! palette ids matching the name, particle counts must be whole and non-negative, and a
//! `Vector3` must be Unity's `"(x, y, z)"` string. Errors name the file and the dotted field.
//! Maps keep file order (`IndexMap`).
//!
//! One normalisation: density relations are stored between base fluids. The release writes
//! emitter names, so a predictive emitter's fluid appears as `Later Emitted <C> Fluid`, and a
//! fluid sharing a container with its own predictive emitter gave the release relations in both
//! directions (and, after its closure, a fluid heavier than itself). Here `Later Emitted ` is
//! stripped, pairs of a fluid with itself are dropped and repeated pairs kept once.

use std::path::Path;

use indexmap::IndexMap;
use serde::Serialize;

use super::names::{
    ContainerPart, FluidObjectKind, FluidObjectName, base_fluid_name, container_part_name,
    palette_name, parse_fluid_object_name,
};
use super::outcome::{DensityOrdering, Receptor, Rect};
use crate::dataset::DatasetError;
use crate::dataset::camera::{Camera, parse_camera};
use crate::dataset::fields::{Node, expect_mode, light_rotations, read_json};
use crate::dataset::segmentation::parse_image_descriptions;

/// `mode` of a factual record.
const FACTUAL_MODE: &str = "FACTUAL_PREDICTIVE";
/// `mode` of a counterfactual record.
const COUNTERFACTUAL_MODE: &str = "COUNTERFACTUAL_";
/// The numeric keys of `metaSamplingData.container` besides `size` and `centre_location`.
const TANK_NUMBER_KEYS: [&str; 18] = [
    "lowerLimitY",
    "wall_thickness",
    "O_x",
    "O_y",
    "pos_x_vert1",
    "pos_x_vert2",
    "pos_y_vert1",
    "pos_y_vert2",
    "pos_x_hori1",
    "pos_x_hori2",
    "pos_y_hori1",
    "pos_y_hori2",
    "pos_z",
    "scl_x_vert",
    "scl_y_vert",
    "scl_x_hori",
    "scl_y_hori",
    "scl_z",
];

/// `heavier` is denser than `lighter`: one entry of `allDensityRelations`, between base fluids.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub struct DensityRelation {
    /// The denser fluid (`Pink Fluid`).
    pub heavier: String,
    /// The lighter fluid.
    pub lighter: String,
}

/// `trackingData` of one run.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct FluidTracking {
    /// Fluid (emitter name, `Later Emitted …` included) → collider → particles that touched it
    /// (more than 20, except the fluid's own `… Emitter` entry).
    pub per_emitter_stick_stat: IndexMap<String, IndexMap<String, u32>>,
    /// Every regular stick of the run → its temperature (`Normal`).
    pub temperature_stick: IndexMap<String, String>,
    /// Regular sticks some fluid touched with more than 20 particles → temperature.
    pub temperature_askable_stick: IndexMap<String, String>,
    /// Container → fluid → particles ending inside its cup or funnel (more than 20).
    pub per_receptor_fluid_stat: IndexMap<String, IndexMap<String, u32>>,
    /// `allDensityRelations`, normalised to base fluids (see the module docs).
    pub density_relations: Vec<DensityRelation>,
}

impl FluidTracking {
    /// The colliders `fluid` touched (`perEmitterStickStat[fluid]`), if it is listed.
    pub fn contacts(&self, fluid: &str) -> Option<&IndexMap<String, u32>> {
        self.per_emitter_stick_stat.get(fluid)
    }

    /// Particles of `fluid` ending in `container`; 0 when not listed (20 or fewer).
    pub fn particles_in(&self, container: &str, fluid: &str) -> u32 {
        self.per_receptor_fluid_stat
            .get(container)
            .and_then(|fluids| fluids.get(fluid))
            .copied()
            .unwrap_or(0)
    }

    /// Whether `container` holds strictly more of `fluid` than every other container (an
    /// unlisted count is 0, so a container without the fluid never holds most, and a container
    /// the run does not list cannot beat one that holds some).
    pub fn holds_most(&self, container: &str, fluid: &str) -> bool {
        let count = self.particles_in(container, fluid);
        count > 0
            && self
                .per_receptor_fluid_stat
                .keys()
                .filter(|other| *other != container)
                .all(|other| self.particles_in(other, fluid) < count)
    }

    /// The run's density relations, closed transitively.
    pub fn density_ordering(&self) -> DensityOrdering {
        let relations: Vec<(String, String)> = self
            .density_relations
            .iter()
            .map(|relation| (relation.heavier.clone(), relation.lighter.clone()))
            .collect();
        DensityOrdering::new(&relations)
    }
}

/// A stick of `metaSamplingData` (a regular stick, or a container's guided stick).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StickRecord {
    /// `<C> Stick` (or `<C> Container Left|Right Guided Stick`).
    pub name: String,
    /// Palette colour id.
    pub color: u8,
    /// `Normal` (or `Boiling`, never drawn by the release).
    pub temperature: String,
    /// Flagged rotatable (the release builds every stick from the fixed prefab).
    pub is_rotatable: bool,
    /// Centre relative to the tank origin `(O_x, O_y, pos_z)`, units.
    pub position: [f64; 3],
    /// Unity Euler angles, degrees (only z is non-zero).
    pub rotation_deg: [f64; 3],
    /// `(length, 0.15, 0.20)`, units.
    pub scale: [f64; 3],
    /// One end `(x, y)` relative to the tank origin, units.
    pub start: [f64; 2],
    /// The other end, units.
    pub end: [f64; 2],
    /// Length, units.
    pub length: f64,
    /// Angle to the x axis, radians.
    pub angle_rad: f64,
}

/// A container of `metaSamplingData.reservoirs`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReservoirRecord {
    /// `<C> Container`.
    pub name: String,
    /// Palette colour id.
    pub color: u8,
    /// Cup centre relative to the tank origin, units.
    pub cup_position: [f64; 3],
    /// Cup size, units.
    pub cup_scale: [f64; 3],
    /// The funnel's left guided stick.
    pub stick_left: StickRecord,
    /// The funnel's right guided stick.
    pub stick_right: StickRecord,
}

impl ReservoirRecord {
    /// The cup in world coordinates (`origin` is the tank origin `(O_x, O_y)`).
    pub fn cup_box(&self, origin: [f64; 2]) -> Rect {
        Rect::from_centre_size(
            [
                self.cup_position[0] + origin[0],
                self.cup_position[1] + origin[1],
            ],
            [self.cup_scale[0], self.cup_scale[1]],
        )
    }

    /// The bounding box of the guided sticks' end points in world coordinates.
    pub fn funnel_box(&self, origin: [f64; 2]) -> Rect {
        let shifted = |point: [f64; 2]| [point[0] + origin[0], point[1] + origin[1]];
        let corners = [
            shifted(self.stick_left.start),
            shifted(self.stick_left.end),
            shifted(self.stick_right.start),
            shifted(self.stick_right.end),
        ];
        Rect::bounding(&corners).unwrap_or(Rect {
            min: corners[0],
            max: corners[0],
        })
    }
}

/// `"Sticky"` or `"Non-Sticky"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Viscosity {
    /// `"Sticky"` (Obi viscosity 10).
    Sticky,
    /// `"Non-Sticky"` (Obi viscosity 0.02).
    NonSticky,
}

/// A fluid of `metaSamplingData.fluids`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FluidRecord {
    /// `<C> Fluid`.
    pub name: String,
    /// Palette colour id.
    pub color: u8,
    /// Obi rest density (one of the video's density pool).
    pub density: f64,
    /// Sticky or not.
    pub viscosity: Viscosity,
    /// The Obi viscosity used (`viscositiesUnderTemperature`).
    pub viscosity_value: f64,
    /// Obi surface tension.
    pub surface_tension: f64,
    /// Particles per emitter.
    pub amount: u32,
    /// The emitter's position relative to the tank origin, units.
    pub emitter_position: [f64; 3],
    /// Whether a predictive emitter (`Later Emitted <C> Fluid`) emits the same fluid late.
    pub has_predictive_emitter: bool,
    /// The predictive emitter's position (zeros when there is none), units.
    pub predictive_emitter_position: [f64; 3],
    /// The predictive emitter's colour id (`None` for the release's `-1`).
    pub predictive_emitter_color: Option<u8>,
}

/// `metaSamplingData.container`: the tank.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TankLayout {
    /// Inner size `(x, y, z)`, units.
    pub size: [f64; 3],
    /// Centre, units.
    pub centre: [f64; 3],
    /// The origin `(O_x, O_y)` that sticks, cups and emitters are placed from, units.
    pub origin: [f64; 2],
    /// Every other number (`lowerLimitY`, `wall_thickness`, wall positions and scales), by key.
    pub numbers: IndexMap<String, f64>,
}

/// `metaSamplingData`: the sampled layout.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FluidLayout {
    /// The tank.
    pub tank: TankLayout,
    /// The regular sticks, in the release's order (bottom to top).
    pub sticks: Vec<StickRecord>,
    /// The containers, left to right.
    pub reservoirs: Vec<ReservoirRecord>,
    /// The fluids (factual emitters).
    pub fluids: Vec<FluidRecord>,
}

impl FluidLayout {
    /// Each container's cup and funnel boxes in world coordinates, as the counting of
    /// `perReceptorFluidStat` sees them.
    pub fn receptors(&self) -> Vec<Receptor<'_>> {
        self.reservoirs
            .iter()
            .map(|reservoir| Receptor {
                name: &reservoir.name,
                cup: reservoir.cup_box(self.tank.origin),
                funnel: reservoir.funnel_box(self.tank.origin),
            })
            .collect()
    }
}

/// One collider's pose in `allObjectTransforms`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ObjectTransform {
    /// World position, units.
    pub position: [f64; 3],
    /// Unity Euler angles, degrees.
    pub rotation_deg: [f64; 3],
    /// Lossy scale.
    pub scale: [f64; 3],
}

/// One counterfactual run: the factual scene without one stick, factual emitters only.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FluidCounterfactual {
    /// The record key in `CounterFactualAnnotations`.
    pub key: String,
    /// The removed stick (`removedStickName`).
    pub removed_stick: String,
    /// Its tracking data.
    pub tracking: FluidTracking,
}

/// The fluid annotations of one valid video.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FluidAnnotation {
    /// The factual run's tracking data (includes 200 updates after the video).
    pub tracking: FluidTracking,
    /// The sampled layout.
    pub layout: FluidLayout,
    /// Every collider's pose, by name.
    pub object_transforms: IndexMap<String, ObjectTransform>,
    /// The main camera, when recorded.
    pub camera: Option<Camera>,
    /// The light's Euler angles in degrees, by light object name.
    pub light_rotation_deg: IndexMap<String, [f64; 3]>,
    /// The counterfactual runs in file order.
    pub counterfactuals: Vec<FluidCounterfactual>,
    /// Instance id → scene object name (`Id2ObjectNameDict`), in file order; empty if absent.
    pub id_to_object_name: Vec<(u32, String)>,
    /// Number of annotated frames (`perFrameAnnotations`), 0 if absent.
    pub frame_count: usize,
}

impl FluidAnnotation {
    /// Loads and validates the annotations of `path` (an `outputs.json`).
    pub fn load(path: &Path) -> Result<FluidAnnotation, DatasetError> {
        let value = read_json(path)?;
        FluidAnnotation::from_json(path, &value)
    }

    /// Validates an already parsed document; `path` is used in error messages.
    pub fn from_json(
        path: &Path,
        value: &serde_json::Value,
    ) -> Result<FluidAnnotation, DatasetError> {
        let root = Node::root(path, value);
        if !root.field("validity", |n| n.boolean())? {
            return Err(root.error("has `validity: false`: an invalid trial has no annotations"));
        }
        root.field("mode", |n| expect_mode(n, FACTUAL_MODE))?;
        let tracking = root.field("trackingData", parse_tracking)?;
        let layout = root.field("metaSamplingData", parse_layout)?;
        let object_transforms = root.field("allObjectTransforms", |n| {
            Ok(
                n.entries(|name, transform| Ok((name.to_string(), parse_transform(transform)?)))?
                    .into_iter()
                    .collect(),
            )
        })?;
        let camera = root.field("outputCamera", parse_camera)?;
        let light_rotation_deg = root.field("outputLight", light_rotations)?;
        let counterfactuals = root.field("CounterFactualAnnotations", |n| {
            n.entries(parse_counterfactual)
        })?;
        let (id_to_object_name, frame_count) = root
            .optional_field("imgAnnotationDescriptions", parse_image_descriptions)?
            .unwrap_or_default();
        Ok(FluidAnnotation {
            tracking,
            layout,
            object_transforms,
            camera,
            light_rotation_deg,
            counterfactuals,
            id_to_object_name,
            frame_count,
        })
    }

    /// The counterfactual run without `stick`, if there is one (the first, should two exist).
    pub fn counterfactual_without(&self, stick: &str) -> Option<&FluidCounterfactual> {
        self.counterfactuals
            .iter()
            .find(|run| run.removed_stick == stick)
    }
}

/// A name of `kind` (and, for fluids, `later` or not when `later` is given).
fn object_name(
    node: &Node<'_>,
    name: &str,
    kind: FluidObjectKind,
    later: Option<bool>,
) -> Result<FluidObjectName, DatasetError> {
    let described = match (kind, later) {
        (FluidObjectKind::Fluid, Some(false)) => "a fluid name (`<Colour> Fluid`)",
        (FluidObjectKind::Fluid, _) => {
            "a fluid name (`<Colour> Fluid` or `Later Emitted <Colour> Fluid`)"
        }
        (FluidObjectKind::Stick, _) => "a stick name (`<Colour> Stick`)",
        (FluidObjectKind::Container, _) => "a container name (`<Colour> Container`)",
        _ => "a fluid-scene object name",
    };
    parse_fluid_object_name(name)
        .filter(|parsed| parsed.kind == kind && later.is_none_or(|later| parsed.later == later))
        .ok_or_else(|| node.error(format!("names `{name}`, which is not {described}")))
}

/// A map of names of `kind` to particle counts.
fn count_map(
    node: Node<'_>,
    kind: Option<FluidObjectKind>,
) -> Result<IndexMap<String, u32>, DatasetError> {
    let entries = node.entries(|name, count| {
        if let Some(kind) = kind {
            object_name(&count, name, kind, None)?;
        }
        Ok((name.to_string(), particle_count(count)?))
    })?;
    Ok(entries.into_iter().collect())
}

fn particle_count(node: Node<'_>) -> Result<u32, DatasetError> {
    let count = node.integer()?;
    u32::try_from(count).map_err(|_| {
        node.error(format!(
            "must be a particle count (0 or more), found {count}"
        ))
    })
}

fn temperature_map(node: Node<'_>) -> Result<IndexMap<String, String>, DatasetError> {
    let entries = node.entries(|name, temperature| {
        object_name(&temperature, name, FluidObjectKind::Stick, None)?;
        Ok((name.to_string(), temperature.string()?))
    })?;
    Ok(entries.into_iter().collect())
}

fn parse_tracking(node: Node<'_>) -> Result<FluidTracking, DatasetError> {
    let per_emitter_stick_stat = node.field("perEmitterStickStat", |n| {
        Ok(n.entries(|fluid, colliders| {
            object_name(&colliders, fluid, FluidObjectKind::Fluid, None)?;
            // Colliders are any object with an Obi collider (sticks, walls, container parts,
            // emitter parts): not checked against the grammar.
            Ok((fluid.to_string(), count_map(colliders, None)?))
        })?
        .into_iter()
        .collect())
    })?;
    let temperature_stick = node.field("temperatureStick", temperature_map)?;
    let temperature_askable_stick = node.field("temperatureAskableStick", temperature_map)?;
    let per_receptor_fluid_stat = node.field("perReceptorFluidStat", |n| {
        Ok(n.entries(|container, fluids| {
            object_name(&fluids, container, FluidObjectKind::Container, None)?;
            Ok((
                container.to_string(),
                count_map(fluids, Some(FluidObjectKind::Fluid))?,
            ))
        })?
        .into_iter()
        .collect())
    })?;
    let written = node.field("allDensityRelations", |n| {
        n.items(|relation| {
            let heavier = relation.field("Item1", density_fluid)?;
            let lighter = relation.field("Item2", density_fluid)?;
            Ok(DensityRelation { heavier, lighter })
        })
    })?;
    let mut density_relations: Vec<DensityRelation> = Vec::with_capacity(written.len());
    for relation in written {
        if relation.heavier != relation.lighter && !density_relations.contains(&relation) {
            density_relations.push(relation);
        }
    }
    Ok(FluidTracking {
        per_emitter_stick_stat,
        temperature_stick,
        temperature_askable_stick,
        per_receptor_fluid_stat,
        density_relations,
    })
}

/// A fluid of a density relation, as its base fluid.
fn density_fluid(node: Node<'_>) -> Result<String, DatasetError> {
    let name = node.string()?;
    object_name(&node, &name, FluidObjectKind::Fluid, None)?;
    Ok(base_fluid_name(&name).to_string())
}

/// A palette colour id that must match the colour of `name`.
fn palette_color(node: Node<'_>, name: &FluidObjectName) -> Result<u8, DatasetError> {
    let id = node.integer()?;
    let Some(palette) = palette_name(id) else {
        return Err(node.error(format!("must be a palette colour id (0 to 16), found {id}")));
    };
    if name.color != Some(palette) {
        return Err(node.error(format!(
            "is {id} ({palette}), but the object is named `{}`",
            name.full
        )));
    }
    u8::try_from(id).map_err(|_| node.error("must be a palette colour id (0 to 16)"))
}

fn parse_stick(node: Node<'_>, expected_name: Option<&str>) -> Result<StickRecord, DatasetError> {
    let name = node.field("name", |n| {
        let name = n.string()?;
        match expected_name {
            Some(expected) if name != expected => {
                Err(n.error(format!("must be `{expected}`, found `{name}`")))
            }
            Some(_) => Ok(name),
            None => object_name(&n, &name, FluidObjectKind::Stick, None).map(|_| name),
        }
    })?;
    let parsed = parse_fluid_object_name(&name)
        .ok_or_else(|| node.error(format!("names `{name}`, which is not a stick name")))?;
    Ok(StickRecord {
        color: node.field("color", |n| palette_color(n, &parsed))?,
        temperature: node.field("temperature", |n| n.string())?,
        is_rotatable: node.field("isRotatable", |n| n.boolean())?,
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

fn parse_reservoir(node: Node<'_>) -> Result<ReservoirRecord, DatasetError> {
    let name = node.field("name", |n| n.string())?;
    let parsed = node.field("name", |n| {
        object_name(&n, &name, FluidObjectKind::Container, None)
    })?;
    let guided = |part: ContainerPart| container_part_name(&name, part);
    Ok(ReservoirRecord {
        color: node.field("color", |n| palette_color(n, &parsed))?,
        cup_position: node.field("cupPosition", |n| n.unity_vector3())?,
        cup_scale: node.field("cupScale", |n| n.unity_vector3())?,
        stick_left: node.field("stickLeft", |n| {
            parse_stick(n, Some(&guided(ContainerPart::LeftGuidedStick)))
        })?,
        stick_right: node.field("stickRight", |n| {
            parse_stick(n, Some(&guided(ContainerPart::RightGuidedStick)))
        })?,
        name,
    })
}

fn parse_fluid(node: Node<'_>) -> Result<FluidRecord, DatasetError> {
    let name = node.field("name", |n| n.string())?;
    let parsed = node.field("name", |n| {
        object_name(&n, &name, FluidObjectKind::Fluid, Some(false))
    })?;
    let density = node.field("density", |n| {
        let density = n.number()?;
        if density > 0.0 {
            Ok(density)
        } else {
            Err(n.error(format!("must be a positive density, found {density}")))
        }
    })?;
    let viscosity = node.field("viscosity", |n| match n.string()?.as_str() {
        "Sticky" => Ok(Viscosity::Sticky),
        "Non-Sticky" => Ok(Viscosity::NonSticky),
        other => Err(n.error(format!("must be `Sticky` or `Non-Sticky`, found `{other}`"))),
    })?;
    let has_predictive_emitter = node.field("hasPredEmitter", |n| n.boolean())?;
    let predictive_emitter_color = node.field("pred_emitter_color", |n| {
        match (has_predictive_emitter, n.integer()?) {
            (false, -1) => Ok(None),
            (false, other) => Err(n.error(format!(
                "must be -1 for a fluid without a predictive emitter, found {other}"
            ))),
            (true, _) => palette_color(n, &parsed).map(Some),
        }
    })?;
    Ok(FluidRecord {
        color: node.field("color", |n| palette_color(n, &parsed))?,
        density,
        viscosity,
        viscosity_value: node.field("viscositiesUnderTemperature", |n| n.number())?,
        surface_tension: node.field("surfaceTension", |n| n.number())?,
        amount: node.field("amount", particle_count)?,
        emitter_position: node.field("emitter_pos", |n| n.unity_vector3())?,
        has_predictive_emitter,
        predictive_emitter_position: node.field("pred_emitter_pos", |n| n.unity_vector3())?,
        predictive_emitter_color,
        name,
    })
}

fn parse_tank(node: Node<'_>) -> Result<TankLayout, DatasetError> {
    let triple = |key: &str| {
        node.field(key, |n| {
            let values = n.numbers(Some(3))?;
            Ok([values[0], values[1], values[2]])
        })
    };
    let mut numbers = IndexMap::new();
    for key in TANK_NUMBER_KEYS {
        numbers.insert(key.to_string(), node.field(key, |n| n.number())?);
    }
    let origin = [
        numbers.get("O_x").copied().unwrap_or_default(),
        numbers.get("O_y").copied().unwrap_or_default(),
    ];
    Ok(TankLayout {
        size: triple("size")?,
        centre: triple("centre_location")?,
        origin,
        numbers,
    })
}

fn parse_layout(node: Node<'_>) -> Result<FluidLayout, DatasetError> {
    Ok(FluidLayout {
        tank: node.field("container", parse_tank)?,
        sticks: node.field("sticks", |n| n.items(|stick| parse_stick(stick, None)))?,
        reservoirs: node.field("reservoirs", |n| n.items(parse_reservoir))?,
        fluids: node.field("fluids", |n| n.items(parse_fluid))?,
    })
}

fn parse_transform(node: Node<'_>) -> Result<ObjectTransform, DatasetError> {
    let triple = |key: &str| {
        node.field(key, |n| {
            let values = n.numbers(Some(3))?;
            Ok([values[0], values[1], values[2]])
        })
    };
    Ok(ObjectTransform {
        position: triple("position")?,
        rotation_deg: triple("rotation")?,
        scale: triple("scale")?,
    })
}

fn parse_counterfactual(key: &str, node: Node<'_>) -> Result<FluidCounterfactual, DatasetError> {
    node.field("mode", |n| expect_mode(n, COUNTERFACTUAL_MODE))?;
    let removed_stick = node.field("removedStickName", |n| {
        let name = n.string()?;
        object_name(&n, &name, FluidObjectKind::Stick, None)?;
        Ok(name)
    })?;
    Ok(FluidCounterfactual {
        key: key.to_string(),
        removed_stick,
        tracking: node.field("trackingData", parse_tracking)?,
    })
}

#[cfg(test)]
#[expect(
    clippy::float_cmp,
    reason = "numbers read from the fixture's decimal text equal the same literals exactly"
)]
mod tests {
    //! Checks against the hand-written fluid video `tests/data/fluid_slides/0/outputs.json`
    //! (3 fluids, one with a predictive emitter, 3 sticks, 2 containers, 2 counterfactual runs).
    use serde_json::{Value, json};

    use super::*;
    use crate::dataset::fluid::outcome::{
        counterfactual_sticks, density_relations, temperature_askable_sticks,
    };
    use crate::util::seeded_rng;

    fn fixture() -> Value {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fluid_slides/0/outputs.json");
        serde_json::from_slice(&fs_err::read(&path).unwrap()).unwrap()
    }

    fn read(value: &Value) -> Result<FluidAnnotation, DatasetError> {
        FluidAnnotation::from_json(Path::new("outputs.json"), value)
    }

    fn close(actual: [f64; 2], expected: [f64; 2]) -> bool {
        (actual[0] - expected[0]).abs() < 1e-9 && (actual[1] - expected[1]).abs() < 1e-9
    }

    #[test]
    fn the_fixture_loads_with_its_hand_written_contents() {
        let annotation = read(&fixture()).unwrap();
        let layout = &annotation.layout;
        let sticks: Vec<(&str, u8)> = layout
            .sticks
            .iter()
            .map(|s| (s.name.as_str(), s.color))
            .collect();
        assert_eq!(
            sticks,
            [("Brown Stick", 8), ("Cyan Stick", 4), ("Gray Stick", 9)]
        );
        let cyan = &layout.sticks[1];
        assert_eq!(cyan.position, [3.3, 1.3, 0.0]);
        assert_eq!(cyan.rotation_deg, [0.0, 0.0, 35.0]);
        assert_eq!(cyan.scale, [1.8, 0.15, 0.2]);
        assert_eq!((cyan.start, cyan.end), ([2.5628, 0.7838], [4.0372, 1.8162]));
        assert_eq!(layout.tank.origin, [-2.5, -1.25]);
        assert_eq!(layout.tank.numbers["scl_y_vert"], 7.85);
        // Red cup: centre (1.15 - 2.5, -2.31 - 1.25), size (1.62, 0.88).
        let red = &layout.reservoirs[0];
        assert_eq!(red.stick_left.name, "Red Container Left Guided Stick");
        let cup = red.cup_box(layout.tank.origin);
        assert!(
            close(cup.min, [-2.16, -4.0]) && close(cup.max, [-0.54, -3.12]),
            "{cup:?}"
        );
        // Red funnel: guided stick ends (-0.2, -1.5), (0.583, -2.04375), (2.5, -1.5),
        // (1.717, -2.04375), shifted by the origin.
        let funnel = red.funnel_box(layout.tank.origin);
        assert!(
            close(funnel.min, [-2.7, -3.29375]) && close(funnel.max, [0.0, -2.75]),
            "{funnel:?}"
        );
        assert_eq!(layout.receptors()[1].name, "Green Container");
        let yellow = &layout.fluids[2];
        assert_eq!(
            (yellow.name.as_str(), yellow.density, yellow.viscosity),
            ("Yellow Fluid", 3000.0, Viscosity::NonSticky)
        );
        assert!(yellow.has_predictive_emitter);
        assert_eq!(yellow.predictive_emitter_color, Some(2));
        assert_eq!(yellow.predictive_emitter_position, [3.2, 4.1, 0.0]);
        assert_eq!(layout.fluids[0].viscosity, Viscosity::Sticky);
        assert_eq!(layout.fluids[0].predictive_emitter_color, None);

        let tracking = &annotation.tracking;
        assert_eq!(
            tracking.contacts("Later Emitted Yellow Fluid").unwrap()["Gray Stick"],
            230
        );
        assert_eq!(
            tracking.particles_in("Green Container", "Later Emitted Yellow Fluid"),
            240
        );
        assert_eq!(
            tracking.particles_in("Red Container", "Light Blue Fluid"),
            0
        );
        // Written as (Pink, Yellow) and (Later Emitted Yellow, Light Blue).
        let relations: Vec<(&str, &str)> = tracking
            .density_relations
            .iter()
            .map(|r| (r.heavier.as_str(), r.lighter.as_str()))
            .collect();
        assert_eq!(
            relations,
            [
                ("Pink Fluid", "Yellow Fluid"),
                ("Yellow Fluid", "Light Blue Fluid")
            ]
        );
        let removed: Vec<(&str, &str)> = annotation
            .counterfactuals
            .iter()
            .map(|run| (run.key.as_str(), run.removed_stick.as_str()))
            .collect();
        assert_eq!(removed, [("0", "Brown Stick"), ("1", "Gray Stick")]);
        let without_gray = annotation.counterfactual_without("Gray Stick").unwrap();
        assert_eq!(
            without_gray
                .tracking
                .particles_in("Red Container", "Light Blue Fluid"),
            900
        );
        assert!(
            without_gray
                .tracking
                .contacts("Later Emitted Yellow Fluid")
                .unwrap()
                .is_empty()
        );
        assert!(annotation.counterfactual_without("Cyan Stick").is_none());
        assert_eq!(annotation.camera.as_ref().unwrap().vertical_fov_deg, 55.3);
        assert_eq!(
            annotation.light_rotation_deg["Prefabs/Fluid Slides/Directional Light"],
            [-5.2, 31.7, 0.0]
        );
        assert_eq!(
            annotation.object_transforms["Floor"].position,
            [0.0, -4.25, 0.0]
        );
        assert_eq!(
            annotation.id_to_object_name[1],
            (7, "Brown Stick".to_string())
        );
        assert_eq!(annotation.frame_count, 0);
    }

    #[test]
    fn the_release_labelling_reproduces_the_fixtures_tracking() {
        let value = fixture();
        let annotation = read(&value).unwrap();
        let tracking = &annotation.tracking;
        // Pink: brown 900 (cyan 90 is not over 100); light blue: gray; yellow: brown again;
        // later yellow: gray again.
        let sticks: Vec<&str> = annotation
            .layout
            .sticks
            .iter()
            .map(|s| s.name.as_str())
            .collect();
        assert_eq!(
            counterfactual_sticks(
                &tracking.per_emitter_stick_stat,
                &sticks,
                &mut seeded_rng(0)
            ),
            ["Brown Stick", "Gray Stick"]
        );
        let densities: Vec<(&str, f64)> = annotation
            .layout
            .fluids
            .iter()
            .map(|f| (f.name.as_str(), f.density))
            .collect();
        let written: Vec<(String, String)> = value["trackingData"]["allDensityRelations"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| {
                (
                    r["Item1"].as_str().unwrap().to_string(),
                    r["Item2"].as_str().unwrap().to_string(),
                )
            })
            .collect();
        assert_eq!(
            density_relations(&tracking.per_receptor_fluid_stat, &densities),
            written
        );
        assert_eq!(
            temperature_askable_sticks(
                &tracking.per_emitter_stick_stat,
                &tracking.temperature_stick
            ),
            tracking.temperature_askable_stick
        );
    }

    #[test]
    fn missing_tracking_data_is_one_clear_error() {
        let mut value = fixture();
        value.as_object_mut().unwrap().remove("trackingData");
        assert_eq!(
            read(&value).unwrap_err().to_string(),
            "`outputs.json`: field `trackingData` is missing"
        );
        let mut value = fixture();
        value["CounterFactualAnnotations"]["1"]
            .as_object_mut()
            .unwrap()
            .remove("trackingData");
        assert_eq!(
            read(&value).unwrap_err().to_string(),
            "`outputs.json`: field `CounterFactualAnnotations.1.trackingData` is missing"
        );
        let error = FluidAnnotation::load(Path::new("no/such/outputs.json")).unwrap_err();
        assert!(
            error.to_string().contains("no/such/outputs.json"),
            "{error}"
        );
    }

    #[test]
    fn malformed_fields_are_named() {
        // (JSON pointer, new value, the error after "`outputs.json`: field ")
        let cases = [
            (
                "/metaSamplingData/sticks/1/position",
                json!("(3.30, 1.30)"),
                "`metaSamplingData.sticks.1.position` must be a Unity vector string \"(x, y, z)\" of three finite numbers, found \"(3.30, 1.30)\"",
            ),
            (
                "/metaSamplingData/reservoirs/0/cupScale",
                json!("(1.62; 0.88; 0.20)"),
                "`metaSamplingData.reservoirs.0.cupScale` must be a Unity vector string \"(x, y, z)\" of three finite numbers, found \"(1.62; 0.88; 0.20)\"",
            ),
            (
                "/metaSamplingData/sticks/0/color",
                json!(4),
                "`metaSamplingData.sticks.0.color` is 4 (Cyan), but the object is named `Brown Stick`",
            ),
            (
                "/metaSamplingData/fluids/1/color",
                json!(17),
                "`metaSamplingData.fluids.1.color` must be a palette colour id (0 to 16), found 17",
            ),
            (
                "/metaSamplingData/fluids/0/viscosity",
                json!("Runny"),
                "`metaSamplingData.fluids.0.viscosity` must be `Sticky` or `Non-Sticky`, found `Runny`",
            ),
            (
                "/metaSamplingData/fluids/2/pred_emitter_color",
                json!(-1),
                "`metaSamplingData.fluids.2.pred_emitter_color` must be a palette colour id (0 to 16), found -1",
            ),
            (
                "/metaSamplingData/reservoirs/1/stickLeft/name",
                json!("Green Container Right Guided Stick"),
                "`metaSamplingData.reservoirs.1.stickLeft.name` must be `Green Container Left Guided Stick`, found `Green Container Right Guided Stick`",
            ),
            (
                "/trackingData/perReceptorFluidStat/Red Container/Pink Fluid",
                json!(-3),
                "`trackingData.perReceptorFluidStat.Red Container.Pink Fluid` must be a particle count (0 or more), found -3",
            ),
            (
                "/trackingData/perEmitterStickStat/Pink Fluid/Brown Stick",
                json!(900.5),
                "`trackingData.perEmitterStickStat.Pink Fluid.Brown Stick` must be an integer, found 900.5",
            ),
            (
                "/trackingData/allDensityRelations/1/Item2",
                json!("Light Blue Liquid"),
                "`trackingData.allDensityRelations.1.Item2` names `Light Blue Liquid`, which is not a fluid name (`<Colour> Fluid` or `Later Emitted <Colour> Fluid`)",
            ),
            (
                "/mode",
                json!("FACTUAL"),
                "`mode` must be `FACTUAL_PREDICTIVE`, found `FACTUAL`",
            ),
            (
                "/CounterFactualAnnotations/0/removedStickName",
                json!("Red Container Left Guided Stick"),
                "`CounterFactualAnnotations.0.removedStickName` names `Red Container Left Guided Stick`, which is not a stick name (`<Colour> Stick`)",
            ),
            (
                "/CounterFactualAnnotations/1/mode",
                json!("COUNTERFACTUAL_remove_stick"),
                "`CounterFactualAnnotations.1.mode` must be `COUNTERFACTUAL_`, found `COUNTERFACTUAL_remove_stick`",
            ),
        ];
        for (pointer, replacement, expected) in cases {
            let mut value = fixture();
            *value.pointer_mut(pointer).unwrap() = replacement;
            assert_eq!(
                read(&value).unwrap_err().to_string(),
                format!("`outputs.json`: field {expected}"),
                "{pointer}"
            );
        }
        // An unknown fluid as a key.
        let mut value = fixture();
        value["trackingData"]["perEmitterStickStat"]["Teal Fluid"] = json!({});
        assert_eq!(
            read(&value).unwrap_err().to_string(),
            "`outputs.json`: field `trackingData.perEmitterStickStat.Teal Fluid` names `Teal Fluid`, which is not a fluid name (`<Colour> Fluid` or `Later Emitted <Colour> Fluid`)"
        );
        let mut value = fixture();
        value["validity"] = json!(false);
        assert!(
            read(&value)
                .unwrap_err()
                .to_string()
                .contains("validity: false")
        );
    }

    #[test]
    fn density_relations_are_stored_between_base_fluids() {
        let mut value = fixture();
        let relation = |a: &str, b: &str| json!({"Item1": a, "Item2": b});
        // The release's relations when a fluid shares a container with its own predictive
        // emitter: both directions, and after its closure the fluid heavier than itself.
        value["trackingData"]["allDensityRelations"] = json!([
            relation("Yellow Fluid", "Later Emitted Yellow Fluid"),
            relation("Later Emitted Yellow Fluid", "Yellow Fluid"),
            relation("Pink Fluid", "Later Emitted Yellow Fluid"),
            relation("Pink Fluid", "Yellow Fluid"),
            relation("Yellow Fluid", "Yellow Fluid"),
            relation("Later Emitted Yellow Fluid", "Light Blue Fluid"),
        ]);
        let annotation = read(&value).unwrap();
        let relations: Vec<(&str, &str)> = annotation
            .tracking
            .density_relations
            .iter()
            .map(|r| (r.heavier.as_str(), r.lighter.as_str()))
            .collect();
        assert_eq!(
            relations,
            [
                ("Pink Fluid", "Yellow Fluid"),
                ("Yellow Fluid", "Light Blue Fluid")
            ]
        );
    }
}
