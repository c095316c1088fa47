//! Typed rope annotations (`pulley_group/<id>/outputs.json`, `docs/data/rope.md`): related
//! groups, factual results, tensions, masses, counterfactual records, the camera and the layout.
//!
//! Maps keep file order (`IndexMap`), because the question engine, like the public Python one,
//! iterates them in that order.

use std::path::Path;

use indexmap::IndexMap;
use serde::Serialize;

use super::names::parse_rope_object_name;
use crate::dataset::DatasetError;
use crate::dataset::camera::{Camera, parse_camera};
use crate::dataset::fields::{Node, read_json};
use crate::dataset::segmentation::parse_image_descriptions;

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
/// opposite change with every sign negated), never simulated (`docs/data/rope.md`, counterfactual
/// records).
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
            .optional_field("imgAnnotationDescriptions", parse_image_descriptions)?
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
