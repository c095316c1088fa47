//! The release camera: Unity's pinhole camera with Euler angles applied Z, then X, then Y, in a
//! left-handed world (x right, y up, z forward), projecting to pixels with y pointing down
//! (`docs/data/common.md`, camera, verified on the real rope video to within a pixel of its
//! bounding boxes).
//!
//! Input: position (world units), Euler angles (degrees), vertical field of view (degrees) and the
//! image size. Output: pixel coordinates of world points, camera-space depths, and the records the
//! release writes for a capture (rotation quaternion `[x, y, z, w]`, the 3×3 NDC intrinsic).

/// Near and far clip planes of the release cameras, world units (the intrinsic's third row:
/// `-(far + near) / (far - near) = -1.0006001`).
pub const NEAR_CLIP: f64 = 0.3;
/// See [`NEAR_CLIP`].
pub const FAR_CLIP: f64 = 1000.0;

/// A 3×3 rotation, row-major.
pub type Rotation = [[f64; 3]; 3];

/// A perspective camera as Unity models it.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraModel {
    /// World position, units.
    pub position: [f64; 3],
    /// World-from-camera rotation (columns: the camera's right, up and forward axes in world).
    pub rotation: Rotation,
    /// Vertical field of view, degrees.
    pub vertical_fov_deg: f64,
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
}

/// A point in camera space and on the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projected {
    /// Pixel column (0 at the left edge), sub-pixel.
    pub x: f64,
    /// Pixel row (0 at the top edge), sub-pixel.
    pub y: f64,
    /// Distance along the viewing axis, units (positive in front of the camera).
    pub depth: f64,
}

impl CameraModel {
    /// A camera from Unity's Euler angles (degrees, applied Z, X, Y).
    pub fn from_unity_euler(
        position: [f64; 3],
        euler_deg: [f64; 3],
        vertical_fov_deg: f64,
        width: u32,
        height: u32,
    ) -> CameraModel {
        CameraModel {
            position,
            rotation: unity_euler_rotation(euler_deg),
            vertical_fov_deg,
            width,
            height,
        }
    }

    /// A camera at `position` looking at `target`, with no roll (world up stays up on screen).
    pub fn looking_at(
        position: [f64; 3],
        target: [f64; 3],
        vertical_fov_deg: f64,
        width: u32,
        height: u32,
    ) -> CameraModel {
        let forward = normalize(sub(target, position));
        // Unity's yaw and pitch of a forward vector (Quaternion.LookRotation with up = +y).
        let yaw = forward[0].atan2(forward[2]);
        let pitch = (-forward[1]).clamp(-1.0, 1.0).asin();
        let euler = [pitch.to_degrees(), yaw.to_degrees(), 0.0];
        CameraModel::from_unity_euler(position, euler, vertical_fov_deg, width, height)
    }

    /// `f = 1 / tan(vfov / 2)`.
    pub fn focal(&self) -> f64 {
        1.0 / (self.vertical_fov_deg.to_radians() / 2.0).tan()
    }

    /// Width over height.
    pub fn aspect(&self) -> f64 {
        f64::from(self.width) / f64::from(self.height)
    }

    /// A world point in camera space (`x` right, `y` up, `z` forward).
    pub fn to_camera(&self, point: [f64; 3]) -> [f64; 3] {
        let d = sub(point, self.position);
        let r = &self.rotation;
        // Rᵀ · d.
        [
            r[0][0] * d[0] + r[1][0] * d[1] + r[2][0] * d[2],
            r[0][1] * d[0] + r[1][1] * d[1] + r[2][1] * d[2],
            r[0][2] * d[0] + r[1][2] * d[1] + r[2][2] * d[2],
        ]
    }

    /// A camera-space point on the image; `None` behind the near plane.
    pub fn project_camera(&self, camera_point: [f64; 3]) -> Option<Projected> {
        let [x, y, z] = camera_point;
        // Written so that a NaN depth is rejected too.
        if z.is_nan() || z <= NEAR_CLIP {
            return None;
        }
        let f = self.focal();
        let x_ndc = x * f / z / self.aspect();
        let y_ndc = y * f / z;
        let width = f64::from(self.width);
        let height = f64::from(self.height);
        Some(Projected {
            x: (x_ndc / 2.0 + 0.5) * width,
            y: height - (y_ndc / 2.0 + 0.5) * height,
            depth: z,
        })
    }

    /// A world point on the image; `None` behind the near plane.
    pub fn project(&self, point: [f64; 3]) -> Option<Projected> {
        self.project_camera(self.to_camera(point))
    }

    /// The viewing ray through pixel `(x, y)` (sub-pixel), as a unit world direction.
    pub fn ray(&self, x: f64, y: f64) -> [f64; 3] {
        let f = self.focal();
        let x_ndc = (x / f64::from(self.width) - 0.5) * 2.0;
        let y_ndc = ((f64::from(self.height) - y) / f64::from(self.height) - 0.5) * 2.0;
        let camera = [x_ndc * self.aspect() / f, y_ndc / f, 1.0];
        let r = &self.rotation;
        normalize([
            r[0][0] * camera[0] + r[0][1] * camera[1] + r[0][2] * camera[2],
            r[1][0] * camera[0] + r[1][1] * camera[1] + r[1][2] * camera[2],
            r[2][0] * camera[0] + r[2][1] * camera[1] + r[2][2] * camera[2],
        ])
    }

    /// The world point `(x, y)` on the plane `z = plane_z` seen at pixel `(x, y)`, if the
    /// viewing ray meets the plane in front of the camera.
    pub fn lift_to_plane(&self, x: f64, y: f64, plane_z: f64) -> Option<[f64; 2]> {
        let direction = self.ray(x, y);
        if direction[2].abs() < 1e-9 {
            return None;
        }
        let distance = -(self.position[2] - plane_z) / direction[2];
        let world = [
            self.position[0] + distance * direction[0],
            self.position[1] + distance * direction[1],
        ];
        (distance > 0.0 && world.iter().all(|v| v.is_finite())).then_some(world)
    }

    /// The world point `(x, z)` on the horizontal plane `y = plane_y` seen at pixel `(x, y)`,
    /// if the viewing ray meets the plane in front of the camera.
    pub fn lift_to_height(&self, x: f64, y: f64, plane_y: f64) -> Option<[f64; 2]> {
        let direction = self.ray(x, y);
        if direction[1].abs() < 1e-9 {
            return None;
        }
        let distance = -(self.position[1] - plane_y) / direction[1];
        let world = [
            self.position[0] + distance * direction[0],
            self.position[2] + distance * direction[2],
        ];
        (distance > 0.0 && world.iter().all(|v| v.is_finite())).then_some(world)
    }

    /// The camera's forward axis in world.
    pub fn forward(&self) -> [f64; 3] {
        [
            self.rotation[0][2],
            self.rotation[1][2],
            self.rotation[2][2],
        ]
    }

    /// Unity Euler angles (degrees in `[0, 360)`) of the rotation, for `outputCamera`.
    pub fn euler_deg(&self) -> [f64; 3] {
        let r = &self.rotation;
        // R = Ry·Rx·Rz: r[1][2] = −sin x; r[0][2] = cos x sin y; r[2][2] = cos x cos y;
        // r[1][0] = cos x sin z; r[1][1] = cos x cos z.
        let x = (-r[1][2]).clamp(-1.0, 1.0).asin();
        let y = r[0][2].atan2(r[2][2]);
        let z = r[1][0].atan2(r[1][1]);
        [x, y, z].map(|angle| angle.to_degrees().rem_euclid(360.0))
    }

    /// The rotation as a unit quaternion `[x, y, z, w]`, as a capture records it.
    pub fn quaternion(&self) -> [f64; 4] {
        rotation_to_quaternion(&self.rotation)
    }

    /// The capture's row-major 3×3 intrinsic in NDC: `[f/aspect,0,0, 0,f,0,
    /// 0,0,-(far+near)/(far-near)]`.
    pub fn intrinsic_ndc(&self) -> [f64; 9] {
        let f = self.focal();
        [
            f / self.aspect(),
            0.0,
            0.0,
            0.0,
            f,
            0.0,
            0.0,
            0.0,
            -(FAR_CLIP + NEAR_CLIP) / (FAR_CLIP - NEAR_CLIP),
        ]
    }
}

/// Unity's rotation for Euler angles in degrees: `Ry · Rx · Rz` (z applied first).
pub fn unity_euler_rotation(euler_deg: [f64; 3]) -> Rotation {
    let [x, y, z] = euler_deg.map(f64::to_radians);
    let rx = [
        [1.0, 0.0, 0.0],
        [0.0, x.cos(), -x.sin()],
        [0.0, x.sin(), x.cos()],
    ];
    let ry = [
        [y.cos(), 0.0, y.sin()],
        [0.0, 1.0, 0.0],
        [-y.sin(), 0.0, y.cos()],
    ];
    let rz = [
        [z.cos(), -z.sin(), 0.0],
        [z.sin(), z.cos(), 0.0],
        [0.0, 0.0, 1.0],
    ];
    multiply(&multiply(&ry, &rx), &rz)
}

/// The product of two rotations.
pub fn multiply(a: &Rotation, b: &Rotation) -> Rotation {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, cell) in row.iter_mut().enumerate() {
            *cell = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    out
}

/// `R · v`.
pub fn rotate(r: &Rotation, v: [f64; 3]) -> [f64; 3] {
    [
        r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
        r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
        r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
    ]
}

#[expect(
    clippy::many_single_char_names,
    reason = "the quaternion's components and the matrix keep their textbook names"
)]
fn rotation_to_quaternion(r: &Rotation) -> [f64; 4] {
    // Shepperd's method: branch on the largest of w², x², y², z² for accuracy.
    let trace = r[0][0] + r[1][1] + r[2][2];
    let (x, y, z, w);
    if trace > 0.0 {
        let s = (trace + 1.0).sqrt() * 2.0;
        w = 0.25 * s;
        x = (r[2][1] - r[1][2]) / s;
        y = (r[0][2] - r[2][0]) / s;
        z = (r[1][0] - r[0][1]) / s;
    } else if r[0][0] > r[1][1] && r[0][0] > r[2][2] {
        let s = (1.0 + r[0][0] - r[1][1] - r[2][2]).sqrt() * 2.0;
        w = (r[2][1] - r[1][2]) / s;
        x = 0.25 * s;
        y = (r[0][1] + r[1][0]) / s;
        z = (r[0][2] + r[2][0]) / s;
    } else if r[1][1] > r[2][2] {
        let s = (1.0 + r[1][1] - r[0][0] - r[2][2]).sqrt() * 2.0;
        w = (r[0][2] - r[2][0]) / s;
        x = (r[0][1] + r[1][0]) / s;
        y = 0.25 * s;
        z = (r[1][2] + r[2][1]) / s;
    } else {
        let s = (1.0 + r[2][2] - r[0][0] - r[1][1]).sqrt() * 2.0;
        w = (r[1][0] - r[0][1]) / s;
        x = (r[0][2] + r[2][0]) / s;
        y = (r[1][2] + r[2][1]) / s;
        z = 0.25 * s;
    }
    // The release writes the hemisphere with w ≥ 0.
    if w < 0.0 {
        [-x, -y, -z, -w]
    } else {
        [x, y, z, w]
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if length > 0.0 {
        [v[0] / length, v[1] / length, v[2] / length]
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// The segment along the principal axis of `points` spanning their extent: the centre line of
/// a bar seen from the front (its ends at the bar's ends). `None` for fewer than 3 points.
pub fn principal_segment(points: &[[f64; 2]]) -> Option<([f64; 2], [f64; 2])> {
    if points.len() < 3 {
        return None;
    }
    let n = points.len() as f64;
    let mean = [
        points.iter().map(|p| p[0]).sum::<f64>() / n,
        points.iter().map(|p| p[1]).sum::<f64>() / n,
    ];
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in points {
        let (dx, dy) = (p[0] - mean[0], p[1] - mean[1]);
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
    }
    // The major axis of the 2 × 2 covariance.
    let angle = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let axis = [angle.cos(), angle.sin()];
    let along = |p: &[f64; 2]| (p[0] - mean[0]) * axis[0] + (p[1] - mean[1]) * axis[1];
    let low = points.iter().map(along).fold(f64::INFINITY, f64::min);
    let high = points.iter().map(along).fold(f64::NEG_INFINITY, f64::max);
    // The axis through the bar's middle: the extent's midpoint, not the pixels' mean (a bar
    // partly hidden keeps its ends).
    let at = |t: f64| [mean[0] + t * axis[0], mean[1] + t * axis[1]];
    let (start, end) = (at(low), at(high));
    (start.iter().chain(&end).all(|v| v.is_finite()) && high > low).then_some((start, end))
}

#[cfg(test)]
#[expect(
    clippy::unreadable_literal,
    reason = "values copied digit for digit from the release's files"
)]
mod tests {
    use super::*;

    /// The real rope video's camera (`outputCamera`) and its first capture record.
    fn release_camera() -> CameraModel {
        CameraModel::from_unity_euler(
            [-7.45587063, -1.51208258, -43.0518341],
            [348.4731, 346.7676, 1.08918478e-07],
            40.14217,
            1920,
            1080,
        )
    }

    #[test]
    fn the_release_capture_records_are_reproduced() {
        let camera = release_camera();
        let q = camera.quaternion();
        let recorded = [-0.0997528061, -0.11463549, -0.0115703652, 0.9883189];
        for (got, want) in q.iter().zip(recorded) {
            assert!((got - want).abs() < 1e-6, "{q:?} vs {recorded:?}");
        }
        let k = camera.intrinsic_ndc();
        let recorded = [1.53951037, 2.73690724, -1.0006001];
        for (got, want) in [k[0], k[4], k[8]].iter().zip(recorded) {
            assert!((got - want).abs() < 1e-6, "{k:?}");
        }
        let euler = camera.euler_deg();
        assert!((euler[0] - 348.4731).abs() < 1e-9 && (euler[1] - 346.7676).abs() < 1e-9);
    }

    #[test]
    fn centroids_project_onto_their_annotated_boxes() {
        // First-frame centroids (outputs4D.json) and box centres (perFrameAnnotations "1").
        let camera = release_camera();
        let cases = [
            ([-23.1300011, 12.0, 0.0], [791.5, 410.5]),
            ([-19.4300022, 0.0, 0.0], [900.0, 789.5]),
            ([-25.2855034, 6.33296, 0.0], [721.5, 587.0]),
            ([-13.1250238, 5.08361, 0.0], [1107.0, 613.5]),
        ];
        for (world, centre) in cases {
            let p = camera.project(world).unwrap();
            assert!(
                (p.x - centre[0]).abs() < 1.5 && (p.y - centre[1]).abs() < 2.0,
                "{world:?} → ({}, {}), box centre {centre:?}",
                p.x,
                p.y
            );
        }
    }

    #[test]
    fn rays_invert_projection_and_look_at_points_forward() {
        let camera = release_camera();
        let point = [-20.0, 5.0, 0.0];
        let p = camera.project(point).unwrap();
        let ray = camera.ray(p.x, p.y);
        let to_point = normalize(sub(point, camera.position));
        for (a, b) in ray.iter().zip(to_point) {
            assert!((a - b).abs() < 1e-12);
        }
        let aimed = CameraModel::looking_at([3.0, 4.0, -30.0], [0.0, 2.0, 0.0], 45.0, 640, 480);
        let centre = aimed.project([0.0, 2.0, 0.0]).unwrap();
        assert!((centre.x - 320.0).abs() < 1e-9 && (centre.y - 240.0).abs() < 1e-9);
        assert!(
            aimed.project([0.0, 2.0, -40.0]).is_none(),
            "behind the camera"
        );
        // No roll: a vertical world line stays vertical on screen at the image centre column.
        let above = aimed.project([0.0, 3.0, 0.0]).unwrap();
        assert!(above.y < centre.y && (above.x - centre.x).abs() < 1.0);
    }
}
