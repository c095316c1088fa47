//! What a fluid video shows: the tank, sticks, containers and emitters as boxes in their palette
//! colours, each fluid as a flat coloured surface over its particles, with the release's labels
//! (`FluidSlidesIdLabelConfig`), and the 4-D data (`outputs4D.json`).
//!
//! A fluid's surface is the union of discs of one particle spacing round its particles, so
//! neighbouring particles merge into one surface and a lone drop stays a dot. The release
//! labelled no fluid; fluids here carry the extra label `Fluid` (id 11), so perception can learn
//! and be checked on them, and the emitter boxes are named `<fluid> Emitter` (the release's
//! static part name) because the fluid surface takes the fluid's name.

use std::sync::Arc;

use serde_json::Value;

use super::layout::{EMITTER_WIDTH, Layout};
use super::simulate::{FluidRun, FluidScene};
use crate::physics::fluid::FluidParameters;
use crate::synth::annotate::LabelledObject;
use crate::synth::mesh::{Mesh, Pose};
use crate::synth::palette::palette_color;
use crate::synth::{Item, StaticPart, four_d_document};

/// Depth (z extent) of every box, units (`receptor_scale_z`).
const DEPTH: f64 = 0.2;
/// Colour of the tank walls (the release's light gray wall material), sRGB.
const WALL_COLOR: [f64; 3] = [0.78, 0.78, 0.76];
/// Disc radius round each particle of a fluid surface, in particle spacings.
const SURFACE_RADIUS_SPACINGS: f64 = 1.0;
/// Voxel spacing along a part's centre line in the 4-D data, units (the release: 0.07).
const VOXEL: f64 = 0.07;
/// Tracked particles: every 15th of an emitter's (`interval_particle_sample_output`).
const TRACKED_EVERY: usize = 15;

/// One labelled box of the scene.
#[derive(Debug, Clone)]
struct Part {
    name: String,
    label: (u32, &'static str),
    color: [f64; 3],
    mesh: Arc<Mesh>,
    pose: Pose,
    /// Centre line end points, world units (for the 4-D voxels).
    line: ([f64; 2], [f64; 2]),
}

/// The drawable scene of a layout.
#[derive(Debug, Clone)]
pub struct FluidView {
    parts: Vec<Part>,
    /// Per emitter key: its fluid surface's name, label instance and colour.
    fluids: Vec<(String, u32, [f64; 3])>,
}

fn color_of(id: usize) -> [f64; 3] {
    u8::try_from(id).ok().and_then(palette_color).map_or(
        [0.5, 0.5, 0.5],
        crate::perception::palette::PaletteColor::unit_rgb,
    )
}

fn bar(start: [f64; 2], end: [f64; 2], thickness: f64) -> (Arc<Mesh>, Pose) {
    let length = (end[0] - start[0]).hypot(end[1] - start[1]);
    let angle = (end[1] - start[1]).atan2(end[0] - start[0]);
    let centre = [
        f64::midpoint(start[0], end[0]),
        f64::midpoint(start[1], end[1]),
        0.0,
    ];
    (
        Arc::new(Mesh::cuboid([length + thickness, thickness, DEPTH])),
        Pose::turned_about_z(centre, angle),
    )
}

impl FluidView {
    /// The parts of `scene` (built from `layout`), with instance ids in scene order.
    pub fn new(layout: &Layout, scene: &FluidScene) -> FluidView {
        let mut parts = Vec::new();
        let mut push = |name: &str, label, color, start, end, thickness| {
            let (mesh, pose) = bar(start, end, thickness);
            parts.push(Part {
                name: name.to_string(),
                label,
                color,
                mesh,
                pose,
                line: (start, end),
            });
        };
        for named in &scene.colliders {
            let c = &named.collider;
            let thickness = 2.0 * c.half_thickness;
            let name = named.name.as_str();
            // Capsules are drawn as boxes their length plus thickness long (the walls' corners).
            let label = match name {
                "Left Vertical Wall" => (1, "WallVertical1"),
                "Floor" => (2, "WallHorizonal"),
                "Right Vertical Wall" => (3, "WallVertical2"),
                _ if name.ends_with("Bottom Floor") => (9, "ReceptorHorizonal"),
                _ if name.ends_with("Left Vertical Wall") => (8, "ReceptorVertical1"),
                _ if name.ends_with("Right Vertical Wall") => (10, "ReceptorVertical2"),
                _ if name.contains("Emitter") => continue,
                _ => (6, "Stick"),
            };
            let color = if label.0 <= 3 {
                WALL_COLOR
            } else if let Some(stick) = layout.sticks.iter().find(|s| s.name == name) {
                color_of(stick.color)
            } else {
                layout
                    .containers
                    .iter()
                    .find(|container| name.starts_with(&container.name))
                    .map_or(WALL_COLOR, |container| color_of(container.color))
            };
            push(name, label, color, c.start, c.end, thickness);
        }
        // The ceiling: drawn, not a collider.
        let top = scene.colliders.first().map_or(3.35, |wall| {
            wall.collider.start[1].max(wall.collider.end[1])
        });
        push(
            "Ceiling",
            (2, "WallHorizonal"),
            WALL_COLOR,
            [-3.2, top - 0.25],
            [3.2, top - 0.25],
            0.5,
        );
        for emitter in &scene.emitters {
            let color = color_of(layout.fluids[emitter.fluid].color);
            let [x, y] = emitter.centre;
            push(
                &format!("{} Emitter", emitter.name),
                (4, "Emitter"),
                color,
                [x - EMITTER_WIDTH / 2.0, y],
                [x + EMITTER_WIDTH / 2.0, y],
                0.25,
            );
        }
        #[expect(clippy::cast_possible_truncation, reason = "a few dozen parts")]
        let first_fluid = parts.len() as u32 + 1;
        let fluids = scene
            .emitters
            .iter()
            .zip(first_fluid..)
            .map(|(emitter, instance)| {
                let color = color_of(layout.fluids[emitter.fluid].color);
                (emitter.name.clone(), instance, color)
            })
            .collect();
        FluidView { parts, fluids }
    }

    /// Every labelled object: the parts, then the fluids.
    pub fn labels(&self) -> Vec<LabelledObject> {
        let parts = self
            .parts
            .iter()
            .zip(1..)
            .map(|(part, instance)| LabelledObject {
                instance,
                name: part.name.clone(),
                label_id: part.label.0,
                label_name: part.label.1.to_string(),
            });
        let fluids = self
            .fluids
            .iter()
            .map(|(name, instance, _)| LabelledObject {
                instance: *instance,
                name: name.clone(),
                label_id: 11,
                label_name: "Fluid".to_string(),
            });
        parts.chain(fluids).collect()
    }

    /// The drawables of a frame whose particles are `positions` (the first `positions.len()`
    /// of `run.emitter_of`).
    pub fn items(&self, run: &FluidRun, positions: &[[f64; 2]]) -> Vec<Item> {
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
        for (key, (_, instance, color)) in self.fluids.iter().enumerate() {
            let points: Vec<[f64; 2]> = positions
                .iter()
                .zip(&run.emitter_of)
                .filter(|(_, emitter)| **emitter == key)
                .map(|(p, _)| *p)
                .collect();
            if let Some(mesh) = surface(&points) {
                items.push(Item {
                    mesh: Arc::new(mesh),
                    pose: Pose::at([0.0, 0.0, 0.0]),
                    color: *color,
                    instance: *instance,
                    stripes: None,
                });
            }
        }
        items
    }

    /// World bounds of the static parts, for framing the camera.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut low = [f64::INFINITY; 3];
        let mut high = [f64::NEG_INFINITY; 3];
        for part in &self.parts {
            let mesh = part.mesh.transformed(&part.pose);
            if let Some((a, b)) = mesh.bounds() {
                for axis in 0..3 {
                    low[axis] = low[axis].min(a[axis]);
                    high[axis] = high[axis].max(b[axis]);
                }
            }
        }
        (low, high)
    }

    /// `outputs4D.json`: the static parts (staticity, first-capture mesh, pose and centre-line
    /// voxels) and each fluid key's tracked particles per frame.
    pub fn four_d(&self, run: &FluidRun) -> Value {
        let parts: Vec<StaticPart<'_>> = self
            .parts
            .iter()
            .map(|part| StaticPart {
                name: &part.name,
                mesh: part.mesh.transformed(&part.pose),
                line: part.line,
            })
            .collect();
        let fluids = self
            .fluids
            .iter()
            .enumerate()
            .map(|(key, (name, _, _))| {
                let ids: Vec<usize> = run
                    .emitter_of
                    .iter()
                    .enumerate()
                    .filter(|(_, emitter)| **emitter == key)
                    .map(|(particle, _)| particle)
                    .step_by(TRACKED_EVERY)
                    .collect();
                let frames = run
                    .frames
                    .iter()
                    .map(|positions| {
                        ids.iter()
                            .filter_map(|&id| positions.get(id))
                            .map(|p| [p[0], p[1], 0.0])
                            .collect()
                    })
                    .collect();
                (name.clone(), frames)
            })
            .collect();
        four_d_document(&parts, VOXEL, fluids)
    }
}

/// A flat mesh (at `z = 0`, facing −z) covering discs round `points`: an octagon of
/// [`SURFACE_RADIUS_SPACINGS`] spacings round every particle, so packed particles (a spacing
/// apart) merge into one surface and a lone drop stays a dot. Discs rather than a grid: a
/// surface made of cells finer than a pixel would leave holes at low resolutions. `None` without
/// points.
fn surface(points: &[[f64; 2]]) -> Option<Mesh> {
    if points.is_empty() {
        return None;
    }
    let radius = SURFACE_RADIUS_SPACINGS * FluidParameters::default().spacing;
    let rim: Vec<[f64; 2]> = (0..8)
        .map(|k| {
            let angle = f64::from(k) * std::f64::consts::FRAC_PI_4;
            [radius * angle.cos(), radius * angle.sin()]
        })
        .collect();
    let normal = [0.0, 0.0, -1.0];
    let mut mesh = Mesh::default();
    for p in points {
        let base = u32::try_from(mesh.positions.len()).unwrap_or(u32::MAX);
        mesh.positions.push([p[0], p[1], 0.0]);
        for offset in &rim {
            mesh.positions
                .push([p[0] + offset[0], p[1] + offset[1], 0.0]);
        }
        mesh.normals.extend(std::iter::repeat_n(normal, 9));
        mesh.along.extend(std::iter::repeat_n(0.0, 9));
        for k in 0..8 {
            mesh.triangles
                .push([base, base + 1 + k, base + 1 + (k + 1) % 8]);
        }
    }
    Some(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fluid_surface_covers_its_particles_and_nothing_far_from_them() {
        let spacing = FluidParameters::default().spacing;
        let row: Vec<[f64; 2]> = (0..10).map(|k| [f64::from(k) * spacing, 0.0]).collect();
        let mesh = surface(&row).unwrap();
        assert_eq!(mesh.triangles.len(), 80);
        let radius = SURFACE_RADIUS_SPACINGS * spacing;
        // Every vertex lies within a disc radius of a particle, and the midpoint between two
        // neighbours is covered by both their discs (the surface has no gap between them).
        for p in &mesh.positions {
            let nearest = row
                .iter()
                .map(|q| (p[0] - q[0]).hypot(p[1] - q[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(nearest <= radius + 1e-12);
        }
        // An octagon's inner radius is cos(22.5°) of its outer: still over half a spacing.
        assert!(radius * (std::f64::consts::PI / 8.0).cos() > spacing / 2.0);
        assert!(surface(&[]).is_none());
    }
}
