//! Perception: what the pixels of a video say, independent of questions, Python or LLMs.
//!
//! Input: video files (mp4 through `ffmpeg`, or PNG folders) and camera records. Output: frames
//! as RGB pixel buffers, detections and tracks, and the geometry that ties world points to
//! pixels. Layer 1 (`docs/architecture.md`): uses only `util`.
//!
//! Each scenario brings its detector classes and default model files
//! ([`ScenarioPerception`], `perception/<scenario>/`); the rest is shared.
//!
//! * [`camera`]: the release's Unity camera (projection, capture records).
//! * [`frames`]: decoding only the frames asked for, from an mp4 or a PNG folder.
//! * [`palette`]: the release's object colours and Unity's instance-segmentation colours.
//! * [`classes`]: a model's classes (from its description file) as a scenario reads them.
//! * [`detection`]: instance masks and detections.
//! * [`color`]: palette colour words from masked pixels, relative to the wall.
//! * [`truth`]: ground-truth instance masks from segmentation frames.
//! * [`runtime`]: finding and loading the ONNX Runtime library (`ort`, `load-dynamic`).
//! * [`detector`]: the Mask R-CNN ONNX model: preprocessing, inference, mask pasting.
//! * [`assignment`]: optimal one-to-one matching (the Hungarian method).
//! * [`overlay`]: detections drawn on their frame (masks tinted, boxes outlined) for the viewer.
//! * [`tracking`]: linking detections across frames into tracks with stable ids.
//! * [`closer`]: a track's class decided again on windows of the frame at twice the scale.
//! * [`distinct`]: distinct colours for the tracks of a class whose objects never share one.
//! * [`silhouette`]: convex solids' silhouettes against masks (IoU), and the pattern search that
//!   fits them.
//! * [`evaluation`]: perception metrics against ground truth (mask and box AP, attribute
//!   accuracy, identity switches).

pub mod assignment;
pub mod ball;
pub mod camera;
pub mod classes;
pub mod closer;
pub mod cloth;
pub mod color;
pub mod detection;
pub mod detector;
pub mod distinct;
pub mod evaluation;
pub mod fluid;
pub mod frames;
pub mod overlay;
pub mod palette;
pub mod rope;
pub mod runtime;
pub mod silhouette;
pub mod tracking;
pub mod truth;

/// What a scenario's perception brings: its detector classes and its default model files
/// (relative to the repository root).
#[derive(Debug, Clone, Copy)]
pub struct ScenarioPerception {
    /// The classes its objects fall into.
    pub classes: classes::ScenarioClasses,
    /// The default Mask R-CNN model (its description is the `.json` beside it).
    pub detector: &'static str,
    /// The default colour model.
    pub colors: &'static str,
}
