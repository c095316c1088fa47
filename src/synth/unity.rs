//! The release's record formats shared by the scenarios' generators: Unity's `Vector3`
//! strings, rounded numbers, the `outputCamera` record, Euler angles, and the light's draw.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use super::raster::Light;

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

/// The release's light: Euler x in U(20, 60)°, y in U(−20, 20)°.
pub fn sample_light(rng: &mut ChaCha8Rng) -> [f64; 3] {
    [
        rng.random_range(20.0..60.0),
        rng.random_range(-20.0..20.0),
        0.0,
    ]
}

/// The renderer's light for the release's Euler angles: x tilts it down from the horizon, y
/// turns it sideways; it comes from the camera's side (−z).
pub fn light_from_euler(euler_deg: [f64; 3]) -> Light {
    let (x, y) = (euler_deg[0].to_radians(), euler_deg[1].to_radians());
    let direction = [-(y.sin() * x.cos()), x.sin(), -(y.cos() * x.cos())];
    let length = direction.iter().map(|c| c * c).sum::<f64>().sqrt();
    Light {
        direction: direction.map(|c| c / length),
        ambient: 0.5,
        diffuse: 0.6,
        specular: 0.25,
        shininess: 32.0,
    }
}

/// Unity's Euler angles (degrees in `[0, 360)`) of rotation matrix `r` (row-major): Unity turns
/// about z, then x, then y (`R = Ry · Rx · Rz`), so `sin x = −r₁₂`, `tan y = r₀₂ / r₂₂` and
/// `tan z = r₁₀ / r₁₁`.
pub fn unity_euler_degrees(r: &[[f64; 3]; 3]) -> [f64; 3] {
    let x = (-r[1][2]).clamp(-1.0, 1.0).asin();
    let (y, z) = if x.cos() > 1e-9 {
        (r[0][2].atan2(r[2][2]), r[1][0].atan2(r[1][1]))
    } else {
        // Looking straight up or down: y and z turn about the same axis; put it all in y.
        ((-r[2][0]).atan2(r[0][0]), 0.0)
    };
    [x, y, z].map(|angle| angle.to_degrees().rem_euclid(360.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::vector3::{multiply, rotation_matrix};

    fn about(axis: usize, degrees: f64) -> [[f64; 3]; 3] {
        let half = degrees.to_radians() / 2.0;
        let mut q = [half.cos(), 0.0, 0.0, 0.0];
        q[axis + 1] = half.sin();
        rotation_matrix(q)
    }

    #[test]
    fn unity_euler_angles_undo_the_z_x_y_turns() {
        let (x, y, z) = (20.0, 130.0, 300.0);
        let r = multiply(&multiply(&about(1, y), &about(0, x)), &about(2, z));
        let euler = unity_euler_degrees(&r);
        for (found, expected) in euler.iter().zip([x, y, z]) {
            assert!((found - expected).abs() < 1e-9, "{euler:?}");
        }
    }
}
