//! The release's record formats shared by the scenarios' generators: Unity's `Vector3`
//! strings, rounded numbers, and the `outputCamera` record.

use serde_json::{Value, json};

use crate::perception::camera::CameraModel;

/// `value` rounded to `digits` decimals.
pub fn round(value: f64, digits: i32) -> f64 {
    let scale = 10_f64.powi(digits);
    (value * scale).round() / scale
}

/// Unity's `Vector3.ToString()`: two decimals, `(x, y, z)`.
pub fn vector3(v: [f64; 3]) -> String {
    let fixed = |c: f64| {
        let text = format!("{c:.2}");
        if text == "-0.00" {
            "0.00".to_string()
        } else {
            text
        }
    };
    format!("({}, {}, {})", fixed(v[0]), fixed(v[1]), fixed(v[2]))
}

/// The `outputCamera` record of the main camera.
pub fn camera_json(camera: &CameraModel) -> Value {
    json!({"Main Camera": {
        "position": camera.position.map(|c| round(c, 6)),
        "rotation": camera.euler_deg().map(|c| round(c, 6)),
        "fov": [round(camera.vertical_fov_deg, 6)],
    }})
}
