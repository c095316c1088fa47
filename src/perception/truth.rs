//! Ground-truth instance masks from a segmentation frame: each pixel belongs to the instance whose
//! painted colour is nearest, if it is within a tolerance (the release's segmentation videos are
//! lossy mp4s, so colours arrive blurred; PNG folders are exact).
//!
//! Input: a segmentation [`RgbFrame`] and the `(instance id, colour)` pairs painted in it.
//! Output: one [`InstanceMask`] per instance that has pixels, in the order given.

use super::detection::InstanceMask;
use super::frames::RgbFrame;

/// Colour distance (Euclidean, in bytes) within which a blurred mp4 pixel still counts as its
/// instance's colour. Unity's instance colours are at least ~100 apart.
pub const MP4_TOLERANCE: u32 = 60;

/// The masks of `painted` instances in `segmentation`.
pub fn painted_masks(
    segmentation: &RgbFrame,
    painted: &[(u32, [u8; 3])],
    tolerance: u32,
) -> Vec<(u32, InstanceMask)> {
    let (width, height) = (segmentation.width, segmentation.height);
    let limit = tolerance * tolerance;
    // The nearest painted colour of every pixel (u16::MAX: background).
    let mut owner = vec![u16::MAX; width as usize * height as usize];
    for (at, pixel) in segmentation.rgb.chunks_exact(3).enumerate() {
        let mut best = (u32::MAX, u16::MAX);
        for (index, (_, color)) in painted.iter().enumerate() {
            let distance: u32 = (0..3)
                .map(|c| {
                    let d = i32::from(pixel[c]) - i32::from(color[c]);
                    d.unsigned_abs() * d.unsigned_abs()
                })
                .sum();
            if distance < best.0 {
                best = (distance, u16::try_from(index).unwrap_or(u16::MAX));
            }
        }
        if best.0 <= limit && at < owner.len() {
            owner[at] = best.1;
        }
    }
    painted
        .iter()
        .enumerate()
        .filter_map(|(index, (id, _))| {
            let index = u16::try_from(index).ok()?;
            let mask = InstanceMask::from_predicate(width, height, |x, y| {
                owner[y as usize * width as usize + x as usize] == index
            });
            (mask.area() > 0).then_some((*id, mask))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blurred_colours_go_to_the_nearest_instance_within_the_tolerance() {
        // Three pixels: near red, near blue, and grey far from both.
        let frame = RgbFrame {
            index: 0,
            width: 3,
            height: 1,
            rgb: vec![240, 10, 5, 10, 70, 250, 128, 128, 128],
        };
        let masks = painted_masks(&frame, &[(1, [255, 0, 0]), (2, [0, 74, 255])], 60);
        assert_eq!(masks.len(), 2);
        assert_eq!(masks[0].0, 1);
        assert!(masks[0].1.contains(0, 0) && masks[0].1.area() == 1);
        assert!(masks[1].1.contains(1, 0) && masks[1].1.area() == 1);
    }
}
