//! The camera calibration every scenario records (`outputCamera["Main Camera"]`): position,
//! Unity Euler angles and vertical field of view; read from a file, and written back in the same
//! form for annotation types that serialise themselves.

use serde::Serialize;
use serde_json::{Value, json};

use super::DatasetError;
use super::fields::Node;

/// The main camera (`outputCamera["Main Camera"]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Camera {
    /// World position (Unity units, nominally metres).
    pub position: [f64; 3],
    /// Unity Euler angles in degrees (applied Z, X, Y).
    pub rotation_deg: [f64; 3],
    /// Vertical field of view in degrees.
    pub vertical_fov_deg: f64,
    /// The release's `mirrored` flag (`0` when absent): the camera sits at −z looking towards
    /// +z. Rope rotation results are already sign-corrected, so +1 means clockwise as seen in the
    /// video either way.
    pub mirrored: bool,
}

/// Reads `outputCamera` (`node`): its `Main Camera`, when recorded.
pub(crate) fn parse_camera(node: Node<'_>) -> Result<Option<Camera>, DatasetError> {
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

/// The `outputCamera` record [`parse_camera`] reads back as `camera`: `{}` when none was
/// recorded; `mirrored` written only when set (the release wrote it for rope only).
pub(crate) fn camera_record(camera: Option<&Camera>) -> Value {
    let Some(camera) = camera else {
        return json!({});
    };
    let mut main = json!({
        "position": camera.position,
        "rotation": camera.rotation_deg,
        "fov": [camera.vertical_fov_deg],
    });
    if camera.mirrored
        && let Some(fields) = main.as_object_mut()
    {
        fields.insert("mirrored".into(), json!(1));
    }
    json!({ "Main Camera": main })
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    #[test]
    fn a_written_camera_reads_back_equal() {
        let cameras = [
            Some(Camera {
                position: [0.1, 3.25, -11.0],
                rotation_deg: [30.0, 0.0, 1.0e-7],
                vertical_fov_deg: 34.5,
                mirrored: false,
            }),
            Some(Camera {
                position: [-7.455_870_63, -1.512_082_58, -43.051_834_1],
                rotation_deg: [348.4731, 346.7676, 0.0],
                vertical_fov_deg: 40.14217,
                mirrored: true,
            }),
            None,
        ];
        for camera in cameras {
            let record = camera_record(camera.as_ref());
            let read = parse_camera(Node::root(Path::new("outputs.json"), &record)).unwrap();
            assert_eq!(read, camera);
        }
    }
}
