//! What the detector says about one frame: instance masks and detections (their classes are
//! `classes`).
//!
//! Input: the model's label ids, boxes and pasted masks (from [`super::detector`]), or the
//! release's object names and segmentation frames (ground truth for evaluation). Output: plain
//! values that tracking, evaluation and the scene API share. Pixel coordinates are those of the
//! frame the mask was made for (x right, y down, origin at the top-left corner).

use super::classes::Class;

/// A binary instance mask stored over its bounding rectangle in frame pixels.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InstanceMask {
    left: u32,
    top: u32,
    width: u32,
    height: u32,
    /// Row-major, `width × height`.
    bits: Vec<bool>,
}

impl InstanceMask {
    /// A mask over the rectangle at `(left, top)` of `width × height` pixels; `None` when `bits`
    /// has the wrong length.
    pub fn new(left: u32, top: u32, width: u32, height: u32, bits: Vec<bool>) -> Option<Self> {
        (bits.len() == width as usize * height as usize).then_some(InstanceMask {
            left,
            top,
            width,
            height,
            bits,
        })
    }

    /// An empty mask (no pixels).
    pub fn empty() -> Self {
        InstanceMask {
            left: 0,
            top: 0,
            width: 0,
            height: 0,
            bits: Vec::new(),
        }
    }

    /// The mask of the pixels of a full `width × height` frame for which `inside(x, y)` holds,
    /// cropped to their bounding rectangle.
    pub fn from_predicate(width: u32, height: u32, inside: impl Fn(u32, u32) -> bool) -> Self {
        let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
        for y in 0..height {
            for x in 0..width {
                if inside(x, y) {
                    x0 = x0.min(x);
                    y0 = y0.min(y);
                    x1 = x1.max(x + 1);
                    y1 = y1.max(y + 1);
                }
            }
        }
        if x0 == u32::MAX {
            return InstanceMask::empty();
        }
        let (w, h) = (x1 - x0, y1 - y0);
        let mut bits = Vec::with_capacity(w as usize * h as usize);
        for y in y0..y1 {
            for x in x0..x1 {
                bits.push(inside(x, y));
            }
        }
        InstanceMask {
            left: x0,
            top: y0,
            width: w,
            height: h,
            bits,
        }
    }

    /// The rectangle `(left, top, width, height)` the mask is stored over.
    pub fn rectangle(&self) -> (u32, u32, u32, u32) {
        (self.left, self.top, self.width, self.height)
    }

    /// Whether frame pixel `(x, y)` is in the mask.
    pub fn contains(&self, x: u32, y: u32) -> bool {
        if x < self.left || y < self.top {
            return false;
        }
        let (dx, dy) = (x - self.left, y - self.top);
        if dx >= self.width || dy >= self.height {
            return false;
        }
        self.bits[dy as usize * self.width as usize + dx as usize]
    }

    /// The frame pixels in the mask, row by row.
    pub fn pixels(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        let width = self.width.max(1);
        (self.top..self.top + self.height)
            .flat_map(move |y| (self.left..self.left + width).map(move |x| (x, y)))
            .zip(self.bits.iter())
            .filter(|(_, inside)| **inside)
            .map(|(pixel, _)| pixel)
    }

    /// Number of pixels in the mask.
    pub fn area(&self) -> u64 {
        self.bits.iter().filter(|b| **b).count() as u64
    }

    /// Pixels in both masks.
    pub fn intersection(&self, other: &InstanceMask) -> u64 {
        let x0 = self.left.max(other.left);
        let y0 = self.top.max(other.top);
        let x1 = (self.left + self.width).min(other.left + other.width);
        let y1 = (self.top + self.height).min(other.top + other.height);
        let mut count = 0;
        for y in y0..y1.max(y0) {
            for x in x0..x1.max(x0) {
                if self.contains(x, y) && other.contains(x, y) {
                    count += 1;
                }
            }
        }
        count
    }

    /// Intersection over union; 0 when both are empty.
    pub fn iou(&self, other: &InstanceMask) -> f64 {
        let intersection = self.intersection(other);
        let union = self.area() + other.area() - intersection;
        if union == 0 {
            0.0
        } else {
            intersection as f64 / union as f64
        }
    }

    /// The tight bounding box `[x0, y0, x1, y1)` of the set pixels; `None` when empty.
    pub fn bounds(&self) -> Option<[u32; 4]> {
        let mut result: Option<[u32; 4]> = None;
        for (x, y) in self.pixels() {
            let b = result.get_or_insert([x, y, x + 1, y + 1]);
            b[0] = b[0].min(x);
            b[1] = b[1].min(y);
            b[2] = b[2].max(x + 1);
            b[3] = b[3].max(y + 1);
        }
        result
    }

    /// The mean pixel position (pixel centres at `+0.5`); `None` when empty.
    pub fn centroid(&self) -> Option<[f64; 2]> {
        let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
        for (x, y) in self.pixels() {
            sx += f64::from(x) + 0.5;
            sy += f64::from(y) + 0.5;
            n += 1.0;
        }
        (n > 0.0).then(|| [sx / n, sy / n])
    }
}

/// One object found in one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Detection {
    /// 0-based frame index in the video.
    pub frame: usize,
    /// The detector's class.
    pub class: Class,
    /// The detector's confidence in `[0, 1]`.
    pub score: f32,
    /// The detector's box `[x0, y0, x1, y1]` in frame pixels.
    pub bbox: [f32; 4],
    /// The pasted, thresholded mask in frame pixels.
    pub mask: InstanceMask,
    /// The palette id of its colour (`perception::palette`), from the masked pixels; `None`
    /// when no palette colour is close.
    pub color: Option<u8>,
}

/// IoU of two `[x0, y0, x1, y1]` boxes; 0 for empty, inverted or non-finite ones.
pub fn box_iou(a: [f64; 4], b: [f64; 4]) -> f64 {
    let area = |r: [f64; 4]| (r[2] - r[0]).max(0.0) * (r[3] - r[1]).max(0.0);
    if !a.iter().chain(&b).all(|v| v.is_finite()) {
        return 0.0;
    }
    let inner = [
        a[0].max(b[0]),
        a[1].max(b[1]),
        a[2].min(b[2]),
        a[3].min(b[3]),
    ];
    let intersection = area(inner);
    let union = area(a) + area(b) - intersection;
    if union > 0.0 {
        intersection / union
    } else {
        0.0
    }
}

/// Mask overlap (intersection over union) above which two detections are one object whatever
/// their classes: the model's NMS is per class, so one pulley can come out as a solid and as a
/// hollow one, or a cube also as a sphere.
pub const DUPLICATE_MASK_IOU: f64 = 0.5;

/// Share of a detection's mask inside a surer detection of the same class above which it is a
/// fragment of that one (a piece of a rope found beside the whole rope).
pub const FRAGMENT_SHARE: f64 = 0.8;

/// Class-agnostic duplicate suppression: detections in descending score (ties: the earlier
/// first), each dropped when its mask overlaps a kept one by [`DUPLICATE_MASK_IOU`], or lies
/// [`FRAGMENT_SHARE`] inside a kept one of its own class. Masks of different classes may nest
/// (a coarse rope band round a small fixed point) without either being dropped.
pub fn suppress_duplicates(mut detections: Vec<Detection>) -> Vec<Detection> {
    // A stable sort keeps the model's order among equal scores.
    detections.sort_by(|a, b| b.score.total_cmp(&a.score));
    let mut kept: Vec<Detection> = Vec::with_capacity(detections.len());
    for detection in detections {
        let area = detection.mask.area();
        let duplicate = kept.iter().any(|surer| {
            let shared = surer.mask.intersection(&detection.mask);
            let union = surer.mask.area() + area - shared;
            let iou = if union == 0 {
                0.0
            } else {
                shared as f64 / union as f64
            };
            iou >= DUPLICATE_MASK_IOU
                || (surer.class == detection.class
                    && area > 0
                    && shared as f64 >= FRAGMENT_SHARE * area as f64)
        });
        if !duplicate {
            kept.push(detection);
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_overlap_is_intersection_over_union() {
        assert!((box_iou([0.0, 0.0, 2.0, 2.0], [1.0, 0.0, 3.0, 2.0]) - 1.0 / 3.0).abs() < 1e-12);
        assert!(box_iou([0.0, 0.0, 1.0, 1.0], [2.0, 2.0, 3.0, 3.0]).abs() < 1e-12);
    }

    fn detection(class: &str, score: f32, mask: InstanceMask) -> Detection {
        Detection {
            frame: 0,
            class: crate::perception::rope::test_class(class),
            score,
            bbox: [0.0; 4],
            mask,
            color: None,
        }
    }

    fn block(x: std::ops::Range<u32>, y: std::ops::Range<u32>) -> InstanceMask {
        InstanceMask::from_predicate(40, 40, move |px, py| x.contains(&px) && y.contains(&py))
    }

    #[test]
    fn duplicates_are_suppressed_across_classes_and_fragments_within_one() {
        let detections = vec![
            // A pulley read as class 5 (0.6) and, surer, as class 6 (0.9): one object.
            detection("solid static pulley", 0.6, block(10..20, 10..20)),
            detection("hollow static pulley", 0.9, block(11..20, 10..20)),
            // A rope (class 3) and a piece of it, also class 3, found on its own: a fragment.
            detection("rope", 0.8, block(0..2, 0..40)),
            detection("rope", 0.4, block(0..2, 30..40)),
            // A small fixed point (class 4) inside the rope's band: another class, kept.
            detection("fixed point", 0.3, block(0..1, 0..2)),
            // A second, separate pulley: kept.
            detection("solid static pulley", 0.5, block(25..35, 25..35)),
        ];
        let kept: Vec<(u16, f32)> = suppress_duplicates(detections)
            .iter()
            .map(|d| (d.class.label(), d.score))
            .collect();
        // Labels of the rope model: 6 hollow static pulley, 3 rope, 5 solid static, 4 fixed point.
        assert_eq!(kept, vec![(6, 0.9), (3, 0.8), (5, 0.5), (4, 0.3)]);
    }

    #[test]
    fn masks_measure_area_overlap_bounds_and_centroid() {
        // A 4×2 block at (2, 3) and a 2×2 block at (4, 3) in a 10×10 frame.
        let a =
            InstanceMask::from_predicate(10, 10, |x, y| (2..6).contains(&x) && (3..5).contains(&y));
        let b =
            InstanceMask::from_predicate(10, 10, |x, y| (4..6).contains(&x) && (3..5).contains(&y));
        assert_eq!(a.rectangle(), (2, 3, 4, 2));
        assert_eq!(a.area(), 8);
        assert_eq!(a.intersection(&b), 4);
        assert!((a.iou(&b) - 0.5).abs() < 1e-12);
        assert_eq!(a.bounds(), Some([2, 3, 6, 5]));
        assert_eq!(a.centroid(), Some([4.0, 4.0]));
        assert!(a.contains(5, 4) && !a.contains(6, 4) && !a.contains(1, 3));
        let empty = InstanceMask::empty();
        assert_eq!(empty.area(), 0);
        assert!(empty.iou(&empty).abs() < f64::MIN_POSITIVE);
        assert_eq!(empty.bounds(), None);
        assert!(InstanceMask::new(0, 0, 2, 2, vec![true; 3]).is_none());
    }
}
