//! Image annotations of a rendered frame in the release's Unity Perception "solo" form
//! (`docs/data/common.md`, image annotations): one RGB capture per step with a 2-D bounding-box
//! annotation and an instance-segmentation annotation, both derived from the frame's instance-id
//! image, so boxes and masks agree with the pixels by construction.

use serde_json::{Value, json};

use super::palette::instance_color;
use super::raster::Frame;
use crate::perception::camera::CameraModel;

/// An object that carries a label: its instance id, scene name and label.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LabelledObject {
    /// Instance id (1-based; the colour of its mask follows from it).
    pub instance: u32,
    /// Scene object name (`Purple Cube`).
    pub name: String,
    /// Label id of the scenario's label configuration.
    pub label_id: u32,
    /// Label name (`Filo Cube`).
    pub label_name: String,
}

/// `Id2ObjectNameDict` of a scene whose labelled objects are all its named ones: each object's
/// instance id and name, in `labels`' order.
pub fn names_by_id(labels: &[LabelledObject]) -> Vec<(u32, String)> {
    labels
        .iter()
        .map(|label| (label.instance, label.name.clone()))
        .collect()
}

/// A visible object's pixel box: `(min_x, min_y, max_x, max_y)`, inclusive pixel indices.
pub type PixelBox = (u32, u32, u32, u32);

/// Per instance id (index), the box of its visible pixels; `None` when no pixel shows it.
pub fn visible_boxes(frame: &Frame, max_instance: u32) -> Vec<Option<PixelBox>> {
    let mut boxes: Vec<Option<PixelBox>> = vec![None; max_instance as usize + 1];
    let width = frame.width as usize;
    for (index, &id) in frame.instance.iter().enumerate() {
        if id == 0 || id > max_instance {
            continue;
        }
        #[expect(
            clippy::cast_possible_truncation,
            reason = "pixel coordinates of an image whose size is a u32"
        )]
        let (x, y) = ((index % width) as u32, (index / width) as u32);
        let slot = &mut boxes[id as usize];
        *slot = Some(match *slot {
            None => (x, y, x, y),
            Some((x0, y0, x1, y1)) => (x0.min(x), y0.min(y), x1.max(x), y1.max(y)),
        });
    }
    boxes
}

/// The `perFrameAnnotations` entry of one step: a list holding the RGB capture.
///
/// `step` is the solo step number (the entry's key), `segmentation_first` puts the
/// segmentation annotation before the boxes, as half of the release's frames do.
pub fn capture_record(
    step: usize,
    camera: &CameraModel,
    frame: &Frame,
    labels: &[LabelledObject],
    segmentation_first: bool,
) -> Value {
    let max_instance = labels.iter().map(|l| l.instance).max().unwrap_or(0);
    let boxes = visible_boxes(frame, max_instance);
    let mut sorted: Vec<&LabelledObject> = labels.iter().collect();
    sorted.sort_by_key(|l| l.instance);
    let visible: Vec<(&LabelledObject, PixelBox)> = sorted
        .into_iter()
        .filter_map(|label| {
            boxes
                .get(label.instance as usize)
                .copied()
                .flatten()
                .map(|b| (label, b))
        })
        .collect();
    let box_values: Vec<Value> = visible
        .iter()
        .map(|(label, (x0, y0, x1, y1))| {
            json!({
                "instanceId": label.instance,
                "labelId": label.label_id,
                "labelName": label.label_name,
                "origin": [f64::from(*x0), f64::from(*y0)],
                "dimension": [f64::from(x1 - x0 + 1), f64::from(y1 - y0 + 1)],
            })
        })
        .collect();
    let instances: Vec<Value> = visible
        .iter()
        .map(|(label, _)| {
            json!({
                "instanceId": label.instance,
                "labelId": label.label_id,
                "labelName": label.label_name,
                "color": instance_color(label.instance),
            })
        })
        .collect();
    let dimension = [f64::from(frame.width), f64::from(frame.height)];
    let bounding_boxes = json!({
        "@type": "type.unity.com/unity.solo.BoundingBox2DAnnotation",
        "id": "bounding box",
        "sensorId": "camera",
        "description": "Produces 2D bounding box annotations for all visible objects that bear a label defined in this labeler's associated label configuration.",
        "values": box_values,
    });
    let segmentation = json!({
        "@type": "type.unity.com/unity.solo.InstanceSegmentationAnnotation",
        "id": "instance segmentation",
        "sensorId": "camera",
        "description": "Produces an instance segmentation image for each frame. The image will render the pixels of each labeled object in a distinct color.",
        "imageFormat": "Png",
        "dimension": dimension,
        "filename": format!("step{step}.camera.instance segmentation.png"),
        "instances": instances,
    });
    let annotations = if segmentation_first {
        vec![segmentation, bounding_boxes]
    } else {
        vec![bounding_boxes, segmentation]
    };
    json!([{
        "@type": "type.unity.com/unity.solo.RGBCamera",
        "id": "camera",
        "description": Value::Null,
        "position": camera.position,
        "rotation": camera.quaternion(),
        "velocity": [0.0, 0.0, 0.0],
        "acceleration": [0.0, 0.0, 0.0],
        "filename": format!("step{step}.camera.png"),
        "imageFormat": "Png",
        "dimension": dimension,
        "projection": "Perspective",
        "matrix": camera.intrinsic_ndc(),
        "annotations": annotations,
    }])
}

/// The segmentation image of a frame: each labelled pixel in its instance colour, the rest
/// black (RGB, 3 bytes per pixel).
pub fn segmentation_rgb(frame: &Frame, labelled: &[bool]) -> Vec<u8> {
    let mut colors: Vec<[u8; 3]> = Vec::with_capacity(labelled.len());
    for (id, &on) in labelled.iter().enumerate() {
        let id = u32::try_from(id).unwrap_or(0);
        let [r, g, b, _] = if on {
            instance_color(id)
        } else {
            [0, 0, 0, 255]
        };
        colors.push([r, g, b]);
    }
    let mut rgb = Vec::with_capacity(frame.instance.len() * 3);
    for &id in &frame.instance {
        rgb.extend_from_slice(colors.get(id as usize).unwrap_or(&[0, 0, 0]));
    }
    rgb
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> Frame {
        // 4×3 image: instance 2 covers (1,0)–(2,1), instance 5 the pixel (3,2).
        let mut instance = vec![0; 12];
        for (x, y) in [(1, 0), (2, 0), (1, 1), (2, 1)] {
            instance[y * 4 + x] = 2;
        }
        instance[2 * 4 + 3] = 5;
        Frame {
            width: 4,
            height: 3,
            rgb: vec![0; 36],
            instance,
            inverse_depth: vec![0.0; 12],
        }
    }

    fn label(instance: u32, name: &str) -> LabelledObject {
        LabelledObject {
            instance,
            name: name.into(),
            label_id: 3,
            label_name: "Filo Cube".into(),
        }
    }

    #[test]
    fn boxes_and_instances_come_from_visible_pixels_only() {
        let camera = CameraModel::looking_at([0.0, 0.0, -10.0], [0.0; 3], 40.0, 4, 3);
        let labels = [label(5, "B"), label(2, "A"), label(9, "Hidden")];
        let record = capture_record(7, &camera, &frame(), &labels, false);
        let capture = &record[0];
        assert_eq!(capture["filename"], "step7.camera.png");
        let boxes = &capture["annotations"][0]["values"];
        assert_eq!(
            boxes.as_array().unwrap().len(),
            2,
            "the hidden object has no box"
        );
        assert_eq!(boxes[0]["instanceId"], 2);
        assert_eq!(boxes[0]["origin"], json!([1.0, 0.0]));
        assert_eq!(boxes[0]["dimension"], json!([2.0, 2.0]));
        assert_eq!(boxes[1]["origin"], json!([3.0, 2.0]));
        assert_eq!(boxes[1]["dimension"], json!([1.0, 1.0]));
        let instances = &capture["annotations"][1]["instances"];
        assert_eq!(instances[0]["color"], json!([0, 74, 255, 255]));
        let flipped = capture_record(7, &camera, &frame(), &labels, true);
        assert_eq!(
            flipped[0]["annotations"][0]["@type"],
            "type.unity.com/unity.solo.InstanceSegmentationAnnotation"
        );
    }

    #[test]
    fn segmentation_paints_labelled_instances_only() {
        let mut labelled = vec![false; 6];
        labelled[2] = true;
        let rgb = segmentation_rgb(&frame(), &labelled);
        assert_eq!(&rgb[3..6], &[0, 74, 255]);
        assert_eq!(
            &rgb[(2 * 4 + 3) * 3..][..3],
            &[0, 0, 0],
            "instance 5 is not labelled"
        );
    }
}
