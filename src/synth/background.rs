//! The static background of a scene: a textured plaster wall behind the objects, rendered once
//! per video by casting each pixel's ray onto the wall plane (the camera does not move).
//!
//! The texture is hashed value noise in wall coordinates (no RNG state: the same wall point has
//! the same shade in every frame and every run), with vertical streaks like the release's wall.

use crate::perception::camera::CameraModel;

use super::raster::{Light, linear_to_srgb_byte, srgb_to_linear};

/// A wall plane `z = depth` facing the camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wall {
    /// The plane's `z`, units.
    pub depth: f64,
    /// Base colour, sRGB in `[0, 1]`.
    pub color: [f64; 3],
    /// Texture variant (shifts the noise).
    pub variant: u64,
    /// Texture scale: noise cells per unit.
    pub frequency: f64,
    /// Texture contrast: the shade spans `1 − 0.6·contrast … 1 + 0.4·contrast` (0.3 for the
    /// release's plaster).
    pub contrast: f64,
    /// Stretch of the noise along `x` and `y` (`[3.0, 0.6]`: the release's vertical streaks).
    pub grain: [f64; 2],
}

/// Renders the wall as seen by `camera` (RGB bytes, the camera's size).
pub fn render_wall(camera: &CameraModel, wall: &Wall, light: &Light) -> Vec<u8> {
    let width = camera.width as usize;
    let height = camera.height as usize;
    let mut rgb = vec![0_u8; width * height * 3];
    let normal_z = if camera.position[2] < wall.depth {
        -1.0
    } else {
        1.0
    };
    let lambert = (light.direction[2] * normal_z).max(0.0);
    let shade = light.ambient + light.diffuse * lambert;
    let base = wall.color.map(srgb_to_linear);
    for y in 0..height {
        for x in 0..width {
            let ray = camera.ray(x as f64 + 0.5, y as f64 + 0.5);
            let t = if ray[2].abs() > 1e-9 {
                (wall.depth - camera.position[2]) / ray[2]
            } else {
                -1.0
            };
            let texture = if t > 0.0 {
                let u = camera.position[0] + t * ray[0];
                let v = camera.position[1] + t * ray[1];
                plaster(
                    u * wall.frequency * wall.grain[0],
                    v * wall.frequency * wall.grain[1],
                    wall.variant,
                )
            } else {
                0.5
            };
            let factor = shade * (1.0 - 0.6 * wall.contrast + wall.contrast * texture);
            let at = (y * width + x) * 3;
            for channel in 0..3 {
                rgb[at + channel] = linear_to_srgb_byte(base[channel] * factor);
            }
        }
    }
    rgb
}

/// Plaster texture in `[0, 1]`: three octaves of value noise (stretched by the wall's grain).
fn plaster(u: f64, v: f64, variant: u64) -> f64 {
    let mut total = 0.0;
    let mut weight = 0.5;
    let mut frequency = 1.0;
    let mut norm = 0.0;
    for octave in 0..3_u64 {
        total += weight * value_noise(u * frequency, v * frequency, variant + octave);
        norm += weight;
        weight *= 0.5;
        frequency *= 2.7;
    }
    total / norm
}

fn value_noise(x: f64, y: f64, seed: u64) -> f64 {
    let (xf, yf) = (x.floor(), y.floor());
    let (tx, ty) = (smooth(x - xf), smooth(y - yf));
    #[expect(
        clippy::cast_possible_truncation,
        reason = "lattice coordinates of a wall tens of units wide"
    )]
    let (xi, yi) = (xf as i64, yf as i64);
    let corner = |dx: i64, dy: i64| lattice(xi + dx, yi + dy, seed);
    let top = corner(0, 0) + tx * (corner(1, 0) - corner(0, 0));
    let bottom = corner(0, 1) + tx * (corner(1, 1) - corner(0, 1));
    top + ty * (bottom - top)
}

fn smooth(t: f64) -> f64 {
    t * t * (3.0 - 2.0 * t)
}

/// A hash of a lattice point to `[0, 1]` (SplitMix64 finaliser).
fn lattice(x: i64, y: i64, seed: u64) -> f64 {
    #[expect(clippy::cast_sign_loss, reason = "bit patterns are hashed, not values")]
    let mut z = (x as u64)
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add((y as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F))
        .wrapping_add(seed.wrapping_mul(0x1656_67B1_9E37_79F9));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    #[expect(clippy::cast_precision_loss, reason = "53 bits are enough for a shade")]
    let unit = (z >> 11) as f64 / (1_u64 << 53) as f64;
    unit
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_wall_is_textured_deterministic_and_fills_the_frame() {
        let camera = CameraModel::looking_at([0.0, 0.0, -30.0], [0.0; 3], 45.0, 64, 36);
        let wall = Wall {
            depth: 2.0,
            color: [0.8, 0.78, 0.74],
            variant: 3,
            frequency: 2.0,
            grain: [3.0, 0.6],
            contrast: 0.3,
        };
        let light = Light {
            direction: [0.0, 0.0, -1.0],
            ambient: 0.4,
            diffuse: 0.6,
            specular: 0.0,
            shininess: 1.0,
        };
        let first = render_wall(&camera, &wall, &light);
        assert_eq!(first, render_wall(&camera, &wall, &light));
        let mut values: Vec<u8> = first.chunks(3).map(|p| p[0]).collect();
        values.sort_unstable();
        values.dedup();
        assert!(values.len() > 5, "textured, not flat: {values:?}");
        assert!(values.iter().all(|&v| v > 120), "a light wall: {values:?}");
    }
}
