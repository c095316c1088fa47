//! The release's per-frame instance-segmentation records (Unity Perception's solo captures inside
//! `outputs.json`): which instance is painted in which colour in each segmentation frame, and the
//! object name of each instance id.
//!
//! Input: an `outputs.json` path. Output: [`SegmentationRecords`], frames keyed 0-based (the
//! file's keys count from 1), or a [`DatasetError`] naming the file and field. Used as ground
//! truth for perception. Also the annotation readers' view of the same key
//! ([`parse_image_descriptions`]: instance names and the number of annotated frames).

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value;

use super::error::DatasetError;
use super::fields::Node;

/// One instance painted in a segmentation frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PaintedInstance {
    /// Unity's instance id (a key of `Id2ObjectNameDict`).
    pub instance_id: u32,
    /// Its colour in the segmentation frame (RGB).
    pub color: [u8; 3],
}

/// A video's segmentation records.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SegmentationRecords {
    /// Instance id → scene object name (`Pink Hollow Static Pulley (0 5)`).
    pub names: BTreeMap<u32, String>,
    /// 0-based frame index → the instances painted in it.
    pub frames: BTreeMap<usize, Vec<PaintedInstance>>,
    /// 0-based frame index → the 2-D boxes of the visible instances: instance id and
    /// `[x0, y0, x1, y1]` in pixels.
    pub boxes: BTreeMap<usize, Vec<(u32, [f64; 4])>>,
}

impl SegmentationRecords {
    /// Reads the records of `outputs.json`.
    pub fn read(path: &Path) -> Result<SegmentationRecords, DatasetError> {
        let text = fs_err::read_to_string(path).map_err(|source| DatasetError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let document: Value = serde_json::from_str(&text).map_err(|source| DatasetError::Json {
            path: path.to_path_buf(),
            source,
        })?;
        let field = |field: &str, problem: &str| DatasetError::Field {
            path: path.to_path_buf(),
            field: field.to_string(),
            problem: problem.to_string(),
        };
        let descriptions = document
            .get("imgAnnotationDescriptions")
            .ok_or_else(|| field("imgAnnotationDescriptions", "is missing"))?;
        let mut records = SegmentationRecords::default();
        let names = descriptions
            .get("Id2ObjectNameDict")
            .and_then(Value::as_object)
            .ok_or_else(|| {
                field(
                    "imgAnnotationDescriptions.Id2ObjectNameDict",
                    "is missing or not an object",
                )
            })?;
        for (key, name) in names {
            let id = key.parse::<u32>().map_err(|_| {
                field(
                    "imgAnnotationDescriptions.Id2ObjectNameDict",
                    &format!("has a key `{key}` that is not an instance id"),
                )
            })?;
            let name = name.as_str().ok_or_else(|| {
                field(
                    &format!("imgAnnotationDescriptions.Id2ObjectNameDict.{key}"),
                    "is not a string",
                )
            })?;
            records.names.insert(id, name.to_string());
        }
        let frames = descriptions
            .get("perFrameAnnotations")
            .and_then(Value::as_object)
            .ok_or_else(|| {
                field(
                    "imgAnnotationDescriptions.perFrameAnnotations",
                    "is missing or not an object",
                )
            })?;
        for (key, captures) in frames {
            let where_ = format!("imgAnnotationDescriptions.perFrameAnnotations.{key}");
            let number = key
                .parse::<usize>()
                .ok()
                .filter(|n| *n >= 1)
                .ok_or_else(|| field(&where_, "is not a frame number from 1"))?;
            let annotations = captures
                .get(0)
                .and_then(|c| c.get("annotations"))
                .and_then(Value::as_array)
                .ok_or_else(|| field(&where_, "has no capture with annotations"))?;
            if let Some(boxes) = annotations.iter().find(|a| {
                a.get("@type")
                    .and_then(Value::as_str)
                    .is_some_and(|t| t.ends_with("BoundingBox2DAnnotation"))
            }) {
                let values = boxes
                    .get("values")
                    .and_then(Value::as_array)
                    .ok_or_else(|| {
                        field(&where_, "has a bounding-box annotation without values")
                    })?;
                let mut parsed = Vec::with_capacity(values.len());
                for value in values {
                    let id = value
                        .get("instanceId")
                        .and_then(Value::as_u64)
                        .and_then(|id| u32::try_from(id).ok());
                    let pair = |key: &str| -> Option<[f64; 2]> {
                        let list = value.get(key)?.as_array()?;
                        Some([list.first()?.as_f64()?, list.get(1)?.as_f64()?])
                    };
                    match (id, pair("origin"), pair("dimension")) {
                        (Some(id), Some([x, y]), Some([w, h])) => {
                            parsed.push((id, [x, y, x + w, y + h]));
                        }
                        _ => {
                            return Err(field(
                                &where_,
                                "has a box without id, origin or dimension",
                            ));
                        }
                    }
                }
                records.boxes.insert(number - 1, parsed);
            }
            let Some(segmentation) = annotations.iter().find(|a| {
                a.get("@type")
                    .and_then(Value::as_str)
                    .is_some_and(|t| t.ends_with("InstanceSegmentationAnnotation"))
            }) else {
                continue;
            };
            let instances = segmentation
                .get("instances")
                .and_then(Value::as_array)
                .ok_or_else(|| field(&where_, "has a segmentation without instances"))?;
            let mut painted = Vec::with_capacity(instances.len());
            for instance in instances {
                let id = instance
                    .get("instanceId")
                    .and_then(Value::as_u64)
                    .and_then(|id| u32::try_from(id).ok());
                let color: Option<Vec<u8>> =
                    instance.get("color").and_then(Value::as_array).map(|c| {
                        c.iter()
                            .filter_map(|v| v.as_u64().and_then(|v| u8::try_from(v).ok()))
                            .collect()
                    });
                match (id, color.as_deref()) {
                    (Some(instance_id), Some([r, g, b, ..])) => painted.push(PaintedInstance {
                        instance_id,
                        color: [*r, *g, *b],
                    }),
                    _ => return Err(field(&where_, "has an instance without id or colour")),
                }
            }
            records.frames.insert(number - 1, painted);
        }
        Ok(records)
    }
}

/// `imgAnnotationDescriptions`: `Id2ObjectNameDict` and the number of annotated frames.
pub(crate) fn parse_image_descriptions(
    node: Node<'_>,
) -> Result<(Vec<(u32, String)>, usize), DatasetError> {
    let names = node
        .optional_field("Id2ObjectNameDict", |dict| {
            dict.entries(|key, name| {
                let id = key.parse::<u32>().map_err(|_| {
                    name.error("has a key that is not an instance id (a whole number)")
                })?;
                Ok((id, name.string()?))
            })
        })?
        .unwrap_or_default();
    let frames = node
        .optional_field("perFrameAnnotations", |f| f.len())?
        .unwrap_or(0);
    Ok((names, frames))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_real_videos_records_name_every_painted_instance() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/pulley_group/0/outputs.json");
        let records = SegmentationRecords::read(&path).expect("the demo video's records");
        assert_eq!(records.frames.len(), 150);
        assert_eq!(
            records.names.get(&7).map(String::as_str),
            Some("Purple Cube")
        );
        let first = &records.frames[&0];
        assert_eq!(
            first[0],
            PaintedInstance {
                instance_id: 1,
                color: [255, 0, 0]
            }
        );
        assert!(
            records
                .frames
                .values()
                .flatten()
                .all(|p| records.names.contains_key(&p.instance_id))
        );
    }
}
