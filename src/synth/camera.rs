//! The camera of a generated video: the release's `CameraRandomizer` draws (normal and
//! truncated-normal samplers) and its re-framing on the scene (`EncapsulateObjects`), shared by
//! the scenarios; each scenario samples its own distances and angles.

use std::f64::consts::PI;

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::perception::camera::CameraModel;

/// The sampled camera before re-framing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSample {
    /// Position, units.
    pub position: [f64; 3],
    /// Vertical field of view, degrees.
    pub vertical_fov_deg: f64,
    /// The camera sits at −z (the release's `mirrored = 1`).
    pub mirrored: bool,
}

/// A standard normal draw (Box–Muller).
pub fn normal(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = rng.random::<f64>().max(f64::MIN_POSITIVE);
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
}

/// A normal draw truncated to `[low, high]` (the release's `NormalSampler`), by rejection.
pub fn truncated_normal(rng: &mut ChaCha8Rng, mean: f64, sd: f64, low: f64, high: f64) -> f64 {
    for _ in 0..1000 {
        let value = mean + sd * normal(rng);
        if (low..=high).contains(&value) {
            return value;
        }
    }
    mean.clamp(low, high)
}

/// Re-frames the camera on world bounds (`EncapsulateObjects`): the distance that fits the
/// larger of the bounds' width and height in the vertical field of view, plus `padding` (units),
/// along the sampled viewing direction, aimed at the bounds' centre.
pub fn frame_camera(
    sample: &CameraSample,
    bounds: ([f64; 3], [f64; 3]),
    padding: f64,
    width: u32,
    height: u32,
) -> CameraModel {
    let (low, high) = bounds;
    let centre = [
        f64::midpoint(low[0], high[0]),
        f64::midpoint(low[1], high[1]),
        f64::midpoint(low[2], high[2]),
    ];
    let size = (high[0] - low[0]).max(high[1] - low[1]);
    let distance = size * 0.5 / (sample.vertical_fov_deg.to_radians() / 2.0).tan() + padding;
    let direction = [
        sample.position[0] - centre[0],
        sample.position[1] - centre[1],
        sample.position[2] - centre[2],
    ];
    let length = (direction[0].powi(2) + direction[1].powi(2) + direction[2].powi(2)).sqrt();
    let unit = if length > 0.0 {
        direction.map(|c| c / length)
    } else {
        [0.0, 0.0, if sample.mirrored { -1.0 } else { 1.0 }]
    };
    let position = [
        centre[0] + unit[0] * distance,
        centre[1] + unit[1] * distance,
        centre[2] + unit[2] * distance,
    ];
    CameraModel::looking_at(position, centre, sample.vertical_fov_deg, width, height)
}
