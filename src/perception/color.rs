//! Colour words from pixels: which palette colour (`perception::palette`) an object is painted
//! in, read from the frame pixels under its mask.
//!
//! Shading scales an object's light, and the wall's colour shows the light's tint, so the
//! features are taken in linear light relative to the wall (the median of the pixels no object
//! covers): the chromaticity `(r, g) / (r + g + b)` and the log brightness `ln(r + g + b)` of the
//! mean of the brighter half of the masked pixels (the lit side, away from shadowed edges). A
//! [`ColorModel`] holds one diagonal Gaussian per palette colour, fitted on ground-truth masks of
//! generated and real frames (`contphy-eval perception fit-colors`), and names the colour of
//! highest likelihood. Input: an [`RgbFrame`], masks. Output: palette ids.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::detection::InstanceMask;
use super::frames::RgbFrame;

/// The feature vector of one object: linear chromaticity r, g and log brightness, relative to
/// the wall.
pub type ColorFeatures = [f64; 3];

/// Smallest variance per feature, so a colour seen in few samples is not infinitely sharp.
const VARIANCE_FLOOR: [f64; 3] = [1e-4, 1e-4, 1e-2];

/// Fewest masked pixels a colour is read from.
pub const MIN_PIXELS: usize = 8;

/// sRGB byte to linear light.
pub fn srgb_to_linear(byte: u8) -> f64 {
    let c = f64::from(byte) / 255.0;
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_pixel(frame: &RgbFrame, x: u32, y: u32) -> Option<[f64; 3]> {
    frame.pixel(x, y).map(|p| p.map(srgb_to_linear))
}

fn median(values: &mut [f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    Some(values[values.len() / 2])
}

/// The wall's linear colour: the per-channel median of the pixels outside every mask, sampled on
/// a grid of about 100×60 points. `None` when masks cover everything.
pub fn wall_color(frame: &RgbFrame, masks: &[&InstanceMask]) -> Option<[f64; 3]> {
    let step_x = (frame.width / 100).max(1);
    let step_y = (frame.height / 60).max(1);
    let mut channels: [Vec<f64>; 3] = [Vec::new(), Vec::new(), Vec::new()];
    for y in (0..frame.height).step_by(step_y as usize) {
        for x in (0..frame.width).step_by(step_x as usize) {
            if masks.iter().any(|m| m.contains(x, y)) {
                continue;
            }
            if let Some(p) = linear_pixel(frame, x, y) {
                for c in 0..3 {
                    channels[c].push(p[c]);
                }
            }
        }
    }
    let [r, g, b] = &mut channels;
    Some([median(r)?, median(g)?, median(b)?]).filter(|w| w.iter().all(|c| *c > 1e-4))
}

/// How unlike the wall pixel `(x, y)` is: the squared distance of its colour relative to the
/// wall from (1, 1, 1), in log space (darker and brighter count alike); `None` outside the
/// frame.
pub fn unlike_wall(frame: &RgbFrame, x: u32, y: u32, wall: [f64; 3]) -> Option<f64> {
    let p = linear_pixel(frame, x, y)?;
    Some(
        (0..3)
            .map(|c| (p[c] / wall[c]).max(1e-4).ln().powi(2))
            .sum(),
    )
}

/// The features of one pixel relative to `wall` (those of [`features`] for a single pixel);
/// `None` off the frame or when not finite.
pub fn pixel_features(frame: &RgbFrame, x: u32, y: u32, wall: [f64; 3]) -> Option<ColorFeatures> {
    let p = linear_pixel(frame, x, y)?;
    let relative = [p[0] / wall[0], p[1] / wall[1], p[2] / wall[2]];
    let sum = relative[0] + relative[1] + relative[2] + 1e-6;
    let result = [relative[0] / sum, relative[1] / sum, sum.ln()];
    result.iter().all(|v| v.is_finite()).then_some(result)
}

/// The features of the pixels under `mask`, relative to `wall`; `None` with fewer than
/// [`MIN_PIXELS`] pixels. Only the half of the pixels least like the wall counts: a mask bleeds
/// onto the wall round its object (a thin rope's mask is mostly wall), and taking the brighter
/// half instead would keep that bleed for every object darker than the wall (red, brown, black).
pub fn features(frame: &RgbFrame, mask: &InstanceMask, wall: [f64; 3]) -> Option<ColorFeatures> {
    let mut pixels: Vec<([f64; 3], f64)> = mask
        .pixels()
        .filter_map(|(x, y)| linear_pixel(frame, x, y))
        .map(|p| {
            let relative = [p[0] / wall[0], p[1] / wall[1], p[2] / wall[2]];
            // Unlikeness to the wall: how far the relative colour is from (1, 1, 1), in log
            // space so that darker and brighter count alike.
            let unlike = relative
                .iter()
                .map(|c| c.max(1e-4).ln().powi(2))
                .sum::<f64>();
            (relative, unlike)
        })
        .collect();
    if pixels.len() < MIN_PIXELS {
        return None;
    }
    pixels.sort_by(|a, b| a.1.total_cmp(&b.1));
    let object = &pixels[pixels.len() / 2..];
    let mut mean = [0.0; 3];
    for (p, _) in object {
        for c in 0..3 {
            mean[c] += p[c] / object.len() as f64;
        }
    }
    let sum = mean[0] + mean[1] + mean[2] + 1e-6;
    let result = [mean[0] / sum, mean[1] / sum, sum.ln()];
    result.iter().all(|v| v.is_finite()).then_some(result)
}

/// One palette colour's Gaussian.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ColorPrototype {
    /// Palette id.
    pub palette_id: u8,
    /// Palette name.
    pub name: String,
    /// Feature means.
    pub mean: [f64; 3],
    /// Feature variances (floored).
    pub variance: [f64; 3],
    /// Samples it was fitted on.
    pub samples: usize,
}

/// A fitted colour classifier.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ColorModel {
    /// What it was fitted on (free text, for the record).
    pub fitted_on: String,
    /// One prototype per palette colour seen in fitting, by palette id.
    pub prototypes: Vec<ColorPrototype>,
    /// The fitting samples (palette id, features), for nearest-neighbour voting: a colour
    /// renders differently in the release's Unity frames and in the generator's, and the
    /// neighbours keep both looks apart where one Gaussian would blur them. Empty: Gaussians.
    #[serde(default)]
    pub samples: Vec<(u8, ColorFeatures)>,
    /// The videos fitted on, each with the SHA-256 of its `outputs.json`, so anyone can check
    /// that a held-out video (the release's real one) was not among them.
    #[serde(default)]
    pub training_videos: Vec<TrainingVideo>,
}

/// One video a model was fitted or trained on.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct TrainingVideo {
    /// The video folder, relative to the data root's parent (`train-rope/pulley_group/3`).
    pub video: String,
    /// SHA-256 of its `outputs.json`, lowercase hex.
    pub outputs_sha256: String,
}

/// Neighbours that vote in [`ColorModel::classify`].
pub const NEIGHBOURS: usize = 7;

/// Why a colour model could not be read or fitted.
#[derive(Debug, thiserror::Error)]
pub enum ColorModelError {
    /// The file could not be read.
    #[error("cannot read colour model {path}")]
    Read {
        /// The file.
        path: std::path::PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// The file is not a colour model.
    #[error("colour model {path} is not valid: {message}")]
    Invalid {
        /// The file.
        path: std::path::PathBuf,
        /// What is wrong.
        message: String,
    },
    /// No samples to fit.
    #[error("no coloured objects to fit the colour model on")]
    NoSamples,
}

impl ColorModel {
    /// Fits one Gaussian per palette colour in `samples` (palette id, features).
    pub fn fit(samples: &[(u8, ColorFeatures)], fitted_on: &str) -> Result<Self, ColorModelError> {
        let mut prototypes = Vec::new();
        for color in super::palette::PALETTE {
            let own: Vec<&ColorFeatures> = samples
                .iter()
                .filter(|(id, _)| *id == color.id)
                .map(|(_, f)| f)
                .collect();
            if own.is_empty() {
                continue;
            }
            let n = own.len() as f64;
            let mut mean = [0.0; 3];
            for f in &own {
                for c in 0..3 {
                    mean[c] += f[c] / n;
                }
            }
            let mut variance = [0.0; 3];
            for f in &own {
                for c in 0..3 {
                    variance[c] += (f[c] - mean[c]).powi(2) / n;
                }
            }
            for c in 0..3 {
                variance[c] = variance[c].max(VARIANCE_FLOOR[c]);
            }
            prototypes.push(ColorPrototype {
                palette_id: color.id,
                name: color.name.to_string(),
                mean,
                variance,
                samples: own.len(),
            });
        }
        if prototypes.is_empty() {
            return Err(ColorModelError::NoSamples);
        }
        // Round the stored samples so the file stays small and diffable.
        let round = |v: f64| (v * 1e4).round() / 1e4;
        Ok(ColorModel {
            fitted_on: fitted_on.to_string(),
            prototypes,
            samples: samples.iter().map(|(id, f)| (*id, f.map(round))).collect(),
            training_videos: Vec::new(),
        })
    }

    /// Reads a model written by [`ColorModel::fit`] and serde.
    pub fn read(path: &Path) -> Result<Self, ColorModelError> {
        let text = fs_err::read_to_string(path).map_err(|source| ColorModelError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let model: ColorModel =
            serde_json::from_str(&text).map_err(|e| ColorModelError::Invalid {
                path: path.to_path_buf(),
                message: e.to_string(),
            })?;
        let valid = !model.prototypes.is_empty()
            && model.prototypes.iter().all(|p| {
                super::palette::palette_color(p.palette_id).is_some()
                    && p.mean.iter().all(|v| v.is_finite())
                    && p.variance.iter().all(|v| v.is_finite() && *v > 0.0)
            });
        if !valid {
            return Err(ColorModelError::Invalid {
                path: path.to_path_buf(),
                message: "prototypes must name palette colours and have finite, positive variances"
                    .to_string(),
            });
        }
        Ok(model)
    }

    /// The palette id of `features` among the colours `allowed` (every colour when empty): the
    /// majority of the nearest fitting samples of those colours (distances scaled by each
    /// feature's spread), or the Gaussian of highest likelihood when the model has too few
    /// samples.
    pub fn classify(&self, features: &ColorFeatures, allowed: &[u8]) -> Option<u8> {
        self.votes(features, allowed).first().map(|(id, _)| *id)
    }

    /// The colours `allowed` (every colour when empty) that the nearest fitting samples of
    /// those colours name, with how many of the [`NEIGHBOURS`] each has, most votes first (then
    /// the closer voters, then the smaller id); with too few samples, the Gaussian of highest
    /// likelihood alone, with every vote.
    pub fn votes(&self, features: &ColorFeatures, allowed: &[u8]) -> Vec<(u8, usize)> {
        let admitted = |id: u8| allowed.is_empty() || allowed.contains(&id);
        if self.samples.iter().filter(|(id, _)| admitted(*id)).count() >= NEIGHBOURS {
            return self.nearest_neighbours(features, admitted);
        }
        self.likeliest(features, allowed)
            .map(|id| vec![(id, NEIGHBOURS)])
            .unwrap_or_default()
    }

    /// The colour among `allowed` (every colour when empty) whose Gaussian gives `features` the
    /// highest likelihood (ties: the smaller id): cheap enough for every pixel of a mask, where
    /// the neighbour vote of [`ColorModel::classify`] is for one feature per object.
    pub fn likeliest(&self, features: &ColorFeatures, allowed: &[u8]) -> Option<u8> {
        self.log_likelihoods(features, allowed)
            .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))
            .map(|(_, id)| id)
    }

    /// The colours among `allowed` (every colour when empty), likeliest first by their
    /// Gaussians (ties: the smaller id).
    pub fn ranked(&self, features: &ColorFeatures, allowed: &[u8]) -> Vec<u8> {
        let mut scored: Vec<(f64, u8)> = self.log_likelihoods(features, allowed).collect();
        scored.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        scored.into_iter().map(|(_, id)| id).collect()
    }

    /// Each admitted prototype's finite log-likelihood of `features`, with its palette id.
    fn log_likelihoods<'a>(
        &'a self,
        features: &'a ColorFeatures,
        allowed: &'a [u8],
    ) -> impl Iterator<Item = (f64, u8)> + 'a {
        self.prototypes
            .iter()
            .filter(move |p| allowed.is_empty() || allowed.contains(&p.palette_id))
            .map(move |p| {
                let log_likelihood: f64 = (0..3)
                    .map(|c| {
                        -0.5 * ((features[c] - p.mean[c]).powi(2) / p.variance[c]
                            + p.variance[c].ln())
                    })
                    .sum();
                (log_likelihood, p.palette_id)
            })
            .filter(|(l, _)| l.is_finite())
    }
}

impl ColorModel {
    fn nearest_neighbours(
        &self,
        features: &ColorFeatures,
        admitted: impl Fn(u8) -> bool,
    ) -> Vec<(u8, usize)> {
        let n = self.samples.len() as f64;
        let mut scale = [0.0; 3];
        for c in 0..3 {
            let mean = self.samples.iter().map(|(_, f)| f[c]).sum::<f64>() / n;
            let variance = self
                .samples
                .iter()
                .map(|(_, f)| (f[c] - mean).powi(2))
                .sum::<f64>()
                / n;
            scale[c] = variance.sqrt().max(1e-6);
        }
        // The spread is the whole model's, so distances do not depend on which colours are admitted.
        let mut distances: Vec<(f64, u8)> = self
            .samples
            .iter()
            .filter(|(id, _)| admitted(*id))
            .map(|(id, f)| {
                let d: f64 = (0..3)
                    .map(|c| ((f[c] - features[c]) / scale[c]).powi(2))
                    .sum();
                (d, *id)
            })
            .filter(|(d, _)| d.is_finite())
            .collect();
        distances.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let nearest = &distances[..NEIGHBOURS.min(distances.len())];
        // Votes, then the summed closeness of each colour's voters, then the smaller id.
        let mut tally: Vec<(u8, usize, f64)> = Vec::new();
        for (d, id) in nearest {
            match tally.iter_mut().find(|t| t.0 == *id) {
                Some(entry) => {
                    entry.1 += 1;
                    entry.2 += d;
                }
                None => tally.push((*id, 1, *d)),
            }
        }
        tally.sort_by(|a, b| b.1.cmp(&a.1).then(a.2.total_cmp(&b.2)).then(a.0.cmp(&b.0)));
        tally
            .into_iter()
            .map(|(id, votes, _)| (id, votes))
            .collect()
    }
}

/// Names each detection's colour with `model`, among the colours its class can have (`table`),
/// reading the wall around the detections; leaves the colours unset when the detections cover the
/// whole frame.
pub fn name_colors(
    frame: &RgbFrame,
    detections: &mut [super::detection::Detection],
    model: &ColorModel,
    table: &super::classes::ClassTable,
) {
    let masks: Vec<&InstanceMask> = detections.iter().map(|d| &d.mask).collect();
    let Some(wall) = wall_color(frame, &masks) else {
        return;
    };
    let named: Vec<Option<u8>> = detections
        .iter()
        .map(|d| {
            features(frame, &d.mask, wall).and_then(|f| model.classify(&f, table.colors(d.class)))
        })
        .collect();
    for (detection, color) in detections.iter_mut().zip(named) {
        detection.color = color;
    }
}

/// The palette id of a release object name's colour words (`Light Blue Rope` → 12), the longest
/// palette name the name starts with.
pub fn palette_id_of_name(name: &str) -> Option<u8> {
    super::palette::PALETTE
        .iter()
        .filter(|c| {
            name.len() > c.name.len()
                && name[..c.name.len()].eq_ignore_ascii_case(c.name)
                && name.as_bytes()[c.name.len()] == b' '
        })
        .max_by_key(|c| c.name.len())
        .map(|c| c.id)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_keep_two_looks_of_one_colour_apart_from_a_third_colour() {
        // Purple seen in two looks (generated, brighter; real, darker) either side of red: the
        // nearest samples name each look, and red in between stays red.
        let mut samples = Vec::new();
        for i in 0..5 {
            let jitter = f64::from(i) * 0.002;
            samples.push((6, [0.40 + jitter, 0.20, 0.5]));
            samples.push((6, [0.40 + jitter, 0.20, -0.5]));
            samples.push((0, [0.40 + jitter, 0.20, 0.0]));
            samples.push((3, [0.10 + jitter, 0.60, 0.0]));
        }
        let model = ColorModel::fit(&samples, "test").expect("a model");
        assert_eq!(model.samples.len(), 20);
        assert_eq!(model.classify(&[0.404, 0.2, -0.48], &[]), Some(6));
        assert_eq!(model.classify(&[0.404, 0.2, 0.02], &[]), Some(0));
    }

    #[test]
    fn a_colour_the_class_cannot_have_is_never_read() {
        // A dark sample nearest to black's samples, read for a class without black (a pulley),
        // is the nearest colour the class can have: gray.
        let mut samples = Vec::new();
        for i in 0..8 {
            let jitter = f64::from(i) * 0.002;
            samples.push((10, [0.33 + jitter, 0.33, -2.0]));
            samples.push((9, [0.33 + jitter, 0.33, -1.0]));
            samples.push((0, [0.90 + jitter, 0.05, -0.5]));
        }
        let model = ColorModel::fit(&samples, "test").expect("a model");
        let dark = [0.335, 0.33, -1.8];
        assert_eq!(model.classify(&dark, &[]), Some(10));
        assert_eq!(model.classify(&dark, &[0, 9, 11]), Some(9));
        assert_eq!(model.classify(&dark, &[0]), Some(0));
        // No sample of an admitted colour: nothing is read.
        assert_eq!(model.classify(&dark, &[7]), None);
        // Too few samples: the Gaussians decide, among the admitted colours only.
        let sparse = ColorModel::fit(&samples[..6], "test").expect("a model");
        assert_eq!(sparse.classify(&dark, &[]), Some(10));
        assert_eq!(sparse.classify(&dark, &[0, 9]), Some(9));
    }

    #[test]
    fn names_give_their_longest_palette_colour() {
        assert_eq!(palette_id_of_name("Light Blue Rope"), Some(12));
        assert_eq!(
            palette_id_of_name("Blue Solid Static Pulley (0 1)"),
            Some(5)
        );
        assert_eq!(palette_id_of_name("Gray Sphere"), Some(9));
        assert_eq!(palette_id_of_name("Solver"), None);
        assert_eq!(palette_id_of_name("Red"), None);
    }

    fn frame_with_square(color: [u8; 3]) -> (RgbFrame, InstanceMask) {
        let (width, height) = (40u32, 30u32);
        let inside = |x: u32, y: u32| (10..20).contains(&x) && (10..20).contains(&y);
        let mut rgb = Vec::new();
        for y in 0..height {
            for x in 0..width {
                rgb.extend_from_slice(&if inside(x, y) { color } else { [200, 200, 200] });
            }
        }
        let frame = RgbFrame {
            index: 0,
            width,
            height,
            rgb,
        };
        (frame, InstanceMask::from_predicate(width, height, inside))
    }

    #[test]
    fn features_are_relative_to_the_wall_and_the_nearest_prototype_wins() {
        let (red_frame, mask) = frame_with_square([200, 0, 0]);
        let wall = wall_color(&red_frame, &[&mask]).expect("a wall");
        assert!((wall[0] - srgb_to_linear(200)).abs() < 1e-12);
        let red = features(&red_frame, &mask, wall).expect("100 pixels");
        // Pure red relative to a grey wall: chromaticity (1, 0), brightness ln(1).
        assert!((red[0] - 1.0).abs() < 1e-4 && red[1].abs() < 1e-9 && red[2].abs() < 1e-4);
        let (green_frame, _) = frame_with_square([0, 200, 0]);
        let green = features(&green_frame, &mask, wall).expect("100 pixels");
        let model = ColorModel::fit(&[(0, red), (0, red), (3, green)], "test").expect("a model");
        assert_eq!(model.classify(&red, &[]), Some(0));
        assert_eq!(model.classify(&green, &[]), Some(3));
        assert!(ColorModel::fit(&[], "none").is_err());
        // Too few pixels.
        let tiny = InstanceMask::from_predicate(40, 30, |x, y| x == 10 && y < 3);
        assert_eq!(features(&red_frame, &tiny, wall), None);
    }

    #[test]
    fn one_pixel_reads_like_its_object_and_only_admitted_colours_win() {
        let (red_frame, mask) = frame_with_square([200, 0, 0]);
        let wall = wall_color(&red_frame, &[&mask]).expect("a wall");
        let object = features(&red_frame, &mask, wall).expect("100 pixels");
        // A uniform square: each of its pixels has the object's features.
        let pixel = pixel_features(&red_frame, 12, 15, wall).expect("inside the frame");
        for c in 0..3 {
            assert!((pixel[c] - object[c]).abs() < 1e-9, "feature {c}");
        }
        assert_eq!(pixel_features(&red_frame, 40, 0, wall), None);
        let (green_frame, _) = frame_with_square([0, 200, 0]);
        let green = features(&green_frame, &mask, wall).expect("100 pixels");
        let model = ColorModel::fit(&[(0, object), (3, green)], "test").expect("a model");
        assert_eq!(model.likeliest(&pixel, &[]), Some(0));
        assert_eq!(model.likeliest(&pixel, &[0, 3]), Some(0));
        // Red not admitted: the likeliest of what is.
        assert_eq!(model.likeliest(&pixel, &[3]), Some(3));
        assert_eq!(model.likeliest(&pixel, &[7]), None);
    }
}
