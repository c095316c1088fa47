//! The fluids as the detector sees them (`--perception maskrcnn`): per frame, each fluid's
//! pixels lifted onto the scene's plane, for the property inference that the tracked particles
//! of `outputs4D.json` feed under annotation perception.
//!
//! Input: a [`Perceiver`] on the video, the camera model, the scene's fluids (name and palette
//! colour, from its first emitters) and the frames to read. Output: [`SeenFlow`]. The detector
//! draws regions round the fluid of any colour (the fluid model's `fluid` class: a spray, a
//! film on a stick, the layers in a cup), and the colour model names each pixel in them; a pixel
//! of no fluid's colour is counted and left out (a fluid is known by its emitter's colour, and
//! two fluids never share one).

use indexmap::IndexMap;

use super::perceived::FLUID_PLANE_Z;
use crate::dataset::fluid::FluidLayout;
use crate::perception::camera::CameraModel;
use crate::perception::color::{pixel_features, unlike_wall, wall_color};
use crate::perception::detection::{Detection, InstanceMask};
use crate::perception::frames::RgbFrame;
use crate::scene_api::ApiError;
use crate::scene_api::perceiver::Perceiver;

/// Pixels of the frame size the inference's thresholds are stated in (480 × 270, the
/// detector's input).
const REFERENCE_PIXELS: f64 = 480.0 * 270.0;

/// Per fluid of the scene (in scene order), its pixels' centres on the plane `z = 0`, world
/// units.
pub(crate) type FluidPoints = IndexMap<String, Vec<[f64; 2]>>;

/// The fluids of `layout` as [`seen_flow`] takes them: name and palette colour.
pub(crate) fn fluid_colors(layout: &FluidLayout) -> Vec<(String, u8)> {
    layout
        .fluids
        .iter()
        .map(|fluid| (fluid.name.clone(), fluid.color))
        .collect()
}

/// Each fluid's lifted pixels in the frames read.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct SeenFlow {
    /// Per frame read, in order: the frame and each fluid's pixels.
    pub frames: Vec<(usize, FluidPoints)>,
    /// Pixels of fluid pieces whose colour is no fluid's of the scene (or unread).
    pub unnamed_pixels: u64,
    /// What one pixel of these frames counts for in pixels of a 480×270 frame (the detector's
    /// input size, in which the inference's pixel thresholds are stated).
    pub pixel_weight: f64,
}

impl SeenFlow {
    /// The pixels of `fluid` in the frame at `index` of [`SeenFlow::frames`].
    pub(crate) fn at(&self, index: usize, fluid: &str) -> &[[f64; 2]] {
        self.frames
            .get(index)
            .and_then(|(_, fluids)| fluids.get(fluid))
            .map_or(&[], Vec::as_slice)
    }
}

/// A fluid detection's pixel is fluid when its colour is at least this unlike the wall's
/// ([`unlike_wall`]: squared log distance of the colour relative to the wall; 0.02 is a 15%
/// difference in one channel): the detector's masks are regions round a fluid that is often a
/// spray of drops, and the rules of the inference read the drops.
const FLUID_UNLIKE_WALL: f64 = 0.02;

/// Reads `frames` of the video through `perceiver`: the fluid regions of each, their pixels
/// unlike the wall named pixel by pixel by colour (`fluids`: the scene's fluid names and palette
/// colours) and lifted through `model`.
///
/// The detector draws a region round fluid of any colour (drops of two fluids interleave in a
/// spray or a cup), so each pixel is named by itself: the likeliest colour among the scene's
/// fluids and the colours of the sticks, containers and emitters seen in the frame. A pixel
/// whose colour is a solid object's, or that lies in the mask of a solid object of its colour
/// (a stick under the spray), is not fluid.
pub(crate) fn seen_flow(
    perceiver: &mut Perceiver,
    model: &CameraModel,
    fluids: &[(String, u8)],
    frames: &[usize],
) -> Result<SeenFlow, ApiError> {
    let fluid_class = perceiver
        .classes()
        .and_then(|table| table.all().find(|class| table.kind(*class) == "fluid"));
    let colors = perceiver.color_prototypes()?;
    let mut flow = SeenFlow {
        pixel_weight: REFERENCE_PIXELS
            / (f64::from(model.width) * f64::from(model.height)).max(1.0),
        ..SeenFlow::default()
    };
    let mut visit = |frame: &RgbFrame, found: &[Detection]| {
        let mut by_fluid: FluidPoints = fluids
            .iter()
            .map(|(name, _)| (name.clone(), Vec::new()))
            .collect();
        let masks: Vec<&InstanceMask> = found.iter().map(|d| &d.mask).collect();
        let wall = wall_color(frame, &masks);
        let solids: Vec<&Detection> = found
            .iter()
            .filter(|d| Some(d.class) != fluid_class)
            .collect();
        let mut allowed: Vec<u8> = fluids.iter().map(|(_, color)| *color).collect();
        allowed.extend(solids.iter().filter_map(|d| d.color));
        allowed.sort_unstable();
        allowed.dedup();
        // A pixel inside two overlapping fluid regions is read once.
        let mut read = vec![false; frame.width as usize * frame.height as usize];
        for detection in found {
            if Some(detection.class) != fluid_class {
                continue;
            }
            for (x, y) in detection.mask.pixels() {
                let Some(seen) = read.get_mut(y as usize * frame.width as usize + x as usize)
                else {
                    continue;
                };
                if std::mem::replace(seen, true) {
                    continue;
                }
                let Some(wall) = wall else { continue };
                let fluid_like =
                    unlike_wall(frame, x, y, wall).is_some_and(|u| u >= FLUID_UNLIKE_WALL);
                if !fluid_like {
                    continue;
                }
                let color = pixel_features(frame, x, y, wall)
                    .and_then(|features| colors.likeliest(&features, &allowed));
                let named = color.and_then(|color| {
                    let under_solid = solids
                        .iter()
                        .any(|d| d.color == Some(color) && d.mask.contains(x, y));
                    (!under_solid)
                        .then(|| fluids.iter().find(|(_, c)| *c == color))
                        .flatten()
                });
                let Some(points) = named.and_then(|(name, _)| by_fluid.get_mut(name)) else {
                    flow.unnamed_pixels += 1;
                    continue;
                };
                if let Some(point) =
                    model.lift_to_plane(f64::from(x) + 0.5, f64::from(y) + 0.5, FLUID_PLANE_Z)
                {
                    points.push(point);
                }
            }
        }
        flow.frames.push((frame.index, by_fluid));
    };
    perceiver.visit_detections(frames, &mut visit)?;
    Ok(flow)
}
