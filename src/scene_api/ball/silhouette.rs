//! A slab placed from its mask: the centre line whose box, projected through the camera, covers
//! the detector's mask best (`scene_api::ball::perceived`).
//!
//! Input: a slab's instance mask, the camera projection, the slab's thickness (the release's).
//! Output: its centre line's ends on the scene's plane, units. The box is the centre line's
//! rectangle extruded over the slab's depth (1, centred on `z = 0`); seen from above and in
//! front, its silhouette is the front face and, above it, the top face, so lifting the mask onto
//! one plane would raise the slab by half a unit. The fit maximises the pixel IoU of the
//! silhouette (each pixel sampled at 2 × 2 points) and the mask, by a pattern search from the
//! principal axis of the mask lifted onto the front face's plane.

use crate::perception::camera::{CameraModel, principal_segment};
use crate::perception::detection::InstanceMask;
use crate::perception::silhouette::{convex_hull, pattern_search, polygon_iou};
use crate::synth::ball::layout::SLAB_DEPTH;

/// A slab's centre line, `[centre x, centre y, angle, half length]`.
type SlabParameters = [f64; 4];

/// The centre line `(start, end)` of the slab of `thickness` whose box's silhouette through
/// `model` covers `mask` best; `None` for a mask of fewer than 3 pixels.
pub(crate) fn fit_slab(
    model: &CameraModel,
    mask: &InstanceMask,
    thickness: f64,
) -> Option<([f64; 2], [f64; 2])> {
    let front_z = -SLAB_DEPTH / 2.0;
    let lifted: Vec<[f64; 2]> = mask
        .pixels()
        .filter_map(|(x, y)| model.lift_to_plane(f64::from(x) + 0.5, f64::from(y) + 0.5, front_z))
        .collect();
    let (start, end) = principal_segment(&lifted)?;
    let centre = [
        f64::midpoint(start[0], end[0]),
        f64::midpoint(start[1], end[1]),
    ];
    let half = (end[0] - start[0]).hypot(end[1] - start[1]) / 2.0;
    let angle = (end[1] - start[1]).atan2(end[0] - start[0]);
    let cost = |p: &SlabParameters| 1.0 - silhouette_iou(model, mask, p, thickness);
    // Each parameter up and down by its step until the steps are below a tenth of a pixel's
    // 0.03 units.
    let (best, _) = pattern_search(
        [centre[0], centre[1], angle, half],
        [0.2, 0.2, 0.1, 0.2],
        0.003,
        &|trial: &SlabParameters| trial[3] > 0.0,
        &cost,
    );
    let [cx, cy, angle, half] = best;
    let axis = [angle.cos() * half, angle.sin() * half];
    let ends = ([cx - axis[0], cy - axis[1]], [cx + axis[0], cy + axis[1]]);
    [ends.0, ends.1]
        .iter()
        .flatten()
        .all(|v| v.is_finite())
        .then_some(ends)
}

/// The image polygon (convex hull, counter-clockwise in pixels) of the box of `parameters`
/// through `model`; `None` when a corner is behind the camera.
fn silhouette(
    model: &CameraModel,
    parameters: &SlabParameters,
    thickness: f64,
) -> Option<Vec<[f64; 2]>> {
    let [cx, cy, angle, half] = *parameters;
    let along = [angle.cos(), angle.sin()];
    let across = [-along[1] * thickness / 2.0, along[0] * thickness / 2.0];
    let mut corners = Vec::with_capacity(8);
    for z in [-SLAB_DEPTH / 2.0, SLAB_DEPTH / 2.0] {
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            let point = [
                cx + a * half * along[0] + b * across[0],
                cy + a * half * along[1] + b * across[1],
                z,
            ];
            let projected = model.project(point)?;
            corners.push([projected.x, projected.y]);
        }
    }
    Some(convex_hull(corners))
}

/// The IoU of `mask` and the silhouette of the slab `parameters`, over the image's pixels, each
/// sampled at 2 × 2 points.
fn silhouette_iou(
    model: &CameraModel,
    mask: &InstanceMask,
    parameters: &SlabParameters,
    thickness: f64,
) -> f64 {
    let Some(polygon) = silhouette(model, parameters, thickness) else {
        return 0.0;
    };
    polygon_iou(&polygon, mask, (model.width, model.height), &|_, _| false)
}
