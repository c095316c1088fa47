//! Triangle meshes of the scene primitives (boxes, spheres, cylinders, rings, tubes along a
//! path), in object space with unit normals per vertex, and the rigid transforms that place them.
//!
//! Units are world units (nominally metres); cylinders and rings have their axis along `z`,
//! which is the axis rope pulleys turn about.

use std::f64::consts::TAU;

use crate::perception::camera::{Rotation, rotate};

/// A triangle mesh. Winding is not relied on (the rasterizer draws both faces).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions, object space.
    pub positions: Vec<[f64; 3]>,
    /// Unit normals, one per vertex.
    pub normals: Vec<[f64; 3]>,
    /// Pattern coordinate per vertex, units (arc length along a tube plus its twist; 0 on
    /// meshes without a pattern). The rasterizer paints stripes on it per pixel
    /// ([`super::raster::Stripes`]), so stripes stay sharp however far apart the vertices are.
    pub along: Vec<f64>,
    /// Triangles as vertex indices.
    pub triangles: Vec<[u32; 3]>,
}

/// A rigid placement: `world = rotation · (scale ∘ p) + translation`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Rotation, row-major.
    pub rotation: Rotation,
    /// Translation, units.
    pub translation: [f64; 3],
}

impl Pose {
    /// The identity placement at `translation`.
    pub fn at(translation: [f64; 3]) -> Pose {
        Pose {
            rotation: IDENTITY,
            translation,
        }
    }

    /// A placement turned by `angle` radians about `z` (counter-clockwise seen from −z).
    pub fn turned_about_z(translation: [f64; 3], angle: f64) -> Pose {
        let (s, c) = angle.sin_cos();
        Pose {
            rotation: [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
            translation,
        }
    }

    /// Places an object-space point.
    pub fn apply(&self, point: [f64; 3]) -> [f64; 3] {
        let r = rotate(&self.rotation, point);
        [
            r[0] + self.translation[0],
            r[1] + self.translation[1],
            r[2] + self.translation[2],
        ]
    }

    /// Turns an object-space direction.
    pub fn apply_direction(&self, direction: [f64; 3]) -> [f64; 3] {
        rotate(&self.rotation, direction)
    }
}

/// The identity rotation.
pub const IDENTITY: Rotation = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

impl Mesh {
    fn push(&mut self, position: [f64; 3], normal: [f64; 3]) -> u32 {
        self.positions.push(position);
        self.normals.push(normal);
        self.along.push(0.0);
        u32::try_from(self.positions.len() - 1).unwrap_or(u32::MAX)
    }

    /// Appends a quad (`corners` in order round it, each with its normal) as two triangles.
    fn push_quad(&mut self, corners: [([f64; 3], [f64; 3]); 4]) {
        let v = corners.map(|(position, normal)| self.push(position, normal));
        self.triangles.push([v[0], v[1], v[2]]);
        self.triangles.push([v[0], v[2], v[3]]);
    }

    /// Appends the piece of a cylinder wall of radius `r` about `z` between angles `a0` and
    /// `a1`, from `z = −half_length` to `half_length`, with normals pointing away from the axis
    /// (`outward`) or towards it; the triangles wind counter-clockwise seen from the side the
    /// normals point to.
    fn push_wall(&mut self, r: f64, [a0, a1]: [f64; 2], half_length: f64, outward: bool) {
        let sign = if outward { 1.0 } else { -1.0 };
        let point = |angle: f64, z: f64| [r * angle.cos(), r * angle.sin(), z];
        let n0 = [sign * a0.cos(), sign * a0.sin(), 0.0];
        let n1 = [sign * a1.cos(), sign * a1.sin(), 0.0];
        let corners = [
            (point(a0, -half_length), n0),
            (point(a1, -half_length), n1),
            (point(a1, half_length), n1),
            (point(a0, half_length), n0),
        ];
        let v = corners.map(|(position, normal)| self.push(position, normal));
        if outward {
            self.triangles.push([v[0], v[1], v[2]]);
            self.triangles.push([v[0], v[2], v[3]]);
        } else {
            self.triangles.push([v[0], v[2], v[1]]);
            self.triangles.push([v[0], v[3], v[2]]);
        }
    }

    /// Appends `other` (its indices shifted).
    pub fn merge(&mut self, other: &Mesh) {
        let offset = u32::try_from(self.positions.len()).unwrap_or(u32::MAX);
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.along.extend_from_slice(&other.along);
        self.triangles.extend(
            other
                .triangles
                .iter()
                .map(|t| [t[0] + offset, t[1] + offset, t[2] + offset]),
        );
    }

    /// A copy with every vertex moved by `pose` (normals turned).
    #[must_use]
    pub fn transformed(&self, pose: &Pose) -> Mesh {
        Mesh {
            positions: self.positions.iter().map(|p| pose.apply(*p)).collect(),
            normals: self
                .normals
                .iter()
                .map(|n| pose.apply_direction(*n))
                .collect(),
            along: self.along.clone(),
            triangles: self.triangles.clone(),
        }
    }

    /// An axis-aligned box centred at the origin with the given full sizes.
    pub fn cuboid(size: [f64; 3]) -> Mesh {
        let half = size.map(|s| s / 2.0);
        let mut mesh = Mesh::default();
        // Six faces, each with its own four vertices so normals stay flat.
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                let mut normal = [0.0; 3];
                normal[axis] = sign;
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let corners: Vec<u32> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .iter()
                    .map(|(a, b)| {
                        let mut p = [0.0; 3];
                        p[axis] = sign * half[axis];
                        p[u] = a * half[u];
                        p[v] = b * half[v];
                        mesh.push(p, normal)
                    })
                    .collect();
                mesh.triangles.push([corners[0], corners[1], corners[2]]);
                mesh.triangles.push([corners[0], corners[2], corners[3]]);
            }
        }
        mesh
    }

    /// A UV sphere of `radius` centred at the origin.
    pub fn sphere(radius: f64, segments: u32, rings: u32) -> Mesh {
        let mut mesh = Mesh::default();
        for ring in 0..=rings {
            let polar = std::f64::consts::PI * f64::from(ring) / f64::from(rings);
            for segment in 0..=segments {
                let azimuth = TAU * f64::from(segment) / f64::from(segments);
                let normal = [
                    polar.sin() * azimuth.cos(),
                    polar.cos(),
                    polar.sin() * azimuth.sin(),
                ];
                mesh.push(normal.map(|c| c * radius), normal);
            }
        }
        let row = segments + 1;
        for ring in 0..rings {
            for segment in 0..segments {
                let a = ring * row + segment;
                let b = a + row;
                mesh.triangles.push([a, b, a + 1]);
                mesh.triangles.push([a + 1, b, b + 1]);
            }
        }
        mesh
    }

    /// A closed cylinder (a disc with thickness) of `radius` about the `z` axis, from
    /// `z = -half_length` to `z = half_length`.
    pub fn cylinder(radius: f64, half_length: f64, segments: u32) -> Mesh {
        Mesh::ring(0.0, radius, half_length, segments)
    }

    /// An annulus with thickness about the `z` axis: inner and outer radius, faces at
    /// `z = ±half_length`. An inner radius of 0 makes a solid cylinder.
    pub fn ring(inner: f64, outer: f64, half_length: f64, segments: u32) -> Mesh {
        let mut mesh = Mesh::default();
        let point = |r: f64, angle: f64, z: f64| [r * angle.cos(), r * angle.sin(), z];
        for index in 0..segments {
            let a0 = TAU * f64::from(index) / f64::from(segments);
            let a1 = TAU * f64::from(index + 1) / f64::from(segments);
            mesh.push_wall(outer, [a0, a1], half_length, true);
            if inner > 0.0 {
                mesh.push_wall(inner, [a0, a1], half_length, false);
            }
            // Both faces.
            for (z, normal) in [
                (half_length, [0.0, 0.0, 1.0]),
                (-half_length, [0.0, 0.0, -1.0]),
            ] {
                let outer0 = mesh.push(point(outer, a0, z), normal);
                let outer1 = mesh.push(point(outer, a1, z), normal);
                let inner0 = mesh.push(point(inner, a0, z), normal);
                let inner1 = mesh.push(point(inner, a1, z), normal);
                mesh.triangles.push([inner0, outer0, outer1]);
                if inner > 0.0 {
                    mesh.triangles.push([inner0, outer1, inner1]);
                }
            }
        }
        mesh
    }

    /// A tube of `radius` along a polyline (at least two points), with `sides` facets.
    ///
    /// With `twist: Some(t)` the tube carries a pattern coordinate for painted stripes: arc
    /// length plus `t · radius · angle` around the tube, so stripes wind round it as the strands
    /// of the release's twisted rope do (`t = 0`: rings straight across). Each ring then has one
    /// more vertex closing the seam, so the coordinate is never interpolated across the jump
    /// from a full turn back to zero. `None` keeps the plain layout (`sides` vertices a ring), as
    /// `outputs4D.json` stores it.
    pub fn tube(path: &[[f64; 3]], radius: f64, sides: u32, twist: Option<f64>) -> Mesh {
        let mut mesh = Mesh::default();
        if path.len() < 2 {
            return mesh;
        }
        let ring_vertices = if twist.is_some() { sides + 1 } else { sides };
        let mut length = 0.0;
        let mut rings: Vec<u32> = Vec::with_capacity(path.len());
        for (index, point) in path.iter().enumerate() {
            if index > 0 {
                length += distance(path[index - 1], *point);
            }
            let before = path[index.saturating_sub(1)];
            let after = path[(index + 1).min(path.len() - 1)];
            let tangent = normalized(sub(after, before));
            // A frame perpendicular to the tangent; ropes lie in planes of constant z, so z
            // (or x for a tangent along z) is never parallel to it.
            let helper = if tangent[2].abs() < 0.9 {
                [0.0, 0.0, 1.0]
            } else {
                [1.0, 0.0, 0.0]
            };
            let side = normalized(cross(tangent, helper));
            let up = cross(side, tangent);
            let first = u32::try_from(mesh.positions.len()).unwrap_or(u32::MAX);
            for facet in 0..ring_vertices {
                let angle = TAU * f64::from(facet) / f64::from(sides);
                let normal = [
                    side[0] * angle.cos() + up[0] * angle.sin(),
                    side[1] * angle.cos() + up[1] * angle.sin(),
                    side[2] * angle.cos() + up[2] * angle.sin(),
                ];
                let position = [
                    point[0] + radius * normal[0],
                    point[1] + radius * normal[1],
                    point[2] + radius * normal[2],
                ];
                let vertex = mesh.push(position, normal);
                mesh.along[vertex as usize] = length + twist.unwrap_or(0.0) * radius * angle;
            }
            rings.push(first);
        }
        for pair in rings.windows(2) {
            for facet in 0..sides {
                let next = if twist.is_some() {
                    facet + 1
                } else {
                    (facet + 1) % sides
                };
                let (a, b) = (pair[0] + facet, pair[0] + next);
                let (c, d) = (pair[1] + facet, pair[1] + next);
                mesh.triangles.push([a, c, b]);
                mesh.triangles.push([b, c, d]);
            }
        }
        mesh
    }

    /// A pulley's web with `holes` kidney-shaped openings, as the release's hollow pulley has:
    /// a flat annulus between `hub` and `rim` radii, faces at `z = ±half_length`, with the cells
    /// between radii `hole_inner` and `hole_outer` left open over `hole_angle` radians around
    /// each of the `holes` evenly spaced directions. The hole walls are drawn too.
    pub fn holed_web(
        radii: [f64; 4],
        half_length: f64,
        holes: u32,
        hole_angle: f64,
        segments: u32,
    ) -> Mesh {
        let [hub, hole_inner, hole_outer, rim] = radii;
        let mut mesh = Mesh::default();
        let point = |r: f64, angle: f64, z: f64| [r * angle.cos(), r * angle.sin(), z];
        let is_open = |angle: f64| {
            let spacing = TAU / f64::from(holes.max(1));
            let offset = (angle.rem_euclid(spacing) - spacing / 2.0).abs();
            offset < hole_angle / 2.0
        };
        let bands = [
            (hub, hole_inner),
            (hole_inner, hole_outer),
            (hole_outer, rim),
        ];
        for index in 0..segments {
            let a0 = TAU * f64::from(index) / f64::from(segments);
            let a1 = TAU * f64::from(index + 1) / f64::from(segments);
            let open = holes > 0 && is_open(f64::midpoint(a0, a1));
            for (band, (inner, outer)) in bands.iter().enumerate() {
                if band == 1 && open {
                    continue;
                }
                for (z, normal) in [
                    (half_length, [0.0, 0.0, 1.0]),
                    (-half_length, [0.0, 0.0, -1.0]),
                ] {
                    mesh.push_quad([
                        (point(*inner, a0, z), normal),
                        (point(*outer, a0, z), normal),
                        (point(*outer, a1, z), normal),
                        (point(*inner, a1, z), normal),
                    ]);
                }
            }
            if open {
                // The walls of the opening at its inner and outer radius.
                mesh.push_wall(hole_inner, [a0, a1], half_length, true);
                mesh.push_wall(hole_outer, [a0, a1], half_length, false);
            }
        }
        mesh
    }

    /// Axis-aligned bounds `(min, max)` of the vertices; `None` for an empty mesh.
    pub fn bounds(&self) -> Option<([f64; 3], [f64; 3])> {
        let first = *self.positions.first()?;
        let mut low = first;
        let mut high = first;
        for p in &self.positions {
            for axis in 0..3 {
                low[axis] = low[axis].min(p[axis]);
                high[axis] = high[axis].max(p[axis]);
            }
        }
        Some((low, high))
    }
}

/// `a − b`.
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a × b`.
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `|a − b|`.
pub fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(a, b);
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// `v / |v|` (the `z` axis for a zero vector).
pub fn normalized(v: [f64; 3]) -> [f64; 3] {
    let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if length > 0.0 {
        v.map(|c| c / length)
    } else {
        [0.0, 0.0, 1.0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitives_have_the_asked_extents_and_unit_normals() {
        let cases = [
            (Mesh::cuboid([2.24, 2.24, 2.0]), [1.12, 1.12, 1.0]),
            (Mesh::sphere(1.0, 24, 12), [1.0, 1.0, 1.0]),
            (Mesh::cylinder(1.74, 0.29, 48), [1.74, 1.74, 0.29]),
            (Mesh::ring(1.0, 1.61, 0.17, 48), [1.61, 1.61, 0.17]),
        ];
        for (mesh, half) in cases {
            let (low, high) = mesh.bounds().unwrap();
            for axis in 0..3 {
                assert!(
                    (high[axis] - half[axis]).abs() < 1e-9,
                    "{high:?} vs {half:?}"
                );
                assert!((low[axis] + half[axis]).abs() < 1e-9, "{low:?} vs {half:?}");
            }
            assert_eq!(mesh.normals.len(), mesh.positions.len());
            for n in &mesh.normals {
                assert!(((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() - 1.0).abs() < 1e-12);
            }
            let count = u32::try_from(mesh.positions.len()).unwrap();
            assert!(mesh.triangles.iter().flatten().all(|&i| i < count));
        }
    }

    #[test]
    fn a_holed_web_is_open_in_its_holes_and_closed_on_its_spokes_and_rim() {
        let radii = [0.5, 0.65, 1.2, 1.3];
        let hole_angle = 1.4;
        let web = Mesh::holed_web(radii, 0.1, 3, hole_angle, 72);
        // The front face's triangles, in the plane.
        let front: Vec<[[f64; 2]; 3]> = web
            .triangles
            .iter()
            .filter(|t| t.iter().all(|&i| web.normals[i as usize][2] > 0.5))
            .map(|t| t.map(|i| [web.positions[i as usize][0], web.positions[i as usize][1]]))
            .collect();
        let covered = |r: f64, angle: f64| {
            let p = [r * angle.cos(), r * angle.sin()];
            front.iter().any(|[a, b, c]| {
                let side = |u: [f64; 2], v: [f64; 2]| {
                    (v[0] - u[0]) * (p[1] - u[1]) - (v[1] - u[1]) * (p[0] - u[0])
                };
                let (d0, d1, d2) = (side(*a, *b), side(*b, *c), side(*c, *a));
                (d0 >= 0.0 && d1 >= 0.0 && d2 >= 0.0) || (d0 <= 0.0 && d1 <= 0.0 && d2 <= 0.0)
            })
        };
        // Holes centre between the spokes (60°, 180°, 300°); spokes at 0°, 120°, 240°.
        for hole in 0..3 {
            let centre = TAU / 6.0 + f64::from(hole) * TAU / 3.0;
            assert!(!covered(0.9, centre), "hole {hole} is open");
            assert!(covered(0.9, centre - TAU / 6.0), "spoke {hole} is closed");
            assert!(
                covered(1.25, centre) && covered(0.57, centre),
                "rim and hub rings"
            );
        }
        // Area of the face: the annulus less three sectors (polygonal, 5° segments).
        let area: f64 = front
            .iter()
            .map(|[a, b, c]| {
                ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs() / 2.0
            })
            .sum();
        let segment = TAU / 72.0;
        let open_segments = (0..72)
            .filter(|&i| {
                let mid = (f64::from(i) + 0.5) * segment;
                ((mid.rem_euclid(TAU / 3.0)) - TAU / 6.0).abs() < hole_angle / 2.0
            })
            .count();
        let wedge = |r: f64| r * r * segment.sin() / 2.0;
        #[expect(clippy::cast_precision_loss, reason = "a count below 72")]
        let expected =
            72.0 * (wedge(1.3) - wedge(0.5)) - open_segments as f64 * (wedge(1.2) - wedge(0.65));
        assert!((area - expected).abs() < 1e-9, "{area} vs {expected}");
        assert_eq!(open_segments, 3 * 16, "80° holes of 5° segments");
    }

    #[test]
    fn a_tube_follows_its_path_at_its_radius() {
        let path = [[0.0, 0.0, 0.0], [0.0, 5.0, 0.0], [3.0, 5.0, 0.0]];
        let tube = Mesh::tube(&path, 0.2, 8, None);
        assert_eq!(tube.positions.len(), 24);
        assert_eq!(tube.triangles.len(), 2 * 2 * 8);
        for (index, p) in tube.positions.iter().enumerate() {
            let centre = path[index / 8];
            let d = distance(*p, centre);
            // Corners are mitred by the averaged tangent, so the ring there is the same circle.
            assert!((d - 0.2).abs() < 1e-12, "vertex {index} at {d}");
        }
        // Plain tubes: one coordinate per ring, the arc length (0, 5, 8).
        assert!((tube.along[8] - 5.0).abs() < 1e-12 && (tube.along[23] - 8.0).abs() < 1e-12);
        // Patterned tubes close the seam with a ninth vertex whose coordinate has turned once.
        let twisted = Mesh::tube(&path, 0.2, 8, Some(0.5));
        assert_eq!(twisted.positions.len(), 27);
        assert_eq!(twisted.triangles.len(), 2 * 2 * 8);
        assert!((twisted.along[8] - 0.5 * 0.2 * TAU).abs() < 1e-12);
        assert!(distance(twisted.positions[8], twisted.positions[0]) < 1e-12);
    }

    #[test]
    fn poses_turn_counter_clockwise_about_z() {
        let pose = Pose::turned_about_z([1.0, 2.0, 0.0], std::f64::consts::FRAC_PI_2);
        let p = pose.apply([1.0, 0.0, 0.0]);
        assert!((p[0] - 1.0).abs() < 1e-12 && (p[1] - 3.0).abs() < 1e-12);
    }
}
