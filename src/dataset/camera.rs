//! The camera calibration every scenario records (`outputCamera["Main Camera"]`): position,
//! Unity Euler angles and vertical field of view.

use serde::Serialize;

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
