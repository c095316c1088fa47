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
    let mut best: SlabParameters = [centre[0], centre[1], angle, half];
    let cost = |p: &SlabParameters| 1.0 - silhouette_iou(model, mask, p, thickness);
    let mut best_cost = cost(&best);
    let mut steps = [0.2, 0.2, 0.1, 0.2];
    // Pattern search: try each parameter up and down by its step, keep any improvement, halve
    // the steps when none helps, until they are below a tenth of a pixel's 0.03 units.
    for _ in 0..400 {
        let mut improved = false;
        for axis in 0..4 {
            for sign in [1.0, -1.0] {
                let mut trial = best;
                trial[axis] += sign * steps[axis];
                if trial[3] <= 0.0 {
                    continue;
                }
                let trial_cost = cost(&trial);
                if trial_cost < best_cost {
                    best = trial;
                    best_cost = trial_cost;
                    improved = true;
                }
            }
        }
        if !improved {
            for step in &mut steps {
                *step /= 2.0;
            }
            if steps[0] < 0.003 {
                break;
            }
        }
    }
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

/// The convex hull of `points` (Andrew's monotone chain), counter-clockwise.
fn convex_hull(mut points: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    points.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(points.len() * 2);
    for pass in 0..2 {
        let floor = hull.len();
        let ordered: Box<dyn Iterator<Item = &[f64; 2]>> = if pass == 0 {
            Box::new(points.iter())
        } else {
            Box::new(points.iter().rev())
        };
        for &point in ordered {
            while hull.len() >= floor + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], point) <= 0.0
            {
                hull.pop();
            }
            hull.push(point);
        }
        hull.pop();
    }
    hull
}

/// Whether `point` is inside the counter-clockwise convex `polygon`.
fn inside(polygon: &[[f64; 2]], point: [f64; 2]) -> bool {
    polygon.len() >= 3
        && (0..polygon.len()).all(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
            (b[0] - a[0]) * (point[1] - a[1]) - (b[1] - a[1]) * (point[0] - a[0]) >= 0.0
        })
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
    let Some([mask_x0, mask_y0, mask_x1, mask_y1]) = mask.bounds() else {
        return 0.0;
    };
    let (width, height) = (f64::from(model.width), f64::from(model.height));
    let low = |axis: usize, bound: u32| {
        polygon
            .iter()
            .map(|p| p[axis])
            .fold(f64::from(bound), f64::min)
            .floor()
            .max(0.0)
    };
    let high = |axis: usize, bound: u32, limit: f64| {
        polygon
            .iter()
            .map(|p| p[axis])
            .fold(f64::from(bound), f64::max)
            .ceil()
            .min(limit)
    };
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "clamped to the image"
    )]
    let (x0, y0, x1, y1) = (
        low(0, mask_x0) as u32,
        low(1, mask_y0) as u32,
        high(0, mask_x1, width) as u32,
        high(1, mask_y1, height) as u32,
    );
    let (mut both, mut either) = (0.0, 0.0);
    for y in y0..y1 {
        for x in x0..x1 {
            let in_mask = mask.contains(x, y);
            let mut covered = 0.0;
            for (dx, dy) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)] {
                if inside(&polygon, [f64::from(x) + dx, f64::from(y) + dy]) {
                    covered += 0.25;
                }
            }
            if in_mask {
                both += covered;
                either += 1.0;
            } else {
                either += covered;
            }
        }
    }
    if either > 0.0 { both / either } else { 0.0 }
}
