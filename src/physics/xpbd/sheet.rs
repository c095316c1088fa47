//! One cloth: a square grid of particles held by XPBD stretch constraints along the edges of its
//! triangle mesh and by Obi-style bend constraints, optionally gripped along its front edge by a
//! handle that drags it.
//!
//! * **Stretch**: a distance constraint per mesh edge (rows, columns and one diagonal per quad,
//!   alternating, as Obi builds distance constraints from a mesh's edges) with compliance α (m/N,
//!   the release's `stretchCompliance`, 0.011 or 0). It resists compression as much as stretch:
//!   the release's max compression is 0. With the Lagrange multiplier accumulated over a
//!   substep's iterations, the static stretch is α times the tension whatever the iteration
//!   count (XPBD).
//! * **Bend**: Obi's triplet constraint on three consecutive particles of a row or column: the
//!   middle one's distance from the triplet's centroid may exceed its rest value by the release's
//!   `maxBending` (0.013 or 0.035 m) freely; beyond that the constraint is rigid (the release's
//!   bend compliance is 0). A larger max bending is a cloth that folds and wrinkles more easily.
//!
//! Particle masses follow the area each particle stands for (a third of each incident triangle),
//! so edge and corner particles are lighter, as in an Obi cloth blueprint. Units: metres,
//! kilograms, seconds. Input: a [`SheetSpec`]. Output: particle positions after each substep and
//! the stretch constraints' forces.

use crate::physics::vector3::{self as v3, Vector};

/// The cloth's material, as the release sets it per cloth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SheetProperties {
    /// Stretch compliance, m/N (the release: 0.011 or 0).
    pub stretch_compliance: f64,
    /// Bending allowed before the bend constraint acts, metres (the release: 0.013 or 0.035).
    pub max_bending: f64,
    /// Dynamic friction coefficient of the cloth's contacts with boxes and the table, already
    /// combined with theirs.
    pub friction: f64,
}

/// A flat square cloth lying in the x–z plane.
#[derive(Debug, Clone, PartialEq)]
pub struct SheetSpec {
    /// Particles along each side (the release: 31).
    pub resolution: usize,
    /// Side length, metres.
    pub side: f64,
    /// Position of particle (0, 0), the back-left corner; the grid grows along +x (columns) and
    /// +z (rows), so the last row is the front edge.
    pub corner: Vector,
    /// Total mass, kilograms.
    pub mass: f64,
    /// Contact radius of a particle (half the cloth's thickness), metres.
    pub particle_radius: f64,
    /// Its material.
    pub properties: SheetProperties,
}

/// A distance constraint between two particles.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Edge {
    a: usize,
    b: usize,
    rest: f64,
}

/// A bend constraint on three consecutive particles.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Triplet {
    a: usize,
    middle: usize,
    b: usize,
    rest: f64,
}

/// A simulated cloth.
#[derive(Debug, Clone, PartialEq)]
pub struct Sheet {
    resolution: usize,
    spacing: f64,
    particle_radius: f64,
    properties: SheetProperties,
    /// Particle positions, metres.
    pub(super) positions: Vec<Vector>,
    /// Positions at the start of the substep.
    pub(super) previous: Vec<Vector>,
    /// Velocities, m/s.
    pub(super) velocities: Vec<Vector>,
    /// Inverse masses, 1/kg (0 while gripped).
    pub(super) inverse_masses: Vec<f64>,
    masses: Vec<f64>,
    edges: Vec<Edge>,
    triplets: Vec<Triplet>,
    triangles: Vec<[usize; 3]>,
    /// The stretch constraints' accumulated multipliers of the current substep, kg m.
    stretch_multipliers: Vec<f64>,
    /// Gripped particles (the front edge while the handle holds it).
    grip: Vec<usize>,
    /// The handle's velocity, m/s: gripped particles move with it.
    handle_velocity: Vector,
}

impl Sheet {
    /// Builds the cloth at rest. `resolution` below 2 is raised to 2.
    pub fn new(spec: &SheetSpec) -> Sheet {
        let n = spec.resolution.max(2);
        let spacing = spec.side / (n - 1) as f64;
        let index = |column: usize, row: usize| row * n + column;
        let positions: Vec<Vector> = (0..n * n)
            .map(|k| {
                let (column, row) = (k % n, k / n);
                v3::add(
                    spec.corner,
                    [column as f64 * spacing, 0.0, row as f64 * spacing],
                )
            })
            .collect();
        let mut triangles = Vec::with_capacity(2 * (n - 1) * (n - 1));
        let mut edges = Vec::new();
        let mut add_edge = |a: usize, b: usize| {
            edges.push(Edge {
                a,
                b,
                rest: v3::norm(v3::sub(positions[a], positions[b])),
            });
        };
        for row in 0..n {
            for column in 0..n {
                if column + 1 < n {
                    add_edge(index(column, row), index(column + 1, row));
                }
                if row + 1 < n {
                    add_edge(index(column, row), index(column, row + 1));
                }
                if column + 1 < n && row + 1 < n {
                    let [p00, p10] = [index(column, row), index(column + 1, row)];
                    let [p01, p11] = [index(column, row + 1), index(column + 1, row + 1)];
                    // Alternate the diagonal so that the mesh has no preferred shear direction.
                    if (row + column) % 2 == 0 {
                        add_edge(p00, p11);
                        triangles.push([p00, p11, p10]);
                        triangles.push([p00, p01, p11]);
                    } else {
                        add_edge(p10, p01);
                        triangles.push([p00, p01, p10]);
                        triangles.push([p10, p01, p11]);
                    }
                }
            }
        }
        let mut triplets = Vec::new();
        for row in 0..n {
            for column in 1..n - 1 {
                triplets.push((
                    index(column - 1, row),
                    index(column, row),
                    index(column + 1, row),
                ));
            }
        }
        for column in 0..n {
            for row in 1..n - 1 {
                triplets.push((
                    index(column, row - 1),
                    index(column, row),
                    index(column, row + 1),
                ));
            }
        }
        let triplets: Vec<Triplet> = triplets
            .into_iter()
            .map(|(a, middle, b)| Triplet {
                a,
                middle,
                b,
                rest: v3::norm(centroid_offset(&positions, a, middle, b)),
            })
            .collect();
        let mut areas = vec![0.0; n * n];
        for triangle in &triangles {
            let [a, b, c] = triangle.map(|k| positions[k]);
            let area = 0.5 * v3::norm(v3::cross(v3::sub(b, a), v3::sub(c, a)));
            for &k in triangle {
                areas[k] += area / 3.0;
            }
        }
        let total_area: f64 = areas.iter().sum();
        let masses: Vec<f64> = areas.iter().map(|a| spec.mass * a / total_area).collect();
        Sheet {
            resolution: n,
            spacing,
            particle_radius: spec.particle_radius,
            properties: spec.properties,
            previous: positions.clone(),
            velocities: vec![[0.0; 3]; n * n],
            inverse_masses: masses.iter().map(|m| 1.0 / m).collect(),
            masses,
            stretch_multipliers: vec![0.0; edges.len()],
            positions,
            edges,
            triplets,
            triangles,
            grip: Vec::new(),
            handle_velocity: [0.0; 3],
        }
    }

    /// Particles per side.
    pub fn resolution(&self) -> usize {
        self.resolution
    }

    /// Rest distance between neighbouring particles, metres.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// Contact radius of a particle, metres.
    pub fn particle_radius(&self) -> f64 {
        self.particle_radius
    }

    /// The material.
    pub fn properties(&self) -> SheetProperties {
        self.properties
    }

    /// Particle positions, row by row from the back edge, metres.
    pub fn positions(&self) -> &[Vector] {
        &self.positions
    }

    /// Particle velocities, m/s.
    pub fn velocities(&self) -> &[Vector] {
        &self.velocities
    }

    /// Particle masses, kilograms.
    pub fn masses(&self) -> &[f64] {
        &self.masses
    }

    /// The stretch constraints: `(particle, particle, rest length in metres)`.
    pub fn edges(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.edges.iter().map(|edge| (edge.a, edge.b, edge.rest))
    }

    /// The mesh's triangles (particle indices, counter-clockwise seen from +y at rest).
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// Grips the front edge (the last row): its particles stop responding to forces and move
    /// with the handle.
    pub fn grip_front_edge(&mut self) {
        let n = self.resolution;
        self.grip = ((n - 1) * n..n * n).collect();
        for &k in &self.grip {
            self.inverse_masses[k] = 0.0;
        }
    }

    /// Sets the handle's velocity, m/s.
    pub fn set_handle_velocity(&mut self, velocity: Vector) {
        self.handle_velocity = velocity;
    }

    /// Lets go of the gripped particles; they keep the handle's velocity.
    pub fn release(&mut self) {
        for &k in &self.grip {
            self.inverse_masses[k] = 1.0 / self.masses[k];
            self.velocities[k] = self.handle_velocity;
        }
        self.grip.clear();
        self.handle_velocity = [0.0; 3];
    }

    /// Whether the handle holds the cloth.
    pub fn is_gripped(&self) -> bool {
        !self.grip.is_empty()
    }

    /// Mean stretch-constraint force (N) over the last substep in each quadrant of the cloth's
    /// grid, by the edge's midpoint: `[+x +z, −x +z, −x −z, +x −z]` (quadrants 1 to 4, with x
    /// along columns and z along rows from the grid's centre). `h` is the substep, seconds.
    pub fn quadrant_forces(&self, h: f64) -> [f64; 4] {
        let n = self.resolution;
        let centre = (n - 1) as f64 / 2.0;
        let mut sums = [0.0; 4];
        let mut counts = [0usize; 4];
        for (edge, multiplier) in self.edges.iter().zip(&self.stretch_multipliers) {
            let column = ((edge.a % n) + (edge.b % n)) as f64 / 2.0 - centre;
            let row = ((edge.a / n) + (edge.b / n)) as f64 / 2.0 - centre;
            let quadrant = match (column >= 0.0, row >= 0.0) {
                (true, true) => 0,
                (false, true) => 1,
                (false, false) => 2,
                (true, false) => 3,
            };
            sums[quadrant] += multiplier.abs() / (h * h);
            counts[quadrant] += 1;
        }
        std::array::from_fn(|q| sums[q] / counts[q].max(1) as f64)
    }

    /// Starts a substep of `h` seconds: remembers positions, adds gravity (m/s²) and
    /// damping (1/s), moves free particles by their velocities and gripped ones with the handle,
    /// and clears the multipliers.
    pub(super) fn predict(&mut self, h: f64, gravity: Vector, damping: f64) {
        let keep = (1.0 - damping * h).max(0.0);
        for k in 0..self.positions.len() {
            self.previous[k] = self.positions[k];
            if self.inverse_masses[k] > 0.0 {
                // Damping before gravity: damping the gravity increment too would lower the
                // static load, and the cloth would stretch less than its compliance says.
                let damped = v3::scale(self.velocities[k], keep);
                self.velocities[k] = v3::add(damped, v3::scale(gravity, h));
            }
        }
        for &k in &self.grip {
            self.velocities[k] = self.handle_velocity;
        }
        for (position, velocity) in self.positions.iter_mut().zip(&self.velocities) {
            *position = v3::add(*position, v3::scale(*velocity, h));
        }
        self.stretch_multipliers.fill(0.0);
    }

    /// Ends a substep: velocities from the position change, capped at `max_speed` (m/s).
    pub(super) fn derive_velocities(&mut self, h: f64, max_speed: f64) {
        for k in 0..self.positions.len() {
            let velocity = v3::scale(v3::sub(self.positions[k], self.previous[k]), 1.0 / h);
            let speed = v3::norm(velocity);
            self.velocities[k] = if speed > max_speed {
                v3::scale(velocity, max_speed / speed)
            } else {
                velocity
            };
        }
    }

    /// One Gauss–Seidel pass over the stretch constraints of a substep of `h` seconds.
    pub(super) fn project_stretch(&mut self, h: f64) {
        let scaled_compliance = self.properties.stretch_compliance / (h * h);
        for (edge, multiplier) in self.edges.iter().zip(self.stretch_multipliers.iter_mut()) {
            let (wa, wb) = (self.inverse_masses[edge.a], self.inverse_masses[edge.b]);
            let weight = wa + wb + scaled_compliance;
            if weight <= 0.0 {
                continue;
            }
            let between = v3::sub(self.positions[edge.a], self.positions[edge.b]);
            let length = v3::norm(between);
            if length < 1e-12 {
                continue;
            }
            let direction = v3::scale(between, 1.0 / length);
            let violation = length - edge.rest;
            let change = (-violation - scaled_compliance * *multiplier) / weight;
            *multiplier += change;
            self.positions[edge.a] =
                v3::add(self.positions[edge.a], v3::scale(direction, wa * change));
            self.positions[edge.b] =
                v3::sub(self.positions[edge.b], v3::scale(direction, wb * change));
        }
    }

    /// One Gauss–Seidel pass over the bend constraints (rigid beyond the max bending).
    pub(super) fn project_bend(&mut self) {
        let allowance = self.properties.max_bending;
        for triplet in &self.triplets {
            let offset = centroid_offset(&self.positions, triplet.a, triplet.middle, triplet.b);
            let distance = v3::norm(offset);
            let violation = distance - triplet.rest - allowance;
            if violation <= 0.0 || distance < 1e-12 {
                continue;
            }
            let direction = v3::scale(offset, 1.0 / distance);
            let (wa, wm, wb) = (
                self.inverse_masses[triplet.a],
                self.inverse_masses[triplet.middle],
                self.inverse_masses[triplet.b],
            );
            // ∂C/∂x_middle = 2/3 n, ∂C/∂x_a = ∂C/∂x_b = −1/3 n.
            let weight = wm * 4.0 / 9.0 + (wa + wb) / 9.0;
            if weight <= 0.0 {
                continue;
            }
            let change = -violation / weight;
            let middle = v3::scale(direction, wm * change * 2.0 / 3.0);
            self.positions[triplet.middle] = v3::add(self.positions[triplet.middle], middle);
            for (end, w) in [(triplet.a, wa), (triplet.b, wb)] {
                self.positions[end] =
                    v3::sub(self.positions[end], v3::scale(direction, w * change / 3.0));
            }
        }
    }

    /// Whether every position and velocity is finite.
    pub fn is_finite(&self) -> bool {
        self.positions
            .iter()
            .chain(&self.velocities)
            .all(|p| p.iter().all(|v| v.is_finite()))
    }

    /// Grid neighbours within one row and column (their contacts are the cloth's own
    /// structure, not self-collision).
    pub(super) fn are_neighbours(&self, a: usize, b: usize) -> bool {
        let n = self.resolution;
        (a % n).abs_diff(b % n) <= 1 && (a / n).abs_diff(b / n) <= 1
    }
}

/// `x_middle − (x_a + x_middle + x_b) / 3`.
fn centroid_offset(positions: &[Vector], a: usize, middle: usize, b: usize) -> Vector {
    let sum = v3::add(v3::add(positions[a], positions[middle]), positions[b]);
    v3::sub(positions[middle], v3::scale(sum, 1.0 / 3.0))
}
