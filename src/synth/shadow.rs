//! Soft drop shadows on the wall: the release's renderer lights the scene with a shadow-casting
//! lamp, so every object darkens the plaster just beside it, and a detector trained without
//! shadows takes a shadow's edge for the object's edge.
//!
//! Input: a rendered [`Frame`] (its depth buffer says which pixels show an object) and a
//! [`Shadow`]. Output: the frame's RGB with wall pixels darkened where the objects' silhouette,
//! shifted by the shadow's offset and blurred, falls. Objects themselves, the instance image
//! and every annotation are untouched. The objects lie against the wall, so a screen-space
//! shift is a close enough stand-in for casting: the shadow keeps the silhouette's shape.

use super::raster::{Frame, linear_to_srgb_byte, srgb_to_linear};

/// A drop shadow, sized relative to the image height so that one setting fits every resolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shadow {
    /// Shift of the shadow from its object, image heights (x right, y down).
    pub offset: [f64; 2],
    /// Half-width of the penumbra, image heights.
    pub blur: f64,
    /// Share of the light the shadow's core takes away, in `[0, 1]` (0: no shadow).
    pub strength: f64,
}

/// The release's look: a lamp above and to the left, shadows down and to the right.
pub const RELEASE_SHADOW: Shadow = Shadow {
    offset: [0.006, 0.010],
    blur: 0.004,
    strength: 0.5,
};

impl Shadow {
    /// Darkens the wall pixels of `frame` (those where nothing was drawn) in place.
    pub fn apply(&self, frame: &mut Frame) {
        let (width, height) = (frame.width as usize, frame.height as usize);
        let pixels = width * height;
        if self.strength <= 0.0
            || frame.rgb.len() != pixels * 3
            || frame.inverse_depth.len() != pixels
        {
            return;
        }
        let scale = height as f64;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "offsets and radii of a few pixels, rounded; the radius clamped at 0"
        )]
        let (shift_x, shift_y, radius) = (
            (self.offset[0] * scale).round() as isize,
            (self.offset[1] * scale).round() as isize,
            (self.blur * scale).round().max(0.0) as usize,
        );
        // The silhouette, shifted: a wall pixel is shaded by the object up and to the left.
        let mut cover = vec![0.0_f32; pixels];
        for y in 0..height {
            for x in 0..width {
                let source_x = x.checked_add_signed(-shift_x).filter(|&s| s < width);
                let source_y = y.checked_add_signed(-shift_y).filter(|&s| s < height);
                if let (Some(sx), Some(sy)) = (source_x, source_y)
                    && frame.inverse_depth[sy * width + sx] > 0.0
                {
                    cover[y * width + x] = 1.0;
                }
            }
        }
        // Two box passes each way approximate a Gaussian penumbra.
        let mut scratch = BlurScratch::default();
        for _ in 0..2 {
            box_blur_rows(&mut cover, width, height, radius, &mut scratch);
            box_blur_columns(&mut cover, width, height, radius, &mut scratch);
        }
        let linear: Vec<f64> = (0..=255_u8)
            .map(|byte| srgb_to_linear(f64::from(byte) / 255.0))
            .collect();
        for (index, &shade) in cover.iter().enumerate() {
            if shade <= 0.0 || frame.inverse_depth[index] > 0.0 {
                continue;
            }
            let factor = 1.0 - self.strength.min(1.0) * f64::from(shade);
            for channel in 0..3 {
                let at = index * 3 + channel;
                frame.rgb[at] = linear_to_srgb_byte(linear[usize::from(frame.rgb[at])] * factor);
            }
        }
    }
}

/// Buffers of the box filter, kept across lines and passes (a frame has thousands of lines).
#[derive(Default)]
struct BlurScratch {
    line: Vec<f32>,
    blurred: Vec<f32>,
    prefix: Vec<f64>,
}

/// A running-sum box filter of half-width `radius` along each row (edges clamp the window).
fn box_blur_rows(
    values: &mut [f32],
    width: usize,
    height: usize,
    radius: usize,
    scratch: &mut BlurScratch,
) {
    if radius == 0 {
        return;
    }
    for row in values.chunks_exact_mut(width).take(height) {
        scratch.line.clear();
        scratch.line.extend_from_slice(row);
        blur_line(&scratch.line, row, radius, &mut scratch.prefix);
    }
}

/// The same filter down each column.
fn box_blur_columns(
    values: &mut [f32],
    width: usize,
    height: usize,
    radius: usize,
    scratch: &mut BlurScratch,
) {
    if radius == 0 {
        return;
    }
    scratch.blurred.resize(height, 0.0);
    for x in 0..width {
        scratch.line.clear();
        scratch
            .line
            .extend((0..height).map(|y| values[y * width + x]));
        blur_line(
            &scratch.line,
            &mut scratch.blurred,
            radius,
            &mut scratch.prefix,
        );
        for (y, value) in scratch.blurred.iter().enumerate() {
            values[y * width + x] = *value;
        }
    }
}

/// Mean of `input` over `[i − radius, i + radius]` (clipped to the line) into `output`;
/// `prefix` holds the running sums.
fn blur_line(input: &[f32], output: &mut [f32], radius: usize, prefix: &mut Vec<f64>) {
    prefix.clear();
    prefix.push(0.0);
    let mut total = 0.0_f64;
    for &value in input {
        total += f64::from(value);
        prefix.push(total);
    }
    for (index, slot) in output.iter_mut().enumerate() {
        let low = index.saturating_sub(radius);
        let high = (index + radius + 1).min(input.len());
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_precision_loss,
            reason = "a mean of values in [0, 1] over a short window"
        )]
        let mean = ((prefix[high] - prefix[low]) / (high - low) as f64) as f32;
        *slot = mean;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 40×20 grey frame with a 6×6 object at x, y ∈ [10, 16).
    fn frame() -> Frame {
        let (width, height) = (40_u32, 20_u32);
        let pixels = (width * height) as usize;
        let mut frame = Frame {
            width,
            height,
            rgb: vec![200; pixels * 3],
            instance: vec![0; pixels],
            inverse_depth: vec![0.0; pixels],
        };
        for y in 10..16 {
            for x in 10..16 {
                frame.inverse_depth[y * 40 + x] = 0.1;
                frame.instance[y * 40 + x] = 1;
                frame.rgb[(y * 40 + x) * 3] = 50;
            }
        }
        frame
    }

    #[test]
    fn the_shadow_falls_beside_the_object_on_the_wall_only() {
        let mut shaded = frame();
        // Two pixels right and down at height 20, no penumbra, full strength.
        Shadow {
            offset: [0.1, 0.1],
            blur: 0.0,
            strength: 1.0,
        }
        .apply(&mut shaded);
        let red = |f: &Frame, x: usize, y: usize| f.rgb[(y * 40 + x) * 3];
        // The object keeps its colour; the wall under the shifted silhouette goes black.
        assert_eq!(red(&shaded, 12, 12), 50);
        assert_eq!(red(&shaded, 17, 17), 0);
        // Up and to the left of the object, and far away, the wall is untouched.
        assert_eq!(red(&shaded, 9, 9), 200);
        assert_eq!(red(&shaded, 30, 5), 200);
        assert_eq!(shaded.instance, frame().instance);
    }

    #[test]
    fn a_penumbra_fades_and_a_zero_strength_shadow_changes_nothing() {
        let mut soft = frame();
        Shadow {
            offset: [0.1, 0.1],
            blur: 0.1,
            strength: 0.5,
        }
        .apply(&mut soft);
        let red = |f: &Frame, x: usize, y: usize| f.rgb[(y * 40 + x) * 3];
        let (core, edge, beyond) = (red(&soft, 17, 17), red(&soft, 19, 19), red(&soft, 24, 19));
        assert!(core < edge && edge < beyond, "{core} {edge} {beyond}");
        assert_eq!(beyond, 200);
        let mut none = frame();
        Shadow {
            strength: 0.0,
            ..RELEASE_SHADOW
        }
        .apply(&mut none);
        assert_eq!(none, frame());
    }
}
