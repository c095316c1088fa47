//! The pixel evidence of the ropes of one video, for `perceived`: where each rope's pixels are
//! in a frame (its mask, filled by the pixels of its colour), each rope's path read from them
//! frame by frame (`FrameReader`), and candidate fixed points where a rope's pixels end with no
//! detected object there (`loose_ends`).
//!
//! Input: the first pass's detections and frames, the nodes placed so far, the camera. Output:
//! per frame, each rope's path (`topology::read_ropes`), and the candidate nodes.

use super::perceived::{FirstPass, SAME_OBJECT_DISTANCE, lift};
use super::topology::{Node, NodeKind, RopePath, Sample, distance, read_ropes};
use crate::dataset::Camera;
use crate::perception::camera::CameraModel;
use crate::perception::color::{srgb_to_linear, wall_color};
use crate::perception::detection::{Detection, InstanceMask};
use crate::perception::frames::RgbFrame;

/// Farther than this beyond a node's body from every node, a rope's end pixel is a loose end,
/// units.
const LOOSE_END_CLEARANCE: f64 = 0.5;

/// Within this share of the frame height of an object's mask, a rope's end pixel ends at that
/// object, whatever the scene distance between their centres says: a rope's coarse mask can stop
/// short of the load it is tied to (27 pixels of 1080, 2.5%, at a large cube tied by its
/// corner), farther on the scene plane than the load's nominal body reaches.
const TOUCH_SHARE: f64 = 0.03;

/// Candidate fixed points where the ropes' pixels end: the top and bottom of each rope's first
/// mask, lifted onto the scene plane, when no node (or earlier candidate) is near and no other
/// object's mask in that frame touches the end.
pub(super) fn loose_ends(
    pass: &FirstPass<'_>,
    ropes: &[(usize, &Detection)],
    nodes: &[Node],
    model: &CameraModel,
    camera: &Camera,
) -> Vec<Node> {
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a small positive pixel count"
    )]
    let reach = (f64::from(pass.size.1) * TOUCH_SHARE).ceil().max(1.0) as u32;
    let touches_object = |frame: usize, x: u32, y: u32| {
        pass.detections.get(&frame).is_some_and(|found| {
            found
                .iter()
                .filter(|d| pass.classes.name(d.class) != "rope")
                .any(|d| {
                    (y.saturating_sub(reach)..=y.saturating_add(reach)).any(|ny| {
                        (x.saturating_sub(reach)..=x.saturating_add(reach))
                            .any(|nx| d.mask.contains(nx, ny))
                    })
                })
        })
    };
    let mut found: Vec<Node> = Vec::new();
    for (_, detection) in ropes {
        for (x, y) in mask_ends(&detection.mask, reach) {
            let Some(centre) = lift(model, camera, f64::from(x) + 0.5, f64::from(y) + 0.5) else {
                continue;
            };
            let near = nodes.iter().any(|node| {
                distance(node.centre, centre) < node.kind.body_radius() + LOOSE_END_CLEARANCE
            }) || touches_object(detection.frame, x, y)
                || found
                    .iter()
                    .any(|node| distance(node.centre, centre) < SAME_OBJECT_DISTANCE);
            if !near {
                found.push(Node {
                    kind: NodeKind::Anchor,
                    centre,
                });
            }
        }
    }
    found
}

/// Where a rope's mask may end: its top and bottom pixels, and the top and bottom pixels of its
/// left and right halves (split at the middle of its box) that lie at least `clearance` pixels
/// from the split: a rope hanging in a U from two fixed points has an end at the top of each
/// arm, only one of which is the top of the whole mask, while a sloping rope's halves have
/// their extremes at the split, where no rope ends.
fn mask_ends(mask: &InstanceMask, clearance: u32) -> Vec<(u32, u32)> {
    let (Some(left), Some(right)) = (
        mask.pixels().map(|(x, _)| x).min(),
        mask.pixels().map(|(x, _)| x).max(),
    ) else {
        return Vec::new();
    };
    let split = left + (right - left) / 2;
    // Top and bottom of the whole mask, of its left half and of its right half.
    let mut extremes: [[Option<(u32, u32)>; 2]; 3] = [[None; 2]; 3];
    for (x, y) in mask.pixels() {
        for part in [0, if x < split { 1 } else { 2 }] {
            let [top, bottom] = &mut extremes[part];
            if top.is_none_or(|(_, ty)| y < ty) {
                *top = Some((x, y));
            }
            if bottom.is_none_or(|(_, by)| y >= by) {
                *bottom = Some((x, y));
            }
        }
    }
    let clear = |(x, _): &(u32, u32)| x.abs_diff(split) >= clearance;
    let mut ends: Vec<(u32, u32)> = extremes[0].iter().flatten().copied().collect();
    for half in &extremes[1..] {
        for end in half.iter().flatten() {
            if clear(end) && !ends.contains(end) {
                ends.push(*end);
            }
        }
    }
    ends
}

/// Reads the ropes of one frame.
pub(super) struct FrameReader<'a> {
    pub(super) pass: &'a FirstPass<'a>,
    pub(super) model: &'a CameraModel,
    /// How far from a sample point a rope pixel may be and still cover it, pixels.
    pub(super) reach_px: f64,
}

impl FrameReader<'_> {
    /// Each rope's path in one frame: `nodes` where they are in it, `ropes` each rope's
    /// detection there (`None`: not seen, not read), `frame` its pixels (`None`: masks only).
    pub(super) fn read(
        &self,
        nodes: &[Node],
        ropes: &[Option<&Detection>],
        frame: Option<&RgbFrame>,
    ) -> Vec<Option<RopePath>> {
        let (width, height) = self.pass.size;
        let frame_detections = frame.and_then(|f| self.pass.detections.get(&f.index));
        let wall = frame.and_then(|frame| {
            let masks: Vec<&InstanceMask> = frame_detections
                .map(|list| list.iter().map(|d| &d.mask).collect())
                .unwrap_or_default();
            wall_color(frame, &masks)
        });
        // The pixels of the objects that are not ropes, in this frame.
        let mut occupied = vec![false; frame.map_or(0, |f| f.width as usize * f.height as usize)];
        if let Some(frame) = frame {
            for detection in frame_detections.into_iter().flatten() {
                if self.pass.classes.name(detection.class) != "rope" {
                    for (x, y) in detection.mask.pixels() {
                        if let Some(slot) =
                            occupied.get_mut(y as usize * frame.width as usize + x as usize)
                        {
                            *slot = true;
                        }
                    }
                }
            }
        }
        let evidence: Vec<Option<RopeEvidence>> = ropes
            .iter()
            .map(|detection| detection.map(|d| RopeEvidence::new(d, frame.zip(wall), &occupied)))
            .collect();
        let reach_px = self.reach_px;
        let model = self.model;
        let mut covers = |rope: usize, point: [f64; 2]| -> Option<Sample> {
            let evidence = evidence.get(rope)?.as_ref()?;
            let seen = model.project([point[0], point[1], 0.0])?;
            if seen.depth <= 0.0
                || seen.x < 0.0
                || seen.y < 0.0
                || seen.x >= f64::from(width)
                || seen.y >= f64::from(height)
            {
                return None;
            }
            // In the frame (checked above) and a few pixels wide: small and non-negative.
            #[expect(
                clippy::cast_possible_truncation,
                reason = "pixel coordinates inside the frame and a radius of a few pixels"
            )]
            let (reach, cx, cy) = (
                reach_px.ceil().min(64.0) as i64,
                seen.x.floor() as i64,
                seen.y.floor() as i64,
            );
            let squared = reach_px * reach_px;
            let mut sample = Sample::Missed;
            for dy in -reach..=reach {
                for dx in -reach..=reach {
                    if (dx * dx + dy * dy) as f64 > squared {
                        continue;
                    }
                    let (x, y) = (cx + dx, cy + dy);
                    if x >= 0
                        && y >= 0
                        && let (Ok(x), Ok(y)) = (u32::try_from(x), u32::try_from(y))
                    {
                        match evidence.at(x, y) {
                            Sample::OnMask => return Some(Sample::OnMask),
                            Sample::OnColour => sample = Sample::OnColour,
                            Sample::Missed => {}
                        }
                    }
                }
            }
            Some(sample)
        };
        // A rope not seen in this frame has no path here.
        let seen: Vec<bool> = ropes.iter().map(Option::is_some).collect();
        read_ropes(nodes, &seen, &mut covers)
    }
}

/// A pixel's colour relative to the wall: chromaticity (r, g) and log brightness, of linear RGB
/// divided by the wall's (the per-pixel form of `perception::color::features`).
fn pixel_feature(frame: &RgbFrame, x: u32, y: u32, wall: [f64; 3]) -> Option<[f64; 3]> {
    let p = frame.pixel(x, y)?.map(srgb_to_linear);
    let relative = [p[0] / wall[0], p[1] / wall[1], p[2] / wall[2]];
    let sum = relative[0] + relative[1] + relative[2] + 1e-6;
    let feature = [relative[0] / sum, relative[1] / sum, sum.ln()];
    feature.iter().all(|v| v.is_finite()).then_some(feature)
}

/// How different two pixel features are: chromaticity distance plus a little of the brightness
/// ratio (shading along a rope changes brightness more than hue).
fn feature_distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1]) + BRIGHTNESS_WEIGHT * (a[2] - b[2]).abs()
}

/// Weight of log brightness against chromaticity in [`feature_distance`].
const BRIGHTNESS_WEIGHT: f64 = 0.15;
/// Farthest a pixel's feature may be from its rope's and still count as the rope.
const MAX_ROPE_DISTANCE: f64 = 0.09;

/// Where one rope's pixels are: its mask, and the pixels near its box whose colour is the
/// rope's rather than the wall's. The detector's 28×28 mask of a long thin rope is broken; the
/// colour fills the gaps.
struct RopeEvidence {
    mask: InstanceMask,
    /// The colour-matched pixels over `(left, top, width, height)`.
    left: u32,
    top: u32,
    width: u32,
    height: u32,
    bits: Vec<bool>,
}

impl RopeEvidence {
    /// `occupied` marks, row by row over the whole frame, the pixels of the other objects.
    fn new(
        detection: &Detection,
        frame_and_wall: Option<(&RgbFrame, [f64; 3])>,
        occupied: &[bool],
    ) -> RopeEvidence {
        let mut evidence = RopeEvidence {
            mask: detection.mask.clone(),
            left: 0,
            top: 0,
            width: 0,
            height: 0,
            bits: Vec::new(),
        };
        let Some((frame, wall)) = frame_and_wall else {
            return evidence;
        };
        // The rope's colour: the per-channel median feature of the half of its mask's pixels
        // least like the wall (a thin rope's mask is a band, mostly wall).
        let wall_feature = [1.0 / 3.0, 1.0 / 3.0, 3.0_f64.ln()];
        let mut pixels: Vec<[f64; 3]> = detection
            .mask
            .pixels()
            .filter_map(|(x, y)| pixel_feature(frame, x, y, wall))
            .collect();
        if pixels.len() < 20 {
            return evidence;
        }
        pixels.sort_by(|a, b| {
            feature_distance(*a, wall_feature).total_cmp(&feature_distance(*b, wall_feature))
        });
        let rope_like = &pixels[pixels.len() / 2..];
        let reference = [0, 1, 2].map(|c| {
            let mut values: Vec<f64> = rope_like.iter().map(|f| f[c]).collect();
            values.sort_by(f64::total_cmp);
            values[values.len() / 2]
        });
        // The whole frame, less the objects: the detector's box often misses part of a long
        // rope, and an object of the rope's colour is not rope.
        let (width, height) = (frame.width, frame.height);
        evidence.width = width;
        evidence.height = height;
        evidence.bits = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .zip(occupied)
            .map(|((x, y), object)| {
                !object
                    && pixel_feature(frame, x, y, wall).is_some_and(|f| {
                        let to_rope = feature_distance(f, reference);
                        to_rope < MAX_ROPE_DISTANCE && to_rope < feature_distance(f, wall_feature)
                    })
            })
            .collect();
        evidence
    }

    /// What the rope's pixels show at pixel `(x, y)`.
    fn at(&self, x: u32, y: u32) -> Sample {
        if self.mask.contains(x, y) {
            return Sample::OnMask;
        }
        if x < self.left
            || y < self.top
            || x >= self.left + self.width
            || y >= self.top + self.height
        {
            return Sample::Missed;
        }
        if self.bits[((y - self.top) * self.width + (x - self.left)) as usize] {
            Sample::OnColour
        } else {
            Sample::Missed
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::classes::ClassTable;
    use crate::perception::rope::{PERCEPTION, test_class};
    use crate::scene_api::rope::perceived::camera_model;
    use crate::scene_api::rope::simulation::tests::sample;
    use std::collections::BTreeMap;

    /// A mask of `width × height` from the pixels `inside` says are set.
    fn drawn(width: u32, height: u32, inside: impl Fn(u32, u32) -> bool) -> InstanceMask {
        let bits = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| inside(x, y))
            .collect();
        InstanceMask::new(0, 0, width, height, bits).expect("a mask")
    }

    #[test]
    fn a_rope_hanging_in_a_u_ends_at_the_top_of_each_arm_and_a_sloping_one_at_its_extremes() {
        // Two arms 3 pixels wide, the left one from row 10 down, the right one from row 0,
        // joined by rows 95–99.
        let u = drawn(100, 100, |x, y| x < 3 && y >= 10 || x >= 97 || y >= 95);
        let ends = mask_ends(&u, 20);
        assert!(ends.contains(&(97, 0)), "{ends:?}");
        assert!(ends.contains(&(0, 10)), "{ends:?}");
        // A diagonal: the halves' extremes sit at the split, where the rope does not end.
        let slope = drawn(100, 100, |x, y| x.abs_diff(99 - y) <= 1);
        let ends = mask_ends(&slope, 20);
        assert_eq!(ends.len(), 2, "{ends:?}");
        assert!(ends.iter().all(|(_, y)| *y == 0 || *y == 99), "{ends:?}");
    }

    fn detection(class: &str, mask: InstanceMask) -> Detection {
        Detection {
            frame: 0,
            class: test_class(class),
            score: 0.9,
            bbox: [0.0; 4],
            mask,
            color: None,
        }
    }

    /// Loose ends of a vertical rope (x = 960, y = 300..=500 in a 1920×1080 frame) above a
    /// cube whose mask starts `gap` pixels below the rope's last pixel, with no node near.
    fn loose_ends_with_gap(gap: u32) -> usize {
        let (width, height) = (1920, 1080);
        let rope = detection(
            "rope",
            InstanceMask::from_predicate(width, height, |x, y| {
                x == 960 && (300..=500).contains(&y)
            }),
        );
        let top = 501 + gap;
        let cube = detection(
            "cube",
            InstanceMask::from_predicate(width, height, |x, y| {
                (930..990).contains(&x) && (top..top + 60).contains(&y)
            }),
        );
        let classes = ClassTable::of_scenario(PERCEPTION.classes);
        let detections = BTreeMap::from([(0, vec![rope.clone(), cube])]);
        let pass = FirstPass {
            classes: &classes,
            tracks: &[],
            detections: &detections,
            size: (width, height),
            frame_count: 1,
        };
        let camera = sample().0.camera.unwrap();
        let model = camera_model(&camera, (width, height));
        loose_ends(&pass, &[(0, &rope)], &[], &model, &camera).len()
    }

    #[test]
    fn a_rope_end_touching_an_objects_mask_is_not_a_loose_end() {
        // The rope's top end touches nothing: a candidate fixed point. Its bottom end stops
        // 20 pixels (under 3% of the frame height) short of the cube's mask, as a coarse rope
        // mask does at a load tied by its corner: it ends at the cube, whatever the distance
        // between the cube's centre and the end on the scene plane says.
        assert_eq!(loose_ends_with_gap(20), 1);
        // 60 pixels short: the rope ends in mid-air, at a fixed point the detector missed.
        assert_eq!(loose_ends_with_gap(60), 2);
    }
}
