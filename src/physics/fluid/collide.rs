//! Static colliders of the fluid scene (tank walls, sticks, container parts) and continuous
//! collision of particles against them: a particle's move from its last position to its
//! predicted one stops where it first touches a collider, so no particle ever crosses one, however
//! thin the collider or fast the particle.
//!
//! Input: a collider (a thick segment: a capsule round its centre line) and a particle's start
//! and predicted positions with its radius. Output: the predicted position moved to the
//! collider's surface with friction applied to the sliding part of the move, or left alone.

use super::norm;

/// The `z` component of `(a − o) × (b − o)`: positive when `o → a → b` turns anticlockwise.
pub fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (b[0] - o[0]) * (a[1] - o[1])
}

/// Whether segments `p1`–`q1` and `p2`–`q2` cross or touch (the release's
/// `LineSegmentsIntersect`, which the fluid generator's stick placement uses too).
pub fn segments_intersect(p1: [f64; 2], q1: [f64; 2], p2: [f64; 2], q2: [f64; 2]) -> bool {
    cross(p1, q1, p2) * cross(p1, q1, q2) <= 0.0 && cross(p2, q2, p1) * cross(p2, q2, q1) <= 0.0
}

/// Where along segment `s0`–`s1` (0 at `s0`, 1 at `s1`) its point closest to `point` lies.
fn segment_parameter(point: [f64; 2], s0: [f64; 2], s1: [f64; 2]) -> f64 {
    let along = [s1[0] - s0[0], s1[1] - s0[1]];
    let squared = along[0] * along[0] + along[1] * along[1];
    if squared > 0.0 {
        (((point[0] - s0[0]) * along[0] + (point[1] - s0[1]) * along[1]) / squared).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Shortest distance between segments `a0`–`a1` and `b0`–`b1`, units (0 when they cross or
/// touch).
pub fn segment_distance(a0: [f64; 2], a1: [f64; 2], b0: [f64; 2], b1: [f64; 2]) -> f64 {
    if segments_intersect(a0, a1, b0, b1) {
        return 0.0;
    }
    let to_segment = |p: [f64; 2], s0: [f64; 2], s1: [f64; 2]| {
        let t = segment_parameter(p, s0, s1);
        norm(
            p[0] - s0[0] - t * (s1[0] - s0[0]),
            p[1] - s0[1] - t * (s1[1] - s0[1]),
        )
    };
    to_segment(a0, b0, b1)
        .min(to_segment(a1, b0, b1))
        .min(to_segment(b0, a0, a1))
        .min(to_segment(b1, a0, a1))
}

/// A static collider: a capsule round the segment `start`–`end` (units), with its surface
/// material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Collider {
    /// One end of the centre line, units.
    pub start: [f64; 2],
    /// The other end of the centre line, units.
    pub end: [f64; 2],
    /// Half the collider's thickness, units (a stick 0.15 thick: 0.075).
    pub half_thickness: f64,
    /// Coulomb friction coefficient: a contact removes at most this many times the depth the
    /// move would have gone into the surface from the sliding part of the move (Obi's friction
    /// 0.3–0.5).
    pub friction: f64,
    /// Share of a move away from the surface a contact holds back, 0–1 (Obi's stickiness
    /// 0.03–0.7).
    pub stickiness: f64,
}

impl Collider {
    /// The point of the centre line closest to `point`.
    fn closest(&self, point: [f64; 2]) -> [f64; 2] {
        let t = segment_parameter(point, self.start, self.end);
        [
            self.start[0] + t * (self.end[0] - self.start[0]),
            self.start[1] + t * (self.end[1] - self.start[1]),
        ]
    }

    /// Distance from `point` to the centre line, units.
    fn distance(&self, point: [f64; 2]) -> f64 {
        let c = self.closest(point);
        norm(point[0] - c[0], point[1] - c[1])
    }

    /// The point of the centre line closest to `point`, the distance to it, and the outward
    /// direction from it towards `point` (on the centre line itself: the segment's left normal).
    fn outward(&self, point: [f64; 2]) -> ([f64; 2], f64, [f64; 2]) {
        let centre = self.closest(point);
        let offset = [point[0] - centre[0], point[1] - centre[1]];
        let length = norm(offset[0], offset[1]);
        let normal = if length > 1e-12 {
            [offset[0] / length, offset[1] / length]
        } else {
            let along = [self.end[0] - self.start[0], self.end[1] - self.start[1]];
            let along_length = norm(along[0], along[1]).max(1e-12);
            [-along[1] / along_length, along[0] / along_length]
        };
        (centre, length, normal)
    }

    /// Whether `point` may lie within `margin` (units) of this collider's surface: `false` only
    /// when it is outside the centre line's bounding box grown by the half thickness and the
    /// margin (and a nanometre, so rounding never skips a real contact). A few comparisons, done
    /// before the distance for every particle–collider pair, so far pairs cost next to nothing.
    pub(crate) fn near(&self, point: [f64; 2], margin: f64) -> bool {
        let reach = self.half_thickness + margin + 1e-9;
        point[0] >= self.start[0].min(self.end[0]) - reach
            && point[0] <= self.start[0].max(self.end[0]) + reach
            && point[1] >= self.start[1].min(self.end[1]) - reach
            && point[1] <= self.start[1].max(self.end[1]) + reach
    }

    /// Distance from `point` to this collider's surface (negative inside), units, and the
    /// surface's outward normal there.
    pub(crate) fn surface_gap(&self, point: [f64; 2]) -> (f64, [f64; 2]) {
        let (_, length, normal) = self.outward(point);
        (length - self.half_thickness, normal)
    }

    /// Moves `predicted`, reached from `from` by a particle of radius `radius`, so that the move
    /// stops at this collider's surface; returns whether it touched. The part of the move past
    /// the contact keeps only its sliding component, reduced by Coulomb friction.
    pub(crate) fn resolve(&self, from: [f64; 2], predicted: &mut [f64; 2], radius: f64) -> bool {
        let reach = self.half_thickness + radius;
        // The distance to the centre line changes no faster than the particle moves: a move
        // shorter than its start's clearance cannot touch (most particle–collider pairs).
        let travel = norm(predicted[0] - from[0], predicted[1] - from[1]);
        if !self.near(from, radius + travel) {
            return false;
        }
        let start = self.outward(from);
        if start.1 - travel >= reach {
            return false;
        }
        let at = |t: f64| {
            [
                from[0] + t * (predicted[0] - from[0]),
                from[1] + t * (predicted[1] - from[1]),
            ]
        };
        let inside = start.1 < reach;
        let touch = if inside {
            // Already inside (resting particles jitter into the contact distance, and an earlier
            // correction can push one there): push out from where it starts.
            0.0
        } else {
            // The move touches only if it comes closer to the centre line than `reach`: the
            // shortest distance between two segments, in closed form.
            if segment_distance(from, *predicted, self.start, self.end) >= reach {
                return false;
            }
            // The distance to a segment along a straight move is convex in the move's
            // parameter, so its minimum is found by ternary search and the first touch by
            // bisection before it.
            let (mut low, mut high) = (0.0_f64, 1.0_f64);
            for _ in 0..40 {
                let (a, b) = (low + (high - low) / 3.0, high - (high - low) / 3.0);
                if self.distance(at(a)) <= self.distance(at(b)) {
                    high = b;
                } else {
                    low = a;
                }
            }
            let (mut outside, mut inside) = (0.0_f64, 0.5 * (low + high));
            for _ in 0..50 {
                let middle = 0.5 * (outside + inside);
                if self.distance(at(middle)) < reach {
                    inside = middle;
                } else {
                    outside = middle;
                }
            }
            outside
        };
        let contact = at(touch);
        // A start already inside keeps its own closest point (computed once).
        let (centre, _, normal) = if inside { start } else { self.outward(contact) };
        let surface = [centre[0] + normal[0] * reach, centre[1] + normal[1] * reach];
        let rest = [predicted[0] - contact[0], predicted[1] - contact[1]];
        let normal_part = rest[0] * normal[0] + rest[1] * normal[1];
        let sliding = [
            rest[0] - normal_part * normal[0],
            rest[1] - normal_part * normal[1],
        ];
        // Coulomb friction, as position-based solvers apply it: the slide loses at most
        // `friction` times the depth the move would have gone into the surface.
        let slide = norm(sliding[0], sliding[1]);
        let keep = if slide > 1e-15 {
            (1.0 - self.friction.max(0.0) * (-normal_part).max(0.0) / slide).max(0.0)
        } else {
            0.0
        };
        // A move away from the surface is held back by stickiness; a move into it is stopped.
        let leave = if normal_part > 0.0 {
            normal_part * (1.0 - self.stickiness.clamp(0.0, 1.0))
        } else {
            0.0
        };
        let mut moved = [
            surface[0] + keep * sliding[0] + leave * normal[0],
            surface[1] + keep * sliding[1] + leave * normal[1],
        ];
        // Sliding along a capsule's rounded end or off its edge can re-enter it: project out.
        let (centre, distance, away) = self.outward(moved);
        if distance < reach {
            moved = [centre[0] + away[0] * reach, centre[1] + away[1] * reach];
        }
        *predicted = moved;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn floor() -> Collider {
        Collider {
            start: [-1.0, 0.0],
            end: [1.0, 0.0],
            half_thickness: 0.01,
            friction: 0.0,
            stickiness: 0.0,
        }
    }

    #[test]
    fn a_fast_particle_stops_on_a_thin_collider_instead_of_crossing_it() {
        let collider = floor();
        let mut predicted = [0.2, -5.0];
        assert!(collider.resolve([0.0, 1.0], &mut predicted, 0.0125));
        let reach = 0.01 + 0.0125;
        assert!(predicted[1] >= reach - 1e-9, "{predicted:?}");
        // Frictionless: the sliding part of the move is kept.
        assert!(predicted[0] > 0.19, "{predicted:?}");
    }

    #[test]
    fn friction_removes_its_share_of_the_slide_and_a_clear_move_is_untouched() {
        let mut collider = floor();
        collider.friction = 0.5;
        let mut predicted = [1.0, -1.0];
        collider.resolve([0.0, 1.0], &mut predicted, 0.0);
        // Contact at x = 0.495 (the move crosses y = 0.01 just before half way); of the rest,
        // 0.505 slides and 1.01 goes into the surface, so friction 0.5 removes the whole slide.
        assert!((predicted[0] - 0.495).abs() < 0.001, "{predicted:?}");
        let mut glancing = [2.0, -0.1];
        collider.resolve([0.0, 0.1], &mut glancing, 0.0);
        // Contact at x = 0.9 (y falls 0.09 of 0.2); of the rest 1.1 slides and 0.11 goes in,
        // so friction removes 0.055 of the slide.
        assert!((glancing[0] - 1.945).abs() < 0.001, "{glancing:?}");
        let mut clear = [0.5, 0.5];
        assert!(!collider.resolve([0.0, 1.0], &mut clear, 0.0));
        assert!(clear.iter().all(|v| (v - 0.5).abs() < 1e-15), "{clear:?}");
    }
}
