//! Slabs: rectangles around a centre line in the x–y plane (the ball scenario's ramps, floor
//! pieces and floating walls), shared by the truth solver's contacts
//! (`shape_matching::Slab`) and the MPM core's colliders (`mpm::Shape::Rectangle`). Input: a
//! point and the slab's two ends and thickness. Output: the signed distance and outward normal.

/// Signed distance from `point` to the rectangle around `a`–`b` of `thickness`, and the outward
/// normal: outside, towards the nearest point (corners are rounded); inside, through the nearer
/// face.
pub fn signed_distance(
    point: [f64; 2],
    a: [f64; 2],
    b: [f64; 2],
    thickness: f64,
) -> (f64, [f64; 2]) {
    let centre = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    let along = [b[0] - a[0], b[1] - a[1]];
    let length = along[0].hypot(along[1]);
    let along = if length > 0.0 {
        [along[0] / length, along[1] / length]
    } else {
        [1.0, 0.0]
    };
    let across = [-along[1], along[0]];
    let relative = [point[0] - centre[0], point[1] - centre[1]];
    let local = [
        relative[0] * along[0] + relative[1] * along[1],
        relative[0] * across[0] + relative[1] * across[1],
    ];
    let sign = |value: f64| if value < 0.0 { -1.0 } else { 1.0 };
    let excess = [
        local[0].abs() - 0.5 * length,
        local[1].abs() - 0.5 * thickness,
    ];
    let (distance, local_normal) = if excess[0] > 0.0 || excess[1] > 0.0 {
        let outside = [excess[0].max(0.0), excess[1].max(0.0)];
        let distance = outside[0].hypot(outside[1]);
        (
            distance,
            [
                sign(local[0]) * outside[0] / distance,
                sign(local[1]) * outside[1] / distance,
            ],
        )
    } else if excess[0] > excess[1] {
        (excess[0], [sign(local[0]), 0.0])
    } else {
        (excess[1], [0.0, sign(local[1])])
    };
    (
        distance,
        [
            local_normal[0] * along[0] + local_normal[1] * across[0],
            local_normal[0] * along[1] + local_normal[1] * across[1],
        ],
    )
}
