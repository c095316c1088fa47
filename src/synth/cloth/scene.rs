//! What a cloth video shows: the table, the pillars and plates as boxes in their simulated
//! poses, and the two cloths as meshes over their particles, with the release's labels (`Floor`
//! 1 for the table, `Cloth` 2, `ChamferBox` 3 for pillars and plates); and the 4-D data
//! (`outputs4D.json`: the boxes' poses per frame with their voxels, the table static, each
//! cloth's 961 particles per frame from update 60).

use std::sync::Arc;

use serde_json::{Map, Value, json};

use super::layout::Layout;
use super::simulate::{CAPTURE_EVERY, HalfRun, SPAWN_UPDATE};
use crate::perception::palette::PALETTE;
use crate::physics::vector3::{self as v3, Quaternion, Vector, rotation_matrix};
use crate::synth::Item;
use crate::synth::annotate::LabelledObject;
use crate::synth::mesh::{Mesh, Pose};
use crate::synth::unity::round;
use crate::synth::unity::unity_euler_degrees;

/// The table's top is at y = 0; it is this large (x, thickness, z), units.
const TABLE_SIZE: [f64; 3] = [11.0, 0.3, 9.0];
/// The table's colour (a light wood).
const TABLE_COLOR: [f64; 3] = [0.62, 0.52, 0.41];
/// Voxel spacing of the boxes in the 4-D data, units (the release: 0.14).
const VOXEL: f64 = 0.14;
/// Name of the table in the release's records.
pub const TABLE_NAME: &str = "Table";

/// sRGB of a palette name (grey for an unknown one).
pub fn color_of(name: &str) -> [f64; 3] {
    PALETTE
        .iter()
        .find(|color| color.name == name)
        .map_or([0.5, 0.5, 0.5], |color| color.unit_rgb())
}

/// The drawable scene of a layout and its two runs.
#[derive(Debug, Clone)]
pub struct ClothView {
    /// Every box: name, colour, mesh (centred, unturned).
    boxes: Vec<(String, [f64; 3], Arc<Mesh>)>,
    /// The cloths' colours, left then right.
    cloth_colors: [[f64; 3]; 2],
    table: Arc<Mesh>,
}

impl ClothView {
    /// The view of `layout` with the cloths' texture colours.
    pub fn new(layout: &Layout, cloth_colors: [[f64; 3]; 2]) -> ClothView {
        let boxes = layout
            .halves
            .iter()
            .flat_map(|half| &half.boxes)
            .map(|entry| {
                (
                    entry.name.clone(),
                    color_of(entry.color),
                    Arc::new(Mesh::cuboid(entry.size)),
                )
            })
            .collect();
        ClothView {
            boxes,
            cloth_colors,
            table: Arc::new(Mesh::cuboid(TABLE_SIZE)),
        }
    }

    /// Instance ids: boxes from 1 (left half first), then the two cloths, then the table.
    fn cloth_instance(&self, side: usize) -> u32 {
        u32::try_from(self.boxes.len() + 1 + side).unwrap_or(u32::MAX)
    }

    fn table_instance(&self) -> u32 {
        u32::try_from(self.boxes.len() + 3).unwrap_or(u32::MAX)
    }

    /// Every labelled object.
    pub fn labels(&self) -> Vec<LabelledObject> {
        let boxes = self
            .boxes
            .iter()
            .zip(1..)
            .map(|((name, _, _), instance)| LabelledObject {
                instance,
                name: name.clone(),
                label_id: 3,
                label_name: "ChamferBox".to_string(),
            });
        let cloths = ["Cloth (Left)", "Cloth (Right)"]
            .into_iter()
            .enumerate()
            .map(|(side, name)| LabelledObject {
                instance: self.cloth_instance(side),
                name: name.to_string(),
                label_id: 2,
                label_name: "Cloth".to_string(),
            });
        let table = LabelledObject {
            instance: self.table_instance(),
            name: TABLE_NAME.to_string(),
            label_id: 1,
            label_name: "Floor".to_string(),
        };
        boxes.chain(cloths).chain(std::iter::once(table)).collect()
    }

    /// The drawables of captured frame `frame` of the two halves' runs.
    pub fn items(&self, runs: &[HalfRun; 2], frame: usize) -> Vec<Item> {
        let mut items = vec![Item {
            mesh: self.table.clone(),
            pose: Pose::at([0.0, -TABLE_SIZE[1] / 2.0, 0.0]),
            color: TABLE_COLOR,
            instance: self.table_instance(),
            stripes: None,
        }];
        let mut instance = 1;
        let mut boxes = self.boxes.iter();
        for run in runs {
            let Some(state) = run.frames.get(frame) else {
                continue;
            };
            for &(position, orientation) in &state.boxes {
                let Some((_, color, mesh)) = boxes.next() else {
                    break;
                };
                items.push(Item {
                    mesh: mesh.clone(),
                    pose: Pose {
                        rotation: rotation_matrix(orientation),
                        translation: position,
                    },
                    color: *color,
                    instance,
                    stripes: None,
                });
                instance += 1;
            }
        }
        for (side, run) in runs.iter().enumerate() {
            if let Some(particles) = run.frames.get(frame).and_then(|f| f.cloth.as_ref()) {
                items.push(Item {
                    mesh: Arc::new(cloth_mesh(particles, &run.triangles)),
                    pose: Pose::at([0.0; 3]),
                    color: self.cloth_colors[side],
                    instance: self.cloth_instance(side),
                    stripes: None,
                });
            }
        }
        items
    }

    /// `outputs4D.json`: the boxes' poses per 4-D frame (captures from update 60), with their
    /// first-capture meshes and voxels; the table static; each cloth's particles per frame. The
    /// cloth meshes are left empty per frame, as in the other generated scenarios: their
    /// vertices are the particles and their faces the fixed grid.
    pub fn four_d(&self, layout: &Layout, runs: &[HalfRun; 2]) -> Value {
        let first = SPAWN_UPDATE / CAPTURE_EVERY;
        let rounded = |v: f64| round(v, 5);
        let mut staticity = Map::new();
        let mut centroids = Map::new();
        let mut vertices = Map::new();
        let mut faces = Map::new();
        let mut voxels = Map::new();
        let mut boxes = self.boxes.iter();
        for (half, run) in layout.halves.iter().zip(runs) {
            for (index, entry) in half.boxes.iter().enumerate() {
                let Some((name, _, mesh)) = boxes.next() else {
                    break;
                };
                let poses: Vec<(Vector, Quaternion)> = run
                    .frames
                    .iter()
                    .skip(first)
                    .filter_map(|frame| frame.boxes.get(index).copied())
                    .collect();
                let Some(&(position, orientation)) = poses.first() else {
                    continue;
                };
                let pose_json = |(position, orientation): (Vector, Quaternion)| {
                    let euler = unity_euler_degrees(&rotation_matrix(orientation));
                    json!([position.map(rounded), euler.map(rounded)])
                };
                staticity.insert(name.clone(), json!(false));
                centroids.insert(
                    name.clone(),
                    Value::Array(poses.iter().copied().map(pose_json).collect()),
                );
                let rotation = rotation_matrix(orientation);
                let placed = mesh.transformed(&Pose {
                    rotation,
                    translation: position,
                });
                let points: Vec<[f64; 3]> =
                    placed.positions.iter().map(|p| p.map(rounded)).collect();
                vertices.insert(name.clone(), json!(points));
                let flat: Vec<u32> = placed.triangles.iter().flatten().copied().collect();
                faces.insert(name.clone(), json!(flat));
                let mut rows = vec![
                    json!(position.map(rounded)),
                    json!(unity_euler_degrees(&rotation).map(rounded)),
                ];
                rows.extend(
                    box_voxels(entry.size, position, orientation)
                        .into_iter()
                        .map(|p| json!(p.map(rounded))),
                );
                voxels.insert(name.clone(), Value::Array(rows));
            }
        }
        staticity.insert(TABLE_NAME.to_string(), json!(true));
        centroids.insert(TABLE_NAME.to_string(), json!([]));
        let mut tracked = Map::new();
        let mut empty = Map::new();
        for (half, run) in layout.halves.iter().zip(runs) {
            let frames: Vec<Value> = run
                .frames
                .iter()
                .skip(first)
                .filter_map(|frame| frame.cloth.as_ref())
                .map(|particles| {
                    json!(particles.iter().map(|p| p.map(rounded)).collect::<Vec<_>>())
                })
                .collect();
            let count = frames.len();
            let name = half.side.cloth_name().to_string();
            tracked.insert(name.clone(), Value::Array(frames));
            empty.insert(name, json!(vec![json!([]); count]));
        }
        json!({
            "rigidbody4D": {
                "rigidbodyStatesStaticity": staticity,
                "rigidbodyCentroidStates": centroids,
                "rigidbodyMeshVertices": vertices,
                "rigidbodyMeshFaces": faces,
                "rigidbodyVoxelPosition": voxels,
            },
            "softbody4D": {
                "softbodyTrackedParticles": tracked,
                "softbodyMeshVertices": empty.clone(),
                "softbodyMeshFaces": empty,
            },
        })
    }
}

/// A cloth's mesh over its particles, with per-vertex normals averaged from its triangles.
fn cloth_mesh(particles: &[Vector], triangles: &[[usize; 3]]) -> Mesh {
    let mut normals = vec![[0.0; 3]; particles.len()];
    for triangle in triangles {
        let [a, b, c] = triangle.map(|k| particles[k]);
        let face = v3::cross(v3::sub(b, a), v3::sub(c, a));
        for &k in triangle {
            normals[k] = v3::add(normals[k], face);
        }
    }
    let normals = normals
        .into_iter()
        .map(|n| {
            let length = v3::norm(n);
            if length > 1e-12 {
                v3::scale(n, 1.0 / length)
            } else {
                [0.0, 1.0, 0.0]
            }
        })
        .collect();
    Mesh {
        positions: particles.to_vec(),
        normals,
        along: vec![0.0; particles.len()],
        triangles: triangles
            .iter()
            .map(|t| t.map(|k| u32::try_from(k).unwrap_or(u32::MAX)))
            .collect(),
    }
}

/// Voxel centres filling a box of full size `size` at the given pose, every [`VOXEL`] units.
fn box_voxels(size: [f64; 3], position: Vector, orientation: Quaternion) -> Vec<[f64; 3]> {
    let rotation = rotation_matrix(orientation);
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a box's size over the voxel spacing is a small count"
    )]
    let counts = size.map(|s| (s / VOXEL).round().max(1.0) as usize);
    let mut out = Vec::with_capacity(counts.iter().product());
    for i in 0..counts[0] {
        for j in 0..counts[1] {
            for k in 0..counts[2] {
                #[expect(clippy::cast_precision_loss, reason = "small counts")]
                let local = [
                    ((i as f64 + 0.5) / counts[0] as f64 - 0.5) * size[0],
                    ((j as f64 + 0.5) / counts[1] as f64 - 0.5) * size[1],
                    ((k as f64 + 0.5) / counts[2] as f64 - 0.5) * size[2],
                ];
                out.push(v3::add(position, v3::apply(&rotation, local)));
            }
        }
    }
    out
}
