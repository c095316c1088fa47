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
    (ropes, frames): (&[(usize, &Detection)], &[RgbFrame]),
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
        // The rope's pixels in its frame, to follow each end past the coarse mask.
        let frame = frames.iter().find(|f| f.index == detection.frame);
        let (wall, occupied) = frame.map_or((None, Vec::new()), |f| pass.frame_context(f));
        let evidence = RopeEvidence::new(detection, frame.zip(wall), &occupied);
        for end in mask_ends(&detection.mask, reach) {
            let (x, y) = follow_end(&evidence, end, reach);
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

/// Where a rope's mask may end: its top and bottom pixels, the top and bottom pixels of its
/// left and right halves (split at the middle of its box) that lie at least `clearance` pixels
/// from the split, and its tips ([`mask_tips`]) away from those: a rope hanging in a U from two
/// fixed points has an end at the top of each arm, only one of which is the top of the whole
/// mask, and an arm beside a longer one ends inside the mask's box; a sloping rope's halves
/// have their extremes at the split, where the rope runs on both ways and does not end.
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
    // Tips inside the box, away from every end found so far.
    for tip in mask_tips(mask, clearance) {
        let known = ends
            .iter()
            .any(|end| end.0.abs_diff(tip.0) <= clearance && end.1.abs_diff(tip.1) <= clearance);
        if !known {
            ends.push(tip);
        }
    }
    ends
}

/// Where the mask leaves the square of half-size `radius` round `at` when it crosses the
/// square's border in one run of pixels only, as a rope does round its end (round a point along
/// it, it crosses twice: in and out): the mean of that run's pixels (`None` for no run or
/// several). Pixels outside the frame count as outside the mask.
fn exit_point(mask: &InstanceMask, at: (u32, u32), radius: u32) -> Option<[f64; 2]> {
    if radius == 0 {
        return None;
    }
    let (x, y) = (i64::from(at.0), i64::from(at.1));
    let r = i64::from(radius);
    // The square's border, clockwise from its top-left corner, each pixel once.
    let border: Vec<(i64, i64)> = (0..2 * r)
        .map(|k| (x - r + k, y - r))
        .chain((0..2 * r).map(|k| (x + r, y - r + k)))
        .chain((0..2 * r).map(|k| (x + r - k, y + r)))
        .chain((0..2 * r).map(|k| (x - r, y + r - k)))
        .collect();
    let inside: Vec<bool> = border
        .iter()
        .map(|&(px, py)| match (u32::try_from(px), u32::try_from(py)) {
            (Ok(px), Ok(py)) => mask.contains(px, py),
            _ => false,
        })
        .collect();
    let count = inside.len();
    // Runs: places where the border steps from outside into the mask (cyclically).
    let mut starts = (0..count).filter(|&k| inside[k] && !inside[(k + count - 1) % count]);
    let first = starts.next()?;
    if starts.next().is_some() {
        return None;
    }
    let run: Vec<(i64, i64)> = (0..count)
        .map(|k| (first + k) % count)
        .take_while(|&k| inside[k])
        .map(|k| border[k])
        .collect();
    let n = run.len() as f64;
    let sum = run.iter().fold([0.0, 0.0], |acc, &(px, py)| {
        [acc[0] + px as f64, acc[1] + py as f64]
    });
    Some([sum[0] / n, sum[1] / n])
}

/// Farthest a rope end is followed past its mask along the rope's pixels, in multiples of the
/// touch reach (3 × 33 pixels at 1080p, about 3 units): the detector's mask of a long rope is
/// 28 × 28 cells over its box, so an end can stop a cell (tens of pixels) short of the rope's.
const END_FOLLOW_REACHES: u32 = 3;
/// Half-width of the band across the rope in which its pixels are looked for while following
/// an end, pixels (a rope is about 8 pixels wide at 1080p, and an end pixel of its mask can be
/// off its centre line).
const END_FOLLOW_BAND: i64 = 3;
/// Longest run without rope pixels that following an end steps over, pixels.
const END_FOLLOW_GAP: u32 = 3;

/// Where the rope whose mask ends at `end` really ends: from `end`, away from where the mask
/// leaves the square round it ([`exit_point`]), as far as the rope's pixels (mask or colour)
/// go on. `end` itself when the mask does not end there as a rope does.
fn follow_end(evidence: &RopeEvidence, end: (u32, u32), reach: u32) -> (u32, u32) {
    let Some(exit) = exit_point(&evidence.mask, end, reach) else {
        return end;
    };
    let (x, y) = (f64::from(end.0), f64::from(end.1));
    let (dx, dy) = (x - exit[0], y - exit[1]);
    let norm = dx.hypot(dy);
    if norm < 1.0 {
        return end;
    }
    let (ux, uy) = (dx / norm, dy / norm);
    // Walk one pixel at a time along the direction, re-centred on the rope's pixels found
    // across it at each step (the direction from a coarse mask is a few degrees off).
    let (mut px, mut py) = (x, y);
    let (mut end_x, mut end_y) = (x, y);
    let mut since = 0;
    for _ in 0..END_FOLLOW_REACHES * reach {
        if since >= END_FOLLOW_GAP {
            break;
        }
        px += ux;
        py += uy;
        let across: Vec<f64> = (-END_FOLLOW_BAND..=END_FOLLOW_BAND)
            .map(|k| k as f64)
            .filter(|k| {
                let (qx, qy) = ((px - uy * k).round(), (py + ux * k).round());
                qx >= 0.0 && qy >= 0.0 && evidence.at(pixel(qx), pixel(qy)) != Sample::Missed
            })
            .collect();
        if across.is_empty() {
            since += 1;
            continue;
        }
        let shift = across.iter().sum::<f64>() / across.len() as f64;
        px -= uy * shift;
        py += ux * shift;
        (end_x, end_y) = (px, py);
        since = 0;
    }
    if !(end_x.is_finite() && end_y.is_finite()) {
        return end;
    }
    (pixel(end_x.round().max(0.0)), pixel(end_y.round().max(0.0)))
}

/// A non-negative whole pixel coordinate as `u32` (saturating).
#[expect(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    reason = "non-negative whole values, saturated into u32"
)]
fn pixel(value: f64) -> u32 {
    value.clamp(0.0, f64::from(u32::MAX)) as u32
}

/// The tips of a mask: where it ends as a rope does, wherever that is (the top of an arm that
/// rises beside a longer one ends inside the mask's box, not at an extreme of it). Pixels on
/// the mask's upper or lower edge whose square of half-size `radius` the mask leaves in one
/// direction only ([`exit_point`]) are grouped (within `radius` of a group's first pixel), and
/// each group gives its pixel farthest from the group's mean exit: the tip itself.
fn mask_tips(mask: &InstanceMask, radius: u32) -> Vec<(u32, u32)> {
    // Per group: its first pixel, and its members with their exits.
    type Group = ((u32, u32), Vec<((u32, u32), [f64; 2])>);
    let mut groups: Vec<Group> = Vec::new();
    for (x, y) in mask.pixels() {
        let edge = y == 0 || !mask.contains(x, y - 1) || !mask.contains(x, y + 1);
        if !edge {
            continue;
        }
        let Some(exit) = exit_point(mask, (x, y), radius) else {
            continue;
        };
        match groups
            .iter_mut()
            .find(|(seed, _)| seed.0.abs_diff(x) <= radius && seed.1.abs_diff(y) <= radius)
        {
            Some((_, members)) => members.push(((x, y), exit)),
            None => groups.push(((x, y), vec![((x, y), exit)])),
        }
    }
    groups
        .iter()
        .filter_map(|(_, members)| {
            let n = members.len() as f64;
            let mean = members.iter().fold([0.0, 0.0], |acc, (_, exit)| {
                [acc[0] + exit[0] / n, acc[1] + exit[1] / n]
            });
            let away =
                |&(x, y): &(u32, u32)| (f64::from(x) - mean[0]).hypot(f64::from(y) - mean[1]);
            members
                .iter()
                .map(|(pixel, _)| *pixel)
                .max_by(|a, b| away(a).total_cmp(&away(b)))
        })
        .collect()
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
        let (wall, occupied) = frame.map_or((None, Vec::new()), |f| self.pass.frame_context(f));
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

impl FirstPass<'_> {
    /// What the ropes' colour evidence in `frame` needs: the wall's colour, and per pixel (row
    /// by row) whether an object that is not a rope covers it.
    fn frame_context(&self, frame: &RgbFrame) -> (Option<[f64; 3]>, Vec<bool>) {
        let frame_detections = self.detections.get(&frame.index);
        let masks: Vec<&InstanceMask> = frame_detections
            .map(|list| list.iter().map(|d| &d.mask).collect())
            .unwrap_or_default();
        let wall = wall_color(frame, &masks);
        let mut occupied = vec![false; frame.width as usize * frame.height as usize];
        for detection in frame_detections.into_iter().flatten() {
            if self.classes.name(detection.class) != "rope" {
                for (x, y) in detection.mask.pixels() {
                    if let Some(slot) =
                        occupied.get_mut(y as usize * frame.width as usize + x as usize)
                    {
                        *slot = true;
                    }
                }
            }
        }
        (wall, occupied)
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
/// How far from the wall's feature a mask pixel must be to be taken for the rope's own.
const WALL_MARGIN: f64 = 0.15;
/// Log brightness feature under which a pixel is as dark as a rope tube's shaded sides and
/// strands (linear brightness under 3% of the wall's: those measure 0 to 2.5%, a black rope's
/// lit body 6% and more).
const EDGE_LOG_BRIGHTNESS: f64 = -2.4;
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
        // least like the wall (a thin rope's mask is a band, mostly wall), leaving out the pixels
        // of other objects (a rope's mask covers part of the pulleys it wraps).
        let wall_feature = [1.0 / 3.0, 1.0 / 3.0, 3.0_f64.ln()];
        let mut pixels: Vec<[f64; 3]> = detection
            .mask
            .pixels()
            .filter(|&(x, y)| {
                !occupied
                    .get(y as usize * frame.width as usize + x as usize)
                    .copied()
                    .unwrap_or(false)
            })
            .filter_map(|(x, y)| pixel_feature(frame, x, y, wall))
            .collect();
        if pixels.len() < 20 {
            return evidence;
        }
        pixels.sort_by(|a, b| {
            feature_distance(*a, wall_feature).total_cmp(&feature_distance(*b, wall_feature))
        });
        let median = |features: &[[f64; 3]]| {
            [0, 1, 2].map(|c| {
                let mut values: Vec<f64> = features.iter().map(|f| f[c]).collect();
                values.sort_by(f64::total_cmp);
                values[values.len() / 2]
            })
        };
        let mut reference = median(&pixels[pixels.len() / 2..]);
        // A rope is a shaded, striped tube: its sides turned from the light and its dark strands
        // come out near black whatever its colour, and they are the pixels least like the wall.
        // For a dark rope they outnumber its body in that half, and a reference that dark matches
        // nothing but those shadows (seed 5821's black rope in video 44 was read nowhere). Then
        // the rope's colour is the median of its body: the pixels unlike the wall that are not as
        // dark as a shadow.
        if reference[2] < EDGE_LOG_BRIGHTNESS {
            // `pixels` is in order of distance from the wall.
            let unlike_wall =
                pixels.partition_point(|f| feature_distance(*f, wall_feature) <= WALL_MARGIN);
            let body: Vec<[f64; 3]> = pixels[unlike_wall..]
                .iter()
                .filter(|f| f[2] >= EDGE_LOG_BRIGHTNESS)
                .copied()
                .collect();
            if body.len() >= 10 {
                reference = median(&body);
            }
        }
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

    #[test]
    fn an_arm_ending_inside_the_box_ends_at_its_tip() {
        // A W of ropes 3 pixels wide: the outer arms rise to the top row, a middle arm rises only
        // to row 50, in the middle of the mask's box (no extreme of the mask or of a half), and
        // the three are joined by rows 90-94 (the bottom of the pulleys they wrap).
        let w = drawn(100, 100, |x, y| {
            !(3..97).contains(&x) || (48..51).contains(&x) && y >= 50 || (90..95).contains(&y)
        });
        let ends = mask_ends(&w, 20);
        assert!(
            ends.iter().any(|&(x, y)| (48..51).contains(&x) && y == 50),
            "{ends:?}"
        );
        // Round the middle arm's tip the mask leaves downwards only; halfway up an outer arm
        // it runs on both ways, and at a T junction three ways.
        let exit = exit_point(&w, (49, 50), 20).expect("one exit");
        assert!(
            (exit[0] - 49.0).abs() < 1.0 && (exit[1] - 70.0).abs() < 1e-9,
            "{exit:?}"
        );
        assert!(exit_point(&w, (1, 40), 20).is_none());
        assert!(exit_point(&w, (49, 92), 20).is_none());
        // No rope end where the arms join the bottom rows.
        assert!(ends.iter().all(|&(_, y)| y <= 50 || y >= 94), "{ends:?}");
    }

    #[test]
    fn a_black_ropes_colour_is_its_lit_body_not_its_shadowed_sides() {
        // A vertical black rope 9 pixels wide on a light wall: three near-black pixels on each
        // side (its shaded sides and strands) round three lit ones. The detector's mask is a
        // band round its upper half only, as a coarse mask of a long rope often is.
        let (width, height) = (200_u32, 100_u32);
        let wall = [210_u8, 206, 200];
        let rope_column = |x: u32| -> Option<u8> {
            match x {
                96 | 104 => Some(0),
                97 | 103 => Some(10),
                98 | 102 => Some(30),
                99 => Some(70),
                100 => Some(100),
                101 => Some(80),
                _ => None,
            }
        };
        let mut rgb = Vec::with_capacity((width * height * 3) as usize);
        for _y in 0..height {
            for x in 0..width {
                match rope_column(x) {
                    Some(v) => rgb.extend([v, v, v]),
                    None => rgb.extend(wall),
                }
            }
        }
        let frame = RgbFrame {
            index: 0,
            width,
            height,
            rgb,
        };
        let rope = detection(
            "rope",
            InstanceMask::from_predicate(width, height, |x, y| (91..=109).contains(&x) && y < 50),
        );
        let wall_linear = wall.map(srgb_to_linear);
        let occupied = vec![false; (width * height) as usize];
        let evidence = RopeEvidence::new(&rope, Some((&frame, wall_linear)), &occupied);
        // Below the mask the rope's lit pixels are found by colour; the wall beside it is not.
        for y in [60, 80, 99] {
            assert!(
                (99..=101).any(|x| evidence.at(x, y) == Sample::OnColour),
                "row {y}: no lit rope pixel found"
            );
            assert_eq!(
                evidence.at(120, y),
                Sample::Missed,
                "row {y}: wall taken for rope"
            );
        }
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
        loose_ends(&pass, (&[(0, &rope)], &[]), &[], &model, &camera).len()
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
