//! Ground-truth instance masks from a segmentation frame: each pixel belongs to the instance whose
//! painted colour is nearest, if it is within a tolerance (the release's segmentation videos are
//! lossy mp4s, so colours arrive blurred; PNG folders are exact).
//!
//! Input: a segmentation [`RgbFrame`] and the `(instance id, colour)` pairs painted in it.
//! Output: one [`InstanceMask`] per instance that has pixels, in the order given; the
//! connected [`pieces`] of a mask, for objects the detector finds piece by piece.

use super::classes::{Class, ClassTable};
use super::detection::InstanceMask;
use super::evaluation::TruthInstance;
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
    let boxed: Vec<(u32, [u8; 3], Option<[f64; 4]>)> = painted
        .iter()
        .map(|(id, color)| (*id, *color, None))
        .collect();
    boxed_masks(segmentation, &boxed, tolerance)
}

/// An instance id, its colour and, when known, the box its pixels lie in.
type BoxedInstance = (u32, [u8; 3], Option<[f64; 4]>);

/// The masks of `painted` instances in `segmentation`, a pixel going to the nearest colour
/// among the instances whose box (when given) holds the pixel's centre.
fn boxed_masks(
    segmentation: &RgbFrame,
    painted: &[BoxedInstance],
    tolerance: u32,
) -> Vec<(u32, InstanceMask)> {
    let (width, height) = (segmentation.width, segmentation.height);
    let limit = tolerance * tolerance;
    let holds = |bbox: &Option<[f64; 4]>, at: usize| {
        bbox.is_none_or(|[x0, y0, x1, y1]| {
            let (x, y) = (at % width as usize, at / width as usize);
            let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
            cx >= x0 && cx <= x1 && cy >= y0 && cy <= y1
        })
    };
    // The nearest painted colour of every pixel (u16::MAX: background).
    let mut owner = vec![u16::MAX; width as usize * height as usize];
    for (at, pixel) in segmentation.rgb.chunks_exact(3).enumerate() {
        let mut best = (u32::MAX, u16::MAX);
        for (index, (_, color, bbox)) in painted.iter().enumerate() {
            let distance: u32 = (0..3)
                .map(|c| {
                    let d = i32::from(pixel[c]) - i32::from(color[c]);
                    d.unsigned_abs() * d.unsigned_abs()
                })
                .sum();
            if distance < best.0 && holds(bbox, at) {
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
        .filter_map(|(index, (id, _, _))| {
            let index = u16::try_from(index).ok()?;
            let mask = InstanceMask::from_predicate(width, height, |x, y| {
                owner[y as usize * width as usize + x as usize] == index
            });
            (mask.area() > 0).then_some((*id, mask))
        })
        .collect()
}

/// A truth object's instances gathered so far.
struct GroupedObject {
    name: String,
    /// Its first instance's id, which numbers it.
    instance_id: u32,
    class: Class,
    color: Option<u8>,
    masks: Vec<InstanceMask>,
}

/// An instance painted in a segmentation frame.
#[derive(Debug, Clone, Copy)]
pub struct Painted<'a> {
    /// Its instance id.
    pub id: u32,
    /// Its segmentation colour.
    pub color: [u8; 3],
    /// Its release object name.
    pub name: &'a str,
    /// Its annotated box `[x0, y0, x1, y1]` (pixels), when recorded: only pixels inside it can
    /// be the instance's (a lossy video's colours bleed, and instance colours can be close).
    pub bbox: Option<[f64; 4]>,
}

/// The truth objects of a segmentation frame from its painted instances: instances of a class of `classes`, grouped into the objects they are part
/// of (the scenario's truth objects: one mask per object, numbered by its first instance), and
/// objects of a class found piece by piece split into their connected [`pieces`]. A pixel goes
/// to the nearest colour among the instances whose annotated box holds it, and each instance's
/// pieces under [`MIN_PIECE_PIXELS`] are dropped as colour bleeding.
pub fn truth_instances(
    segmentation: &RgbFrame,
    painted: &[Painted<'_>],
    classes: &ClassTable,
    tolerance: u32,
) -> Vec<TruthInstance> {
    // Every painted instance competes for the pixels (a wall's blurred edge is the wall's,
    // not a nearby stick's), and only those of a class are kept.
    let all: Vec<BoxedInstance> = painted.iter().map(|p| (p.id, p.color, p.bbox)).collect();
    // Per object, in order of its first instance.
    let mut objects: Vec<GroupedObject> = Vec::new();
    for (instance_id, mask) in boxed_masks(segmentation, &all, tolerance) {
        let Some(instance) = painted.iter().find(|p| p.id == instance_id) else {
            continue;
        };
        let name = instance.name;
        let Some(class) = classes.of_object(name) else {
            continue;
        };
        // An mp4's colours bleed: specks under MIN_PIECE_PIXELS are blur, not the instance.
        let boxed = mask;
        let kept = pieces(&boxed);
        let mask = match kept.as_slice() {
            [] => continue,
            [only] => only.clone(),
            _ => InstanceMask::from_predicate(segmentation.width, segmentation.height, |x, y| {
                kept.iter().any(|piece| piece.contains(x, y))
            }),
        };
        let object = classes.truth_object(name);
        match objects.iter_mut().find(|entry| entry.name == object.name) {
            Some(entry) => entry.masks.push(mask),
            None => objects.push(GroupedObject {
                name: object.name,
                instance_id,
                class,
                color: object.color,
                masks: vec![mask],
            }),
        }
    }
    let (width, height) = (segmentation.width, segmentation.height);
    let mut out = Vec::new();
    for GroupedObject {
        instance_id,
        class,
        color,
        masks,
        ..
    } in objects
    {
        let mask = if let [only] = masks.as_slice() {
            only.clone()
        } else {
            InstanceMask::from_predicate(width, height, |x, y| {
                masks.iter().any(|mask| mask.contains(x, y))
            })
        };
        let parts = if classes.pieces(class) {
            pieces(&mask)
        } else {
            vec![mask]
        };
        // Pieces are numbered apart (the object's id, then 65,536 higher per piece): the
        // evaluation pairs truths by id within a frame.
        out.extend(
            parts
                .into_iter()
                .zip(0_u32..)
                .map(|(mask, piece)| TruthInstance {
                    instance_id: instance_id.saturating_add(piece << 16),
                    class,
                    color,
                    mask,
                }),
        );
    }
    out
}

/// Pieces smaller than this (pixels) are dropped: specks no detector is trained to find.
pub const MIN_PIECE_PIXELS: u64 = 6;

/// The connected pieces of `mask`, in order of their first pixel (row by row, counting the
/// grown pixels): pixels within
/// one pixel of each other (8-neighbours of the mask grown by one pixel) are one piece, so
/// droplets that touch join; each piece keeps only the mask's own pixels, and pieces under
/// [`MIN_PIECE_PIXELS`] are left out. The detector was trained on these pieces.
pub fn pieces(mask: &InstanceMask) -> Vec<InstanceMask> {
    let (left, top, width, height) = mask.rectangle();
    if width == 0 || height == 0 {
        return Vec::new();
    }
    // Grid coordinates: the rectangle grown by two pixels on every side (one for the growth,
    // one for its neighbours); grid (gx, gy) is frame (left + gx − 2, top + gy − 2).
    let (grid_width, grid_height) = (width + 4, height + 4);
    let index = |gx: u32, gy: u32| gy as usize * grid_width as usize + gx as usize;
    let frame = |gx: u32, gy: u32| Some(((left + gx).checked_sub(2)?, (top + gy).checked_sub(2)?));
    let inside = |gx: u32, gy: u32| frame(gx, gy).is_some_and(|(x, y)| mask.contains(x, y));
    let mut grown = vec![false; grid_width as usize * grid_height as usize];
    for gy in 1..grid_height - 1 {
        for gx in 1..grid_width - 1 {
            grown[index(gx, gy)] =
                (gy - 1..=gy + 1).any(|y| (gx - 1..=gx + 1).any(|x| inside(x, y)));
        }
    }
    let mut labelled = vec![false; grown.len()];
    let mut out = Vec::new();
    for gy in 0..grid_height {
        for gx in 0..grid_width {
            if !grown[index(gx, gy)] || labelled[index(gx, gy)] {
                continue;
            }
            labelled[index(gx, gy)] = true;
            let mut stack = vec![(gx, gy)];
            let mut pixels = std::collections::BTreeSet::new();
            while let Some((x, y)) = stack.pop() {
                if let Some(pixel) = frame(x, y).filter(|_| inside(x, y)) {
                    pixels.insert((pixel.1, pixel.0));
                }
                for ny in y.saturating_sub(1)..=(y + 1).min(grid_height - 1) {
                    for nx in x.saturating_sub(1)..=(x + 1).min(grid_width - 1) {
                        if grown[index(nx, ny)] && !labelled[index(nx, ny)] {
                            labelled[index(nx, ny)] = true;
                            stack.push((nx, ny));
                        }
                    }
                }
            }
            let piece = mask_of_pixels(&pixels);
            if piece.area() >= MIN_PIECE_PIXELS {
                out.push(piece);
            }
        }
    }
    out
}

/// The mask of a set of frame pixels (as `(y, x)`), over their bounding rectangle.
fn mask_of_pixels(pixels: &std::collections::BTreeSet<(u32, u32)>) -> InstanceMask {
    let Some(x0) = pixels.iter().map(|p| p.1).min() else {
        return InstanceMask::empty();
    };
    let x1 = pixels.iter().map(|p| p.1).max().unwrap_or(x0) + 1;
    let y0 = pixels.iter().map(|p| p.0).min().unwrap_or(0);
    let y1 = pixels.iter().map(|p| p.0).max().unwrap_or(y0) + 1;
    let bits = (y0..y1)
        .flat_map(|y| (x0..x1).map(move |x| (x, y)))
        .map(|(x, y)| pixels.contains(&(y, x)))
        .collect();
    InstanceMask::new(x0, y0, x1 - x0, y1 - y0, bits).unwrap_or_else(InstanceMask::empty)
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

    #[test]
    fn pieces_join_pixels_a_pixel_apart_and_drop_specks() {
        // Three blobs on a 20 × 6 frame: a 3 × 2 block at x 0–2 and a 2 × 3 block at x 4–5
        // (a one-pixel gap: one piece after growing), a 4 × 2 block at x 10–13 (its own piece),
        // and a 2-pixel speck at x 18–19 (dropped).
        let inside = |x: u32, y: u32| {
            (x <= 2 && y <= 1)
                || ((4..=5).contains(&x) && y <= 2)
                || ((10..=13).contains(&x) && (3..=4).contains(&y))
                || (x >= 18 && y == 5)
        };
        let mask = InstanceMask::from_predicate(20, 6, inside);
        let found = pieces(&mask);
        assert_eq!(found.len(), 2);
        assert_eq!(found[0].area(), 12);
        assert_eq!(found[0].bounds(), Some([0, 0, 6, 3]));
        assert!(!found[0].contains(3, 0), "the gap stays out of the piece");
        assert_eq!(found[1].area(), 8);
        assert_eq!(found[1].bounds(), Some([10, 3, 14, 5]));
        assert!(pieces(&InstanceMask::empty()).is_empty());
    }
}
