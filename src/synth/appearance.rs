//! Domain randomisation of how a generated video looks (`generate --appearance randomized`), for
//! training perception models on generated frames only: the real videos are held out, so the
//! detector and the colour model must meet lighting, wall, surface colours and sensor effects
//! they were not drawn with.
//!
//! Input: a [`SynthesizedVideo`] and a seed. [`randomize`] redraws the video's light (direction,
//! ambient, diffuse, highlight), its wall (colour, texture scale, grain and contrast), jitters
//! each labelled object's colour by a few percent (the same in every frame, small enough that
//! its palette name stays right), redraws painted stripes (period, dark share, depth, softness)
//! and the drop shadow (offset, penumbra, strength); it returns a [`FrameFinish`], which
//! [`FrameFinish::apply`] uses after rendering each frame: white balance, gamma, a light blur
//! and Gaussian sensor noise.
//! Geometry, simulation, annotations and masks are untouched, so a randomised video answers its
//! questions exactly as the release-looking one of the same seed. Every draw comes from a seeded
//! ChaCha stream: the same seed gives the same bytes.

use std::collections::BTreeMap;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::SynthesizedVideo;
use super::raster::Stripes;
use super::shadow::Shadow;
use crate::util::derive_seed;

/// How generated frames look.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Appearance {
    /// The release's look (fixed light and wall per scene family): the default.
    #[default]
    Release,
    /// Light, wall, colours and sensor effects drawn per video (domain randomisation).
    Randomized,
}

/// What happens to each rendered frame of a randomised video.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameFinish {
    /// Per-channel gain (white balance and exposure).
    pub gain: [f64; 3],
    /// Exponent on values in `[0, 1]` (1: none).
    pub gamma: f64,
    /// Weight of a 3×3 box blur mixed into each pixel (0: sharp).
    pub blur: f64,
    /// Standard deviation of the additive Gaussian noise, in 8-bit levels.
    pub noise: f64,
    /// Seed of the noise (each frame draws its own stream from it).
    pub seed: u64,
}

/// Redraws the light, the wall and the objects' colours of `video` from `seed`, and returns the
/// per-frame finish to apply after rendering.
pub fn randomize(video: &mut SynthesizedVideo, seed: u64) -> FrameFinish {
    let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(seed, "appearance"));
    // The light stays on the camera's side of the wall (its z sign is the scene's).
    let toward_camera = video.light.direction[2].signum();
    let direction = [
        rng.random_range(-0.7..0.7),
        rng.random_range(-0.2..0.9),
        toward_camera * rng.random_range(0.4..1.0),
    ];
    let norm = direction.iter().map(|c: &f64| c * c).sum::<f64>().sqrt();
    video.light.direction = direction.map(|c| c / norm);
    video.light.ambient = rng.random_range(0.25..0.6);
    // Ambient and diffuse together stay under 1.25, so lit faces keep their hue (no clipping to
    // white).
    video.light.diffuse = rng.random_range(0.35..(1.25 - video.light.ambient).min(0.85));
    video.light.specular = rng.random_range(0.0..0.5);
    video.light.shininess = rng.random_range(6.0..64.0);
    let grey: f64 = rng.random_range(0.45..0.92);
    video.wall.color = [0; 3].map(|_| (grey * rng.random_range(0.96..1.03)).min(1.0));
    video.wall.frequency = rng.random_range(0.5..3.0);
    video.wall.contrast = rng.random_range(0.1..0.6);
    // Streaks either way or none: the grain's stretch ratio spans 1:5 to 5:1.
    let stretch: f64 = rng.random_range(-1.6_f64..1.6).exp();
    video.wall.grain = [1.3 * stretch.sqrt(), 1.3 / stretch.sqrt()];
    video.wall.variant = rng.random_range(0..1_000_000);
    // One colour factor per labelled instance, drawn in instance order (deterministic).
    let mut factors: BTreeMap<u32, [f64; 3]> = BTreeMap::new();
    for label in &video.labels {
        factors.insert(label.instance, [0.0; 3]);
    }
    for factor in factors.values_mut() {
        *factor = [0; 3].map(|_| rng.random_range(0.93..1.07));
    }
    // Stripes per striped instance, drawn in instance order after the colours.
    let mut stripes: BTreeMap<u32, Stripes> = BTreeMap::new();
    for frame in &video.frames {
        for item in frame {
            if let Some(pattern) = item.stripes {
                stripes.entry(item.instance).or_insert(pattern);
            }
        }
    }
    for pattern in stripes.values_mut() {
        pattern.period = rng.random_range(0.1..0.6);
        pattern.dark_share = rng.random_range(0.25..0.6);
        pattern.dark = rng.random_range(0.15..0.85);
        pattern.softness = rng.random_range(0.1..0.5);
    }
    for frame in &mut video.frames {
        for item in frame.iter_mut() {
            if let Some(factor) = factors.get(&item.instance) {
                for (channel, scale) in item.color.iter_mut().zip(factor) {
                    *channel = (*channel * scale).clamp(0.0, 1.0);
                }
            }
            if item.stripes.is_some() {
                item.stripes = stripes.get(&item.instance).copied();
            }
        }
    }
    let shadow_angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
    let shadow_distance: f64 = rng.random_range(0.0..0.016);
    video.shadow = Shadow {
        offset: [
            shadow_distance * shadow_angle.cos(),
            shadow_distance * shadow_angle.sin(),
        ],
        blur: rng.random_range(0.001..0.012),
        strength: rng.random_range(0.0..0.6),
    };
    FrameFinish {
        gain: [0; 3].map(|_| rng.random_range(0.95..1.05)),
        gamma: rng.random_range(0.85..1.15),
        blur: if rng.random_bool(0.5) {
            rng.random_range(0.2..0.8)
        } else {
            0.0
        },
        noise: rng.random_range(0.0..5.0),
        seed: rng.random(),
    }
}

impl FrameFinish {
    /// Applies the finish to frame `index` (RGB bytes, `width`×`height`, row-major).
    pub fn apply(&self, index: usize, width: u32, height: u32, rgb: &mut [u8]) {
        let (width, height) = (width as usize, height as usize);
        if rgb.len() != width * height * 3 {
            return;
        }
        // The unblurred frame, kept only when the blur reads neighbours that are rewritten.
        let source: Option<Vec<f64>> =
            (self.blur > 0.0).then(|| rgb.iter().map(|&b| f64::from(b)).collect());
        let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(self.seed, &format!("frame/{index}")));
        for y in 0..height {
            for x in 0..width {
                for channel in 0..3 {
                    let at = (y * width + x) * 3 + channel;
                    let mut value = f64::from(rgb[at]);
                    if let Some(source) = &source {
                        let mut sum = 0.0;
                        let mut count = 0.0;
                        for ny in y.saturating_sub(1)..=(y + 1).min(height - 1) {
                            for nx in x.saturating_sub(1)..=(x + 1).min(width - 1) {
                                sum += source[(ny * width + nx) * 3 + channel];
                                count += 1.0;
                            }
                        }
                        value = (1.0 - self.blur) * value + self.blur * sum / count;
                    }
                    let normalised = (value / 255.0 * self.gain[channel]).clamp(0.0, 1.0);
                    let noise = self.noise * gaussian(&mut rng);
                    let level = normalised.powf(self.gamma) * 255.0 + noise;
                    // Clamped to the byte range first: the cast cannot truncate.
                    #[expect(
                        clippy::cast_possible_truncation,
                        clippy::cast_sign_loss,
                        reason = "clamped to 0..=255"
                    )]
                    let byte = level.round().clamp(0.0, 255.0) as u8;
                    rgb[at] = byte;
                }
            }
        }
    }
}

/// A standard normal draw (Box–Muller).
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = rng.random_range(f64::EPSILON..1.0);
    let v: f64 = rng.random_range(0.0..1.0);
    (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn finish(noise: f64, blur: f64) -> FrameFinish {
        FrameFinish {
            gain: [1.0; 3],
            gamma: 1.0,
            blur,
            noise,
            seed: 7,
        }
    }

    #[test]
    fn an_identity_finish_keeps_the_frame_and_noise_has_its_spread() {
        let frame: Vec<u8> = (0..48_u8 * 3).map(|i| i.wrapping_mul(5)).collect();
        let mut same = frame.clone();
        finish(0.0, 0.0).apply(0, 12, 4, &mut same);
        assert_eq!(same, frame);
        // Noise of σ = 4 levels on a flat grey frame: the sample spread is about 4.
        let mut grey = vec![128_u8; 100 * 100 * 3];
        finish(4.0, 0.0).apply(3, 100, 100, &mut grey);
        let values: Vec<f64> = grey.iter().map(|&b| f64::from(b) - 128.0).collect();
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let spread =
            (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt();
        assert!(mean.abs() < 0.1, "mean {mean}");
        assert!((spread - 4.0).abs() < 0.15, "spread {spread}");
        // The same frame index gives the same noise; another index other noise.
        let mut again = vec![128_u8; 100 * 100 * 3];
        finish(4.0, 0.0).apply(3, 100, 100, &mut again);
        assert_eq!(again, grey);
        let mut other = vec![128_u8; 100 * 100 * 3];
        finish(4.0, 0.0).apply(4, 100, 100, &mut other);
        assert_ne!(other, grey);
    }

    #[test]
    fn a_full_blur_averages_the_neighbourhood() {
        // A single bright pixel in the middle of a 3×3 black frame spreads to a ninth.
        let mut frame = vec![0_u8; 27];
        frame[12..15].copy_from_slice(&[90, 90, 90]);
        finish(0.0, 1.0).apply(0, 3, 3, &mut frame);
        assert_eq!(&frame[12..15], &[10, 10, 10]);
        // A corner averages its four in-frame neighbours: 90 / 4 rounds to 23.
        assert_eq!(&frame[0..3], &[23, 23, 23]);
    }
}
