//! Typed 4-D sensor data (`outputs4D.json`, `docs/data/common.md`, outputs4D.json): rigid-body
//! poses per frame and tracked soft-body particles per frame, in Unity world units (nominally
//! metres) and degrees.
//!
//! Mesh vertices and faces are not read (nothing uses them yet); voxels are kept because the
//! simulators rebuild rigid bodies from them.

use std::path::Path;

use indexmap::IndexMap;

use super::DatasetError;
use super::fields::{Node, read_json};

/// One rigid body's record.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBodyTrack {
    /// `true` for bodies that never move (no per-frame states are recorded for them).
    pub is_static: bool,
    /// Per frame: centroid position (m) and Unity Euler angles (degrees). Empty when static.
    pub poses: Vec<([f64; 3], [f64; 3])>,
    /// Voxel centres (m) at the first capture; the two pose rows of the file are split off.
    pub voxels: Vec<[f64; 3]>,
    /// Position and Euler angles at the first capture (the voxel file's first two rows).
    pub first_pose: Option<([f64; 3], [f64; 3])>,
}

/// One soft body's tracked particles.
#[derive(Debug, Clone, PartialEq)]
pub struct SoftBodyTrack {
    /// Per frame, the tracked particle positions (m). The count never decreases: constant for
    /// ropes, cloths and balls; a fluid's grows from 0 as its emitter releases particles, and
    /// entry `k` is the same particle in every frame that holds it.
    pub particles: Vec<Vec<[f64; 3]>>,
}

/// The 4-D data of one video.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FourDData {
    /// Rigid bodies by scene object name, in file order.
    pub rigid_bodies: IndexMap<String, RigidBodyTrack>,
    /// Soft bodies (ropes, fluids, cloths, balls) by name, in file order.
    pub soft_bodies: IndexMap<String, SoftBodyTrack>,
}

impl FourDData {
    /// Loads and validates an `outputs4D.json`.
    pub fn load(path: &Path) -> Result<FourDData, DatasetError> {
        let value = read_json(path)?;
        let root = Node::root(path, &value);
        let rigid_bodies = root.field("rigidbody4D", parse_rigid_bodies)?;
        let soft_bodies = root.field("softbody4D", |soft| {
            let tracks = soft.field("softbodyTrackedParticles", |tracked| {
                tracked.entries(|name, frames| {
                    let particles = frames.items(|frame| frame.items(point))?;
                    // A body never loses tracked particles; a fluid gains them as its emitter
                    // releases them (the k-th entry is the same particle in every frame).
                    if let Some((bad, [before, after])) =
                        particles.windows(2).enumerate().find_map(|(i, w)| match w {
                            [before, after] if after.len() < before.len() => {
                                Some((i, [before, after]))
                            }
                            _ => None,
                        })
                    {
                        return Err(frames.error(format!(
                            "frame {} has {} particles, fewer than the {} of frame {bad}",
                            bad + 1,
                            after.len(),
                            before.len()
                        )));
                    }
                    Ok((name.to_string(), SoftBodyTrack { particles }))
                })
            })?;
            Ok(tracks.into_iter().collect::<IndexMap<_, _>>())
        })?;
        Ok(FourDData {
            rigid_bodies,
            soft_bodies,
        })
    }

    /// The number of frames: the longest per-frame record of any body.
    pub fn frame_count(&self) -> usize {
        let rigid = self.rigid_bodies.values().map(|b| b.poses.len());
        let soft = self.soft_bodies.values().map(|b| b.particles.len());
        rigid.chain(soft).max().unwrap_or(0)
    }
}

#[expect(
    clippy::type_complexity,
    reason = "one local map of per-frame (position, Euler angles) pairs"
)]
fn parse_rigid_bodies(node: Node<'_>) -> Result<IndexMap<String, RigidBodyTrack>, DatasetError> {
    let staticity: IndexMap<String, bool> = node
        .field("rigidbodyStatesStaticity", |n| {
            n.entries(|name, v| Ok((name.to_string(), v.boolean()?)))
        })?
        .into_iter()
        .collect();
    let mut poses: IndexMap<String, Vec<([f64; 3], [f64; 3])>> = node
        .field("rigidbodyCentroidStates", |n| {
            n.entries(|name, frames| {
                let frames = frames.items(|frame| {
                    let rows = frame.items(point)?;
                    match rows.as_slice() {
                        [position, euler] => Ok((*position, *euler)),
                        _ => Err(frame.error("must be [[x, y, z], [ex, ey, ez]]")),
                    }
                })?;
                Ok((name.to_string(), frames))
            })
        })?
        .into_iter()
        .collect();
    let mut voxels: IndexMap<String, Vec<[f64; 3]>> = node
        .optional_field("rigidbodyVoxelPosition", |n| {
            n.entries(|name, rows| Ok((name.to_string(), rows.items(point)?)))
        })?
        .unwrap_or_default()
        .into_iter()
        .collect();
    let mut bodies = IndexMap::new();
    for (name, is_static) in staticity {
        let body_poses = poses.shift_remove(&name).unwrap_or_default();
        let mut body_voxels = voxels.shift_remove(&name).unwrap_or_default();
        let first_pose = if body_voxels.len() >= 2 {
            let rest = body_voxels.split_off(2);
            let pose = (body_voxels[0], body_voxels[1]);
            body_voxels = rest;
            Some(pose)
        } else {
            None
        };
        bodies.insert(
            name,
            RigidBodyTrack {
                is_static,
                poses: body_poses,
                voxels: body_voxels,
                first_pose,
            },
        );
    }
    if let Some(orphan) = poses.keys().next() {
        return Err(node.error(format!(
            "names `{orphan}` in `rigidbodyCentroidStates` but not in `rigidbodyStatesStaticity`"
        )));
    }
    Ok(bodies)
}

fn point(node: Node<'_>) -> Result<[f64; 3], DatasetError> {
    let values = node.numbers(Some(3))?;
    Ok([values[0], values[1], values[2]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn real_sample_4d_has_150_frames_of_poses_and_rope_particles() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/pulley_group/0/outputs4D.json");
        let data = FourDData::load(&path).unwrap();
        assert_eq!(data.frame_count(), 150);
        let cube = &data.rigid_bodies["Purple Cube"];
        assert!(!cube.is_static);
        assert_eq!(cube.poses.len(), 150);
        assert_eq!(cube.voxels.len(), 994 - 2);
        assert!(data.rigid_bodies["Brown Fixed Point"].is_static);
        let rope = &data.soft_bodies["Purple Rope"];
        assert_eq!((rope.particles.len(), rope.particles[0].len()), (150, 90));
        assert_eq!(data.soft_bodies["Green Rope"].particles[0].len(), 22);
    }
}
