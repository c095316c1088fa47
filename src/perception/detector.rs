//! The Mask R-CNN detector: an ONNX model (exported by `scripts/perception/export.py`) run with
//! `ort` on one frame at a time.
//!
//! Input: an [`RgbFrame`] at any resolution. The frame is area-averaged down to the model's
//! input size (480×270 for the committed model; the release's 1920×1080 is an exact 4× box
//! average), turned into CHW `f32` in `[0, 1]`, and run. The model returns boxes, labels, scores
//! and raw 28×28 mask probabilities; only detections above the score threshold are kept, and
//! only their masks are pasted, at the frame's own resolution, with torchvision's
//! `paste_masks_in_image` arithmetic (one pixel of padding, `int64` box truncation, bilinear
//! resampling without corner alignment). Output: [`Detection`]s in the frame's pixels.
//!
//! The model contract (names and types) is checked when the model is loaded, so a wrong or
//! corrupt file fails once, with its path, instead of on every frame.

#![expect(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    reason = "pixel coordinates and sizes are far below 2^31, and torch's int64 box cast truncates"
)]

use std::path::{Path, PathBuf};

use ndarray::{Array3, ArrayView3};
use ort::session::Session;
use ort::session::builder::GraphOptimizationLevel;
use ort::value::TensorRef;

use super::classes::{ClassError, ClassTable, ScenarioClasses};
use super::detection::{Detection, InstanceMask, suppress_duplicates};
use super::frames::RgbFrame;
use super::runtime::{RuntimeError, environment};

/// Side length of the model's raw masks.
pub const MASK_SIZE: usize = 28;

/// The model's input name.
pub const INPUT_NAME: &str = "images_tensors";

/// The model's output names, in the order [`RawDetections`] reads them.
pub const OUTPUT_NAMES: [&str; 4] = ["boxes", "labels", "scores", "masks"];

/// How the detector runs.
#[derive(Debug, Clone, PartialEq)]
pub struct DetectorConfig {
    /// The ONNX model file.
    pub model: PathBuf,
    /// Model input width, pixels.
    pub input_width: u32,
    /// Model input height, pixels.
    pub input_height: u32,
    /// Detections scoring below this are dropped before their masks are pasted.
    pub score_threshold: f32,
    /// A pasted mask pixel belongs to the object when its probability is at least this.
    pub mask_threshold: f32,
    /// ONNX Runtime intra-op threads.
    pub threads: usize,
}

impl DetectorConfig {
    /// The committed model's settings for `model`, with `threads` intra-op threads.
    pub fn new(model: PathBuf, threads: usize) -> Self {
        DetectorConfig {
            model,
            input_width: 480,
            input_height: 270,
            score_threshold: 0.5,
            mask_threshold: 0.5,
            threads: threads.max(1),
        }
    }
}

/// Why detection failed.
#[derive(Debug, Clone, thiserror::Error)]
pub enum DetectorError {
    /// The runtime library is missing or unusable.
    #[error(transparent)]
    Runtime(#[from] RuntimeError),
    /// The model file is missing.
    #[error("model file {path} does not exist")]
    MissingModel {
        /// The model path.
        path: PathBuf,
    },
    /// ONNX Runtime could not load the model (a corrupt or foreign file).
    #[error("cannot load model {path}: {message}")]
    Model {
        /// The model path.
        path: PathBuf,
        /// What ONNX Runtime said, first line only.
        message: String,
    },
    /// The model's description file is missing, or names no class of the scenario.
    #[error(transparent)]
    Classes(#[from] ClassError),
    /// The model does not have the inputs and outputs this detector reads.
    #[error("model {path} is not a contphy Mask R-CNN export: {problem}")]
    Contract {
        /// The model path.
        path: PathBuf,
        /// What is missing or wrong.
        problem: String,
    },
    /// Running the model or reading its outputs failed.
    #[error("running model {path} on frame {frame}: {message}")]
    Inference {
        /// The model path.
        path: PathBuf,
        /// The frame index.
        frame: usize,
        /// What went wrong.
        message: String,
    },
    /// A frame with no pixels.
    #[error("frame {frame} is empty ({width}×{height})")]
    EmptyFrame {
        /// The frame index.
        frame: usize,
        /// Width.
        width: u32,
        /// Height.
        height: u32,
    },
}

fn first_line(text: &str) -> String {
    text.lines().next().unwrap_or_default().trim().to_string()
}

/// The model's outputs for one input, before thresholding.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RawDetections {
    /// `[x0, y0, x1, y1]` in input pixels.
    pub boxes: Vec<[f32; 4]>,
    /// Label ids (1-based classes, named by the model's description file).
    pub labels: Vec<i64>,
    /// Scores in `[0, 1]`, descending.
    pub scores: Vec<f32>,
    /// Raw mask probabilities, `MASK_SIZE × MASK_SIZE` row-major per detection.
    pub masks: Vec<Vec<f32>>,
}

/// Wall-clock time of the stages of one [`Detector::detect_timed`] call, ms.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct StageTimes {
    /// Scaling to the model input and conversion to `f32`.
    pub preprocess_ms: f64,
    /// The ONNX Runtime session run and reading its outputs.
    pub inference_ms: f64,
    /// Thresholding and mask pasting.
    pub postprocess_ms: f64,
}

/// A loaded detector. `detect` needs `&mut self` because an `ort` session runs mutably.
pub struct Detector {
    session: Session,
    config: DetectorConfig,
    classes: ClassTable,
}

impl std::fmt::Debug for Detector {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Detector")
            .field("config", &self.config)
            .finish_non_exhaustive()
    }
}

impl Detector {
    /// Loads and checks the model, and reads its classes (the description file beside it) as
    /// `scenario` knows them.
    pub fn load(
        config: DetectorConfig,
        scenario: ScenarioClasses,
    ) -> Result<Detector, DetectorError> {
        let path = config.model.clone();
        if !path.is_file() {
            return Err(DetectorError::MissingModel { path });
        }
        let environment = environment()?;
        let model_error = |message: String| DetectorError::Model {
            path: path.clone(),
            message: first_line(&message),
        };
        let builder = Session::builder(environment).map_err(|e| model_error(e.to_string()))?;
        let mut builder = builder
            .with_optimization_level(GraphOptimizationLevel::Level3)
            .map_err(|e| model_error(e.to_string()))?
            .with_intra_threads(config.threads)
            .map_err(|e| model_error(e.to_string()))?
            .with_inter_threads(1)
            .map_err(|e| model_error(e.to_string()))?;
        let session = builder
            .commit_from_file(&path)
            .map_err(|e| model_error(e.to_string()))?;
        check_contract(&session, &path)?;
        let classes = ClassTable::for_model(&path, scenario)?;
        Ok(Detector {
            session,
            config,
            classes,
        })
    }

    /// The settings it runs with.
    pub fn config(&self) -> &DetectorConfig {
        &self.config
    }

    /// Its classes, as the scenario it was loaded for reads them.
    pub fn classes(&self) -> &ClassTable {
        &self.classes
    }

    /// Runs the model on a CHW `f32` image in `[0, 1]` and returns its raw outputs.
    pub fn run_raw(
        &mut self,
        image: &ArrayView3<'_, f32>,
        frame: usize,
    ) -> Result<RawDetections, DetectorError> {
        let path = self.config.model.clone();
        let fail = |message: String| DetectorError::Inference {
            path: path.clone(),
            frame,
            message: first_line(&message),
        };
        let input = TensorRef::from_array_view(image.view()).map_err(|e| fail(e.to_string()))?;
        let outputs = self
            .session
            .run(ort::inputs![INPUT_NAME => input])
            .map_err(|e| fail(e.to_string()))?;
        let boxes = outputs[OUTPUT_NAMES[0]]
            .try_extract_array::<f32>()
            .map_err(|e| fail(format!("boxes: {e}")))?;
        let labels = outputs[OUTPUT_NAMES[1]]
            .try_extract_array::<i64>()
            .map_err(|e| fail(format!("labels: {e}")))?;
        let scores = outputs[OUTPUT_NAMES[2]]
            .try_extract_array::<f32>()
            .map_err(|e| fail(format!("scores: {e}")))?;
        let masks = outputs[OUTPUT_NAMES[3]]
            .try_extract_array::<f32>()
            .map_err(|e| fail(format!("masks: {e}")))?;
        let count = scores.len();
        let shapes_agree = boxes.shape() == [count, 4]
            && labels.len() == count
            && masks.shape() == [count, 1, MASK_SIZE, MASK_SIZE];
        if !shapes_agree {
            return Err(fail(format!(
                "output shapes disagree: boxes {:?}, labels {:?}, scores {:?}, masks {:?}",
                boxes.shape(),
                labels.shape(),
                scores.shape(),
                masks.shape()
            )));
        }
        let mut raw = RawDetections::default();
        let box_values: Vec<f32> = boxes.iter().copied().collect();
        let mask_values: Vec<f32> = masks.iter().copied().collect();
        for i in 0..count {
            let b = &box_values[i * 4..i * 4 + 4];
            raw.boxes.push([b[0], b[1], b[2], b[3]]);
            raw.masks.push(
                mask_values[i * MASK_SIZE * MASK_SIZE..(i + 1) * MASK_SIZE * MASK_SIZE].to_vec(),
            );
        }
        raw.labels = labels.iter().copied().collect();
        raw.scores = scores.iter().copied().collect();
        Ok(raw)
    }

    /// Detects the objects of `frame`: preprocess, run, keep detections above the score
    /// threshold with a known class, and paste their masks at the frame's resolution. Colours
    /// are not read here (see `perception::color`).
    pub fn detect(&mut self, frame: &RgbFrame) -> Result<Vec<Detection>, DetectorError> {
        self.detect_timed(frame).map(|(detections, _)| detections)
    }

    /// [`Detector::detect`], with the time each stage took.
    pub fn detect_timed(
        &mut self,
        frame: &RgbFrame,
    ) -> Result<(Vec<Detection>, StageTimes), DetectorError> {
        let started = std::time::Instant::now();
        if frame.width == 0 || frame.height == 0 {
            return Err(DetectorError::EmptyFrame {
                frame: frame.index,
                width: frame.width,
                height: frame.height,
            });
        }
        let image = model_input(frame, self.config.input_width, self.config.input_height);
        let preprocessed = std::time::Instant::now();
        let raw = self.run_raw(&image.view(), frame.index)?;
        let inferred = std::time::Instant::now();
        let scale_x = frame.width as f32 / self.config.input_width as f32;
        let scale_y = frame.height as f32 / self.config.input_height as f32;
        let mut detections = Vec::new();
        for i in 0..raw.scores.len() {
            let score = raw.scores[i];
            if score.is_nan() || score < self.config.score_threshold {
                continue;
            }
            let Some(class) = self.classes.class(raw.labels[i]) else {
                continue;
            };
            let b = raw.boxes[i];
            if b.iter().any(|v| !v.is_finite()) {
                continue;
            }
            let bbox = [
                b[0] * scale_x,
                b[1] * scale_y,
                b[2] * scale_x,
                b[3] * scale_y,
            ];
            let mask = paste_mask(
                &raw.masks[i],
                bbox,
                frame.width,
                frame.height,
                self.config.mask_threshold,
            );
            if mask.area() == 0 {
                continue;
            }
            detections.push(Detection {
                frame: frame.index,
                class,
                score,
                bbox,
                mask,
                color: None,
            });
        }
        let detections = suppress_duplicates(detections);
        let times = StageTimes {
            preprocess_ms: (preprocessed - started).as_secs_f64() * 1e3,
            inference_ms: (inferred - preprocessed).as_secs_f64() * 1e3,
            postprocess_ms: inferred.elapsed().as_secs_f64() * 1e3,
        };
        Ok((detections, times))
    }
}

fn check_contract(session: &Session, path: &Path) -> Result<(), DetectorError> {
    let problem = |problem: String| DetectorError::Contract {
        path: path.to_path_buf(),
        problem,
    };
    let input = session
        .inputs()
        .iter()
        .find(|i| i.name() == INPUT_NAME)
        .ok_or_else(|| {
            let names: Vec<&str> = session
                .inputs()
                .iter()
                .map(ort::value::Outlet::name)
                .collect();
            problem(format!(
                "no input `{INPUT_NAME}` (inputs: {})",
                names.join(", ")
            ))
        })?;
    let input_ok = input.dtype().tensor_type() == Some(ort::value::TensorElementType::Float32)
        && input.dtype().tensor_shape().is_some_and(|s| s.len() == 3);
    if !input_ok {
        return Err(problem(format!(
            "input `{INPUT_NAME}` must be a float32 [3, H, W] tensor, found {}",
            input.dtype()
        )));
    }
    for name in OUTPUT_NAMES {
        if !session.outputs().iter().any(|o| o.name() == name) {
            return Err(problem(format!("no output `{name}`")));
        }
    }
    Ok(())
}

/// Scales a frame to `width × height` and returns it as CHW `f32` in `[0, 1]`. Downscaling by
/// whole factors is an exact box average rounded half up to bytes (so a 1080p frame gives the
/// same bytes as `scripts/perception`'s 4×4 average); other sizes are bilinear.
pub fn model_input(frame: &RgbFrame, width: u32, height: u32) -> Array3<f32> {
    let bytes = resize_rgb(frame, width, height);
    let (w, h) = (width as usize, height as usize);
    Array3::from_shape_fn((3, h, w), |(c, y, x)| {
        f32::from(bytes[(y * w + x) * 3 + c]) / 255.0
    })
}

/// RGB bytes of `frame` scaled to `width × height` (see [`model_input`]).
pub fn resize_rgb(frame: &RgbFrame, width: u32, height: u32) -> Vec<u8> {
    if frame.width == width && frame.height == height {
        return frame.rgb.clone();
    }
    let whole = frame.width.is_multiple_of(width)
        && frame.height.is_multiple_of(height)
        && frame.width >= width
        && frame.height >= height;
    if whole {
        let fx = (frame.width / width) as usize;
        let fy = (frame.height / height) as usize;
        let source_width = frame.width as usize;
        let count = (fx * fy) as u32;
        let mut out = Vec::with_capacity(width as usize * height as usize * 3);
        for y in 0..height as usize {
            for x in 0..width as usize {
                for c in 0..3 {
                    let mut sum = 0u32;
                    for dy in 0..fy {
                        let row = (y * fy + dy) * source_width;
                        for dx in 0..fx {
                            sum += u32::from(frame.rgb[(row + x * fx + dx) * 3 + c]);
                        }
                    }
                    // Round half up, in integers.
                    out.push(((2 * sum + count) / (2 * count)) as u8);
                }
            }
        }
        return out;
    }
    match image::RgbImage::from_raw(frame.width, frame.height, frame.rgb.clone()) {
        Some(image) => {
            image::imageops::resize(&image, width, height, image::imageops::FilterType::Triangle)
                .into_raw()
        }
        None => vec![0; width as usize * height as usize * 3],
    }
}

/// Pastes a raw `MASK_SIZE²` mask into a `width × height` image at `bbox` (image pixels) with
/// torchvision's `paste_masks_in_image(..., padding=1)` arithmetic, and thresholds it.
pub fn paste_mask(
    raw: &[f32],
    bbox: [f32; 4],
    width: u32,
    height: u32,
    threshold: f32,
) -> InstanceMask {
    const PADDED: usize = MASK_SIZE + 2;
    if raw.len() != MASK_SIZE * MASK_SIZE || width == 0 || height == 0 {
        return InstanceMask::empty();
    }
    // expand_masks: one pixel of zero padding on every side.
    let mut padded = [0f32; PADDED * PADDED];
    for y in 0..MASK_SIZE {
        for x in 0..MASK_SIZE {
            padded[(y + 1) * PADDED + x + 1] = raw[y * MASK_SIZE + x];
        }
    }
    // expand_boxes, in f32, then `.to(int64)` (truncation towards zero).
    let scale = (PADDED as f32) / (MASK_SIZE as f32);
    let w_half = (bbox[2] - bbox[0]) * 0.5 * scale;
    let h_half = (bbox[3] - bbox[1]) * 0.5 * scale;
    let x_center = (bbox[2] + bbox[0]) * 0.5;
    let y_center = (bbox[3] + bbox[1]) * 0.5;
    #[expect(
        clippy::cast_possible_truncation,
        reason = "torch's int64 cast truncates"
    )]
    let expanded = [
        (x_center - w_half) as i64,
        (y_center - h_half) as i64,
        (x_center + w_half) as i64,
        (y_center + h_half) as i64,
    ];
    // paste_mask_in_image.
    let box_width = (expanded[2] - expanded[0] + 1).max(1);
    let box_height = (expanded[3] - expanded[1] + 1).max(1);
    let x0 = expanded[0].max(0);
    let x1 = (expanded[2] + 1).min(i64::from(width));
    let y0 = expanded[1].max(0);
    let y1 = (expanded[3] + 1).min(i64::from(height));
    if x1 <= x0 || y1 <= y0 {
        return InstanceMask::empty();
    }
    let columns = bilinear_taps(PADDED, box_width as usize);
    let rows = bilinear_taps(PADDED, box_height as usize);
    let (out_width, out_height) = ((x1 - x0) as usize, (y1 - y0) as usize);
    let mut bits = Vec::with_capacity(out_width * out_height);
    for y in y0..y1 {
        let (r0, r1, ry) = rows[(y - expanded[1]) as usize];
        for x in x0..x1 {
            let (c0, c1, cx) = columns[(x - expanded[0]) as usize];
            let top = (1.0 - cx) * padded[r0 * PADDED + c0] + cx * padded[r0 * PADDED + c1];
            let bottom = (1.0 - cx) * padded[r1 * PADDED + c0] + cx * padded[r1 * PADDED + c1];
            let value = (1.0 - ry) * top + ry * bottom;
            bits.push(value >= threshold);
        }
    }
    InstanceMask::new(
        x0 as u32,
        y0 as u32,
        out_width as u32,
        out_height as u32,
        bits,
    )
    .unwrap_or_else(InstanceMask::empty)
}

/// PyTorch's `upsample_bilinear2d` source taps (`align_corners=False`): for each output index,
/// the two input indices and the weight of the second.
fn bilinear_taps(input: usize, output: usize) -> Vec<(usize, usize, f32)> {
    let scale = input as f32 / output as f32;
    (0..output)
        .map(|i| {
            let source = (scale * (i as f32 + 0.5) - 0.5).max(0.0);
            #[expect(
                clippy::cast_possible_truncation,
                reason = "source is non-negative and small"
            )]
            let first = (source as usize).min(input - 1);
            let second = if first < input - 1 { first + 1 } else { first };
            (first, second, source - first as f32)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_full_mask_pastes_to_its_box_widened_by_the_padding() {
        // A mask of ones over the box [10, 20, 38, 48) (28×28 pixels): torchvision widens the box
        // by 30/28 around its centre (24, 34): half sizes 15, so [9, 19] .. [39, 49], int64.
        let raw = vec![1.0; MASK_SIZE * MASK_SIZE];
        let mask = paste_mask(&raw, [10.0, 20.0, 38.0, 48.0], 100, 100, 0.5);
        let bounds = mask.bounds().expect("a non-empty mask");
        // The padding ring is zero; bilinear weights reach 0.5 half a source pixel (about 0.5
        // output pixels here) inside the padded edge, so the mask is the original box.
        assert_eq!(bounds, [10, 20, 39, 49]);
        assert!(mask.contains(24, 34));
    }

    #[test]
    fn pasting_clips_at_the_image_edge_and_rejects_bad_input() {
        let raw = vec![1.0; MASK_SIZE * MASK_SIZE];
        let mask = paste_mask(&raw, [-10.0, -10.0, 5.0, 5.0], 20, 20, 0.5);
        let bounds = mask.bounds().expect("a non-empty mask");
        assert_eq!(&bounds[..2], &[0, 0]);
        assert!(bounds[2] <= 20 && bounds[3] <= 20);
        assert_eq!(
            paste_mask(&raw[1..], [0.0, 0.0, 5.0, 5.0], 20, 20, 0.5).area(),
            0
        );
        assert_eq!(
            paste_mask(&raw, [30.0, 30.0, 40.0, 40.0], 20, 20, 0.5).area(),
            0
        );
    }

    #[test]
    fn whole_factor_downscaling_is_a_rounded_box_average() {
        let frame = RgbFrame {
            index: 0,
            width: 4,
            height: 2,
            rgb: vec![
                0, 0, 0, 1, 1, 1, 10, 20, 30, 10, 20, 30, //
                0, 0, 0, 0, 0, 0, 10, 20, 30, 10, 20, 31,
            ],
        };
        // Left 2×2: (0+1+0+0)/4 = 0.25 → 0; right: blue (30·3+31)/4 = 30.25 → 30.
        assert_eq!(resize_rgb(&frame, 2, 1), vec![0, 0, 0, 10, 20, 30]);
        let input = model_input(&frame, 2, 1);
        assert_eq!(input.shape(), &[3, 1, 2]);
        assert!((input[[2, 0, 1]] - 30.0 / 255.0).abs() < 1e-7);
    }
}
