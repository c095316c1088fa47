//! A small software rasterizer: triangle meshes under the release camera into an RGB image, an
//! instance-id image and a depth buffer, so that every rendered pixel, mask and box comes from
//! the same coverage test.
//!
//! Input: a [`CameraModel`], a static background image, a [`Light`] and the [`Drawable`]s of one
//! frame. Output: a [`Frame`]. Pixels are sampled at their centres with a top-left fill rule (a
//! pixel on an edge shared by two triangles belongs to exactly one), depth is tested on `1/z`
//! (interpolated linearly in screen space, so the test is perspective-correct), and shading is
//! Gouraud: Lambert plus a Blinn highlight per vertex, computed in linear light and written as
//! sRGB. Triangles crossing the near plane are clipped against it. Both faces are drawn.

use super::mesh::{Mesh, Pose, normalized, sub};
use crate::perception::camera::{CameraModel, NEAR_CLIP};

/// One thing to draw.
#[derive(Debug, Clone, Copy)]
pub struct Drawable<'a> {
    /// The mesh, object space.
    pub mesh: &'a Mesh,
    /// Where it is.
    pub pose: Pose,
    /// Surface colour, sRGB in `[0, 1]`.
    pub color: [f64; 3],
    /// Instance id written to the id image (0: not labelled, drawn but left out of masks).
    pub instance: u32,
    /// Stripes painted on the mesh's pattern coordinate ([`Mesh::along`]), if any.
    pub stripes: Option<Stripes>,
}

/// Dark stripes across a patterned surface (the strands of a twisted rope), painted per pixel
/// and box-filtered over the pixel's footprint, so that stripes finer than a pixel blend to
/// their mean shade instead of aliasing into moiré.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stripes {
    /// Length of one light and one dark band together, units of the pattern coordinate.
    pub period: f64,
    /// Share of the period that is dark, in `(0, 1)`.
    pub dark_share: f64,
    /// Brightness factor of the dark band, in `[0, 1]`.
    pub dark: f64,
    /// Softness of the band edges as a share of the period (strands are round, not cut).
    pub softness: f64,
}

impl Stripes {
    /// The brightness factor at pattern coordinate `along`, averaged over a window `footprint`
    /// units wide (at least the edge softness).
    fn tint(&self, along: f64, footprint: f64) -> f64 {
        let period = self.period.max(1e-9);
        let dark_length = self.dark_share.clamp(0.0, 1.0) * period;
        // Dark length from 0 to `u` of the periodic profile (dark band first in each period).
        let cumulative = |u: f64| {
            let cycles = (u / period).floor();
            cycles * dark_length + (u - cycles * period).min(dark_length)
        };
        let window = footprint.max(self.softness * period).max(1e-12);
        let dark_fraction = ((cumulative(along + window / 2.0) - cumulative(along - window / 2.0))
            / window)
            .clamp(0.0, 1.0);
        1.0 - (1.0 - self.dark.clamp(0.0, 1.0)) * dark_fraction
    }
}

/// A directional light with ambient fill.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Unit direction from a surface towards the light.
    pub direction: [f64; 3],
    /// Ambient share of the surface colour.
    pub ambient: f64,
    /// Diffuse (Lambert) share at normal incidence.
    pub diffuse: f64,
    /// Strength of the white highlight.
    pub specular: f64,
    /// Highlight exponent (larger is tighter).
    pub shininess: f64,
}

/// A rendered frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// RGB, row-major from the top-left, 3 bytes per pixel.
    pub rgb: Vec<u8>,
    /// Instance id per pixel (0 for background and unlabelled objects).
    pub instance: Vec<u32>,
    /// `1/z` per pixel (0 where nothing was drawn), for depth tests and checks.
    pub inverse_depth: Vec<f32>,
}

/// A vertex after transformation: screen position, `1/z`, its colour and pattern coordinate
/// divided by `z`, and the pattern coordinate itself (for the footprint of a pixel).
#[derive(Debug, Clone, Copy)]
struct ScreenVertex {
    x: f64,
    y: f64,
    inverse_z: f64,
    color_over_z: [f64; 3],
    along_over_z: f64,
    along: f64,
}

/// A vertex in camera space with its shaded linear colour and pattern coordinate.
#[derive(Debug, Clone, Copy)]
struct CameraVertex {
    position: [f64; 3],
    color: [f64; 3],
    along: f64,
}

/// Renders `drawables` over `background` (an RGB image of the camera's size).
pub fn render(
    camera: &CameraModel,
    background: &[u8],
    light: &Light,
    drawables: &[Drawable<'_>],
) -> Frame {
    let width = camera.width;
    let height = camera.height;
    let pixels = width as usize * height as usize;
    let mut frame = Frame {
        width,
        height,
        rgb: if background.len() == pixels * 3 {
            background.to_vec()
        } else {
            vec![0; pixels * 3]
        },
        instance: vec![0; pixels],
        inverse_depth: vec![0.0; pixels],
    };
    for drawable in drawables {
        draw(&mut frame, camera, light, drawable);
    }
    frame
}

fn draw(frame: &mut Frame, camera: &CameraModel, light: &Light, drawable: &Drawable<'_>) {
    let linear = drawable.color.map(srgb_to_linear);
    let mesh = drawable.mesh;
    let vertices: Vec<CameraVertex> = mesh
        .positions
        .iter()
        .zip(&mesh.normals)
        .enumerate()
        .map(|(index, (position, normal))| {
            let world = drawable.pose.apply(*position);
            let mut n = drawable.pose.apply_direction(*normal);
            let to_eye = normalized(sub(camera.position, world));
            // Two-sided lighting: a face seen from behind is lit as if it faced the camera.
            if dot(n, to_eye) < 0.0 {
                n = n.map(|c| -c);
            }
            let lambert = dot(n, light.direction).max(0.0);
            let half = normalized([
                light.direction[0] + to_eye[0],
                light.direction[1] + to_eye[1],
                light.direction[2] + to_eye[2],
            ]);
            let highlight = light.specular * dot(n, half).max(0.0).powf(light.shininess);
            let shade = light.ambient + light.diffuse * lambert;
            let color = linear.map(|c| c * shade + highlight);
            CameraVertex {
                position: camera.to_camera(world),
                color,
                along: mesh.along.get(index).copied().unwrap_or(0.0),
            }
        })
        .collect();
    for triangle in &mesh.triangles {
        let corners = triangle.map(|index| vertices.get(index as usize).copied());
        let [Some(a), Some(b), Some(c)] = corners else {
            continue;
        };
        for clipped in clip_near(&[a, b, c]) {
            let screen = clipped.map(|v| to_screen(camera, &v));
            let [Some(p0), Some(p1), Some(p2)] = screen else {
                continue;
            };
            fill(frame, [p0, p1, p2], drawable.instance, drawable.stripes);
        }
    }
}

fn to_screen(camera: &CameraModel, vertex: &CameraVertex) -> Option<ScreenVertex> {
    let projected = camera.project_camera(vertex.position)?;
    let inverse_z = 1.0 / projected.depth;
    Some(ScreenVertex {
        x: projected.x,
        y: projected.y,
        inverse_z,
        color_over_z: vertex.color.map(|c| c * inverse_z),
        along_over_z: vertex.along * inverse_z,
        along: vertex.along,
    })
}

/// Clips a triangle against the plane just in front of the near plane; 0, 1 or 2 triangles.
fn clip_near(triangle: &[CameraVertex; 3]) -> Vec<[CameraVertex; 3]> {
    let plane = NEAR_CLIP * 1.001;
    let inside = |v: &CameraVertex| v.position[2] >= plane;
    if triangle.iter().all(inside) {
        return vec![*triangle];
    }
    let mut polygon: Vec<CameraVertex> = Vec::with_capacity(4);
    for index in 0..3 {
        let current = triangle[index];
        let next = triangle[(index + 1) % 3];
        if inside(&current) {
            polygon.push(current);
        }
        if inside(&current) != inside(&next) {
            let t = (plane - current.position[2]) / (next.position[2] - current.position[2]);
            let lerp = |a: f64, b: f64| a + t * (b - a);
            polygon.push(CameraVertex {
                position: [
                    lerp(current.position[0], next.position[0]),
                    lerp(current.position[1], next.position[1]),
                    plane,
                ],
                color: [
                    lerp(current.color[0], next.color[0]),
                    lerp(current.color[1], next.color[1]),
                    lerp(current.color[2], next.color[2]),
                ],
                along: lerp(current.along, next.along),
            });
        }
    }
    (1..polygon.len().saturating_sub(1))
        .map(|i| [polygon[0], polygon[i], polygon[i + 1]])
        .collect()
}

/// Edge function: twice the signed area of `(a, b, p)`.
fn edge(a: (f64, f64), b: (f64, f64), p: (f64, f64)) -> f64 {
    (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0)
}

/// Whether an edge `a → b` of a counter-clockwise (in pixel space, y down) triangle is a top or
/// left edge: pixels exactly on it are drawn.
fn is_top_left(a: (f64, f64), b: (f64, f64)) -> bool {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    (dy == 0.0 && dx > 0.0) || dy < 0.0
}

fn fill(frame: &mut Frame, vertices: [ScreenVertex; 3], instance: u32, stripes: Option<Stripes>) {
    let mut v = vertices;
    let point = |s: &ScreenVertex| (s.x, s.y);
    let mut area = edge(point(&v[0]), point(&v[1]), point(&v[2]));
    if !area.is_finite() || area == 0.0 {
        return;
    }
    if area < 0.0 {
        v.swap(1, 2);
        area = -area;
    }
    let (p0, p1, p2) = (point(&v[0]), point(&v[1]), point(&v[2]));
    // How far the pattern coordinate moves across one pixel (the triangle's affine gradient):
    // the window its stripes are averaged over.
    let footprint = {
        let (du1, du2) = (v[1].along - v[0].along, v[2].along - v[0].along);
        let (dx1, dy1) = (p1.0 - p0.0, p1.1 - p0.1);
        let (dx2, dy2) = (p2.0 - p0.0, p2.1 - p0.1);
        let gradient_x = (du1 * dy2 - du2 * dy1) / area;
        let gradient_y = (du2 * dx1 - du1 * dx2) / area;
        gradient_x.abs() + gradient_y.abs()
    };
    let width = f64::from(frame.width);
    let height = f64::from(frame.height);
    let min_x = p0.0.min(p1.0).min(p2.0).floor().max(0.0);
    let max_x = p0.0.max(p1.0).max(p2.0).ceil().min(width);
    let min_y = p0.1.min(p1.1).min(p2.1).floor().max(0.0);
    let max_y = p0.1.max(p1.1).max(p2.1).ceil().min(height);
    if min_x >= max_x || min_y >= max_y {
        return;
    }
    let biases = [
        if is_top_left(p1, p2) {
            0.0
        } else {
            f64::EPSILON
        },
        if is_top_left(p2, p0) {
            0.0
        } else {
            f64::EPSILON
        },
        if is_top_left(p0, p1) {
            0.0
        } else {
            f64::EPSILON
        },
    ];
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "bounds clamped to the image above"
    )]
    let (x_range, y_range) = (
        (min_x as usize)..(max_x as usize),
        (min_y as usize)..(max_y as usize),
    );
    let row_length = frame.width as usize;
    for y in y_range {
        let centre_y = y as f64 + 0.5;
        for x in x_range.clone() {
            let p = (x as f64 + 0.5, centre_y);
            let w0 = edge(p1, p2, p);
            let w1 = edge(p2, p0, p);
            let w2 = edge(p0, p1, p);
            if w0 < biases[0] || w1 < biases[1] || w2 < biases[2] {
                continue;
            }
            let (b0, b1, b2) = (w0 / area, w1 / area, w2 / area);
            let inverse_z = b0 * v[0].inverse_z + b1 * v[1].inverse_z + b2 * v[2].inverse_z;
            let index = y * row_length + x;
            #[expect(
                clippy::cast_possible_truncation,
                reason = "depth precision of f32 is ample for ordering surfaces"
            )]
            let depth = inverse_z as f32;
            if depth <= frame.inverse_depth[index] {
                continue;
            }
            frame.inverse_depth[index] = depth;
            frame.instance[index] = instance;
            let tint = stripes.map_or(1.0, |stripes| {
                let along_over_z =
                    b0 * v[0].along_over_z + b1 * v[1].along_over_z + b2 * v[2].along_over_z;
                stripes.tint(along_over_z / inverse_z, footprint)
            });
            for channel in 0..3 {
                let over_z = b0 * v[0].color_over_z[channel]
                    + b1 * v[1].color_over_z[channel]
                    + b2 * v[2].color_over_z[channel];
                frame.rgb[index * 3 + channel] = linear_to_srgb_byte(tint * over_z / inverse_z);
            }
        }
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// sRGB `[0, 1]` to linear light.
pub fn srgb_to_linear(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light to an sRGB byte (clamped).
pub fn linear_to_srgb_byte(c: f64) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "clamped to [0, 255] first"
    )]
    let byte = (s * 255.0).round().clamp(0.0, 255.0) as u8;
    byte
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> CameraModel {
        CameraModel::looking_at([0.0, 0.0, -20.0], [0.0, 0.0, 0.0], 40.0, 320, 240)
    }

    fn light() -> Light {
        Light {
            direction: normalized([0.3, 0.5, -1.0]),
            ambient: 0.5,
            diffuse: 0.6,
            specular: 0.0,
            shininess: 16.0,
        }
    }

    #[test]
    fn a_cube_covers_its_projected_outline_and_nearer_objects_win() {
        let camera = camera();
        let cube = Mesh::cuboid([2.0, 2.0, 2.0]);
        let sphere = Mesh::sphere(0.5, 16, 8);
        let drawables = [
            Drawable {
                mesh: &cube,
                pose: Pose::at([0.0, 0.0, 0.0]),
                color: [1.0, 0.0, 0.0],
                instance: 7,
                stripes: None,
            },
            // In front of the cube (towards the camera at −z).
            Drawable {
                mesh: &sphere,
                pose: Pose::at([0.0, 0.0, -2.0]),
                color: [0.0, 0.0, 1.0],
                instance: 9,
                stripes: None,
            },
        ];
        let frame = render(&camera, &[], &light(), &drawables);
        let at = |x: usize, y: usize| frame.instance[y * 320 + x];
        assert_eq!(at(160, 120), 9, "the sphere is nearer");
        // The cube's front face spans x ∈ [−1, 1] at depth 19: ±f·1/19 in NDC.
        let front = camera.project([1.0, 0.0, -1.0]).unwrap();
        let right_edge = front.x;
        #[expect(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let inside = (right_edge - 1.5) as usize;
        #[expect(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let outside = (right_edge + 1.5) as usize;
        assert_eq!(at(inside, 120), 7);
        assert_eq!(at(outside, 120), 0);
        // Colour follows the instance: red where the cube shows.
        let pixel = &frame.rgb[(120 * 320 + inside) * 3..][..3];
        assert!(
            pixel[0] > 100 && pixel[1] == 0 && pixel[2] == 0,
            "{pixel:?}"
        );
    }

    #[test]
    fn shared_edges_are_drawn_once_and_no_pixel_is_lost() {
        // A quad split along its diagonal, each half rendered alone: with the top-left rule no
        // pixel belongs to both halves, and together they cover exactly the whole quad.
        let camera = camera();
        let quad = Mesh {
            positions: vec![
                [-3.0, -3.0, 0.0],
                [3.0, -2.0, 0.0],
                [3.0, 3.0, 0.0],
                [-3.0, 3.0, 0.0],
            ],
            normals: vec![[0.0, 0.0, -1.0]; 4],
            along: vec![0.0; 4],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        };
        let covered = |triangles: Vec<[u32; 3]>| {
            let mut mesh = quad.clone();
            mesh.triangles = triangles;
            let drawables = [Drawable {
                mesh: &mesh,
                pose: Pose::at([0.0; 3]),
                color: [1.0; 3],
                instance: 1,
                stripes: None,
            }];
            render(&camera, &[], &light(), &drawables)
                .instance
                .iter()
                .map(|&i| i == 1)
                .collect::<Vec<bool>>()
        };
        let first = covered(vec![[0, 1, 2]]);
        let second = covered(vec![[0, 2, 3]]);
        let whole = covered(vec![[0, 1, 2], [0, 2, 3]]);
        let both = first
            .iter()
            .zip(&second)
            .filter(|(a, b)| **a && **b)
            .count();
        let either: Vec<bool> = first.iter().zip(&second).map(|(a, b)| *a || *b).collect();
        assert!(first.iter().any(|&c| c) && second.iter().any(|&c| c));
        assert_eq!(both, 0, "pixels on the diagonal are drawn twice");
        assert_eq!(either, whole, "pixels on the diagonal are dropped");
    }

    #[test]
    fn geometry_behind_the_camera_is_clipped_not_wrapped() {
        let camera = camera();
        // A long bar from behind the camera to in front of it, off to the side.
        let bar = Mesh::cuboid([0.5, 0.5, 60.0]);
        let drawables = [Drawable {
            mesh: &bar,
            pose: Pose::at([2.0, 0.0, -20.0]),
            color: [0.0, 1.0, 0.0],
            instance: 4,
            stripes: None,
        }];
        let frame = render(&camera, &[], &light(), &drawables);
        let covered = frame.instance.iter().filter(|&&i| i == 4).count();
        assert!(covered > 0);
        // Everything drawn lies right of the image centre (the bar is at x = +2).
        for (index, &id) in frame.instance.iter().enumerate() {
            if id == 4 {
                assert!(
                    index % 320 >= 160,
                    "pixel {index} wrapped to the wrong side"
                );
            }
        }
    }

    #[test]
    fn stripes_are_dark_in_their_band_and_blend_to_their_mean_when_finer_than_a_pixel() {
        let stripes = Stripes {
            period: 1.0,
            dark_share: 0.4,
            dark: 0.3,
            softness: 0.01,
        };
        // Middle of the dark band [0, 0.4) and of the light band [0.4, 1).
        assert!((stripes.tint(0.2, 0.0) - 0.3).abs() < 1e-12);
        assert!((stripes.tint(3.7, 0.0) - 1.0).abs() < 1e-12);
        // Averaged over ten periods: 40% dark at 0.3, 60% light.
        let mean = 1.0 - 0.7 * 0.4;
        assert!((stripes.tint(0.123, 10.0) - mean).abs() < 1e-12);
        // Drawn on a tube seen side-on: coarse stripes alternate along it, fine ones do not.
        let camera = camera();
        let path: Vec<[f64; 3]> = (0..=8).map(|i| [f64::from(i) - 4.0, 0.0, 0.0]).collect();
        let tube = Mesh::tube(&path, 0.5, 12, Some(0.0));
        let row = |period: f64| {
            let drawables = [Drawable {
                mesh: &tube,
                pose: Pose::at([0.0; 3]),
                color: [0.8; 3],
                instance: 1,
                stripes: Some(Stripes { period, ..stripes }),
            }];
            let frame = render(&camera, &[], &light(), &drawables);
            (100..220)
                .filter(|&x| frame.instance[120 * 320 + x] == 1)
                .map(|x| frame.rgb[(120 * 320 + x) * 3])
                .collect::<Vec<u8>>()
        };
        let spread = |values: &[u8]| {
            let low = values.iter().min().copied().unwrap_or(0);
            let high = values.iter().max().copied().unwrap_or(0);
            high - low
        };
        let coarse = row(2.0);
        let fine = row(0.002);
        assert!(coarse.len() > 100 && fine.len() == coarse.len());
        assert!(spread(&coarse) > 60, "coarse stripes alternate: {coarse:?}");
        assert!(spread(&fine) < 4, "fine stripes blend: {fine:?}");
    }

    #[test]
    fn srgb_round_trips() {
        for byte in [0_u8, 1, 10, 100, 128, 200, 255] {
            let c = f64::from(byte) / 255.0;
            assert_eq!(linear_to_srgb_byte(srgb_to_linear(c)), byte);
        }
    }
}
