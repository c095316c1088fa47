//! Silhouettes of convex solids against instance masks: the convex hull of a solid's projected
//! corners, its pixel IoU with a detector's mask, and the pattern search that fits a solid's
//! parameters by that IoU (the scene readings that place boxes and slabs through the camera).
//!
//! Input: image polygons (pixels), instance masks, a cost over parameters. Output: hulls, IoUs,
//! fitted parameters. Every pixel is sampled at 2 × 2 points, so a polygon edge moving by a
//! fraction of a pixel changes the IoU.

use super::detection::InstanceMask;

/// The sub-pixel points each pixel is sampled at.
const SAMPLES: [(f64, f64); 4] = [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)];

/// The convex hull of `points` (Andrew's monotone chain), counter-clockwise.
pub fn convex_hull(mut points: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
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

/// The area of the simple `polygon` (shoelace formula), whichever way it turns.
pub fn polygon_area(polygon: &[[f64; 2]]) -> f64 {
    let twice: f64 = (0..polygon.len())
        .map(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    twice.abs() / 2.0
}

/// Whether `point` is inside the counter-clockwise convex `polygon`.
pub fn inside(polygon: &[[f64; 2]], point: [f64; 2]) -> bool {
    polygon.len() >= 3
        && (0..polygon.len()).all(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % polygon.len()]);
            (b[0] - a[0]) * (point[1] - a[1]) - (b[1] - a[1]) * (point[0] - a[0]) >= 0.0
        })
}

/// The IoU of `mask` and the convex `polygon` over the pixels of a `size` (width, height)
/// image, each pixel sampled at 2 × 2 points; pixels `ignored` says are hidden (another
/// object's mask in front) count for neither. 0 for an empty mask or polygon.
pub fn polygon_iou(
    polygon: &[[f64; 2]],
    mask: &InstanceMask,
    size: (u32, u32),
    ignored: &dyn Fn(u32, u32) -> bool,
) -> f64 {
    let Some([mask_x0, mask_y0, mask_x1, mask_y1]) = mask.bounds() else {
        return 0.0;
    };
    if polygon.len() < 3 {
        return 0.0;
    }
    let (width, height) = (f64::from(size.0), f64::from(size.1));
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
            if !in_mask && ignored(x, y) {
                continue;
            }
            let covered = SAMPLES
                .iter()
                .filter(|(dx, dy)| inside(polygon, [f64::from(x) + dx, f64::from(y) + dy]))
                .count() as f64
                / SAMPLES.len() as f64;
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

/// Minimises `cost` from `start` by a pattern search: each parameter tried up and down by its
/// step, any improvement kept, the steps halved when none helps, until the first step is below
/// `finest` (or 400 rounds). `valid` rejects trial points (a non-positive length). Returns the
/// best point and its cost.
pub fn pattern_search<const N: usize>(
    start: [f64; N],
    mut steps: [f64; N],
    finest: f64,
    valid: &dyn Fn(&[f64; N]) -> bool,
    cost: &dyn Fn(&[f64; N]) -> f64,
) -> ([f64; N], f64) {
    let mut best = start;
    let mut best_cost = cost(&best);
    for _ in 0..400 {
        let mut improved = false;
        for axis in 0..N {
            for sign in [1.0, -1.0] {
                let mut trial = best;
                trial[axis] += sign * steps[axis];
                if !valid(&trial) {
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
            if steps.first().is_none_or(|step| *step < finest) {
                break;
            }
        }
    }
    (best, best_cost)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_s_hull_drops_its_inner_point_and_its_iou_with_itself_is_one() {
        let hull = convex_hull(vec![
            [0.0, 0.0],
            [4.0, 0.0],
            [2.0, 2.0],
            [4.0, 4.0],
            [0.0, 4.0],
        ]);
        assert_eq!(hull.len(), 4);
        // 4 × 4 either way round; a triangle of base 4 and height 2.
        assert!((polygon_area(&hull) - 16.0).abs() < 1e-12);
        let reversed: Vec<_> = hull.iter().rev().copied().collect();
        assert!((polygon_area(&reversed) - 16.0).abs() < 1e-12);
        assert!((polygon_area(&[[0.0, 0.0], [4.0, 0.0], [2.0, 2.0]]) - 4.0).abs() < 1e-12);
        assert!(inside(&hull, [1.0, 3.0]));
        assert!(!inside(&hull, [5.0, 1.0]));
        let mask = InstanceMask::from_predicate(8, 8, |x, y| x < 4 && y < 4);
        let iou = polygon_iou(&hull, &mask, (8, 8), &|_, _| false);
        assert!((iou - 1.0).abs() < 1e-12, "{iou}");
        // Half the square hidden by an occluder that the mask lacks: still a full match.
        let cut = InstanceMask::from_predicate(8, 8, |x, y| x < 2 && y < 4);
        assert!(polygon_iou(&hull, &cut, (8, 8), &|_, _| false) < 0.6);
        let iou = polygon_iou(&hull, &cut, (8, 8), &|x, _| x >= 2);
        assert!((iou - 1.0).abs() < 1e-12, "{iou}");
    }

    #[test]
    fn the_pattern_search_finds_a_quadratic_s_minimum() {
        let (best, cost) = pattern_search([0.0, 0.0], [1.0, 1.0], 1e-4, &|_| true, &|p| {
            (p[0] - 1.3).powi(2) + (p[1] + 0.7).powi(2)
        });
        assert!((best[0] - 1.3).abs() < 1e-3 && (best[1] + 0.7).abs() < 1e-3);
        assert!(cost < 1e-6);
    }
}
