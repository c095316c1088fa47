//! What a generated rope video looks like: the release's prefabs as meshes (solid and hollow
//! pulleys with their white marker and grey shaft, cubes, spheres, fixed points, striped rope
//! tubes), the camera sampled and re-framed as the release does, the labels and instance ids,
//! the per-frame drawables, and the 4-D records (`outputs4D.json`) of the same geometry.
//!
//! Input: a [`TruthModel`] and the factual run's recorded [`FrameState`]s. Output: items per
//! frame, a [`CameraModel`](crate::perception::camera::CameraModel), labels, and the 4-D JSON. Units: world units; angles in degrees in
//! the JSON as the release writes them.

use std::f64::consts::PI;
use std::sync::Arc;

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use super::simulate::{BodyRole, FrameState, TruthModel};
use crate::dataset::rope::world;
use crate::physics::rope::Mount;
use crate::synth::Item;
use crate::synth::annotate::LabelledObject;
use crate::synth::camera::{CameraSample, truncated_normal};
use crate::synth::mesh::{Mesh, Pose};
use crate::synth::palette::palette_color;
use crate::synth::raster::Stripes;

/// The release camera's look-at point before re-framing.
const LOOK_AT: [f64; 3] = [-8.9, 0.0, 0.0];
/// Padding added to the framing distance, units.
pub const FIELD_PADDING: f64 = 6.0;
/// Sides of rope tubes when rendered.
const ROPE_SIDES: u32 = 8;
/// The release's twisted rope: dark grooves between strands about every 0.2 units, winding
/// round the rope.
const ROPE_STRIPES: Stripes = Stripes {
    period: 0.2,
    dark_share: 0.45,
    dark: 0.3,
    softness: 0.3,
};
/// How far the strands wind: pattern units per unit of arc round the rope.
const ROPE_TWIST: f64 = 0.6;
/// Spacing of tracked rope particles, units.
const PARTICLE_SPACING: f64 = 0.5;
/// Spacing of the voxels written to `rigidbodyVoxelPosition`, units (the release used 0.07
/// with a mesh voxelizer; a coarser interior grid keeps the files small).
const VOXEL_SPACING: f64 = 0.25;

/// Samples the camera as the release's `CameraRandomizer` does.
pub fn sample_camera(rng: &mut ChaCha8Rng) -> CameraSample {
    let distance = truncated_normal(rng, 35.0, 1.0, 33.0, 36.0);
    let elevation = truncated_normal(rng, 0.0, 6.0, -6.0, 6.0).to_radians();
    let mut azimuth = truncated_normal(rng, 90.0, 4.0, 86.0, 94.0).to_radians();
    let vertical_fov_deg = rng.random_range(40.0..50.0);
    let mirrored = rng.random::<f64>() > 0.5;
    if mirrored {
        azimuth += PI;
    }
    CameraSample {
        position: [
            LOOK_AT[0] + distance * elevation.cos() * azimuth.cos(),
            LOOK_AT[1] + distance * elevation.sin(),
            LOOK_AT[2] + distance * elevation.cos() * azimuth.sin(),
        ],
        vertical_fov_deg,
        mirrored,
    }
}

/// The release's label ids and names (`PulleyGroupIdLabelConfig`).
fn label_of(kind: ObjectKind) -> (u32, &'static str) {
    match kind {
        ObjectKind::Rope => (5, "Filo Rope"),
        ObjectKind::Pulley {
            solid: true,
            movable: false,
        } => (8, "Filo Little Pulley Static"),
        ObjectKind::Pulley {
            solid: false,
            movable: false,
        } => (7, "Filo Large Pulley Static"),
        ObjectKind::Pulley {
            solid: true,
            movable: true,
        } => (10, "Filo Little Pulley Dynamic"),
        ObjectKind::Pulley {
            solid: false,
            movable: true,
        } => (9, "Filo Large Pulley Dynamic"),
        // Spheres carry the cube label too (the `Filo Sphere` prefab does).
        ObjectKind::Cube | ObjectKind::Sphere => (3, "Filo Cube"),
        ObjectKind::FixedPoint => (11, "Filo Static"),
    }
}

/// What a labelled object is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ObjectKind {
    Rope,
    Pulley { solid: bool, movable: bool },
    Cube,
    Sphere,
    FixedPoint,
}

/// The shared meshes of a video.
struct Prefabs {
    solid_disc: Arc<Mesh>,
    hollow_disc: Arc<Mesh>,
    solid_marker: Arc<Mesh>,
    hollow_marker: Arc<Mesh>,
    shaft: Arc<Mesh>,
    cube: Arc<Mesh>,
    sphere: Arc<Mesh>,
    fixed_point: Arc<Mesh>,
}

impl Prefabs {
    fn new() -> Prefabs {
        let solid_half = 0.289;
        let hollow_half = 0.174;
        // The release's hollow pulley: a rim, a thinner web with three kidney-shaped holes, and
        // a hub.
        let rim = world::HOLLOW_PULLEY_RADIUS;
        let mut hollow = Mesh::ring(rim - 0.3, rim, hollow_half, 48);
        hollow.merge(&Mesh::holed_web(
            [0.5, 0.65, rim - 0.4, rim - 0.3],
            hollow_half * 0.6,
            3,
            0.7 * 2.0 * PI / 3.0,
            72,
        ));
        hollow.merge(&Mesh::cylinder(0.55, hollow_half, 24));
        let marker = |radius: f64, half: f64| {
            Arc::new(
                Mesh::cuboid([0.28, 0.9, 2.0 * half + 0.02]).transformed(&Pose::at([
                    0.0,
                    radius - 0.62,
                    0.0,
                ])),
            )
        };
        let shaft = Mesh::cylinder(0.5, 0.9, 20);
        Prefabs {
            solid_disc: Arc::new(Mesh::cylinder(world::SOLID_PULLEY_RADIUS, solid_half, 48)),
            hollow_disc: Arc::new(hollow),
            solid_marker: marker(world::SOLID_PULLEY_RADIUS, solid_half),
            hollow_marker: marker(world::HOLLOW_PULLEY_RADIUS, hollow_half),
            shaft: Arc::new(shaft),
            cube: Arc::new(Mesh::cuboid([2.0, 2.0, 2.0])),
            sphere: Arc::new(Mesh::sphere(1.0, 28, 14)),
            fixed_point: Arc::new(Mesh::cuboid([1.425, 0.7, 0.425])),
        }
    }
}

/// A labelled object of the scene.
#[derive(Debug, Clone)]
struct SceneObject {
    name: String,
    instance: u32,
    kind: ObjectKind,
    color: [f64; 3],
}

/// The renderable description of a generated rope video.
pub struct RopeScene {
    objects: Vec<SceneObject>,
    prefabs: Prefabs,
}

/// The colour id of an object name's colour words (`Light Blue Cube` → 12).
fn color_of(name: &str) -> [f64; 3] {
    (0..17_u8)
        .filter_map(palette_color)
        .filter(|c| name.starts_with(&format!("{} ", c.name)))
        .max_by_key(|c| c.name.len())
        .map_or(
            [0.5, 0.5, 0.5],
            super::super::palette::PaletteColor::unit_rgb,
        )
}

impl RopeScene {
    /// Labels every object of `model` in the release's id order: each main rope followed by its
    /// pulleys (and hanging load connections), then the ends, then the pulley–pulley cables.
    pub fn new(model: &TruthModel) -> RopeScene {
        let mut objects: Vec<SceneObject> = Vec::new();
        let mut add = |name: &str, kind: ObjectKind| {
            if name.is_empty() || objects.iter().any(|o| o.name == name) {
                return;
            }
            let instance = u32::try_from(objects.len() + 1).unwrap_or(u32::MAX);
            objects.push(SceneObject {
                name: name.to_string(),
                instance,
                kind,
                color: color_of(name),
            });
        };
        let kind_of = |name: &str| -> ObjectKind {
            if let Some(&pulley) = model.pulleys.get(name) {
                ObjectKind::Pulley {
                    solid: model.solid[pulley],
                    movable: matches!(model.network.pulleys[pulley].mount, Mount::Body(_)),
                }
            } else if name.ends_with("Sphere") {
                ObjectKind::Sphere
            } else if name.ends_with("Cube") {
                ObjectKind::Cube
            } else if name.ends_with("Fixed Point") {
                ObjectKind::FixedPoint
            } else {
                ObjectKind::Rope
            }
        };
        let mut ends: Vec<String> = Vec::new();
        for (rope, elements) in model.ropes.iter().zip(&model.rope_elements) {
            if elements.len() == 2 && elements.iter().all(|e| model.pulleys.contains_key(e)) {
                continue; // A pulley–pulley cable: labelled after the ends.
            }
            add(rope, ObjectKind::Rope);
            let last = elements.len().saturating_sub(1);
            for (index, element) in elements.iter().enumerate() {
                if model.pulleys.contains_key(element) {
                    add(element, kind_of(element));
                } else if index == 0 || index == last {
                    ends.push(element.clone());
                }
            }
        }
        for end in &ends {
            add(end, kind_of(end));
        }
        for (rope, elements) in model.ropes.iter().zip(&model.rope_elements) {
            if elements.len() == 2 && elements.iter().all(|e| model.pulleys.contains_key(e)) {
                add(rope, ObjectKind::Rope);
            }
        }
        RopeScene {
            objects,
            prefabs: Prefabs::new(),
        }
    }

    /// Labelled objects for the annotations.
    pub fn labels(&self) -> Vec<LabelledObject> {
        self.objects
            .iter()
            .map(|o| {
                let (label_id, label_name) = label_of(o.kind);
                LabelledObject {
                    instance: o.instance,
                    name: o.name.clone(),
                    label_id,
                    label_name: label_name.to_string(),
                }
            })
            .collect()
    }

    /// `Id2ObjectNameDict`, highest id first as the release writes it, with the solver last.
    pub fn id_to_name(&self) -> Vec<(u32, String)> {
        let solver = u32::try_from(self.objects.len() + 1).unwrap_or(u32::MAX);
        let mut entries = vec![(solver, "Solver".to_string())];
        entries.extend(
            self.objects
                .iter()
                .rev()
                .map(|o| (o.instance, o.name.clone())),
        );
        entries
    }

    fn instance(&self, name: &str) -> u32 {
        self.objects
            .iter()
            .find(|o| o.name == name)
            .map_or(0, |o| o.instance)
    }

    fn color(&self, name: &str) -> [f64; 3] {
        self.objects
            .iter()
            .find(|o| o.name == name)
            .map_or([0.5; 3], |o| o.color)
    }

    /// Where each rope's drawn tube runs: the polyline with its body ends moved up to the
    /// attachment point (0.8 above a load's centre).
    fn rope_paths(model: &TruthModel, frame: &FrameState) -> Vec<Vec<[f64; 3]>> {
        model
            .network
            .ropes
            .iter()
            .zip(&frame.ropes)
            .map(|(rope, polyline)| {
                let mut points: Vec<[f64; 3]> =
                    polyline.iter().map(|p| [p[0], p[1], 0.0]).collect();
                let last = points.len().saturating_sub(1);
                for (end, index) in [(rope.path.first(), 0), (rope.path.last(), last)] {
                    if let Some(crate::physics::rope::Point::Body(body)) = end
                        && matches!(model.roles.get(*body), Some(BodyRole::Load(_)))
                        && let Some(point) = points.get_mut(index)
                    {
                        point[1] += world::LOAD_ATTACH_HEIGHT;
                    }
                }
                points
            })
            .collect()
    }

    /// The drawables of one frame.
    pub fn items(&self, model: &TruthModel, frame: &FrameState) -> Vec<Item> {
        let p = &self.prefabs;
        let mut items = Vec::new();
        for (pulley, spec) in model.network.pulleys.iter().enumerate() {
            let centre = frame.pulley_centres[pulley];
            let angle = frame.state.angles[pulley];
            let pose = Pose::turned_about_z([centre[0], centre[1], 0.0], angle);
            let instance = self.instance(&spec.name);
            let solid = model.solid[pulley];
            items.push(Item {
                mesh: if solid {
                    p.solid_disc.clone()
                } else {
                    p.hollow_disc.clone()
                },
                pose,
                color: self.color(&spec.name),
                instance,
                stripes: None,
            });
            items.push(Item {
                mesh: if solid {
                    p.solid_marker.clone()
                } else {
                    p.hollow_marker.clone()
                },
                pose,
                color: [0.92, 0.92, 0.9],
                instance,
                stripes: None,
            });
            if matches!(spec.mount, Mount::Fixed(_)) {
                items.push(Item {
                    mesh: p.shaft.clone(),
                    pose: Pose::at([centre[0], centre[1], 0.0]),
                    color: [0.55, 0.55, 0.55],
                    instance: 0,
                    stripes: None,
                });
            }
        }
        for (body, spec) in model.network.bodies.iter().enumerate() {
            if let BodyRole::Load(_) = model.roles[body] {
                let mesh = if spec.name.ends_with("Sphere") {
                    p.sphere.clone()
                } else {
                    p.cube.clone()
                };
                items.push(Item {
                    mesh,
                    pose: Pose::at([spec.position[0], frame.state.y[body], 0.0]),
                    color: self.color(&spec.name),
                    instance: self.instance(&spec.name),
                    stripes: None,
                });
            }
        }
        for ((name, _, _), centre) in model.anchors.iter().zip(&frame.anchors) {
            items.push(Item {
                mesh: p.fixed_point.clone(),
                pose: Pose::at([centre[0], centre[1], 0.0]),
                color: self.color(name),
                instance: self.instance(name),
                stripes: None,
            });
        }
        for (rope, path) in model.ropes.iter().zip(Self::rope_paths(model, frame)) {
            items.push(Item {
                mesh: Arc::new(Mesh::tube(
                    &path,
                    world::ROPE_RADIUS,
                    ROPE_SIDES,
                    Some(ROPE_TWIST),
                )),
                pose: Pose::at([0.0; 3]),
                color: self.color(rope),
                instance: self.instance(rope),
                stripes: Some(ROPE_STRIPES),
            });
        }
        items
    }

    /// World bounds of every labelled object in `frame` (for the camera's framing).
    pub fn bounds(&self, model: &TruthModel, frame: &FrameState) -> ([f64; 3], [f64; 3]) {
        let mut low = [f64::INFINITY; 3];
        let mut high = [f64::NEG_INFINITY; 3];
        for item in self.items(model, frame).iter().filter(|i| i.instance > 0) {
            for v in &item.mesh.positions {
                let w = item.pose.apply(*v);
                for axis in 0..3 {
                    low[axis] = low[axis].min(w[axis]);
                    high[axis] = high[axis].max(w[axis]);
                }
            }
        }
        (low, high)
    }

    /// `outputs4D.json`: rigid bodies (pulleys, shafts, loads, fixed points) with per-frame
    /// poses, first-frame meshes and voxels; ropes with tracked particles and meshes per frame.
    pub fn four_d(&self, model: &TruthModel, frames: &[FrameState]) -> Value {
        let Some(first) = frames.first() else {
            return json!({});
        };
        json!({
            "rigidbody4D": self.rigid_four_d(model, frames, first),
            "softbody4D": Self::soft_four_d(model, frames),
        })
    }

    /// `rigidbody4D`: per rigid body (pulleys and the shafts of static ones, loads, fixed
    /// points) whether it is static, its per-frame centroid and rotation, its first-frame mesh
    /// and its voxels; `first` is the first of `frames`.
    fn rigid_four_d(&self, model: &TruthModel, frames: &[FrameState], first: &FrameState) -> Value {
        let p = &self.prefabs;
        let mut staticity = serde_json::Map::new();
        let mut centroids = serde_json::Map::new();
        let mut vertices = serde_json::Map::new();
        let mut faces = serde_json::Map::new();
        let mut voxels = serde_json::Map::new();
        let mut rigid = |name: String,
                         is_static: bool,
                         mesh: &Mesh,
                         poses: Vec<([f64; 3], [f64; 3])>,
                         shape: Shape| {
            let (position, euler) = poses.first().copied().unwrap_or(([0.0; 3], [0.0; 3]));
            let pose = Pose::turned_about_z(position, euler[2].to_radians());
            staticity.insert(name.clone(), json!(is_static));
            centroids.insert(
                name.clone(),
                if is_static {
                    json!([])
                } else {
                    json!(
                        poses
                            .iter()
                            .map(|(p, e)| json!([round(p), round(e)]))
                            .collect::<Vec<_>>()
                    )
                },
            );
            vertices.insert(
                name.clone(),
                json!(
                    mesh.positions
                        .iter()
                        .map(|v| round(&pose.apply(*v)))
                        .collect::<Vec<_>>()
                ),
            );
            faces.insert(
                name.clone(),
                json!(mesh.triangles.iter().flatten().collect::<Vec<_>>()),
            );
            let mut rows = vec![round(&position), round(&euler)];
            rows.extend(shape.voxels().iter().map(|v| round(&pose.apply(*v))));
            voxels.insert(name, json!(rows));
        };
        for (pulley, spec) in model.network.pulleys.iter().enumerate() {
            let solid = model.solid[pulley];
            let poses: Vec<([f64; 3], [f64; 3])> = frames
                .iter()
                .map(|f| {
                    let c = f.pulley_centres[pulley];
                    let degrees = f.state.angles[pulley].to_degrees().rem_euclid(360.0);
                    ([c[0], c[1], 0.0], [0.0, 0.0, degrees])
                })
                .collect();
            let (mesh, shape) = if solid {
                (
                    &p.solid_disc,
                    Shape::Cylinder(world::SOLID_PULLEY_RADIUS, 0.289),
                )
            } else {
                (
                    &p.hollow_disc,
                    Shape::Cylinder(world::HOLLOW_PULLEY_RADIUS, 0.174),
                )
            };
            rigid(spec.name.clone(), false, mesh, poses.clone(), shape);
            if matches!(spec.mount, Mount::Fixed(_)) {
                let centre = poses.first().map_or([0.0; 3], |(c, _)| *c);
                rigid(
                    format!("Shaft of {}", spec.name),
                    true,
                    &p.shaft,
                    vec![(centre, [0.0; 3])],
                    Shape::Cylinder(0.5, 0.9),
                );
            }
        }
        for (body, spec) in model.network.bodies.iter().enumerate() {
            if let BodyRole::Load(_) = model.roles[body] {
                let poses = frames
                    .iter()
                    .map(|f| ([spec.position[0], f.state.y[body], 0.0], [0.0; 3]))
                    .collect();
                let sphere = spec.name.ends_with("Sphere");
                let (mesh, shape) = if sphere {
                    (&p.sphere, Shape::Sphere(1.0))
                } else {
                    (&p.cube, Shape::Box([2.0, 2.0, 2.0]))
                };
                rigid(spec.name.clone(), false, mesh, poses, shape);
            }
        }
        for ((name, _, _), centre) in model.anchors.iter().zip(&first.anchors) {
            rigid(
                name.clone(),
                true,
                &p.fixed_point,
                vec![([centre[0], centre[1], 0.0], [0.0; 3])],
                Shape::Box([1.425, 0.7, 0.425]),
            );
        }
        json!({
            "rigidbodyStatesStaticity": staticity,
            "rigidbodyCentroidStates": centroids,
            "rigidbodyMeshVertices": vertices,
            "rigidbodyMeshFaces": faces,
            "rigidbodyVoxelPosition": voxels,
        })
    }

    /// `softbody4D`: per rope, its tracked particles (evenly spaced along its first-frame
    /// length) and its tube mesh, frame by frame.
    fn soft_four_d(model: &TruthModel, frames: &[FrameState]) -> Value {
        let mut particles = serde_json::Map::new();
        let mut soft_vertices = serde_json::Map::new();
        let mut soft_faces = serde_json::Map::new();
        let paths: Vec<Vec<Vec<[f64; 3]>>> =
            frames.iter().map(|f| Self::rope_paths(model, f)).collect();
        for (rope, name) in model.ropes.iter().enumerate() {
            let rest = paths
                .first()
                .and_then(|f| f.get(rope))
                .map_or(0.0, |path| length(path));
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a rope of tens of units over a positive spacing"
            )]
            let count = (rest / PARTICLE_SPACING).floor() as usize + 1;
            let mut per_frame = Vec::with_capacity(frames.len());
            let mut mesh_vertices = Vec::with_capacity(frames.len());
            let mut mesh_faces = Vec::with_capacity(frames.len());
            for frame_paths in &paths {
                let path = frame_paths.get(rope).map_or(&[][..], Vec::as_slice);
                let mut points: Vec<[f64; 3]> = (0..count)
                    .map(|k| point_at(path, k as f64 * PARTICLE_SPACING))
                    .collect();
                if let Some(end) = path.last() {
                    points.push(*end);
                }
                let tube = Mesh::tube(&points, world::ROPE_RADIUS, 4, None);
                mesh_vertices.push(tube.positions.iter().map(round).collect::<Vec<_>>());
                mesh_faces.push(tube.triangles.iter().flatten().copied().collect::<Vec<_>>());
                per_frame.push(points.iter().map(round).collect::<Vec<_>>());
            }
            particles.insert(name.clone(), json!(per_frame));
            soft_vertices.insert(name.clone(), json!(mesh_vertices));
            soft_faces.insert(name.clone(), json!(mesh_faces));
        }
        json!({
            "softbodyTrackedParticles": particles,
            "softbodyMeshVertices": soft_vertices,
            "softbodyMeshFaces": soft_faces,
        })
    }
}

/// A primitive's solid, for voxels.
#[derive(Debug, Clone, Copy)]
enum Shape {
    Box([f64; 3]),
    Sphere(f64),
    /// Radius and half length along z.
    Cylinder(f64, f64),
}

impl Shape {
    /// Centres of the grid cells (spacing [`VOXEL_SPACING`]) inside the solid, object space.
    fn voxels(self) -> Vec<[f64; 3]> {
        let half = match self {
            Shape::Box(size) => size.map(|s| s / 2.0),
            Shape::Sphere(r) => [r; 3],
            Shape::Cylinder(r, h) => [r, r, h],
        };
        let cells = half.map(|h| {
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a handful of cells along a prefab's size"
            )]
            let n = ((2.0 * h / VOXEL_SPACING).floor() as usize).max(1);
            n
        });
        let mut out = Vec::new();
        let coordinate = |axis: usize, index: usize| {
            let n = cells[axis] as f64;
            (index as f64 + 0.5) * (2.0 * half[axis] / n) - half[axis]
        };
        for i in 0..cells[0] {
            for j in 0..cells[1] {
                for k in 0..cells[2] {
                    let v = [coordinate(0, i), coordinate(1, j), coordinate(2, k)];
                    let inside = match self {
                        Shape::Box(_) => true,
                        Shape::Sphere(r) => v[0] * v[0] + v[1] * v[1] + v[2] * v[2] <= r * r,
                        Shape::Cylinder(r, _) => v[0] * v[0] + v[1] * v[1] <= r * r,
                    };
                    if inside {
                        out.push(v);
                    }
                }
            }
        }
        out
    }
}

fn length(path: &[[f64; 3]]) -> f64 {
    path.windows(2)
        .map(|w| crate::synth::mesh::distance(w[0], w[1]))
        .sum()
}

/// The point at arc length `s` along `path` (its last point past the end).
fn point_at(path: &[[f64; 3]], s: f64) -> [f64; 3] {
    let mut travelled = 0.0;
    for w in path.windows(2) {
        let segment = crate::synth::mesh::distance(w[0], w[1]);
        if travelled + segment >= s && segment > 0.0 {
            let t = (s - travelled) / segment;
            return [
                w[0][0] + t * (w[1][0] - w[0][0]),
                w[0][1] + t * (w[1][1] - w[0][1]),
                w[0][2] + t * (w[1][2] - w[0][2]),
            ];
        }
        travelled += segment;
    }
    path.last().copied().unwrap_or([0.0; 3])
}

/// Rounds to 1e-6 as the release's single-precision floats print, so files stay compact.
fn round(v: &[f64; 3]) -> [f64; 3] {
    v.map(|c| {
        let r = (c * 1e6).round() / 1e6;
        if r == 0.0 { 0.0 } else { r }
    })
}
