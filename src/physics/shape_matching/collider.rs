//! Static colliders of the ball scenario: slabs (ramps, floor pieces, floating walls) as oriented
//! rectangles in the x–y plane, extruded without end along z, and a particle's contact with
//! them.
//!
//! A slab is given as the release records a "stick": the two ends of its centre line and its
//! thickness. Contact is the exact signed distance to the rectangle, so corners are rounded for
//! a particle of radius `r`, and any angle works.

use crate::physics::vector3::Vector;

/// A static slab: the rectangle around the segment `start`–`end` (units, x–y), `thickness` across.
#[derive(Debug, Clone, PartialEq)]
pub struct Slab {
    /// One end of the centre line, units.
    pub start: [f64; 2],
    /// The other end, units.
    pub end: [f64; 2],
    /// Full thickness across the centre line, units.
    pub thickness: f64,
}

/// Where a point touches a slab: the signed distance (negative inside) and the outward normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Signed distance from the slab's surface, units.
    pub distance: f64,
    /// Outward unit normal in the x–y plane (z is 0).
    pub normal: [f64; 2],
}

impl Slab {
    /// The slab's centre, unit direction along its length, half-length and half-thickness.
    fn frame(&self) -> ([f64; 2], [f64; 2], f64, f64) {
        let centre = [
            0.5 * (self.start[0] + self.end[0]),
            0.5 * (self.start[1] + self.end[1]),
        ];
        let along = [self.end[0] - self.start[0], self.end[1] - self.start[1]];
        let length = along[0].hypot(along[1]);
        let direction = if length > 0.0 {
            [along[0] / length, along[1] / length]
        } else {
            [1.0, 0.0]
        };
        (centre, direction, 0.5 * length, 0.5 * self.thickness)
    }

    /// The signed distance of `point` (its x and y) to the slab and the outward normal there.
    pub fn contact(&self, point: Vector) -> Contact {
        let (distance, normal) = crate::physics::slab::signed_distance(
            [point[0], point[1]],
            self.start,
            self.end,
            self.thickness,
        );
        Contact { distance, normal }
    }

    /// The slab's four corners, counter-clockwise (for drawing).
    pub fn corners(&self) -> [[f64; 2]; 4] {
        let (centre, along, half_length, half_thickness) = self.frame();
        let across = [-along[1], along[0]];
        let corner = |s: f64, t: f64| {
            [
                centre[0] + s * half_length * along[0] + t * half_thickness * across[0],
                centre[1] + s * half_length * along[1] + t * half_thickness * across[1],
            ]
        };
        [
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_to_a_tilted_slab_match_geometry() {
        // A slab along the diagonal, 2√2 long, 0.4 thick.
        let slab = Slab {
            start: [-1.0, -1.0],
            end: [1.0, 1.0],
            thickness: 0.4,
        };
        let s = std::f64::consts::FRAC_1_SQRT_2;
        // Above the middle, along the normal (−s, s): distance 1 − 0.2.
        let above = slab.contact([-s, s, 0.0]);
        assert!((above.distance - 0.8).abs() < 1e-12);
        assert!((above.normal[0] + s).abs() < 1e-12 && (above.normal[1] - s).abs() < 1e-12);
        // Inside, near the top face: negative, pointing out of that face.
        let inside = slab.contact([-0.1 * s, 0.1 * s, 5.0]);
        assert!((inside.distance + 0.1).abs() < 1e-12);
        assert!(inside.normal[1] > 0.0);
        // Beyond the end, on the axis: the distance to the end face.
        let beyond = slab.contact([2.0, 2.0, 0.0]);
        assert!((beyond.distance - std::f64::consts::SQRT_2).abs() < 1e-12);
        // Off a corner: Euclidean distance to the corner.
        let corner = slab.corners()[2];
        let probe = [corner[0] + 0.3 * s, corner[1] + 0.3 * s, 0.0];
        assert!((slab.contact(probe).distance - 0.3).abs() < 1e-12);
    }
}
