//! The frames perception read, kept for the run viewer (`view`): each with its detections drawn
//! (`perception::overlay`), as a JPEG, and listed with what each detection is.
//!
//! Input: a folder (`RUN/frames/<scenario>/<video>/`), the model's classes and frames with their
//! detections. Output: `<frame>.jpg` (at most [`OVERLAY_WIDTH`] wide) and `detections.json`
//! (`frames`: per frame its number, image and detections: class, colour word, score, box in
//! frame pixels, outline colour), merged with what the folder lists already, in frame order.

use std::collections::BTreeMap;
use std::path::Path;

use image::ImageEncoder as _;
use serde_json::{Value, json};

use crate::perception::classes::ClassTable;
use crate::perception::detection::Detection;
use crate::perception::frames::RgbFrame;
use crate::perception::overlay::{class_colour, draw_detections};
use crate::perception::palette::palette_color;
use crate::util::write_atomic;

/// Width of the frames written for the viewer, pixels.
const OVERLAY_WIDTH: u32 = 480;
/// Their JPEG quality: about 26 kB a frame of the real video, where PNG takes 260 kB.
const OVERLAY_QUALITY: u8 = 80;

/// Writes `frames` with their detections drawn into `dir` and adds them to its listing.
pub(crate) fn write_overlays(
    dir: &Path,
    table: Option<&ClassTable>,
    frames: &[(&RgbFrame, &[Detection])],
) -> Result<(), String> {
    let listing = dir.join("detections.json");
    // What the folder lists already (a first pass before this full pass), by frame.
    let mut listed: BTreeMap<u64, Value> = fs_err::read(&listing)
        .ok()
        .and_then(|bytes| serde_json::from_slice::<Value>(&bytes).ok())
        .and_then(|value| value.get("frames").and_then(Value::as_array).cloned())
        .unwrap_or_default()
        .into_iter()
        .filter_map(|frame| Some((frame.get("frame")?.as_u64()?, frame)))
        .collect();
    for (frame, detections) in frames {
        let image = draw_detections(frame, detections, OVERLAY_WIDTH);
        let mut jpeg = Vec::new();
        image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, OVERLAY_QUALITY)
            .write_image(
                image.as_raw(),
                image.width(),
                image.height(),
                image::ExtendedColorType::Rgb8,
            )
            .map_err(|e| e.to_string())?;
        let file = format!("{:04}.jpg", frame.index);
        write_atomic(&dir.join(&file), &jpeg).map_err(|e| e.to_string())?;
        let described: Vec<Value> = detections
            .iter()
            .map(|detection| {
                let [r, g, b] = class_colour(detection.class.label());
                json!({
                    "class": table.map_or("?", |table| table.name(detection.class)),
                    "color": detection.color.and_then(palette_color).map(|c| c.word),
                    "score": (f64::from(detection.score) * 1000.0).round() / 1000.0,
                    "box": detection.bbox.map(|v| (f64::from(v) * 10.0).round() / 10.0),
                    "outline": format!("#{r:02x}{g:02x}{b:02x}"),
                })
            })
            .collect();
        listed.insert(
            frame.index as u64,
            json!({"frame": frame.index, "image": file, "detections": described}),
        );
    }
    let frames: Vec<Value> = listed.into_values().collect();
    let text =
        serde_json::to_string_pretty(&json!({ "frames": frames })).map_err(|e| e.to_string())?;
    write_atomic(&listing, text.as_bytes()).map_err(|e| e.to_string())
}
