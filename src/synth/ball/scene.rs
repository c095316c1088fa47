//! What a ball video shows: the ramps, floor pieces and floating walls as boxes, the balls as
//! spheres deformed as their particles are, with the release's labels (`Elastic Ball` 1 for the
//! elastic and the rigid ball, which share a prefab; `Plastic Ball` 2; `Stick` 4 for every
//! slab), and the 4-D data (`outputs4D.json`: static slabs with voxels, each ball's 91 tracked
//! particles per frame).

use std::sync::Arc;

use serde_json::Value;

use super::layout::{BALL_RADIUS, Layout, SLAB_DEPTH, SlabLayout};
use super::simulate::BallRun;
use crate::dataset::ball::ElasticityType;
use crate::synth::annotate::LabelledObject;
use crate::synth::mesh::{Mesh, Pose};
use crate::synth::palette::palette_color;
use crate::synth::{Item, StaticPart, four_d_document};

/// A ball's mesh: 24 segments, 16 rings (768 triangles, as the release's ball mesh).
const SPHERE: (u32, u32) = (24, 16);
/// Voxel spacing along a slab's centre line in the 4-D data, units (the release: 0.1).
const VOXEL: f64 = 0.1;

/// One labelled slab.
#[derive(Debug, Clone)]
struct Part {
    name: String,
    color: [f64; 3],
    mesh: Arc<Mesh>,
    pose: Pose,
    line: ([f64; 2], [f64; 2]),
}

/// The drawable scene of a layout.
#[derive(Debug, Clone)]
pub struct BallView {
    parts: Vec<Part>,
    /// Per ball of the layout: name, label, colour.
    balls: Vec<(String, (u32, &'static str), [f64; 3])>,
    sphere: Arc<Mesh>,
}

/// sRGB of a palette id.
pub fn color_of(id: usize) -> [f64; 3] {
    u8::try_from(id).ok().and_then(palette_color).map_or(
        [0.5, 0.5, 0.5],
        crate::perception::palette::PaletteColor::unit_rgb,
    )
}

fn slab_part(slab: &SlabLayout) -> Part {
    let centre = [
        f64::midpoint(slab.start[0], slab.end[0]),
        f64::midpoint(slab.start[1], slab.end[1]),
        0.0,
    ];
    Part {
        name: slab.name.clone(),
        color: color_of(slab.color),
        mesh: Arc::new(Mesh::cuboid([slab.length(), slab.thickness, SLAB_DEPTH])),
        pose: Pose::turned_about_z(centre, slab.angle()),
        line: (slab.start, slab.end),
    }
}

impl BallView {
    /// The parts of `layout`: slabs first (instance ids from 1), then the balls.
    pub fn new(layout: &Layout) -> BallView {
        let parts = layout.slabs().map(slab_part).collect();
        let balls = layout
            .balls
            .iter()
            .map(|ball| {
                let label = match ball.elasticity {
                    ElasticityType::Plastic => (2, "Plastic Ball"),
                    ElasticityType::Elastic | ElasticityType::Rigid => (1, "Elastic Ball"),
                };
                (ball.name.clone(), label, color_of(ball.color))
            })
            .collect();
        BallView {
            parts,
            balls,
            sphere: Arc::new(Mesh::sphere(BALL_RADIUS, SPHERE.0, SPHERE.1)),
        }
    }

    /// The instance id of ball `index` of the layout.
    fn ball_instance(&self, index: usize) -> u32 {
        u32::try_from(self.parts.len() + index + 1).unwrap_or(u32::MAX)
    }

    /// Every labelled object: the slabs, then the balls.
    pub fn labels(&self) -> Vec<LabelledObject> {
        let parts = self
            .parts
            .iter()
            .zip(1..)
            .map(|(part, instance)| LabelledObject {
                instance,
                name: part.name.clone(),
                label_id: 4,
                label_name: "Stick".to_string(),
            });
        let balls = self
            .balls
            .iter()
            .enumerate()
            .map(|(index, (name, label, _))| LabelledObject {
                instance: self.ball_instance(index),
                name: name.clone(),
                label_id: label.0,
                label_name: label.1.to_string(),
            });
        parts.chain(balls).collect()
    }

    /// The drawables of captured frame `frame` of the factual run.
    pub fn items(&self, run: &BallRun, frame: usize) -> Vec<Item> {
        let mut items: Vec<Item> = self
            .parts
            .iter()
            .zip(1..)
            .map(|(part, instance)| Item {
                mesh: part.mesh.clone(),
                pose: part.pose,
                color: part.color,
                instance,
                stripes: None,
            })
            .collect();
        if let Some(states) = run.frames.get(frame) {
            for (state, &index) in states.iter().zip(&run.balls) {
                let Some((_, _, color)) = self.balls.get(index) else {
                    continue;
                };
                items.push(Item {
                    mesh: self.sphere.clone(),
                    pose: Pose {
                        rotation: state.deformation,
                        translation: state.centre,
                    },
                    color: *color,
                    instance: self.ball_instance(index),
                    stripes: None,
                });
            }
        }
        items
    }

    /// World bounds of the static parts and of the balls' release points.
    pub fn bounds(&self, layout: &Layout) -> ([f64; 3], [f64; 3]) {
        let mut low = [f64::INFINITY; 3];
        let mut high = [f64::NEG_INFINITY; 3];
        for part in &self.parts {
            if let Some((a, b)) = part.mesh.transformed(&part.pose).bounds() {
                for axis in 0..3 {
                    low[axis] = low[axis].min(a[axis]);
                    high[axis] = high[axis].max(b[axis]);
                }
            }
        }
        for ball in &layout.balls {
            for axis in 0..3 {
                low[axis] = low[axis].min(ball.release[axis] - BALL_RADIUS);
                high[axis] = high[axis].max(ball.release[axis] + BALL_RADIUS);
            }
        }
        (low, high)
    }

    /// `outputs4D.json`: the static slabs (staticity, mesh, centre-line voxels) and each ball's
    /// tracked particles per captured frame.
    pub fn four_d(&self, run: &BallRun) -> Value {
        let parts: Vec<StaticPart<'_>> = self
            .parts
            .iter()
            .map(|part| StaticPart {
                name: &part.name,
                mesh: part.mesh.transformed(&part.pose),
                line: part.line,
            })
            .collect();
        let balls = run
            .balls
            .iter()
            .enumerate()
            .filter_map(|(slot, &index)| {
                let (name, _, _) = self.balls.get(index)?;
                let frames = run
                    .frames
                    .iter()
                    .filter_map(|states| states.get(slot))
                    .map(|state| state.particles.clone())
                    .collect();
                Some((name.clone(), frames))
            })
            .collect();
        four_d_document(&parts, VOXEL, balls)
    }
}
