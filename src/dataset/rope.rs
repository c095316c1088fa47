//! Typed rope annotations (`pulley_group/<id>/outputs.json`, `contphy/FORMAT.md` §2) and the
//! grammar of rope object names (`Blue Solid Static Pulley (0 1)`, `Light Blue Cube`, ...).
//!
//! Maps keep file order (`IndexMap`), because the question engine, like the public Python one,
//! iterates them in that order.

use std::path::Path;

use indexmap::IndexMap;
use serde::Serialize;

use super::DatasetError;
use super::fields::{Node, read_json};

/// Facts of the release's rope world that answers and simulations depend on: the timeline and
/// thresholds of `ResultMotion`/`ResultRotation` (FORMAT.md §2.3) and the prefabs' sizes and
/// masses (read from the generator's prefabs; the pulley inertia is checked against the real
/// video, whose loads move as 1 kg disc pulleys predict). Units: world units (nominally metres),
/// kilograms, seconds.
pub mod world {
    /// One physics update of the generator, s (60 Hz); frames are taken every second update.
    pub const UPDATE_SECONDS: f64 = 1.0 / 60.0;
    /// Updates from one captured frame (video frame, 4-D record) to the next.
    pub const UPDATES_PER_FRAME: u32 = 2;
    /// The update at which the factual run applies its random masses and starts recording
    /// (and counterfactual runs make their change).
    pub const CHANGE_UPDATE: u32 = 100;
    /// Updates a factual run simulates after the change (the video's 300 plus 200 unseen).
    pub const FACTUAL_UPDATES_AFTER_CHANGE: u32 = 500;
    /// Updates a counterfactual run simulates after its change.
    pub const COUNTERFACTUAL_UPDATES_AFTER_CHANGE: u32 = 300;
    /// Vertical travel from the change that counts as motion, units.
    pub const MOTION_THRESHOLD: f64 = 1.2;
    /// Turn from the change that counts as rotation, degrees.
    pub const ROTATION_THRESHOLD_DEG: f64 = 35.0;
    /// The masses a factual run draws each load's from, kg, in the generator's order (times
    /// the load's multiplier).
    pub const LOAD_MASSES_KG: [f64; 3] = [0.15, 0.25, 0.20];
    /// Every load's mass in counterfactual runs (and before the change), kg, times its
    /// multiplier.
    pub const BASELINE_MASS_KG: f64 = 0.2;
    /// A counterfactual run's mass change, kg, times the load's multiplier (lighter: −).
    pub const COUNTERFACTUAL_MASS_STEP_KG: f64 = 0.1;
    /// Mass multiplier of a load hanging under a movable pulley.
    pub const MOVABLE_PULLEY_LOAD_MULTIPLIER: f64 = 1.975;
    /// Speed of a pulled static pulley or fixed point, units/s.
    pub const PULL_SPEED: f64 = 2.0;
    /// How far a pulled static pulley moves, units.
    pub const PULL_PULLEY_DISTANCE: f64 = 3.5;
    /// How far a pulled fixed point moves, units.
    pub const PULL_ANCHOR_DISTANCE: f64 = 7.0;
    /// Mass of a static pulley's disc, kg (it turns about its axle).
    pub const STATIC_PULLEY_KG: f64 = 1.0;
    /// Mass of a movable pulley, kg.
    pub const MOVABLE_PULLEY_KG: f64 = 0.005;
    /// Disc radius of a solid ("little") pulley, units.
    pub const SOLID_PULLEY_RADIUS: f64 = 1.74;
    /// Disc radius of a hollow ("big") pulley, units.
    pub const HOLLOW_PULLEY_RADIUS: f64 = 1.613;
    /// Radius at which the rope wraps a solid pulley, units.
    pub const SOLID_WRAP_RADIUS: f64 = 1.914;
    /// Radius at which the rope wraps a hollow pulley, units.
    pub const HOLLOW_WRAP_RADIUS: f64 = 1.61;
    /// Horizontal offset of an end load or anchor from its pulley's centre in the layout
    /// (`metaSamplingData.name2position`), units.
    pub const LAYOUT_END_OFFSET: f64 = 1.48;
    /// Half the height of a load (cube side 2, sphere diameter 2), units.
    pub const LOAD_HALF_HEIGHT: f64 = 1.0;
    /// Height of a load's rope attachment above its centre, units.
    pub const LOAD_ATTACH_HEIGHT: f64 = 0.8;
    /// Height of a fixed point's rope attachment above its centre, units.
    pub const ANCHOR_ATTACH_HEIGHT: f64 = 0.28;
    /// Rope radius, units.
    pub const ROPE_RADIUS: f64 = 0.2;

    /// Moment of inertia of a static pulley's disc about its axle, kg·m²: a uniform disc,
    /// `½ m r²`.
    pub fn static_pulley_inertia(solid: bool) -> f64 {
        let radius = if solid {
            SOLID_PULLEY_RADIUS
        } else {
            HOLLOW_PULLEY_RADIUS
        };
        0.5 * STATIC_PULLEY_KG * radius * radius
    }

    /// The rope's wrap radius round a pulley, units.
    pub fn wrap_radius(solid: bool) -> f64 {
        if solid {
            SOLID_WRAP_RADIUS
        } else {
            HOLLOW_WRAP_RADIUS
        }
    }
}

/// The kind of a rope-scene object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RopeObjectKind {
    /// A cube load.
    Cube,
    /// A sphere load.
    Sphere,
    /// A static or movable pulley.
    Pulley,
    /// A rope (main cable, load connection or pulley–pulley cable).
    Rope,
    /// A rope end anchored to the ceiling or floor.
    FixedPoint,
}

impl RopeObjectKind {
    /// The word used in questions (`fixed point`).
    pub fn word(self) -> &'static str {
        match self {
            RopeObjectKind::Cube => "cube",
            RopeObjectKind::Sphere => "sphere",
            RopeObjectKind::Pulley => "pulley",
            RopeObjectKind::Rope => "rope",
            RopeObjectKind::FixedPoint => "fixed point",
        }
    }

    /// Whether the object is a load (its mass can be queried and changed).
    pub fn is_load(self) -> bool {
        matches!(self, RopeObjectKind::Cube | RopeObjectKind::Sphere)
    }
}

/// A rope object name split into its parts. All text fields are lower case.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct RopeObjectName {
    /// The annotation name, as written (`Blue Solid Static Pulley (0 1)`).
    pub full: String,
    /// The colour words (`blue`, `light blue`).
    pub color: String,
    /// The object kind.
    pub kind: RopeObjectKind,
    /// `solid` (little) or `hollow` (big), for pulleys.
    pub pulley_shape: Option<String>,
    /// `static` or `dynamic` (movable). Loads and ropes are dynamic, fixed points static.
    pub dynamics: String,
    /// The grid id `(layer, column)` of pulleys (columns can be negative in the release).
    pub grid: Option<(i32, i32)>,
}

impl RopeObjectName {
    /// The name without the grid suffix, lower case (`blue solid static pulley`); the public
    /// engine's object key.
    pub fn base_name(&self) -> String {
        self.full
            .split('(')
            .next()
            .unwrap_or_default()
            .trim()
            .to_lowercase()
    }
}

/// Parses a rope object name; `None` for names that are not question objects (`Solver`,
/// `Shaft of …`) or that do not follow the generator's grammar.
pub fn parse_rope_object_name(name: &str) -> Option<RopeObjectName> {
    if name.starts_with("Shaft of") {
        return None;
    }
    let (words_part, grid) = match name.split_once('(') {
        Some((head, tail)) => {
            let inner = tail.strip_suffix(')')?;
            let mut numbers = inner.split_whitespace().map(str::parse::<i32>);
            let layer = numbers.next()?.ok()?;
            let column = numbers.next()?.ok()?;
            if numbers.next().is_some() {
                return None;
            }
            (head.trim(), Some((layer, column)))
        }
        None => (name.trim(), None),
    };
    let words: Vec<String> = words_part
        .split_whitespace()
        .map(str::to_lowercase)
        .collect();
    let joined = |slice: &[String]| slice.join(" ");
    let (kind, color_words, pulley_shape, dynamics) = match words.as_slice() {
        [color @ .., last] if last == "cube" => (RopeObjectKind::Cube, color, None, "dynamic"),
        [color @ .., last] if last == "sphere" => (RopeObjectKind::Sphere, color, None, "dynamic"),
        [color @ .., last] if last == "rope" => (RopeObjectKind::Rope, color, None, "dynamic"),
        [color @ .., fixed, point] if fixed == "fixed" && point == "point" => {
            (RopeObjectKind::FixedPoint, color, None, "static")
        }
        [color @ .., shape, dynamics, pulley]
            if pulley == "pulley"
                && (shape == "solid" || shape == "hollow")
                && (dynamics == "static" || dynamics == "dynamic") =>
        {
            (
                RopeObjectKind::Pulley,
                color,
                Some(shape.clone()),
                dynamics.as_str(),
            )
        }
        _ => return None,
    };
    if color_words.is_empty() {
        return None;
    }
    Some(RopeObjectName {
        full: name.to_string(),
        color: joined(color_words),
        kind,
        pulley_shape,
        dynamics: dynamics.to_string(),
        grid,
    })
}

/// The main camera (`outputCamera["Main Camera"]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Camera {
    /// World position (Unity units, nominally metres).
    pub position: [f64; 3],
    /// Unity Euler angles in degrees (applied Z, X, Y).
    pub rotation_deg: [f64; 3],
    /// Vertical field of view in degrees.
    pub vertical_fov_deg: f64,
    /// Rope only: the camera sits at −z looking towards +z. Rotation results are already
    /// sign-corrected, so +1 means clockwise as seen in the video either way.
    pub mirrored: bool,
}

/// What a counterfactual run changed.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum RopeChange {
    /// `COUNTERFACTUAL_change_one_object_mass`: one load's mass changed at update 100.
    Mass {
        /// The load's annotation name.
        target: String,
        /// Mass before the change, kg (the equal-mass CF baseline, not the video's mass).
        before_kg: f64,
        /// Mass after the change, kg.
        after_kg: f64,
    },
    /// `COUNTERFACTUAL_pull_object_up_or_down`: a static pulley or fixed point was moved.
    Pull {
        /// The moved object's annotation name.
        agent: String,
        /// `up` or `down`.
        direction: String,
    },
    /// Any other mode, kept so nothing is silently lost.
    Other {
        /// The `mode` string.
        mode: String,
    },
}

impl RopeChange {
    /// For a mass change: `true` if the load became lighter, comparing masses rounded to 0.01 kg
    /// as the public engine does (`round(Item1, 2) > round(Item2, 2)`).
    pub fn is_lighter(&self) -> Option<bool> {
        match self {
            RopeChange::Mass {
                before_kg,
                after_kg,
                ..
            } => Some(round_to_hundredths(*before_kg) > round_to_hundredths(*after_kg)),
            _ => None,
        }
    }
}

fn round_to_hundredths(value: f64) -> f64 {
    (value * 100.0).round() / 100.0
}

/// One counterfactual outcome: the change and the resulting motion and rotation signs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RopeCounterfactual {
    /// What was changed.
    pub change: RopeChange,
    /// Pulley → +1 clockwise (as seen in the video), −1 anti-clockwise, 0 none.
    pub rotation: IndexMap<String, i8>,
    /// Pulley, load or fixed point → +1 up, −1 down, 0 none (threshold 1.2 units).
    pub motion: IndexMap<String, i8>,
}

/// A counterfactual record: sub-entry `"0"` was simulated; `"1"` is the generator's mirror (the
/// opposite change with every sign negated), never simulated (`contphy/FORMAT.md` §2.3).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RopeCounterfactualPair {
    /// The record key in `CounterFactualAnnotations`.
    pub key: String,
    /// Sub-entry `"0"`.
    pub simulated: RopeCounterfactual,
    /// Sub-entry `"1"`.
    pub mirrored: RopeCounterfactual,
    /// The masses of the CF baseline (`outputMass` of the record), kg.
    pub baseline_mass_kg: IndexMap<String, f64>,
}

/// The rope annotations of one valid video.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RopeAnnotation {
    /// `mode` (e.g. `FACTUAL_PREDICTIVE_set_random_mass`).
    pub mode: String,
    /// One ordered element list per mechanically coupled group (ropes repeated between elements).
    pub related_groups: Vec<Vec<String>>,
    /// The same groups keyed by rope: `[{rope: [elements]}]`.
    pub related_groups_in_rope: Vec<IndexMap<String, Vec<String>>>,
    /// Factual pulley rotation, +1 clockwise on screen (includes 200 updates after the video).
    pub result_rotation: IndexMap<String, i8>,
    /// Factual motion of pulleys, loads and fixed points, +1 up (includes post-video updates).
    pub result_motion: IndexMap<String, i8>,
    /// Per rope, per consecutive body pair: joint impulse / dt in N (negative), measured under
    /// equal masses before the video's random masses were applied.
    pub result_tension: IndexMap<String, IndexMap<String, f64>>,
    /// Per rope: `Attach`, `Detach` or `None` after the video ends.
    pub predictive_event_type: IndexMap<String, String>,
    /// Per rope: the body attached or detached, or `None`.
    pub predictive_event_body: IndexMap<String, String>,
    /// Load masses in kg as simulated (loads under a movable pulley carry the ×1.975 factor).
    pub output_mass_kg: IndexMap<String, f64>,
    /// The main camera, when recorded.
    pub camera: Option<Camera>,
    /// Counterfactual records in file order.
    pub counterfactuals: Vec<RopeCounterfactualPair>,
    /// Instance id → scene object name (`Id2ObjectNameDict`), in file order.
    pub id_to_object_name: Vec<(u32, String)>,
    /// Number of annotated frames (`perFrameAnnotations`), 0 if absent.
    pub frame_count: usize,
    /// Layout positions `(x, y)` of every element (`metaSamplingData.name2position`): pulley
    /// centres, anchors, and the loads' start positions. Empty when absent.
    pub element_positions: IndexMap<String, [f64; 2]>,
}

impl RopeAnnotation {
    /// Loads and validates the annotations of `path` (an `outputs.json`).
    pub fn load(path: &Path) -> Result<RopeAnnotation, DatasetError> {
        let value = read_json(path)?;
        RopeAnnotation::from_json(path, &value)
    }

    /// Validates an already parsed document; `path` is used in error messages.
    pub fn from_json(
        path: &Path,
        value: &serde_json::Value,
    ) -> Result<RopeAnnotation, DatasetError> {
        let root = Node::root(path, value);
        let validity = root.field("validity", |n| n.boolean())?;
        if !validity {
            return Err(root.error("has `validity: false`: an invalid trial has no annotations"));
        }
        let string_list = |node: Node<'_>| node.items(|item| item.string());
        let sign_map = |node: Node<'_>| -> Result<IndexMap<String, i8>, DatasetError> {
            Ok(node
                .entries(|key, n| Ok((key.to_string(), n.sign()?)))?
                .into_iter()
                .collect())
        };
        let string_map = |node: Node<'_>| -> Result<IndexMap<String, String>, DatasetError> {
            Ok(node
                .entries(|key, n| Ok((key.to_string(), n.string()?)))?
                .into_iter()
                .collect())
        };
        let mass_map = |node: Node<'_>| -> Result<IndexMap<String, f64>, DatasetError> {
            let entries = node.entries(|key, n| {
                let mass = n.number()?;
                if mass <= 0.0 {
                    return Err(n.error(format!("must be a positive mass in kg, found {mass}")));
                }
                Ok((key.to_string(), mass))
            })?;
            Ok(entries.into_iter().collect())
        };

        let mode = root
            .optional_field("mode", |n| n.string())?
            .unwrap_or_default();
        let related_groups = root.field("relatedGroups", |n| n.items(string_list))?;
        let related_groups_in_rope = root.field("relatedGroupsInRope", |n| {
            n.items(|group| {
                Ok(group
                    .entries(|rope, elements| Ok((rope.to_string(), string_list(elements)?)))?
                    .into_iter()
                    .collect())
            })
        })?;
        let result_rotation = root.field("ResultRotation", sign_map)?;
        let result_motion = root.field("ResultMotion", sign_map)?;
        let result_tension = root.field("ResultTension", |n| {
            Ok(n.entries(|rope, pairs| {
                let values: IndexMap<String, f64> = pairs
                    .entries(|pair, v| Ok((pair.to_string(), v.number()?)))?
                    .into_iter()
                    .collect();
                Ok((rope.to_string(), values))
            })?
            .into_iter()
            .collect())
        })?;
        let predictive_event_type = root
            .optional_field("PredictiveEventType", string_map)?
            .unwrap_or_default();
        let predictive_event_body = root
            .optional_field("PredictiveEventPulleyName", string_map)?
            .unwrap_or_default();
        let output_mass_kg = root.field("outputMass", mass_map)?;
        let camera = root.optional_field("outputCamera", parse_camera)?.flatten();
        let counterfactuals = root.field("CounterFactualAnnotations", |n| {
            n.entries(parse_counterfactual_pair)
        })?;
        let element_positions = root
            .optional_field("metaSamplingData", |meta| {
                meta.optional_field("name2position", |positions| {
                    positions.entries(|name, xy| {
                        let numbers = xy.numbers(Some(2))?;
                        Ok((name.to_string(), [numbers[0], numbers[1]]))
                    })
                })
            })?
            .flatten()
            .unwrap_or_default()
            .into_iter()
            .collect();
        let (id_to_object_name, frame_count) = root
            .optional_field("imgAnnotationDescriptions", |n| {
                let names = n
                    .optional_field("Id2ObjectNameDict", |dict| {
                        dict.entries(|key, name| {
                            let id = key.parse::<u32>().map_err(|_| {
                                name.error("has a key that is not an instance id (a whole number)")
                            })?;
                            Ok((id, name.string()?))
                        })
                    })?
                    .unwrap_or_default();
                let frames = n
                    .optional_field("perFrameAnnotations", |f| f.len())?
                    .unwrap_or(0);
                Ok((names, frames))
            })?
            .unwrap_or_default();

        let annotation = RopeAnnotation {
            mode,
            related_groups,
            related_groups_in_rope,
            result_rotation,
            result_motion,
            result_tension,
            predictive_event_type,
            predictive_event_body,
            output_mass_kg,
            camera,
            counterfactuals,
            id_to_object_name,
            frame_count,
            element_positions,
        };
        annotation.check_names(&root)?;
        Ok(annotation)
    }

    /// Every load, pulley and fixed point the results mention must parse as a rope object name,
    /// so later stages can rely on the grammar.
    fn check_names(&self, root: &Node<'_>) -> Result<(), DatasetError> {
        let named = self
            .output_mass_kg
            .keys()
            .map(|name| ("outputMass", name))
            .chain(self.result_motion.keys().map(|name| ("ResultMotion", name)))
            .chain(
                self.result_rotation
                    .keys()
                    .map(|name| ("ResultRotation", name)),
            );
        for (field, name) in named {
            if parse_rope_object_name(name).is_none() {
                return Err(root.field(field, |n| {
                    Ok(n.error(format!(
                        "has object name `{name}` that is not `<Colour> <Kind>`"
                    )))
                })?);
            }
        }
        Ok(())
    }

    /// The mass counterfactual sub-entries (`"0"` and `"1"` of each mass record), in file order,
    /// as the public engine's `sim.counterfactual` holds them.
    pub fn mass_counterfactuals(&self) -> impl Iterator<Item = &RopeCounterfactual> {
        self.counterfactuals
            .iter()
            .flat_map(|pair| [&pair.simulated, &pair.mirrored])
            .filter(|cf| matches!(cf.change, RopeChange::Mass { .. }))
    }
}

fn parse_camera(node: Node<'_>) -> Result<Option<Camera>, DatasetError> {
    node.optional_field("Main Camera", |camera| {
        let position = camera.field("position", |n| n.numbers(Some(3)))?;
        let rotation = camera.field("rotation", |n| n.numbers(Some(3)))?;
        let fov = camera.field("fov", |n| n.numbers(Some(1)))?;
        let mirrored = camera
            .optional_field("mirrored", |n| n.integer())?
            .unwrap_or(0)
            != 0;
        Ok(Camera {
            position: [position[0], position[1], position[2]],
            rotation_deg: [rotation[0], rotation[1], rotation[2]],
            vertical_fov_deg: fov[0],
            mirrored,
        })
    })
}

fn parse_counterfactual_pair(
    key: &str,
    record: Node<'_>,
) -> Result<RopeCounterfactualPair, DatasetError> {
    let simulated = record.field("0", parse_counterfactual)?;
    let mirrored = record.field("1", parse_counterfactual)?;
    let baseline_mass_kg = record
        .optional_field("outputMass", |n| {
            Ok(n.entries(|name, m| Ok((name.to_string(), m.number()?)))?
                .into_iter()
                .collect())
        })?
        .unwrap_or_default();
    Ok(RopeCounterfactualPair {
        key: key.to_string(),
        simulated,
        mirrored,
        baseline_mass_kg,
    })
}

fn parse_counterfactual(node: Node<'_>) -> Result<RopeCounterfactual, DatasetError> {
    let mode = node.field("mode", |n| n.string())?;
    let change = match mode.as_str() {
        "COUNTERFACTUAL_change_one_object_mass" => {
            let target = node.field("TargetObj_Name", |n| n.string())?;
            let (before_kg, after_kg) = node.field("TargetObj_Mass_Before_After", |n| {
                Ok((
                    n.field("Item1", |m| m.number())?,
                    n.field("Item2", |m| m.number())?,
                ))
            })?;
            RopeChange::Mass {
                target,
                before_kg,
                after_kg,
            }
        }
        "COUNTERFACTUAL_pull_object_up_or_down" => {
            let (agent, direction) = node.field("TargetMovingAgent", |n| {
                Ok((
                    n.field("name", |m| m.string())?,
                    n.field("direction", |m| m.string())?,
                ))
            })?;
            RopeChange::Pull { agent, direction }
        }
        _ => RopeChange::Other { mode },
    };
    let sign_map = |n: Node<'_>| -> Result<IndexMap<String, i8>, DatasetError> {
        Ok(n.entries(|key, v| Ok((key.to_string(), v.sign()?)))?
            .into_iter()
            .collect())
    };
    Ok(RopeCounterfactual {
        change,
        rotation: node.field("ResultRotation", sign_map)?,
        motion: node.field("ResultMotion", sign_map)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn object_names_follow_the_generator_grammar() {
        let pulley = parse_rope_object_name("Blue Solid Static Pulley (0 1)").unwrap();
        assert_eq!(pulley.color, "blue");
        assert_eq!(pulley.kind, RopeObjectKind::Pulley);
        assert_eq!(pulley.pulley_shape.as_deref(), Some("solid"));
        assert_eq!(pulley.dynamics, "static");
        assert_eq!(pulley.grid, Some((0, 1)));
        assert_eq!(pulley.base_name(), "blue solid static pulley");
        let cube = parse_rope_object_name("Light Blue Cube").unwrap();
        assert_eq!(
            (cube.color.as_str(), cube.kind),
            ("light blue", RopeObjectKind::Cube)
        );
        let fixed = parse_rope_object_name("Brown Fixed Point").unwrap();
        assert_eq!(
            (fixed.kind, fixed.dynamics.as_str()),
            (RopeObjectKind::FixedPoint, "static")
        );
        let movable = parse_rope_object_name("Red Hollow Dynamic Pulley (1 2)").unwrap();
        assert_eq!(movable.dynamics, "dynamic");
        // The release's walk can step left of column 0 in its second layer.
        let left = parse_rope_object_name("Gray Solid Static Pulley (1 -1)").unwrap();
        assert_eq!(left.grid, Some((1, -1)));
        for not_an_object in [
            "Solver",
            "Shaft of Blue Solid Static Pulley (0 1)",
            "Cube",
            "Pulley (0 1)",
            "Red Pulley (x y)",
        ] {
            assert!(
                parse_rope_object_name(not_an_object).is_none(),
                "{not_an_object}"
            );
        }
    }

    #[test]
    fn lighter_compares_rounded_masses() {
        let change = |before_kg, after_kg| RopeChange::Mass {
            target: "x".into(),
            before_kg,
            after_kg,
        };
        assert_eq!(change(0.2, 0.1).is_lighter(), Some(true));
        assert_eq!(change(0.2, 0.3).is_lighter(), Some(false));
        assert_eq!(change(0.395, 0.1975).is_lighter(), Some(true));
        assert_eq!(RopeChange::Other { mode: "m".into() }.is_lighter(), None);
    }
}

#[cfg(test)]
mod sample_tests {
    //! Checks against the one real rope video of the public release (eval/demo).
    use super::*;

    fn sample() -> RopeAnnotation {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/pulley_group/0/outputs.json");
        RopeAnnotation::load(&path).unwrap()
    }

    #[test]
    fn real_sample_loads_with_expected_contents() {
        let annotation = sample();
        assert_eq!(annotation.mode, "FACTUAL_PREDICTIVE_set_random_mass");
        let masses: Vec<(&str, f64)> = annotation
            .output_mass_kg
            .iter()
            .map(|(k, v)| (k.as_str(), *v))
            .collect();
        assert_eq!(
            masses,
            vec![
                ("Purple Cube", 0.2),
                ("Green Cube", 0.25),
                ("Pink Sphere", 0.15)
            ]
        );
        assert_eq!(annotation.related_groups.len(), 2);
        assert_eq!(annotation.related_groups[1][0], "Brown Fixed Point");
        assert_eq!(
            annotation.result_rotation["Blue Solid Static Pulley (0 1)"],
            1
        );
        assert_eq!(annotation.result_motion["Green Cube"], -1);
        assert_eq!(annotation.counterfactuals.len(), 5);
        assert_eq!(annotation.mass_counterfactuals().count(), 6);
        let camera = annotation.camera.as_ref().unwrap();
        assert!(camera.mirrored);
        assert!((camera.vertical_fov_deg - 40.14217).abs() < 1e-9);
        assert_eq!(annotation.frame_count, 150);
        assert_eq!(annotation.id_to_object_name.len(), 11);
        let first_mass = annotation.mass_counterfactuals().next().unwrap();
        assert_eq!(first_mass.change.is_lighter(), Some(true));
    }

    #[test]
    fn corrupted_fields_are_named() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/pulley_group/0/outputs.json");
        let mut value: serde_json::Value =
            serde_json::from_slice(&fs_err::read(&path).unwrap()).unwrap();
        value["CounterFactualAnnotations"]["2"]["0"]["ResultMotion"]["Purple Cube"] =
            serde_json::json!(3);
        let error = RopeAnnotation::from_json(Path::new("outputs.json"), &value).unwrap_err();
        assert_eq!(
            error.to_string(),
            "`outputs.json`: field `CounterFactualAnnotations.2.0.ResultMotion.Purple Cube` must be -1, 0 or 1, found 3"
        );
        value["outputMass"]["Green Cube"] = serde_json::json!(-0.2);
        value["CounterFactualAnnotations"]["2"]["0"]["ResultMotion"]["Purple Cube"] =
            serde_json::json!(1);
        let error = RopeAnnotation::from_json(Path::new("outputs.json"), &value).unwrap_err();
        assert!(
            error
                .to_string()
                .contains("field `outputMass.Green Cube` must be a positive mass"),
            "{error}"
        );
        value.as_object_mut().unwrap().remove("relatedGroups");
        let error = RopeAnnotation::from_json(Path::new("outputs.json"), &value).unwrap_err();
        assert_eq!(
            error.to_string(),
            "`outputs.json`: field `relatedGroups` is missing"
        );
    }
}
