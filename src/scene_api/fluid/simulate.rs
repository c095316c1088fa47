//! ContPRO's fluid dynamics (`--dynamics simulate`): the scene rebuilt from what perception sees,
//! simulated with MLS-MPM (`physics::mpm`), and labelled by the release's rules
//! (`dataset::fluid::outcome`), so a simulated run answers `happen` exactly as a recorded
//! `trackingData` would. The truth comes from position-based fluids (`physics::fluid`); this is a
//! different method on purpose (DESIGN.md §10).
//!
//! **Scene.** Every collider is a box in `allObjectTransforms` (centre, angle, length ×
//! thickness), simulated as a capsule along its length with half its thickness as radius:
//! sticks, the containers' funnel sticks, cup floors and walls, and the emitters' side walls. The
//! tank's walls and floor are the MPM grid's own walls, placed on their inner faces. Each emitter
//! sits between its two side walls and releases rows of particles downwards from the bottom of
//! its box, [`EMITTER_SPEED`] fast, until it has released its 1,500 particles; first emitters open
//! at update 2, later ones at update 460 (`dataset::fluid::world`).
//!
//! **Materials.** One material per emitter (a later emitter is a fluid key of its own, as in the
//! release), weakly compressible: bulk modulus `ρ c²` with one sound speed `c` for every fluid,
//! and a kinematic viscosity by class ([`RunSettings`]).
//!
//! **Labels.** After every update (1/60 s) each particle records the colliders whose surface it
//! is within [`RunSettings::contact_reach`] of; the final positions after the last update give
//! the containers' contents. Both go through the release's counting
//! (`emitter_stick_stat`, `receptor_fluid_stat`, `density_relations`). An emitter releases the
//! release's volume of fluid (1,500 particles of spacing 1/40) in particles of half the grid
//! spacing; before counting, each emitter's particles are resampled evenly to the release's
//! count, so the thresholds (more than 20 particles) mean the same fraction at any resolution.
//!
//! Input: the perceived [`FluidGeometry`], the containers' boxes, the fluids' inferred
//! [`FluidMaterialGuess`]es and the run to make. Output: a [`SimulatedRun`]: its
//! [`FluidTracking`] and the work done.

use indexmap::IndexMap;

use crate::dataset::fluid::base_fluid_name;
use crate::dataset::fluid::outcome::{
    Receptor, density_relations, emitter_stick_stat, is_regular_stick, receptor_fluid_stat,
    temperature_askable_sticks,
};
use crate::dataset::fluid::world::{
    COUNTERFACTUAL_UPDATES, EMITTER_OPEN_UPDATE, FACTUAL_UPDATES, NORMAL_TEMPERATURE,
    PARTICLES_PER_EMITTER, PREDICTIVE_EMITTER_OPEN_UPDATE, UPDATE_SECONDS,
};
use crate::dataset::fluid::{DensityRelation, FluidAnnotation, FluidTracking};
use crate::physics::mpm::{
    Boundary, Collider, Emitter, GridSpec, LiquidMaterial, Material, MpmError, ParticleState,
    Settings, Shape, Solver, Walls, WorkCounters,
};

/// The world's gravity, units/s² downwards: the release's setting, which a falling particle in
/// the video shows.
pub const GRAVITY: f64 = 4.8;
/// Emission speed, units/s: the release's emitters all release at 0.7.
pub const EMITTER_SPEED: f64 = 0.7;
/// Height of an emitter's box, units: particles leave from its bottom edge.
const EMITTER_HEIGHT: f64 = 0.25;
/// Inner faces of the tank: x = ±2.7, the floor's top at y = −4.0; nothing rises above y = 3.2
/// (the emitters sit at 2.85, the ceiling, which does not collide, at 3.1).
pub(crate) const TANK_INNER: [[f64; 2]; 2] = [[-2.7, -4.0], [2.7, 3.2]];
/// Coulomb friction of every collider against the fluid.
const COLLIDER_FRICTION: f64 = 0.3;
/// Grid nodes of the domain walls on each side (the tank's walls).
const WALL_NODES: usize = 3;

/// A collider as perception sees it: a named box, simulated as a capsule.
#[derive(Debug, Clone, PartialEq)]
pub struct PerceivedCollider {
    /// Scene object name (`Red Stick`, `Blue Container Bottom Floor`).
    pub name: String,
    /// One end of its centre line, world units.
    pub start: [f64; 2],
    /// The other end.
    pub end: [f64; 2],
    /// Half its thickness, units.
    pub radius: f64,
}

impl PerceivedCollider {
    /// The MPM collider it is simulated as (and whose surface contacts are measured from).
    fn capsule(&self) -> Collider {
        Collider {
            shape: Shape::Capsule {
                a: self.start,
                b: self.end,
                radius: self.radius,
            },
            boundary: Boundary::Separate {
                friction: COLLIDER_FRICTION,
            },
        }
    }
}

/// An emitter as perception sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct PerceivedEmitter {
    /// Its fluid key (`Blue Fluid`, `Later Emitted Blue Fluid`).
    pub key: String,
    /// Centre of its box, world units.
    pub centre: [f64; 2],
    /// Inner width between its side walls, units.
    pub width: f64,
    /// Whether it is a later (predictive) emitter.
    pub later: bool,
}

/// The scene's static geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct FluidGeometry {
    /// Colliders, in the order perception lists them.
    pub colliders: Vec<PerceivedCollider>,
    /// Emitters: first emitters, then later ones, each in listing order.
    pub emitters: Vec<PerceivedEmitter>,
}

/// Why the geometry cannot be read.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum GeometryError {
    /// An emitter lacks one of its two side walls.
    #[error("allObjectTransforms: the {key} Emitter has no {side} Wall")]
    MissingEmitterWall {
        /// The emitter's fluid key.
        key: String,
        /// `Left` or `Right`.
        side: &'static str,
    },
    /// A transform holds a number that is not finite or a negative size.
    #[error("allObjectTransforms: `{0}` has a position, angle or scale that is not finite")]
    BadTransform(String),
}

impl FluidGeometry {
    /// The geometry of `annotation`'s `allObjectTransforms` (annotation perception): every box
    /// but the tank's walls and floor (the grid's walls) is a collider; emitters are found by
    /// their side walls.
    pub fn from_annotation(annotation: &FluidAnnotation) -> Result<FluidGeometry, GeometryError> {
        const TANK: [&str; 3] = ["Left Vertical Wall", "Right Vertical Wall", "Floor"];
        let mut colliders = Vec::new();
        for (name, transform) in &annotation.object_transforms {
            if TANK.contains(&name.as_str()) {
                continue;
            }
            let [x, y, _] = transform.position;
            let angle = transform.rotation_deg[2].to_radians();
            let [length, thickness, _] = transform.scale;
            if ![x, y, angle, length, thickness]
                .iter()
                .all(|value| value.is_finite())
                || length < 0.0
                || thickness < 0.0
            {
                return Err(GeometryError::BadTransform(name.clone()));
            }
            let half = [0.5 * length * angle.cos(), 0.5 * length * angle.sin()];
            colliders.push(PerceivedCollider {
                name: name.clone(),
                start: [x - half[0], y - half[1]],
                end: [x + half[0], y + half[1]],
                radius: 0.5 * thickness,
            });
        }
        let mut emitters = Vec::new();
        for later in [false, true] {
            for collider in &colliders {
                let Some(key) = collider.name.strip_suffix(" Emitter Left Wall") else {
                    continue;
                };
                if key.starts_with("Later Emitted ") != later {
                    continue;
                }
                let right_name = format!("{key} Emitter Right Wall");
                let right = colliders
                    .iter()
                    .find(|other| other.name == right_name)
                    .ok_or_else(|| GeometryError::MissingEmitterWall {
                        key: key.to_string(),
                        side: "Right",
                    })?;
                let centre = |c: &PerceivedCollider| {
                    [0.5 * (c.start[0] + c.end[0]), 0.5 * (c.start[1] + c.end[1])]
                };
                let (left_centre, right_centre) = (centre(collider), centre(right));
                let width =
                    (right_centre[0] - left_centre[0]).abs() - collider.radius - right.radius;
                emitters.push(PerceivedEmitter {
                    key: key.to_string(),
                    centre: [
                        0.5 * (left_centre[0] + right_centre[0]),
                        0.5 * (left_centre[1] + right_centre[1]),
                    ],
                    width: width.max(0.0),
                    later,
                });
            }
        }
        // A right wall without its left wall is as broken as the reverse.
        for collider in &colliders {
            if let Some(key) = collider.name.strip_suffix(" Emitter Right Wall")
                && !emitters.iter().any(|emitter| emitter.key == key)
            {
                return Err(GeometryError::MissingEmitterWall {
                    key: key.to_string(),
                    side: "Left",
                });
            }
        }
        Ok(FluidGeometry {
            colliders,
            emitters,
        })
    }
}

/// A fluid's material as inferred from the video.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FluidMaterialGuess {
    /// Rest density, kg/m³ (a value of the release's pool, by inferred rank).
    pub density: f64,
    /// Whether the fluid is `Sticky` (slow, viscous) rather than `Non-Sticky`.
    pub sticky: bool,
}

/// Resolution and material constants of the simulation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSettings {
    /// Grid spacing, units.
    pub grid_spacing: f64,
    /// Particles laid per cell along each axis (2: four per cell, spacing half the grid's).
    pub particles_per_cell_side: u32,
    /// Sound speed of every fluid, units/s: ten times the fastest flow would be incompressible
    /// to 1%; a fraction of that is the usual weakly compressible compromise.
    pub sound_speed: f64,
    /// Kinematic viscosity of a `Non-Sticky` fluid, units²/s.
    pub thin_viscosity: f64,
    /// Kinematic viscosity of a `Sticky` fluid, units²/s.
    pub sticky_viscosity: f64,
    /// A particle touches a collider when its centre is this close to the surface, units (at
    /// least 0.75 grid spacings: MPM keeps fluid about half a cell off a collider, so a shorter
    /// reach would miss fluid lying on it). A fixed reach makes "touched" a layer of fluid of
    /// one thickness at every resolution, as the release's contacts are (its particles have one
    /// radius); a reach in grid spacings made the share that touches a stick shrink with the
    /// grid (`bench physics --scenario fluid`).
    pub contact_reach: f64,
    /// Coulomb friction of every collider against the fluid.
    pub collider_friction: f64,
    /// Solver threads.
    pub threads: usize,
}

impl Default for RunSettings {
    fn default() -> Self {
        RunSettings {
            grid_spacing: 0.05,
            particles_per_cell_side: 2,
            sound_speed: 20.0,
            thin_viscosity: 1e-4,
            sticky_viscosity: 0.05,
            contact_reach: 0.0375,
            collider_friction: COLLIDER_FRICTION,
            threads: 1,
        }
    }
}

/// Which run to simulate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunKind<'a> {
    /// Every emitter, through update 700.
    Factual,
    /// The first emitters only, through update 500, without the named stick.
    Without(&'a str),
}

/// A simulated run, labelled.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulatedRun {
    /// Its `trackingData`, by the release's counting.
    pub tracking: FluidTracking,
    /// The solver's work.
    pub work: WorkCounters,
}

/// Simulates `kind` in the scene of `geometry` with `materials` (by emitter key; a later
/// emitter takes its base fluid's), and labels it; `receptors` are the containers' boxes.
///
/// # Errors
/// The solver's: a bad setting, a missing material, a particle that is not finite.
pub fn simulate(
    geometry: &FluidGeometry,
    receptors: &[Receptor<'_>],
    materials: &IndexMap<String, FluidMaterialGuess>,
    kind: RunKind<'_>,
    settings: &RunSettings,
) -> Result<SimulatedRun, MpmError> {
    simulate_observed(
        geometry,
        receptors,
        materials,
        kind,
        settings,
        &mut |_, _| {},
    )
}

/// The particles after an update: state, emitter index (into the run's emitters: first ones,
/// then later ones, as listed) and mass, indexed by id.
pub type Particles = [(ParticleState, usize, f64)];

/// [`simulate`], showing `observe` the particles after every update (numbered from 1).
///
/// # Errors
/// As [`simulate`].
pub fn simulate_observed(
    geometry: &FluidGeometry,
    receptors: &[Receptor<'_>],
    materials: &IndexMap<String, FluidMaterialGuess>,
    kind: RunKind<'_>,
    settings: &RunSettings,
    observe: &mut dyn FnMut(u32, &Particles),
) -> Result<SimulatedRun, MpmError> {
    let removed = match kind {
        RunKind::Factual => None,
        RunKind::Without(stick) => Some(stick),
    };
    let colliders: Vec<&PerceivedCollider> = geometry
        .colliders
        .iter()
        .filter(|collider| Some(collider.name.as_str()) != removed)
        .collect();
    let emitters: Vec<&PerceivedEmitter> = geometry
        .emitters
        .iter()
        .filter(|emitter| kind == RunKind::Factual || !emitter.later)
        .collect();
    let mut solver = build_solver(&colliders, &emitters, materials, settings)?;
    let updates = match kind {
        RunKind::Factual => FACTUAL_UPDATES,
        RunKind::Without(_) => COUNTERFACTUAL_UPDATES,
    };
    let reach = settings.contact_reach.max(0.75 * settings.grid_spacing);
    let contacts = ContactMap::new(&colliders, reach);
    let mut touched: Vec<u64> = Vec::new();
    for update in 1..=updates {
        solver.advance(UPDATE_SECONDS)?;
        let particles = solver.particles_by_id();
        touched.resize(particles.len(), 0);
        for (bits, (state, _, _)) in touched.iter_mut().zip(&particles) {
            *bits |= contacts.touching(state.position);
        }
        observe(update, &particles);
    }
    let particles = solver.particles_by_id();
    let tracking = label(
        &colliders,
        &emitters,
        receptors,
        materials,
        &particles,
        &touched,
        emitter_budget(settings),
    );
    Ok(SimulatedRun {
        tracking,
        work: solver.counters(),
    })
}

/// The material of emitter `key`: its own entry, or its base fluid's.
fn material_of(
    materials: &IndexMap<String, FluidMaterialGuess>,
    key: &str,
) -> Option<FluidMaterialGuess> {
    materials
        .get(key)
        .or_else(|| materials.get(base_fluid_name(key)))
        .copied()
}

fn build_solver(
    colliders: &[&PerceivedCollider],
    emitters: &[&PerceivedEmitter],
    materials: &IndexMap<String, FluidMaterialGuess>,
    settings: &RunSettings,
) -> Result<Solver, MpmError> {
    let dx = settings.grid_spacing;
    if !(dx.is_finite() && dx > 0.0) {
        return Err(MpmError::InvalidGrid(format!(
            "fluid grid spacing {dx} is not positive and finite"
        )));
    }
    if settings.particles_per_cell_side == 0 {
        return Err(MpmError::InvalidGrid(
            "fluid particles per cell side is 0".to_string(),
        ));
    }
    // Node `WALL_NODES` lies on each inner face of the tank.
    let walls = WALL_NODES as f64 * dx;
    let origin = [TANK_INNER[0][0] - walls, TANK_INNER[0][1] - walls];
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a checked positive spacing over a fixed tank gives a small count"
    )]
    let cells = |axis: usize| ((TANK_INNER[1][axis] - TANK_INNER[0][axis]) / dx).ceil() as usize;
    let grid = GridSpec {
        origin,
        spacing: dx,
        nodes: [cells(0) + 2 * WALL_NODES + 1, cells(1) + 2 * WALL_NODES + 1],
        walls: Walls {
            low: WALL_NODES,
            high: WALL_NODES,
        },
    };
    let mut fluid_materials = Vec::new();
    for emitter in emitters {
        let guess =
            material_of(materials, &emitter.key).ok_or_else(|| MpmError::InvalidMaterial {
                index: fluid_materials.len(),
                reason: format!("no material was inferred for the {}", emitter.key),
            })?;
        let viscosity = if guess.sticky {
            settings.sticky_viscosity
        } else {
            settings.thin_viscosity
        };
        fluid_materials.push(Material::Liquid(LiquidMaterial {
            density: guess.density,
            bulk_modulus: guess.density * settings.sound_speed * settings.sound_speed,
            viscosity: guess.density * viscosity,
        }));
    }
    let mpm_colliders: Vec<Collider> = colliders
        .iter()
        .map(|c| Collider {
            boundary: Boundary::Separate {
                friction: settings.collider_friction,
            },
            ..c.capsule()
        })
        .collect();
    let mpm_settings = Settings {
        gravity: [0.0, -GRAVITY],
        threads: settings.threads,
        ..Settings::default()
    };
    let mut solver = Solver::new(grid, fluid_materials, &mpm_colliders, mpm_settings)?;
    for (index, emitter) in emitters.iter().enumerate() {
        let opens = if emitter.later {
            PREDICTIVE_EMITTER_OPEN_UPDATE
        } else {
            EMITTER_OPEN_UPDATE
        };
        // Update `n` runs from `(n − 1)·Δt`.
        let start = f64::from(opens - 1) * UPDATE_SECONDS;
        solver.add_emitter(Emitter::new(
            index,
            [emitter.centre[0], emitter.centre[1] - EMITTER_HEIGHT / 2.0],
            [0.0, -1.0],
            emitter.width,
            EMITTER_SPEED,
            particle_spacing(settings),
            (start, f64::INFINITY),
            emitter_budget(settings),
        ))?;
    }
    Ok(solver)
}

/// The release's particle spacing, units (Obi resolution 40).
const RELEASE_SPACING: f64 = 1.0 / 40.0;

/// Spacing of the particles an emitter lays, units.
fn particle_spacing(settings: &RunSettings) -> f64 {
    settings.grid_spacing / f64::from(settings.particles_per_cell_side.max(1))
}

/// Particles an emitter releases: the release's volume in particles of our spacing.
pub(crate) fn emitter_budget(settings: &RunSettings) -> usize {
    let ratio = RELEASE_SPACING / particle_spacing(settings);
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a positive count of particles, at least one"
    )]
    let budget = (f64::from(PARTICLES_PER_EMITTER) * ratio * ratio)
        .round()
        .max(1.0) as usize;
    budget
}

/// `count` indices spread evenly over `0..available` (the release's particles standing for
/// ours).
fn resample(available: usize, count: usize) -> impl Iterator<Item = usize> {
    (0..count).map(move |index| index * available / count.max(1))
}

/// Which colliders a point touches, by a coarse lookup: each cell lists the colliders within
/// reach of it, so a particle tests a handful instead of all.
struct ContactMap {
    capsules: Vec<Collider>,
    origin: [f64; 2],
    cell: f64,
    columns: usize,
    rows: usize,
    /// Per cell, a bit per collider within reach of some point of the cell.
    near: Vec<u64>,
    reach: f64,
}

impl ContactMap {
    fn new(colliders: &[&PerceivedCollider], reach: f64) -> ContactMap {
        let cell = 0.1;
        let origin = [TANK_INNER[0][0] - 0.5, TANK_INNER[0][1] - 0.5];
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a fixed tank over a fixed cell"
        )]
        let count =
            |axis: usize| ((TANK_INNER[1][axis] - TANK_INNER[0][axis] + 1.0) / cell) as usize + 1;
        let (columns, rows) = (count(0), count(1));
        // At most 64 colliders get a bit (the release's scenes have about 30).
        let capsules: Vec<Collider> = colliders
            .iter()
            .take(64)
            .map(|collider| collider.capsule())
            .collect();
        let mut near = vec![0u64; columns * rows];
        // A cell's centre within reach + half its diagonal of a capsule's surface.
        let slack = reach + cell * std::f64::consts::FRAC_1_SQRT_2;
        for column in 0..columns {
            for row in 0..rows {
                let centre = [
                    origin[0] + (column as f64 + 0.5) * cell,
                    origin[1] + (row as f64 + 0.5) * cell,
                ];
                for (index, capsule) in capsules.iter().enumerate() {
                    if capsule.signed_distance(centre).0 < slack {
                        near[column * rows + row] |= 1 << index;
                    }
                }
            }
        }
        ContactMap {
            capsules,
            origin,
            cell,
            columns,
            rows,
            near,
            reach,
        }
    }

    /// A bit per collider whose surface `point` is within reach of.
    fn touching(&self, point: [f64; 2]) -> u64 {
        let column = ((point[0] - self.origin[0]) / self.cell).floor();
        let row = ((point[1] - self.origin[1]) / self.cell).floor();
        if !(column >= 0.0 && row >= 0.0) {
            return 0;
        }
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "non-negative, and the lookup below is checked"
        )]
        let (column, row) = (column as usize, row as usize);
        if column >= self.columns || row >= self.rows {
            return 0;
        }
        let mut candidates = self
            .near
            .get(column * self.rows + row)
            .copied()
            .unwrap_or(0);
        let mut bits = 0;
        while candidates != 0 {
            let index = candidates.trailing_zeros() as usize;
            candidates &= candidates - 1;
            if let Some(capsule) = self.capsules.get(index)
                && capsule.signed_distance(point).0 < self.reach
            {
                bits |= 1 << index;
            }
        }
        bits
    }
}

/// The run's `trackingData` from each particle's contacts and final position (particles in id
/// order: emitter by emitter as they were released), counted as the release counts, with counts
/// scaled to 1,500 particles an emitter.
fn label(
    colliders: &[&PerceivedCollider],
    emitters: &[&PerceivedEmitter],
    receptors: &[Receptor<'_>],
    materials: &IndexMap<String, FluidMaterialGuess>,
    particles: &[(ParticleState, usize, f64)],
    touched: &[u64],
    budget: usize,
) -> FluidTracking {
    let mut paths: Vec<Vec<Vec<&str>>> = vec![Vec::new(); emitters.len()];
    let mut finals: Vec<Vec<[f64; 2]>> = vec![Vec::new(); emitters.len()];
    let mut by_emitter: Vec<Vec<usize>> = vec![Vec::new(); emitters.len()];
    for (index, (_, emitter, _)) in particles.iter().enumerate() {
        if let Some(list) = by_emitter.get_mut(*emitter) {
            list.push(index);
        }
    }
    let chosen = by_emitter.iter().flat_map(|indices| {
        // The release's count for the share of the budget this emitter released.
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a non-negative particle count"
        )]
        let count = (indices.len() as f64 * f64::from(PARTICLES_PER_EMITTER) / budget as f64)
            .round() as usize;
        resample(indices.len(), count).filter_map(|slot| indices.get(slot).copied())
    });
    for index in chosen {
        let (Some((state, emitter, _)), Some(&bits)) = (particles.get(index), touched.get(index))
        else {
            continue;
        };
        let path: Vec<&str> = colliders
            .iter()
            .take(64)
            .enumerate()
            .filter(|(index, _)| bits & (1 << index) != 0)
            .map(|(_, collider)| collider.name.as_str())
            .collect();
        if let (Some(list), Some(positions)) = (paths.get_mut(*emitter), finals.get_mut(*emitter)) {
            list.push(path);
            positions.push(state.position);
        }
    }
    let per_emitter_stick_stat: IndexMap<String, IndexMap<String, u32>> = emitters
        .iter()
        .zip(&paths)
        .filter(|(_, paths)| !paths.is_empty())
        .map(|(emitter, paths)| (emitter.key.clone(), emitter_stick_stat(&emitter.key, paths)))
        .collect();
    let fluids: Vec<(&str, &[[f64; 2]])> = emitters
        .iter()
        .zip(&finals)
        .map(|(emitter, positions)| (emitter.key.as_str(), positions.as_slice()))
        .collect();
    let per_receptor_fluid_stat = receptor_fluid_stat(receptors, &fluids);
    let densities: Vec<(String, f64)> = emitters
        .iter()
        .filter(|emitter| !emitter.later)
        .filter_map(|emitter| {
            material_of(materials, &emitter.key).map(|guess| (emitter.key.clone(), guess.density))
        })
        .collect();
    let density_pairs: Vec<(&str, f64)> = densities
        .iter()
        .map(|(key, density)| (key.as_str(), *density))
        .collect();
    let density_relations: Vec<DensityRelation> =
        density_relations(&per_receptor_fluid_stat, &density_pairs)
            .into_iter()
            .map(|(heavier, lighter)| {
                (
                    base_fluid_name(&heavier).to_string(),
                    base_fluid_name(&lighter).to_string(),
                )
            })
            .filter(|(heavier, lighter)| heavier != lighter)
            .map(|(heavier, lighter)| DensityRelation { heavier, lighter })
            .collect();
    let temperature_stick: IndexMap<String, String> = colliders
        .iter()
        .filter(|collider| is_regular_stick(&collider.name))
        .map(|collider| (collider.name.clone(), NORMAL_TEMPERATURE.to_string()))
        .collect();
    let temperature_askable_stick =
        temperature_askable_sticks(&per_emitter_stick_stat, &temperature_stick);
    FluidTracking {
        per_emitter_stick_stat,
        temperature_stick,
        temperature_askable_stick,
        per_receptor_fluid_stat,
        density_relations,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::fluid::outcome::Rect;

    fn demo_annotation() -> FluidAnnotation {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("eval/demo/fluid_slides/0/outputs.json");
        FluidAnnotation::load(&path).unwrap()
    }

    #[test]
    fn the_transforms_give_the_sticks_of_the_layout_and_the_emitters_between_their_walls() {
        let annotation = demo_annotation();
        let geometry = FluidGeometry::from_annotation(&annotation).unwrap();
        let origin = annotation.layout.tank.origin;
        // Every stick's capsule runs between the layout's start and end points (relative to the
        // tank origin there), to the transforms' rounding.
        for stick in &annotation.layout.sticks {
            let collider = geometry
                .colliders
                .iter()
                .find(|collider| collider.name == stick.name)
                .unwrap();
            let start = [stick.start[0] + origin[0], stick.start[1] + origin[1]];
            let end = [stick.end[0] + origin[0], stick.end[1] + origin[1]];
            let distance = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
            let matched = (distance(collider.start, start) + distance(collider.end, end))
                .min(distance(collider.start, end) + distance(collider.end, start));
            assert!(
                matched < 2e-3,
                "{}: {collider:?} against {start:?}–{end:?}",
                stick.name
            );
            assert!((collider.radius - 0.075).abs() < 1e-12);
        }
        // The Gray Stick by hand: centre (1.44133, −1.2), 125°, length 1.71076.
        let gray = geometry
            .colliders
            .iter()
            .find(|collider| collider.name == "Gray Stick")
            .unwrap();
        assert!((gray.start[0] - 1.931_96).abs() < 1e-5 && (gray.start[1] + 1.900_68).abs() < 1e-5);
        // Tank walls are the grid's, not colliders.
        assert!(geometry.colliders.iter().all(|c| c.name != "Floor"));
        // Three first emitters, then the later one; the pink one between walls at 1.5276 and
        // 2.0776 (0.05 thick): centre 1.8026, width 0.5.
        let keys: Vec<&str> = geometry.emitters.iter().map(|e| e.key.as_str()).collect();
        assert_eq!(
            keys,
            [
                "Pink Fluid",
                "Yellow Fluid",
                "Light Blue Fluid",
                "Later Emitted Light Blue Fluid"
            ]
        );
        let pink = &geometry.emitters[0];
        assert!((pink.centre[0] - 1.8026).abs() < 1e-9 && (pink.centre[1] - 2.85).abs() < 1e-9);
        assert!((pink.width - 0.5).abs() < 1e-9 && !pink.later);
        assert!(geometry.emitters[3].later);
    }

    #[test]
    fn an_emitter_without_its_right_wall_is_a_named_error() {
        let mut annotation = demo_annotation();
        annotation
            .object_transforms
            .shift_remove("Yellow Fluid Emitter Right Wall");
        assert_eq!(
            FluidGeometry::from_annotation(&annotation),
            Err(GeometryError::MissingEmitterWall {
                key: "Yellow Fluid".into(),
                side: "Right"
            })
        );
    }

    #[test]
    fn emitters_release_the_release_volume_and_counts_resample_evenly() {
        let at = |grid_spacing, particles_per_cell_side| {
            emitter_budget(&RunSettings {
                grid_spacing,
                particles_per_cell_side,
                ..RunSettings::default()
            })
        };
        assert_eq!(at(0.05, 2), 1500);
        assert_eq!(at(0.1, 2), 375);
        assert_eq!(at(0.025, 2), 6000);
        assert_eq!(at(0.05, 3), 3375);
        assert_eq!(at(0.05, 1), 375);
        assert_eq!(
            resample(375, 1500).take(5).collect::<Vec<_>>(),
            [0, 0, 0, 0, 1]
        );
        assert_eq!(resample(6000, 1500).take(3).collect::<Vec<_>>(), [0, 4, 8]);
        assert_eq!(resample(375, 1500).last(), Some(374));
    }

    #[test]
    fn the_contact_map_agrees_with_testing_every_collider() {
        let colliders = [
            PerceivedCollider {
                name: "Red Stick".into(),
                start: [-1.0, 0.5],
                end: [1.0, -0.3],
                radius: 0.075,
            },
            PerceivedCollider {
                name: "Blue Stick".into(),
                start: [0.5, -0.2],
                end: [2.0, 0.6],
                radius: 0.075,
            },
        ];
        let borrowed: Vec<&PerceivedCollider> = colliders.iter().collect();
        let reach = 0.04;
        let map = ContactMap::new(&borrowed, reach);
        let mut touching = 0;
        for i in 0..200 {
            for j in 0..100 {
                let point = [-1.5 + f64::from(i) * 0.0173, -0.8 + f64::from(j) * 0.0161];
                let expected: u64 = colliders
                    .iter()
                    .enumerate()
                    .filter(|(_, c)| c.capsule().signed_distance(point).0 < reach)
                    .map(|(index, _)| 1 << index)
                    .sum();
                assert_eq!(map.touching(point), expected, "{point:?}");
                touching += u32::from(expected != 0);
            }
        }
        assert!(touching > 500, "the grid of points crosses the sticks");
        assert_eq!(map.touching([100.0, 0.0]), 0);
        assert_eq!(map.touching([f64::NAN, 0.0]), 0);
    }

    /// One fluid falls from its emitter onto a stick sloping down to the right, which carries it
    /// into the wide cup to its right; without the stick it falls straight into the cup below.
    /// (Inviscid MPM fluid landing at 5–6 units/s splashes and overshoots: the cups are wide and
    /// deep, and the assertions ask for most of the fluid, not all.)
    #[test]
    fn a_stick_carries_the_fluid_into_the_far_cup_and_without_it_the_fluid_falls_straight() {
        let capsule = |name: &str, start, end, radius| PerceivedCollider {
            name: name.into(),
            start,
            end,
            radius,
        };
        let mut colliders = vec![capsule("Red Stick", [-2.0, -0.5], [0.0, -1.2], 0.075)];
        let cups = [
            ("White Container", -2.7, -0.6),
            ("Green Container", 0.1, 2.7),
        ];
        for (name, left, right) in cups {
            for (side, x) in [("Left", left), ("Right", right)] {
                colliders.push(capsule(
                    &format!("{name} {side} Vertical Wall"),
                    [x, -4.0],
                    [x, -2.0],
                    0.1,
                ));
            }
        }
        let geometry = FluidGeometry {
            colliders,
            emitters: vec![PerceivedEmitter {
                key: "Blue Fluid".into(),
                centre: [-1.5, 2.85],
                width: 0.5,
                later: false,
            }],
        };
        let receptors: Vec<Receptor<'_>> = cups
            .iter()
            .map(|&(name, left, right)| Receptor {
                name,
                cup: Rect {
                    min: [left, -4.1],
                    max: [right, -2.0],
                },
                funnel: Rect {
                    min: [left, -2.0],
                    max: [right, -1.9],
                },
            })
            .collect();
        let materials: IndexMap<String, FluidMaterialGuess> = [(
            "Blue Fluid".to_string(),
            FluidMaterialGuess {
                density: 1600.0,
                sticky: false,
            },
        )]
        .into_iter()
        .collect();
        let settings = RunSettings {
            grid_spacing: 0.1,
            ..RunSettings::default()
        };
        let factual = simulate(
            &geometry,
            &receptors,
            &materials,
            RunKind::Factual,
            &settings,
        )
        .unwrap();
        let tracking = &factual.tracking;
        let (white, green) = (
            tracking.particles_in("White Container", "Blue Fluid"),
            tracking.particles_in("Green Container", "Blue Fluid"),
        );
        assert!(
            tracking
                .contacts("Blue Fluid")
                .unwrap()
                .contains_key("Red Stick")
        );
        assert!(green > 900 && green > 3 * white, "{tracking:?}");
        assert_eq!(factual.work.emitted, 375);
        let without = simulate(
            &geometry,
            &receptors,
            &materials,
            RunKind::Without("Red Stick"),
            &settings,
        )
        .unwrap();
        let tracking = &without.tracking;
        let (white, green) = (
            tracking.particles_in("White Container", "Blue Fluid"),
            tracking.particles_in("Green Container", "Blue Fluid"),
        );
        assert!(
            !tracking
                .contacts("Blue Fluid")
                .unwrap()
                .contains_key("Red Stick")
        );
        assert!(white > 900 && white > 3 * green, "{tracking:?}");
    }
}
