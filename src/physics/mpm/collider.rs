//! Static colliders of the MPM core as signed distances (negative inside), at any angle: half
//! planes (floors, walls), capsules (sticks, funnel and container walls) and rectangles (slabs). Each grid node inside
//! a collider has its velocity projected once per substep by the collider's boundary condition
//! (sticky, slip, or separate with Coulomb friction), as taichi_elements does; the nodes each
//! collider reaches are found once, when the solver is built, since colliders do not move.
//!
//! Grid projection alone lets particles drift through a capsule about a cell thick: a particle
//! takes its velocity from all nine nodes of its stencil, most of them outside the collider.
//! So a particle that ends a substep inside a collider is also put back on its surface, its
//! velocity projected by the same boundary condition (counted in `WorkCounters::pushed_out`).
//! Only particles whose nearest node lies within two cells of a collider are tested.
//! [`Collider::node_radius`] is the thinnest capsule every point of whose axis has a node inside.

use super::{GridSpec, ParticleState};

/// A collider's shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// Everything on the side opposite `normal` from `point` is solid.
    HalfPlane {
        /// A point on the boundary.
        point: [f64; 2],
        /// Unit outward normal (pointing into the free side).
        normal: [f64; 2],
    },
    /// The rectangle around the segment `a`–`b`, `thickness` across it, with square ends (a
    /// slab: the ball scenario's ramps, floor pieces and floating walls).
    Rectangle {
        /// One end of the centre line.
        a: [f64; 2],
        /// The other end.
        b: [f64; 2],
        /// Full thickness across the centre line.
        thickness: f64,
    },
    /// Points within `radius` of the segment `a`–`b` are solid.
    Capsule {
        /// One end.
        a: [f64; 2],
        /// The other end.
        b: [f64; 2],
        /// Half thickness.
        radius: f64,
    },
}

/// What a collider does to the grid velocity of a node inside it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Boundary {
    /// The velocity becomes zero (the fluid sticks).
    Sticky,
    /// The normal component is removed, the tangential one kept (free slip, both ways).
    Slip,
    /// Only an approaching normal component is removed; the tangential one loses
    /// `friction × |normal|` (Coulomb), down to zero.
    Separate {
        /// Coulomb friction coefficient.
        friction: f64,
    },
}

/// A static collider.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Collider {
    /// Its shape.
    pub shape: Shape,
    /// Its boundary condition.
    pub boundary: Boundary,
}

impl Collider {
    /// Signed distance from `point` (negative inside) and the outward unit normal there.
    pub fn signed_distance(&self, point: [f64; 2]) -> (f64, [f64; 2]) {
        match self.shape {
            Shape::HalfPlane { point: on, normal } => (
                (point[0] - on[0]) * normal[0] + (point[1] - on[1]) * normal[1],
                normal,
            ),
            Shape::Rectangle { a, b, thickness } => {
                crate::physics::slab::signed_distance(point, a, b, thickness)
            }
            Shape::Capsule { a, b, radius } => {
                let ab = [b[0] - a[0], b[1] - a[1]];
                let ap = [point[0] - a[0], point[1] - a[1]];
                let length_squared = ab[0] * ab[0] + ab[1] * ab[1];
                let t = if length_squared > 0.0 {
                    ((ap[0] * ab[0] + ap[1] * ab[1]) / length_squared).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let offset = [ap[0] - t * ab[0], ap[1] - t * ab[1]];
                let distance = (offset[0] * offset[0] + offset[1] * offset[1]).sqrt();
                let normal = if distance > 0.0 {
                    [offset[0] / distance, offset[1] / distance]
                } else if length_squared > 0.0 {
                    // On the axis: push out across the segment.
                    let length = length_squared.sqrt();
                    [-ab[1] / length, ab[0] / length]
                } else {
                    [0.0, 1.0]
                };
                (distance - radius, normal)
            }
        }
    }

    /// The radius a capsule needs so that every point of its axis has a grid node inside it:
    /// half the diagonal of a cell.
    pub fn node_radius(spacing: f64) -> f64 {
        spacing * std::f64::consts::FRAC_1_SQRT_2
    }

    /// Checks that the numbers are finite and the normal is a unit vector.
    pub fn is_valid(&self) -> bool {
        let finite = |values: &[f64]| values.iter().all(|value| value.is_finite());
        let boundary_ok = match self.boundary {
            Boundary::Separate { friction } => friction.is_finite() && friction >= 0.0,
            Boundary::Sticky | Boundary::Slip => true,
        };
        let shape_ok = match self.shape {
            Shape::HalfPlane { point, normal } => {
                finite(&[point[0], point[1], normal[0], normal[1]])
                    && ((normal[0] * normal[0] + normal[1] * normal[1]).sqrt() - 1.0).abs() < 1e-9
            }
            Shape::Capsule { a, b, radius } => {
                finite(&[a[0], a[1], b[0], b[1], radius]) && radius >= 0.0
            }
            Shape::Rectangle { a, b, thickness } => {
                finite(&[a[0], a[1], b[0], b[1], thickness]) && thickness > 0.0
            }
        };
        boundary_ok && shape_ok
    }
}

/// Projects a node velocity by a boundary with outward normal `normal`.
#[inline]
pub(super) fn project(velocity: [f64; 2], normal: [f64; 2], boundary: Boundary) -> [f64; 2] {
    match boundary {
        Boundary::Sticky => [0.0, 0.0],
        Boundary::Slip => {
            let normal_speed = velocity[0] * normal[0] + velocity[1] * normal[1];
            [
                velocity[0] - normal_speed * normal[0],
                velocity[1] - normal_speed * normal[1],
            ]
        }
        Boundary::Separate { friction } => {
            let normal_speed = velocity[0] * normal[0] + velocity[1] * normal[1];
            if normal_speed >= 0.0 {
                return velocity;
            }
            let tangent = [
                velocity[0] - normal_speed * normal[0],
                velocity[1] - normal_speed * normal[1],
            ];
            let tangent_speed = (tangent[0] * tangent[0] + tangent[1] * tangent[1]).sqrt();
            if tangent_speed == 0.0 {
                return [0.0, 0.0];
            }
            let keep = (1.0 + friction * normal_speed / tangent_speed).max(0.0);
            [tangent[0] * keep, tangent[1] * keep]
        }
    }
}

/// Colliders rasterised onto the grid nodes, once, since they do not move.
#[derive(Debug, Clone)]
pub(super) struct ColliderGrid {
    colliders: Vec<Collider>,
    /// Per node: index into `constraints` of the collider it lies deepest inside, or `u32::MAX`.
    node_constraint: Vec<u32>,
    /// (outward normal at the node, boundary) of each constrained node.
    constraints: Vec<([f64; 2], Boundary)>,
    /// Per node: within two cells of some collider (particles there are tested).
    near: Vec<bool>,
}

impl ColliderGrid {
    /// Rasterises `colliders` onto the nodes of `grid`: a node is held by the collider it lies
    /// deepest in, counting nodes up to `layer` cells outside its surface (see
    /// [`super::Settings::collider_layer`]).
    pub(super) fn new(grid: &GridSpec, colliders: &[Collider], layer: f64) -> ColliderGrid {
        let node_count = grid.nodes[0] * grid.nodes[1];
        let mut rasterised = ColliderGrid {
            colliders: colliders.to_vec(),
            node_constraint: vec![u32::MAX; node_count],
            constraints: Vec::new(),
            near: vec![false; node_count],
        };
        if colliders.is_empty() {
            return rasterised;
        }
        let margin = 2.0 * grid.spacing;
        let held = layer * grid.spacing;
        for i in 0..grid.nodes[0] {
            for j in 0..grid.nodes[1] {
                let index = i * grid.nodes[1] + j;
                let position = grid.node_position(i, j);
                let distances = colliders
                    .iter()
                    .map(|collider| (collider.signed_distance(position), collider.boundary));
                let deepest = distances.clone().min_by(|a, b| a.0.0.total_cmp(&b.0.0));
                if let Some(((distance, normal), boundary)) = deepest {
                    rasterised.near[index] = distance < margin;
                    if distance < held {
                        rasterised.node_constraint[index] =
                            u32::try_from(rasterised.constraints.len()).unwrap_or(u32::MAX);
                        rasterised.constraints.push((normal, boundary));
                    }
                }
            }
        }
        rasterised
    }

    /// The colliders.
    pub(super) fn colliders(&self) -> &[Collider] {
        &self.colliders
    }

    /// Whether there is any collider (without, the per-node and per-particle tests are skipped).
    #[inline]
    pub(super) fn has_colliders(&self) -> bool {
        !self.colliders.is_empty()
    }

    /// The (outward normal, boundary) constraining node `index`, if it lies inside a collider.
    #[inline]
    pub(super) fn constraint(&self, index: usize) -> Option<([f64; 2], Boundary)> {
        let constraint = *self.node_constraint.get(index)?;
        self.constraints.get(constraint as usize).copied()
    }

    /// Puts a particle that ended a substep inside a collider back on the surface and projects
    /// its velocity; `nearest` is the index of the node nearest to it. Returns whether it moved.
    #[inline]
    pub(super) fn push_out(&self, particle: &mut ParticleState, nearest: usize) -> bool {
        if !self.near.get(nearest).copied().unwrap_or(false) {
            return false;
        }
        let mut moved = false;
        for collider in &self.colliders {
            let (distance, normal) = collider.signed_distance(particle.position);
            if distance < 0.0 {
                particle.position[0] -= distance * normal[0];
                particle.position[1] -= distance * normal[1];
                particle.velocity = project(particle.velocity, normal, collider.boundary);
                moved = true;
            }
        }
        moved
    }
}
