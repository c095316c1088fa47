//! What the detector saw, drawn on the frame: each detection's mask tinted and its box outlined
//! in its class's colour, scaled down for the run viewer (`view`).
//!
//! Input: a frame and its detections. Output: an RGB image no wider than asked, deterministic
//! for the same inputs (no text is drawn: the viewer lists each detection's class, colour and
//! score beside the image, in the colour of its outline).

use image::{Rgb, RgbImage, imageops};

use super::detection::Detection;
use super::frames::RgbFrame;

/// Outline and tint colours, by class label (cycled): distinct on the release's grey walls.
const CLASS_COLOURS: [[u8; 3]; 8] = [
    [230, 25, 75],
    [60, 180, 75],
    [0, 130, 200],
    [245, 130, 48],
    [145, 30, 180],
    [70, 240, 240],
    [240, 50, 230],
    [210, 245, 60],
];

/// Share of the class colour in a tinted mask pixel.
const TINT: f32 = 0.45;

/// The outline and tint colour of class label `label`.
pub fn class_colour(label: u16) -> [u8; 3] {
    CLASS_COLOURS[usize::from(label) % CLASS_COLOURS.len()]
}

/// `frame` with `detections` drawn on it (masks tinted, boxes outlined two pixels wide in the
/// result), then
/// scaled to at most `max_width` pixels wide (the aspect kept; never scaled up).
pub fn draw_detections(frame: &RgbFrame, detections: &[Detection], max_width: u32) -> RgbImage {
    // Two pixels wide once scaled down.
    let thickness = if max_width > 0 && frame.width > max_width {
        (2 * frame.width).div_ceil(max_width)
    } else {
        2
    };
    let mut image = RgbImage::from_fn(frame.width, frame.height, |x, y| {
        Rgb(frame.pixel(x, y).unwrap_or([0, 0, 0]))
    });
    for detection in detections {
        let colour = class_colour(detection.class.label());
        for (x, y) in detection.mask.pixels() {
            if let Some(pixel) = image.get_pixel_mut_checked(x, y) {
                for (channel, tint) in pixel.0.iter_mut().zip(colour) {
                    *channel = blend(*channel, tint);
                }
            }
        }
        outline(&mut image, detection.bbox, colour, thickness);
    }
    if frame.width > max_width && max_width > 0 {
        let height =
            (u64::from(frame.height) * u64::from(max_width) / u64::from(frame.width)).max(1);
        let height = u32::try_from(height).unwrap_or(u32::MAX);
        image = imageops::resize(&image, max_width, height, imageops::FilterType::Triangle);
    }
    image
}

fn blend(base: u8, tint: u8) -> u8 {
    let mixed = f32::from(base) * (1.0 - TINT) + f32::from(tint) * TINT;
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a mix of two bytes lies in 0..=255"
    )]
    let byte = mixed.round().clamp(0.0, 255.0) as u8;
    byte
}

/// Draws the box `[x0, y0, x1, y1]` (frame pixels, clipped to the image), its edges
/// `thickness` pixels wide inwards.
fn outline(image: &mut RgbImage, bbox: [f32; 4], colour: [u8; 3], thickness: u32) {
    let (width, height) = image.dimensions();
    if width == 0 || height == 0 || bbox.iter().any(|v| !v.is_finite()) {
        return;
    }
    let clip = |value: f32, limit: u32| -> u32 {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "clamped to the image first"
        )]
        let pixel = value.floor().clamp(0.0, (limit - 1) as f32) as u32;
        pixel
    };
    let (x0, y0) = (clip(bbox[0], width), clip(bbox[1], height));
    let (x1, y1) = (
        clip(bbox[2] - 1.0, width).max(x0),
        clip(bbox[3] - 1.0, height).max(y0),
    );
    for y in y0..=y1 {
        for x in x0..=x1 {
            let on_edge = x < x0 + thickness
                || x + thickness > x1
                || y < y0 + thickness
                || y + thickness > y1;
            if on_edge {
                image.put_pixel(x, y, Rgb(colour));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::classes::Class;
    use crate::perception::detection::InstanceMask;

    #[test]
    fn masks_are_tinted_boxes_outlined_and_the_rest_left_alone() {
        let frame = RgbFrame {
            index: 0,
            width: 40,
            height: 20,
            rgb: vec![100; 40 * 20 * 3],
        };
        let mask = InstanceMask::new(10, 5, 4, 4, vec![true; 16]).unwrap();
        let detection = Detection {
            frame: 0,
            class: Class::for_tests(2),
            score: 0.9,
            bbox: [8.0, 3.0, 16.0, 11.0],
            mask,
            color: None,
        };
        let image = draw_detections(&frame, &[detection], 100);
        let colour = class_colour(2);
        assert_eq!(image.dimensions(), (40, 20));
        // Inside the mask, away from the outline: 55% grey, 45% class colour.
        let tinted = colour.map(|c| blend(100, c));
        assert_eq!(image.get_pixel(12, 7).0, tinted);
        // The box's corners and edges, two pixels wide.
        assert_eq!(image.get_pixel(8, 3).0, colour);
        assert_eq!(image.get_pixel(15, 10).0, colour);
        assert_eq!(image.get_pixel(9, 6).0, colour);
        // Outside: untouched.
        assert_eq!(image.get_pixel(30, 15).0, [100, 100, 100]);
        assert_eq!(image.get_pixel(7, 3).0, [100, 100, 100]);
        // Scaled to half the width, the aspect kept.
        let small = draw_detections(&frame, &[], 20);
        assert_eq!(small.dimensions(), (20, 10));
    }
}
